"""The child processes of a run, watched while the run waits on them.

A child process that dies is seen by its executor (the pool's sentinels, a lost
connection).  A child that is *stopped* (``SIGSTOP``, or ``SIGTSTP`` sent to it alone)
neither finishes nor dies: a run that waited for it would wait for good, and so would an
interrupted run that asked it to shut down.  :class:`Watch` looks at the state of the
run's children between two waits and ends the run (:class:`StoppedChild`, a
:class:`WorkerLost`) once one of them has stayed stopped for :data:`STOP_GRACE`
seconds: seen stopped (state ``T``, or ``t`` under a tracer) at every check of the
grace *and* without any CPU time spent since the first of them.

Why a grace and why this one: it does not measure the work (a stopped process does
none, whatever the points cost), it tells a stop that nobody will undo from the short
stops of a throttle such as ``cpulimit``, which stops and continues a process many times
a second.  A heavily throttled child (running a tenth of the time, say) may be caught
stopped at every check of a whole grace; its CPU time still advances between the
checks, and that keeps it counted as running.  A stop of the whole process group (Ctrl-Z in a
terminal) stops this process
as well, so it never waits out the grace; after ``fg`` every child runs again.

The process states come from ``psutil`` (installed with Dask distributed).
"""
from __future__ import annotations

import time

#: seconds a child may stay stopped before the run counts it as lost (see the module
#: docstring: a policy about stops, not a measure of the work)
STOP_GRACE = 1.0


class WorkerLost(RuntimeError):
    """A worker process (or the process of the points' queue, or a Dask worker more
    often than Dask retries a task) died or stayed stopped while the run needed it; the
    points finished before it are reported, the ones in flight are lost."""


class StoppedChild(WorkerLost):
    """A child process of the run stayed stopped (SIGSTOP): what it held is lost."""


def is_stopped(pid: int) -> bool:
    """Whether process ``pid`` is stopped by a signal or a tracer (state ``T`` or
    ``t``; False when it is gone or its state cannot be read)."""
    return stopped_cpu(pid) is not None


def stopped_cpu(pid: int) -> float | None:
    """The CPU time (user + system, seconds) process ``pid`` has spent, when it is
    stopped (state ``T`` or ``t``); None when it runs, is gone or cannot be read."""
    import psutil

    try:
        proc = psutil.Process(pid)
        if proc.status() not in (psutil.STATUS_STOPPED,
                                 getattr(psutil, "STATUS_TRACING_STOP", "tracing-stop")):
            return None
        cpu = proc.cpu_times()
        return float(cpu.user) + float(cpu.system)
    except (psutil.Error, OSError):
        return None


class Watch:
    """Watch child processes for stops.

    Parameters
    ----------
    children : callable
        ``children()`` -> ``{pid: what}``: the processes to watch now and how a message
        names each ("a worker process", "the points' queue process").
    grace : float
        Seconds a child must stay stopped, seen stopped at every check in between and
        without spending CPU time from the first of them, before :meth:`check` raises.
    """

    def __init__(self, children, grace: float = STOP_GRACE) -> None:
        self.children = children
        self.grace = grace
        self.since: dict[int, float] = {}
        self.cpu: dict[int, float] = {}

    def check(self) -> None:
        """Raise :class:`StoppedChild` naming the first child that has stayed stopped,
        its CPU time unchanged, for the grace; forget the children that run again (or
        spent CPU time since they were first seen stopped: a throttle's short stops)."""
        now = time.monotonic()
        watched = self.children()
        for pid in list(self.since):
            if pid not in watched:
                del self.since[pid]
                self.cpu.pop(pid, None)
        for pid, what in watched.items():
            cpu = stopped_cpu(pid)
            if cpu is None or (pid in self.cpu and cpu != self.cpu[pid]):
                self.since.pop(pid, None)   # running, or it ran since: a new start
                self.cpu.pop(pid, None)
                if cpu is None:
                    continue
            first = self.since.setdefault(pid, now)
            self.cpu.setdefault(pid, cpu)
            if now - first >= self.grace:
                raise StoppedChild(f"{what} was stopped (SIGSTOP) and did not continue "
                                   f"within {self.grace:g} s; the run cannot finish")
