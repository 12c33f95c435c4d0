"""Bad input, damaged files and reproducibility (issue 7): every refusal is one clear line.

CLI cases run ``vibimpact.cli.main`` in this process (fast) and check: exit status 2,
exactly one stderr line starting with ``vibimpact: error:`` that names the problem, no
traceback, nothing on stdout, and no new file (output, partial or temporary) in the
working directory.  API cases check for a ``ValueError`` whose message names the
parameter.  Then: a grid whose STOP is off the grid is accepted; ``vibimpact rerun``
reproduces simulate, classify and bifurcation outputs bit for bit and reports an altered
file; a checkpoint with damaged point files resumes to the uninterrupted result.
"""
import math
import os
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

from vibimpact.cli import main

SIM = ["simulate", "--eta", "1.2", "--periods", "5", "--transient", "5"]
FROM = ["simulate", "--from", "s.nc", "--eta", "1.25", "--periods", "5", "--transient", "5"]
ONE = ["classify", "--eta", "1.0:1.0:0.01", "--no-progress", "--workers", "1"]
CONT = ["continue", "--eta", "1.12", "--stop", "1.25"]


def run_cli(argv, capfd):
    """main(argv) in this process -> (status, stdout, stderr); SystemExit is a status."""
    try:
        rc = main([str(a) for a in argv])
    except SystemExit as exc:
        rc = exc.code
    out, err = capfd.readouterr()
    return rc, out, err


def listing(d):
    return sorted(p.name for p in Path(d).iterdir())


def assert_refused(rc, out, err, needle):
    assert rc == 2, (rc, out, err)
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("vibimpact: error: "), lines[0]
    assert needle in lines[0], (needle, lines[0])
    assert "Traceback" not in err and out == ""


# --- files the cases start from ---------------------------------------------------------

def _tiny_sweep_file(path, command="vibimpact classify --eta 1.0:1.01:0.01 -o c.nc"):
    import xarray as xr

    from vibimpact.io import write_netcdf

    ds = xr.Dataset({"regime": ("eta", np.array([1, 3], dtype="i1")),
                     "X_m": ("eta", [0.5, np.nan]),
                     "poincare_X": (("eta", "sample"), np.ones((2, 64)))},
                    coords={"eta": [1.0, 1.01]}, attrs={"command": command})
    write_netcdf(ds, path)


def _sweep_as(name):
    def make(d):
        _tiny_sweep_file(Path(d) / name)
    return make


def _garbage(d, name="bad.nc"):
    (Path(d) / name).write_bytes(b"this is not a NetCDF file\n" * 20)


def _garbage_as(name):
    return lambda d: _garbage(d, name)


def _empty(d, name="bad.nc"):
    (Path(d) / name).write_bytes(b"")


def _truncated(d, name="bad.nc"):
    full = Path(d) / ".full.nc"
    _tiny_sweep_file(full)
    data = full.read_bytes()
    full.unlink()
    (Path(d) / name).write_bytes(data[: len(data) // 2])


def _foreign(d, name="bad.nc"):
    """A valid NetCDF file that vibimpact did not write (no command, other variables)."""
    import xarray as xr

    xr.Dataset({"temperature": ("time", np.arange(5.0))}).to_netcdf(Path(d) / name)


def _foreign_command(d, name="bad.nc"):
    _tiny_sweep_file(Path(d) / name, command="rm -rf /")


def _png_as_nc(d, name="bad.nc"):
    (Path(d) / name).write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(200))


def _existing(name):
    def make(d):
        (Path(d) / name).write_bytes(b"old")
    return make


def _checkpoint(request_text):
    def make(d):
        ck = Path(d) / "c.nc.partial"
        ck.mkdir()
        (ck / "request.json").write_text(request_text)
    return make


def _directory(name):
    def make(d):
        (Path(d) / name).mkdir()
    return make


def _damaged_store(d):
    store = Path(d) / "m.zarr"
    store.mkdir()
    (store / "zarr.json").write_text("{ not json")


def _checkpoint_file(d):
    (Path(d) / "c.nc.partial").write_text("not a directory")


def _readonly_dir(d):
    ro = Path(d) / "ro"
    ro.mkdir()
    ro.chmod(0o500)


def _unwritable_target():
    """A directory this process cannot write to: a read-only dir, or /sys for root."""
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        return "/sys/vibimpact_test_out.nc"
    return "ro/out.nc"


def _sweep_ds(direction):
    """A small fig8 sweep (eta 1.1, 1.25; period only), computed once per direction."""
    import vibimpact as vi

    if direction not in _SWEEPS:
        _SWEEPS[direction] = vi.sweep(vi.presets.get("fig8"), [1.1, 1.25],
                                      direction=direction, analyses=("period",),
                                      workers=1, progress=False)
    return _SWEEPS[direction].copy(deep=True)


_SWEEPS = {}


def _sweep_file(direction="up", regime=None, **attrs):
    """``s.nc``: the small sweep, the point at 1.25 set to ``regime`` (its final_state
    NaN, as the sweep leaves a point not computed or diverged), ``attrs`` added."""
    def make(d):
        from vibimpact.io import write_netcdf

        ds = _sweep_ds(direction)
        if regime is not None:
            ds["regime"].values[..., 1] = regime
            ds["final_state"].values[..., 1, :] = np.nan
        ds.attrs.update(attrs)
        write_netcdf(ds, Path(d) / "s.nc")
    return make


def _run_file(d):
    """``r.nc``: a simulate run, not a sweep."""
    import vibimpact as vi

    vi.io.write_netcdf(vi.simulate(vi.presets.get("fig8").replace(eta=1.25), periods=3),
                       Path(d) / "r.nc")


# --- CLI: id -> (argv, needle, setup) ----------------------------------------------------

CLI_CASES = {
    # eta ranges
    "eta reversed": (["classify", "--eta", "1.2:1.0:0.01", "-o", "c.nc"], "eta", None),
    "eta zero step": (["classify", "--eta", "1.0:1.2:0", "-o", "c.nc"], "eta", None),
    "eta negative step": (["classify", "--eta", "1.0:1.2:-0.01", "-o", "c.nc"], "eta", None),
    "eta negative start": (["classify", "--eta", "-1:1.2:0.1", "-o", "c.nc"], "eta", None),
    "eta NaN": (["classify", "--eta", "nan:1.2:0.01", "-o", "c.nc"], "eta", None),
    "eta inf": (["classify", "--eta", "1:inf:0.01", "-o", "c.nc"], "eta", None),
    "eta non-numeric": (["classify", "--eta", "a:b:c", "-o", "c.nc"], "eta", None),
    "eta two parts": (["classify", "--eta", "1.0:1.2", "-o", "c.nc"], "eta", None),
    "eta 1e9 points": (["classify", "--eta", "0.5:1000000000.5:1", "-o", "c.nc"],
                       "1000000001 points (about", None),
    "eta step too small": (["classify", "--eta", "1:2:1e-320", "-o", "c.nc"], "eta", None),
    # a STEP (or START) below the 12-decimal rounding of a range: repeated values or 0,
    # once refused by the grid check without naming --eta, blaming the direction
    "eta step below rounding": (["classify", "--eta", "1:1.000000000001:1e-13", "-o",
                                 "c.nc"], "--eta: eta STEP must be >= 1e-12", None),
    "eta start below rounding": (["classify", "--eta", "1e-13:1e-12:1e-13", "-o", "c.nc"],
                                 "--eta: eta START must be >= 1e-12", None),
    "eta step below rounding (map)": (["map", "--eta", "1:1.000000000001:1e-13", "--vary",
                                       "kh=10,20", "-o", "m.zarr"], "--eta: eta STEP",
                                      None),
    "eta list decreasing": (["classify", "--eta", "1.2,1.1", "-o", "c.nc"], "eta", None),
    "eta list repeated": (["classify", "--eta", "1.1,1.1", "-o", "c.nc"], "eta", None),
    "eta list non-numeric": (["classify", "--eta", "1.0,x", "-o", "c.nc"], "eta", None),
    "eta list empty item": (["classify", "--eta", "1.0,,1.2", "-o", "c.nc"], "eta", None),
    "eta list NaN": (["classify", "--eta", "1.0,nan", "-o", "c.nc"], "eta", None),
    "eta list zero": (["classify", "--eta", "0,1.0", "-o", "c.nc"], "eta", None),
    "eta list (map)": (["map", "--eta", "1.2,1.0", "--vary", "kh=10,20", "-o", "m.zarr"],
                       "eta", None),
    "bifurcation reversed": (["bifurcation", "--eta", "2:1:0.1", "-o", "b.png"], "eta",
                             None),
    # names
    "unknown preset (classify)": ([*ONE, "--preset", "fig99", "-o", "c.nc"], "fig99", None),
    "unknown preset (simulate)": ([*SIM, "--preset", "fig99", "-o", "r.nc"], "fig99", None),
    "unknown parameter (classify)": ([*ONE, "--set", "kq=1", "-o", "c.nc"], "kq", None),
    "unknown parameter (simulate)": ([*SIM, "--set", "kq=1", "-o", "r.nc"], "kq", None),
    "unknown analysis": ([*ONE, "--analyses", "period,spectrum", "-o", "c.nc"],
                         "spectrum", None),
    "unknown direction": ([*ONE, "--direction", "sideways", "-o", "c.nc"], "sideways", None),
    "unknown plot kind": (["plot", "x.nc", "--kind", "spectrum"], "spectrum", None),
    # the model's domain
    "kh < 0": ([*SIM, "--set", "kh=-1", "-o", "r.nc"], "kh", None),
    "B < 0": ([*SIM, "--set", "B=-0.1", "-o", "r.nc"], "B ", None),
    "Bh < 0": ([*SIM, "--set", "Bh=-0.05", "-o", "r.nc"], "Bh", None),
    "BT < 0": ([*SIM, "--set", "BT=-0.05", "-o", "r.nc"], "BT", None),
    "f < 0": ([*SIM, "--set", "f=-0.1", "-o", "r.nc"], "f ", None),
    "Ec < 0": ([*ONE, "--set", "Ec=-0.1", "-o", "c.nc"], "Ec", None),
    "eta = 0": ([*SIM[:1], "--eta", "0", "-o", "r.nc"], "eta", None),
    "eta < 0": ([*SIM[:1], "--eta", "-1.2", "-o", "r.nc"], "eta", None),
    "G NaN": ([*SIM, "--set", "G=nan", "-o", "r.nc"], "G", None),
    "kh inf": ([*ONE, "--set", "kh=inf", "-o", "c.nc"], "kh", None),
    # absurd sizes
    "periods 1e9": (["simulate", "--periods", "1000000000", "-o", "r.nc"],
                    "periods=1000000000", None),
    "transient 1e9": (["simulate", "--transient", "1000000000", "-o", "r.nc"], "about",
                      None),
    # output
    "unwritable directory": ([*SIM, "-o", _unwritable_target()], "not writable",
                             _readonly_dir),
    "existing output (simulate)": ([*SIM, "-o", "r.nc"], "--overwrite", _existing("r.nc")),
    "existing output (classify)": ([*ONE, "-o", "c.nc"], "--overwrite", _existing("c.nc")),
    "existing image (bifurcation)": (["bifurcation", "--eta", "1:1.01:0.01", "-o", "b.png"],
                                     "--overwrite", _existing("b.png")),
    # damaged or foreign files to plot
    "plot garbage": (["plot", "bad.nc", "-o", "p.png"], "cannot read", _garbage),
    "plot empty file": (["plot", "bad.nc", "-o", "p.png"], "cannot read", _empty),
    "plot truncated NetCDF": (["plot", "bad.nc", "-o", "p.png"], "cannot read", _truncated),
    "plot foreign NetCDF": (["plot", "bad.nc", "-o", "p.png"], "neither", _foreign),
    "plot PNG named .nc": (["plot", "bad.nc", "-o", "p.png"], "cannot read", _png_as_nc),
    "plot missing file": (["plot", "missing.nc", "-o", "p.png"], "no such file", None),
    # ... and to rerun
    "rerun garbage": (["rerun", "bad.nc"], "cannot read", _garbage),
    "rerun truncated NetCDF": (["rerun", "bad.nc"], "cannot read", _truncated),
    "rerun foreign NetCDF": (["rerun", "bad.nc"], "no 'command' attribute", _foreign),
    "rerun foreign command": (["rerun", "bad.nc"], "not a vibimpact", _foreign_command),
    "rerun missing file": (["rerun", "missing.nc"], "no such file", None),
    "rerun onto itself": (["rerun", "bad.nc", "-o", "bad.nc"], "differ", _foreign_command),
    "rerun a directory": (["rerun", "dir.nc"], "is a directory", _directory("dir.nc")),
    "rerun damaged Zarr store": (["rerun", "m.zarr"], "cannot read", _damaged_store),
    # damaged checkpoints
    "resume garbage request.json": ([*ONE, "-o", "c.nc", "--resume"], "request.json",
                                    _checkpoint("\x00garbage{")),
    "resume foreign request.json": ([*ONE, "-o", "c.nc", "--resume"], "request.json",
                                    _checkpoint("[1, 2, 3]")),
    "checkpoint is a file": ([*ONE, "-o", "c.nc", "--resume"], "not a directory",
                             _checkpoint_file),
    # figure options of every command that draws (plot, bifurcation, map/simulate --plot)
    "plot figsize 0x3": (["plot", "c.nc", "--figsize", "0x3", "-o", "p.png"],
                         "argument --figsize: must be WIDTHxHEIGHT", _sweep_as("c.nc")),
    "plot figsize abc": (["plot", "c.nc", "--figsize", "abc", "-o", "p.png"],
                         "argument --figsize: must be WIDTHxHEIGHT", _sweep_as("c.nc")),
    "plot dpi -1": (["plot", "c.nc", "--dpi", "-1", "-o", "p.png"],
                    "argument --dpi: must be a number > 0", _sweep_as("c.nc")),
    "plot style nope": (["plot", "c.nc", "--style", "nope", "-o", "p.png"],
                        "argument --style: must be one of 'default', 'paper'",
                        _sweep_as("c.nc")),
    "bifurcation figsize abc": (["bifurcation", "--eta", "1:1.01:0.01", "--figsize", "abc",
                                 "-o", "b.png"], "argument --figsize", None),
    "map --plot dpi -1": (["map", "--eta", "1,1.1", "--vary", "kh=10,20", "--plot",
                           "m.png", "--dpi", "-1", "-o", "m.zarr"], "argument --dpi", None),
    "simulate --plot style nope": ([*SIM, "-o", "r.nc", "--plot", "xy.png", "--style",
                                    "nope"], "argument --style", None),
    "simulate figsize without --plot": ([*SIM, "-o", "r.nc", "--figsize", "3x2"],
                                        "--figsize: for the image of --plot", None),
    # simulate --from SWEEP.nc (coexisting attractors): the file, the point, conflicts
    "from: missing file": ([*FROM, "-o", "x.nc"], "no such file", None),
    "from: garbage": ([*FROM, "-o", "x.nc"], "cannot read", _garbage_as("s.nc")),
    "from: a run, not a sweep": (["simulate", "--from", "r.nc", "--eta", "1.25", "-o",
                                  "x.nc"], "not a sweep dataset", _run_file),
    "from: foreign NetCDF": ([*FROM, "-o", "x.nc"], "not a sweep dataset",
                             lambda d: _foreign(d, "s.nc")),
    "from: a map": ([*FROM, "-o", "x.nc"], "parameter map",
                    _sweep_file(map_vary="kh")),
    "from: eta off the grid": ([*FROM[:3], "--eta", "1.26", "-o", "x.nc"],
                               "not on the sweep's grid (2 points from 1.1 to 1.25); "
                               "nearest grid values: 1.25", _sweep_file()),
    "from: eta between grid values": ([*FROM[:3], "--eta", "1.2", "-o", "x.nc"],
                                      "nearest grid values: 1.1 and 1.25", _sweep_file()),
    "from: no eta on a grid of two": ([*FROM[:3], "-o", "x.nc"], "eta: give one of the "
                                      "sweep's 2 grid values", _sweep_file()),
    "from: direction the file lacks": ([*FROM, "--direction", "down", "-o", "x.nc"],
                                       "direction 'down' is not in the sweep (it has up)",
                                       _sweep_file()),
    "from: both directions, none given": ([*FROM, "-o", "x.nc"], "direction: the sweep "
                                          "has up and down", _sweep_file("both")),
    "from: point not computed": ([*FROM, "-o", "x.nc"], "did not compute eta = 1.25 (up)",
                                 _sweep_file(regime=0)),
    "from: point diverged": ([*FROM, "-o", "x.nc"], "diverged at eta = 1.25 (up)",
                             _sweep_file(regime=4)),
    "from: with --preset": ([*FROM, "--preset", "fig10", "-o", "x.nc"],
                            "--preset cannot be combined with --from", _sweep_file()),
    "from: with --state0": ([*FROM, "--state0", "0", "0", "0", "0", "-o", "x.nc"],
                            "--state0 cannot be combined with --from", _sweep_file()),
    "from: --set unknown name": ([*FROM, "--set", "kq=1", "-o", "x.nc"], "kq",
                                 _sweep_file()),
    "from: --set out of domain": ([*FROM, "--set", "BT=-1", "-o", "x.nc"], "BT",
                                  _sweep_file()),
    "direction without --from": ([*SIM, "--direction", "up", "-o", "x.nc"],
                                 "--direction needs --from", None),
    # continue: the window, the parameter, the steps, the start, the output
    "continue without --stop": ([*CONT[:-2], "-o", "b.nc"], "--stop", None),
    "continue stop = start": ([*CONT[:-1], "1.12", "-o", "b.nc"], "--stop", None),
    "continue stop NaN": ([*CONT[:-1], "nan", "-o", "b.nc"], "--stop", None),
    "continue stop eta < 0": ([*CONT[:-1], "-1", "-o", "b.nc"], "--stop", None),
    "continue stop not a number": ([*CONT[:-1], "x", "-o", "b.nc"], "--stop", None),
    "continue unknown param": ([*CONT, "--param", "kq", "-o", "b.nc"], "--param", None),
    "continue stop outside the domain": (["continue", "--param", "kh", "--stop", "-5",
                                          "-o", "b.nc"], "--stop: kh", None),
    "continue period 0": ([*CONT, "--period", "0", "-o", "b.nc"], "--period", None),
    "continue max-points 1": ([*CONT, "--max-points", "1", "-o", "b.nc"], "--max-points",
                              None),
    "continue max-points 1e9": ([*CONT, "--max-points", "1000000000", "-o", "b.nc"],
                                "--max-points grid has 1000000000 points", None),
    "continue ds 0": ([*CONT, "--ds", "0", "-o", "b.nc"], "--ds must be", None),
    "continue ds-max NaN": ([*CONT, "--ds-max", "nan", "-o", "b.nc"], "--ds-max", None),
    "continue refine < 0": ([*CONT, "--refine", "-1e-6", "-o", "b.nc"], "--refine", None),
    "continue approach 0": ([*CONT, "--approach", "0", "-o", "b.nc"], "--approach", None),
    "continue transient 1e9": ([*CONT, "--transient", "1000000000", "-o", "b.nc"],
                               "--transient", None),
    "continue unknown preset": ([*CONT, "--preset", "fig99", "-o", "b.nc"], "fig99", None),
    "continue unknown --set": ([*CONT, "--set", "kq=1", "-o", "b.nc"], "kq", None),
    "continue existing output": ([*CONT, "-o", "b.nc"], "--overwrite", _existing("b.nc")),
    "continue state0 short": ([*CONT, "--state0", "0", "0", "-o", "b.nc"], "--state0",
                              None),
    "continue no orbit at the start": (["continue", "--eta", "1.23", "--approach", "1.1",
                                        "--transient", "200", "--stop", "1.25",
                                        "--period", "7", "-o", "b.nc"],
                                       "no period-7 orbit found at eta = 1.23", None),
    # ... and its plots
    "plot --branch missing": (["plot", "c.nc", "--branch", "missing.nc", "-o", "p.png"],
                              "--branch 'missing.nc': no such file", _sweep_as("c.nc")),
    "plot --branch a sweep": (["plot", "c.nc", "--branch", "c.nc", "-o", "p.png"],
                              "is not a 'vibimpact continue' file", _sweep_as("c.nc")),
    "plot --branch garbage": (["plot", "c.nc", "--branch", "bad.nc", "-o", "p.png"],
                              "--branch: cannot read", lambda d: (_sweep_as("c.nc")(d),
                                                                  _garbage(d))),
    "plot --branch on intervals": (["plot", "c.nc", "--kind", "intervals", "--branch",
                                    "c.nc", "-o", "p.png"], "--branch draws over "
                                   "response curves", _sweep_as("c.nc")),
    "plot --kind branch of a sweep": (["plot", "c.nc", "--kind", "branch", "-o", "p.png"],
                                      "--kind branch needs a 'vibimpact continue' file",
                                      _sweep_as("c.nc")),
}


@pytest.mark.parametrize("case", list(CLI_CASES))
def test_cli_refuses_bad_input(case, tmp_path, monkeypatch, capfd):
    """Exit 2, one line 'vibimpact: error: ...' naming the problem, no traceback, no
    stdout, and no file created (nor removed) in the working directory."""
    argv, needle, setup = CLI_CASES[case]
    if setup is not None:
        setup(tmp_path)
    before = listing(tmp_path)
    monkeypatch.chdir(tmp_path)
    try:
        rc, out, err = run_cli(argv, capfd)
    finally:
        if (tmp_path / "ro").exists():
            (tmp_path / "ro").chmod(0o700)
    assert_refused(rc, out, err, needle)
    assert listing(tmp_path) == before
    if (tmp_path / "ro").exists():
        assert listing(tmp_path / "ro") == []
    assert not os.path.exists("/sys/vibimpact_test_out.nc")


def test_too_many_points_message_has_the_estimate(tmp_path, monkeypatch, capfd):
    """10^9 points: refused before any work with the estimated time and the limit."""
    monkeypatch.chdir(tmp_path)
    from vibimpact._limits import SECONDS_PER_POINT, human_duration

    rc, out, err = run_cli(["classify", "--eta", "0.5:1000000000.5:1", "-o", "c.nc"], capfd)
    cost = human_duration(1000000001 * SECONDS_PER_POINT)
    assert_refused(rc, out, err, f"--eta: eta grid has 1000000001 points (about {cost} "
                                 f"at ~{SECONDS_PER_POINT:g} s per point); at most 100000")


# --- API: id -> (callable, needle) --------------------------------------------------------

def _params(**kw):
    import vibimpact as vi

    return vi.Params(**kw)


def _replace(**kw):
    import vibimpact as vi

    return vi.presets.get("fig8").replace(**kw)


def _parse(text):
    from vibimpact.sweeps import parse_range

    return parse_range(text)


def _sweep(eta, **kw):
    import vibimpact as vi

    return vi.sweep(vi.presets.get("fig8"), eta, **kw)


def _simulate(**kw):
    import vibimpact as vi

    return vi.simulate(vi.presets.get("fig8"), **kw)


def _preset(name):
    import vibimpact as vi

    return vi.presets.get(name)


def _system(**kw):
    import vibimpact as vi

    return vi.System(vi.presets.get("fig8"), **kw)


def _analyse(name, *args, system=True, **kw):
    """Call analyser ``name`` of vibimpact.analysis (or vibimpact.points) on fig8 (a
    System unless told)."""
    import vibimpact as vi
    from vibimpact import analysis, points

    first = _system() if system else vi.presets.get("fig8")
    return getattr(analysis if hasattr(analysis, name) else points, name)(first, *args, **kw)


def _averaging(**kw):
    from vibimpact.analysis import Averaging

    return Averaging(**kw)


def _steps(**kw):
    from vibimpact.analysis import Steps

    return Steps(**kw)


def _follow(**kw):
    import vibimpact as vi
    from vibimpact.branches import follow_branch

    return follow_branch(vi.presets.get("fig8"), stop=1.1, **kw)


def _branch_io(name, what):
    """branches.NAME given a Run (branch_to_dataset) or a foreign dataset."""
    import xarray as xr

    import vibimpact as vi
    from vibimpact import branches

    if what == "run":
        run = vi.simulate(vi.presets.get("fig8"), periods=1)
        return branches.branch_to_dataset(run, vi.System(vi.presets.get("fig8")))
    return getattr(branches, name)(xr.Dataset({"x": ("t", [1.0])}))


API_CASES = {
    "Params kh < 0": (lambda: _params(kh=-1.0), "kh"),
    "Params B < 0": (lambda: _params(B=-0.1), "B "),
    "Params Bh < 0": (lambda: _params(Bh=-0.1), "Bh"),
    "Params BT < 0": (lambda: _params(BT=-0.1), "BT"),
    "Params f < 0": (lambda: _params(f=-0.1), "f "),
    "Params Ec < 0": (lambda: _params(Ec=-0.1), "Ec"),
    "Params eta = 0": (lambda: _params(eta=0.0), "eta"),
    "Params eta NaN": (lambda: _params(eta=math.nan), "eta"),
    "Params G inf": (lambda: _params(G=math.inf), "G"),
    "Params kh string": (lambda: _params(kh="120"), "kh"),
    "replace kh < 0": (lambda: _replace(kh=-5.0), "kh"),
    "replace eta < 0": (lambda: _replace(eta=-1.0), "eta"),
    "replace Ec NaN": (lambda: _replace(Ec=math.nan), "Ec"),
    "replace unknown name": (lambda: _replace(kq=1.0), "kq"),
    "unknown preset": (lambda: _preset("fig99"), "fig99"),
    "parse_range reversed": (lambda: _parse("1.2:1.0:0.01"), "eta"),
    "parse_range zero step": (lambda: _parse("1:2:0"), "eta"),
    "parse_range NaN": (lambda: _parse("1:nan:0.1"), "eta"),
    "parse_range words": (lambda: _parse("one:two:three"), "eta"),
    "parse_range 1e9 points": (lambda: _parse("0.5:1000000000.5:1"), "about"),
    "sweep huge array": (lambda: _sweep(np.linspace(1.0, 2.0, 100_001)), "eta"),
    "sweep decreasing eta": (lambda: _sweep([1.2, 1.1]), "eta"),
    "sweep eta <= 0": (lambda: _sweep([0.0, 1.0]), "eta"),
    "sweep NaN eta": (lambda: _sweep([1.0, math.nan]), "eta"),
    "sweep direction": (lambda: _sweep([1.0], direction="sideways"), "direction"),
    "sweep analysis": (lambda: _sweep([1.0], analyses=("spectrum",)), "analyses"),
    "simulate 1e9 periods": (lambda: _simulate(periods=10**9), "periods"),
    "simulate 1e9 transient": (lambda: _simulate(periods=1, transient=10**9), "transient"),
    "simulate periods 0": (lambda: _simulate(periods=0), "periods"),
    "System rtol < 0": (lambda: _system(rtol=-1e-9), "rtol"),
    "System unknown method": (lambda: _system(method="euler"), "method"),
    "System unknown solver setting": (lambda: _system().with_solver(tol=1.0), "solver"),
    "System unknown parameter": (lambda: _system().param("kq"), "param"),
    "analyser given Params": (lambda: _analyse("lyapunov_spectrum", system=False), "system"),
    "shooting given Params": (lambda: _analyse("shoot_periodic_orbit", [0.0] * 4,
                                               system=False), "system"),
    "classify_params given Params": (lambda: _analyse("classify_params", system=False),
                                     "system"),
    "classify_params unknown setting": (lambda: _analyse("classify_params", periods=10),
                                        "periods"),
    "shooting state0 too short": (lambda: _analyse("shoot_periodic_orbit", [0.0]), "state0"),
    "monodromy rk4": (lambda: _system(method="rk4").monodromy([0.0] * 4), "method"),
    "continuation unknown parameter": (lambda: _analyse("continue_orbit", [0.0] * 4,
                                                        param="kq", stop=1.2), "param"),
    "Averaging block 1": (lambda: _averaging(block=1), "block"),
    "Averaging max < min": (lambda: _averaging(min_periods=10, max_periods=5),
                            "max_periods"),
    "Steps ds 0": (lambda: _steps(ds=0.0), "ds"),
    "Steps max_points 1": (lambda: _steps(max_points=1), "max_points"),
    "continuation refine < 0": (lambda: _analyse("continue_orbit", [0.0] * 4, stop=1.2,
                                                 refine=-1.0), "refine"),
    "refine_stability_change same stability": (
        lambda: _analyse("refine_stability_change", "eta", 1, (1.0, 1.01),
                         ([0.0] * 4, [0.0] * 4)), "values"),
    "follow_branch approach 0": (lambda: _follow(approach=0.0), "approach"),
    "follow_branch transient < 0": (lambda: _follow(transient=-1), "transient"),
    "branch_to_dataset of a Run": (lambda: _branch_io("branch_to_dataset", "run"),
                                   "branch"),
    "branch_from_dataset foreign": (lambda: _branch_io("branch_from_dataset", "foreign"),
                                    "ds"),
}


@pytest.mark.parametrize("case", list(API_CASES))
def test_api_raises_value_error_naming_the_parameter(case):
    """The public API refuses bad input with a ValueError whose message names it."""
    call, needle = API_CASES[case]
    with pytest.raises(ValueError) as info:
        call()
    assert needle in str(info.value), str(info.value)


def _run_to(name):
    """Call ``name`` with a Run where it expects an array or a dataset."""
    import vibimpact as vi
    from vibimpact.plotting import plot_xy

    from vibimpact.plotting.map2d import plot_map

    run = vi.simulate(vi.presets.get("fig8").replace(eta=1.2), periods=3)
    call = {"classify": vi.analysis.classify, "intervals": vi.intervals, "plot_xy": plot_xy,
            "classify diverged": lambda r: vi.analysis.classify(r, diverged=True),
            "plot_response": vi.plotting.plot_response,
            "plot_bifurcation": vi.plotting.plot_bifurcation,
            "plot_intervals": vi.plotting.plot_intervals, "plot_map": plot_map,
            "write_netcdf": lambda r: vi.io.write_netcdf(r, "never.nc"),
            "format_intervals": vi.sweeps.format_intervals}
    return call[name](run)


@pytest.mark.parametrize("name, needle", [("classify", "points"), ("intervals", "ds")])
def test_a_run_where_an_array_or_dataset_is_expected_is_a_clear_type_error(name, needle):
    """A Run handed to classify (points) or intervals (a sweep dataset) raises a
    TypeError that names the argument and says what to pass, not a raw error from deep
    inside (plot_xy and write_netcdf take a Run: tests/test_sweep_start.py)."""
    with pytest.raises(TypeError) as info:
        _run_to(name)
    assert needle in str(info.value) and "Run" in str(info.value), str(info.value)


@pytest.mark.parametrize("name, needle", [
    ("classify diverged", "points"), ("plot_response", "ds"), ("plot_bifurcation", "ds"),
    ("plot_intervals", "ds"), ("plot_map", "ds"), ("format_intervals", "iv")])
def test_a_run_given_to_the_other_dataset_functions_is_a_clear_type_error(
        name, needle, tmp_path, monkeypatch):
    """Hypothesis: the Run check covered only classify and intervals; the sibling
    functions that expect a sweep (classify with diverged=True, which returned DIVERGED
    before looking at points, the sweep and map figures, format_intervals) still failed
    with a raw AttributeError from inside (or none at all), and left no file."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(TypeError) as info:
        _run_to(name)
    assert needle in str(info.value) and "Run" in str(info.value), str(info.value)
    assert listing(tmp_path) == []


def test_simulate_periods_message_has_the_estimate():
    """A run of 10^9 periods is refused at once with the estimated time (the measured cost
    per period of vibimpact._limits)."""
    import re

    from vibimpact._limits import SECONDS_PER_PERIOD, human_duration

    cost = human_duration(10**9 * SECONDS_PER_PERIOD)
    with pytest.raises(ValueError, match=rf"periods=1000000000 .*about {re.escape(cost)}"):
        _simulate(periods=10**9)


@pytest.mark.parametrize("text,grid", [("1.0:1.05:0.02", [1.0, 1.02, 1.04]),
                                       ("1.0:1.06:0.02", [1.0, 1.02, 1.04, 1.06]),
                                       ("1.0:1.0:0.5", [1.0])])
def test_stop_off_the_grid_is_accepted(text, grid):
    """STOP off the grid is not an error: the grid stops before it (STOP on the grid is
    included)."""
    assert _parse(text).tolist() == grid


# --- rerun ---------------------------------------------------------------------------------

def test_rerun_simulate_is_identical(tmp_path, monkeypatch, capfd):
    """A simulate file (with --plot, which implies dense samples) reruns bit-identical;
    the temporary rerun file is removed and the plot is not redrawn."""
    monkeypatch.chdir(tmp_path)
    rc, _, err = run_cli([*SIM, "--set", "Ec=0.3", "-o", "run.nc", "--plot", "xy.png"], capfd)
    assert rc == 0, err
    rc, out, err = run_cli(["rerun", "run.nc"], capfd)
    assert rc == 0, err
    assert out.startswith("identical: ") and out.strip().endswith("variables")
    assert int(out.split()[1]) >= 10
    assert listing(tmp_path) == ["run.nc", "xy.png"]


@pytest.fixture(scope="module")
def classified(tmp_path_factory):
    """classify with STOP off the grid (1.025: the grid is 1.00, 1.01, 1.02), keeping its
    checkpoint for the damaged-checkpoint test."""
    d = tmp_path_factory.mktemp("rerun")
    mp = pytest.MonkeyPatch()
    mp.chdir(d)
    try:
        rc = main(["classify", "--eta", "1.0:1.025:0.01", "--no-progress", "--workers", "1",
                   "--analyses", "period,impacts,response,poincare", "-o", "c.nc",
                   "--keep-checkpoint"])
    finally:
        mp.undo()
    assert rc == 0
    return d


def test_stop_off_the_grid_classifies(classified):
    """The off-grid STOP is accepted by classify: three points, STOP excluded."""
    from vibimpact.io import read_netcdf

    ds = read_netcdf(classified / "c.nc")
    assert ds["eta"].values.tolist() == [1.0, 1.01, 1.02]


def test_rerun_classify_identical_and_altered_copy_differs(classified, monkeypatch, capfd):
    """classify's file reruns identical (exit 0); a copy with one altered value is reported
    as different, naming the variable (exit 1); -o keeps the rerun file."""
    from vibimpact.io import read_netcdf, write_netcdf

    monkeypatch.chdir(classified)
    rc, out, err = run_cli(["rerun", "c.nc"], capfd)
    assert rc == 0, err
    assert out.startswith("identical: ")
    ds = read_netcdf("c.nc")
    ds["X_m"].values[1] = np.nextafter(ds["X_m"].values[1], 2.0)  # one bit
    write_netcdf(ds, "altered.nc", overwrite=True)
    rc, out, err = run_cli(["rerun", "altered.nc", "-o", "again.nc", "--overwrite"], capfd)
    assert rc == 1, err
    lines = out.splitlines()
    assert lines[0].startswith("different: 1 of ")
    assert lines[1].split(":")[0].strip() == "X_m"
    assert (classified / "again.nc").is_file()
    assert not [n for n in listing(classified) if "rerun" in n]


def test_rerun_bifurcation_data(tmp_path, monkeypatch, capfd):
    """bifurcation's data file reruns identical without drawing an image."""
    monkeypatch.chdir(tmp_path)
    rc, _, err = run_cli(["bifurcation", "--eta", "1.0:1.01:0.01", "--no-progress",
                          "--workers", "1", "-o", "b.png"], capfd)
    assert rc == 0, err
    rc, out, err = run_cli(["rerun", "b.nc"], capfd)
    assert rc == 0, err
    assert out.startswith("identical: ")
    assert listing(tmp_path) == ["b.nc", "b.png"]


@pytest.mark.parametrize("flag", ["-v", "-vv", "--verbose"])
def test_rerun_of_a_command_with_verbose_before_its_name(flag, tmp_path, monkeypatch,
                                                          capfd):
    """Hypothesis: a file written by `vibimpact -v simulate ...` (-v before the command
    name, as the README shows) records that command line, and rerun took the word after
    'vibimpact' for the command, refusing the file as 'not a vibimpact ... command'."""
    from vibimpact._cli_common import set_verbosity

    monkeypatch.chdir(tmp_path)
    try:
        rc, _, err = run_cli([flag, *SIM, "-o", "r.nc"], capfd)
        assert rc == 0, err
        rc, out, err = run_cli(["rerun", "r.nc"], capfd)
    finally:
        set_verbosity(0)
    assert rc == 0, err
    assert out.startswith("identical: ")
    assert listing(tmp_path) == ["r.nc"]


@pytest.mark.parametrize("out", ["m.zarr", "m.nc"])
def test_rerun_map_store_and_netcdf(out, tmp_path, monkeypatch, capfd):
    """A map, as a Zarr store or a NetCDF file, reruns identical (exit 0) with no image
    redrawn and no temporary store left; -o keeps the rerun output in the same format."""
    monkeypatch.chdir(tmp_path)
    rc, _, err = run_cli(["map", "--eta", "1.0:1.02:0.02", "--vary", "kh=60,120",
                          "--workers", "1", "--no-progress", "-o", out, "--plot", "m.png"],
                         capfd)
    assert rc == 0, err
    rc, text, err = run_cli(["rerun", out], capfd)
    assert rc == 0, err
    assert text.startswith("identical: ") and int(text.split()[1]) >= 10
    assert listing(tmp_path) == sorted([out, "m.png"])
    again = "again" + out[1:]
    rc, text, err = run_cli(["rerun", out, "-o", again], capfd)
    assert rc == 0, err
    assert (tmp_path / again).exists() and text.strip().endswith(f"wrote {again}")


# --- damaged checkpoint points ----------------------------------------------------------------

def test_damaged_checkpoint_points_are_recomputed(classified, monkeypatch, capfd):
    """Garbage and truncated point files in a checkpoint are set aside as *.corrupt and
    recomputed (one warning line); the resumed file equals the uninterrupted one."""
    from vibimpact.io import differences as _differences
    from vibimpact.io import read_netcdf

    monkeypatch.chdir(classified)
    if os.path.exists("d.nc.partial"):
        shutil.rmtree("d.nc.partial")
    shutil.copytree("c.nc.partial", "d.nc.partial")
    ck = classified / "d.nc.partial"
    first, second = sorted(ck.glob("up_*.npz"))[:2]  # one entry per point
    first.write_bytes(b"garbage")
    good = second.read_bytes()
    second.write_bytes(good[: len(good) // 2])
    rc, out, err = run_cli(["classify", "--eta", "1.0:1.025:0.01", "--no-progress",
                            "--workers", "1", "--analyses", "period,impacts,response,poincare",
                            "-o", "d.nc", "--resume"], capfd)
    assert rc == 0, err
    assert "Traceback" not in err
    assert "vibimpact: warning: 2 damaged point files" in err
    assert "1 point loaded" in err  # one, not "1 points"
    assert out.splitlines()[-1] == "wrote d.nc"
    assert not ck.exists()
    diffs, total = _differences(read_netcdf("c.nc"), read_netcdf("d.nc"))
    assert diffs == [] and total > 10


def test_load_sets_aside_a_foreign_npz(tmp_path):
    """An entry that loads but is not one (missing fields), or one of another request,
    counts as not done: set aside as *.corrupt and listed by the resume."""
    from vibimpact.engine.store import Checkpoint, entry_name

    ck = Checkpoint(tmp_path / "ck").open("sweep", {"a": 1}, {"points": 5}, False)
    np.savez(ck.path / entry_name(0, "up", 3, 4), a=np.arange(3))
    ck.save(0, "up", [(1, {"regime": 1, "final_state": np.zeros(4)})])
    other = Checkpoint(tmp_path / "other").open("sweep", {"a": 2}, {"points": 5}, False)
    other.save(0, "up", [(2, {"regime": 1, "final_state": np.ones(4)})])
    os.replace(other.path / entry_name(0, "up", 2, 3), ck.path / entry_name(0, "up", 2, 3))
    done = ck.load()
    assert list(done) == [(0, "up")] and list(done[(0, "up")]) == [1]
    assert done[(0, "up")][1]["final_state"].tolist() == [0.0] * 4
    assert ck.last_resume()["damaged"] == [entry_name(0, "up", 2, 3) + ".corrupt",
                                           entry_name(0, "up", 3, 4) + ".corrupt"]
    assert ck.saved() == (1, 0)
    assert list(ck.load()) == [(0, "up")]  # now simply absent


def test_rerun_help_is_light():
    """`rerun --help` exits 0 with an example and imports no heavy module."""
    import subprocess

    code = ("import sys\nfrom vibimpact.cli import main\n"
            "try:\n    main(['rerun', '--help'])\nexcept SystemExit as e:\n    rc = e.code\n"
            "heavy = [m for m in ('numba', 'numpy', 'xarray', 'matplotlib') "
            "if m in sys.modules]\nprint('HEAVY', heavy, 'RC', rc)\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       timeout=60, cwd=Path(__file__).resolve().parents[1])
    assert r.returncode == 0, r.stderr
    assert "HEAVY [] RC 0" in r.stdout and "vibimpact rerun " in r.stdout
