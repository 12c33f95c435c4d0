"""The command line speaks in its own words: options, never the API's (issue 33).

Hypothesis: whatever refusal a command prints -- bad input, an impossible output, a
request over a limit, an output or a checkpoint that appeared while it computed -- says
what to type on the command line (``--overwrite``, ``--resume``, ``--rtol``, ``-o``),
never how to call the library: no keyword argument (``overwrite=True``, ``periods=5``,
``state0 must ...``), no "pass X=...", no Python name (``Params``, ``vi.sweep``,
``ValueError``, a traceback).

The cases are every case of the bad-input tables (test_bad_input.py, test_bad_output.py,
test_bad_input_messages.py) and, below, the refusals those tables lack, for every command
``vibimpact --help`` lists.  Each runs ``vibimpact.cli.main`` in this process, as
test_bad_input.py does.  The API keeps its own words (tests/test_bad_input_api.py and the
last tests here).
"""
import inspect
import os
import re
from pathlib import Path

import numpy as np
import pytest

import test_bad_input as bad_input
import test_bad_input_messages as bad_messages
import test_bad_output as bad_output
from test_bad_input import CONT, ONE, SIM, run_cli, sweep_as, tiny_sweep_file


# --- what API-only wording looks like ---------------------------------------------------

def _api_keywords():
    """The keyword arguments of the library functions the commands call, and of the
    settings objects they take (solver, execution, continuation), less the model
    parameters (``--set kh=10`` is the command line's own ``NAME=VALUE``) and names
    shorter than three letters."""
    import vibimpact as vi
    from vibimpact import io
    from vibimpact.continuation.branches import follow_branch
    from vibimpact.maps.store import write_map
    from vibimpact.sweeps.start import sweep_start

    names = set()
    for fn in (vi.simulate, vi.sweep, vi.map2d, io.write_netcdf, io.check_output_path,
               write_map, sweep_start, follow_branch, vi.SolverSettings, vi.Execution,
               vi.Continuation):
        names |= set(inspect.signature(fn).parameters)
    return sorted(names - set(vi.presets.get("fig8").as_dict()) - {"eta"}, key=len)[::-1]


def _cli_dests():
    """The names of the options of every command, as the API would spell them."""
    from vibimpact.cli import build_parser

    dests = set()
    sub = next(a for a in build_parser()._actions if a.dest == "command")
    for parser in sub.choices.values():
        dests |= {a.dest for a in parser._actions if a.option_strings}
    return dests


KEYWORDS = [k for k in _api_keywords() if len(k) >= 3]
#: API arguments that are also options of the command line: their bare names
SHARED = sorted(set(KEYWORDS) & _cli_dests(), key=len)[::-1]

API_ONLY = [
    r"\w+=(True|False|None)\b",                      # overwrite=True, resume=False
    r"\bpass \w+=",                                  # pass resume=...
    r"(?<![-\w])(%s)=" % "|".join(KEYWORDS),         # periods=5, state0=, checkpoint=
    # an option named as the API's argument: 'rtol must be', 'state0 must', 'blocks:'
    r"(?<![-\w])(%s)(\s+must\b|:)" % "|".join(SHARED),
    r"\bkeyword argument",
    r"\b(vi|vibimpact)\.[A-Za-z_]",                  # vi.sweep, vibimpact.Params
    r"\b(Params|DuffingParams|System|SweepSettings|Steps|SweepStart)\b",
    r"\b[A-Z]\w*(Error|Exception)\b",                # ValueError, OSError, KeyError
    r"Traceback",
]


def api_wording(text):
    """The API-only phrases of ``text`` (empty when it speaks the command line's)."""
    return [m.group(0) for pattern in API_ONLY for m in re.finditer(pattern, text)]


def test_the_patterns_catch_api_wording_and_pass_the_cli_s():
    """The patterns flag the API's words (the messages this issue found) and none of
    the command line's own (a false positive would hide nothing, but a pattern that
    flags nothing would make every case below pass without testing anything)."""
    for text in ("output file 'r.nc' exists; pass overwrite=True to replace it",
                 "checkpoint c.partial already exists: pass resume=True (--resume)",
                 "periods=1000000000 (+ transient=500) is 1000000500 forcing periods",
                 "periods=5 with dense=1000000000 needs about 373 GiB",
                 "rtol must be finite and > 0, got -1.0",
                 "state0 must be 4 finite numbers, got [nan, 0.0, 0.0, 0.0]",
                 "blocks must be <= 100000, got 200000",
                 "direction: the sweep has up and down; give one",
                 "cannot draw intervals from 'c.nc': ValueError: no label",
                 "cannot read 'bad.nc' as NetCDF: OSError: [Errno -51] NetCDF: ...",
                 "p must be vibimpact.Params, got str",
                 "call vi.sweep(p, eta) instead"):
        assert api_wording(text), text
    for text in ("output file 'r.nc' exists; pass --overwrite to replace it",
                 "checkpoint 'c.nc.partial' exists (an interrupted run); pass --resume "
                 "to continue it, or remove it",
                 "--set kh given twice (kh=10 and kh=200); give each parameter once",
                 "argument --rtol: must be a finite number > 0, got '-1'",
                 "--periods 1000000000 + --transient 500 is 1000000500 forcing periods",
                 "kh must be >= 0, got -1.0", "eta must be > 0, got 0.0",
                 "--from 's.nc': --direction: the sweep has up and down; give one",
                 "'c.nc' was written by 'simulate --from' but it records no start from a "
                 "sweep (missing start_sweep, state0)",
                 "cannot write 'r.nc': No space left on device",
                 "--vary kh: kh must be >= 0, got -10.0"):
        assert not api_wording(text), (text, api_wording(text))


# --- the cases: every table of the bad-input suite, then the refusals they lack ---------

def _tabled():
    """``{id: (argv, setup)}`` of every case of the bad-input tables."""
    cases = {}
    for name, table in (("input", bad_input.CLI_CASES), ("limits", bad_output.LIMITS),
                        ("messages", bad_messages.CASES)):
        for case, (argv, _needle, setup) in table.items():
            cases[f"{name}: {case}"] = (argv, setup)
    for command, output in bad_output.CASES:
        argv, out, _needle, setup, make = bad_output._case(command, output)
        if out == "/dev/full":
            argv = [*argv, "--overwrite"]

        def both(d, setup=setup, make=make, out=out):
            if setup is not None:
                setup(d)
            if make is not None:
                make(d, out)
        cases[f"output: {command}, {output}"] = (argv, both)
    return cases


def _file(name, text="old"):
    return lambda d: (Path(d) / name).write_text(text)


def _dir(name, *files):
    def make(d):
        (Path(d) / name).mkdir()
        for f in files:
            (Path(d) / name / f).write_text("{}")
    return make


def _recorded(command):
    return lambda d: tiny_sweep_file(Path(d) / "c.nc", command=command)


def _damaged_branch(d):
    """A file that says it is a 'vibimpact continue' branch but holds none of its
    variables: drawing it fails inside the plotting function."""
    import xarray as xr

    from vibimpact.continuation import branches
    from vibimpact.io import write_netcdf

    ds = xr.Dataset(coords={"eta": ("point", [1.1, 1.2])},
                    attrs={"title": branches._TITLE, "continuation_param": "eta"})
    write_netcdf(ds, Path(d) / "b.nc")


BIF = ["bifurcation", "--eta", "1:1.01:0.01", "--no-progress"]
MAP = ["map", "--eta", "1,1.1", "--vary", "kh=10,20", "--workers", "1", "--no-progress"]
REC = "vibimpact simulate --eta 1.2 --periods 5 --transient 5"

#: the refusals the tables lack: id -> (argv, setup)
EXTRA = {
    # presets and the main parser
    "presets: an unknown option": (["presets", "--eta", "1"], None),
    "main: an unknown command": (["sweep"], None),
    # simulate: each option's bad values
    "simulate: --rtol < 0": ([*SIM, "--rtol", "-1", "-o", "r.nc"], None),
    "simulate: --rtol 0": ([*SIM, "--rtol", "0", "-o", "r.nc"], None),
    "simulate: --rtol NaN": ([*SIM, "--rtol", "nan", "-o", "r.nc"], None),
    "simulate: --atol inf": ([*SIM, "--atol", "inf", "-o", "r.nc"], None),
    "simulate: --atol < 0": ([*SIM, "--atol", "-1e-12", "-o", "r.nc"], None),
    "simulate: --state0 NaN": ([*SIM, "--state0", "nan", "0", "0", "0", "-o", "r.nc"],
                               None),
    "simulate: --state0 inf": ([*SIM, "--state0", "0", "inf", "0", "0", "-o", "r.nc"],
                               None),
    "simulate: --eta NaN": (["simulate", "--eta", "nan", "-o", "r.nc"], None),
    "simulate: --eta inf": (["simulate", "--eta", "inf", "-o", "r.nc"], None),
    "simulate: --periods 0": ([*SIM, "--periods", "0", "-o", "r.nc"], None),
    "simulate: --method": ([*SIM, "--method", "euler", "-o", "r.nc"], None),
    "simulate: --periods + --transient over the limit": (
        ["simulate", "--periods", "9000000", "--transient", "2000000", "-o", "r.nc"], None),
    "simulate: existing --plot image": ([*SIM, "-o", "r.nc", "--plot", "xy.png"],
                                        _file("xy.png")),
    # classify
    "classify: --blocks over the limit": ([*ONE, "--blocks", "200000", "-o", "c.nc"],
                                          None),
    "classify: --workers 0": ([*ONE, "--workers", "0", "-o", "c.nc"], None),
    "classify: existing checkpoint without --resume": ([*ONE, "-o", "c.nc"],
                                                       _dir("c.nc.partial")),
    "classify: --resume onto a directory that is no checkpoint": (
        [*ONE, "-o", "c.nc", "--resume"], _dir("c.nc.partial")),
    "classify: --resume of another request": (
        [*ONE, "-o", "c.nc", "--resume"],
        lambda d: (_dir("c.nc.partial")(d), (Path(d) / "c.nc.partial" / "request.json")
                   .write_text('{"kind": "sweep", "fingerprint": "0"}'))),
    "classify: --analyses empty": ([*ONE, "--analyses", ",", "-o", "c.nc"], None),
    # bifurcation
    "bifurcation: existing data file": ([*BIF, "-o", "b.png"], _file("b.nc")),
    "bifurcation: --blocks over the limit": ([*BIF, "--blocks", "200000", "-o", "b.png"],
                                             None),
    "bifurcation: --workers 0": ([*BIF, "--workers", "0", "-o", "b.png"], None),
    # map
    "map: existing Zarr store": ([*MAP, "-o", "m.zarr"], _dir("m.zarr", "zarr.json")),
    "map: existing directory": ([*MAP, "-o", "m.zarr"], _dir("m.zarr")),
    "map: existing .nc": ([*MAP, "-o", "m.nc"], _file("m.nc")),
    "map: existing checkpoint without --resume": ([*MAP, "-o", "m.zarr"],
                                                  _dir("m.zarr.partial")),
    "map: --resume onto a directory that is no checkpoint": (
        [*MAP, "-o", "m.zarr", "--resume"], _dir("m.zarr.partial")),
    "map: unknown extension": ([*MAP, "-o", "m.txt"], None),
    "map: --vary out of the domain": ([*MAP[:3], "--vary", "f=-1,0.1", "-o", "m.zarr"],
                                      None),
    "map: --vary reversed": ([*MAP[:3], "--vary", "kh=20:10:1", "-o", "m.zarr"], None),
    "map: --vary unknown name": ([*MAP[:3], "--vary", "kq=1,2", "-o", "m.zarr"], None),
    "map: --vary eta": ([*MAP[:3], "--vary", "eta=1,2", "-o", "m.zarr"], None),
    "map: --vary twice": ([*MAP, "--vary", "f=0,0.1", "-o", "m.zarr"], None),
    "map: --vary and --set of one name": ([*MAP, "--set", "kh=5", "-o", "m.zarr"], None),
    "map: too many points": (["map", "--eta", "0.5:1.5:0.0001", "--vary", "kh=1:100:0.1",
                              "-o", "m.zarr"], None),
    "map: --scheduler with --workers": (["map", "--eta", "1,1.1", "--vary", "kh=10,20",
                                         "--scheduler", "x", "--workers", "2", "-o",
                                         "m.zarr"], None),
    "map: --scheduler not an address": ([*MAP[:5], "--scheduler", "nofile.json", "-o",
                                         "m.zarr"], None),
    "map: --task-points 0": ([*MAP, "--task-points", "0", "-o", "m.zarr"], None),
    "map: existing --plot image": ([*MAP, "--plot", "m.png", "-o", "m.zarr"],
                                   _file("m.png")),
    "map: --plot unknown extension": ([*MAP, "--plot", "m.txt", "-o", "m.zarr"], None),
    # continue
    "continue: --state0 NaN": ([*CONT, "--state0", "nan", "0", "0", "0", "-o", "b.nc"],
                               None),
    "continue: --eta inf": (["continue", "--eta", "inf", "--stop", "1.2", "-o", "b.nc"],
                            None),
    "continue: --ds inf": ([*CONT, "--ds", "inf", "-o", "b.nc"], None),
    "continue: --refine NaN": ([*CONT, "--refine", "nan", "-o", "b.nc"], None),
    "continue2: --kind hopf": (["continue2", "--kind", "hopf", "--param2", "kh",
                                "--range2", "110:130", "-o", "c.nc"], None),
    "continue2: --range2 inf": (["continue2", "--kind", "fold", "--param2", "kh",
                                 "--range2", "110:inf", "-o", "c.nc"], None),
    "attractors: --eta decreasing": (["attractors", "--eta", "1.1:1.0:0.01", "-o", "c.nc"],
                                     None),
    "attractors: --set unknown": (["attractors", "--set", "zz=1", "-o", "c.nc"], None),
    "orbits: --period 0": (["orbits", "--period", "0", "-o", "o.nc"], None),
    "orbits: --window 0": (["orbits", "--window", "0", "-o", "o.nc"], None),
    "basins: --grid 0x10": (["basins", "--grid", "0x10", "-o", "b.nc"], None),
    "basins: --plane X,X": (["basins", "--plane", "X,X", "-o", "b.nc"], None),
    # rerun: the recorded command's refusals, said as a command line would
    "rerun: existing -o": (["rerun", "c.nc", "-o", "n.nc"],
                           lambda d: (tiny_sweep_file(Path(d) / "c.nc"),
                                      _file("n.nc")(d))),
    "rerun: recorded --state0 NaN": (["rerun", "c.nc"],
                                     _recorded(f"{REC} --state0 nan 0 0 0 -o c.nc")),
    "rerun: recorded --rtol < 0": (["rerun", "c.nc"],
                                   _recorded(f"{REC} --rtol -1 -o c.nc")),
    "rerun: recorded --periods over the limit": (
        ["rerun", "c.nc"], _recorded("vibimpact simulate --periods 1000000000 -o c.nc")),
    "rerun: recorded --blocks over the limit": (
        ["rerun", "c.nc"], _recorded("vibimpact classify --eta 1:1.01:0.01 --blocks "
                                     "200000 -o c.nc")),
    "rerun: recorded 'simulate --from' without its start": (
        ["rerun", "c.nc"], _recorded(f"{REC} --from s.nc -o c.nc")),
    "rerun: recorded unknown option": (["rerun", "c.nc"],
                                       _recorded(f"{REC} --speed 3 -o c.nc")),
    "rerun: recorded command unparsable": (["rerun", "c.nc"],
                                           _recorded("vibimpact 'unbalanced")),
    # plot
    "plot: existing image": (["plot", "c.nc"],
                             lambda d: (tiny_sweep_file(Path(d) / "c.nc"),
                                        _file("c_response.png")(d))),
    # a sweep file without labels: drawing its intervals fails inside the plotting
    "plot: intervals of a file without labels": (["plot", "c.nc", "--kind", "intervals",
                                                  "-o", "i.png"], sweep_as("c.nc")),
    "plot: a directory that is no Zarr store": (["plot", "d.zarr"], _dir("d.zarr")),
    "plot: a damaged Zarr store": (["plot", "d.zarr", "--kind", "map"],
                                   lambda d: (_dir("d.zarr")(d), (Path(d) / "d.zarr" /
                                              "zarr.json").write_text("{ not json"))),
    "plot: --kind map of a sweep": (["plot", "c.nc", "--kind", "map"], sweep_as("c.nc")),
    "plot: --kind xy of a sweep": (["plot", "c.nc", "--kind", "xy"], sweep_as("c.nc")),
    "plot: a damaged branch file": (["plot", "b.nc", "-o", "b.png"], _damaged_branch),
}

ALL = {**_tabled(), **{f"extra: {k}": v for k, v in EXTRA.items()}}


def _run(argv, setup, d, monkeypatch, capfd):
    if setup is not None:
        setup(d)
    monkeypatch.chdir(d)
    try:
        return run_cli(argv, capfd)
    finally:
        if (d / "ro").exists():
            (d / "ro").chmod(0o700)


@pytest.mark.parametrize("case", [
    pytest.param(c) for c in ALL])
def test_a_refusal_names_options_not_api_arguments(case, tmp_path, monkeypatch, capfd):
    """Every refusal of every command (exit status 2) says it in the command line's
    words: no keyword argument, no 'pass X=', no Python name, no traceback."""
    argv, setup = ALL[case]
    rc, out, err = _run(argv, setup, tmp_path, monkeypatch, capfd)
    assert rc == 2, (rc, out, err)
    assert "vibimpact: error: " in err, err
    assert not api_wording(err + out), (api_wording(err + out), err)


def test_every_command_has_refusals_in_the_scan():
    """The scan covers every command of ``vibimpact --help``: each has a case."""
    from vibimpact.cli import build_parser

    sub = next(a for a in build_parser()._actions if a.dest == "command")
    scanned = {next((a for a in argv if not a.startswith("-")), None)
               for argv, _ in ALL.values()}
    assert set(sub.choices) <= scanned, set(sub.choices) - scanned


# --- races: an output or a checkpoint that appears while the command computes -----------

def _output_appears_on_write(monkeypatch, name):
    """``name`` appears (as an unrelated file) the moment a NetCDF writer has vetted
    its path: another process took the name while the command computed."""
    import vibimpact.io as vio

    original = vio.for_file

    def for_file(ds, call):
        if not os.path.lexists(name):
            Path(name).write_text("someone else's")
        return original(ds, call)
    monkeypatch.setattr(vio, "for_file", for_file)


def _store_appears_on_compute(monkeypatch, name):
    """The Zarr store ``name`` appears while the map computes."""
    import importlib

    # vibimpact.maps.map2d is also the name of the function the package exports
    m = importlib.import_module("vibimpact.maps.map2d")
    original = m.map2d

    def map2d(*args, **kwargs):
        ds = original(*args, **kwargs)
        _dir(name, "zarr.json")(".")
        return ds
    monkeypatch.setattr(m, "map2d", map2d)


def _checkpoint_appears_after_the_check(monkeypatch, name):
    """The checkpoint ``name`` appears between the command's check and the run."""
    from vibimpact.engine.store import Checkpoint

    original = Checkpoint.check_reusable

    def check_reusable(self, resume):
        original(self, resume)
        os.makedirs(name, exist_ok=True)
    monkeypatch.setattr(Checkpoint, "check_reusable", check_reusable)


RACES = {
    "simulate": ([*SIM, "-o", "r.nc"], _output_appears_on_write, "r.nc"),
    "classify": ([*ONE, "-o", "c.nc"], _output_appears_on_write, "c.nc"),
    "bifurcation": ([*BIF, "-o", "b.png"], _output_appears_on_write, "b.nc"),
    "map .nc": ([*MAP, "-o", "m.nc"], _output_appears_on_write, "m.nc"),
    "map .zarr": ([*MAP, "-o", "m.zarr"], _store_appears_on_compute, "m.zarr"),
    "rerun -o": (["rerun", "r.nc", "-o", "n.nc"], _output_appears_on_write, "n.nc"),
    "continue": ([*CONT, "--max-points", "3", "-o", "b.nc"], _output_appears_on_write,
                 "b.nc"),
    "classify checkpoint": ([*ONE, "-o", "c.nc"], _checkpoint_appears_after_the_check,
                            "c.nc.partial"),
    "map checkpoint": ([*MAP, "-o", "m.zarr"], _checkpoint_appears_after_the_check,
                       "m.zarr.partial"),
}


@pytest.mark.parametrize("argv,appear,name", [
    pytest.param(*v, id=k)
    for k, v in RACES.items()])
def test_a_refusal_at_write_time_names_options(argv, appear, name, tmp_path, monkeypatch,
                                               capfd):
    """An output or checkpoint that appears while the command computes is refused by
    the writer (never clobbered); the line names --overwrite or --resume, not the API's
    overwrite=True or resume=True."""
    monkeypatch.chdir(tmp_path)
    if argv[0] == "rerun":  # a small run file to rerun
        rc, _, err = run_cli([*SIM, "-o", "r.nc"], capfd)
        assert rc == 0, err
    appear(monkeypatch, name)
    rc, out, err = run_cli(argv, capfd)
    assert rc == 2, (rc, out, err)
    assert "vibimpact: error: " in err and ("--overwrite" in err or "--resume" in err), err
    assert not api_wording(err + out), (api_wording(err + out), err)
    assert Path(name).exists()  # the other file is left alone


# --- the API keeps its own words ------------------------------------------------------

def test_the_api_still_says_overwrite_true(tmp_path, monkeypatch):
    """The writers' refusal, called from Python, names the keyword argument: an API
    caller reads overwrite=True, not --overwrite (also when the file appeared while
    the dataset was written)."""
    import xarray as xr

    from vibimpact.io import check_output_path, write_netcdf
    from vibimpact.maps.store import write_map

    (tmp_path / "x.nc").write_text("old")
    (tmp_path / "m.zarr").mkdir()
    ds = xr.Dataset({"x": ("i", [1.0])})
    for call in (lambda: write_netcdf(ds, tmp_path / "x.nc"),
                 lambda: write_map(ds, tmp_path / "m.zarr"),
                 lambda: check_output_path(tmp_path / "x.nc")):
        with pytest.raises(ValueError, match=r"exists; pass overwrite=True to replace it"):
            call()
    monkeypatch.chdir(tmp_path)
    _output_appears_on_write(monkeypatch, "late.nc")
    with pytest.raises(ValueError, match=r"'late.nc' exists; pass overwrite=True"):
        write_netcdf(ds, "late.nc")
    assert (tmp_path / "late.nc").read_text() == "someone else's"


def test_the_api_still_says_resume_true(tmp_path):
    """A sweep or map onto an existing checkpoint without resume names resume=True."""
    import vibimpact as vi

    (tmp_path / "ck").mkdir()
    with pytest.raises(ValueError, match=r"already exists.*pass resume=True"):
        vi.sweep(vi.presets.get("fig8"), [1.0],
                 execution=vi.Execution(checkpoint=tmp_path / "ck"))
    with pytest.raises(ValueError, match=r"already exists.*pass resume=True"):
        vi.map2d(vi.presets.get("fig8"), [1.0], {"kh": np.array([10.0])},
                 execution=vi.Execution(checkpoint=tmp_path / "ck"))


def test_a_failed_start_of_continuation_is_structured_not_parsed():
    """The API's refusal of a continuation start without an orbit is a StartFailed
    (a ValueError naming state0, with the shooting's reason as data), so the command line
    words it from the data (no message text matched): shooting a period-7 orbit from a
    state thirty clearances out fails, and the exception carries why."""
    import numpy as np

    import vibimpact as vi
    from vibimpact.analysis import StartFailed, Steps, continue_orbit

    system = vi.System(vi.presets.get("fig8").replace(eta=1.23))
    with pytest.raises(StartFailed) as info:
        continue_orbit(system, np.array([30.0, 0.0, 0.0, 0.0]), 7, stop=1.24,
                       steps=Steps(max_points=2))
    assert str(info.value).startswith("state0: shooting failed at the start (")
    assert info.value.reason and info.value.reason in str(info.value)


@pytest.mark.parametrize("argv", [
    ["simulate", "--eta", "1.2", "--set", "BT=-1", "-o", "x.nc"],
    ["classify", "--eta", "1.0:1.1:0.05", "--set", "BT=-1", "-o", "x.nc"],
    ["bifurcation", "--eta", "1.0:1.1:0.05", "--set", "BT=-1", "-o", "x.png"],
    ["map", "--eta", "1.0:1.1:0.05", "--vary", "kh=50,60", "--set", "BT=-1", "-o", "x.zarr"],
    ["continue", "--eta", "1.12", "--stop", "1.2", "--set", "BT=-1", "-o", "x.nc"],
], ids=["simulate", "classify", "bifurcation", "map", "continue"])
def test_a_set_value_outside_its_domain_names_the_option_in_every_command(argv, tmp_path,
                                                                          monkeypatch):
    """Every command that takes --set refuses a value outside its parameter's domain in
    one line naming the option and the rule (one helper, cli.common.args.with_sets, for
    all), before any work: nothing is written."""
    from test_continue_cli import run

    monkeypatch.chdir(tmp_path)
    rc, out, err = run(*argv)
    assert rc == 2 and out == ""
    assert err.splitlines() == ["vibimpact: error: --set BT: BT must be >= 0, got -1.0"]
    assert not list(tmp_path.iterdir())
