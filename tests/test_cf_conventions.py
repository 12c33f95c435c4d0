"""Files that fit the ecosystem: CF attributes, declared flags and provenance in every output.

A small CF checker (:func:`cf_problems`, in the spirit of the CF checker's rules) runs
over the files that ``simulate``, ``classify``, ``bifurcation``, ``map`` (Zarr store
and NetCDF) and ``continue`` write in small runs (a few eta points, a few periods),
read back with netCDF4 or zarr directly, not through xarray's decoding:

* ``Conventions`` (CF-x.y), ``date_created`` (ISO-8601 UTC, written during this test
  run) and ``history`` (lines that start with an ISO-8601 UTC time; the last one holds
  the command line) are present and parse;
* every numeric data variable has ``units`` or is a flag variable whose ``flag_values``
  (the variable's type) and ``flag_meanings`` (valid words) have the same length and
  cover every value present in the data (``period`` declares only its special value 0,
  no period; its other values are periods, at least 1); the integer-coded variables are
  flag variables;
* no coordinate has a ``_FillValue``;
* the provenance attributes are present and true for this process.

The commands run in this process through :func:`vibimpact.cli.main`, as in
tests/test_map2d.py.
"""
import contextlib
import datetime
import io as stdio
import math
import platform
import re
import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.base import provenance
from vibimpact.cli import main

#: integer-coded variables: each must be a CF flag variable where present
CODED = ("regime", "contact", "stable", "impacts_constant", "row_done", "bifurcation_kind")
ETA = ["--eta", "1.0:1.02:0.01", "--no-progress", "--workers", "1"]
COMMANDS = {  # the command, its -o argument, the file it writes
    "simulate": (["simulate", "--eta", "1.25", "--periods", "5", "--transient", "5"],
                 "sim.nc", "sim.nc"),
    "classify": (["classify", *ETA, "--direction", "both"], "cls.nc", "cls.nc"),
    "bifurcation": (["bifurcation", *ETA], "bif.png", "bif.nc"),
    "map_zarr": (["map", "--eta", "1.0:1.04:0.02", "--vary", "kh=40:80:40", "--workers",
                  "1", "--no-progress"], "map.zarr", "map.zarr"),
    "map_nc": (["map", "--eta", "1.0:1.04:0.02", "--vary", "kh=40:80:40", "--workers", "1",
                "--no-progress", "--direction", "both"], "map.nc", "map.nc"),
    # fig8's P1 through its Neimark-Sacker point: both stabilities and one bifurcation
    "continue": (["continue", "--eta", "1.18", "--stop", "1.2", "--approach", "1.1",
                  "--transient", "100"], "cont.nc", "cont.nc"),
}
OUTPUT = {kind: file for kind, (_, _, file) in COMMANDS.items()}


def run(*args):
    """``vibimpact ARGS`` in this process: ``(status, stdout, stderr)``."""
    out, err = stdio.StringIO(), stdio.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main([str(a) for a in args])
        except SystemExit as exc:  # argparse errors
            rc = exc.code
    return rc, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """``(directory, time before the first write)``: every command of COMMANDS run once,
    its output under its own name in the directory; the time is the directory's
    creation, as the file system stamped it (to the second), not a clock read by the
    test (tests/test_no_wall_clock.py)."""
    d = tmp_path_factory.mktemp("cf")
    start = datetime.datetime.fromtimestamp(int(d.stat().st_mtime), datetime.timezone.utc)
    for name, (args, out, _) in COMMANDS.items():
        rc, _, err = run(*args, "-o", d / out)
        assert rc == 0, (name, err)
    return d, start


# --- the checker ------------------------------------------------------------------------

def read_raw(path):
    """``(global attributes, {name: (attributes, values)}, coordinate names)`` of a NetCDF
    file (netCDF4, no masking or scaling) or a Zarr store (zarr), read directly."""
    import xarray as xr

    path = Path(path)
    if path.is_dir():
        import zarr

        group = zarr.open_group(str(path), mode="r")
        variables = {k: (dict(a.attrs), np.asarray(a[...])) for k, a in group.arrays()}
        glob = dict(group.attrs)
        with xr.open_zarr(path, chunks=None) as ds:
            coords = set(ds.coords)
    else:
        import netCDF4

        with netCDF4.Dataset(path) as f:
            f.set_auto_maskandscale(False)
            variables = {k: ({a: v.getncattr(a) for a in v.ncattrs()}, np.asarray(v[...]))
                         for k, v in f.variables.items()}
            glob = {a: f.getncattr(a) for a in f.ncattrs()}
        with xr.open_dataset(path, engine="netcdf4") as ds:
            coords = set(ds.coords)
    return glob, variables, coords


def _utc(text):
    """An ISO-8601 UTC time (``...Z`` or ``+00:00``) as an aware datetime; ValueError
    otherwise."""
    t = datetime.datetime.fromisoformat(str(text).replace("Z", "+00:00"))
    if t.utcoffset() != datetime.timedelta(0):
        raise ValueError(f"{text!r} is not UTC")
    return t


def _global_problems(glob, since, until=None):
    bad = []
    if not re.fullmatch(r"CF-1\.\d+", str(glob.get("Conventions", ""))):
        bad.append(f"Conventions {glob.get('Conventions')!r}")
    try:
        created = _utc(glob["date_created"])
        if since is not None and not since <= created <= (until or created):
            bad.append(f"date_created {created} not between {since} and {until}")
    except (KeyError, ValueError) as exc:
        bad.append(f"date_created: {exc!r}")
    lines = str(glob.get("history", "")).splitlines()
    if not lines:
        bad.append("no history")
    for line in lines:
        try:
            _utc(line.split(" ", 1)[0])
        except ValueError:
            bad.append(f"history line without an ISO-8601 UTC time: {line!r}")
    command = str(glob.get("command", ""))
    if lines and command and not lines[-1].endswith(" " + command):
        bad.append(f"history {lines[-1]!r} does not name the command {command!r}")
    return bad


def _flag_problems(name, attrs, values):
    fv, fm = attrs.get("flag_values"), attrs.get("flag_meanings")
    if fv is None or fm is None:
        return [f"{name}: no flag_values/flag_meanings"]
    fv, words = np.atleast_1d(np.asarray(fv)), str(fm).split()
    bad = []
    if fv.size != len(words) or len(set(fv.tolist())) != fv.size:
        bad.append(f"{name}: {fv.size} flag_values, {len(words)} flag_meanings")
    if any(not re.fullmatch(r"[A-Za-z0-9_.+@-]+", w) for w in words):
        bad.append(f"{name}: flag_meanings {fm!r}")
    # NetCDF keeps the attribute's type; JSON (Zarr) keeps integers that must fit
    if fv.dtype != values.dtype and not (fv.dtype.kind in "iu" and np.array_equal(
            fv.astype(values.dtype), fv)):
        bad.append(f"{name}: flag_values {fv.dtype} for a {values.dtype} variable")
    missing = set(np.unique(values).tolist()) - set(fv.tolist())
    if name == "period":  # flags declare its one special value, 0; the rest are periods
        missing = {v for v in missing if v < 1}
    if missing:
        bad.append(f"{name}: values {sorted(missing)} not in flag_values")
    return bad


def cf_problems(path, since=None):
    """Every violation of the rules of this module's docstring in the file ``path``; an
    empty list for a file that passes.  ``since``: the earliest acceptable date_created;
    the latest is the file's modification time (to the second above), as the file
    system stamped it."""
    glob, variables, coords = read_raw(path)
    until = datetime.datetime.fromtimestamp(math.ceil(Path(path).stat().st_mtime),
                                            datetime.timezone.utc)
    bad = _global_problems(glob, since, until)
    for name, (attrs, values) in variables.items():
        if name in coords:
            if "_FillValue" in attrs:
                bad.append(f"coordinate {name} has _FillValue")
            continue
        if values.dtype.kind not in "biuf":  # text: no units in CF
            continue
        if name in CODED or "flag_values" in attrs:
            bad += _flag_problems(name, attrs, values)
        elif "units" not in attrs:
            bad.append(f"{name}: no units")
    expected = {"vibimpact_version": vi.__version__,
                "python_version": platform.python_version(),
                "numpy_version": np.__version__,
                "cpu_model": provenance.cpu_model()}
    commit, _ = provenance.git_commit()
    if commit is not None:
        expected["vibimpact_git_commit"] = commit
    backend = "zarr_version" if Path(path).is_dir() else "netCDF4_version"
    for key in ("xarray_version", backend, "platform", "source"):
        if not str(glob.get(key, "")):
            bad.append(f"no {key}")
    bad += [f"{k} = {glob.get(k)!r}, expected {v!r}" for k, v in expected.items()
            if str(glob.get(k)) != v]
    return bad


# --- the tests ----------------------------------------------------------------------------

@pytest.mark.parametrize("kind", list(COMMANDS))
def test_every_output_passes_the_cf_checker(written, kind):
    """Hypothesis: the file of every writing command (simulate, classify, bifurcation,
    map as Zarr and as NetCDF, continue) passes every rule of the checker: CF global
    attributes written now, units or complete flag declarations on every numeric
    variable (the bifurcation file holds contact = -1, not computed, and declares it;
    the continue file a Neimark-Sacker bifurcation_kind and both stabilities), no
    _FillValue on coordinates, and true provenance attributes."""
    d, start = written
    assert cf_problems(d / OUTPUT[kind], since=start) == []


def test_the_checker_finds_each_violation(tmp_path):
    """Hypothesis: the checker is not vacuous: a file written by plain xarray with a
    coordinate _FillValue, a variable without units, a flag value missing from
    flag_values and mismatched flag_meanings, and no CF or provenance attributes, is
    reported for each of these."""
    import xarray as xr

    ds = xr.Dataset({"x": ("eta", [1.0, 2.0]),
                     "regime": ("eta", np.array([1, 0], dtype="i1"),
                                dict(flag_values=np.array([1, 2], dtype="i1"),
                                     flag_meanings="periodic"))},
                    coords={"eta": ("eta", [1.0, 1.1], dict(units="1"))})
    ds.to_netcdf(tmp_path / "bad.nc", engine="netcdf4")
    text = "\n".join(cf_problems(tmp_path / "bad.nc"))
    for needle in ("Conventions", "date_created", "no history", "coordinate eta has "
                   "_FillValue", "x: no units", "2 flag_values, 1 flag_meanings",
                   "values [0] not in flag_values", "no source", "vibimpact_version"):
        assert needle in text, (needle, text)


def test_zarr_store_is_consolidated_and_opens_without_warning(written):
    """Hypothesis: the map's Zarr store carries consolidated metadata, so that
    ``xarray.open_zarr(path)`` with no options gives no warning, and the consolidated
    view holds every row with the data of :func:`vibimpact.maps.open_map`."""
    import json

    import xarray as xr

    d, _ = written
    path = d / "map.zarr"
    assert json.loads((path / "zarr.json").read_text()).get("consolidated_metadata")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with xr.open_zarr(path) as ds:
            ds = ds.load()
    ref = vi.maps.open_map(path)
    assert ds.sizes == ref.sizes and ds.sizes["kh"] == 2
    diffs, _ = vi.io.differences(ds, ref)
    assert diffs == []


def test_resumed_map_store_sees_every_row(tmp_path):
    """Hypothesis: a map resumed from a checkpoint that lost a row (the row is computed
    again, the other loaded) writes a consolidated Zarr store whose data, read through the
    consolidated metadata, equal the uninterrupted map bit for bit, every row included."""
    import xarray as xr

    from vibimpact.engine.store import Checkpoint
    from vibimpact.sweeps import SweepSettings

    fast = SweepSettings(transient_max=60, record=32, lyap_min=20, lyap_max=60)
    args = (vi.presets.get("fig8"), np.array([1.0, 1.02, 1.04]), {"kh": [40.0, 80.0, 120.0]})
    ref = vi.map2d(*args, settings=fast)
    store = tmp_path / "ckpt"
    vi.map2d(*args, settings=fast, execution=vi.Execution(checkpoint=store))
    entries = Checkpoint(store).entries()
    assert len(entries) == 3
    (store / entries[1][0]).unlink()
    resumed = vi.map2d(*args, settings=fast,
                       execution=vi.Execution(checkpoint=store, resume=True))
    vi.maps.write_map(resumed, tmp_path / "m.zarr")
    with xr.open_zarr(tmp_path / "m.zarr", consolidated=True, chunks=None) as back:
        back = back.load()
    assert back.sizes["kh"] == 3
    assert vi.io.differences(back, ref)[0] == []


@pytest.mark.parametrize("kind", ["simulate", "classify", "map_zarr", "continue"])
def test_rerun_is_identical_despite_new_time_stamps(written, kind, tmp_path):
    """Hypothesis: 'vibimpact rerun' of a file stamped with date_created and history
    reports identical data, and its recomputed file (-o) carries its own stamps and
    provenance and passes the checker; the time-stamp attributes never enter the
    comparison (a copy with other stamps compares equal)."""
    d, start = written
    path = d / OUTPUT[kind]
    new = tmp_path / ("again.zarr" if kind == "map_zarr" else "again.nc")
    rc, out, err = run("rerun", path, "-o", new)
    assert rc == 0, (out, err)
    assert out.startswith("identical: ")
    assert cf_problems(new, since=start) == []
    old = vi.maps.open_map(path) if kind == "map_zarr" else vi.io.read_netcdf(path)
    other = old.copy()
    other.attrs.update(date_created="1999-01-01T00:00:00Z",
                       history="1999-01-01T00:00:00Z something else")
    assert vi.io.differences(old, other)[0] == []


def test_writers_leave_the_dataset_alone_and_append_history(written, tmp_path):
    """Hypothesis: writing a dataset read from a file adds no attribute to the dataset in
    memory, keeps its date_created and appends one history line (CF: an audit trail)."""
    d, _ = written
    ds = vi.io.read_netcdf(d / "sim.nc")
    before = dict(ds.attrs)
    vi.io.write_netcdf(ds, tmp_path / "copy.nc")
    assert ds.attrs == before
    copy = vi.io.read_netcdf(tmp_path / "copy.nc")
    assert copy.attrs["date_created"] == before["date_created"]
    lines = copy.attrs["history"].splitlines()
    assert lines[:-1] == before["history"].splitlines() and len(lines) == 2


def test_provenance_without_git_never_fails(monkeypatch):
    """Hypothesis: without a git executable the commit is simply not recorded (no error,
    no attribute), and the lookup runs once per process (cached)."""
    calls = []

    def no_git(*args, **kwargs):
        calls.append(args)
        raise FileNotFoundError("git")

    monkeypatch.setattr(provenance.subprocess, "run", no_git)
    assert provenance.git_commit.__wrapped__() == (None, None)
    monkeypatch.setattr(provenance, "git_commit", lambda: (None, None))
    attrs = provenance.file_attrs({}, "test")
    assert "vibimpact_git_commit" not in attrs and attrs["Conventions"].startswith("CF-")
    assert re.fullmatch(r"\S+Z test\(\) called from .*", attrs["history"])
    calls.clear()
    monkeypatch.undo()
    first = provenance.git_commit()
    monkeypatch.setattr(provenance.subprocess, "run", no_git)
    assert provenance.git_commit() == first and calls == []
    if shutil.which("git") and (Path(provenance.__file__).parents[1] / ".git").exists():
        assert first[0] is not None and len(first[0]) == 40
