"""``map --overwrite`` and ``write_map(..., overwrite=True)`` replace only what the toolkit
wrote (issue 44, class 12): a directory that held a ``zarr.json`` was deleted whole, the
user's other files with it.  Now a store is replaced only when its metadata carries the
toolkit's provenance and it holds nothing but a Zarr store's entries; anything else is
refused in one line naming what was found, and left as it was."""
import os
import shutil

import numpy as np
import pytest
import xarray as xr

from vibimpact.maps import write_map
from vibimpact.maps.store import check_replaceable

from test_bad_input import assert_refused, run_cli  # noqa: F401

#: a map command refused before any work (its grid is never computed)
MAP = ["map", "--eta", "1.0,1.01", "--vary", "kh=100,120", "--analyses", "period",
       "--workers", "1", "--no-progress", "--overwrite", "-o"]


def _map_dataset():
    return xr.Dataset({"regime": (("kh", "eta"), np.ones((2, 2), "i1"))},
                      coords={"kh": [100.0, 120.0], "eta": [1.0, 1.01]},
                      attrs={"map_vary": "kh"})


@pytest.fixture(scope="module")
def ours(tmp_path_factory):
    """A store the toolkit wrote (write_map)."""
    path = tmp_path_factory.mktemp("ours") / "m.zarr"
    write_map(_map_dataset(), str(path))
    return path


def _copy_with(name):
    def make(ours, d):
        dst = d / "m.zarr"
        shutil.copytree(ours, dst)
        (dst / name).write_text("the user's notes\n")
        return dst
    return make


def _directory_without_zarr_json(ours, d):
    (d / "m.zarr").mkdir()
    (d / "m.zarr" / "data.csv").write_text("1,2\n")
    return d / "m.zarr"


def _someone_elses_store(ours, d):
    import zarr

    group = zarr.open_group(str(d / "m.zarr"), mode="w")
    group.create_array("a", shape=(2,), dtype="f8")
    return d / "m.zarr"


def _link_to_ours(ours, d):
    shutil.copytree(ours, d / "real.zarr")
    os.symlink("real.zarr", d / "m.zarr")
    return d / "m.zarr"


def _regular_file(ours, d):
    (d / "m.zarr").write_text("not a store\n")
    return d / "m.zarr"


def _link_inside(ours, d):
    shutil.copytree(ours, d / "m.zarr")
    (d / "elsewhere").mkdir()
    os.symlink(d / "elsewhere", d / "m.zarr" / "regime" / "c" / "9")
    return d / "m.zarr"


#: what stands at the output -> what the one line names
FOUND = {
    "zarr.json and a user file": (_copy_with("notes.txt"), "holds 'notes.txt'"),
    "a user file among the chunks": (_copy_with(os.path.join("regime", "c", "notes")),
                                     "holds 'regime/c/notes'"),
    "a user file beside an array's metadata": (_copy_with(os.path.join("regime",
                                                                       "x.json")),
                                               "holds 'regime/x.json'"),
    "a directory without zarr.json": (_directory_without_zarr_json,
                                      "is a directory without a zarr.json"),
    "a Zarr store someone else wrote": (_someone_elses_store,
                                        "without vibimpact's provenance"),
    "a symbolic link to a store": (_link_to_ours, "is a symbolic link"),
    "a regular file": (_regular_file, "is a file, not a Zarr store"),
    "a symbolic link inside the store": (_link_inside, "holds 'regime/c/9'"),
}


def _snapshot(d):
    return sorted((os.path.relpath(os.path.join(top, n), d), os.path.islink(
        os.path.join(top, n))) for top, dirs, files in os.walk(d) for n in dirs + files)


@pytest.mark.parametrize("case", list(FOUND))
def test_map_overwrite_refuses_what_the_toolkit_did_not_write(case, ours, tmp_path,
                                                              monkeypatch, capfd):
    """Hypothesis: map --overwrite removed any directory holding a zarr.json (and
    replaced other things than its own stores); now it refuses, before any work, in one
    line naming what it found, and leaves everything as it was."""
    make, needle = FOUND[case]
    make(ours, tmp_path)
    before = _snapshot(tmp_path)
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli([*MAP, "m.zarr"], capfd)
    assert_refused(rc, out, err, needle)
    assert _snapshot(tmp_path) == before


@pytest.mark.parametrize("case", list(FOUND))
def test_write_map_overwrite_refuses_what_the_toolkit_did_not_write(case, ours,
                                                                    tmp_path):
    """Hypothesis: the API's write_map(..., overwrite=True) is held to the same rule: a
    ValueError naming the path, nothing changed."""
    make, needle = FOUND[case]
    path = make(ours, tmp_path)
    before = _snapshot(tmp_path)
    with pytest.raises(ValueError, match="m.zarr"):
        write_map(_map_dataset(), str(path), overwrite=True)
    assert _snapshot(tmp_path) == before


def test_write_map_replaces_a_store_it_wrote(ours, tmp_path):
    """Hypothesis: a store the toolkit wrote, untouched, is still replaced."""
    path = tmp_path / "m.zarr"
    shutil.copytree(ours, path)
    check_replaceable(str(path))
    ds = _map_dataset()
    ds["regime"][:] = 2
    write_map(ds, str(path), overwrite=True)
    assert (xr.open_zarr(path)["regime"].values == 2).all()


def test_a_netcdf_map_output_that_is_a_directory_is_refused(tmp_path, monkeypatch,
                                                            capfd):
    """Hypothesis: -o m.nc naming a directory is refused with --overwrite too, and the
    directory kept."""
    (tmp_path / "m.nc").mkdir()
    (tmp_path / "m.nc" / "keep.txt").write_text("x")
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli([*MAP, "m.nc"], capfd)
    assert_refused(rc, out, err, "is a directory")
    assert (tmp_path / "m.nc" / "keep.txt").exists()


@pytest.mark.slow
def test_map_overwrite_replaces_its_own_store(tmp_path, monkeypatch, capfd):
    """Hypothesis: the map command still replaces a store it wrote itself (exit 0)."""
    monkeypatch.chdir(tmp_path)
    rc, _, err = run_cli(MAP[:-2] + ["-o", "m.zarr"], capfd)
    assert rc == 0, err
    rc, _, err = run_cli([*MAP, "m.zarr"], capfd)
    assert rc == 0, err
