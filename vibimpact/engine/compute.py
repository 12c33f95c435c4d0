"""Running a plan: the tasks on an executor, every finished point saved in the checkpoint
and counted by the progress callback, in the process that asked for the results."""
from __future__ import annotations

import logging
import time

from .logtext import Lazy, block
from .progress import nothing
from .signals import StopWorkersOnSignal, signals_deferred

log = logging.getLogger(__name__)


def _runs(points):
    """``[(position, result)]`` cut into runs of consecutive positions."""
    runs: list[list[tuple]] = []
    for i, res in points:
        if runs and runs[-1][-1][0] == i - 1:
            runs[-1].append((i, res))
        else:
            runs.append([(i, res)])
    return runs


def compute(tasks, executor, on_task, *, make_jobs=None, store=None, progress=nothing,
            stream=True):
    """Run ``tasks`` on ``executor``; ``on_task(task, results)`` as each one finishes.

    Parameters
    ----------
    tasks : list of Task
    executor : Executor
        Serial, Processes, Dask or a user's (:class:`vibimpact.engine.executors.
        Executor`).
    on_task : callable
        ``on_task(task, [(position, result)])`` with every point of the task, the ones
        loaded from the checkpoint included.
    make_jobs : callable, optional
        ``make_jobs(slots) -> list of jobs``; one task per job by default.
    store : Checkpoint, optional
        Opened for the request: every point computed is saved.
    progress : callable
        ``progress(k)``: ``k`` more points computed.
    stream : bool
        True: every point is saved (as its own entry) and counted as soon as it is
        finished, where the executor can report points; False: a task's points are saved
        together (one entry) and counted when the task finishes.

    Raises
    ------
    Interrupted
        SIGINT or SIGTERM during the run (:class:`vibimpact.engine.signals.
        StopWorkersOnSignal`): the executor has stopped its workers; the points finished
        before are saved in ``store``.
    """
    if make_jobs is None:
        def make_jobs(slots):
            return [[t] for t in tasks]
    streamed = set()

    def on_point(task, i, res):
        StopWorkersOnSignal.check()  # a signal lost so far (see its docstring)
        streamed.add(id(task))
        if store is not None:
            with signals_deferred():  # an entry is saved whole (see signals_deferred)
                store.save(task.row, task.direction, [(i, res)])
        progress(1)

    def finished(task, results):
        StopWorkersOnSignal.check()
        if id(task) not in streamed:
            new = [(i, r) for i, r in results if i not in task.done]
            if store is not None:
                for run in _runs(new):
                    with signals_deferred():
                        store.save(task.row, task.direction, run)
            progress(len(new))
        on_task(task, results)
        blocks_done.append(task)
        log.info("%s", Lazy(block, task, results, len(blocks_done), len(tasks),
                            time.perf_counter() - t0))

    blocks_done = []
    todo = sum(getattr(t, "todo", 0) for t in tasks)
    log.info("%d tasks (%d points to compute) on %s", len(tasks), todo, executor_name(executor))
    t0 = time.perf_counter()
    with StopWorkersOnSignal():
        executor.run(make_jobs, on_point if stream else None, finished)
    log.info("%d tasks done in %.1f s", len(tasks), time.perf_counter() - t0)


def executor_name(executor):
    """``"serial"``, ``"2 local processes"``, ... for the log."""
    workers = getattr(executor, "workers", None)
    kind = type(executor).__name__.lower()
    return kind if workers is None else f"{workers} {kind}"
