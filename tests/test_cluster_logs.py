"""A local Dask cluster's workers say nothing on stderr: the run's own lines are the
only ones (a worker stopped with its process group would otherwise log its closed
connection with a traceback)."""
import logging

from vibimpact.engine.cluster import Dask


def _levels_on_a_worker(slots):
    """One job of one task whose policy, run on a worker, returns the effective level of
    distributed's loggers there (classes made here travel by value)."""

    class Probe:
        def run(self, task, on_point):
            import logging as lg

            return [lg.getLogger(n).getEffectiveLevel()
                    for n in ("distributed", "distributed.batched", "distributed.worker")]

    class Task:
        policy = Probe()

    return [[Task()]]


def test_a_local_clusters_workers_log_nothing_below_critical():
    """Hypothesis: on a worker of the local cluster a run starts, distributed's loggers
    (the batched stream's, which logs a closed connection with its traceback at INFO,
    and the worker's) let nothing below CRITICAL through; Dask's own configuration
    leaves them at INFO."""
    got = []
    Dask(workers=1).run(_levels_on_a_worker, None, lambda task, res: got.append(res))
    assert got == [[logging.CRITICAL] * 3]
