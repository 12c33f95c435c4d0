"""The Dask executor: the jobs of a plan on a local Dask cluster or on a remote one.

No scheduling of our own: the jobs are handed to Dask distributed (``Client.submit``)
and their results taken in the order they finish (``distributed.as_completed``), so
Dask's scheduler decides placement, load balance and recovery.  When a worker dies, the
scheduler gives its jobs to another worker (up to ``distributed.scheduler.allowed-
failures`` times); every job is a pure function of its arguments, so a recomputed job
returns the same numbers.  Results come back per job: :class:`Dask` reports whole tasks
(``on_point`` is not called).

``distributed`` is imported only when a cluster is used.
"""
from __future__ import annotations

import contextlib
import logging
import os
import threading
import uuid

from ..base._text import one_line

#: seconds to wait for a remote scheduler (and for the workers of a local cluster)
CONNECT_TIMEOUT = 20

#: Dask settings of the local cluster's workers: no statistical profiler (it samples the
#: running task's stack many times a second) and no GIL monitor (it polls the GIL),
#: both of which interrupt the task that holds the GIL through every numba call and cost
#: the workers CPU time.  The workers of a remote cluster take these settings
#: from their own configuration (see the README).
WORKER_CONFIG = {"distributed.worker.profile.enabled": False,
                 "distributed.admin.system-monitor.gil.enabled": False}


def _worker_version():
    """Runs on a worker: the vibimpact version it imports."""
    import vibimpact

    return vibimpact.__version__


def check_workers(client):
    """ValueError unless every worker imports the same vibimpact version as this process.

    Bit-identical maps need the same code everywhere; a worker without vibimpact would
    fail every task with a less helpful error.  Only the workers present now are checked;
    a cluster without workers yet (a batch queue still starting them) passes, its tasks
    wait for them.
    """
    from .. import __version__

    try:
        got = client.run(_worker_version, on_error="return")
    except Exception as exc:  # the scheduler went away meanwhile
        raise ValueError(f"cannot reach the Dask workers: {one_line(exc)}") from None
    for worker, v in sorted(got.items()):
        if isinstance(v, BaseException):
            raise ValueError(f"Dask worker {worker} cannot import vibimpact "
                             f"({one_line(v)}); install it in the workers' "
                             "environment")
        if v != __version__:
            raise ValueError(f"Dask worker {worker} runs vibimpact {v}, this process "
                             f"{__version__}: results would not be reproducible")


def connect(scheduler, timeout=CONNECT_TIMEOUT):
    """A ``distributed.Client`` for ``scheduler``, and whether the caller must close it.

    Parameters
    ----------
    scheduler : str, distributed.Client or cluster object
        An address (``tcp://host:8786``), the path of a scheduler file (as written by
        ``dask scheduler --scheduler-file``, dask-jobqueue or dask-mpi), a connected
        ``Client`` (used as is, never closed here), or a cluster object with a
        ``scheduler_address`` (``LocalCluster``, ``SLURMCluster``, ``KubeCluster``, ...).

    Raises
    ------
    ValueError
        For a scheduler that cannot be reached in ``timeout`` seconds, or workers that do
        not run the same vibimpact.
    """
    from distributed import Client

    if isinstance(scheduler, Client):
        check_workers(scheduler)
        return scheduler, False
    if isinstance(scheduler, (str, os.PathLike)):
        what = os.fspath(scheduler)
        try:
            kw = {"address": scheduler_address(what)}
        except ValueError as exc:
            raise ValueError(f"cannot connect to the Dask scheduler {what!r}: {exc}") \
                from None
    elif hasattr(scheduler, "scheduler_address"):
        kw = {"address": scheduler}
        what = str(scheduler.scheduler_address)
    else:
        raise ValueError("scheduler must be an address, a scheduler file, a "
                         f"distributed.Client or a Dask cluster, got {scheduler!r}")
    client = Client.__new__(Client)
    try:
        Client.__init__(client, **kw, timeout=timeout, set_as_default=False)
    except Exception as exc:  # OSError, TimeoutError, ValueError for a bad address, ...
        _abandon(client)
        raise ValueError(f"cannot connect to the Dask scheduler {what!r}: "
                         f"{one_line(exc)}") from None
    try:
        check_workers(client)
    except BaseException:
        client.close()
        raise
    return client, True


def scheduler_address(text):
    """The scheduler address that ``text`` names: the ``address`` of a scheduler file
    (JSON, as ``dask scheduler --scheduler-file`` writes), or ``text`` itself, checked
    (a known protocol, a port).  ValueError otherwise, before any connection is tried.
    """
    from distributed.comm import get_address_host_port, parse_address, registry

    from ..base._json import load_file

    if os.path.isdir(text):
        raise ValueError("a directory, not a scheduler file or address")
    if os.path.isfile(text):
        try:
            address = load_file(text, "scheduler file")["address"]
            if not isinstance(address, str):
                raise TypeError
        except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError):
            raise ValueError("not a Dask scheduler file (JSON with an 'address') nor an "
                             "address") from None
        text = address
    scheme, _ = parse_address(text, strict=False)
    if scheme not in registry.backends:
        raise ValueError(f"unknown protocol {scheme!r} in {text!r} (known: "
                         f"{', '.join(sorted(registry.backends))})")
    if scheme in ("tcp", "tls", "ws", "wss"):
        try:
            get_address_host_port(text)
        except ValueError as exc:
            raise ValueError(f"{exc} (e.g. tcp://host:8786)") from None
    return text


def _abandon(client):
    """Let a Client whose constructor failed be collected quietly: without this its
    ``__del__`` waits out its connect timeout for a connection that never was and prints
    a traceback."""
    with contextlib.suppress(Exception):
        client.status = "closed"
    with contextlib.suppress(Exception):
        client._loop_runner.stop()  # noqa: SLF001 -- distributed's own attribute


@contextlib.contextmanager
def _local_cluster(workers):
    """A ``LocalCluster`` of ``workers`` single-threaded processes and its client.

    Closing it never waits on a stopped worker (SIGSTOP): those are killed first (a
    nanny asks its worker to close and waits for an answer that a stopped process never
    gives)."""
    import multiprocessing as mp

    import dask
    from distributed import Client, LocalCluster

    quiet_resource_tracker()
    before = set(mp.active_children())
    try:
        with dask.config.set(WORKER_CONFIG):
            # no workers yet: the constructor would wait for them itself, unwatched
            cluster = LocalCluster(n_workers=0, threads_per_worker=1,
                                   processes=True, dashboard_address=":0",
                                   silence_logs=logging.CRITICAL)  # errors: ours
    except Exception as exc:
        raise _cannot_start(workers, exc) from exc
    # the worker processes its nannies start in this process (the cluster's own
    # records of them lag behind while they start); an attribute of ours on dask's object
    cluster.vibimpact_children = lambda: {  # type: ignore[attr-defined]
        p.pid: "a Dask worker process" for p in set(mp.active_children()) - before}
    try:
        client = Client(cluster, set_as_default=False)
        # its worker processes are watched (Dask.run); an attribute of ours on the Client
        client.local_cluster = cluster  # type: ignore[attr-defined]
        try:
            # before the workers start, so that each one (and one started later) has it
            from .worker_logs import QuietLogs

            client.register_plugin(QuietLogs(), name=QuietLogs.name)
            with dask.config.set(WORKER_CONFIG):
                cluster.scale(workers)
            _wait_for_workers(client, cluster, workers)
            yield client
        finally:
            _kill_stopped(cluster)
            client.close()
    finally:
        _kill_stopped(cluster)
        _close(cluster)


def _close(cluster):
    """Close the local ``cluster`` in at most :data:`CONNECT_TIMEOUT` s; a cluster that
    does not close (a worker killed while it started leaves its nanny waiting) has its
    worker processes killed and is left out of Dask's clean-up at exit (which would
    wait for it again, then print an AssertionError)."""
    import signal

    try:
        cluster.close(timeout=CONNECT_TIMEOUT)
        return
    except BaseException:  # TimeoutError; or a second Ctrl-C: leave at once
        for pid in local_workers(cluster):
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)
        with contextlib.suppress(Exception):
            cluster.shutdown_on_close = False
        raise


def quiet_resource_tracker():
    """Have multiprocessing's resource tracker (it tracks the semaphores of the spawned
    worker processes) relaunched quietly after it died.

    A tracker killed mid-run (SIGKILL, the OOM killer) is relaunched by the next
    semaphore made or freed, with a UserWarning here and, from the new tracker, a
    ``KeyError`` traceback for each semaphore it never saw registered: a run that
    succeeds would end in tracebacks.  The relaunch keeps working; the tracker is
    started with its stderr on the null device and the warning is not shown.  Idempotent;
    returns the tracker (None where multiprocessing has none).
    """
    import warnings
    from multiprocessing import resource_tracker

    tracker = getattr(resource_tracker, "_resource_tracker", None)
    if tracker is None or getattr(tracker, "vibimpact_quiet", False):
        return tracker
    launch = tracker.ensure_running

    def ensure_running():
        alive = getattr(tracker, "_check_alive", None)
        if getattr(tracker, "_fd", None) is not None and alive is not None and alive():
            return launch()  # running: nothing is started, stderr is left alone
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message="resource_tracker: process died")
            return _with_stderr_on_null(launch)

    tracker.ensure_running = ensure_running
    tracker.vibimpact_quiet = True
    return tracker


#: one relaunch at a time: file descriptor 2 is the process's, not a thread's
_STDERR_LOCK = threading.RLock()


def _with_stderr_on_null(call):
    """``call()`` with file descriptor 2 on the null device (a process it starts
    inherits that), then put back.

    A map stopped by a group SIGTERM (which kills the tracker too) now and then exited
    143 with its 'interrupted' line unseen: its stderr was left on the null device.
    Two threads relaunching at once (the main thread unwinding, Dask's closing its
    connections) each saved descriptor 2, the second one saving the null device and
    putting it back last; one relaunch at a time fixes that.  The put-back also
    survives a signal whose exception is raised as the ``finally`` block begins (which
    skips it): the exception handler puts it back then, the one signal spent."""
    with _STDERR_LOCK:
        saved = os.dup(2)
        try:
            try:
                null = os.open(os.devnull, os.O_WRONLY)
                try:
                    os.dup2(null, 2)
                finally:
                    os.close(null)
                return call()
            finally:
                os.dup2(saved, 2)
        except BaseException:
            os.dup2(saved, 2)  # the finally above was cut short by the signal
            raise
        finally:
            os.close(saved)


def _cannot_start(workers, exc):
    """The :class:`~vibimpact.engine.watch.WorkerLost` (a RuntimeError) of a local
    cluster whose workers did not start (the command line says it in one line)."""
    from .watch import WorkerLost

    return WorkerLost(
        f"cannot start {workers} local Dask worker processes ({one_line(exc)}); worker "
        "processes are spawned and import the main module, so a script must call map2d "
        "under `if __name__ == '__main__':` (not needed in Jupyter or the command line)")


def _wait_for_workers(client, cluster, workers):
    """Wait (at most :data:`CONNECT_TIMEOUT` s) until ``workers`` workers of the local
    ``cluster`` are up, its processes watched meanwhile (one stopped while starting
    ends the wait: :class:`~vibimpact.engine.watch.StoppedChild`)."""
    import time

    from .watch import Watch

    tracker = quiet_resource_tracker()
    watch = Watch(lambda: local_workers(cluster))
    deadline = time.monotonic() + CONNECT_TIMEOUT
    while True:
        # a tracker killed meanwhile is relaunched (quietly: quiet_resource_tracker)
        # before a nanny restarts a worker that could not reach it
        if tracker is not None:
            tracker.ensure_running()
        try:
            client.wait_for_workers(workers, timeout=0.1)
            return
        except TimeoutError:
            pass
        except Exception as exc:  # a worker that failed to start
            raise _cannot_start(workers, exc) from exc
        watch.check()
        if time.monotonic() > deadline:
            raise _cannot_start(workers, TimeoutError(
                f"not up after {CONNECT_TIMEOUT} s"))


def local_workers(cluster):
    """``{pid: "a Dask worker process"}`` of the worker processes of a local cluster
    started by :func:`_local_cluster` (none for another cluster)."""
    children = getattr(cluster, "vibimpact_children", None)
    return {} if children is None else children()


def _kill_stopped(cluster):
    """SIGKILL the local cluster's worker processes that are stopped."""
    import signal

    from .watch import is_stopped

    for pid in local_workers(cluster):
        if is_stopped(pid):
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)


@contextlib.contextmanager
def _client(scheduler, workers):
    if scheduler is None:
        with _local_cluster(workers) as client:
            yield client
        return
    client, owned = connect(scheduler)
    try:
        yield client
    finally:
        if owned:
            client.close()


def slots(client):
    """Threads of all the workers of ``client`` (at least 1)."""
    try:
        return max(1, sum(client.nthreads().values()))
    except Exception:
        return 1


class Dask:
    """Run the jobs on Dask: ``scheduler`` None starts a ``LocalCluster`` of ``workers``
    single-threaded processes for the run; otherwise see :func:`connect`.  Task keys start
    with ``prefix``."""

    def __init__(self, scheduler=None, workers=1, prefix="vibimpact"):
        self.scheduler = scheduler
        self.workers = workers
        self.prefix = prefix

    def run(self, make_jobs, on_point, on_task):
        """See :mod:`vibimpact.engine.executors`.  On any exception (a failing job,
        Ctrl-C) the jobs not yet finished are cancelled before it propagates; results
        already passed to ``on_task`` stay delivered.  The worker processes of a local
        cluster are watched while the results are awaited: one that stays stopped
        (SIGSTOP) ends the run (:class:`~vibimpact.engine.watch.StoppedChild`)."""
        import time

        from distributed import KilledWorker, as_completed

        from . import plan
        from .executors import WorkerLost
        from .watch import Watch

        with _client(self.scheduler, self.workers) as client:
            cluster = getattr(client, "local_cluster", None)
            watch = Watch(lambda: {} if cluster is None else local_workers(cluster))
            jobs = make_jobs(slots(client))
            prefix = f"{self.prefix}-{uuid.uuid4().hex[:12]}"
            futures = [client.submit(plan.run_job, job, key=f"{prefix}-{k:06d}",
                                     pure=False) for k, job in enumerate(jobs)]
            index = {f.key: k for k, f in enumerate(futures)}
            try:
                done = as_completed(futures, with_results=True, loop=client.loop)
                while not done.is_empty():
                    if not done.has_ready():  # short waits, the workers watched between
                        watch.check()
                        time.sleep(0.05)
                        continue
                    fut, results = next(done)
                    for task, res in zip(jobs[index[fut.key]], results):
                        on_task(task, res)
                    fut.release()
            except BaseException as exc:
                with contextlib.suppress(Exception):
                    client.cancel(futures)
                if isinstance(exc, KilledWorker):  # died on more workers than Dask retries
                    raise WorkerLost("Dask workers died running a task more often than "
                                     "Dask retries one (distributed.scheduler.allowed-"
                                     "failures)") from exc
                raise
