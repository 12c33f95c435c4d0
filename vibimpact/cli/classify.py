"""``vibimpact classify``: sweep eta with continuation, classify every point, write the
dataset and print the labelled intervals.

Only the standard library and the command line's shared parts are imported at module
level; numpy, numba, xarray and matplotlib inside the command.
"""
import os

from .common.args import parse_analyses
from .common.checkpoints import (check_checkpoint, checkpoint_of, finish_checkpointed,
                                 run_checkpointed)
from .common.files import check_output, sweep_file_bytes
from .common.sweeps import add_sweep_options, command_line, sweep_inputs
from ..engine.leftovers import output_of

_CLASSIFY_EPILOG = """\
examples:
  vibimpact classify --eta 0.9:1.5:0.002 -o fig8.nc
  vibimpact classify --eta 1.0:1.3:0.005 --preset fig10 --set BT=0.07 \\
      --direction both --analyses period,impacts,response -o fig10.nc

Every point starts from the previous point's final state (continuation) inside each of
--blocks blocks (16 by default), so jumps and hysteresis show as in the paper; every
block but the first starts from a short seeding pass, and --blocks 1 is one unbroken
continuation.  --workers processes compute the blocks at once.  The result depends on
--blocks, never on --workers.

Each finished point is saved at once in the checkpoint directory OUT.partial.  After
Ctrl-C (exit status 130), SIGTERM (143), a worker process killed (2) or a crash, run the
same command again with --resume: the saved points are loaded, not recomputed, and the
file is the one an uninterrupted run writes (on the same CPU type with the same versions:
see the reproducibility page of the docs).
The checkpoint is removed once OUT is written.

Labels need evidence: periodic a period found (or an orbit found by Newton shooting
from a slowly settling transient and confirmed by integration), chaotic a positive
exponent beyond its error, quasi-periodic a zero exponent, a regular 0-1 test and
Poincare points that neither contract nor stop recurring; what no test decides within
the transient budget is "unsettled" (its contraction rate and the periods it would
still need are stored).  This keeps labels right at the very low damping of passive
magnetic bearings, where transients decay over thousands of periods.

The NetCDF file holds per eta (and direction): regime (flag), label, period,
impacts_per_period, lyapunov, lyapunov_err, k01, floquet_exponent, contraction,
settle_periods, shoot_residual, X_m, Y_m, R_m, min_gap, arcs, poincare_X, poincare_Y,
...; every parameter and the command line as attributes.  The interval table
(consecutive points with the same label) is printed on stdout.

exit status: 0 written, 2 bad input (nothing computed) or a worker process died
(checkpoint kept), 130 interrupted (Ctrl-C), 143 terminated (SIGTERM).
"""


def _cmd_classify(args):
    out = os.fspath(args.output)
    etas, params = sweep_inputs(args)
    analyses = parse_analyses(args.analyses)
    ckpt = checkpoint_of(out)
    resuming = args.resume and ckpt.exists()
    resumable = not getattr(args, "rerun_of", None)  # rerun has no --resume
    # an existing output is replaced with --overwrite, or by --resume if it was written
    # from this checkpoint (kept, or its run killed before removing it); never otherwise
    check_output(out, args.overwrite or (resuming and output_of(ckpt, out)), "output file",
                 size=sweep_file_bytes(params, etas.size, args.direction))
    check_checkpoint(ckpt, args.resume)

    import vibimpact as vi
    from .. import io
    from ..sweeps import format_intervals

    run = vi.Execution(workers=args.workers, checkpoint=ckpt.path, resume=args.resume,
                       progress=not args.no_progress and "classify")
    ds, status = run_checkpointed(ckpt, "points", lambda: vi.sweep(
        params, etas, direction=args.direction, analyses=analyses,
        continuation=vi.Continuation(blocks=args.blocks), execution=run),
        resumable=resumable)
    if ds is None:
        return status
    ds.attrs.update(command=command_line(args), preset=args.preset, eta_range=args.eta)
    finish_checkpointed(ds, out, ckpt, io.write_netcdf, resuming=resuming,
                        keep=args.keep_checkpoint, overwrite=args.overwrite, unit="points",
                        resumable=resumable)
    print(format_intervals(vi.intervals(ds)))
    print(f"wrote {out}")
    return 0


def add_parser(sub, fmt):
    """Add ``classify`` to the subparsers ``sub``."""
    c = sub.add_parser("classify", help="sweep eta, classify every point, print the "
                       "intervals", formatter_class=fmt, epilog=_CLASSIFY_EPILOG,
                       description="Sweep the forcing frequency eta with continuation, "
                                   "classify the motion at every point\n(period, impacts, "
                                   "Lyapunov exponent, 0-1 test, Floquet multipliers), "
                                   "write a NetCDF file and "
                                   "print the\nlabelled frequency intervals.")
    add_sweep_options(c, "up")
    c.add_argument("--analyses", default="all", metavar="A,B,...",
                   help="what to compute: comma-separated subset of period, impacts, "
                        "response, poincare, lyapunov, test01, floquet (Floquet "
                        "multipliers of periodic points by shooting) (default: all; "
                        "period always runs)")
    c.add_argument("-o", "--output", default="classify.nc", metavar="OUT.nc",
                   help="NetCDF file to write (default: classify.nc)")
    c.add_argument("--resume", action="store_true",
                   help="continue an interrupted run from its checkpoint OUT.partial")
    c.add_argument("--keep-checkpoint", action="store_true",
                   help="keep OUT.partial after OUT is written")
    c.set_defaults(func=_cmd_classify)
