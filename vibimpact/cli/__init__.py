"""The ``vibimpact`` command line.

One module of this package per command (:data:`COMMANDS`, the registration table: the
command's name and its module), the parts they share in :mod:`vibimpact.cli.common`; no
command imports another.  Only :mod:`argparse`, :mod:`importlib` and :mod:`sys` and the
shared parts are imported at module level, here and in every command module, so that
``vibimpact --help`` is instant; numpy, numba and xarray are imported inside the
commands.  Bad input ends with one line ``vibimpact: error: ...`` on stderr and exit
code 2, never a traceback.
"""
import argparse
import importlib
import sys

from .common.args import Parser, set_verbosity, verbosity
from .common.errors import PROGRAM, UsageError, hold_signals
from ..engine.signals import (interrupt_status, quiet_after_interrupt, signal_decides,
                              StopWorkersOnSignal)

_MAIN_EPILOG = """\
examples:
  vibimpact presets
  vibimpact simulate --preset fig8 --eta 1.25 -o run.nc --plot xy.png
  vibimpact classify --eta 0.9:1.5:0.002 -o fig8.nc
  vibimpact bifurcation --eta 0.9:1.5:0.002 --preset fig8 -o bif.png
  vibimpact plot fig8.nc --kind response -o response.png
  vibimpact continue --preset fig8 --eta 1.12 --stop 1.25 --approach 1.1 -o p1.nc
  vibimpact rerun fig8.nc

'vibimpact COMMAND --help' shows the options and an example of each command.
"""

#: the commands, in the order ``vibimpact --help`` lists them: name -> the module of
#: this package that adds its parser (``add_parser(sub, fmt)``) and runs it.  A module is
#: imported when the parser is built; it imports only the standard library and
#: :mod:`vibimpact.cli.common` at module level, and no other command.
COMMANDS = {
    "presets": "presets",
    "simulate": "simulate",
    "classify": "classify",
    "bifurcation": "bifurcation",
    "plot": "plot",
    "map": "map",
    "continue": "continue_",
    "orbits": "orbits",
    "basins": "basins",
    "continue2": "continue2",
    "attractors": "attractors",
    "rerun": "rerun",
}


class _VersionAction(argparse.Action):
    """``--version``: the package's version and, on a second line, whether the kernel
    compiled at install time is in use and why not (computed only when asked: it imports
    numba)."""

    def __init__(self, option_strings, version, dest=argparse.SUPPRESS,
                 default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)
        self.version = version

    def __call__(self, parser, namespace, values, option_string=None):
        from .._kernel.boundary import precompiled_status

        print(f"{self.version}\nprecompiled kernel: {precompiled_status()}")
        parser.exit()


def build_parser():
    """The argument parser of the ``vibimpact`` command.

    Returns
    -------
    argparse.ArgumentParser
    """
    fmt = argparse.RawDescriptionHelpFormatter
    parser = Parser(prog="vibimpact", formatter_class=fmt, epilog=_MAIN_EPILOG,
                     verbose_dest="verbose_before",
                     description="Bifurcation and chaos analysis of vibro-impact models: the "
                                 "built-in ones\n(Pust & Kozanek's eq. 5 and others; "
                                 "'vibimpact presets') and the user's.")
    from .. import __version__

    parser.add_argument("--version", action=_VersionAction, version=f"vibimpact {__version__}",
                        help="show the version and whether the kernel compiled at install "
                             "(numba's cache) is in use, and why not; then exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    sub.required = True

    for module in COMMANDS.values():
        importlib.import_module(f"{__name__}.{module}").add_parser(sub, fmt)
    # rerun reads a recorded command line with the whole parser, handed down here
    parser.set_defaults(build_parser=build_parser)
    return parser


def main(argv=None):
    """Run the ``vibimpact`` command.

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name; ``sys.argv[1:]`` by default.

    Returns
    -------
    int
        The exit status: 0 success, 1 ``rerun`` found a difference, 2 bad input, a
        failed write or a worker process that died, 74 the command ran but its printed
        output could not be written (stdout or stderr full, closed, failing), 141 its
        printed output went to a pipe whose reader had gone (``| head -1``), 130
        interrupted (SIGINT, Ctrl-C), 143 terminated (SIGTERM, as ``timeout`` and batch
        systems send).  An interrupted or terminated command removes its temporary files
        and keeps its checkpoint (SIGTERM is handled as Ctrl-C at every phase).

    Raises
    ------
    SystemExit
        From argparse (``--help``, ``--version``, a refused option), its status changed
        as above when the text it printed was lost.
    """
    from .common.streams import Streams

    program = argv is None  # the process's own command line: it exits after this
    PROGRAM["on"] = program  # only then does saying the last line hold the signals
    stopped = None
    with Streams(program) as streams:  # a stream that cannot be written: a status
        try:
            status = _main(argv, program)
        except KeyboardInterrupt as exc:  # before the command's guard (reading options)
            hold_signals()
            print("vibimpact: interrupted", file=sys.stderr)
            status = interrupt_status(exc)
        except SystemExit as exc:  # argparse: --help, --version, a usage error
            stopped, status = exc, exc.code
        status = streams.status(status)
    if stopped is not None:
        if status == stopped.code:
            raise stopped
        raise SystemExit(status) from None
    if program and status in (130, 143):
        _exit_after_interrupt(status)
    return status


def _exit_after_interrupt(status):
    """End the process at once with ``status`` after an interrupt, once its output is
    flushed (the command has removed its temporaries and kept its checkpoint; its worker
    processes die with it, PR_SET_PDEATHSIG).  The interpreter's own shutdown would join the process
    pool's manager thread, which blocks for good reading a result that a worker killed by the
    interrupt left half-written (its pipe never reaches end of file while this process
    holds the other end): SIGTERM printed its line and then hung."""
    import os

    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass
    # no exit handlers: multiprocessing's would run its finalizers a second time
    # ("Exception ignored in: <Finalize object, dead>")
    os._exit(status)


def _main(argv, program):
    """:func:`main` in the process (``program``) or called with ``argv``."""
    argv = sys.argv[1:] if argv is None else list(argv)
    args = build_parser().parse_args(argv)
    args.argv = argv
    set_verbosity(verbosity(args))
    StopWorkersOnSignal.received = None
    if program:
        quiet_after_interrupt()
        from .common.first_run import listen

        listen(args.command)  # a first run says that it compiles, before it does
    try:
        try:
            from .common.figures import check_figure_size

            check_figure_size(args)  # every command that draws, before any work
            with StopWorkersOnSignal():
                return args.func(args)
        except Exception as exc:  # an error a signal caused is that signal
            interrupt = signal_decides(exc)
            if interrupt is None:
                raise
            raise interrupt from exc
    except UsageError as exc:
        hold_signals()  # the line says how it ended: a signal now adds none
        print("vibimpact: error: " + " ".join(str(exc).split()), file=sys.stderr)
        return 2
    except KeyboardInterrupt as exc:
        hold_signals()
        if not getattr(exc, "reported", False):  # a command may have said more already
            print("vibimpact: interrupted", file=sys.stderr)
        return interrupt_status(exc)
    finally:
        # the command is over, its files in place: a signal during the interpreter's
        # exit must not kill it silently (exit -15, no line)
        hold_signals()

