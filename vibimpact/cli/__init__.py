"""The ``vibimpact`` command line.

Only :mod:`argparse` and :mod:`sys` are imported at module level, so that ``vibimpact
--help`` is instant; numpy, numba and xarray are imported inside the commands.  Bad input
ends with one line ``vibimpact: error: ...`` on stderr and exit code 2, never a traceback.
"""
import argparse
import sys

_PRESET_COLUMNS = ("kh", "G", "Bh", "BT", "f", "Rr", "B", "Ec")

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

_PRESETS_EPILOG = """\
example:
  vibimpact presets

B (support damping) and Ec (unbalance eccentricity) are not given in the paper; every
preset uses our documented defaults for them.
"""

_SIMULATE_EPILOG = """\
examples:
  vibimpact simulate --preset fig8 --eta 1.25 --set BT=0.05 --periods 50 \\
      --transient 300 -o run.nc --plot xy.png
  vibimpact classify --eta 1.1:1.3:0.01 --direction both -o sweep.nc
  vibimpact simulate --from sweep.nc --eta 1.25 --direction up -o chaos.nc --plot chaos.png
  vibimpact simulate --from sweep.nc --eta 1.25 --direction up --set BT=0.01 -o near.nc

--from SWEEP.nc starts the run where the sweep left the motion at that grid value of
eta and direction (its final_state there), on the attractor the sweep followed: from
rest the rotor may settle on another one (fig8 at eta 1.25: the sweep up from 1.1 is
chaotic, the run from rest impactless).  --eta must be a grid value of the sweep (the
error names the nearest ones); --direction is needed when the sweep has both.  The run
uses the sweep's parameters; --set changes named ones explicitly (the file keeps both);
--preset and --state0 cannot be given with --from.  The file records the start (state0
and start_* attributes), so 'vibimpact rerun' needs no sweep file.

The NetCDF file holds the stroboscopic samples (strobe), one record per impact
(impact_*), the dense trajectory when asked for (--dense, or --plot, which keeps 64
samples per period unless --dense says otherwise), and as global attributes every
parameter (param_*), the solver settings (solver_*), counters, status and the command line.

exit status: 0 when the file was written, also for a run that DIVERGED or FAILED: its
rows up to the stop are written, the status and reason are stored as the attributes
'status' and 'reason', and a warning line goes to stderr.  2 for bad input (nothing is
written).
"""


from .common.args import (number, parse_sets, Parser, positive_int, positive_number,
                       set_verbosity, verbosity, with_sets)
from .common.errors import error_text, UsageError
from .common.figures import add_figure_options, figure_options
from .common.files import check_output, write_outputs
from ..engine.signals import (interrupt_status, quiet_after_interrupt, signal_decides,
                             StopWorkersOnSignal)
from ..base._text import count


def _cmd_presets(args):
    from ..models import presets

    header = ("name",) + tuple(c + "*" if c in ("B", "Ec") else c for c in _PRESET_COLUMNS)
    rows = []
    for name in presets.paper_names():
        p = presets.get(name).as_dict()
        rows.append((name,) + tuple(f"{p[c]:g}" for c in _PRESET_COLUMNS)
                    + (presets.describe(name),))
    widths = [max(len(r[i]) for r in rows + [header]) for i in range(len(header))]
    print("  ".join(h.ljust(w) for h, w in zip(header, widths)) + "  description")
    for r in rows:
        print("  ".join(c.ljust(w) for c, w in zip(r, widths)) + "  " + r[-1])
    print("\n* B and Ec are our defaults, not values from the paper; all the paper's presets have "
          "k3 = -0.002 and eta is set per run (--eta).")
    others = [n for n in presets.names() if n not in presets.paper_names()]
    if others:
        print("\nPresets of the other built-in models:")
        for name in others:
            values = ", ".join(f"{k}={v:g}" for k, v in presets.get(name).as_dict().items())
            print(f"  {name}  ({type(presets.get(name)).__name__}: {values})  "
                  f"{presets.describe(name)}")
    return 0


def _cmd_simulate(args):
    import os
    import shlex
    import time

    from ..models import presets

    out = os.fspath(args.output)
    check_output(out, args.overwrite, "output file")
    fig_kw = figure_options(args, drawing=args.plot is not None)
    if args.plot is not None:
        check_output(args.plot, args.overwrite, "plot file")
        ext = os.path.splitext(args.plot)[1].lstrip(".").lower()
        from matplotlib.backend_bases import FigureCanvasBase

        if ext not in FigureCanvasBase.get_supported_filetypes():
            raise UsageError(f"--plot {args.plot!r}: unknown image extension "
                              "(use .png, .pdf or .svg)")
    from .common.inputs import check_distinct, check_state0

    check_distinct(("-o", out), ("--plot", args.plot),
                   inputs=(("--from", args.from_sweep),))
    attrs, note = {"preset": "fig8" if args.preset is None else args.preset}, ""
    state0 = args.state0
    if args.from_sweep is not None:
        from .common.start import start_of

        params, state0, start_attrs, note = start_of(args)
        attrs = start_attrs
    elif args.direction is not None:
        raise UsageError("--direction needs --from (the sweep's direction to start from)")
    else:
        try:
            base = presets.get(attrs["preset"])
        except ValueError as exc:
            raise UsageError(error_text(exc)) from None
        params = with_sets(base, parse_sets(args.set), args.eta)
    dense = args.dense if args.dense is not None else (64 if args.plot else 0)
    from ..base import _limits
    from ..core.system import to_system

    check_state0(state0 if args.from_sweep is None else None, to_system(params))
    n_state = to_system(params).n_state
    check_run_limits(args, dense, n_state)  # before sizing the output
    # the file holds the run's arrays once: is there room for it?
    check_output(out, args.overwrite, "output file",
                 size=_limits.run_bytes(args.periods, dense, n_state) // 2)

    from .. import io
    from ..core.simulation import simulate
    from ..core.solver import SolverSettings

    start = time.perf_counter()
    try:
        run = simulate(params, periods=args.periods, transient=args.transient,
                       state0=state0, dense=dense, solver=SolverSettings(
                           method=args.method, rtol=args.rtol, atol=args.atol))
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    elapsed = time.perf_counter() - start
    command = shlex.join(["vibimpact"] + list(args.argv))
    ds = run.to_dataset(command, attrs={**attrs, "wall_time_s": round(elapsed, 3)})
    writes = [(out, lambda: io.write_netcdf(ds, out, overwrite=args.overwrite))]
    if args.plot is not None:
        from ..plotting import plot_xy

        writes.append((args.plot, lambda: plot_xy(ds, args.plot, **fig_kw)))
    write_outputs(*writes)  # both or neither
    if not run.ok:
        print(f"vibimpact: warning: run {run.status.value.upper()}: {run.reason}; "
              f"wrote the {count(len(run.strobe), 'sample')} computed", file=sys.stderr)
    print(f"wrote {out}: {count(len(run.strobe), 'stroboscopic sample')}, "
          f"{count(len(run.impacts), 'impact')}, "
          f"status {run.status.value} ({elapsed:.1f} s)"
          + (f"; plot {args.plot}" if args.plot else "") + (f"; {note}" if note else ""))
    return 0


def check_run_limits(args, dense, n_state):
    """The limits of :func:`vibimpact.base._limits.check_run` (forcing periods, memory),
    checked here so that the refusal names the options (``--periods 5 with --dense
    10``), not the API's arguments (``periods=5``)."""
    from ..base import _limits

    total = args.periods + args.transient
    if total > _limits.MAX_PERIODS:
        cost = _limits.human_duration(total * _limits.SECONDS_PER_PERIOD)
        raise UsageError(f"--periods {args.periods} + --transient {args.transient} is "
                         f"{total} forcing periods (about {cost} at "
                         f"~{_limits.SECONDS_PER_PERIOD * 1e3:g} ms per period); at most "
                         f"{_limits.MAX_PERIODS} in one run")
    samples = (f"--dense {dense}" if args.dense is not None else
               f"the {dense} samples per period of --plot")
    try:
        _limits.check_memory(_limits.run_bytes(args.periods, dense, n_state),
                             f"--periods {args.periods} with {samples}")
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None


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
                     description="Bifurcation and chaos analysis of a vibro-impact rotor on "
                                 "magnetic bearings\n(Pust & Kozanek, eq. 5).")
    from .. import __version__

    parser.add_argument("--version", action=_VersionAction, version=f"vibimpact {__version__}",
                        help="show the version and whether the kernel compiled at install "
                             "(numba's cache) is in use, and why not; then exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    sub.required = True

    p = sub.add_parser("presets", help="list the paper's parameter sets",
                       description="List the presets (one per figure of the paper) with "
                                   "their parameters.", epilog=_PRESETS_EPILOG,
                       formatter_class=fmt)
    p.set_defaults(func=_cmd_presets)

    s = sub.add_parser("simulate", help="integrate one run and write it as NetCDF",
                       description="Integrate the rotor model at one speed eta and write "
                                   "the run (stroboscopic\nsamples, impacts, parameters) "
                                   "to a NetCDF file.", epilog=_SIMULATE_EPILOG,
                       formatter_class=fmt)
    s.add_argument("--preset", default=None, help="parameter set (default: fig8); "
                   "see 'vibimpact presets'")
    s.add_argument("--eta", type=number, default=None,
                   help="forcing (rotor speed) frequency ratio, > 0 (default: the preset's, 1.0)")
    s.add_argument("--set", action="append", metavar="NAME=VALUE", default=[],
                   help="change a parameter of the preset, e.g. BT=0.05 (repeatable)")
    s.add_argument("--from", dest="from_sweep", metavar="SWEEP.nc", default=None,
                   help="start from the state a sweep ('vibimpact classify' or "
                        "'bifurcation' file) had at --eta, with its parameters (see below)")
    s.add_argument("--direction", choices=("up", "down"), default=None,
                   help="with --from: the sweep direction to start from (needed when the "
                        "sweep has both)")
    s.add_argument("--periods", type=positive_int(1), default=200,
                   help="forcing periods recorded (default: 200)")
    s.add_argument("--transient", type=positive_int(0), default=500,
                   help="forcing periods integrated first and discarded (default: 500)")
    s.add_argument("--state0", type=number, nargs="+", metavar="X",
                   help="initial state at tau = 0, one value per state of the model "
                        "(default: rest, 0 0 0 0)")
    s.add_argument("--method", choices=("dop853", "dp5", "rk4"), default="dop853",
                   help="integrator (default: dop853)")
    s.add_argument("--rtol", type=positive_number, default=1e-9, help="relative "
                   "tolerance, > 0 (default: 1e-9)")
    s.add_argument("--atol", type=positive_number, default=1e-12, help="absolute "
                   "tolerance, > 0 (default: 1e-12)")
    s.add_argument("--dense", type=positive_int(0), default=None, metavar="N",
                   help="keep N evenly spaced samples per period (default: 0, or 64 with "
                        "--plot)")
    s.add_argument("-o", "--output", required=True, metavar="FILE.nc",
                   help="NetCDF file to write")
    s.add_argument("--plot", metavar="FILE.png", help="also draw the orbit in the (X, Y) "
                   "plane with the retainer and the impacts")
    add_figure_options(s, "the --plot image")
    s.add_argument("--overwrite", action="store_true",
                   help="replace existing output files")
    s.set_defaults(func=_cmd_simulate)

    from .attractors import add_parser as add_attractors
    from .basins import add_parser as add_basins
    from .continue_ import add_parser as add_continue
    from .continue2 import add_parser as add_continue2
    from .map import add_parser as add_map
    from .orbits import add_parser as add_orbits
    from .rerun import add_parser as add_rerun
    from .plot import add_parsers

    add_parsers(sub, fmt)
    add_map(sub, fmt)
    add_continue(sub, fmt)
    add_orbits(sub, fmt)
    add_basins(sub, fmt)
    add_continue2(sub, fmt)
    add_attractors(sub, fmt)
    add_rerun(sub, fmt, build_parser)
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
    stopped = None
    with Streams(program) as streams:  # a stream that cannot be written: a status
        try:
            status = _main(argv, program)
        except KeyboardInterrupt as exc:  # before the command's guard (reading options)
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
    processes die with it, PR_SET_PDEATHSIG).  The interpreter's own shutdown would join the process pool's
    manager thread, which blocks for good reading a result that a worker killed by the
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
        print("vibimpact: error: " + " ".join(str(exc).split()), file=sys.stderr)
        return 2
    except KeyboardInterrupt as exc:
        if not getattr(exc, "reported", False):  # a command may have said more already
            print("vibimpact: interrupted", file=sys.stderr)
        return interrupt_status(exc)
    finally:
        if program:  # the command is over, its files in place: a signal during the
            # interpreter's exit must not kill it silently (exit -15, no line)
            import signal

            for sig in (signal.SIGINT, signal.SIGTERM):
                signal.signal(sig, signal.SIG_IGN)


if __name__ == "__main__":
    sys.exit(main())
