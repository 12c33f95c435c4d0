"""SIGINT and SIGTERM during a computation: both raise :class:`Interrupted`, so that a
sweep or map unwinds alike for either (workers stopped, temporary files removed, the
finished points kept in the checkpoint).

:func:`vibimpact.engine.compute.compute` enters :class:`StopWorkersOnSignal` around every
run, so ``vi.sweep`` and ``vi.map2d`` get it as the command line does; the command line
enters it once more for the whole command.  Standard library only (the command line's
``--help`` imports this module).
"""
from __future__ import annotations

import contextlib
import os


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM; ``signum`` decides the exit status 128 + signum."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


class StopWorkersOnSignal:
    """While it is entered: SIGINT and SIGTERM (what ``timeout`` and batch systems send)
    raise :class:`Interrupted` in the main thread, so that both unwind alike: temporary
    files are removed on the way out, workers are killed (finished points are already
    saved atomically, the points in flight are lost) and the command ends with one line
    and exit status 128 + signum.  The first signal restores the handlers found on
    entry, so a second one acts at once.  Outside the main thread it leaves the signals
    alone.
    """

    #: the signal that stopped this command, once one has (see :func:`signal_decides`)
    received = None
    #: depth of :func:`signals_deferred` blocks now running, and the signal one of them
    #: holds back (``(guard, signum)``)
    deferring = 0
    pending = None

    def __enter__(self):
        import signal

        self._old = {}
        self._pid = os.getpid()
        try:
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._old[sig] = signal.signal(sig, self._handle)
        except ValueError:  # not the main thread: leave the signals alone
            self.__exit__(None, None, None)
        return self

    def _handle(self, signum, frame):
        import signal

        if os.getpid() != self._pid:  # a worker forked before its own set-up (the pool
            # ends its workers with SIGTERM): die as by default, no Interrupted traceback
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)
            return
        if StopWorkersOnSignal.deferring:  # raised when the block is over
            StopWorkersOnSignal.pending = StopWorkersOnSignal.pending or (self, signum)
            return
        self.stop(signum)

    def stop(self, signum):
        """Restore the handlers found on entry and raise :class:`Interrupted`."""
        self.__exit__(None, None, None)  # a second Ctrl-C acts at once
        StopWorkersOnSignal.received = signum  # for every guard of this command
        raise Interrupted(signum)  # the executor stops its workers on the way out

    def __exit__(self, *exc):
        import signal

        for sig, old in self._old.items():
            signal.signal(sig, old)
        self._old = {}
        return False


@contextlib.contextmanager
def signals_deferred():
    """A block that a signal does not cut: SIGINT or SIGTERM received inside it raises
    :class:`Interrupted` as soon as it is over.  A checkpoint entry is saved in one such
    block, so a signal never stops Python's ``zipfile`` half-way (which turns the
    interrupt into "Can't close the ZIP file while there is an open writing handle")
    and the point being saved is kept."""
    StopWorkersOnSignal.deferring += 1
    try:
        yield
    finally:
        StopWorkersOnSignal.deferring -= 1
        pending = StopWorkersOnSignal.pending
        if pending is not None and not StopWorkersOnSignal.deferring:
            StopWorkersOnSignal.pending = None
            guard, signum = pending
            guard.stop(signum)


def signal_decides(exc):
    """The interrupt to report instead of the error ``exc``, or None.

    A signal that unwinds a command can surface as another error: Python's ``zipfile``
    (a checkpoint entry being compressed) turns it into "Can't close the ZIP file while
    there is an open writing handle", a write cut short reports its own failure.  When a
    signal has stopped the command (:class:`StopWorkersOnSignal`), that signal decides
    the line and the exit status, not the error it caused."""
    signum = StopWorkersOnSignal.received
    if signum is None or isinstance(exc, KeyboardInterrupt):
        return None
    return Interrupted(signum)


def interrupt_status(exc):
    """128 + the signal number of an interrupt (130 for a plain KeyboardInterrupt)."""
    import signal

    return 128 + int(getattr(exc, "signum", signal.SIGINT))
