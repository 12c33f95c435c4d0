"""Faults from outside (issue 23, failures 1, 4 and 8): a worker process killed with
SIGKILL (what the OOM killer does) at different moments of classify, bifurcation and map;
SIGTERM (what ``timeout`` and batch systems send) and SIGINT while every writing command
computes or writes; rerun stopped; ``map --scheduler`` with a scheduler that cannot be.

Every case runs the real command line in a subprocess and sends real signals; it checks
the exit status, the one line on stderr, that no temporary file is left, that the
checkpoint is kept, and that ``--resume`` gives the uninterrupted result bit for bit.
"""
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from test_cli_sweep import _env, _points, assert_same_data, cli

#: real processes killed and signalled at moments of their runs: a long study, run by CI
#: on a line of its own (pyproject.toml, .ci/run)
pytestmark = pytest.mark.slow

#: a classify sweep long enough to be killed at three moments
SWEEP = ["--eta", "0.95:1.25:0.002", "--preset", "fig8", "--direction", "both",
         "--no-progress"]
N_SWEEP = 2 * 151
#: a map of 8 rows of 11 points in both directions
MAP = ["--eta", "1.0:1.1:0.01", "--vary", "kh=10:80:10", "--preset", "fig8",
       "--direction", "both", "--no-progress"]

#: runs the command line with every dataset write stalled after its temporary file is
#: complete (it says WRITING on stderr first), so that a signal lands while writing; the
#: stalled write returns when the file GO appears (the test makes it after its signal:
#: a write holds SIGINT and SIGTERM until the file library returns) or after its 12000 polls
STALL = r"""
import os, sys, time
import xarray as xr
def stall(write):
    def stalled(self, *args, **kwargs):
        out = write(self, *args, **kwargs)
        sys.stderr.write("WRITING\n")
        sys.stderr.flush()
        for _ in range(12000):
            if os.path.exists("GO"):
                break
            time.sleep(0.01)
        return out
    return stalled
xr.Dataset.to_netcdf = stall(xr.Dataset.to_netcdf)
xr.Dataset.to_zarr = stall(xr.Dataset.to_zarr)
from vibimpact.cli import main
sys.exit(main(sys.argv[1:]))
"""


#: the same with the figure's save stalled instead (the data file is written before it)
STALL_IMAGE = STALL.replace(
    "xr.Dataset.to_netcdf = stall(xr.Dataset.to_netcdf)\n"
    "xr.Dataset.to_zarr = stall(xr.Dataset.to_zarr)\n",
    "import matplotlib.figure as mf\nmf.Figure.savefig = stall(mf.Figure.savefig)\n")


def start(args, cwd, stall=False, env=None, module="vibimpact.cli", ignoring=(),
          prelude=None):
    """Start ``vibimpact ARGS`` (stderr to ``cwd/err.txt``, ``env`` added to the
    environment) in its own session, as ``python -m module`` (``"vibimpact"``: through
    the script's entry point) with the signals ``ignoring`` ignored from its start;
    ``stall``: True stalls the dataset writes, ``"image"`` the figure's; ``prelude``:
    Python run first, then the command line's ``main()`` as the process's program."""
    code = (["-c", STALL_IMAGE] if stall == "image" else ["-c", STALL] if stall
            else ["-c", f"{prelude}\nimport sys\nfrom vibimpact.cli import main\n"
                        "sys.exit(main())"] if prelude else ["-m", module])

    def ignore():
        for sig in ignoring:
            signal.signal(sig, signal.SIG_IGN)

    err = open(Path(cwd) / "err.txt", "w")
    try:
        return subprocess.Popen([sys.executable, *code, *map(str, args)], cwd=cwd,
                                env=dict(_env(), **(env or {})),
                                stdout=subprocess.DEVNULL, stderr=err,
                                start_new_session=True,
                                preexec_fn=ignore if ignoring else None)
    finally:
        err.close()


def wait_for(condition, proc, what, timeout=120):
    """Poll ``condition()`` until true; fail if ``proc`` ends first, or (a guard against
    a hang, not a claim about speed) after ``timeout`` seconds."""
    deadline = time.monotonic() + timeout
    while not condition():
        assert proc.poll() is None, f"ended before {what}"
        if time.monotonic() > deadline:
            pytest.fail(f"no {what} in {timeout} s")
        time.sleep(0.005)


def finish(proc, timeout=60):
    """Wait for ``proc`` (killed after ``timeout`` s: a hang fails the test)."""
    try:
        proc.wait(timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        pytest.fail(f"still running {timeout} s after the fault: a hang")
    return proc.returncode


def signal_and_finish(proc, signum, timeout=120):
    """Send ``signum`` to ``proc`` and wait for it (:func:`finish`); its process group
    is killed if the test fails first."""
    try:
        proc.send_signal(signum)
        return finish(proc, timeout)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)


def assert_one_interrupted_line(cwd, status, expect=143):
    """The command ended with status ``expect`` and said one line, its interrupted
    line (the saved points may follow it)."""
    lines = messages(cwd)
    assert status == expect and len(lines) == 1, (status, lines)
    assert lines[0].startswith("vibimpact: interrupted"), lines


def messages(cwd):
    """The lines on stderr, without the stall marker."""
    text = (Path(cwd) / "err.txt").read_text()
    assert "Traceback" not in text and "Exception ignored" not in text, text
    return [line for line in text.splitlines() if line != "WRITING"]


def children(pid):
    """The process ids of the children of ``pid``."""
    out = set()
    for task in os.listdir(f"/proc/{pid}/task"):
        try:
            out |= {int(c) for c in
                    Path(f"/proc/{pid}/task/{task}/children").read_text().split()}
        except OSError:
            pass
    return sorted(out)


def files(cwd):
    """The names in ``cwd`` but the test's own stderr file (hidden ones included)."""
    return sorted(p.name for p in Path(cwd).iterdir() if p.name != "err.txt")


def saved_entries(ckpt):
    """The entry files a checkpoint directory holds now (none while it is absent)."""
    try:
        return [p for p in Path(ckpt).iterdir()
                if p.suffix == ".npz" and not p.name.startswith(".")]
    except OSError:
        return []


def no_temporaries(ckpt):
    """No temporary entry inside a checkpoint directory."""
    return not [p for p in Path(ckpt).iterdir() if p.name.startswith(".tmp")]


@pytest.fixture(scope="module")
def references(tmp_path_factory):
    """The uninterrupted outputs: classify (two workers) and map (in this process)."""
    from vibimpact.io import read_netcdf
    from vibimpact.maps import open_map

    d = tmp_path_factory.mktemp("references")
    r = cli("classify", *SWEEP, "--workers", "2", "-o", "c.nc", cwd=d)
    assert r.returncode == 0, r.stderr
    r = cli("map", *MAP, "--workers", "1", "-o", "m.zarr", cwd=d)
    assert r.returncode == 0, r.stderr
    return {"classify": read_netcdf(d / "c.nc"), "map": open_map(d / "m.zarr")}


# --- a worker killed with SIGKILL ----------------------------------------------------

@pytest.mark.parametrize("moment", [0.0, 0.5, 0.85])
def test_killed_sweep_worker_ends_classify_with_a_resumable_checkpoint(moment, tmp_path,
                                                                        references):
    """Hypothesis: a pool worker of 'classify --workers 2' SIGKILLed early (before any
    point was saved or just after), mid-run or near the end ends the command within
    seconds (no hang) with exit status 2 and one line naming the dead worker, the saved
    points and --resume; the checkpoint holds exactly that many points, nothing goes on
    computing afterwards, no temporary file is left, and --resume writes the
    uninterrupted sweep bit for bit.  A worker that dies idle after the last point was
    computed (near the end, the other worker finishing) leaves a complete sweep: then the
    command writes it, exit 0, no line, no checkpoint, bit for bit the uninterrupted
    one."""
    from vibimpact.io import read_netcdf

    ckpt = tmp_path / "c.nc.partial"
    proc = start(["classify", *SWEEP, "--workers", "2", "-o", "c.nc"], tmp_path)
    try:
        wait_for(lambda: len(children(proc.pid)) >= 3 and
                 len(_points(ckpt)) >= moment * N_SWEEP, proc, "pool workers")
        victim = children(proc.pid)[-1]  # the pool's workers start after the queue's
        os.kill(victim, signal.SIGKILL)
        status = finish(proc)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    if status == 0:  # the worker died idle, after its last point: the sweep was complete
        assert not messages(tmp_path)
        assert_same_data(read_netcdf(tmp_path / "c.nc"), references["classify"])
        assert files(tmp_path) == ["c.nc"]
        return
    assert status == 2, (status, (tmp_path / "err.txt").read_text())
    lines = messages(tmp_path)
    assert len(lines) == 1, lines
    saved = _points(ckpt)
    m = re.fullmatch(r"vibimpact: error: a worker process died unexpectedly \(killed by "
                     r"the system or a signal\)(?:: (\d+) points? saved in c\.nc\.partial; "
                     r"rerun with --resume| before any point was saved)", lines[0])
    assert m, lines[0]
    assert int(m.group(1) or 0) == len(saved) <= N_SWEEP  # all: the kill came last
    time.sleep(0.3)
    assert _points(ckpt) == saved  # no orphaned worker goes on computing
    assert files(tmp_path) == (["c.nc.partial"] if ckpt.exists() else [])
    if ckpt.exists():
        assert no_temporaries(ckpt)

    r = cli("classify", *SWEEP, "--workers", "2", "-o", "c.nc", "--resume", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert_same_data(read_netcdf(tmp_path / "c.nc"), references["classify"])
    assert files(tmp_path) == ["c.nc"]


def test_killed_queue_process_ends_classify_with_a_resumable_checkpoint(tmp_path):
    """Hypothesis: the process that carries finished points back (the queue's manager,
    the first child) SIGKILLed mid-run also ends the command within seconds, exit 2, one
    line with --resume advice, and the checkpoint is kept."""
    ckpt = tmp_path / "c.nc.partial"
    proc = start(["classify", *SWEEP, "--workers", "2", "-o", "c.nc"], tmp_path)
    try:
        wait_for(lambda: len(children(proc.pid)) >= 3 and len(_points(ckpt)) >= 20, proc,
                 "20 saved points")
        os.kill(children(proc.pid)[0], signal.SIGKILL)
        status = finish(proc)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    lines = messages(tmp_path)
    assert status == 2 and len(lines) == 1, (status, lines)
    assert lines[0].startswith("vibimpact: error: ") and "died" in lines[0]
    assert lines[0].endswith("saved in c.nc.partial; rerun with --resume"), lines[0]
    assert files(tmp_path) == ["c.nc.partial"], files(tmp_path)
    assert no_temporaries(ckpt), sorted(p.name for p in ckpt.iterdir())


def test_killed_worker_ends_bifurcation_with_one_line_and_no_file(tmp_path):
    """Hypothesis: bifurcation (no checkpoint, no --resume) with a pool worker SIGKILLed
    mid-run ends within seconds, exit 2, one line naming the dead worker and saying
    nothing was written (no --resume advice), and leaves no file at all."""
    proc = start(["bifurcation", *SWEEP, "--workers", "2", "-o", "b.png"], tmp_path)
    try:
        wait_for(lambda: len(children(proc.pid)) >= 3, proc, "pool workers")
        time.sleep(0.5)
        os.kill(children(proc.pid)[-1], signal.SIGKILL)
        status = finish(proc)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert status == 2, (status, (tmp_path / "err.txt").read_text())
    assert messages(tmp_path) == ["vibimpact: error: a worker process died unexpectedly "
                                  "(killed by the system or a signal); nothing written"]
    assert files(tmp_path) == []


def dask_workers(pid):
    """The Dask worker processes of a local cluster started by the command ``pid`` (the
    nannies run in its process, their workers are spawned children)."""
    return [w for w in children(pid)
            if b"spawn_main" in Path(f"/proc/{w}/cmdline").read_bytes()]


@pytest.mark.parametrize("retries", [3, 0])
def test_killed_dask_worker_is_replaced_or_ends_the_map_resumably(retries, tmp_path,
                                                                   references):
    """Hypothesis: 'map --workers 2' (a local Dask cluster) whose worker process is
    SIGKILLed after the first saved row loses nothing.  With Dask's default retries the
    worker is restarted and its tasks run again: exit 0, no temporary file, the serial
    map bit for bit.  With no retries left (allowed-failures 0) the map ends within
    seconds with exit 2 and one line (no scheduler log lines) naming the saved rows and
    --resume, and --resume gives the serial map bit for bit."""
    from vibimpact.maps import open_map

    ckpt = tmp_path / "m.zarr.partial"
    env = {"DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES": str(retries)}
    proc = start(["map", *MAP, "--workers", "2", "-o", "m.zarr"], tmp_path, env=env)
    try:
        wait_for(lambda: _points(ckpt), proc, "a saved row")
        workers = dask_workers(proc.pid)
        assert workers, children(proc.pid)
        os.kill(workers[-1], signal.SIGKILL)
        assert len(_points(ckpt)) < 16  # 8 rows, 2 directions: killed mid-run
        status = finish(proc, timeout=120)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    if retries:
        assert status == 0, messages(tmp_path)
    else:
        lines = messages(tmp_path)
        assert status == 2 and len(lines) == 1, (status, lines)
        m = re.fullmatch(r"vibimpact: error: Dask workers died running a task more often "
                         r"than Dask retries one \(distributed\.scheduler\.allowed-"
                         r"failures\): (\d+) rows? saved in m\.zarr\.partial; rerun with "
                         r"--resume", lines[0])
        assert m, lines[0]
        assert files(tmp_path) == ["m.zarr.partial"] and no_temporaries(ckpt)
        r = cli("map", *MAP, "--workers", "2", "-o", "m.zarr", "--resume", cwd=tmp_path)
        assert r.returncode == 0, r.stderr
    assert files(tmp_path) == ["m.zarr"]
    assert_same_data(open_map(tmp_path / "m.zarr"), references["map"])


# --- SIGTERM / SIGINT at every phase --------------------------------------------------

def interrupt_while_writing(args, cwd, signum=signal.SIGTERM, stall=True, times=1):
    """Run ``args`` with its writes stalled, send ``signum`` ``times`` times once it
    writes, then let the write return (the file GO, removed again); the exit status and
    the stderr lines."""
    proc = start(args, cwd, stall=stall)
    try:
        wait_for(lambda: "WRITING" in (Path(cwd) / "err.txt").read_text(), proc,
                 "a write")
        for _ in range(times):
            proc.send_signal(signum)
        if times == 1:
            (Path(cwd) / "GO").touch()
        status = finish(proc)
        (Path(cwd) / "GO").unlink(missing_ok=True)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    return status, messages(cwd)


SIMPLE = {
    "simulate": ["simulate", "--preset", "fig8", "--eta", "1.0", "--periods", "20",
                 "--transient", "20", "-o", "r.nc"],
    "simulate --plot": ["simulate", "--preset", "fig8", "--eta", "1.0", "--periods", "20",
                        "--transient", "20", "-o", "r.nc", "--plot", "xy.png"],
    "bifurcation": ["bifurcation", "--eta", "1.0:1.03:0.01", "--no-progress", "-o",
                    "b.png"],
    "continue": ["continue", "--preset", "fig8", "--eta", "1.12", "--stop", "1.13", "-o",
                 "p.nc"],
}


@pytest.mark.parametrize("name", sorted(SIMPLE))
def test_sigterm_while_writing_leaves_nothing(name, tmp_path):
    """Hypothesis: SIGTERM while a command without a checkpoint writes its output (its
    temporary file complete, not yet renamed) is handled as Ctrl-C: exit 143, the one
    line 'vibimpact: interrupted', and no file left, temporary or final."""
    status, lines = interrupt_while_writing(SIMPLE[name], tmp_path)
    assert status == 143 and lines == ["vibimpact: interrupted"], (status, lines)
    assert files(tmp_path) == []


@pytest.mark.parametrize("name", ["simulate --plot", "bifurcation"])
def test_sigterm_while_drawing_the_image_leaves_no_output(name, tmp_path):
    """Hypothesis: a command's outputs stay together under a signal too: SIGTERM while
    simulate --plot or bifurcation saves its image (the data file already in place)
    removes the data file again, with the image's temporary file: exit 143, one line, no
    file left."""
    status, lines = interrupt_while_writing(SIMPLE[name], tmp_path, stall="image")
    assert status == 143 and lines == ["vibimpact: interrupted"], (status, lines)
    assert files(tmp_path) == []


CHECKPOINTED = {
    "classify": (["classify", "--eta", "1.0:1.03:0.01", "--preset", "fig8",
                  "--no-progress", "-o", "c.nc"], "c.nc", "4 points"),
    "map": (["map", "--eta", "1.0:1.02:0.01", "--vary", "kh=10:20:10", "--preset",
             "fig8", "--workers", "1", "--no-progress", "-o", "m.zarr"], "m.zarr",
            "2 rows"),
}


@pytest.mark.parametrize("sig", ["SIGTERM", "SIGINT"])
@pytest.mark.parametrize("name", sorted(CHECKPOINTED))
def test_signal_while_writing_keeps_the_checkpoint_and_resumes(name, sig, tmp_path):
    """Hypothesis: SIGTERM (exit 143) or SIGINT (130) while classify or map writes its
    output removes the temporary file, keeps the complete checkpoint and says so in one
    line with --resume advice; a stale temporary file of the output and of the
    checkpoint (what a SIGKILL at that moment leaves) is removed by --resume, whose
    output equals the uninterrupted run's bit for bit."""
    from vibimpact.io import read_netcdf
    from vibimpact.maps import open_map

    args, out, saved = CHECKPOINTED[name]
    signum = getattr(signal, sig)
    status, lines = interrupt_while_writing(args, tmp_path, signum)
    assert status == 128 + signum, (status, lines)
    assert lines == [f"vibimpact: interrupted: {saved} saved in {out}.partial; rerun "
                     "with --resume"]
    assert files(tmp_path) == [f"{out}.partial"]
    ckpt = tmp_path / f"{out}.partial"
    assert no_temporaries(ckpt)
    (tmp_path / f".{out}.abc123.tmp").write_bytes(b"stale")  # as a SIGKILL leaves
    (ckpt / ".tmp-xyz.npz").write_bytes(b"stale")

    r = cli(*args, "--resume", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert files(tmp_path) == [out] and "Traceback" not in r.stderr
    read = read_netcdf if out.endswith(".nc") else open_map
    ref = tmp_path / "ref"
    ref.mkdir()
    assert cli(*args, cwd=ref).returncode == 0
    assert_same_data(read(tmp_path / out), read(ref / out))


COMPUTING = {"classify": (["classify", *SWEEP, "--workers", "2", "-o", "c.nc"], "c.nc",
                          "point"),
             "map": (["map", *MAP, "--workers", "2", "-o", "m.zarr"], "m.zarr", "row")}


@pytest.mark.parametrize("name", sorted(COMPUTING))
def test_group_sigterm_while_computing_keeps_the_saved_points(name, tmp_path,
                                                              references):
    """Hypothesis: SIGTERM to the whole process group (as 'timeout' sends it) while
    'classify --workers 2' (a process pool) or 'map --workers 2' (a Dask cluster)
    computes ends it within seconds with exit 143 and the saved-count line; the workers
    stop with it (nothing is saved afterwards) and --resume gives the uninterrupted
    result bit for bit."""
    from vibimpact.io import read_netcdf
    from vibimpact.maps import open_map

    args, out, unit = COMPUTING[name]
    ckpt = tmp_path / f"{out}.partial"
    proc = start(args, tmp_path)
    try:
        wait_for(lambda: len(_points(ckpt)) >= 2, proc, "2 saved entries")
        os.killpg(proc.pid, signal.SIGTERM)
        status = finish(proc)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    lines = messages(tmp_path)
    saved = _points(ckpt)
    n = len(saved) if unit == "point" else len({f.split("-")[0] for f in saved})
    assert status == 143, status
    assert lines == [f"vibimpact: interrupted: {n} {unit}{'s' * (n != 1)} saved in "
                     f"{out}.partial; rerun with --resume"]
    time.sleep(0.5)
    assert _points(ckpt) == saved and files(tmp_path) == [f"{out}.partial"]
    r = cli(*args, "--resume", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    read = read_netcdf if out.endswith(".nc") else open_map
    assert_same_data(read(tmp_path / out), references[name])


def test_sigterm_while_simulating_leaves_nothing(tmp_path):
    """Hypothesis: SIGTERM while a long simulate integrates (or still imports) ends it
    within seconds (the kernel returns to Python often enough), exit 143, the one line
    'vibimpact: interrupted', no file."""
    proc = start(["simulate", "--preset", "fig8", "--eta", "1.0", "--periods", "100000",
                  "--transient", "0", "-o", "r.nc"], tmp_path)
    try:
        time.sleep(2.5)
        assert proc.poll() is None, messages(tmp_path)
        proc.send_signal(signal.SIGTERM)
        status = finish(proc)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert status == 143, status
    assert messages(tmp_path) == ["vibimpact: interrupted"]
    assert files(tmp_path) == []


#: stderr made to send the process the signal SECOND_SIGNAL as the first line that
#: begins with "vibimpact:" is written: a signal that lands while the command says how
#: it ended
SECOND_SIGNAL = """
import os, sys
class Said:
    def __init__(self, stream):
        self.stream, self.sent = stream, False
    def write(self, text):
        if not self.sent and text.startswith("vibimpact:"):
            self.sent = True
            os.kill(os.getpid(), int(os.environ["SECOND_SIGNAL"]))
        return self.stream.write(text)
    def __getattr__(self, name):
        return getattr(self.stream, name)
sys.stderr = Said(sys.stderr)
"""


@pytest.mark.parametrize("second", [signal.SIGTERM, signal.SIGINT], ids=["TERM", "INT"])
@pytest.mark.parametrize("ending", ["error", "interrupted", "saved points"])
def test_a_signal_while_the_last_line_is_said_adds_no_line(ending, second, tmp_path):
    """Hypothesis: a SIGTERM or SIGINT that arrives while the command says how it ended
    (its error line, exit 2; its interrupted line after a first SIGTERM, exit 143; a
    checkpointed sweep's interrupted line with its saved points, which the command
    says itself) neither adds a second line nor changes the status: the line said
    decides (what the slow line found when a stopped worker's error and the test's
    SIGTERM met)."""
    env = {"SECOND_SIGNAL": str(int(second))}
    if ending == "error":
        proc = start(["simulate", "--from", "missing.nc", "-o", "r.nc"], tmp_path,
                     env=env, prelude=SECOND_SIGNAL)
        status = finish(proc)
        lines = messages(tmp_path)
        assert status == 2 and len(lines) == 1, (status, lines)
        assert lines[0].startswith("vibimpact: error:") and "missing.nc" in lines[0]
    else:
        args = (["simulate", "--preset", "fig8", "--eta", "1.0", "--periods", "100000",
                 "--transient", "0", "-o", "r.nc"] if ending == "interrupted" else
                ["classify", *SWEEP, "--workers", "1", "-o", "r.nc"])
        proc = start(args, tmp_path, env=env, prelude=SECOND_SIGNAL)
        try:
            if ending == "interrupted":
                time.sleep(2.5)
            else:  # a point saved, however loaded the machine (a fixed sleep was not)
                wait_for(lambda: saved_entries(tmp_path / "r.nc.partial"), proc,
                         "saved point")
            assert proc.poll() is None, messages(tmp_path)
        except BaseException:
            os.killpg(proc.pid, signal.SIGKILL)
            raise
        assert_one_interrupted_line(tmp_path, signal_and_finish(proc, signal.SIGTERM))
    if ending == "saved points":  # the checkpoint is kept, named on the line
        assert files(tmp_path) == ["r.nc.partial"]
        assert "saved in r.nc.partial" in messages(tmp_path)[0]
        return
    assert files(tmp_path) == []  # no output, no temporary


@pytest.mark.parametrize("moment", ["computing", "writing"])
def test_stopped_rerun_leaves_no_hidden_file_and_no_resume_advice(moment, tmp_path):
    """Hypothesis: 'vibimpact rerun c.nc' stopped by SIGTERM while it recomputes or
    writes removes its hidden output and checkpoint (.c.nc.rerun-*), exits 143 and says
    'interrupted; nothing written' without advising a --resume that rerun lacks."""
    args = ["classify", "--eta", "1.0:1.03:0.01", "--preset", "fig8", "--no-progress",
            "-o", "c.nc"]
    assert cli(*args, cwd=tmp_path).returncode == 0
    if moment == "writing":
        status, lines = interrupt_while_writing(["rerun", "c.nc"], tmp_path)
    else:
        proc = start(["rerun", "c.nc"], tmp_path)
        try:
            wait_for(lambda: any(p.name.endswith(".partial") and _points(p)
                                 for p in tmp_path.iterdir()), proc, "a saved point")
            proc.send_signal(signal.SIGTERM)
            status = finish(proc)
        finally:
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGKILL)
        lines = messages(tmp_path)
    announced, *lines = lines  # rerun says what it runs first (issue 44, class 5)
    assert announced.startswith("vibimpact: rerunning 'vibimpact classify "), announced
    assert status == 143 and lines == ["vibimpact: interrupted; nothing written"], \
        (status, lines)
    assert files(tmp_path) == ["c.nc"]


def test_next_rerun_removes_what_a_killed_rerun_left(tmp_path):
    """Hypothesis: a rerun SIGKILLed while it recomputes cannot clean up (its hidden
    checkpoint .c.nc.rerun-PID-*.nc.partial stays); the next rerun of the same file
    removes it, since process PID is gone, and still reports 'identical'."""
    args = ["classify", "--eta", "1.0:1.03:0.01", "--preset", "fig8", "--no-progress",
            "-o", "c.nc"]
    assert cli(*args, cwd=tmp_path).returncode == 0
    proc = start(["rerun", "c.nc"], tmp_path)
    try:
        wait_for(lambda: any(p.name.endswith(".partial") and _points(p)
                             for p in tmp_path.iterdir()), proc, "a saved point")
        proc.send_signal(signal.SIGKILL)
        assert finish(proc) == -signal.SIGKILL
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    left = [n for n in files(tmp_path) if n != "c.nc"]
    assert left and all(n.startswith(f".c.nc.rerun-{proc.pid}-") for n in left), left
    r = cli("rerun", "c.nc", cwd=tmp_path)
    assert r.returncode == 0 and r.stdout.startswith("identical: "), r.stderr
    assert files(tmp_path) == ["c.nc"]


# --- map --scheduler that cannot be ---------------------------------------------------

@pytest.mark.parametrize("scheduler,needle", [
    ("garbage.json", "not a Dask scheduler file"),
    ("adir", "a directory, not a scheduler file"),
    ("foo://bar", "unknown protocol 'foo'"),
    ("tcp://somehost", "missing port number")])
def test_map_with_an_impossible_scheduler_is_refused_before_connecting(scheduler, needle,
                                                                       tmp_path):
    """Hypothesis: 'map --scheduler' with a garbage file, a directory, an unknown
    protocol or an address without a port is refused before any connection is tried
    (the line is the address check's, which runs before a Client exists): one line,
    exit 2, no 'Exception ignored in Client.__del__' traceback afterwards (what a
    Client that failed to connect printed after its connect timeout) and no file."""
    (tmp_path / "garbage.json").write_text("not json")
    (tmp_path / "adir").mkdir()
    try:  # a guard against a hang; that no connection was tried is what the line says
        r = subprocess.run([sys.executable, "-m", "vibimpact.cli", "map", "--eta",
                            "1.0:1.02:0.01", "--vary", "kh=10:20:10", "--scheduler",
                            scheduler, "-o", "m.zarr"], cwd=tmp_path, env=_env(),
                           capture_output=True, text=True, timeout=120)
    except subprocess.TimeoutExpired:
        pytest.fail("still running after 120 s: a hang")
    assert r.returncode == 2 and r.stderr.splitlines() == [r.stderr.strip()], r.stderr
    assert r.stderr.startswith("vibimpact: error: --scheduler: cannot connect to the Dask "
                               f"scheduler {scheduler!r}: ") and needle in r.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["adir", "garbage.json"]


def test_an_error_a_signal_causes_is_reported_as_that_signal(tmp_path, monkeypatch, capfd):
    """Hypothesis: a signal that lands inside a zip write (a checkpoint entry being
    compressed) surfaces as zipfile's ValueError "Can't close the ZIP file while there is
    an open writing handle"; the command still reports the signal (exit 143, 'vibimpact:
    interrupted ...', no traceback), not that error, and keeps its checkpoint.  (The
    fault injection found it: SIGTERM to a rerun reported the zip error, exit 2.)"""
    import zipfile

    import numpy as np

    from vibimpact.cli import main

    calls = []

    def savez_signalled(buf, **arrays):
        calls.append(1)
        if len(calls) < 2:  # the first entry is saved; the second is cut by SIGTERM
            return original(buf, **arrays)
        zf = zipfile.ZipFile(buf, "w")
        handle = zf.open("a.npy", "w")
        try:
            os.kill(os.getpid(), signal.SIGTERM)  # the handler raises here
            time.sleep(5)
        finally:
            try:
                zf.close()  # ValueError: an open writing handle (the mask)
            finally:  # leave nothing for the garbage collector to complain about
                handle.close()
                zf.close()

    original = np.savez_compressed
    monkeypatch.chdir(tmp_path)
    args = ["classify", "--eta", "1.0:1.03:0.01", "--workers", "1", "--no-progress", "-o"]
    monkeypatch.setattr(np, "savez_compressed", savez_signalled)
    rc = main([*args, "c.nc"])
    err = capfd.readouterr().err
    assert rc == 143, err
    assert "Traceback" not in err and "ZIP" not in err
    assert err.strip().splitlines()[-1].startswith("vibimpact: interrupted"), err
    assert not (tmp_path / "c.nc").exists() and (tmp_path / "c.nc.partial").is_dir()
    # the same cut in a rerun (which reports its command's failures as its own)
    monkeypatch.setattr(np, "savez_compressed", original)
    assert main([*args, "d.nc"]) == 0
    calls.clear()
    monkeypatch.setattr(np, "savez_compressed", savez_signalled)
    rc = main(["rerun", "d.nc"])
    err = capfd.readouterr().err
    assert rc == 143, err
    assert "Traceback" not in err and "ZIP" not in err
    assert err.strip().splitlines()[-1].startswith("vibimpact: interrupted"), err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.nc.partial", "d.nc"]


def test_a_signal_after_the_command_finished_does_not_kill_it_silently(tmp_path):
    """Hypothesis: once the command line's command has written its output, a SIGTERM or
    SIGINT during the interpreter's exit neither kills the process silently (exit -15 and
    no line: what the fault injection found for SIGTERM at 95 % of a simulate) nor prints a
    traceback; the process exits with the command's own status, its file in place."""
    code = ("import os, signal, sys\n"
            "sys.argv = ['vibimpact', 'simulate', '--eta', '1.2', '--periods', '5', '-o',"
            " 'r.nc']\n"
            "from vibimpact.cli import main\n"
            "rc = main()\n"
            "os.kill(os.getpid(), signal.SIGTERM)\n"
            "os.kill(os.getpid(), signal.SIGINT)\n"
            "sys.exit(rc)\n")
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True,
                          text=True, timeout=120, env=_env())
    assert proc.returncode == 0, (proc.returncode, proc.stderr)
    assert "Traceback" not in proc.stderr and "interrupted" not in proc.stderr
    assert (tmp_path / "r.nc").is_file()
