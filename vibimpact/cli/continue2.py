"""``vibimpact continue2``: follow a fold, period doubling or grazing of a periodic orbit
in two parameters (:func:`vibimpact.analysis.continue_bifurcation`), write the curve
(:func:`vibimpact.continuation.curves.curve_to_dataset`) and draw it, over a regime map when given
(:func:`vibimpact.plotting.bifurcation_curves.plot_bifurcation_curves`).

Like :mod:`vibimpact.cli`, only the standard library is imported at module level.
"""
import math
import os
import shlex
import time

from ..base._text import parse_real
from .common.args import (DEFAULT_PRESET, DEFAULT_PRESET_HELP, number, parse_sets,
                          positive_int, preset_name, with_sets)
from .common.errors import UsageError, error_text, reason
from .common.files import check_output, read_input, write_outputs
from .common.figures import add_figure_options, figure_options, image_ext_ok
from .common.inputs import check_distinct, check_state0

_EPILOG = """\
examples:
  vibimpact continue2 --preset fig8 --eta 1.12 --approach 1.1 --stop1 1.25 \\
      --kind grazing --param2 kh --range2 110:130 -o graze.nc --plot graze.png
  vibimpact continue2 --preset soft-impact --eta 0.83 --kind grazing --param2 A \\
      --range2 0.25:0.35 -o soft.nc
  vibimpact map --preset soft-impact --eta 0.8:0.88:0.01 --vary A=0.28:0.34:0.02 -o m.nc
  vibimpact continue2 --preset soft-impact --eta 0.83 --kind grazing --param2 A \\
      --range2 0.27:0.35 -o soft.nc --over m.nc --plot soft.png --overwrite

The start: as 'vibimpact continue', the motion is integrated --transient periods from
rest (or --state0) at the start, or eta is stepped from --approach to --eta.  With
--stop1 the period-N orbit is then continued in --param1 towards --stop1, and the first
bifurcation of --kind on that branch seeds the curve (the robust start); without it the
start value of --param1 is taken as a guess of the bifurcation.  At every value of
--param2 in --range2 (a window holding its start value, followed both ways) the
bifurcation is located in --param1: a fold or period doubling by Newton's method on the
orbit's equations with det(M -+ I) = 0, a grazing by a root search of the orbit's signed
gap to the contact surface.  The curve must be a graph over --param2; it ends where the
location fails (the printed status says where).

The NetCDF file holds per curve point (dimension point): both parameters (coordinates),
orbit_state, floquet_real, floquet_imag, test_function, impacts_per_period; the scalar
bifurcation_kind; every parameter, the solver settings and the command line.
--over MAP.nc (a 'vibimpact map' file over eta and --param2) draws the curve over its
regime cells.

exit status: 0 written, 2 bad input or no bifurcation found at the start (nothing
written).
"""

_SEED_KINDS = {"fold": ("fold", "fold (turning point)"),
               "period doubling": ("period doubling",), "grazing": ("grazing",)}


def _range(text):
    parts = text.split(":")
    if len(parts) != 2:
        raise UsageError(f"--range2 must be LO:HI, got {text!r}")
    try:
        lo, hi = (parse_real(p) for p in parts)
    except ValueError:
        raise UsageError(f"--range2 must be two numbers LO:HI, got {text!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo >= hi:
        raise UsageError(f"--range2 must be finite with LO < HI, got {text!r}")
    return lo, hi


def _inputs(args):
    """``(System, kind, window)``; UsageError for bad input."""
    from ..base import _limits
    from ..models import presets
    from ..analysis.two_parameter import curve_kind
    from ..core.system import System

    try:
        base = presets.get(args.preset)
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    system = System(with_sets(base, parse_sets(args.set), args.eta))
    if args.param1 is None:  # the model's forcing frequency, what --eta sets
        args.param1 = system.model.frequency_name
    for flag, name in (("--param1", args.param1), ("--param2", args.param2)):
        try:
            system.param(name)
        except ValueError:
            raise UsageError(f"{flag}: unknown parameter {name!r}; choose from "
                             f"{', '.join(system.model.param_names)}") from None
    if args.param1 == args.param2:
        raise UsageError("--param2 must differ from --param1")
    try:
        kind = curve_kind(args.kind)
    except ValueError as exc:
        raise UsageError(f"--{error_text(exc)}") from None
    lo, hi = _range(args.range2)
    domain = system.param_domain(args.param2)
    for end in (lo, hi):  # the curve may end on a bound of the domain, not beyond it
        if end not in domain:
            raise UsageError(f"--range2: {domain.rule(args.param2)}, got {end!r}")
    start = system.param(args.param2)
    if not lo <= start <= hi:
        raise UsageError(f"--range2 {lo:g}:{hi:g} must hold the start value "
                         f"{args.param2} = {start:g}")
    for name in ("stop1", "approach", "step"):
        value = getattr(args, name)
        if value is not None and not math.isfinite(value):
            raise UsageError(f"--{name} must be finite, got {value:g}")
    if args.approach is not None and not args.approach > 0:
        raise UsageError(f"--approach must be a value of eta > 0, got {args.approach:g}")
    if args.stop1 is not None:
        _check_stop1(args, system)
    check_state0(args.state0, system)
    if args.step is not None:
        _check_step(args, start, lo, hi)
    if args.transient > _limits.MAX_PERIODS:
        raise UsageError(f"--transient: at most {_limits.MAX_PERIODS} forcing periods, "
                         f"got {args.transient}")
    return system, kind, (lo, hi)


def _check_stop1(args, system):
    """UsageError unless ``--stop1`` differs from the start value of ``--param1`` and lies
    in its domain (as ``vibimpact continue --stop``)."""
    start = system.param(args.param1)
    if args.stop1 == start:
        raise UsageError(f"--stop1 must differ from the start value {args.param1} = "
                         f"{start:g}")
    domain = system.param_domain(args.param1)
    if args.stop1 not in domain:
        raise UsageError(f"--stop1: {domain.rule(args.param1)}, got {args.stop1!r}")


def _check_over(over, path, args):
    """UsageError, before any work, unless ``--over`` is a map over eta and the curve's
    other parameter that can be drawn (drawn once into a figure that is thrown away)."""
    from ..plotting.bifurcation_curves import check_over

    try:
        check_over(over, (args.param1, args.param2))
    except Exception as exc:  # a foreign or damaged map can fail anywhere in drawing
        raise UsageError(f"--over {path!r}: {reason(exc)}") from None


def _check_step(args, start, lo, hi):
    """UsageError when ``--step``, or the smallest step the curve halves it to (a 64th),
    is below the float resolution of ``--param2`` over ``--range2``
    (:data:`vibimpact.analysis.continuation.STEP_ULPS` units in the last place)."""
    import numpy as np

    from ..analysis.continuation import STEP_ULPS

    if args.step <= 0.0:
        raise UsageError(f"--step must be > 0, got {args.step:g}")
    if args.step > hi - lo:
        raise UsageError(f"--step {args.step:g} is larger than the window --range2 "
                         f"{lo:g}:{hi:g} (its first step would leave it)")
    big = max(abs(start), abs(lo), abs(hi))
    floor = 64.0 * STEP_ULPS * float(np.spacing(big))
    if args.step < floor:
        raise UsageError(f"--step must be >= {floor:.3g} (a 64th of it, the smallest step "
                         f"the curve takes, must be resolvable at {args.param2} = "
                         f"{big:g} in floats), got {args.step:.3g}")


def _seed(args, system, kind):
    """``(system at the seed, state)``: the start of the curve (see the epilog)."""
    import numpy as np

    from ..analysis import StartFailed, shoot_periodic_orbit
    from ..continuation.branches import follow_branch

    if args.stop1 is None:
        if args.approach is not None:
            from ..sweeps import continued_state

            x = continued_state(system.params, system.omega, eta_start=args.approach,
                                transient=args.transient, state0=args.state0)
        else:
            x = system.simulate(periods=1, transient=args.transient,
                                state0=args.state0).final_state
        orb = shoot_periodic_orbit(system, x, args.period)
        return system, orb.state if orb.converged else np.asarray(x)
    try:
        branch, _ = follow_branch(system, stop=args.stop1, param=args.param1,
                                  n=args.period, state0=args.state0,
                                  transient=args.transient, approach=args.approach)
    except StartFailed as exc:
        raise UsageError(f"no period-{args.period} orbit found at the start: Newton "
                         f"shooting failed ({exc.reason}); try --approach, a longer "
                         "--transient or --state0") from None
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    for i, found, value in branch.bifurcations:
        if found.value in _SEED_KINDS[kind.value]:
            j = i if found.value == "fold (turning point)" else i - 1
            v = value if kind.value == "period doubling" else float(branch.values[j])
            return system.with_param(args.param1, v), branch.states[j]
    raise UsageError(f"no {kind.value} on the period-{args.period} branch from "
                     f"{args.param1} = {system.param(args.param1):g} to {args.stop1:g}")


def _cmd_continue2(args):
    out = check_output(os.fspath(args.output), args.overwrite, "output file")
    if args.plot:
        image_ext_ok(args.plot, "--plot")
        check_output(args.plot, args.overwrite, "image file")
    elif args.over:
        raise UsageError("--over draws under --plot: give --plot FILE.png too")
    check_distinct(("-o", out), ("--plot", args.plot), inputs=(("--over", args.over),))
    system, kind, window = _inputs(args)
    over = read_input(args.over, "--over") if args.over else None
    if over is not None:
        _check_over(over, args.over, args)

    from .. import io
    from ..analysis import continue_bifurcation
    from ..continuation.curves import curve_to_dataset

    t0 = time.perf_counter()
    seed, x = _seed(args, system, kind)
    try:
        curve = continue_bifurcation(seed, x, args.period, kind,
                                     pair=(args.param1, args.param2), stop=window,
                                     step=args.step, max_points=args.max_points)
    except ValueError as exc:  # the API's state0 is the start the command reached
        raise UsageError(error_text(exc).removeprefix("state0: ") + (
            "" if args.stop1 is not None else "; try --stop1 to seed it from a branch"))\
            from None
    elapsed = time.perf_counter() - t0
    ds = curve_to_dataset(curve, seed, command=shlex.join(["vibimpact"] + list(args.argv)),
                          attrs={"preset": args.preset, "wall_time_s": round(elapsed, 3)})
    from ..plotting.bifurcation_curves import plot_bifurcation_curves

    fig = None
    if args.plot:  # drawn before anything is written: a figure that fails writes nothing
        try:
            fig = plot_bifurcation_curves(ds, over=over, **figure_options(args))
        except ValueError as exc:
            raise UsageError(f"--plot: {error_text(exc)}") from None
    writes = [(out, lambda: io.write_netcdf(ds, out, overwrite=args.overwrite))]
    if fig is not None:
        from ..plotting.style import save_figure

        writes.append((args.plot, lambda: save_figure(fig, args.plot)))
    write_outputs(*writes)  # both or neither
    p1, p2 = curve.params
    print(f"P{curve.n} {kind.value} curve: {curve.values.shape[0]} points, {p2} "
          f"{curve.values[0, 1]:.6g} .. {curve.values[-1, 1]:.6g}, {p1} "
          f"{curve.values[:, 0].min():.8g} .. {curve.values[:, 0].max():.8g} "
          f"({curve.status})")
    print(f"wrote {out}" + (f" and {args.plot}" if args.plot else "") +
          f" ({elapsed:.1f} s)")
    return 0


def add_parser(sub, fmt):
    """Add ``continue2`` to the subparsers ``sub``."""
    c = sub.add_parser("continue2", help="follow a fold, period doubling or grazing in "
                       "two parameters", formatter_class=fmt, epilog=_EPILOG,
                       description="Locate a bifurcation of a periodic orbit and follow "
                                   "it in a plane of two parameters;\nwrite the curve as "
                                   "NetCDF and print what was found.")
    c.add_argument("--preset", default=DEFAULT_PRESET, type=preset_name,
                   help=f"parameter set (default: {DEFAULT_PRESET_HELP}); see "
                        "'vibimpact presets'")
    c.add_argument("--set", action="append", metavar="NAME=VALUE", default=[],
                   help="change a parameter of the preset (repeatable)")
    c.add_argument("--eta", type=number, default=None, help="eta of the start")
    c.add_argument("--kind", required=True, help="fold, 'period doubling' (or pd) or "
                   "grazing")
    c.add_argument("--param1", default=None, metavar="NAME",
                   help="parameter the bifurcation is located in (default: the model's "
                        "forcing frequency, what --eta sets)")
    c.add_argument("--param2", required=True, metavar="NAME",
                   help="parameter stepped along the curve")
    c.add_argument("--range2", required=True, metavar="LO:HI",
                   help="window of --param2, holding its start value")
    c.add_argument("--stop1", type=number, default=None, metavar="VALUE",
                   help="seed from the first --kind on the branch continued in "
                        "--param1 to VALUE")
    c.add_argument("--period", type=positive_int(1), default=1, metavar="N",
                   help="period of the orbit in forcing periods (default: 1)")
    c.add_argument("--state0", type=number, nargs="+", metavar="X",
                   help="where the integration towards the orbit starts (default: rest)")
    c.add_argument("--approach", type=number, default=None, metavar="ETA0",
                   help="reach the start by stepping eta from ETA0, as a sweep does")
    c.add_argument("--transient", type=positive_int(0), default=500, metavar="N",
                   help="forcing periods integrated before shooting (default: 500)")
    c.add_argument("--step", type=number, default=None,
                   help="first step in --param2 (default: a 40th of --range2)")
    c.add_argument("--max-points", type=positive_int(1), default=200, metavar="N",
                   help="curve points at most per direction (default: 200)")
    c.add_argument("-o", "--output", default="curve.nc", metavar="OUT.nc",
                   help="NetCDF file to write (default: curve.nc)")
    c.add_argument("--over", metavar="MAP.nc", help="a 'vibimpact map' file drawn under "
                   "the curve (with --plot)")
    c.add_argument("--plot", metavar="FILE.png", help="also draw the curve")
    add_figure_options(c, "the --plot image")
    c.add_argument("--overwrite", action="store_true", help="replace existing files")
    c.set_defaults(func=_cmd_continue2)


__all__ = ["add_parser"]
