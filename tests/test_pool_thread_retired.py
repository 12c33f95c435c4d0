"""No thread of a process pool outlives the run that made it.

Python 3.11's exit hook for process pools writes to each pool's wake-up pipe without the
lock that the pool's own thread takes when it closes that pipe on its way out; a command
that ended while the thread was still closing it printed "Exception ignored ...
OSError: [Errno 9] Bad file descriptor" and a traceback after its own last line (CI saw
it once in a stopped worker's run).  The executor therefore waits for the pool's thread
before it returns or lets an error through; these tests check that wait on every way out
of a run: finished, failed in this process, failed in a worker, and stopped by a worker
that stays stopped.
"""
import os
import signal
import threading

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


def _pool_threads():
    """The live threads of process pools in this process."""
    return [t for t in threading.enumerate()
            if type(t).__name__ == "_ExecutorManagerThread" and t.is_alive()]


def test_no_pool_thread_outlives_a_finished_run():
    """Hypothesis: when Processes.run returns, every task reported, the pool's thread
    has ended (the exit hook then finds nothing to wake)."""
    out = {}
    executors.Processes(2).run(_jobs, None, lambda task, res: out.update(dict(res)))
    assert sorted(out) == [0, 1, 2, 3]
    assert _pool_threads() == []


class Boom(Exception):
    """An error of this test's own."""


def test_no_pool_thread_outlives_an_error_in_this_process():
    """Hypothesis: an error raised by ``on_task`` (in this process) goes through
    Processes.run only after the pool's thread has ended."""
    def on_task(task, res):
        raise Boom("on_task")

    with pytest.raises(Boom):
        executors.Processes(2).run(_jobs, None, on_task)
    assert _pool_threads() == []


def test_no_pool_thread_outlives_an_error_in_a_worker(monkeypatch):
    """Hypothesis: an error raised in a worker (a task that cannot run) reaches this
    process only after the pool's thread has ended."""
    def bad_jobs(slots):
        return [[object()], [object()]]  # run_job fails on a job that holds no tasks

    with pytest.raises(Exception):
        executors.Processes(2).run(bad_jobs, None, lambda task, res: None)
    assert _pool_threads() == []


@pytest.mark.slow
def test_no_pool_thread_outlives_a_stopped_worker():
    """Hypothesis: a worker stopped with SIGSTOP ends the run (StoppedChild) only after
    the pool's thread has ended, and no worker is left."""
    from vibimpact.engine.watch import StoppedChild
    import multiprocessing as mp

    stopped = []

    def on_point(task, i, res):
        if not stopped:
            kids = mp.active_children()
            worker = max(kids, key=lambda p: p.pid)
            os.kill(worker.pid, signal.SIGSTOP)
            stopped.append(worker)

    def long_jobs(slots):
        states = np.zeros((40, 4)) + np.arange(40)[:, None] * [1e-4, 0, 0, 0]
        return [[t] for t in plan.plan_states(FIG8, 1.18, states, SETTINGS, blocks=2)]

    with pytest.raises(StoppedChild):
        executors.Processes(2).run(long_jobs, on_point, lambda task, res: None)
    assert stopped and _pool_threads() == []
    assert not any(p.is_alive() for p in mp.active_children() if p is stopped[0])
