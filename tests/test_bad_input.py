"""Bad input on the command line: every refusal is one clear line.

CLI cases run ``vibimpact.cli.main`` in this process (fast) and check: exit status 2,
exactly one stderr line starting with ``vibimpact: error:`` that names the problem, no
traceback, nothing on stdout, and no new file (output, partial or temporary) in the
working directory.  The API's cases are in test_bad_input_api.py; rerun and resume of
written files in test_rerun.py.
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

def tiny_sweep_file(path, command="vibimpact classify --eta 1.0:1.01:0.01 -o c.nc"):
    import xarray as xr

    from vibimpact.io import write_netcdf

    ds = xr.Dataset({"regime": ("eta", np.array([1, 3], dtype="i1")),
                     "X_m": ("eta", [0.5, np.nan]),
                     "poincare_X": (("eta", "sample"), np.ones((2, 64)))},
                    coords={"eta": [1.0, 1.01]}, attrs={"command": command})
    write_netcdf(ds, path)


def sweep_as(name):
    def make(d):
        tiny_sweep_file(Path(d) / name)
    return make


def _garbage(d, name="bad.nc"):
    (Path(d) / name).write_bytes(b"this is not a NetCDF file\n" * 20)


def _garbage_as(name):
    return lambda d: _garbage(d, name)


def _empty(d, name="bad.nc"):
    (Path(d) / name).write_bytes(b"")


def _truncated(d, name="bad.nc"):
    full = Path(d) / ".full.nc"
    tiny_sweep_file(full)
    data = full.read_bytes()
    full.unlink()
    (Path(d) / name).write_bytes(data[: len(data) // 2])


def _foreign(d, name="bad.nc"):
    """A valid NetCDF file that vibimpact did not write (no command, other variables)."""
    import xarray as xr

    xr.Dataset({"temperature": ("time", np.arange(5.0))}).to_netcdf(Path(d) / name)


def _foreign_command(d, name="bad.nc"):
    tiny_sweep_file(Path(d) / name, command="rm -rf /")


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
                                      execution=vi.Execution(workers=1, progress=False))
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
                    "--periods 1000000000 + --transient 500", None),
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
    "plot foreign NetCDF": (["plot", "bad.nc", "-o", "p.png"], "is not a file plot draws",
                            _foreign),
    "plot PNG named .nc": (["plot", "bad.nc", "-o", "p.png"], "cannot read", _png_as_nc),
    "plot missing file": (["plot", "missing.nc", "-o", "p.png"], "no such file", None),
    # ... and to rerun
    "rerun garbage": (["rerun", "bad.nc"], "cannot read", _garbage),
    "rerun truncated NetCDF": (["rerun", "bad.nc"], "cannot read", _truncated),
    "rerun foreign NetCDF": (["rerun", "bad.nc"], "no 'command' attribute", _foreign),
    "rerun foreign command": (["rerun", "bad.nc"], "not a vibimpact", _foreign_command),
    "rerun missing file": (["rerun", "missing.nc"], "no such file", None),
    "rerun onto itself": (["rerun", "bad.nc", "-o", "bad.nc"], "is the file being rerun",
                          _foreign_command),
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
                         "argument --figsize: must be WIDTHxHEIGHT", sweep_as("c.nc")),
    "plot figsize abc": (["plot", "c.nc", "--figsize", "abc", "-o", "p.png"],
                         "argument --figsize: must be WIDTHxHEIGHT", sweep_as("c.nc")),
    "plot dpi -1": (["plot", "c.nc", "--dpi", "-1", "-o", "p.png"],
                    "argument --dpi: must be a number > 0", sweep_as("c.nc")),
    "plot style nope": (["plot", "c.nc", "--style", "nope", "-o", "p.png"],
                        "argument --style: must be one of 'default', 'paper'",
                        sweep_as("c.nc")),
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
                              "--branch 'missing.nc': no such file", sweep_as("c.nc")),
    "plot --branch a sweep": (["plot", "c.nc", "--branch", "c.nc", "-o", "p.png"],
                              "is not a 'vibimpact continue' file", sweep_as("c.nc")),
    "plot --branch garbage": (["plot", "c.nc", "--branch", "bad.nc", "-o", "p.png"],
                              "--branch: cannot read", lambda d: (sweep_as("c.nc")(d),
                                                                  _garbage(d))),
    "plot --branch on intervals": (["plot", "c.nc", "--kind", "intervals", "--branch",
                                    "c.nc", "-o", "p.png"], "--branch draws over "
                                   "response curves", sweep_as("c.nc")),
    "plot --kind branch of a sweep": (["plot", "c.nc", "--kind", "branch", "-o", "p.png"],
                                      "--kind branch needs a continued branch "
                                      "('vibimpact continue')",
                                      sweep_as("c.nc")),
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
    from vibimpact.base._limits import SECONDS_PER_POINT, human_duration

    rc, out, err = run_cli(["classify", "--eta", "0.5:1000000000.5:1", "-o", "c.nc"], capfd)
    cost = human_duration(1000000001 * SECONDS_PER_POINT)
    assert_refused(rc, out, err, f"--eta: eta grid has 1000000001 points (about {cost} "
                                 f"at ~{SECONDS_PER_POINT:g} s per point); at most 100000")
