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

from ..base._writing import on_before_write


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
    alone, and a signal this process ignores (``SIG_IGN``, as a shell script's
    background job starts with SIGINT, so that the terminal's Ctrl-C does not reach it,
    or as ``trap '' TERM`` asks) stays ignored, as Python leaves it.
    """

    #: the signal that stopped this command, once one has (see :func:`signal_decides`)
    received: int | None = None
    #: whether :attr:`received` has unwound through a guard (False: it was lost so far)
    delivered = False
    #: depth of :func:`signals_deferred` blocks now running, and the signal one of them
    #: holds back (``(guard, signum)``)
    deferring = 0
    pending: tuple[StopWorkersOnSignal, int] | None = None
    #: guards entered in the main thread and not left yet
    depth = 0
    _unraisable = None

    def __enter__(self):
        import signal
        import sys
        import threading

        self._old = {}
        self._pid = os.getpid()
        self._counted = False
        if threading.current_thread() is not threading.main_thread():
            return self  # not the main thread: leave the signals alone
        try:
            for sig in (signal.SIGINT, signal.SIGTERM):
                if signal.getsignal(sig) == signal.SIG_IGN:  # ignored on purpose
                    continue
                self._old[sig] = signal.signal(sig, self._handle)
        except ValueError:  # not the main interpreter: leave the signals alone
            self._restore()
            return self
        cls = StopWorkersOnSignal
        if cls.depth == 0:  # a new request: no signal yet
            cls.received, cls.delivered, cls.pending = None, False, None
            cls._unraisable = sys.unraisablehook
            sys.unraisablehook = _quiet_interrupts(sys.unraisablehook)
        cls.depth += 1
        self._counted = True
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
        self._restore()  # a second Ctrl-C acts at once
        StopWorkersOnSignal.received = signum  # for every guard of this command
        raise Interrupted(signum)  # the executor stops its workers on the way out

    @classmethod
    def check(cls):
        """Raise :class:`Interrupted` for a signal received and lost so far.

        A handler's exception is lost where Python cannot raise it: in a ``ctypes``
        callback (numba's compiler calls one; the exception is printed as "Exception
        ignored" and the compile goes on), a finaliser, or a library's bare
        ``except:``.  The signal is recorded before the exception is raised, so a
        computation or a write that calls this at its safe points ends as the signal
        asked, not with the full result (a SIGINT early in a map ran to the end and
        exited 0)."""
        if cls.received is not None and not cls.delivered and cls.depth:
            cls.delivered = True  # raised at a safe point: it unwinds from here
            raise Interrupted(cls.received)

    def _restore(self):
        import signal

        for sig, old in self._old.items():
            signal.signal(sig, old)
        self._old = {}

    def __exit__(self, exc_type, exc, tb):
        import sys

        self._restore()
        if not self._counted:
            return False
        self._counted = False
        cls = StopWorkersOnSignal
        if exc_type is not None and issubclass(exc_type, KeyboardInterrupt):
            cls.delivered = True  # it unwinds: not lost
        try:
            if exc_type is None:
                cls.check()  # a signal lost inside the block ends it now
        finally:
            cls.depth -= 1
            if cls.depth == 0 and cls._unraisable is not None:
                sys.unraisablehook, cls._unraisable = cls._unraisable, None
        return False


def _quiet_interrupts(hook):
    """``sys.unraisablehook`` that, once a signal has stopped the command, only logs (at
    debug level) what cannot be raised, and passes anything else to ``hook``.

    An interrupt lost where Python cannot raise it (:meth:`StopWorkersOnSignal.check`
    raises it again at the next safe point), and the finaliser of an object the
    interrupt left half-built (llvmlite's ``ObjectRef.__del__``: "no attribute
    '_as_parameter_'"), are consequences of the signal, not errors of their own."""
    if getattr(hook, "quiets_interrupts", False):
        return hook

    def unraisable(info):
        if StopWorkersOnSignal.received is None:
            hook(info)
            return
        import logging

        logging.getLogger(__name__).debug(
            "after the interrupt: %s in %r", info.exc_type.__name__, info.object)

    unraisable.quiets_interrupts = True  # type: ignore[attr-defined]  # an attribute of a function
    return unraisable


def quiet_after_interrupt():
    """For the rest of the process: what Python cannot raise after a signal has stopped
    the command is logged at debug level, not printed (see :func:`_quiet_interrupts`);
    the command line calls this once."""
    import sys

    sys.unraisablehook = _quiet_interrupts(sys.unraisablehook)


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
    the line and the exit status, not the error it caused.  The interrupt returned is
    the signal delivered (its caller raises it): no guard raises it once more on its
    way out."""
    signum = StopWorkersOnSignal.received
    if signum is None or isinstance(exc, KeyboardInterrupt):
        return None
    StopWorkersOnSignal.delivered = True
    return Interrupted(signum)


def interrupt_status(exc):
    """128 + the signal number of an interrupt (130 for a plain KeyboardInterrupt)."""
    import signal

    return 128 + int(getattr(exc, "signum", signal.SIGINT))


on_before_write(StopWorkersOnSignal.check)  # a command a signal stopped writes nothing
