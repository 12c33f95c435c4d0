"""Progress as an explicit callback: ``progress(k)`` is called with every ``k`` points
finished, in the process that runs the request (never in a worker)."""
from __future__ import annotations

import contextlib
import sys


def nothing(k):
    """The progress callback that reports nothing."""


@contextlib.contextmanager
def bar(enabled, total, desc):
    """A progress callback: a tqdm bar of ``total`` points on stderr when ``enabled`` (and
    there is something to do), :func:`nothing` otherwise; the bar is closed on exit."""
    if not enabled or total <= 0:
        yield nothing
        return
    from tqdm import tqdm

    b = tqdm(total=total, desc=desc, unit="pt", file=sys.stderr)
    try:
        yield b.update
    finally:
        b.close()


def callback(progress, total, desc):
    """The context of a front end's ``progress`` argument: a bool (a bar or nothing) or a
    callable ``progress(k)`` used as is."""
    if callable(progress):
        return contextlib.nullcontext(progress)
    return bar(bool(progress), total, desc)
