"""``vibimpact orbits``: hunt the periodic orbits of the stroboscopic map, stable or not,
and continue each to where it exists and is stable.

Like :mod:`vibimpact.cli`, only the standard library is imported at module level; the
work is :func:`vibimpact.orbits.hunt_orbits`, the file
:func:`vibimpact.orbits.hunt_to_dataset`, the figure
:func:`vibimpact.plotting.orbits.plot_orbits`.
"""
import os
import sys

from ..base._text import parse_integer
from .common.args import (DEFAULT_PRESET, DEFAULT_PRESET_HELP, number, parse_sets, positive_int,
                          preset_name, MAX_WORKERS)
from .common.errors import error_text, UsageError
from .common.figures import add_figure_options
from .common.files import read_input

_ORBITS_EPILOG = """\
examples:
  vibimpact orbits --preset fig11 --eta 1.06 --period 1:16 -o orbits.nc
  vibimpact orbits --preset fig11 --eta 1.06 --period 6,8,14 --random 100 --seed 3 \\
      --window 0.02 -o orbits.nc --plot orbits.png
  vibimpact orbits --preset soft-impact --period 1:3 --no-continue -o s.nc
  vibimpact orbits --preset fig11 --eta 1.06 --seeds census.nc -o orbits.nc
  vibimpact orbits --preset fig11 --eta 1.06 --period 1:8 --workers 2 -o o.nc --resume

Seeds: the states of --seeds FILE.nc (every variable whose last dimension is 'state': a
census's representatives, a sweep's final_state, a run's strobe; each is itself a Newton
start, then the points of its trajectory) and --random states drawn with the generator
seeded by --seed in a box (a planar contact's two positions uniform in the unit disk,
their velocities in [-1, 1]; another model: [-1, 1] for every state variable).  From
each seed the motion is integrated a few forcing periods; for each period N its closest
returns after N periods start Newton shooting for the period-N orbit (variational
equations with saltation matrices).  Orbits met at another phase of their cycle, or of a
lower period than shot for, are one orbit.  Each orbit gets its minimal period, impacts per period,
contact arcs and Floquet multipliers (stable: every |mu| < 1), and is continued in the
forcing frequency both ways within --window of --eta: where it exists (up to a fold, a
period doubling onto the orbit it doubled, or where the continuation stops, with the
reason) and where it is stable.

The NetCDF file holds per orbit: period, impacts_per_period, n_arcs, arcs, stable,
label, orbit_point (its cycle), floquet_real, floquet_imag, exists_lo, exists_hi and
their reasons, stable_lo, stable_hi, same_impacts_lo/hi, and its branch (branch_eta,
branch_stable, branch_impacts, branch_abs_max); the seeds; every parameter, the solver
settings and the command line.  --plot draws each orbit's interval as a bar against
eta: solid where stable, dashed where unstable.

exit status: 0 written, 2 bad input (nothing written).
"""


def parse_periods(text):
    """``"1:16"``, ``"6"`` or ``"6,8,14"`` -> a sorted tuple of ints; UsageError
    naming ``--period``."""
    from ..orbits.hunt import MAX_PERIOD

    out: set[int] = set()
    for part in str(text).split(","):
        a, sep, b = part.strip().partition(":")
        try:
            lo = parse_integer(a)
            hi = parse_integer(b) if sep else lo
        except ValueError:
            raise UsageError(f"--period expects N, A:B or a comma list, got {text!r}") \
                from None
        if not 1 <= lo <= hi <= MAX_PERIOD:
            raise UsageError(f"--period: periods from 1 to {MAX_PERIOD}, low <= high, got "
                             f"{text!r}")
        out.update(range(lo, hi + 1))
    return tuple(sorted(out))


def _system(args):
    """The System of the parsed arguments; UsageError for bad input."""
    from ..models import presets
    from .common.args import with_sets
    from ..core.system import System

    try:
        base = presets.get(args.preset)
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    return System(with_sets(base, parse_sets(args.set), args.eta))


def _seeds(args, system):
    """``(seeds, dataset)`` of --seeds (``(None, None)`` without one)."""
    if args.seeds is None:
        return None, None
    from ..orbits import seeds_from_dataset

    ds = read_input(os.fspath(args.seeds), "--seeds")
    try:
        return seeds_from_dataset(ds, system.n_state), ds
    except ValueError as exc:
        text = error_text(exc)  # the API names its argument ds: here it is the file
        text = text[len("ds "):] if text.startswith("ds ") else text
        raise UsageError(f"--seeds {args.seeds!r} {text}") from None


def _cmd_orbits(args):
    from .common.checkpoints import checkpoint_of
    from .common.census_steps import check_outputs, draw, run_and_write

    out = os.fspath(args.output)
    ckpt = checkpoint_of(out)
    resuming, opts = check_outputs(args, out, ckpt, inputs=(("--seeds", args.seeds),))
    periods = parse_periods(args.period)
    if not args.window > 0:
        raise UsageError(f"--window must be a finite number > 0, got {args.window:g}")
    system = _system(args)
    seeds, seeds_ds = _seeds(args, system)

    from ..orbits import hunt_orbits, hunt_to_dataset, write_orbits

    hunts = []
    # a census as --seeds names the orbits after its attractors
    census = seeds_ds if seeds_ds is not None and seeds_ds.attrs.get("kind") == "census" \
        else None

    def compute(run):
        hunt = hunt_orbits(system, periods, seeds=seeds, random=args.random,
                           seed=args.seed, transient=args.transient,
                           continuation=not args.no_continue,
                           window=args.window, execution=run)
        hunts.append(hunt)
        ds = hunt_to_dataset(hunt, system)
        if census is not None:  # the census' names, stored in the file
            from ..census.locate import orbits_named_after

            ds = orbits_named_after(ds, census) or ds
        return ds

    ds, status, elapsed = run_and_write(args, out, ckpt, resuming, "orbits", compute,
                                        write_orbits)
    if ds is None:
        return status
    hunt = hunts[0]
    print("\n".join(hunt.table()))
    if hunt.failed_note() is not None:  # written, said, exit 0 (as a census)
        print(f"vibimpact: warning: {hunt.failed_note()}", file=sys.stderr)
    print("\n".join(_name_lines(ds, census, args.seeds)))
    print(f"wrote {out} ({elapsed:.1f} s: hunt {hunt.timings['hunt_s']:.1f} s, "
          f"continuation {hunt.timings['continuation_s']:.1f} s)")
    from ..plotting.orbits import plot_orbits

    draw(args, ds, out, plot_orbits, opts)
    return 0


def _name_lines(ds, census, seeds):
    """Lines giving each stable orbit its attractor's name in the ``census`` of --seeds
    (``A<id>``) and naming those no start of it reached at the hunt's eta (none when
    --seeds is no census or holds no point there)."""
    if census is None or "global_id" not in ds:
        return []
    known = {int(g) for g in ds.attrs["census_ids"]}
    eta = float(ds.attrs["forcing_value"])
    names = [f"orbit {o} ({ds.label.values[o]}) is A{int(g)} of the census" for o, g in
             enumerate(ds.global_id.values) if int(g) in known]
    missed = [(o, str(ds.label.values[o])) for o, g in enumerate(ds.global_id.values)
              if int(g) >= 0 and int(g) not in known]
    i = int(abs(census.eta.values - eta).argmin())
    unseen = (f" (the census says up to {float(census.unseen.values[i]):.3g} of its "
              "basin may be unseen)" if "unseen" in census else "")
    if not missed:
        return names + [f"every stable orbit is an attractor of the census "
                        f"{os.fspath(seeds)!r}"]
    return names + [f"orbit {o} ({label}) is stable, but no start of the census "
                    f"{os.fspath(seeds)!r} reached it at eta = {eta:g}{unseen}: more "
                    f"starts, or 'vibimpact basins' for where its basin lies (named "
                    f"A{int(ds.global_id.values[o])} here)" for o, label in missed]


#: the API's default random seeds (:data:`vibimpact.orbits.hunt.DEFAULT_RANDOM`), here
#: so that building the parser imports nothing heavy
DEFAULT_RANDOM = 48


def add_parser(sub, fmt):
    """Add ``orbits`` to the subparsers ``sub``."""
    c = sub.add_parser("orbits", help="hunt periodic orbits, stable or not, and where "
                       "each exists", formatter_class=fmt, epilog=_ORBITS_EPILOG,
                       description="Find periodic orbits of the stroboscopic map by "
                                   "multi-start Newton shooting,\nwith their impacts, "
                                   "arcs and Floquet multipliers; continue each in the\n"
                                   "forcing frequency; write a NetCDF file and print a "
                                   "table.")
    c.add_argument("--preset", default=DEFAULT_PRESET, type=preset_name,
                   help=f"parameter set (default: {DEFAULT_PRESET_HELP}); see "
                        "'vibimpact presets'")
    c.add_argument("--set", action="append", metavar="NAME=VALUE", default=[],
                   help="change a parameter of the preset (repeatable)")
    c.add_argument("--eta", type=number, default=None,
                   help="forcing frequency eta of the hunt (default: the preset's)")
    c.add_argument("--period", default="1:16", metavar="N|A:B|LIST",
                   help="periods to shoot for (default: 1:16)")
    c.add_argument("--seeds", default=None, metavar="FILE.nc",
                   help="NetCDF file whose states seed the hunt")
    c.add_argument("--random", type=positive_int(0), default=DEFAULT_RANDOM, metavar="N",
                   help=f"random seed states (default: {DEFAULT_RANDOM})")
    c.add_argument("--seed", type=positive_int(0), default=0, metavar="S",
                   help="seed of the random generator (default: 0)")
    c.add_argument("--transient", type=positive_int(0, 100_000), default=5, metavar="N",
                   help="forcing periods each seed is integrated before Newton's method "
                        "(default: 5; more for a slowly settling state)")
    c.add_argument("--window", type=number, default=0.05, metavar="W",
                   help="continue each orbit within +-W of --eta (default: 0.05)")
    c.add_argument("--no-continue", action="store_true",
                   help="do not continue the orbits (no intervals)")
    c.add_argument("-o", "--output", default="orbits.nc", metavar="OUT.nc",
                   help="NetCDF file to write (default: orbits.nc)")
    c.add_argument("--plot", default=None, metavar="FILE.png",
                   help="also draw each orbit's interval against eta")
    add_figure_options(c, "the --plot image")
    c.add_argument("--workers", type=positive_int(1, MAX_WORKERS), default=1, metavar="N",
                   help="local processes continuing the orbits (default: 1); never "
                        "changes a number")
    c.add_argument("--resume", action="store_true",
                   help="continue an interrupted run from its checkpoint OUT.partial (the "
                        "orbits already continued are loaded)")
    c.add_argument("--keep-checkpoint", action="store_true",
                   help="keep OUT.partial after the file is written")
    c.add_argument("--no-progress", action="store_true", help="no progress bar")
    c.add_argument("--overwrite", action="store_true", help="replace existing files")
    c.set_defaults(func=_cmd_orbits)


__all__ = ["add_parser", "parse_periods", "DEFAULT_RANDOM"]
