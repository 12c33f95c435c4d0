"""``vibimpact rerun`` and :func:`vibimpact.io.differences` compare attributes: every
global attribute but the deny-list of :data:`vibimpact.base.provenance.NOT_COMPARED` (time
stamps, versions, platform, command line) and every attribute of every variable and
coordinate, so that a file that contradicts itself is never "identical"."""
import shutil

import netCDF4
import numpy as np
import pytest

import vibimpact as vi
from vibimpact.base import provenance
from vibimpact.io import attribute_differences, differences, read_netcdf

from test_bad_input import run_cli  # noqa: F401

#: a short simulate run: its file reruns in a fraction of a second
SHORT = ["simulate", "--eta", "1.2", "--periods", "2", "--transient", "0", "-o", "s.nc"]


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """A simulate file of the command line (``s.nc``) in a directory of its own."""
    from vibimpact.cli import main

    d = tmp_path_factory.mktemp("attrs")
    mp = pytest.MonkeyPatch()
    mp.chdir(d)
    try:
        assert main(SHORT) == 0
    finally:
        mp.undo()
    return d


def _tampered(src, dst, change):
    """A copy of ``src`` at ``dst`` with ``change(nc)`` applied in place by netCDF4 (the
    data untouched, so only the attributes can tell)."""
    shutil.copy(src, dst)
    with netCDF4.Dataset(dst, "a") as nc:
        change(nc)
    return dst


#: tampering -> the attribute rerun must name
TAMPERINGS = {
    "impact_theta:units='radian'": (
        lambda nc: nc["impact_theta"].setncattr("units", "radian"), "impact_theta:units"),
    "strobe:long_name changed": (
        lambda nc: nc["strobe"].setncattr("long_name", "something else"),
        "strobe:long_name"),
    "a variable attribute added": (
        lambda nc: nc["strobe"].setncattr("scale_note", "x10"), "strobe:scale_note"),
    "a variable attribute removed": (
        lambda nc: nc["impact_theta"].delncattr("units"), "impact_theta:units"),
    "reason='diverged at tau=3'": (
        lambda nc: nc.setncattr("reason", "diverged at tau=3"), "reason"),
    "counter_steps=1": (lambda nc: nc.setncattr("counter_steps", 1), "counter_steps"),
    "state_X changed": (lambda nc: nc.setncattr("state_X", "vertical velocity"),
                        "state_X"),
    "param_kh='abc'": (lambda nc: nc.setncattr("param_kh", "abc"), "param_kh"),
    "Conventions='CF-1.6'": (lambda nc: nc.setncattr("Conventions", "CF-1.6"),
                             "Conventions"),
    "title removed": (lambda nc: nc.delncattr("title"), "title"),
    "a global attribute added": (lambda nc: nc.setncattr("note", "checked"), "note"),
}


@pytest.mark.parametrize("case", list(TAMPERINGS))
def test_rerun_names_every_attribute_that_contradicts_the_command(case, written, tmp_path,
                                                                  monkeypatch, capfd):
    """Hypothesis: rerun compared only an allow-list of global attributes and no
    variable's, so a file whose units, status, counters, state names or parameters were
    changed after the run read "identical"; now any attribute outside the deny-list
    that differs (changed, added or removed, global or a variable's) is reported by
    name, exit 1."""
    change, name = TAMPERINGS[case]
    _tampered(written / "s.nc", tmp_path / "t.nc", change)
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(["rerun", "t.nc"], capfd)
    assert rc == 1, (out, err)
    lines = out.splitlines()
    assert lines[0].startswith("different: 1 of ") and "attributes of the run" in lines[0]
    assert lines[1].startswith(f"  attribute {name}: "), out


def test_rerun_of_the_untouched_file_and_of_new_stamps_is_identical(written, tmp_path,
                                                                    monkeypatch, capfd):
    """Hypothesis: the attributes of the deny-list (time stamps, versions, platform,
    CPU, git commit) differ between two writes of the same data and never make a file
    "different": a copy with every one of them changed reruns identical."""
    def restamp(nc):
        for key in provenance.VOLATILE + provenance.ENVIRONMENT:
            nc.setncattr(key, "changed")

    _tampered(written / "s.nc", tmp_path / "t.nc", restamp)
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(["rerun", "t.nc"], capfd)
    assert rc == 0 and out.startswith("identical: "), (out, err)


def test_rerun_reports_swapped_flag_meanings_of_a_sweep(tmp_path, monkeypatch, capfd):
    """Hypothesis: a sweep file whose regime:flag_meanings has two meanings swapped
    (periodic read as quasi-periodic) contradicts its data and is reported, naming the
    attribute, exit 1."""
    monkeypatch.chdir(tmp_path)
    rc, _, err = run_cli(["classify", "--eta", "1.0,1.01", "--analyses", "period",
                          "--workers", "1", "--no-progress", "-o", "c.nc"], capfd)
    assert rc == 0, err

    def swap(nc):
        words = nc["regime"].getncattr("flag_meanings").split()
        words[0], words[1] = words[1], words[0]
        nc["regime"].setncattr("flag_meanings", " ".join(words))

    _tampered("c.nc", "t.nc", swap)
    rc, out, err = run_cli(["rerun", "t.nc"], capfd)
    assert rc == 1, (out, err)
    assert out.splitlines()[1].startswith("  attribute regime:flag_meanings: ")


def test_the_deny_list_holds_every_provenance_attribute():
    """Hypothesis: every attribute the provenance records about the machine and the
    installation (whatever this process imported) is on the deny-list, so that a rerun
    elsewhere is not "different" for its platform; and nothing about the run (param_*,
    model, status, units) is."""
    recorded = set(provenance.provenance()) | {"source"}
    assert recorded <= set(provenance.NOT_COMPARED)
    assert {f"{d}_version" for d in provenance.DEPENDENCIES} <= set(provenance.ENVIRONMENT)
    for key in ("model", "status", "reason", "param_kh", "units", "title", "Conventions"):
        assert key not in provenance.NOT_COMPARED


def _pair():
    """A dataset and a copy with the same data."""
    import xarray as xr

    ds = xr.Dataset({"regime": ("eta", np.array([1, 2], dtype=np.int8),
                                {"flag_values": np.array([1, 2], dtype=np.int8),
                                 "flag_meanings": "periodic chaotic", "units": "1"})},
                    coords={"eta": ("eta", [1.0, 1.1], {"units": "1"})},
                    attrs={"model": "rotor", "param_kh": 120.0, "history": "a"})
    return ds, ds.copy(deep=True)


@pytest.mark.parametrize("where,key,value", [
    ("regime", "flag_meanings", "chaotic periodic"),
    ("regime", "flag_values", np.array([1, 3], dtype=np.int8)),
    ("regime", "units", "radian"),
    ("eta", "units", "Hz"),
    (None, "param_kh", "abc"),
    (None, "param_kh", 120.0 + 1e-13),
    (None, "model", "duffing"),
])
def test_differences_reports_a_changed_attribute_of_a_variable_coordinate_or_file(
        where, key, value):
    """Hypothesis: io.differences compared data only; now a changed attribute of a data
    variable, of a coordinate or of the dataset (one bit of a number, text for a number)
    is a difference named ``attribute VAR:NAME`` or ``attribute NAME``."""
    a, b = _pair()
    (b[where].attrs if where else b.attrs)[key] = value
    diffs, total = differences(a, b)
    name = f"attribute {where}:{key}" if where else f"attribute {key}"
    assert [n for n, _ in diffs] == [name] and total == 2
    assert differences(a, b, attributes=False)[0] == []


def test_attribute_values_compare_by_value_not_by_container():
    """Hypothesis: the same attribute read back from NetCDF (a scalar, an int8 array) or
    from Zarr (a JSON list) and held in memory (a list, a Python int) compares equal:
    the comparison is of values, NaN equal to NaN, not of their containers."""
    a, b = _pair()
    b["regime"].attrs["flag_values"] = [1, 2]
    a.attrs.update(one=np.array([7]), nan=float("nan"), text=np.str_("x"))
    b.attrs.update(one=7, nan=np.float64("nan"), text="x")
    assert attribute_differences(a, b) == ([], 9)  # 5 global (history left out), 4 of variables
    b.attrs["one"] = "7"  # text is not a number
    assert [n for n, _ in attribute_differences(a, b)[0]] == ["one"]


def test_an_attribute_on_one_side_only_counts_for_files_alone():
    """Hypothesis: a dataset of the API lacks the attributes the command line adds
    (preset, start_*), so io.differences compares the attributes both have; between two
    files of the same command (files=True, rerun's) one missing is a difference, and
    the deny-list (history here) is left out either way."""
    a, b = _pair()
    a.attrs["preset"] = "fig8"
    del b.attrs["history"]
    assert differences(a, b)[0] == []
    assert attribute_differences(a, b, files=True)[0] == [
        ("preset", "only in the original ('fig8')")]


def test_written_and_read_back_has_the_attributes_of_the_run(tmp_path):
    """Hypothesis: a Run's dataset written with write_netcdf and read back has every
    attribute the dataset had, equal by value (the writer adds its own, which the
    dataset lacks), so io.differences finds nothing."""
    run = vi.simulate(vi.presets.get("fig8").replace(eta=1.2), periods=3, transient=0)
    vi.io.write_netcdf(run, tmp_path / "r.nc")
    ds = run.to_dataset()
    assert differences(ds, read_netcdf(tmp_path / "r.nc")) == ([], len(ds.variables))


@pytest.mark.parametrize("where", ["rerun --help", "docs/user_guide/files.rst"])
def test_the_deny_list_is_spelled_out_where_rerun_is_documented(where):
    """Hypothesis: the attributes rerun leaves out are named (a family by its pattern:
    ``*_version``, ``vibimpact_git_*``) in rerun's help and in the files guide, so a
    documented list cannot drift from provenance.NOT_COMPARED."""
    from pathlib import Path

    from vibimpact.cli.rerun import _RERUN_EPILOG

    text = _RERUN_EPILOG if where == "rerun --help" else (
        Path(__file__).resolve().parents[1] / where).read_text()
    text = " ".join(text.replace("``", "").split())
    for name in provenance.NOT_COMPARED:
        family = ("*_version" if name.endswith("_version") else
                  "vibimpact_git_*" if name.startswith("vibimpact_git_") else name)
        assert family in text, (where, name)
