"""Issue 32: plot refused damaged sweep and map files only for NaN eta and undeclared
regime codes; a continue file with eta = NaN ("from 1.12 to nan") and a classify file
with period = -7 were drawn.  Every figure of a file now checks its grid and every
variable that declares codes (flag_values), and period as 0 or an integer >= 1."""
import os

import numpy as np
import pytest
import xarray as xr

from test_bad_input_round3_cli import _refused, _sweep_file

from vibimpact.io import write_netcdf
from vibimpact.plotting._sweep import check_contents


def _with(path, out, **changes):
    """Write ``path``'s dataset with ``changes`` ({variable: (index, value)}) to
    ``out``."""
    with xr.open_dataset(path) as ds:
        ds = ds.load()
    for name, (i, value) in changes.items():
        values = ds[name].values.astype(float if isinstance(value, float) else
                                        ds[name].dtype)
        values[i] = value
        ds[name] = (ds[name].dims, values, ds[name].attrs)
    write_netcdf(ds, out, overwrite=True)


@pytest.mark.parametrize("period, words", [(-7, "period holds -7"),
                                           (2.5, "period holds 2.5")])
@pytest.mark.parametrize("kind", ["response", "bifurcation"])
def test_plot_refuses_a_sweep_file_whose_period_is_no_count(period, words, kind, tmp_path,
                                                            monkeypatch, capfd):
    """A sweep file's period is 0 (none) or an integer >= 1; -7 or 2.5 is refused in one
    line naming period, for every kind of sweep figure."""
    _sweep_file(tmp_path / "s.nc")
    _with(tmp_path / "s.nc", tmp_path / "t.nc", period=(0, period))
    os.remove(tmp_path / "s.nc")
    line = _refused(["plot", "t.nc", "--kind", kind, "-o", "p.png"], tmp_path,
                    monkeypatch, capfd)
    assert words in line and "neither an integer >= 1" in line


@pytest.fixture(scope="module")
def branch_file(tmp_path_factory):
    """A three-point continue file (made by the command line)."""
    from vibimpact.cli import main

    path = tmp_path_factory.mktemp("branch") / "b.nc"
    assert main(["continue", "--preset", "fig8", "--eta", "1.12", "--stop", "1.13",
                 "--max-points", "3", "-o", str(path)]) == 0
    return path


@pytest.mark.parametrize("change, words", [
    (dict(eta=(1, np.nan)), "eta holds 1 non-finite"),
    (dict(eta=(2, np.inf)), "eta holds 1 non-finite"),
    (dict(stable=(0, 7)), "stable holds code(s) 7 not among its flag_values"),
], ids=["eta-nan", "eta-inf", "stable-7"])
def test_plot_refuses_a_damaged_continue_file(branch_file, change, words, tmp_path,
                                             monkeypatch, capfd):
    """A continue file whose parameter holds NaN or inf, or whose stability codes are
    undeclared, is refused in one line naming the variable (it was drawn 'from 1.12 to
    nan')."""
    _with(branch_file, tmp_path / "b.nc", **change)
    line = _refused(["plot", "b.nc", "-o", "p.png"], tmp_path, monkeypatch, capfd)
    assert words in line


def test_plot_basins_refuses_a_non_finite_plane_coordinate():
    """A basins dataset whose plane coordinate holds NaN is refused naming it, before
    anything is drawn."""
    from vibimpact.plotting.basins import plot_basins

    ds = xr.Dataset({"basin": (("row", "column"), np.zeros((2, 2), dtype="i4"))},
                    coords={"X": ("column", [0.0, np.nan]), "Y": ("row", [0.0, 1.0])},
                    attrs={"plane_x": "X", "plane_y": "Y"})
    with pytest.raises(ValueError, match="^X holds 1 non-finite"):
        plot_basins(ds)


@pytest.mark.parametrize("name, values, flags, ok", [
    ("period", [0, 1, 64], [0], True),
    ("period", [0, -1], [0], False),
    ("period", [0.0, 1.5], None, False),          # checked without flag_values too
    ("found_by", [1, 2], [1, 2, 4], True),
    ("found_by", [1, 3], [1, 2, 4], False),       # any variable that declares codes
])
def test_every_declared_code_is_checked(name, values, flags, ok):
    """check_contents checks every variable with flag_values, whatever its name, and
    period as a count; it accepts what the declaration allows."""
    attrs = {} if flags is None else {"flag_values": np.array(flags)}
    ds = xr.Dataset({name: ("i", np.array(values), attrs)})
    if ok:
        check_contents(ds, grids=(), codes=())
    else:
        with pytest.raises(ValueError, match=rf"^{name} holds "):
            check_contents(ds, grids=(), codes=())
