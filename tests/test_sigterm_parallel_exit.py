"""SIGTERM ends a parallel sweep at whatever moment it arrives: the command prints its
one line, exits 143 and leaves no process behind.  A worker killed while it sent a result
left half a message in the pool's result pipe, and the interpreter's shutdown then joined
the pool's manager thread, blocked reading it: the command printed 'interrupted' and hung
(the reliability study caught it once in twelve SIGTERMs)."""
import os
import signal
import subprocess
import sys
import time

import pytest

GRID = ["classify", "--eta", "0.9:1.5:0.001", "--direction", "both", "--workers", "2",
        "--no-progress", "-o", "c.nc"]


def _saved(ckpt):
    try:
        return sum(f.endswith(".npz") and not f.startswith(".") for f in os.listdir(ckpt))
    except OSError:
        return 0


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


@pytest.mark.slow
@pytest.mark.parametrize("after", [1, 10, 40, 80, 160, 240])
def test_sigterm_ends_a_two_worker_sweep_after_any_number_of_points(after, tmp_path):
    """Hypothesis: whichever point the sweep has reached (``after`` points saved), SIGTERM
    ends it with exit status 143 and one 'interrupted' line, and no worker of it stays
    alive; the guard below only turns a hang into a failure."""
    proc = subprocess.Popen([sys.executable, "-m", "vibimpact", *GRID], cwd=tmp_path,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    try:
        for _ in range(6000):  # a hang guard, not a speed claim
            if _saved(tmp_path / "c.nc.partial") >= after or proc.poll() is not None:
                break
            time.sleep(0.01)
        if proc.poll() is not None:
            pytest.fail(f"the sweep ended before {after} points: {proc.stderr.read()}")
        children = [int(p) for p in os.popen(f"pgrep -P {proc.pid}").read().split()]
        proc.send_signal(signal.SIGTERM)
        try:
            out, err = proc.communicate(timeout=120)
        except subprocess.TimeoutExpired:
            pytest.fail("SIGTERM did not end the command (it hung after the signal)")
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    lines = err.strip().splitlines()
    assert proc.returncode == 143, (proc.returncode, lines)
    assert len(lines) == 1 and lines[0].startswith("vibimpact: interrupted"), lines
    for _ in range(500):  # the workers die with their parent (PR_SET_PDEATHSIG)
        if not any(_alive(c) for c in children):
            break
        time.sleep(0.01)
    assert not [c for c in children if _alive(c)]


def test_the_exit_after_an_interrupt_flushes_and_joins_no_thread(tmp_path):
    """Hypothesis: after an interrupt the command line ends the process with its status
    once its output is flushed, without the interpreter's join of pool threads (here a
    thread-exit hook that would block for good, as the pool's manager thread blocked on
    a half-written result)."""
    code = (
        "import atexit, threading, sys\n"
        "import vibimpact.cli as c\n"
        "threading._register_atexit(lambda: threading.Event().wait())\n"
        "print('line', file=sys.stderr, end='')\n"
        "c._exit_after_interrupt(143)\n")
    try:
        r = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True,
                           text=True, timeout=120)
    except subprocess.TimeoutExpired:
        pytest.fail("the exit joined the blocked thread")
    assert r.returncode == 143 and r.stderr == "line"
