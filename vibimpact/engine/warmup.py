"""Compiling, in a second process, what a request's points will need.

A sweep or map first compiles the integrator in the process that plans it (its seeding
pass integrates); the points then call a few array routines (least squares, eigenvalues,
the recurrence residuals of period detection: :func:`vibimpact._kernel.boundary.
compile_array_routines`) that the integrator does not use.  :func:`start` compiles those
in a forked helper process, on another core, while the planning process compiles the
integrator, so that the workers load them from numba's disk cache instead of compiling
them after the seeding: a cold first run is shorter by their compilation time, a warm one
is not changed (the helper loads them from the cache and exits).  Nothing a run computes
depends on it.
"""
from __future__ import annotations

import logging
import sys
import threading

log = logging.getLogger(__name__)

_started = False


def start():
    """Start the helper once per process; Linux only (fork), and only while this process
    runs no other thread (a fork then could copy a lock another thread holds)."""
    global _started
    from .._kernel import boundary as _kb

    if (_started or not sys.platform.startswith("linux") or threading.active_count() > 1
            or _kb.array_routines_compiled()):
        return
    import multiprocessing as mp

    import atexit

    _started = True
    log.debug("compiling the array routines in a warm-up process")
    helper = mp.get_context("fork").Process(target=_compile, name="vibimpact-warm-up",
                                            daemon=True)
    helper.start()
    # at exit multiprocessing sends a daemon child SIGTERM and joins it: a helper that
    # was stopped (SIGSTOP) would never die of it, and the exit would wait for good.
    # Registered after multiprocessing's own exit function, this one runs first.
    atexit.register(_end, helper)


def _end(helper):
    """Kill the helper if it still runs (stopped or not) and reap it."""
    try:
        if helper.is_alive():
            helper.kill()
        helper.join(5.0)
    except (OSError, ValueError, AssertionError):  # already reaped, or not our child
        pass


def _compile():
    import signal

    from .._kernel import boundary as _kb
    from .children import worker_setup

    worker_setup()
    # multiprocessing ends a daemon child with SIGTERM when this process exits; nothing
    # depends on the helper, so SIGTERM ends it at once
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    _kb.compile_array_routines()
