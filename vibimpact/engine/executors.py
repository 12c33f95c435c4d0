"""Executors: where the jobs of a plan run.

The executor protocol
---------------------
An executor is any object with one method (:class:`Executor`)::

    run(make_jobs, on_point, on_task)

``make_jobs(slots)``
    The jobs (lists of :class:`~vibimpact.engine.plan.Task`), given the number of worker
    threads (None when the executor does not know it), so that jobs can be sized to it.
``on_point(task, position, result)`` or None
    Called in this process for every point as soon as it is finished (None: only whole
    tasks are reported).  An executor that cannot report single points may ignore it.
``on_task(task, results)``
    Called in this process for every finished task with its ``[(position, result)]``:
    what :func:`vibimpact.engine.plan.run_task` returns for it, wherever it ran.

``run`` returns when every task is reported; it may run the tasks in any order, in any
process, grouped as it likes (tasks are pure functions of their fields).  When it is
interrupted (an exception, Ctrl-C) it stops its workers and lets the exception through.
An ensemble or GPU backend is such an object: it needs no change to
:mod:`vibimpact.points` or to the engine.  Pass one as
``vi.Execution(executor=...)``.

* :class:`Serial`: in this process, in order.
* :class:`Processes`: local worker processes (``concurrent.futures.ProcessPoolExecutor``,
  forked on Linux); points travel back through a queue of a manager process.  A worker
  (or the queue's process) that dies, killed by the OOM killer or ``kill -9``, ends the
  run at once with :class:`WorkerLost` instead of a hang; the points finished before are
  reported (saved in the checkpoint), so a resumed run loses nothing else.  A worker
  or queue process that stays stopped (SIGSTOP) ends the run alike
  (:mod:`vibimpact.engine.watch`): no wait on a child is unbounded.  Ctrl-C, SIGTERM or
  any error kills the workers and the queue's process at once (stopped ones too).
* :class:`vibimpact.engine.cluster.Dask`: a Dask cluster (local or remote).

Which executor runs a plan never changes a number.
"""
from __future__ import annotations

import collections
import os
import queue as _queue
import sys
import threading
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool

from typing import Any, Protocol, runtime_checkable

from . import plan
from .children import worker_setup
from .watch import Watch, WorkerLost  # WorkerLost: this module's name too


#: what :class:`WorkerLost` says of a pool worker that died
DIED = "a worker process died unexpectedly (killed by the system or a signal)"


@runtime_checkable
class Executor(Protocol):
    """The executor protocol (see the module docstring): one method, ``run``."""

    def run(self, make_jobs, on_point, on_task):
        """Run every job of ``make_jobs(slots)``; report points and tasks as they
        finish."""


class Serial:
    """Run every job in this process, in order."""

    def run(self, make_jobs, on_point, on_task):
        for job in make_jobs(None):
            for task, results in zip(job, plan.run_job(job, on_point)):
                on_task(task, results)


class QueueLink:
    """The points' queue (a manager's queue proxy) as it travels to a worker: pickled
    without connecting, opened by the worker with :meth:`open`.  A proxy unpickled by
    the pool connects to its manager there and then, outside the task, so a dead
    manager printed a traceback from the worker on the command's stderr; here the
    worker ends quietly and the parent reports the lost queue (:class:`WorkerLost`)."""

    def __init__(self, proxy):
        self.rebuild, self.args = proxy.__reduce__()

    def open(self):
        """The queue proxy, connected; a worker whose manager is gone exits at once."""
        try:
            return self.rebuild(*self.args)
        except (EOFError, OSError):
            os._exit(1)


def run_job_streaming(job, link):
    """Runs in a worker: :func:`plan.run_job`, every finished point put on the queue of
    ``link`` (a :class:`QueueLink`) as ``(row, direction, start, position, result)``;
    returns the results.  A worker whose queue is gone exits quietly."""
    points = link.open()

    def put(task, i, res):
        try:
            points.put((task.row, task.direction, task.start, i, res))
        except (EOFError, OSError):
            os._exit(1)

    return plan.run_job(job, put)


class Processes:
    """Run the jobs on ``workers`` local processes (see the module docstring)."""

    def __init__(self, workers):
        self.workers = workers

    def run(self, make_jobs, on_point, on_task):
        import multiprocessing as mp

        jobs = make_jobs(None)
        if not jobs:
            return
        ctx = mp.get_context("fork" if sys.platform != "win32" else "spawn")
        manager = None
        try:
            if on_point is not None:
                from multiprocessing.managers import SyncManager

                manager = SyncManager(ctx=ctx)
                manager.start(worker_setup)
            before = set(mp.active_children())  # the manager's process: not a worker
            pool = ProcessPoolExecutor(min(self.workers, len(jobs)), mp_context=ctx,
                                       initializer=worker_setup)

            def children():
                out = {p.pid: "a worker process"
                       for p in set(mp.active_children()) - before}
                process = getattr(manager, "_process", None)  # private (no manager: None)
                if process:
                    out[process.pid] = "the points' queue process"
                return out

            try:
                self._loop(pool, jobs, manager, on_point, on_task, Watch(children))
            except BaseException:
                # Ctrl-C, SIGTERM, an error or a lost worker: kill the workers now (the
                # finished points are already reported; the points in flight are lost);
                # a stopped worker dies of SIGKILL too
                _kill(set(mp.active_children()) - before)
                _shutdown(pool, cancel_futures=True)
                raise
            # every result is in: the workers are idle and end on the pool's sentinels;
            # shutdown(wait=True) would hang for good if one was killed meanwhile (the
            # pool's thread then waits for a worker that never gets its sentinel)
            _shutdown(pool)
            _end(set(mp.active_children()) - before, grace=2.0)
        finally:
            if manager is not None:
                _end_manager(manager)

    @staticmethod
    def _loop(pool, jobs, manager, on_point, on_task, watch):
        q = None if manager is None else manager.Queue()
        tasks = {(t.row, t.direction, t.start): t for job in jobs for t in job}
        try:
            if q is None:
                futures = {pool.submit(plan.run_job, job): job for job in jobs}
            else:
                link = QueueLink(q)
                futures = {pool.submit(run_job_streaming, job, link): job
                           for job in jobs}
        except BrokenProcessPool as exc:  # a worker died while the jobs were handed out
            raise WorkerLost(DIED) from exc
        points = None if q is None else Drainer(q)
        try:
            if points is not None:
                points.start()
            pending = set(futures)
            while pending:
                done, pending = wait(pending, timeout=0.05, return_when=FIRST_COMPLETED)
                if done and points is not None:  # every point of a finished job first
                    points.sync(watch)
                _deliver(points, tasks, on_point)
                for f in done:
                    try:
                        results = f.result()  # re-raises a worker's exception
                    except BrokenProcessPool as exc:
                        _deliver(points, tasks, on_point)  # what the others finished
                        raise WorkerLost(DIED) from exc
                    except (EOFError, ConnectionError) as exc:  # the queue's process died
                        raise _queue_died(exc) from exc
                    for task, res in zip(futures[f], results):
                        on_task(task, res)
                if pending:
                    watch.check()  # a stopped worker or queue process ends the run
            if points is not None:
                points.sync(watch)
            _deliver(points, tasks, on_point)
        finally:
            if points is not None:
                points.finish = True


def _queue_died(exc):
    """The WorkerLost of a lost connection to the points' queue process (``exc``: an
    EOFError or a ConnectionError), said in words."""
    why = getattr(exc, "strerror", None) or " ".join(str(exc).split()) or \
        "its connection closed"
    return WorkerLost(f"the points' queue process died unexpectedly ({why})")


class Drainer(threading.Thread):
    """The thread that takes the finished points off the points' queue (a manager's
    queue proxy), so that this process's main thread never waits on the queue's
    process: a stopped queue process (SIGSTOP), even one stopped half-way through an
    answer or a connection's handshake, blocks this thread only, and the main thread's
    waits (:meth:`sync`) watch the children meanwhile.  The thread ends when told to
    (:attr:`finish`) or when the queue's process is gone (killed after every run)."""

    def __init__(self, q):
        super().__init__(name="vibimpact-points", daemon=True)
        self.q = q
        self.items: collections.deque[Any] = collections.deque()  # points taken
        self.error: BaseException | None = None
        self.finish = False
        self.requests: _queue.SimpleQueue[threading.Event] = _queue.SimpleQueue()

    def run(self):
        try:
            while True:
                asked = []  # requests made before this get: all answered by its Empty
                while True:
                    try:
                        asked.append(self.requests.get_nowait())
                    except _queue.Empty:
                        break
                try:
                    self.items.append(self.q.get(timeout=0.05))
                except _queue.Empty:
                    for event in asked:
                        event.set()
                    if self.finish:
                        return
                    continue
                for event in asked:  # not answered yet: asked again
                    self.requests.put(event)
        except BaseException as exc:  # noqa: BLE001 -- handed to the main thread
            self.error = exc

    def sync(self, watch):
        """Return once every point put on the queue before this call has been taken
        (see :meth:`take`), :meth:`Watch.check` between short waits; the thread's error
        (a lost queue process) is raised, as :class:`WorkerLost`."""
        event = threading.Event()
        self.requests.put(event)
        while not event.wait(0.05):
            if self.error is not None or not self.is_alive():
                break
            watch.check()
        if self.error is not None:
            exc = self.error
            if isinstance(exc, (EOFError, ConnectionError)):
                raise _queue_died(exc) from exc
            raise exc

    def take(self):
        """The points taken so far and not returned before."""
        out = []
        while self.items:
            out.append(self.items.popleft())
        return out


def _deliver(points, tasks, on_point):
    """``on_point`` for every point the :class:`Drainer` ``points`` has taken; a lost
    queue process is raised (:class:`WorkerLost`)."""
    if points is None:
        return
    for row, d, start, i, res in points.take():
        on_point(tasks[(row, d, start)], i, res)
    if isinstance(points.error, (EOFError, ConnectionError)):
        raise _queue_died(points.error) from points.error


def _end_manager(manager):
    """End the points' queue process: killed, never asked (a stopped or dying manager
    would not answer ``shutdown``, and every point is drained or lost by now), then the
    manager's own clean-up, which finds its process gone."""
    proc = getattr(manager, "_process", None)
    if proc is not None:
        _kill([proc])
        proc.join(5.0)  # a SIGKILLed process is reaped at once; bounded all the same
    try:
        manager.shutdown()
    except Exception:  # noqa: BLE001 -- a manager that never started, already ended
        pass


def _shutdown(pool, cancel_futures=False):
    """``pool.shutdown(wait=False)``, and the pool's thread taken off the list that
    Python's exit hook for process pools wakes (``concurrent.futures.process.
    _python_exit``).

    That thread closes its wake-up pipe on its way out, under the pool's lock; Python
    3.11's exit hook writes to the same pipe without that lock, so a command that ended
    while the thread was still closing it printed "Exception ignored ... OSError:
    [Errno 9] Bad file descriptor" and a traceback after its own last line (a stopped
    worker's run, now and then).  ``shutdown`` wakes the thread itself, so the hook's
    wake-up has nothing left to do; waiting for the thread instead could take long (a
    worker killed half-way through a result blocks it until the process exits)."""
    thread = getattr(pool, "_executor_manager_thread", None)  # shutdown forgets it
    pool.shutdown(wait=False, cancel_futures=cancel_futures)
    if thread is None:
        return
    try:
        from concurrent.futures import process as _cf_process

        _cf_process._threads_wakeups.pop(thread, None)
    except (ImportError, AttributeError, TypeError):  # another Python's internals
        pass


def _end(processes, grace):
    """Let ``processes`` exit for ``grace`` seconds, then kill those still running."""
    import time

    deadline = time.monotonic() + grace
    while any(p.is_alive() for p in processes) and time.monotonic() < deadline:
        time.sleep(0.01)
    _kill(p for p in processes if p.is_alive())


def _kill(processes):
    for proc in processes:
        try:
            proc.kill()
        except (OSError, ValueError, AttributeError):
            pass


def choose(workers, n_tasks):
    """The local executor for ``workers`` processes and ``n_tasks`` tasks."""
    return Serial() if workers == 1 or n_tasks <= 1 else Processes(workers)
