"""Python's exit hook finds no process pool of a run left to wake.

Python 3.11's exit hook for process pools writes to each pool's wake-up pipe without the
lock that the pool's own thread takes when it closes that pipe on its way out; a command
that ended while the thread was still closing it printed "Exception ignored ...
OSError: [Errno 9] Bad file descriptor" and a traceback after its own last line (CI saw
it once in a stopped worker's run).  The executor therefore takes its pool off the
hook's list once the pool is shut down (shutting down wakes it already); these tests
check that on every way out of a run: finished, failed in this process, failed in a
worker, and stopped by a worker that stays stopped.
"""
import os
import signal

import numpy as np
import pytest

from vibimpact.engine import executors, plan
from vibimpact.sweeps import SweepSettings
from conftest import preset

FIG8 = preset("fig8")
SETTINGS = SweepSettings(transient_max=40, record=16, analyses=("period",))


def _jobs(slots):
    """Two one-task jobs of two starting states each at fig8, eta = 1.18."""
    states = np.array([np.zeros(4), [1e-3, 0, 0, 0], [2e-3, 0, 0, 0], [3e-3, 0, 0, 0]])
    return [[t] for t in plan.plan_states(FIG8, 1.18, states, SETTINGS, blocks=2)]


def _ends(pid, within=30.0):
    """Whether process ``pid`` is gone or a zombie within ``within`` seconds (asked of
    the kernel: the pool's thread may reap it meanwhile, and multiprocessing's own
    ``is_alive`` then answers True for good)."""
    import time

    deadline = time.monotonic() + within
    while time.monotonic() < deadline:
        try:
            with open(f"/proc/{pid}/stat") as f:
                if f.read().rsplit(")", 1)[1].split()[0] in "ZX":
                    return True
        except (FileNotFoundError, ProcessLookupError):
            return True
        time.sleep(0.05)
    return False


def _pool_threads():
    """The pools' threads whose wake-up pipe Python's exit hook would write to: those
    on its list with a pipe not closed yet."""
    from concurrent.futures.process import _threads_wakeups

    return [t for t, wakeup in list(_threads_wakeups.items()) if not wakeup._closed]


def test_the_exit_hook_has_no_pool_to_wake_after_a_finished_run():
    """Hypothesis: when Processes.run returns, every task reported, the exit hook has no
    open wake-up pipe of its pool to write to."""
    out = {}
    executors.Processes(2).run(_jobs, None, lambda task, res: out.update(dict(res)))
    assert sorted(out) == [0, 1, 2, 3]
    assert _pool_threads() == []


class Boom(Exception):
    """An error of this test's own."""


def test_the_exit_hook_has_no_pool_to_wake_after_an_error_in_this_process():
    """Hypothesis: an error raised by ``on_task`` (in this process) goes through
    Processes.run with its pool off the exit hook's list."""
    def on_task(task, res):
        raise Boom("on_task")

    with pytest.raises(Boom):
        executors.Processes(2).run(_jobs, None, on_task)
    assert _pool_threads() == []


def test_the_exit_hook_has_no_pool_to_wake_after_an_error_in_a_worker():
    """Hypothesis: an error raised in a worker (a task that cannot run) reaches this
    process with the pool off the exit hook's list."""
    def bad_jobs(slots):
        return [[object()], [object()]]  # run_job fails on a job of non-tasks

    with pytest.raises(Exception):
        executors.Processes(2).run(bad_jobs, None, lambda task, res: None)
    assert _pool_threads() == []


@pytest.mark.slow
def test_the_exit_hook_has_no_pool_to_wake_after_a_stopped_worker():
    """Hypothesis: workers (and the points' queue process) stopped with SIGSTOP end the
    run (StoppedChild) with the pool off the exit hook's list, and no stopped process
    is left alive (each is killed)."""
    from vibimpact.engine.watch import StoppedChild
    import multiprocessing as mp

    stopped = []

    def on_point(task, i, res):
        if not stopped:  # every child: the run cannot finish whichever holds a job
            for child in mp.active_children():
                os.kill(child.pid, signal.SIGSTOP)
                stopped.append(child)

    def long_jobs(slots):
        states = np.zeros((40, 4)) + np.arange(40)[:, None] * [1e-4, 0, 0, 0]
        return [[t] for t in plan.plan_states(FIG8, 1.18, states, SETTINGS, blocks=2)]

    with pytest.raises(StoppedChild):
        executors.Processes(2).run(long_jobs, on_point, lambda task, res: None)
    assert stopped and _pool_threads() == []
    assert all(_ends(p.pid) for p in stopped)
