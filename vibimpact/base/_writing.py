"""What every writer of a file does around its temporary: a name that carries the
writing process's id, the temporaries of dead writers removed, and SIGINT / SIGTERM
held while a file library writes.  Standard library only.

Temporary names
    ``.NAME.PID-XXXXXXXX.tmp`` beside the output ``NAME`` (``.old`` for a Zarr store set
    aside while it is replaced): a run killed with SIGKILL cannot remove its temporary,
    a later write of the same output removes it (:func:`remove_dead_temporaries`) once
    process PID is gone.  Only names of this pattern are removed, never a live
    process's.

Signals held during a write
    netCDF4 (HDF5) and zarr hold locks while they write; a ``KeyboardInterrupt`` raised
    by a signal handler between a lock's acquisition and its release leaves it held,
    and the clean-up that closes the file then waits on it for good (``rerun`` of a
    150 MB file deadlocked so, leaving its temporary).  :func:`held_signals` lets the
    library finish the call it is in: the first SIGINT or SIGTERM is delivered as soon
    as the block ends (after the temporary is removed), a second one ends the process
    at once (its temporaries removed first).
"""
from __future__ import annotations

import contextlib
import os
import re
import signal
from collections.abc import Callable
import threading

__all__ = ["temp_prefix", "temporary_pid", "remove_dead_temporaries", "held_signals",
           "running", "before_write", "on_before_write"]

#: checks run before any output is written (see :func:`on_before_write`)
_BEFORE_WRITE: list[Callable[[], None]] = []


def on_before_write(check) -> None:
    """Have ``check()`` run before every write of an output (:func:`before_write`): the
    signal guard registers the check that raises a signal received and lost so far, so
    that a command it should have stopped writes nothing."""
    if check not in _BEFORE_WRITE:
        _BEFORE_WRITE.append(check)


def before_write() -> None:
    """Run the checks of :func:`on_before_write`; every writer calls this before it
    creates its temporary (:func:`held_signals` does on entry)."""
    for check in _BEFORE_WRITE:
        check()


def temp_prefix(path: str) -> str:
    """The prefix of a temporary of ``path``: ``.NAME.PID-`` (for ``tempfile``)."""
    return f".{os.path.basename(path)}.{os.getpid()}-"


def _pattern(name: str) -> re.Pattern:
    return re.compile(r"\." + re.escape(name) + r"\.(\d+)-[^/]*\.(?:tmp|old)\Z")


def temporary_pid(output: str, candidate: str) -> int | None:
    """The writer's pid in ``candidate`` when it is a temporary of ``output`` named by
    :func:`temp_prefix`, else None."""
    m = _pattern(os.path.basename(output)).match(os.path.basename(candidate))
    return int(m.group(1)) if m else None


def running(pid: int) -> bool:
    """Whether process ``pid`` exists (another user's included)."""
    if pid <= 0:
        return True  # never ours to judge
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    return True


def remove_dead_temporaries(path: str) -> list[str]:
    """Remove the temporaries of ``path`` (:func:`temp_prefix` names, beside it) whose
    writing process no longer runs; returns the names removed."""
    import shutil

    directory, name = os.path.split(os.path.abspath(path))
    pattern = _pattern(name)
    try:
        names = os.listdir(directory)
    except OSError:
        return []
    removed = []
    for base in names:
        m = pattern.match(base)
        if not m or running(int(m.group(1))):
            continue
        full = os.path.join(directory, base)
        try:
            if os.path.isdir(full) and not os.path.islink(full):
                shutil.rmtree(full)
            else:
                os.unlink(full)
            removed.append(base)
        except OSError:
            pass
    return removed


class SignalHeld(KeyboardInterrupt):
    """A signal held during a write whose handler returned (see :func:`held_signals`);
    ``signum`` decides the exit status 128 + signum."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


class _Held:
    def __init__(self):
        self.signum = None
        self.temporaries = []


def _remove(paths):
    import shutil

    for p in paths:
        if os.path.isdir(p) and not os.path.islink(p):
            shutil.rmtree(p, ignore_errors=True)
        elif os.path.lexists(p):
            with contextlib.suppress(OSError):
                os.unlink(p)


def _ours(handler):
    """Whether a handler found on entry is one :func:`held_signals` may hold back: the
    defaults (termination, KeyboardInterrupt) or the package's signal guard.  A user's
    own handler, or an ignored signal, is left as it is."""
    if handler in (signal.SIG_DFL, signal.default_int_handler):
        return True
    owner = getattr(handler, "__self__", None)
    return type(owner).__name__ == "StopWorkersOnSignal"


@contextlib.contextmanager
def held_signals():
    """A block that SIGINT and SIGTERM do not cut (see the module docstring).

    Yields an object whose ``temporaries`` list the block fills with the paths it
    creates: a second signal removes them before the process ends.  On leaving the
    block, a held signal is delivered to the handler found on entry (which raises, or
    ends the process); if that handler returns, :class:`KeyboardInterrupt` is raised, so
    a held signal never lets the write look finished.  Outside the main thread the
    block changes nothing.
    """
    held = _Held()
    if threading.current_thread() is not threading.main_thread():
        yield held
        return
    before_write()
    old = {}

    def handle(signum, frame):
        if held.signum is not None:  # the second: at once
            _remove(held.temporaries)
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)
            return
        held.signum = signum

    try:
        for sig in (signal.SIGINT, signal.SIGTERM):
            found = signal.getsignal(sig)
            if _ours(found):
                old[sig] = signal.signal(sig, handle)
    except ValueError:  # not the main interpreter's main thread
        pass
    try:
        yield held
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)
        if held.signum is not None:
            os.kill(os.getpid(), held.signum)  # the handler runs in os.kill
            raise SignalHeld(held.signum)
