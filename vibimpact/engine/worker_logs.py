"""The worker plugin that keeps a local Dask cluster's workers quiet on stderr.

A local cluster (``vibimpact map --workers N``) is this process's own: its errors are
said here, in one line.  Its workers' ``distributed`` logs (configured by Dask at INFO
on stderr) would otherwise interleave with that line; in particular a worker stopped
with its process group (SIGTERM from ``timeout``) logs the closed connection to the
scheduler with a traceback, which reads as a crash after a clean interruption.
``LocalCluster``'s ``silence_logs`` silences this process's handlers and each nanny's
logger, not the worker processes' own loggers.  Importing this module imports
``distributed``: only :mod:`.cluster` does, when it starts a local cluster.
"""
import logging

from distributed import WorkerPlugin


class QuietLogs(WorkerPlugin):
    """On each worker (those present and those started later): the ``distributed``
    loggers print nothing below CRITICAL."""

    name = "vibimpact-quiet-logs"

    def setup(self, worker):
        """Run on the worker as it starts, or when the plugin is registered."""
        logging.getLogger("distributed").setLevel(logging.CRITICAL)


__all__ = ["QuietLogs"]
