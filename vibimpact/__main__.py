"""``python -m vibimpact``: the ``vibimpact`` command line.

SIGINT and SIGTERM are handled from the first line: while the command line is still
being imported, either ends it with one line and exit status 128 + signum (not a
``KeyboardInterrupt`` traceback, not a silent death by SIGTERM).  A signal the
process was started ignoring (a shell script's background job ignores SIGINT) stays
ignored throughout.  A standard stream the process was started without (``>&-``) gets
the null device as its descriptor before anything else is opened
(:func:`vibimpact.cli.common.streams.fill_closed_descriptors`).
"""
import signal
import sys


class _Stopped(KeyboardInterrupt):
    """SIGINT or SIGTERM before the command has its own signal handlers."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


def _stop(signum, frame):
    raise _Stopped(signum)


def run():
    """The command line, with SIGINT and SIGTERM handled while it is imported; returns
    the exit status (the ``vibimpact`` script's entry point)."""
    for sig in (signal.SIGINT, signal.SIGTERM):
        if signal.getsignal(sig) != signal.SIG_IGN:  # an ignored signal stays ignored
            signal.signal(sig, _stop)
    try:
        from vibimpact.cli.common.streams import fill_closed_descriptors

        fill_closed_descriptors()  # no file the command opens may become its stdout
        from vibimpact.cli import main
    except KeyboardInterrupt as exc:
        print("vibimpact: interrupted", file=sys.stderr)
        return 128 + int(getattr(exc, "signum", signal.SIGINT))
    return main()


if __name__ == "__main__":
    sys.exit(run())
