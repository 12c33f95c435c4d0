"""Output paths that cannot work and requests over the limits: refused before any work.

A second table of the bad-input suite (test_bad_input.py holds the first and its
helpers): every command that writes (simulate, its --plot, classify, bifurcation, map,
continue, plot, rerun) is given each kind of impossible output name, and each request
whose arrays grow with a user number (--dense, --blocks, the Poincaré samples of a sweep)
is given one far over the limit.  Each must end at once (before any point is computed)
with exit status 2, one line ``vibimpact: error: ...`` naming the problem, and no file
created or removed.  "Before any work" is proved by what was done, never by a clock: no
integration was started (every one goes through ``Solver._start``, counted by the
fixture ``integrations``) and no file was written.
"""
import os

import numpy as np
import pytest

from test_bad_input import (CONT, ONE, SIM, assert_refused, listing, run_cli, sweep_as,
                            tiny_sweep_file)

LONG = "a" * 250 + ".nc"
LONG_PNG = "a" * 250 + ".png"
BAD_UTF8 = "\udcff.nc"

#: command -> argv with the output name as OUT, whether OUT is an image, setup
COMMANDS = {
    "simulate": ([*SIM, "-o", "OUT"], False, None),
    "simulate --plot": ([*SIM, "-o", "r.nc", "--plot", "OUT"], True, None),
    "classify": ([*ONE, "-o", "OUT"], False, None),
    "bifurcation": (["bifurcation", "--eta", "1:1.01:0.01", "--no-progress", "-o", "OUT"],
                    True, None),
    "map": (["map", "--eta", "1,1.1", "--vary", "kh=10,20", "--no-progress", "-o", "OUT"],
            False, None),
    "continue": ([*CONT, "-o", "OUT"], False, None),
    "plot": (["plot", "c.nc", "-o", "OUT"], True, sweep_as("c.nc")),
    "rerun": (["rerun", "c.nc", "-o", "OUT"], False, sweep_as("c.nc")),
}


def _dangling(d, name):
    os.symlink("/nonexistent/vibimpact/target", d / name)


#: bad output -> (file name, image name, needle, setup(d, name) or None)
OUTPUTS = {
    "trailing slash": ("x.nc/", "x.png/", "x.", None),
    "empty name": ("", "", "''", None),
    "name too long": (LONG, LONG_PNG, "aaaa", None),
    "not UTF-8": (BAD_UTF8, "\udcff.png", "\\udcff", None),
    "dangling symlink": ("link.nc", "link.png", "link.", _dangling),
    "device node": ("/dev/full", "/dev/full", "/dev/full", None),
}


def _case(command, output):
    argv, image, setup = COMMANDS[command]
    name, image_name, needle, make = OUTPUTS[output]
    out = image_name if image else name
    if command == "map" and output == "trailing slash":  # a Zarr store may end in '/'
        out = "m.nc/"
        needle = "m.nc/"
    return [out if a == "OUT" else a for a in argv], out, needle, setup, make


CASES = [(c, o) for c in COMMANDS for o in OUTPUTS]


@pytest.fixture
def integrations(monkeypatch):
    """A list that grows by one with every integration started in this process (every
    simulate, sweep point, seeding pass and orbit goes through ``Solver._start``)."""
    from vibimpact.core.solver import Solver

    started = []
    original = Solver._start

    def counted(self, *args, **kwargs):
        started.append(1)
        return original(self, *args, **kwargs)

    monkeypatch.setattr(Solver, "_start", counted)
    return started


def test_the_integration_counter_sees_a_command_that_computes(integrations, tmp_path,
                                                              monkeypatch, capfd):
    """Hypothesis: the counter the refusals below rely on does count: a simulate that is
    not refused starts at least one integration (so 'none started' means refused before
    any work, not a counter that sees nothing)."""
    monkeypatch.chdir(tmp_path)
    rc, _, err = run_cli([*SIM, "-o", "r.nc"], capfd)
    assert rc == 0, err
    assert integrations


@pytest.mark.parametrize("command,output", CASES)
def test_impossible_output_is_refused_before_computing(command, output, tmp_path,
                                                       monkeypatch, capfd, integrations):
    """Every writing command refuses every impossible output name (trailing '/', empty,
    too long, not UTF-8, a dangling link, a device even with --overwrite) at once: exit 2,
    one line naming it, no file created or removed."""
    argv, out, needle, setup, make = _case(command, output)
    if setup is not None:
        setup(tmp_path)
    if make is not None:
        make(tmp_path, out)
    if out == "/dev/full":
        argv = [*argv, "--overwrite"]
    before = listing(tmp_path)
    monkeypatch.chdir(tmp_path)
    rc, stdout, err = run_cli(argv, capfd)
    assert_refused(rc, stdout, err, needle)
    assert not integrations  # before any point: no sweep or run
    assert listing(tmp_path) == before


def _recorded(command):
    def make(d):
        tiny_sweep_file(d / "c.nc", command=command)
    return make


def _interrupted_beside(out):
    """An interrupted run's checkpoint OUT.partial next to an unrelated file OUT."""
    def make(d):
        tiny_sweep_file(d / out)
        (d / (out + ".partial")).mkdir()
    return make


#: requests over a limit: argv, needle, setup
LIMITS = {
    "simulate --dense 1e9": ([*SIM, "--dense", "1000000000", "-o", "r.nc"],
                             "of memory for its arrays; at most 4 GiB", None),
    "simulate --dense 1e30": ([*SIM, "--dense", "1" + "0" * 30, "-o", "r.nc"],
                              "--dense", None),
    "rerun of --dense 1e9": (["rerun", "c.nc", "-o", "new.nc"], "of memory for its arrays",
                             _recorded("vibimpact simulate --eta 1.2 --periods 5 "
                                       "--transient 5 --dense 1000000000 -o c.nc")),
    "classify --blocks 1e20": ([*ONE, "--blocks", "99999999999999999999", "-o", "c.nc"],
                               "argument --blocks: must be <= 100000", None),
    "bifurcation --blocks 1e20": (["bifurcation", "--eta", "1:1.01:0.01", "--blocks",
                                   "99999999999999999999", "-o", "b.png"],
                                  "argument --blocks: must be <= 100000", None),
    "resume over an unrelated output": ([*ONE, "-o", "c.nc", "--resume"], "--overwrite",
                                        _interrupted_beside("c.nc")),
    "map resume over an unrelated output": (["map", "--eta", "1,1.1", "--vary",
                                             "kh=10,20", "-o", "m.nc", "--resume"],
                                            "--overwrite", _interrupted_beside("m.nc")),
    "checkpoint name too long": ([*ONE, "-o", "a" * 241 + ".nc"], "too long", None),
}


@pytest.mark.parametrize("case", list(LIMITS))
def test_request_over_a_limit_is_refused_before_computing(case, tmp_path, monkeypatch,
                                                          capfd, integrations):
    """Arrays that grow with a user number (--dense, also through rerun), a --blocks
    that cannot be recorded, a resume onto an unrelated file without --overwrite: exit 2
    at once, one line, no file created or removed."""
    argv, needle, setup = LIMITS[case]
    if setup is not None:
        setup(tmp_path)
    before = listing(tmp_path)
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(argv, capfd)
    assert_refused(rc, out, err, needle)
    assert not integrations
    assert listing(tmp_path) == before


API_LIMITS = {
    "simulate dense": (lambda vi, p: vi.simulate(p, periods=5, transient=5,
                                                 dense=10 ** 9), "dense=1000000000"),
    "sweep blocks": (lambda vi, p: vi.sweep(
        p, [1.0], continuation=vi.Continuation(blocks=10 ** 20)), "blocks"),
    "sweep samples": (lambda vi, p: vi.sweep(p, np.linspace(1.0, 1.1, 1000), settings=
                                             vi.sweeps.SweepSettings(n_samples=10 ** 6)),
                      "Poincare sample"),
    "map samples": (lambda vi, p: vi.map2d(p, [1.0, 1.1], {"kh": [10.0, 20.0]}, settings=
                                           vi.sweeps.SweepSettings(n_samples=10 ** 9)),
                    "Poincare samples per point"),
}


@pytest.mark.parametrize("case", list(API_LIMITS))
def test_api_refuses_the_same_limits(case, integrations):
    """The API applies the same memory limit as the command line, before any work:
    ValueError naming the number, no integration started."""
    import vibimpact as vi

    call, needle = API_LIMITS[case]
    with pytest.raises(ValueError, match=needle):
        call(vi, vi.presets.get("fig8"))
    assert not integrations


def test_api_writers_vet_the_path_as_the_commands_do(tmp_path):
    """write_netcdf, write_map and save_figure refuse what the commands refuse (a device
    even with overwrite, a trailing '/', an empty name), before writing anything."""
    import matplotlib.pyplot as plt
    import xarray as xr

    from vibimpact.io import write_netcdf
    from vibimpact.maps.store import write_map
    from vibimpact.plotting import save_figure

    ds = xr.Dataset({"x": ("i", [1.0, 2.0])})
    fig = plt.figure()
    try:
        for path, needle in (("/dev/full", "not a regular file"),
                             (str(tmp_path / "x.nc") + "/", "names a directory"),
                             ("", "the name is empty")):
            with pytest.raises(ValueError, match=needle):
                write_netcdf(ds, path, overwrite=True)
            if path.endswith(".nc/"):  # a map's NetCDF file, not a Zarr store
                with pytest.raises(ValueError, match=needle):
                    write_map(ds, path, overwrite=True)
        with pytest.raises(ValueError, match="not a regular file"):
            save_figure(fig, "/dev/full")
    finally:
        plt.close(fig)
    assert list(tmp_path.iterdir()) == []


def test_a_failed_write_on_a_full_file_system_says_so(tmp_path, monkeypatch):
    """NetCDF reports a full disk as 'RuntimeError: NetCDF: HDF error'; when the file
    system has no space left, the writer's OSError says 'No space left on device' and
    names the file."""
    import errno

    from vibimpact.io import write_failed

    class Full:
        f_bavail, f_frsize = 0, 4096

    exc = write_failed(str(tmp_path / "r.nc"), RuntimeError("NetCDF: HDF error"))
    assert "NetCDF: HDF error" in str(exc)
    monkeypatch.setattr(os, "statvfs", lambda path: Full())
    exc = write_failed(str(tmp_path / "r.nc"), RuntimeError("NetCDF: HDF error"))
    assert exc.errno == errno.ENOSPC
    expected = f"cannot write {str(tmp_path / 'r.nc')!r}: No space left on device"
    assert exc.strerror == expected
