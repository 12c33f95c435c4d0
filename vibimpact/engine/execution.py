"""How a request runs, apart from what it computes: :class:`Execution`.

Where the tasks run (``workers``, ``scheduler`` or a user's ``executor``), where finished
points are saved (``checkpoint``, ``resume``), how progress is shown (``progress``) and
how tasks are grouped (``task_points``) never change a number; the science (the
:class:`~vibimpact.SweepSettings`, the continuation policy and its blocks) lives apart.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

from ..base import _limits
from ..base import _validate as _v

#: least points per job of a map (a second or more of work at the points per second and
#: core that reports/performance.md, section map, measures)
DEFAULT_TASK_POINTS = 300


@dataclass(frozen=True)
class Execution:
    """Execution settings of :func:`vibimpact.sweep` and :func:`vibimpact.map2d`.

    None of them changes a result: serial, parallel, clustered, reordered or resumed runs
    are bit-identical.

    Parameters
    ----------
    workers : int
        Local processes computing at once (1: in this process).  A sweep runs them as a
        process pool, a map as a local Dask cluster.
    executor : Executor, optional
        A user's executor (:class:`vibimpact.engine.executors.Executor`: one method
        ``run(make_jobs, on_point, on_task)``); ``workers`` and ``scheduler`` are then
        not given.
    scheduler : optional
        Run on Dask: a scheduler address (``tcp://host:8786``), a scheduler file, a
        ``distributed.Client`` or a cluster object (``LocalCluster``, dask-jobqueue's
        ``SLURMCluster``, ...); ``workers`` is then not given.
    checkpoint : path, optional
        Directory where every finished point (a map: every finished row) is saved at
        once (:mod:`vibimpact.engine.store`).
    resume : bool
        Load the points found in ``checkpoint`` instead of recomputing them (the
        temporary files a killed run left there are removed).
    progress : bool, str or callable
        A progress bar on stderr, named after the request (True) or by the text given;
        a callable is called as ``progress(k)`` with every ``k`` points finished.
    task_points : int
        Least points per job handed to an executor (a map groups its rows up to this; a
        sweep hands out one block per job).

    Raises
    ------
    ValueError
        Naming the field: a wrong type, a count below 1, an executor without a ``run``
        method, an executor together with ``workers`` or ``scheduler``, ``resume``
        without ``checkpoint``.

    Notes
    -----
    SIGINT (Ctrl-C) and SIGTERM during the computation raise
    :class:`vibimpact.engine.signals.Interrupted` (a ``KeyboardInterrupt`` carrying the
    signal number) after the workers are stopped; the points finished before are in the
    checkpoint, and a run with ``resume=True`` completes the same result.
    """

    workers: int = 1
    executor: Any = None
    scheduler: Any = None
    checkpoint: Any = None
    resume: bool = False
    progress: Any = False
    task_points: int = DEFAULT_TASK_POINTS

    def __post_init__(self):
        put = functools.partial(object.__setattr__, self)
        put("workers", _v.count("workers", self.workers, 1, _limits.MAX_WORKERS))
        put("task_points", _v.count("task_points", self.task_points, 1))
        put("resume", _v.flag("resume", self.resume))
        if self.checkpoint is not None:
            put("checkpoint", _v.path("checkpoint", self.checkpoint))
        if self.resume and self.checkpoint is None:
            raise ValueError("resume=True needs a checkpoint (the directory to resume "
                             "from)")
        if self.executor is not None:
            if not callable(getattr(self.executor, "run", None)):
                raise _v.WrongType(f"executor must have a method run(make_jobs, "
                                   f"on_point, on_task), got "
                                   f"{type(self.executor).__name__}")
            if self.workers != 1 or self.scheduler is not None:
                raise ValueError("executor: give an executor, or workers / scheduler, "
                                 "not both")
        if isinstance(self.scheduler, str) and not self.scheduler.strip():
            raise ValueError("scheduler must be a Dask address, a scheduler file, a "
                             "Client or a cluster, got ''")
        progress = self.progress
        if not (callable(progress) or isinstance(progress, (bool, str)) or
                type(progress).__name__ == "bool_"):
            raise _v.WrongType(f"progress must be True, False, a str or a callable, got "
                               f"{type(progress).__name__}")

    def sweep_executor(self, n_tasks: int) -> Any:
        """The executor of a sweep of ``n_tasks`` tasks: the user's, Dask with a
        ``scheduler``, local processes or this process."""
        from . import executors

        if self.executor is not None:
            return self.executor
        if self.scheduler is not None:
            from .cluster import Dask

            return Dask(self.scheduler, self.workers, prefix="vibimpact-sweep")
        return executors.choose(self.workers, n_tasks)

    def map_executor(self) -> Any:
        """The executor of a map: the user's, this process (one worker, no scheduler),
        or Dask (a local cluster of ``workers`` or the ``scheduler``'s)."""
        from . import executors

        if self.executor is not None:
            return self.executor
        if self.scheduler is None and self.workers == 1:
            return executors.Serial()
        from .cluster import Dask

        return Dask(self.scheduler, self.workers, prefix="vibimpact-map")

    def open_checkpoint(self, kind: str, request: dict, streams: Any,
                        what: str = "checkpoint") -> tuple:
        """``(store, done)``: the checkpoint of ``request`` opened (None without one) and
        the points loaded from it on a resume (``{(row, direction): {position:
        result}}``); a resume first removes the temporary entries a killed run left."""
        from .leftovers import remove_checkpoint_temporaries
        from .store import Checkpoint

        if self.checkpoint is None:
            return None, {}
        ckpt = Checkpoint(self.checkpoint, what=what)
        if self.resume and ckpt.path.is_dir():
            remove_checkpoint_temporaries(ckpt.path)
        store = ckpt.open(kind, request, streams, self.resume)
        return store, (store.load() if self.resume else {})


def as_execution(execution):
    """``execution`` (default :class:`Execution`), or WrongType naming it."""
    if execution is None:
        return Execution()
    if not isinstance(execution, Execution):
        raise _v.WrongType(f"execution must be a vibimpact.Execution, got "
                           f"{type(execution).__name__}")
    return execution


#: where each setting of the former signatures of sweep and map2d went
MOVED = {
    "workers": "execution=vi.Execution(workers=...)",
    "scheduler": "execution=vi.Execution(scheduler=...)",
    "checkpoint": "execution=vi.Execution(checkpoint=...)",
    "store": "execution=vi.Execution(checkpoint=...)",
    "resume": "execution=vi.Execution(resume=...)",
    "progress": "execution=vi.Execution(progress=...)",
    "task_points": "execution=vi.Execution(task_points=...)",
    "blocks": "continuation=vi.Continuation(blocks=...)",
    "seed_periods": "continuation=vi.Continuation(seed_periods=...)",
    "command": "ds.attrs['command'] after the call",
}


def refuse_moved(func):
    """``func`` refusing the keywords of :data:`MOVED` with a WrongType (a TypeError and
    a ValueError) that says where the setting went; its signature stays ``func``'s."""
    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        moved = [k for k in kwargs if k in MOVED]
        if moved:
            raise _v.WrongType(f"{func.__name__}() no longer takes "
                               + "; ".join(f"{k}= (pass {MOVED[k]})" for k in moved))
        return func(*args, **kwargs)
    return wrapper
