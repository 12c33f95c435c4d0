"""Progress as an explicit callback: ``progress(k)`` is called with every ``k`` points
finished, in the process that runs the request (never in a worker)."""
from __future__ import annotations

import contextlib
import sys

from ..base import _validate as _v


def nothing(k):
    """The progress callback that reports nothing."""


@contextlib.contextmanager
def bar(enabled, total, desc, unit="pt"):
    """A progress callback: a tqdm bar named ``desc`` of ``total`` ``unit`` on stderr when
    ``enabled`` (and there is something to do), :func:`nothing` otherwise.

    The bar is closed, and its full line printed, once: as soon as the count reaches
    ``total`` (not again when the work's executor has shut down, which would print a
    second 100 % line with a lower rate), or on exit from the context when it stops short.
    """
    if not enabled or total <= 0:
        yield nothing
        return
    from tqdm import tqdm

    b = tqdm(total=total, desc=desc, unit=unit, file=sys.stderr)

    def report(k):
        if b.disable:
            return
        if b.n + k < total:
            b.update(k)
        else:  # the last one: the final line is drawn by close, and only there
            b.n = total
            b.close()

    try:
        yield report
    finally:
        b.close()


def callback(progress, total, desc, unit="pt"):
    """The context of a front end's ``progress`` argument: a bool (a bar named ``desc``
    or nothing), a str (a bar of that name: the command's, say) or a callable
    ``progress(k)`` used as is."""
    if callable(progress):
        return contextlib.nullcontext(progress)
    if isinstance(progress, str):
        return bar(bool(progress), total, progress, unit)
    return bar(progress is not None and _v.flag("progress", progress), total, desc, unit)
