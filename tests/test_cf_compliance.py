"""Every kind of file the command line writes passes the reference CF checker.

The IOOS compliance-checker (``compliance-checker --test=cf:1.8``, used here through its
Python API) is the reference implementation of the CF conformance rules; a file passes
when none of its checks fails at any priority and none of them raises (a check that
raises did not look at the file: the checker's monotonicity check raises on a
coordinate variable of text, which CF 1.3 forbids).

The files are made by small runs in this process (a few eta points, a few periods, a 6x6
basin grid) through :func:`vibimpact.cli.main`, once per module.  A Zarr map is checked
as the NetCDF file the package makes of it (:func:`vibimpact.maps.open_map` then
:func:`vibimpact.io.write_netcdf`): the checker reads NetCDF only, and Zarr keeps
attributes as JSON, without the types CF's attribute rules are about.
"""
import contextlib
import io as stdio

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.cli import main

N = ["--no-progress", "--workers", "1"]
#: kind -> (command, the -o argument, the file to check)
COMMANDS = {
    "simulate": (["simulate", "--eta", "1.25", "--periods", "5", "--transient", "5"],
                 "sim.nc", "sim.nc"),
    "classify": (["classify", "--eta", "1.0:1.02:0.01", *N, "--direction", "both"],
                 "cls.nc", "cls.nc"),
    "bifurcation": (["bifurcation", "--eta", "1.0:1.02:0.01", *N], "bif.png", "bif.nc"),
    "map_nc": (["map", "--eta", "1.0:1.04:0.02", "--vary", "kh=40:80:40", *N], "map.nc",
               "map.nc"),
    "map_zarr": (["map", "--eta", "1.0:1.04:0.02", "--vary", "kh=40:80:40", *N],
                 "map.zarr", "map.zarr"),
    "continue": (["continue", "--eta", "1.18", "--stop", "1.2", "--approach", "1.1",
                  "--transient", "100"], "cont.nc", "cont.nc"),
    "continue2": (["continue2", "--eta", "1.12", "--approach", "1.1", "--stop1", "1.25",
                   "--kind", "grazing", "--param2", "kh", "--range2", "118:122",
                   "--max-points", "3"], "c2.nc", "c2.nc"),
    "orbits": (["orbits", "--preset", "fig8", "--eta", "1.15", "--period", "1",
                "--random", "4", "--transient", "50", "--window", "0.005",
                "--no-progress"], "orb.nc", "orb.nc"),
    "basins": (["basins", "--eta", "1.06", "--grid", "6x6", "--eps", "2", "--no-progress"],
               "bas.nc", "bas.nc"),
    "attractors": (["attractors", "--eta", "1.06", "--starts", "8", *N], "cen.nc",
                   "cen.nc"),
}


def run(*args):
    """``vibimpact ARGS`` in this process: ``(status, stdout, stderr)``."""
    out, err = stdio.StringIO(), stdio.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main([str(a) for a in args])
        except SystemExit as exc:
            rc = exc.code
    return rc, out.getvalue(), err.getvalue()


_SUITE = []


def cf18_problems(path):
    """Every failed check (``[priority] section: message``) and every check that raised
    (``raised in <check>: <error>``) of compliance-checker's cf:1.8 suite on the NetCDF
    file ``path``; an empty list for a clean file."""
    from compliance_checker.cf.cf_1_8 import CF1_8Check
    from compliance_checker.runner import CheckSuite

    if not _SUITE:  # the cf:1.8 checker alone (loading all of them takes a second)
        suite = CheckSuite()
        suite.checkers = {"cf:1.8": CF1_8Check}
        _SUITE.append(suite)
    suite = _SUITE[0]
    ds = suite.load_dataset(str(path))
    try:
        groups, errors = suite.run_all(ds, ["cf:1.8"], skip_checks=[])["cf:1.8"]
    finally:
        ds.close()
    out = [f"raised in {name}: {err[0]!r}" for name, err in errors.items()]
    for g in groups:
        ok = g.value[0] >= g.value[1] if isinstance(g.value, tuple) else bool(g.value)
        if not ok:
            out += [f"[{g.weight}] {g.name}: {m}" for m in (g.msgs or ["failed"])]
    return out


def as_netcdf(path, tmp):
    """The NetCDF file to check for ``path``: itself, or for a Zarr store the NetCDF file
    that write_netcdf makes of the map open_map reads."""
    if str(path).endswith(".zarr"):
        nc = tmp / (path.name + ".nc")
        vi.io.write_netcdf(vi.maps.open_map(path), nc, overwrite=True)
        return nc
    return path


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """``{kind: path}``: every command of COMMANDS run once in one directory."""
    d = tmp_path_factory.mktemp("cf18")
    out = {}
    for kind, (args, o, checked) in COMMANDS.items():
        rc, _, err = run(*args, "-o", d / o)
        assert rc == 0, (kind, err)
        out[kind] = d / checked
    return out


@pytest.mark.slow
@pytest.mark.parametrize("kind", list(COMMANDS))
def test_every_file_kind_the_cli_writes_passes_cf18(files, kind, tmp_path):
    """Hypothesis: the file of every writing command (simulate, classify, bifurcation,
    map as NetCDF and as Zarr, continue, continue2, orbits, basins, attractors) passes
    every check of compliance-checker's cf:1.8 suite, none of them raising: integers of
    CF-1.8 types only, flags typed as their variables, no text coordinate variable,
    long_name on every variable, the global title."""
    assert cf18_problems(as_netcdf(files[kind], tmp_path)) == []


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["simulate", "classify", "map_zarr", "continue"])
def test_rerun_output_passes_cf18(files, kind, tmp_path):
    """Hypothesis: the file 'vibimpact rerun FILE -o NEW' writes (the command recorded in
    FILE, run again) passes the cf:1.8 suite too, and rerun finds it identical (the
    conversions of the writer are the same on every write)."""
    new = tmp_path / ("again.zarr" if kind == "map_zarr" else "again.nc")
    rc, out, err = run("rerun", files[kind], "-o", new)
    assert rc == 0 and out.startswith("identical: "), (out, err)
    assert cf18_problems(as_netcdf(new, tmp_path)) == []


@pytest.mark.slow
def test_every_file_names_the_paper_and_the_package_and_declares_period_zero(files,
                                                                             tmp_path):
    """Hypothesis: beyond what the checker requires, every file carries the CF
    ``references`` (its model's literature: the paper, for these rotor files), ``source`` (vibimpact and its version) and a ``title``;
    every ``period`` variable that can be 0 declares that value (no period) by
    flag_values = [0] and a flag meaning instead of only in words; every variable on a ``state`` dimension has a
    described ``state`` label.  An orbit's period, never 0, says so by valid_min = 1."""
    import netCDF4

    for kind, path in files.items():
        with netCDF4.Dataset(as_netcdf(path, tmp_path)) as f:
            glob = {a: f.getncattr(a) for a in f.ncattrs()}
            assert glob["references"] == vi.models.get(glob["model"]).references, kind
            assert "Půst" in glob["references"] and "magnetic bearings" in glob[
                "references"], kind
            assert glob["source"] == f"vibimpact {vi.__version__}", kind
            assert glob["title"].startswith("vibimpact"), kind
            for name, var in f.variables.items():
                if name == "period" and "valid_min" in var.ncattrs():
                    assert var.valid_min == 1 and var.size and np.all(var[...] >= 1), kind
                elif name == "period":
                    assert list(np.atleast_1d(var.flag_values)) == [0], kind
                    assert var.flag_meanings == "none", kind
                    assert var.flag_values.dtype == var.dtype, kind
                if name == "state":
                    assert var.long_name.startswith("state variable"), kind


def _messy_dataset():
    """A dataset with every kind of thing CF-1.8 refuses that builders may produce: an
    int64 flag variable with int64 flag_values, an unsigned coordinate, an int64 index
    coordinate and a text dimension coordinate (objects)."""
    import xarray as xr

    return xr.Dataset(
        {"x": (("state", "k"), np.ones((2, 3)), dict(units="1", long_name="x")),
         "code": ("k", np.array([0, 1, 1]), dict(
             long_name="code", flag_values=np.array([0, 1]), flag_meanings="no yes")),
         "count": ("k", np.array([1, 2, 2**40]), dict(long_name="count", units="1"))},
        coords={"state": ("state", np.array(["X", "dX"], dtype=object),
                          dict(long_name="state variable")),
                "k": ("k", np.arange(3, dtype=np.uint16), dict(long_name="k", units="1")),
                "j": ("k", np.arange(3, dtype=np.int64), dict(long_name="j", units="1"))})


def test_writer_makes_any_dataset_cf18_clean_and_reads_it_back(tmp_path):
    """Hypothesis: write_netcdf makes a dataset of CF-1.8-foreign types pass the checker
    (int64 and unsigned integers as int32, flag_values converted with their variable,
    an integer too large for int32 as float64, a text dimension coordinate as
    characters) and read_netcdf gives back the same values and the same text index."""
    ds = _messy_dataset()
    vi.io.write_netcdf(ds, tmp_path / "m.nc")
    assert cf18_problems(tmp_path / "m.nc") == []
    back = vi.io.read_netcdf(tmp_path / "m.nc")
    assert list(back.indexes["state"]) == ["X", "dX"]
    assert back["code"].dtype == np.int32 and back["code"].flag_values.dtype == np.int32
    assert back["count"].values.tolist() == [1, 2, 2**40]
    assert back["k"].values.tolist() == [0, 1, 2] and back["j"].dtype == np.int32
    assert ds["code"].dtype == np.int64 and ds["state"].dtype == object  # ds untouched


def test_checker_finds_what_the_writer_fixes(tmp_path):
    """Hypothesis: the checker is not vacuous: the same dataset written by plain xarray
    fails it: int64 and unsigned types (section 2.2), a check raising on the text
    coordinate variable, and no global title."""
    _messy_dataset().to_netcdf(tmp_path / "plain.nc")
    text = "\n".join(cf18_problems(tmp_path / "plain.nc"))
    for needle in ("datatype is int64", "datatype is uint16",
                   "raised in check_coordinate_variables_strict_monotonicity",
                   "title should exist"):
        assert needle in text, (needle, text)


def test_file_attrs_add_references_source_and_title():
    """Hypothesis: the global attributes of any file name the literature the writer
    passes, else the package (references), the package (source) and say what the file
    holds (title: the dataset's kind or the command), keeping what the dataset already
    says."""
    from vibimpact.base import provenance

    a = provenance.file_attrs({"command": "vibimpact simulate --eta 1.2"}, "test")
    assert a["references"] == provenance.REFERENCES and "vibimpact" in a["references"]
    assert provenance.file_attrs({}, "t", "Shaw 1983")["references"] == "Shaw 1983"
    assert a["source"] == f"vibimpact {vi.__version__}"
    assert a["title"] == "vibimpact simulate output"
    assert provenance.file_attrs({"kind": "census"}, "t")["title"] == "vibimpact census"
    kept = provenance.file_attrs({"title": "mine", "references": "r", "source": "s"}, "t")
    assert (kept["title"], kept["references"], kept["source"]) == ("mine", "r", "s")


@pytest.mark.parametrize("preset", ["fig8", "hard-impact", "soft-impact", "fig11-ring"])
def test_a_file_names_the_literature_of_its_own_model(preset, tmp_path):
    """Hypothesis: a file's CF references is what its model declares (the paper for the
    rotor, Shaw & Holmes for the hard-impact oscillator, ...), each model's own and
    none another's; a model that declares none gets the package's line."""
    p = vi.presets.get(preset)
    model = vi.models.of_params(p)
    run = vi.simulate(p, periods=2, transient=0)
    vi.io.write_netcdf(run.to_dataset(), tmp_path / "r.nc")
    with vi.io.read_netcdf(tmp_path / "r.nc") as ds:
        assert ds.attrs["model"] == model.name
        assert ds.attrs["references"] == model.references != ""
    others = {vi.models.get(n).references for n in vi.models.names()} - {model.references}
    assert model.references not in others


def test_a_file_of_an_unregistered_model_names_the_package():
    """Hypothesis: a file whose model is not registered (a user's) or that names no
    model gets the package's line as its references, never a built-in model's; a user
    model's references must be text."""
    from vibimpact.base import provenance
    from vibimpact.io import _model_references

    for attrs in ({"model": "nobody's"}, {}, {"model": 3}):
        assert _model_references(attrs) is None
        assert provenance.file_attrs(attrs, "t", _model_references(attrs))[
            "references"] == provenance.REFERENCES
    with pytest.raises(TypeError, match="references must be a str"):
        vi.models.Model.from_functions("m", None, None, None, None, None, [1], ("x",),
                                       ("w",), 0, references=3)


def test_a_dataset_read_from_an_int64_file_is_written_cf18_clean(tmp_path):
    """Hypothesis: a dataset read from a file that stores int64 (a file of an older
    vibimpact, or plain xarray) keeps int64 as its stored type; written again by
    write_netcdf it passes the checker all the same, a masked integer variable (read as
    floats with NaN) stored as int32 with its fill value, and reads back the same."""
    import xarray as xr

    plain = tmp_path / "old.nc"
    xr.Dataset({"n": ("k", np.array([1, -1, 3]), dict(_FillValue=-1, long_name="n",
                                                       units="1")),
                "m": ("k", np.array([5, 6, 7]), dict(long_name="m", units="1"))},
               attrs=dict(title="t")).to_netcdf(plain)
    old = vi.io.read_netcdf(plain)
    assert old["m"].encoding["dtype"] == np.int64 and old["n"].dtype == np.float64
    vi.io.write_netcdf(old, tmp_path / "again.nc")
    assert cf18_problems(tmp_path / "again.nc") == []
    back = vi.io.read_netcdf(tmp_path / "again.nc")
    np.testing.assert_array_equal(back["n"].values, [1, np.nan, 3])
    assert back["m"].values.tolist() == [5, 6, 7] and back["m"].dtype == np.int32


@pytest.mark.slow
def test_every_special_value_a_long_name_gives_is_declared(files, tmp_path):
    """Hypothesis: a variable whose long_name gives -1 a meaning ("-1: not counted",
    "-1: none") declares it in CF terms, not only in words: -1 is below its valid_min
    (missing, CF 2.5.1) or one of its flag_values (CF 3.5); every file kind."""
    import netCDF4

    bad = []
    for kind, path in files.items():
        with netCDF4.Dataset(as_netcdf(path, tmp_path)) as f:
            for name, var in f.variables.items():
                text = str(getattr(var, "long_name", ""))
                if "-1:" not in text and "-1 :" not in text:
                    continue
                flags = np.atleast_1d(getattr(var, "flag_values", []))
                low = getattr(var, "valid_min", None)
                if not (-1 in flags.tolist() or (low is not None and low > -1)):
                    bad.append(f"{kind}: {name} ({text})")
    assert bad == []
