"""A signal whose exception Python cannot raise still ends the command.

A SIGINT or SIGTERM handler raises :class:`vibimpact.Interrupted` wherever the main thread
is.  Where Python cannot raise (a ``ctypes`` callback, which numba's compiler runs; a
finaliser; a library's bare ``except:``) the exception is printed as "Exception ignored"
or dropped, and the command went on: the reliability run saw ``rerun`` and ``map``
print a traceback and exit 0 after a SIGINT at 10 %.  The guard records the signal
before raising, and raises it again at its next safe point: the next point of a
computation, the next write, the end of the guarded block.

The loss is made deterministic here: the test sends the signal from inside such a place.
"""
import ctypes
import os
import re
import signal
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import vibimpact as vi
from vibimpact.engine.signals import (_quiet_interrupts, Interrupted,
                                      StopWorkersOnSignal)

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "analyses" / "reliability"))
from _cases_signals import EARLY, IN_PROCESS  # noqa: E402 -- the reliability run's cases

SIGNALS = (signal.SIGINT, signal.SIGTERM)
_CALLBACK = ctypes.CFUNCTYPE(None)


def _wait_for_handler():
    """Run bytecode until the pending handler has run (it runs between instructions)."""
    t_end = time.monotonic() + 5
    while time.monotonic() < t_end:
        pass


def lose_in_ctypes_callback(signum):
    """The signal arrives inside a ctypes callback (numba's compiler calls them):
    ctypes prints 'Exception ignored on calling ctypes callback function' and returns."""
    def callback():
        os.kill(os.getpid(), signum)
        _wait_for_handler()

    _CALLBACK(callback)()


def lose_in_finaliser(signum):
    """The signal arrives inside a ``__del__``: 'Exception ignored in ...'."""
    class Finalised:
        def __del__(self):
            os.kill(os.getpid(), signum)
            _wait_for_handler()

    Finalised()


def lose_in_bare_except(signum):
    """The signal arrives inside library code that swallows everything."""
    try:
        os.kill(os.getpid(), signum)
        _wait_for_handler()
    except BaseException:  # noqa: BLE001 -- the library's mistake being modelled
        pass


WAYS = {"ctypes callback": lose_in_ctypes_callback, "finaliser": lose_in_finaliser,
        "bare except": lose_in_bare_except}


@pytest.fixture(autouse=True)
def _handlers_back():
    found = {s: signal.getsignal(s) for s in SIGNALS}
    hook = sys.unraisablehook
    yield
    for s, h in found.items():
        signal.signal(s, h)
    sys.unraisablehook = hook
    StopWorkersOnSignal.depth = 0


@pytest.mark.parametrize("way", WAYS)
@pytest.mark.parametrize("signum", SIGNALS, ids=["SIGINT", "SIGTERM"])
def test_a_signal_lost_inside_a_guarded_block_ends_the_block_as_that_signal(way, signum,
                                                                             capfd):
    """Hypothesis: a signal whose exception is swallowed inside a guarded block raises
    Interrupted with that signal when the block ends, prints nothing (no 'Exception
    ignored' traceback), and leaves the signal handlers as they were before the block;
    what follows the loss inside the block still runs (the loss is invisible there)."""
    found = {s: signal.getsignal(s) for s in SIGNALS}
    after = []
    with pytest.raises(Interrupted) as info:
        with StopWorkersOnSignal():
            WAYS[way](signum)
            after.append(1)
    assert info.value.signum == signum
    assert after == [1]
    assert capfd.readouterr().err == ""
    assert {s: signal.getsignal(s) for s in SIGNALS} == found


@pytest.mark.parametrize("way", WAYS)
def test_a_lost_signal_is_raised_at_the_next_safe_point_of_nested_guards(way):
    """Hypothesis: with a command's guard around a computation's guard (the command line
    around ``compute``), a signal lost inside the inner block is raised by
    ``StopWorkersOnSignal.check`` at the next safe point, and is raised once: the outer
    guard, which sees it unwind, does not raise it a second time."""
    reached = []
    with pytest.raises(Interrupted) as info:
        with StopWorkersOnSignal():
            try:
                with StopWorkersOnSignal():
                    WAYS[way](signal.SIGINT)
                    reached.append("after the loss")
                    StopWorkersOnSignal.check()
                    reached.append("after the check")
            except Interrupted:
                reached.append("caught")  # a command reporting its interrupt
                raise
    assert reached == ["after the loss", "caught"]
    assert info.value.signum == signal.SIGINT
    # a command that reports its interrupt and returns: the outer guard is quiet
    with StopWorkersOnSignal():
        try:
            with StopWorkersOnSignal():
                WAYS[way](signal.SIGTERM)
        except Interrupted as exc:
            assert exc.signum == signal.SIGTERM


def test_a_new_request_after_an_interrupt_starts_clean():
    """Hypothesis: the signal of an interrupted request is not raised again in the next
    request (a script that catches vi.Interrupted and goes on): a guard entered anew
    starts with no signal received."""
    with pytest.raises(Interrupted):
        with StopWorkersOnSignal():
            lose_in_ctypes_callback(signal.SIGINT)
    with StopWorkersOnSignal():
        StopWorkersOnSignal.check()
        done = True
    assert done and StopWorkersOnSignal.received is None


def _tiny():
    return xr.Dataset({"x": ("eta", np.arange(3.0))}, coords={"eta": [1.0, 1.1, 1.2]})


def _netcdf(path):
    vi.io.write_netcdf(_tiny(), path)


def _figure(path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from vibimpact.plotting.style import save_figure

    fig, ax = plt.subplots(figsize=(2, 2))
    ax.plot([0, 1])
    try:
        save_figure(fig, path)
    finally:
        plt.close(fig)


WRITERS = {"netcdf": (_netcdf, "out.nc"), "figure": (_figure, "out.png")}


@pytest.mark.parametrize("writer", WRITERS)
@pytest.mark.parametrize("way", ["ctypes callback", "bare except"])
def test_a_signal_lost_before_a_write_writes_nothing(writer, way, tmp_path, capfd):
    """Hypothesis: every writer checks for a lost signal before it creates its
    temporary, so a command the signal should have stopped leaves neither the output nor
    a temporary beside it, and says nothing of the lost exception."""
    write, name = WRITERS[writer]
    with pytest.raises(Interrupted):
        with StopWorkersOnSignal():
            WAYS[way](signal.SIGTERM)
            write(str(tmp_path / name))
    assert list(tmp_path.iterdir()) == []
    assert capfd.readouterr().err == ""


def test_a_signal_lost_before_a_map_store_write_writes_nothing(tmp_path):
    """Hypothesis: the Zarr map writer checks as the NetCDF writer does (the same
    variant, the map's own write path): nothing is left in the directory."""
    from vibimpact.maps.store import write_map

    eta = vi.grid("1.0:1.02:0.01")
    ds = vi.map2d(vi.presets.get("fig8"), eta, {"kh": [50.0, 60.0]},
                  analyses=("period",), execution=vi.Execution(workers=1))
    with pytest.raises(Interrupted):
        with StopWorkersOnSignal():
            lose_in_ctypes_callback(signal.SIGINT)
            write_map(ds, str(tmp_path / "m.zarr"))
    assert list(tmp_path.iterdir()) == []


def test_an_api_sweep_stops_at_the_point_after_a_lost_signal():
    """Hypothesis: a serial sweep (the kernel compiles in the main thread, where the
    loss was seen) whose signal is lost while a point is reported stops at the next
    point with Interrupted, rather than computing the rest of the grid."""
    eta = vi.grid("1.0:1.1:0.01")
    seen = []

    def progress(k):
        seen.append(k)
        if len(seen) == 2:
            lose_in_ctypes_callback(signal.SIGINT)

    with pytest.raises(vi.Interrupted):
        vi.sweep(vi.presets.get("fig8"), eta, analyses=("period",),
                 execution=vi.Execution(workers=1, progress=progress))
    assert sum(seen) < len(eta)


@pytest.mark.parametrize("name", IN_PROCESS)
def test_a_command_whose_signal_is_lost_ends_interrupted_and_writes_no_output(
        name, tmp_path, monkeypatch, capfd):
    """Hypothesis: each command whose SIGINT is swallowed early (here: inside the preset
    lookup, as the compiler's callback swallowed it) ends with exit 130 and its one
    'interrupted' line, writes no output (a resumable command keeps only its
    checkpoint), and prints no 'Exception ignored' traceback."""
    from vibimpact import presets
    from vibimpact.cli import main

    monkeypatch.chdir(tmp_path)
    argv, resumable = IN_PROCESS[name]
    before = set()
    if name == "rerun":
        assert main(IN_PROCESS["classify"][0]) == 0
        capfd.readouterr()
        before = {"c.nc"}
    original = presets.get

    def get(*a, **kw):
        lose_in_ctypes_callback(signal.SIGINT)
        return original(*a, **kw)

    monkeypatch.setattr(presets, "get", get)
    rc = main(argv)
    err = capfd.readouterr().err
    assert rc == 130, err
    assert "Exception" not in err and "Traceback" not in err, err
    assert err.strip().splitlines()[-1].startswith("vibimpact: interrupted"), err
    left = {p.name for p in tmp_path.iterdir()} - before
    assert left <= ({argv[-1] + ".partial"} if resumable else set()), left


def test_after_an_interrupt_a_finaliser_error_is_logged_not_printed(capfd):
    """Hypothesis: once a signal has stopped the command, the finaliser of an object the
    interrupt left half-built (llvmlite's ``ObjectRef.__del__``: "no attribute
    '_as_parameter_'") is not printed; before any signal, the same error is printed as
    Python prints it (the hook hides nothing else)."""
    class Broken:
        def __del__(self):
            raise AttributeError("no attribute '_as_parameter_'")

    sys.unraisablehook = _quiet_interrupts(sys.__unraisablehook__)
    StopWorkersOnSignal.received = None
    Broken()
    assert "_as_parameter_" in capfd.readouterr().err
    StopWorkersOnSignal.received = signal.SIGINT
    try:
        Broken()
    finally:
        StopWorkersOnSignal.received = None
    assert capfd.readouterr().err == ""


@pytest.mark.parametrize("when", ["import", "parse"])
@pytest.mark.parametrize("sig", ["SIGINT", "SIGTERM"])
def test_a_signal_before_the_command_has_its_guard_ends_it_with_one_line(when, sig,
                                                                          tmp_path):
    """Hypothesis: a signal while ``python -m vibimpact`` still imports its command line,
    or reads its options, ends it with the one line 'vibimpact: interrupted' and exit
    128 + signum: no KeyboardInterrupt traceback, no silent death by SIGTERM, no file."""
    import subprocess

    env = {k: v for k, v in os.environ.items() if k != "VIBIMPACT_PRECOMPILED"}
    code = EARLY.replace("SIGNAME", sig).replace("WHENNAME", when)
    proc = subprocess.run([sys.executable, "-c", code],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120,
                          env=env)
    assert proc.returncode == 128 + getattr(signal, sig), (proc.returncode, proc.stderr)
    assert proc.stderr == "vibimpact: interrupted\n", proc.stderr
    assert list(tmp_path.iterdir()) == []


def test_the_vibimpact_script_handles_signals_while_it_imports():
    """Hypothesis: the installed ``vibimpact`` script enters through the same function as
    ``python -m vibimpact`` (the one that handles signals during the import), not
    through ``vibimpact.cli:main`` directly."""
    from importlib.metadata import entry_points

    import vibimpact.__main__ as entry

    (script,) = entry_points(group="console_scripts", name="vibimpact")
    assert script.load() is entry.run


@pytest.mark.parametrize("moment", ["as the put-back begins", "while the tracker starts"])
def test_stderr_is_put_back_when_a_signal_cuts_the_tracker_relaunch(moment, monkeypatch):
    """Hypothesis: the resource tracker is relaunched with file descriptor 2 on the null
    device; a signal whose exception surfaces while the tracker starts, or just as the
    descriptor is being put back (the handler runs at the start of the ``finally``
    block and skips it), still leaves descriptor 2 on the original file and the
    exception propagating: the command's 'interrupted' line is seen (a map stopped by a
    group SIGTERM exited 143 with an empty stderr)."""
    from vibimpact.engine import cluster

    real = cluster.os
    onto_2 = []

    class Os:
        def __getattr__(self, name):
            return getattr(real, name)

        def dup2(self, fd, fd2, *a):
            if fd2 == 2:
                onto_2.append(fd)
                if moment == "as the put-back begins" and len(onto_2) == 2:
                    raise Interrupted(signal.SIGTERM)
            return real.dup2(fd, fd2, *a)

    def launch():
        assert os.fstat(2).st_ino == os.stat(os.devnull).st_ino
        if moment == "while the tracker starts":
            raise Interrupted(signal.SIGTERM)
        return "launched"

    before = os.fstat(2)
    monkeypatch.setattr(cluster, "os", Os())
    with pytest.raises(Interrupted):
        cluster._with_stderr_on_null(launch)
    after = os.fstat(2)
    assert (after.st_dev, after.st_ino) == (before.st_dev, before.st_ino)


def test_stderr_is_put_back_when_two_threads_relaunch_the_tracker_at_once():
    """Hypothesis: two threads that relaunch the resource tracker at once (the main
    thread unwinding an interrupt, Dask's thread closing its connections) leave file
    descriptor 2 on the original file: without one relaunch at a time, the second saved
    the null device and put it back last."""
    import threading

    from vibimpact.engine import cluster

    a_in, b_in, a_done = threading.Event(), threading.Event(), threading.Event()

    def launch_a():
        a_in.set()
        b_in.wait(timeout=1.0)  # B relaunches now, unless it must wait for A

    def launch_b():
        b_in.set()
        a_done.wait(timeout=1.0)  # A puts its saved descriptor back first

    def relaunch_a():
        cluster._with_stderr_on_null(launch_a)
        a_done.set()

    before = os.fstat(2)
    a = threading.Thread(target=relaunch_a)
    a.start()
    a_in.wait()
    b = threading.Thread(target=cluster._with_stderr_on_null, args=(launch_b,))
    b.start()
    a.join()
    b.join()
    after = os.fstat(2)
    assert (after.st_dev, after.st_ino) == (before.st_dev, before.st_ino)


#: every command with a checkpoint, small: (arguments, its output)
CHECKPOINTED = {
    "classify": ["classify", "--eta", "1.0:1.03:0.01", "--workers", "1", "--no-progress",
                 "-o", "c.nc"],
    "map": ["map", "--eta", "1.0:1.02:0.01", "--vary", "kh=50,60", "--workers", "1",
            "--no-progress", "-o", "m.zarr"],
    "attractors": ["attractors", "--eta", "1.1", "--starts", "3", "--workers", "1",
                   "--no-progress", "-o", "a.nc"],
    "basins": ["basins", "--grid", "5x5", "--workers", "1", "--no-progress", "-o", "b.nc"],
    "orbits": ["orbits", "--eta", "1.1", "--period", "1", "--workers", "1",
               "--no-progress", "-o", "o.nc"],
}


#: the errors a library may turn a swallowed interrupt into, one per command and moment
#: (ValueError and OSError are the ones the commands word as their own failures)
ERRORS = (RuntimeError, ValueError, OSError, AttributeError)


@pytest.mark.parametrize("moment", ["opened", "saved", "writing"])
@pytest.mark.parametrize("name", CHECKPOINTED)
def test_an_error_a_lost_signal_leads_to_keeps_the_saved_points_line(
        name, moment, tmp_path, monkeypatch, capfd):
    """Hypothesis: a checkpointed command whose SIGTERM is lost in a ctypes callback
    (numba's loader) and whose computation then fails with an error of its own (the
    loader's state left half-built), just after its checkpoint is made, just after an
    entry is saved or while its result is written, ends as the signal asked (exit 143) with its one interrupted line
    saying how many points the checkpoint holds and how to resume, not the bare
    'vibimpact: interrupted' (what the slow line saw under load) nor that error."""
    import contextlib

    from vibimpact.cli import main
    from vibimpact.engine import compute
    from vibimpact.engine.store import Checkpoint

    monkeypatch.chdir(tmp_path)
    argv = CHECKPOINTED[name]
    error = ERRORS[(list(CHECKPOINTED).index(name) * 3
                    + ["opened", "saved", "writing"].index(moment)) % 4]

    def fail():
        lose_in_ctypes_callback(signal.SIGTERM)
        raise error("the loader's state is half-built")

    if moment == "opened":
        open_checkpoint = Checkpoint.open

        def opened(self, *a, **kw):
            open_checkpoint(self, *a, **kw)
            fail()

        monkeypatch.setattr(Checkpoint, "open", opened)
    elif moment == "writing":  # the computed result being written to its output
        from vibimpact.cli import classify, map as map_command
        from vibimpact.cli.common import census_steps

        module = {"classify": classify, "map": map_command}.get(name, census_steps)
        finish = module.finish_checkpointed

        def finishing(ds, out, ckpt, write, **kw):
            return finish(ds, out, ckpt, lambda *a, **k: fail(), **kw)

        monkeypatch.setattr(module, "finish_checkpointed", finishing)
    else:  # just after the first entry is saved, outside the block that saves it
        deferred = compute.signals_deferred

        @contextlib.contextmanager
        def saved():
            with deferred():
                yield
            fail()

        monkeypatch.setattr(compute, "signals_deferred", saved)
    rc = main(argv)
    err = capfd.readouterr().err
    lines = err.strip().splitlines()
    assert rc == 143, err
    assert "Traceback" not in err and "half-built" not in err and len(lines) == 1, err
    ckpt = argv[-1] + ".partial"
    unit = "rows?" if name == "map" else "points?"
    held = "0" if moment == "opened" else "[1-9][0-9]*"
    assert re.fullmatch(rf"vibimpact: interrupted: {held} {unit} saved in "
                        rf"{re.escape(ckpt)}; rerun with --resume", lines[0]), err
    assert {p.name for p in tmp_path.iterdir()} == {ckpt}
