"""The set-up every child process of the engine runs first (pool workers, the manager of
the points' queue, the warm-up helper)."""
from __future__ import annotations

import os
import signal
import sys


def worker_setup():
    """Set-up of a worker or manager process: Ctrl-C and SIGTERM (sent to the whole
    process group by a terminal, ``timeout`` or a batch system) are the parent's to
    handle, which then kills its children (no handler inherited by fork raises here), and
    it dies with the parent."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        try:  # PR_SET_PDEATHSIG: SIGKILL this process when the parent process dies
            import ctypes
            ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)
        except (OSError, AttributeError):
            pass
        if os.getppid() == 1:  # the parent died before the line above
            os._exit(1)
