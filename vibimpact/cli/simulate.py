"""``vibimpact simulate``: one run integrated and written as NetCDF (with ``--plot``, its
X-Y figure too).

Only the standard library and the command line's shared parts are imported at module
level; numpy, numba, xarray and matplotlib inside the command.
"""
from __future__ import annotations

import sys
from typing import TYPE_CHECKING

from .common.args import number, parse_sets, positive_int, positive_number, with_sets
from .common.errors import error_text, UsageError
from .common.figures import add_figure_options, figure_options
from .common.files import check_output, write_outputs
from .common.run_limits import check_run_limits
from ..base._text import count

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Callable

_SIMULATE_EPILOG = """\
examples:
  vibimpact simulate --preset fig8 --eta 1.25 --set BT=0.05 --periods 50 \\
      --transient 300 -o run.nc --plot xy.png
  vibimpact classify --eta 1.1:1.3:0.01 --direction both -o sweep.nc
  vibimpact simulate --from sweep.nc --eta 1.25 --direction up -o chaos.nc --plot chaos.png
  vibimpact simulate --from sweep.nc --eta 1.25 --direction up --set BT=0.01 -o near.nc

--from SWEEP.nc starts the run where the sweep left the motion at that grid value of
eta and direction (its final_state there), on the attractor the sweep followed: from
rest the motion may settle on another one (fig8 at eta 1.25: the sweep up from 1.1 is
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
    attrs, note = {"preset": presets.DEFAULT if args.preset is None else args.preset}, ""
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
                           method=args.method, rtol=args.rtol, atol=args.atol,
                           steps_per_period=args.steps_per_period))
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    elapsed = time.perf_counter() - start
    command = shlex.join(["vibimpact"] + list(args.argv))
    ds = run.to_dataset(command, attrs={**attrs, "wall_time_s": round(elapsed, 3)})
    writes: list[tuple[str, Callable[[], object]]] = [
        (out, lambda: io.write_netcdf(ds, out, overwrite=args.overwrite))]
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


def add_parser(sub, fmt):
    """Add ``simulate`` to the subparsers ``sub``."""
    s = sub.add_parser("simulate", help="integrate one run and write it as NetCDF",
                       description="Integrate a preset's model at one forcing frequency "
                                   "eta and write "
                                   "the run (stroboscopic\nsamples, impacts, parameters) "
                                   "to a NetCDF file.", epilog=_SIMULATE_EPILOG,
                       formatter_class=fmt)
    s.add_argument("--preset", default=None, help="parameter set (default: the one "
                   "'vibimpact presets' marks as the default); see 'vibimpact presets'")
    s.add_argument("--eta", type=number, default=None,
                   help="forcing frequency ratio, > 0 (default: the preset's, 1.0)")
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
                   help="initial state at t = 0, one value per state of the model "
                        "(default: rest, 0 0 0 0)")
    s.add_argument("--method", choices=("dop853", "dp5", "rk4", "rk4-fixed-noevents"),
                   default="dop853", help="integrator (default: dop853); "
                   "rk4-fixed-noevents: RK4 at a fixed step with the contact switch inside "
                   "the right-hand side and no event location, the integrator of a simple "
                   "code of the paper's time, to measure with")
    s.add_argument("--steps-per-period", type=positive_int(1), default=400, metavar="N",
                   help="steps per forcing period of the fixed-step methods (rk4, "
                        "rk4-fixed-noevents; default: 400)")
    s.add_argument("--rtol", type=positive_number, default=1e-9, help="relative "
                   "tolerance, > 0 (default: 1e-9)")
    s.add_argument("--atol", type=positive_number, default=1e-12, help="absolute "
                   "tolerance, > 0 (default: 1e-12)")
    s.add_argument("--dense", type=positive_int(0), default=None, metavar="N",
                   help="keep N evenly spaced samples per period (default: 0, or 64 with "
                        "--plot)")
    s.add_argument("-o", "--output", required=True, metavar="FILE.nc",
                   help="NetCDF file to write")
    s.add_argument("--plot", metavar="FILE.png", help="also draw the orbit in the plane "
                   "of the model's XY plot, with its obstacle and the impacts")
    add_figure_options(s, "the --plot image")
    s.add_argument("--overwrite", action="store_true",
                   help="replace existing output files")
    s.set_defaults(func=_cmd_simulate)
