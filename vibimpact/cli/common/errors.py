"""How the command line words a failure: one line, exit status 2 (standard library
only)."""
import sys

from ...base._text import one_line
from ...engine.signals import interrupt_status


class UsageError(Exception):
    """Bad input: reported as one line and exit status 2."""


#: the option of the command line that sets each flag of the API a refusal names
#: (:class:`vibimpact.io.NeedsFlag`: an existing output, an existing checkpoint)
OPTION_OF_FLAG = {"overwrite": "--overwrite", "resume": "--resume"}


def reason(exc):
    """Why ``exc`` happened, in the command line's words, for one line.

    A refusal that a flag of the API lifts (:class:`vibimpact.io.NeedsFlag`, known by
    its ``flag`` and ``say``) names the option that sets it (``--overwrite``, not
    ``overwrite=True``); an ``OSError`` is its reason without the ``[Errno N]`` prefix;
    a ``KeyError`` names the missing key; anything else is its message.  Python's class
    names are left out (the message says what happened); only an exception without a
    message is named by its class.
    """
    flag, say = getattr(exc, "flag", None), getattr(exc, "say", None)
    if isinstance(flag, str) and callable(say):
        return say(OPTION_OF_FLAG.get(flag, "--" + flag.replace("_", "-")))
    if isinstance(exc, OSError) and exc.strerror:
        return str(exc.strerror)
    if isinstance(exc, KeyError) and exc.args:
        return f"{exc.args[0]!r} is missing"
    return one_line(exc)


def error_text(exc):
    """The message of a failure for one line: :func:`reason`, and the file name of an
    ``OSError`` that has one."""
    if isinstance(exc, OSError) and exc.strerror and exc.filename:
        return f"{reason(exc)}: {exc.filename!r}"
    return reason(exc)


#: whether the command line runs as the process's own program (set by
#: :func:`vibimpact.cli.main`): only then may saying how it ended change the process's
#: signal handling
PROGRAM = {"on": False}


def hold_signals():
    """Ignore SIGINT and SIGTERM from now on, in the command line's own process: the
    command has decided how it ends and is saying so in its last line.  A signal that
    arrives while that line is said (a stopped worker's error as ``timeout`` sends
    SIGTERM) would otherwise interrupt the print and add a second line and another
    status; one already received but not yet handled is dropped with it (Python runs no
    handler for an ignored signal).  Called before every last line: the error and
    interrupted lines of :func:`vibimpact.cli.main`, a command's interrupted line with
    its saved points, a lost worker's line."""
    if PROGRAM["on"]:
        import signal

        for sig in (signal.SIGINT, signal.SIGTERM):
            signal.signal(sig, signal.SIG_IGN)


def report_interrupt(exc, line):
    """Print ``line`` for the interrupt ``exc`` (once: :func:`vibimpact.cli.main` prints
    nothing more for it; signals held first, :func:`hold_signals`) and return its exit
    status."""
    if not getattr(exc, "reported", False):
        hold_signals()
        print(line, file=sys.stderr)
        exc.reported = True
    return interrupt_status(exc)
