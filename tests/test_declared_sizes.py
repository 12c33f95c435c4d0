"""Declared sizes checked before reading (issue 44, class 11): a file of a few kilobytes
can declare a variable of 2**28 x 4 values (8 GiB of fill values once read); every
reader of an input -- :func:`vibimpact.io.read_netcdf` (so every command's input file)
and the map store reader -- adds up the bytes its variables declare, from the metadata
alone, and refuses more than :data:`vibimpact.base._limits.MAX_READ_BYTES` before reading
any: one line and exit 2 on the command line, a ValueError naming the file and the
variable in the API."""
import os
import warnings

import netCDF4
import numpy as np
import pytest
import xarray as xr

from vibimpact.base import _limits
from vibimpact.io import read_netcdf
from vibimpact.maps import open_map, write_map

from test_bad_input import assert_refused, run_cli  # noqa: F401

HUGE = 2**28


def _declaring(path, dims, variables, unlimited=False):
    """A NetCDF file of ``variables`` ({name: dims}) over ``dims`` ({name: length})
    whose data are never written (or, ``unlimited``: one value at the end of an
    unlimited first dimension); small on disk whatever it declares."""
    with netCDF4.Dataset(path, "w") as nc:
        for i, (name, n) in enumerate(dims.items()):
            nc.createDimension(name, None if unlimited and i == 0 else n)
        for name, vdims in variables.items():
            var = nc.createVariable(name, "f8", vdims,
                                    chunksizes=tuple(min(1024, dims[d]) for d in vdims))
            if unlimited:
                var[(dims[vdims[0]] - 1,) + (0,) * (len(vdims) - 1)] = 1.0
        nc.setncattr("model", "rotor")
    assert os.path.getsize(path) < 100_000  # the file stays small
    return path


CRAFTED = {
    "one variable of 2**28 x 4": lambda p: _declaring(
        p, {"eta": HUGE, "state": 4}, {"final_state": ("eta", "state")}),
    "an unlimited dimension written at its end": lambda p: _declaring(
        p, {"eta": HUGE, "state": 4}, {"final_state": ("eta", "state")}, unlimited=True),
    "three variables each under the limit": lambda p: _declaring(
        p, {"eta": HUGE // 4, "state": 4},
        {f"v{i}": ("eta", "state") for i in range(3)}),
    "a huge coordinate (read when opened)": lambda p: _declaring(
        p, {"eta": HUGE * 4}, {"eta": ("eta",)}),
}


@pytest.mark.parametrize("case", list(CRAFTED))
def test_read_netcdf_refuses_declared_sizes_over_the_limit_before_reading(case,
                                                                          tmp_path):
    """Hypothesis: read_netcdf loaded every variable (8 GiB of fill values for a 2**28
    x 4 one) before anyone could refuse it; now it adds up the declared bytes from the
    metadata and raises a ValueError naming the file and the largest variable."""
    path = CRAFTED[case](str(tmp_path / "big.nc"))
    with pytest.raises(ValueError, match=r"big\.nc' declares .* GiB of data \(variable"):
        read_netcdf(path)


#: command -> its argv reading FILE
READERS = {
    "plot": ["plot", "FILE", "-o", "p.png"],
    "simulate --from": ["simulate", "--from", "FILE", "--eta", "1.0", "-o", "o.nc"],
    "rerun": ["rerun", "FILE"],
    "orbits --seeds": ["orbits", "--preset", "fig8", "--eta", "1.0", "--seeds", "FILE",
                       "-o", "o.nc"],
    "attractors --sweep": ["attractors", "--sweep", "FILE", "--eta", "1.0", "-o",
                           "o.nc"],
}


@pytest.mark.parametrize("command", list(READERS))
def test_commands_refuse_a_file_declaring_too_much_in_one_line(command, tmp_path,
                                                               monkeypatch, capfd):
    """Hypothesis: every command that reads an input file refuses one declaring 8 GiB
    before reading it: one line naming the file and 'declares', exit 2, no output."""
    CRAFTED["one variable of 2**28 x 4"](str(tmp_path / "big.nc"))
    monkeypatch.chdir(tmp_path)
    argv = [a.replace("FILE", "big.nc") for a in READERS[command]]
    rc, out, err = run_cli(argv, capfd)
    assert_refused(rc, out, err, "declares 8 GiB of data")
    assert sorted(os.listdir(tmp_path)) == ["big.nc"]


def _store_declaring(path, shape):
    """A map store (write_map) with one more array of ``shape`` declared in its
    consolidated metadata and never written: one chunk, never stored."""
    import zarr

    ds = xr.Dataset({"regime": (("kh", "eta"), np.ones((2, 2), "i1"))},
                    coords={"kh": [1.0, 2.0], "eta": [1.0, 1.1]},
                    attrs={"map_vary": "kh"})
    write_map(ds, path)
    group = zarr.open_group(path, mode="r+")
    group.create_array("huge", shape=shape, chunks=shape, dtype="f8")
    with warnings.catch_warnings():  # consolidated metadata: zarr-python's extension
        warnings.simplefilter("ignore")
        zarr.consolidate_metadata(path)
    return path


def test_open_map_refuses_a_store_declaring_too_much(tmp_path):
    """Hypothesis: a Zarr store's arrays are checked alike, from their metadata, before
    a chunk is read (one 8 GiB chunk of zeros compresses to almost nothing)."""
    path = _store_declaring(str(tmp_path / "m.zarr"), (HUGE, 4))
    with pytest.raises(ValueError, match=r"map '.*m\.zarr' declares 8 GiB .*'huge'"):
        open_map(path)


def test_plot_of_such_a_store_is_one_line(tmp_path, monkeypatch, capfd):
    """Hypothesis: the command line says the store's refusal in one line, exit 2."""
    _store_declaring(str(tmp_path / "m.zarr"), (HUGE, 4))
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(["plot", "m.zarr", "--kind", "map", "-o", "p.png"], capfd)
    assert_refused(rc, out, err, "declares 8 GiB")


def test_check_declared_counts_the_bytes_of_every_variable():
    """Hypothesis: the limit is on the sum over the variables (each itemsize times its
    values; text counts TEXT_ITEM_BYTES a value), inclusive."""
    limit = _limits.MAX_READ_BYTES
    _limits.check_declared([("a", (limit // 8,), 8)], "f")
    with pytest.raises(ValueError, match="'b'"):
        _limits.check_declared([("a", (limit // 16,), 8), ("b", (limit // 16 + 1,), 8)],
                               "f")
    with pytest.raises(ValueError, match="'s'"):
        _limits.check_declared([("s", (limit // _limits.TEXT_ITEM_BYTES + 1,), None)], "f")
