"""Faults of the third adversarial round (issue 32, part 1): waits that had no way out,
writes that a signal cut inside a file library, temporaries a killed run left, a map
store with a chunk missing.

The fast tests drive the pieces in this process (the watch of child processes with a
clock of its own, the queue's answer awaited under the watch, signals held during a
write, the removal of dead writers' temporaries, the store check); the slow ones run the
command line in a subprocess and stop, signal or kill its processes for real.
"""
import os
import signal
import subprocess
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from test_cli_sweep import _points, cli
from test_faults_signals import (assert_one_interrupted_line, children, files, finish,
                                 interrupt_while_writing, messages, signal_and_finish,
                                 start, wait_for)


# --- the watch of child processes ----------------------------------------------------

@pytest.fixture
def stopped_sleeper():
    """A child process (``sleep``) stopped with SIGSTOP, killed afterwards."""
    from vibimpact.engine.watch import is_stopped

    proc = subprocess.Popen(["sleep", "60"])
    os.kill(proc.pid, signal.SIGSTOP)
    for _ in range(10000):  # the stop is asynchronous: wait for its state
        if is_stopped(proc.pid):
            break
        os.sched_yield()
    yield proc
    proc.kill()
    proc.wait()


def test_a_child_that_stays_stopped_ends_the_run_after_the_grace(stopped_sleeper,
                                                                 monkeypatch):
    """Hypothesis: the watch raises StoppedChild (a WorkerLost) naming the child once it
    has been seen stopped for the grace, not before (a clock of the test's own, so no
    sleep and no race), and forgets a child that runs again."""
    from vibimpact.engine import watch as w

    now = [100.0]
    monkeypatch.setattr(w.time, "monotonic", lambda: now[0])
    pid = stopped_sleeper.pid
    watch = w.Watch(lambda: {pid: "a worker process"}, grace=1.0)
    watch.check()  # first seen stopped
    now[0] += 0.9
    watch.check()  # within the grace
    os.kill(pid, signal.SIGCONT)
    for _ in range(10000):
        if not w.is_stopped(pid):
            break
        os.sched_yield()
    now[0] += 5.0
    watch.check()  # running again: forgotten
    assert pid not in watch.since
    os.kill(pid, signal.SIGSTOP)
    for _ in range(10000):
        if w.is_stopped(pid):
            break
        os.sched_yield()
    watch.check()
    now[0] += 1.0
    with pytest.raises(w.StoppedChild, match="a worker process was stopped"):
        watch.check()
    from vibimpact.engine.executors import WorkerLost

    assert issubclass(w.StoppedChild, WorkerLost)


def test_a_running_child_is_never_counted_stopped(monkeypatch):
    """Hypothesis: a child that runs (or sleeps) is never reported, however long the
    run waits on it; the wait's bound is the child's state, not a time."""
    from vibimpact.engine import watch as w

    now = [0.0]
    monkeypatch.setattr(w.time, "monotonic", lambda: now[0])
    proc = subprocess.Popen(["sleep", "60"])
    try:
        watch = w.Watch(lambda: {proc.pid: "a worker process"}, grace=1.0)
        for _ in range(5):
            watch.check()
            now[0] += 1000.0
        assert not watch.since
    finally:
        proc.kill()
        proc.wait()


def test_a_stopped_queue_process_ends_a_wait_instead_of_blocking_it():
    """Hypothesis: the points are taken off the queue by a thread of their own, so that
    waiting for them on a manager whose process is stopped raises StoppedChild in the
    main thread (never a recv or a connection handshake blocked for good); ending the
    manager kills it (a stopped manager never answers 'shutdown') and the thread ends
    with it."""
    import multiprocessing as mp
    from multiprocessing.managers import SyncManager

    from vibimpact.engine.executors import Drainer, _end_manager
    from vibimpact.engine.watch import StoppedChild, Watch, is_stopped

    manager = SyncManager(ctx=mp.get_context("fork"))
    manager.start()
    proc = manager._process
    try:
        q = manager.Queue()
        q.put(1)
        points = Drainer(q)
        points.start()
        watch = Watch(lambda: {proc.pid: "the points' queue process"}, grace=0.0)
        points.sync(watch)
        assert points.take() == [1]
        os.kill(proc.pid, signal.SIGSTOP)
        for _ in range(10000):
            if is_stopped(proc.pid):
                break
            os.sched_yield()
        with pytest.raises(StoppedChild, match="queue process was stopped"):
            points.sync(watch)
    finally:
        _end_manager(manager)
    assert not proc.is_alive()
    points.join(10.0)
    assert not points.is_alive()


# --- signals held during a write, temporaries of dead writers ------------------------

def _signalling(monkeypatch, method, signum):
    """Make ``xr.Dataset.<method>`` send ``signum`` to this process mid-write."""
    original = getattr(xr.Dataset, method)

    def write(self, *args, **kwargs):
        os.kill(os.getpid(), signum)
        return original(self, *args, **kwargs)

    monkeypatch.setattr(xr.Dataset, method, write)


DS = xr.Dataset({"x": (("i", "j"), np.arange(12.0).reshape(3, 4))})


@pytest.mark.parametrize("fmt", ["netcdf", "zarr"])
def test_sigterm_during_a_write_ends_it_with_nothing_left(fmt, tmp_path, monkeypatch):
    """Hypothesis: SIGTERM received while netCDF4 or zarr writes (under the commands'
    signal guard) is delivered once the library returns: Interrupted(15) is raised, the
    temporary is removed and nothing is put in place (no half-written output, no lock
    left held by a handler raising inside the library)."""
    from vibimpact.engine.signals import Interrupted, StopWorkersOnSignal
    from vibimpact.io import write_netcdf
    from vibimpact.maps.store import write_map

    _signalling(monkeypatch, "to_netcdf" if fmt == "netcdf" else "to_zarr",
                signal.SIGTERM)
    with pytest.raises(Interrupted) as info:
        with StopWorkersOnSignal():
            if fmt == "netcdf":
                write_netcdf(DS, tmp_path / "r.nc")
            else:
                write_map(DS, tmp_path / "m.zarr")
    assert info.value.signum == signal.SIGTERM
    assert list(tmp_path.iterdir()) == []


def test_sigint_during_an_api_write_is_a_keyboard_interrupt(tmp_path, monkeypatch):
    """Hypothesis: outside any guard (the API in a script, with Python's own Ctrl-C
    handler, whatever the test run inherited), Ctrl-C during write_netcdf still raises
    KeyboardInterrupt, after the write, with nothing left on disk."""
    from vibimpact.io import write_netcdf

    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        _signalling(monkeypatch, "to_netcdf", signal.SIGINT)
        with pytest.raises(KeyboardInterrupt):
            write_netcdf(DS, tmp_path / "r.nc")
    finally:
        signal.signal(signal.SIGINT, old)
    assert list(tmp_path.iterdir()) == []


def test_a_users_own_signal_handler_is_left_alone(tmp_path, monkeypatch):
    """Hypothesis: a script's own SIGTERM handler is not held back by a write (it is
    called as the signal comes, and the write completes): the package holds only the
    default handlers and its own guard's."""
    from vibimpact.io import write_netcdf

    seen = []
    old = signal.signal(signal.SIGTERM, lambda s, f: seen.append(s))
    try:
        _signalling(monkeypatch, "to_netcdf", signal.SIGTERM)
        write_netcdf(DS, tmp_path / "r.nc")
    finally:
        signal.signal(signal.SIGTERM, old)
    assert seen == [signal.SIGTERM]
    assert [p.name for p in tmp_path.iterdir()] == ["r.nc"]


def _dead_pid():
    """The id of a process that has ended."""
    proc = subprocess.Popen(["true"])
    proc.wait()
    return proc.pid


@pytest.mark.parametrize("name", ["r.nc", "m.zarr"])
def test_a_write_removes_what_dead_writers_left_and_nothing_else(name, tmp_path):
    """Hypothesis: writing an output removes the temporaries of that output whose
    writer's process is gone (``.NAME.PID-*.tmp`` and a Zarr ``.old``), and leaves a
    live process's temporary, another output's, and names of another pattern alone."""
    from vibimpact.io import write_netcdf
    from vibimpact.maps.store import write_map

    dead, live = _dead_pid(), os.getppid()
    stale = [f".{name}.{dead}-abc123.tmp", f".{name}.{dead}-def456.old"]
    kept = [f".{name}.{live}-abc123.tmp", f".other.nc.{dead}-abc123.tmp",
            f".{name}.abc123.tmp", f"{name}.{dead}-abc123.tmp"]
    for n in stale + kept:
        if name.endswith(".zarr") and n.startswith(f".{name}"):
            (tmp_path / n).mkdir()
            (tmp_path / n / "zarr.json").write_text("{}")
        else:
            (tmp_path / n).write_bytes(b"left")
    (write_netcdf if name.endswith(".nc") else write_map)(DS, tmp_path / name)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(kept + [name])


# --- a damaged map store -------------------------------------------------------------

@pytest.fixture
def map_store(tmp_path):
    """A small map-shaped Zarr store written by write_map."""
    from vibimpact.maps.store import write_map

    ds = xr.Dataset({"regime": (("kh", "eta"), np.full((2, 3), 2, dtype=np.int8)),
                     "period": (("kh", "eta"), np.zeros((2, 3), dtype=np.int16)),
                     "lyapunov": (("kh", "eta"), np.full((2, 3), np.nan))},
                    coords={"kh": [10.0, 20.0], "eta": [1.0, 1.1, 1.2]})
    path = tmp_path / "m.zarr"
    write_map(ds, path)
    return path


def test_every_chunk_of_a_map_is_written_and_it_reads_back(map_store):
    """Hypothesis: a map whose variables hold only fill values (period 0, NaN
    exponents) still has every chunk on disk, so that the store check below cannot
    mistake them for damage; the store reads back equal."""
    from vibimpact.maps.store import open_map

    for name in ("regime", "period", "lyapunov"):
        assert list((map_store / name / "c").rglob("*")), name
    ds = open_map(map_store)
    assert (ds.regime.values == 2).all() and (ds.period.values == 0).all()


def _chunk(store, name):
    """The (only) chunk file of variable ``name``."""
    return next(p for p in (store / name / "c").rglob("*") if p.is_file())


def _strip_consolidated(store):
    """Remove the consolidated metadata from the root zarr.json, keeping the rest."""
    import json

    meta = json.loads((store / "zarr.json").read_text())
    meta.pop("consolidated_metadata")
    (store / "zarr.json").write_text(json.dumps(meta))


#: damage -> (what it does to the store, the variable the message must name or None)
DAMAGES = {
    "regime chunk removed": (lambda s: _rmtree(s / "regime" / "c"), "regime"),
    "period directory removed": (lambda s: _rmtree(s / "period"), "period"),
    "lyapunov metadata removed": (lambda s: (s / "lyapunov" / "zarr.json").unlink(),
                                  "lyapunov"),
    "regime chunk truncated to 0 bytes": (
        lambda s: _chunk(s, "regime").write_bytes(b""), "regime"),
    "regime chunk cut in half": (
        lambda s: _chunk(s, "regime").write_bytes(
            _chunk(s, "regime").read_bytes()[:len(_chunk(s, "regime").read_bytes()) // 2]),
        "regime"),
    "period chunk of garbage": (
        lambda s: _chunk(s, "period").write_bytes(b"garbage garbage garbage"), "period"),
    "lyapunov chunk of zero bytes of its size": (
        lambda s: _chunk(s, "lyapunov").write_bytes(
            bytes(len(_chunk(s, "lyapunov").read_bytes()))), "lyapunov"),
    "regime metadata not JSON": (
        lambda s: (s / "regime" / "zarr.json").write_text("{"), "regime"),
    "regime metadata of another kind": (
        lambda s: (s / "regime" / "zarr.json").write_text('{"zarr_format": 3}'),
        "regime"),
    "consolidated metadata stripped": (_strip_consolidated, None),
    "consolidated metadata stripped, period removed": (
        lambda s: (_strip_consolidated(s), _rmtree(s / "period")), None),
    "root zarr.json of garbage": (
        lambda s: (s / "zarr.json").write_bytes(b"\x00\xff garbage"), None),
}


def _rmtree(path):
    import shutil

    shutil.rmtree(path)


@pytest.mark.parametrize("damage", list(DAMAGES))
def test_a_damaged_map_is_refused_naming_the_store_and_variable(damage, map_store):
    """Hypothesis: a Zarr map with a chunk, a variable or an array's metadata missing
    (which Zarr reads as the fill value: a blank map), a chunk truncated, cut or
    overwritten (Zarr raised a RuntimeError of its codec, without the path), an array's
    metadata broken, or no consolidated metadata (which write_map always writes; Zarr
    then opened whatever arrays were left) is refused by open_map with a ValueError
    naming the store and, where one variable is damaged, the variable."""
    from vibimpact.maps.store import open_map

    change, name = DAMAGES[damage]
    change(map_store)
    pattern = r"m\.zarr.*damaged" + (rf".*'{name}'" if name else "")
    with pytest.raises(ValueError, match=pattern):
        open_map(map_store)


@pytest.mark.parametrize("damage", list(DAMAGES))
def test_plot_of_a_damaged_map_is_one_line_and_exit_2(damage, map_store, monkeypatch,
                                                      capfd):
    """Hypothesis: 'vibimpact plot' of a damaged map store (each damage above) says so in
    one line naming the damaged variable, exit 2, and draws nothing (it drew a blank
    map, exit 0, or complained of a missing 'period' or Zarr's codec error without
    naming what was damaged)."""
    from test_bad_input import run_cli

    change, name = DAMAGES[damage]
    change(map_store)
    monkeypatch.chdir(map_store.parent)
    rc, out, err = run_cli(["plot", "m.zarr", "-o", "p.png"], capfd)
    assert rc == 2 and err.startswith("vibimpact: error: "), (rc, err)
    assert len(err.strip().splitlines()) == 1 and "damaged" in err, err
    assert name is None or repr(name) in err, err
    assert not (map_store.parent / "p.png").exists()


# --- the command line, for real (slow) -----------------------------------------------

SWEEP = ["--eta", "0.95:1.25:0.002", "--preset", "fig8", "--direction", "both",
         "--no-progress"]
STOP_CASES = {
    "classify, a worker": (["classify", *SWEEP, "--workers", "2", "-o", "c.nc"], -1,
                           "a worker process", "c.nc.partial"),
    "classify, the queue": (["classify", *SWEEP, "--workers", "2", "-o", "c.nc"], 0,
                            "the points' queue process", "c.nc.partial"),
    "bifurcation, a worker": (["bifurcation", *SWEEP, "--workers", "2", "-o", "b.png"],
                              -1, "a worker process", None),
    "attractors, a worker": (["attractors", "--preset", "fig8", "--eta", "1.25",
                              "--starts", "200", "--workers", "2", "--no-progress", "-o",
                              "a.nc"], -1,
                             "a worker process", "a.nc.partial"),
}


#: the watch's grace for a stopped child made longer than the test can last: a signal
#: the test sends after the stop always lands first, however loaded the machine
PATIENT_WATCH = ("import vibimpact.engine.watch as w\n"
                 "w.Watch.__init__.__defaults__ = (600.0,)")


def _stop_a_child(args, which, tmp_path, prelude=None):
    """Start ``args`` (after ``prelude``), SIGSTOP its child ``which`` (an index into its
    children: the pool's workers are the newest, the queue's process the oldest) once its
    pool runs (three children: the queue's and two workers, or the warm-up helper's and
    two workers; two for a run without a queue); the process."""
    least = 2 if args[0] == "attractors" else 3  # attractors: no queue of points
    proc = start(args, tmp_path, prelude=prelude)
    try:
        wait_for(lambda: len(children(proc.pid)) >= least, proc, "pool workers")
        os.kill(children(proc.pid)[which], signal.SIGSTOP)
    except BaseException:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        raise
    return proc


@pytest.mark.slow
@pytest.mark.parametrize("case", list(STOP_CASES))
def test_a_stopped_child_ends_the_command_with_one_line(case, tmp_path):
    """Hypothesis: a worker or the points' queue process stopped with SIGSTOP (it
    neither finishes nor dies) ends classify, bifurcation and attractors with exit 2
    and one line naming the stopped process (and the saved points and --resume where
    there is a checkpoint); no process of the run is left, stopped or not."""
    args, which, what, ckpt = STOP_CASES[case]
    proc = _stop_a_child(args, which, tmp_path)
    try:
        status = finish(proc, timeout=120)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    lines = messages(tmp_path)
    assert status == 2 and len(lines) == 1, (status, lines)
    assert lines[0].startswith(f"vibimpact: error: {what} was stopped (SIGSTOP)"), lines
    if ckpt is not None:
        assert "rerun with --resume" in lines[0] or "before any" in lines[0], lines
    else:
        assert lines[0].endswith("; nothing written"), lines
    assert subprocess.run(["pgrep", "-g", str(proc.pid)],
                          capture_output=True).stdout == b""


@pytest.mark.slow
@pytest.mark.parametrize("which", [-1, 0], ids=["worker", "queue"])
def test_sigterm_ends_a_command_whose_child_is_stopped(which, tmp_path):
    """Hypothesis: SIGTERM to classify whose worker or queue process is stopped ends it
    (exit 143, the interrupted line with the saved points): the stopped child is killed,
    never asked to shut down, so nothing waits on it.  The watch's grace is made long so
    that the SIGTERM comes first (a stop the watch reports first is the test above; a
    signal while its line is said, test_faults_signals)."""
    proc = _stop_a_child(["classify", *SWEEP, "--workers", "2", "-o", "c.nc"], which,
                         tmp_path, prelude=PATIENT_WATCH)
    assert_one_interrupted_line(tmp_path, signal_and_finish(proc, signal.SIGTERM))


@pytest.mark.slow
def test_a_stopped_dask_worker_ends_the_map_with_one_line(tmp_path):
    """Hypothesis: 'map --workers 2' whose local Dask worker process is stopped (while
    the cluster starts or computes) ends with exit 2 and one line naming the stopped
    worker, no traceback from Dask's clean-up at exit, no process left."""
    args = ["map", "--eta", "1.0:1.3:0.002", "--vary", "kh=50:80:5", "--workers", "2",
            "--no-progress", "-o", "m.zarr"]
    proc = start(args, tmp_path)
    try:
        wait_for(lambda: [c for c in children(proc.pid) if b"spawn_main" in
                          Path(f"/proc/{c}/cmdline").read_bytes()], proc,
                 "a Dask worker process")
        worker = [c for c in children(proc.pid)
                  if b"spawn_main" in Path(f"/proc/{c}/cmdline").read_bytes()][-1]
        os.kill(worker, signal.SIGSTOP)
        status = finish(proc, timeout=180)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    lines = [ln for ln in messages(tmp_path) if "distributed." not in ln]
    assert status == 2 and len(lines) == 1, (status, lines)
    assert "a Dask worker process was stopped (SIGSTOP)" in lines[0], lines


@pytest.mark.slow
def test_a_second_signal_during_a_held_write_ends_at_once(tmp_path):
    """Hypothesis: a write holds the first signal until the file library returns; a
    second one (here SIGINT after SIGTERM, while the write is stalled) ends the process
    at once, by that signal, with the write's temporary removed: the way out of a write
    that does not return."""
    proc = start(["simulate", "--preset", "fig8", "--eta", "1.0", "--periods", "20",
                  "--transient", "20", "-o", "r.nc"], tmp_path, stall=True)
    try:
        wait_for(lambda: "WRITING" in (tmp_path / "err.txt").read_text(), proc,
                 "a write")
        os.kill(proc.pid, signal.SIGTERM)
        os.kill(proc.pid, signal.SIGINT)
        status = finish(proc)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert status in (-signal.SIGINT, -signal.SIGTERM), status
    assert files(tmp_path) == []


#: commands whose write a SIGKILL cuts, and how the same command later succeeds
KILLED_WRITES = {
    "simulate": (["simulate", "--preset", "fig8", "--eta", "1.0", "--periods", "20",
                  "--transient", "20", "-o", "r.nc"], "r.nc", []),
    "continue": (["continue", "--preset", "fig8", "--eta", "1.12", "--stop", "1.13",
                  "-o", "p.nc"], "p.nc", []),
    "classify": (["classify", "--eta", "1.0:1.03:0.01", "--preset", "fig8",
                  "--no-progress", "-o", "c.nc"], "c.nc", ["--resume"]),
    "map": (["map", "--eta", "1.0:1.02:0.01", "--vary", "kh=10:20:10", "--preset",
             "fig8", "--workers", "1", "--no-progress", "-o", "m.zarr"], "m.zarr",
            ["--resume"]),
}


@pytest.mark.slow
@pytest.mark.parametrize("name", list(KILLED_WRITES))
def test_a_later_run_removes_the_temporary_a_killed_write_left(name, tmp_path):
    """Hypothesis: SIGKILL while a command writes its output leaves its temporary
    (``.OUT.PID-*.tmp``: nothing can remove it then); the same command run again
    (with --resume where the killed run kept a checkpoint) succeeds and leaves only its
    output: the dead writer's temporary is gone."""
    args, out, again = KILLED_WRITES[name]
    proc = start(args, tmp_path, stall=True)
    try:
        wait_for(lambda: "WRITING" in (tmp_path / "err.txt").read_text(), proc,
                 "a write")
        proc.send_signal(signal.SIGKILL)
        assert finish(proc) == -signal.SIGKILL
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    left = [n for n in files(tmp_path) if n.startswith(f".{out}.{proc.pid}-")]
    assert left, files(tmp_path)
    r = cli(*args, *again, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert files(tmp_path) == [out]


@pytest.mark.slow
def test_rerun_sigterm_during_its_write_ends_with_nothing_left(tmp_path):
    """Hypothesis: SIGTERM while rerun writes its hidden copy of a simulate file (the
    write that deadlocked) ends it: exit 143, one line, only the original file left."""
    assert cli("simulate", "--preset", "fig8", "--eta", "1.0", "--periods", "50",
               "--transient", "5", "-o", "s.nc", cwd=tmp_path).returncode == 0
    status, (announced, *lines) = interrupt_while_writing(["rerun", "s.nc"], tmp_path)
    assert announced.startswith("vibimpact: rerunning 'vibimpact simulate "), announced
    assert status == 143 and len(lines) == 1, (status, lines)
    assert lines[0].startswith("vibimpact: interrupted"), lines
    assert files(tmp_path) == ["s.nc"]


@pytest.mark.slow
@pytest.mark.parametrize("moment", ["as it appears", "after a saved row"])
def test_a_killed_resource_tracker_leaves_the_map_whole_and_quiet(moment, tmp_path):
    """Hypothesis: 'map --workers 2' whose multiprocessing resource tracker is SIGKILLed
    as soon as it appears (its workers starting) or mid-run succeeds: exit 0, its
    summary only (no relaunch warning, no KeyError traceback from the relaunched
    tracker), the store written and nothing else."""
    args = ["map", "--eta", "1.0:1.3:0.01", "--vary", "kh=50:80:10", "--workers", "2",
            "--no-progress", "-o", "m.zarr"]

    def tracker():
        for c in children(proc.pid):
            try:
                if b"resource_tracker" in Path(f"/proc/{c}/cmdline").read_bytes():
                    return c
            except OSError:
                pass
        return None

    proc = start(args, tmp_path)
    try:
        wait_for(lambda: tracker() is not None, proc, "the resource tracker")
        if moment != "as it appears":
            wait_for(lambda: _points(tmp_path / "m.zarr.partial"), proc, "a saved row")
        os.kill(tracker(), signal.SIGKILL)
        status = finish(proc, timeout=180)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    text = (tmp_path / "err.txt").read_text()
    assert status == 0, text
    assert "Traceback" not in text and "Warning" not in text, text
    assert files(tmp_path) == ["m.zarr"]
