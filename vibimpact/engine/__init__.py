"""The engine of sweeps and maps: plan -> executor -> store, progress as a callback.

* :mod:`~vibimpact.engine.plan`: a request (rows of parameters, a grid of eta, directions,
  blocks) becomes independent tasks, each a contiguous block of one continuation stream
  with its seed state; how a task runs (:func:`~vibimpact.engine.plan.run_task`).  A
  sweep is the one-row case of a map.
* :mod:`~vibimpact.engine.executors` (in this process, local processes) and
  :mod:`~vibimpact.engine.cluster` (Dask): where the tasks run.
* :mod:`~vibimpact.engine.store`: the one checkpoint format of sweeps and maps (resume,
  damaged entries, counts, clean-up).
* :mod:`~vibimpact.engine.progress`: the progress callback.
* :mod:`~vibimpact.engine.compute`: the three put together.

Nothing heavy is imported here: the command line asks the store about a checkpoint
without loading numba.
"""
