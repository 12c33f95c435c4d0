"""The ``vibimpact basins`` command: the basins of attraction in a plane of states.

Like :mod:`vibimpact.cli`, only the standard library is imported at module level; the
work is :func:`vibimpact.census.basins.basins` (an attractor census over a grid of
starts) and the image :func:`vibimpact.plotting.basins.plot_basins`.
"""
import math
import os
import re

from ..base._text import parse_integer, parse_real
from .common.args import (CENSUS_FREQUENCY, CENSUS_PRESET, number, parse_sets,
                          positive_int, with_sets, MAX_WORKERS)
from .common.checkpoints import checkpoint_of
from .common.errors import error_text, UsageError
from .common.figures import add_figure_options

_EPILOG = """\
examples:
  vibimpact basins --preset fig11 --eta 1.06 --grid 200x200 --plane X,Y -o basins.nc \\
      --plot basins.png --workers 2
  vibimpact basins --preset fig11 --eta 1.06 --grid 40x40 --plane X,X' \\
      --range -1:1,-0.5:0.5 -o xdx.nc
  vibimpact basins --preset fig11 --eta 1.06 --grid 100x100 --base 0,0,0.1,0 -o b.nc

Every cell of a COLUMNSxROWS grid in the plane of two states (--plane: state names of
the model, X' standing for dX; the first along the columns, the second along the rows)
is a starting state, the other states at --base (zero by default: X, Y at rest).  The
cell centres span --range (LO:HI of each plane variable; default: the census box, -1:1
for each state of a model with a planar contact).  All cells are one attractor census ('vibimpact
attractors'): each start is integrated until it enters an attractor already found, or
else the settling evidence of a sweep point decides.

Printed: the attractor table (index, name, basin fraction with its standard error) and
the boundary measures: the share of boundary cells (a neighbour up, down, left or right
with another attractor), the basin entropy Sb and the boundary basin entropy Sbb of
Daza et al., Sci. Rep. 6, 31416 (2016), from boxes of --eps x --eps cells; Sbb > log 2
is sufficient for a fractal boundary.

The NetCDF file holds basin (row, column) with the plane variables as coordinates,
boundary, periods and decided_by per cell, the attractor table (name, fraction,
fraction_se, period, impacts_per_period, samples, ...) and the measures.  The census is
checkpointed in OUT.partial (or --checkpoint DIR) as it goes; after Ctrl-C or a kill,
run the same command with --resume.  Serial, parallel and resumed runs give the same
numbers.

exit status: 0 written, 2 bad input (nothing written), 130 interrupted (Ctrl-C), 143
terminated (SIGTERM); the checkpoint is kept for --resume.
"""


def parse_grid(text):
    """``"200x200"`` (columns x rows) or ``"200"`` -> ``(columns, rows)``; UsageError."""
    parts = str(text).lower().replace("×", "x").split("x")
    try:
        values = [parse_integer(p) for p in parts]
    except ValueError:
        values = []
    if len(parts) == 1 and values:
        values = values * 2
    if len(values) != 2 or min(values) < 2:
        raise UsageError(f"--grid expects COLUMNSxROWS with counts >= 2, e.g. 200x200, "
                         f"got {text!r}")
    return tuple(values)


def parse_ranges(text):
    """``"LO:HI,LO:HI"`` -> ``((lo, hi), (lo, hi))``; UsageError naming --range."""
    out = []
    for part in str(text).split(","):
        lo, sep, hi = part.partition(":")
        try:
            a, b = parse_real(lo), parse_real(hi)
        except ValueError:
            a = b = math.nan
        if not sep or not (math.isfinite(a) and math.isfinite(b) and a < b
                           and math.isfinite(b - a)):
            raise UsageError(f"--range expects LO:HI,LO:HI with finite LO < HI (and a "
                             f"finite HI - LO), one per plane variable, got {text!r}")
        out.append((a, b))
    if len(out) != 2:
        raise UsageError(f"--range expects two ranges LO:HI,LO:HI, got {text!r}")
    return tuple(out)


def _inputs(args):
    """``(system, eta, axes names, ranges, base, grid)``; UsageError for bad input."""
    from ..models import presets
    from ..census.basins import default_plane, plane_axes
    from ..core.system import System

    try:
        base = presets.get(args.preset)
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    system = System(with_sets(base, parse_sets(args.set), args.eta))
    plane = ([p.strip() for p in str(args.plane).split(",")] if args.plane is not None
             else list(default_plane(system.model)))
    try:
        plane_axes(system.model, plane)
    except ValueError as exc:
        raise UsageError(f"--plane: {error_text(exc)}") from None
    ranges = parse_ranges(args.range) if args.range is not None else None
    state = None
    if args.base is not None:
        try:
            state = [parse_real(v) for v in args.base.split(",")]
        except ValueError:
            state = []
        if len(state) != system.n_state or not all(math.isfinite(v) for v in state):
            raise UsageError(f"--base expects {system.n_state} finite numbers "
                             f"({','.join(system.model.state_names)}), got {args.base!r}")
    grid = parse_grid(args.grid)
    for (lo, hi), cells, name in zip(ranges or (), grid, plane):
        if (hi - lo) / (cells - 1) < 4.0 * max(math.ulp(lo), math.ulp(hi)):
            raise UsageError(f"--range {lo!r}:{hi!r} of {name} is too narrow for "
                             f"{cells} cells: their centres would coincide in floats")
    if min(grid) < args.eps:
        raise UsageError(f"--grid {args.grid} is smaller than the entropy's boxes "
                         f"(--eps {args.eps})")
    return system, plane, ranges, state, grid


def summary(ds):
    """The printed lines: the attractor table (largest basin first) and the measures."""
    rows = sorted(range(ds.sizes["attractor"]), key=lambda a: -float(ds.fraction[a]))
    cells = ds.sizes["row"] * ds.sizes["column"]
    skipped = int(ds.not_started) if "not_started" in ds else 0
    started = f" ({cells - skipped} started: {skipped} in penetration of the contact " \
              "are not)" if skipped else ""
    lines = [f"{ds.attrs.get('plane')} plane, {ds.sizes['column']} x {ds.sizes['row']} = "
             f"{cells} cells{started}, {ds.sizes['attractor']} attractor"
             f"{'' if ds.sizes['attractor'] == 1 else 's'}:"]
    for a in rows:
        f, se = float(ds.fraction[a]), float(ds.fraction_se[a])
        name = f"A{int(ds.global_id.values[a])}" if "global_id" in ds else f"{a:3d}"
        lines.append(f"  {name:<4s} {f:6.3f} +- {se:.3f}  {ds.name.values[a]}")
    if "failed" in ds and int(ds.failed):
        lines.append(f"   --  {float(ds.failed_fraction):6.3f}           integration "
                     "failed (on no attractor)")
    sbb = float(ds.boundary_basin_entropy)
    lines.append(f"boundary cells {float(ds.boundary_fraction):.4f}; basin entropy Sb "
                 f"{float(ds.basin_entropy):.4f}; boundary basin entropy Sbb "
                 + (f"{sbb:.4f}" if math.isfinite(sbb) else "n/a (one basin)")
                 + f" (boxes of {ds.attrs.get('entropy_eps')}x{ds.attrs.get('entropy_eps')}"
                 f" cells, {int(ds.boundary_boxes)} of {int(ds.boxes)} on the boundary)")
    lines.append("fractal boundary by the log 2 criterion (Sbb > log 2 = 0.6931): "
                 + ("yes" if bool(ds.fractal_by_log2) else "not shown (the criterion is "
                    "sufficient, not necessary)"))
    return lines


def _census_file(args, system):
    """The --census file (None without one), checked before any work: a census of the
    basins' model that holds the basins' eta."""
    if args.census is None:
        return None
    import numpy as np

    from .common.files import read_input

    ds = read_input(os.fspath(args.census), "--census")
    if ds.attrs.get("kind") != "census":
        raise UsageError(f"--census {os.fspath(args.census)!r} is not an attractor census "
                         "('vibimpact attractors')")
    if ds.attrs.get("model") != system.model.name:
        raise UsageError(f"--census {os.fspath(args.census)!r} is a census of the "
                         f"{ds.attrs.get('model')} model, not of {system.model.name}")
    if not np.any(np.round(ds.eta.values.astype(float), 12) == round(system.omega, 12)):
        raise UsageError(f"--census {os.fspath(args.census)!r} holds no point at eta = "
                         f"{system.omega:g}")
    return ds


def _cmd_basins(args):
    from .common.census_steps import check_outputs, draw, run_and_write
    from ..engine.store import Checkpoint

    out = os.fspath(args.output)
    system, plane, ranges, state, grid = _inputs(args)
    ckpt = Checkpoint(args.checkpoint) if args.checkpoint is not None else \
        checkpoint_of(out)
    resuming, fig_kw = check_outputs(args, out, ckpt)

    from ..census.basins import basins, write_basins
    from ..census.locate import name_after

    census = _census_file(args, system)

    ds, status, elapsed = run_and_write(
        args, out, ckpt, resuming, "basins", lambda run: basins(
            system, None, grid=grid, plane=plane, ranges=ranges, base=state,
            eps=args.eps, everywhere=args.everywhere, execution=run)
        if census is None else name_after(basins(
            system, None, grid=grid, plane=plane, ranges=ranges, base=state,
            eps=args.eps, everywhere=args.everywhere, execution=run), census),
        write_basins)
    if ds is None:
        return status
    print("\n".join(summary(ds)))
    print(f"wrote {out} ({grid[0]} x {grid[1]} cells in {elapsed:.1f} s)")
    from ..plotting.basins import plot_basins

    draw(args, ds, out, plot_basins, fig_kw)
    return 0


def add_parser(sub, fmt):
    """Add ``basins`` to the subparsers ``sub``."""
    b = sub.add_parser("basins", help="basins of attraction in a plane of states, with "
                       "the basin entropy", formatter_class=fmt, epilog=_EPILOG,
                       description="Find the attractor every cell of a grid of starting "
                                   "states reaches (an attractor census);\nwrite the "
                                   "basin image as NetCDF and print the attractors and "
                                   "the boundary measures.")
    # values that start with a minus and a digit are values, not options: --range
    # -1:1,-1:1 and --base -0.1,0,0,0 as the examples write them (argparse takes only
    # plain negative numbers so)
    b._negative_number_matcher = re.compile(r"^-\.?\d")
    b.add_argument("--preset", default=CENSUS_PRESET,
                   help=f"parameter set (default: {CENSUS_PRESET})")
    b.add_argument("--set", action="append", metavar="NAME=VALUE", default=[],
                   help="change a parameter of the preset, e.g. B=0.01 (repeatable)")
    b.add_argument("--eta", type=number, default=CENSUS_FREQUENCY,
                   help=f"forcing frequency (default: {CENSUS_FREQUENCY})")
    b.add_argument("--grid", default="200x200", metavar="COLUMNSxROWS",
                   help="cells along the first and second plane variable (default: "
                        "200x200)")
    b.add_argument("--plane", default=None, metavar="A,B",
                   help="two state names of the model, e.g. X,Y or X,X' (X' is dX; "
                        "default: the states the model's XY plots draw)")
    b.add_argument("--range", default=None, metavar="LO:HI,LO:HI",
                   help="the span of the cell centres of each plane variable (default: "
                        "the census box, -1:1 each)")
    b.add_argument("--base", default=None, metavar="V1,V2,...",
                   help="the whole state the plane's two values replace (default: 0: at "
                        "rest)")
    b.add_argument("--everywhere", action="store_true",
                   help="start every cell (default: a cell whose start is in penetration "
                        "of the model's contact is not started, as a start outside a "
                        "retainer's clearance)")
    b.add_argument("--eps", type=positive_int(1, 1000), default=5, metavar="N",
                   help="box side of the basin entropy in cells (default: 5)")
    b.add_argument("--workers", type=positive_int(1, MAX_WORKERS), default=1, metavar="N",
                   help="local processes (default: 1); never changes a number")
    b.add_argument("--census", default=None, metavar="CENSUS.nc",
                   help="name the attractors as this census ('vibimpact attractors' at "
                        "the same eta) does: the same A<id> and colour")
    b.add_argument("-o", "--output", default="basins.nc", metavar="OUT.nc",
                   help="NetCDF file to write (default: basins.nc)")
    b.add_argument("--plot", default=None, metavar="IMAGE",
                   help="also draw the basin image (one colour per attractor)")
    add_figure_options(b, "the --plot image")
    b.add_argument("--checkpoint", default=None, metavar="DIR",
                   help="checkpoint directory (default: OUT.partial)")
    b.add_argument("--resume", action="store_true",
                   help="continue an interrupted run from its checkpoint")
    b.add_argument("--keep-checkpoint", action="store_true",
                   help="keep the checkpoint after the file is written")
    b.add_argument("--no-progress", action="store_true", help="no progress bar")
    b.add_argument("--overwrite", action="store_true", help="replace existing files")
    b.set_defaults(func=_cmd_basins)


__all__ = ["add_parser", "parse_grid", "parse_ranges", "summary"]
