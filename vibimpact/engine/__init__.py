"""The engine of sweeps and maps: plan -> executor -> store, progress as a callback.

* :mod:`~vibimpact.engine.plan`: a request becomes independent tasks, each parameter
  points x starting states x a continuation policy: a contiguous block of one
  continuation stream with its seed state (:func:`~vibimpact.engine.plan.plan`), or many
  starting states at one parameter point (:func:`~vibimpact.engine.plan.plan_states`);
  how a task runs (:func:`~vibimpact.engine.plan.run_task`).  A sweep is the one-row
  case of a map.
* :mod:`~vibimpact.engine.policy`: the continuation policies (:class:`Continuation`,
  :class:`Independent`).
* :mod:`~vibimpact.engine.executors` (the executor protocol, in this process, local
  processes) and :mod:`~vibimpact.engine.cluster` (Dask): where the tasks run; a user's
  executor is any object with ``run(make_jobs, on_point, on_task)``.
* :mod:`~vibimpact.engine.execution`: :class:`Execution`, the settings of where and how
  a request runs (never its numbers).
* :mod:`~vibimpact.engine.store`: the one checkpoint format of sweeps and maps (resume,
  damaged entries, counts, clean-up); :mod:`~vibimpact.engine.leftovers`: what a killed
  run leaves; :mod:`~vibimpact.engine.signals`: SIGINT and SIGTERM as
  :class:`Interrupted`.
* :mod:`~vibimpact.engine.progress`: the progress callback.
* :mod:`~vibimpact.engine.compute`: the executor, the store and the progress put
  together, under the signal guard.

Nothing heavy is imported here (the names below are loaded on first use): the command
line asks the store about a checkpoint without loading numba.
"""
import importlib

#: public name -> submodule
_EXPORTS = {
    "Execution": "execution", "Continuation": "policy", "Independent": "policy",
    "Executor": "executors", "Serial": "executors", "Processes": "executors",
    "WorkerLost": "executors", "Dask": "cluster", "Task": "plan", "run_task": "plan",
    "plan_states": "plan", "Interrupted": "signals", "StopWorkersOnSignal": "signals",
}

# a list at run time: ruff reads only a literal or a tuple/list expression
__all__ = sorted(_EXPORTS)  # noqa: PLE0605


def __getattr__(name):
    if name in _EXPORTS:
        value = getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
