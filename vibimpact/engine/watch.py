"""The child processes of a run, watched while the run waits on them.

A child process that dies is seen by its executor (the pool's sentinels, a lost
connection).  A child that is *stopped* (``SIGSTOP``, or ``SIGTSTP`` sent to it alone)
neither finishes nor dies: a run that waited for it would wait for good, and so would an
interrupted run that asked it to shut down.  :class:`Watch` looks at the state of the
run's children between two waits and ends the run (:class:`StoppedChild`, a
:class:`WorkerLost`) once one of them has stayed stopped for :data:`STOP_GRACE`
seconds.

Why a grace and why this one: it does not measure the work (a stopped process does
none, whatever the points cost), it tells a stop that nobody will undo from the short
stops of a throttle such as ``cpulimit``, which stops and continues a process many times
a second.  A stop of the whole process group (Ctrl-Z in a terminal) stops this process
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
    """Whether process ``pid`` is stopped by a signal (False when it is gone or its
    state cannot be read)."""
    import psutil

    try:
        return psutil.Process(pid).status() == psutil.STATUS_STOPPED
    except (psutil.Error, OSError):
        return False


class Watch:
    """Watch child processes for stops.

    Parameters
    ----------
    children : callable
        ``children()`` -> ``{pid: what}``: the processes to watch now and how a message
        names each ("a worker process", "the points' queue process").
    grace : float
        Seconds a child must stay stopped, seen stopped at every check in between,
        before :meth:`check` raises.
    """

    def __init__(self, children, grace: float = STOP_GRACE) -> None:
        self.children = children
        self.grace = grace
        self.since: dict[int, float] = {}

    def check(self) -> None:
        """Raise :class:`StoppedChild` naming the first child that has stayed stopped
        for the grace; forget the children that run again."""
        now = time.monotonic()
        watched = self.children()
        for pid in list(self.since):
            if pid not in watched:
                del self.since[pid]
        for pid, what in watched.items():
            if not is_stopped(pid):
                self.since.pop(pid, None)
                continue
            first = self.since.setdefault(pid, now)
            if now - first >= self.grace:
                raise StoppedChild(f"{what} was stopped (SIGSTOP) and did not continue "
                                   f"within {self.grace:g} s; the run cannot finish")
