"""``vibimpact continue``: follow a periodic orbit in one parameter, and the branch
figures of ``vibimpact plot`` (``--kind branch``, ``--branch`` over response curves).

Like :mod:`vibimpact.cli`, only the standard library is imported at module level; the
work is :func:`vibimpact.continuation.branches.follow_branch` (pseudo-arclength continuation by
:func:`vibimpact.analysis.continue_orbit`) and the file
:func:`vibimpact.continuation.branches.branch_to_dataset`.
"""
import math
import os
import shlex
import time

from .common.args import (DEFAULT_PRESET, DEFAULT_PRESET_HELP, number, parse_sets, positive_int,
                          preset_name, with_sets)
from .common.errors import error_text, UsageError
from .common.files import check_output
from .common.inputs import check_distinct, check_state0
from ..base._text import count

_CONTINUE_EPILOG = """\
examples:
  vibimpact continue --preset fig8 --eta 1.12 --stop 1.25 --approach 1.1 -o p1.nc
  vibimpact continue --preset fig8 --eta 1.12 --stop 1.25 --approach 1.1 \\
      --ds-max 0.005 --refine 1e-7 -o p1_fine.nc
  vibimpact continue --preset fig10 --eta 1.1 --param kh --stop 60 --ds 0.5 \\
      --ds-max 2 -o kh.nc
  vibimpact plot p1.nc -o p1.png                        # the branch and |mu|max
  vibimpact classify --eta 1.0:1.3:0.002 -o sweep.nc
  vibimpact plot sweep.nc --kind response --branch p1.nc -o overlay.png

The start: the motion is integrated --transient forcing periods from rest (or --state0)
at the start value, or, with --approach ETA0, eta is stepped from ETA0 to --eta in steps
of 0.02 with --transient periods each, every step starting from the previous one's final
state, as a sweep does: the motion then settles on the orbit a sweep from ETA0 follows
(fig8 at eta 1.12 from rest: the impactless orbit; approached from 1.1: the impacting
P1).  The period-N orbit is found there by Newton shooting and followed by
pseudo-arclength continuation in --param (eta by default) towards --stop, through folds
onto unstable parts, with its Floquet multipliers (variational equations with saltation
matrices) at every orbit.  It ends when it leaves the window, after --max-points
orbits, or when the step falls below its minimum.  --ds and --ds-max are steps along
the branch in (state, parameter): scale them to the parameter (kh ~ 100: --ds 0.5
--ds-max 2).  It may start on a bound of the parameter's domain (BT, f, Bh, Rr are 0
in every preset: --param BT --stop 0.1 follows fig8 as tangential damping grows) and
never steps past one: a branch that reaches a bound (--param B --stop 0: B = 0) ends
on it, and the printed status says so.

Where the stability changes, the interval between the two orbits is narrowed by
bisection to --refine (Newton shooting at each midpoint) and the two orbits at its ends
join the branch; the kind comes from the multiplier leaving the unit circle: -1 period
doubling, +1 fold, a complex pair Neimark-Sacker; a turning point of the parameter is a
fold (turning point).  Where the impacts per period of two neighbouring orbits differ
(counted in the event log of one period of each), the orbit grazes the contact
surface (touches it with zero normal velocity; no multiplier crosses the unit circle):
a grazing, narrowed to --refine by bisection on the impacts of orbits shot in between,
printed with the impacts before and after.

The NetCDF file holds per orbit (dimension point): the parameter (a coordinate named
after it), orbit_state, floquet_real, floquet_imag, floquet_abs_max, stable (flag),
impacts_per_period, X_m, Y_m, R_m; per bifurcation: bifurcation_kind (flag),
bifurcation_value, bifurcation_lower, bifurcation_upper, bifurcation_point,
bifurcation_impacts_before, bifurcation_impacts_after; the start state, every
parameter, the solver settings and the command line ('vibimpact rerun' repeats it).

With --switch, the period-2N orbit born at the branch's first period doubling is
followed too (branch switching along the eigenvector of the multiplier -1,
vibimpact.analysis.switch_branch) within the same window and written beside OUT as
OUT_P<2N>.nc (a branch file; its first point is the period doubling itself).

exit status: 0 written, 2 bad input, no orbit at the start or, with --switch, no
period-2N branch switched to (nothing written: both files or neither).
"""


def _inputs(args):
    """``(System, Steps)`` of the parsed arguments; UsageError for bad input."""
    from ..base import _limits
    from ..models import presets
    from ..analysis import Steps
    from ..analysis.continuation import smallest_step
    from ..core.system import System

    try:
        base = presets.get(args.preset)
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    system = System(with_sets(base, parse_sets(args.set), args.eta))
    if args.param is None:  # the model's forcing frequency, what --eta sets
        args.param = system.model.frequency_name
    try:
        start = system.param(args.param)
    except ValueError:
        raise UsageError(f"--param: unknown parameter {args.param!r}; choose from "
                         f"{', '.join(system.model.param_names)}") from None
    if not math.isfinite(args.stop) or args.stop == start:
        raise UsageError(f"--stop must be finite and differ from the start value "
                         f"{args.param} = {start:g}, got {args.stop:g}")
    domain = system.param_domain(args.param)
    if args.stop not in domain:  # a branch may end on a bound (BT = 0), not beyond it
        raise UsageError(f"--stop: {domain.rule(args.param)}, got {args.stop!r}")
    if args.param == system.model.param_names[system.model.omega_index] and not (
            _limits.ETA_RANGE[0] <= args.stop <= _limits.ETA_RANGE[1]):
        raise UsageError(f"--stop: {args.param} must lie in [{_limits.ETA_RANGE[0]:g}, "
                         f"{_limits.ETA_RANGE[1]:g}] (a forcing period the solver can "
                         f"resolve), got {args.stop:g}")
    for name in ("refine", "approach"):
        value = getattr(args, name)
        if value is not None and not (math.isfinite(value) and value > 0):
            raise UsageError(f"--{name} must be a finite number > 0, got {value:g}")
    if args.refine is not None:
        _check_refine(args.refine, args.param, start, args.stop)
    check_state0(args.state0, system)
    if args.transient > _limits.MAX_PERIODS:
        raise UsageError(f"--transient: at most {_limits.MAX_PERIODS} forcing periods, "
                         f"got {args.transient}")
    try:
        _limits.check_points(args.max_points, "--max-points")
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    for name in ("ds", "ds_max"):
        value = getattr(args, name)
        if not (math.isfinite(value) and value > 0):
            raise UsageError(f"--{name.replace('_', '-')} must be a finite number > 0, "
                             f"got {value:g}")
    if args.ds > args.ds_max:
        raise UsageError(f"--ds {args.ds:g} is larger than --ds-max {args.ds_max:g} (the "
                         f"first step must not exceed the largest)")
    floor = smallest_step(Steps(), start)
    for name in ("ds", "ds_max"):
        value = getattr(args, name)
        if value < floor:
            raise UsageError(f"--{name.replace('_', '-')} must be >= {floor:.3g}, the "
                             f"smallest step resolvable at {args.param} = {start:g} (the "
                             f"corrector's tolerance {Steps.newton_tol:g} and the float "
                             f"resolution there), got {value:.3g}")
    steps = Steps(ds=args.ds, ds_min=min(Steps.ds_min, args.ds),
                  ds_max=args.ds_max, max_points=args.max_points)
    return system, steps


def _check_refine(refine, param, start, stop):
    """UsageError for a ``--refine`` width below the float resolution of ``param`` over
    the window (bisection cannot narrow an interval below a few units in the last
    place)."""
    import numpy as np

    floor = 4.0 * float(np.spacing(max(abs(start), abs(stop))))
    if refine < floor:
        raise UsageError(f"--refine (the width stability changes and grazings are "
                         f"narrowed to; default 1e-06) must be >= {floor:.3g}, the float "
                         f"resolution of {param} over the window, got {refine:.3g}")


def _summary(branch):
    """Lines that say what the branch holds: its stable and unstable stretches and its
    bifurcations."""
    import numpy as np

    from ..continuation.branches import stretches

    x = np.asarray(branch.values)
    p = branch.param
    lines = [f"P{branch.n} branch in {p} from {x[0]:.6g} to {x[-1]:.6g}: "
             f"{count(x.size, 'orbit')} ({branch.status})"]
    for i, j, stable in stretches(branch.stable):
        lines.append(f"  {'stable' if stable else 'unstable':9s}{p} {x[i]:.7g} .. "
                     f"{x[j]:.7g}")
    from ..base.bifurcation_kinds import BifurcationKind

    mu = np.abs(np.asarray(branch.multipliers)).max(axis=1)
    around = tuple(branch.event_impacts) or ((-1, -1),) * len(branch.bifurcations)
    for (i, kind, value), (lo, hi), (before, after) in zip(branch.bifurcations,
                                                             branch.brackets, around):
        where = f" in [{min(lo, hi):.8g}, {max(lo, hi):.8g}]" if lo != hi else ""
        line = (f"  {kind} at {p} = {value:.7g}{where}; |mu|max {mu[i - 1]:.6f} -> "
                f"{mu[i]:.6f}" if i > 0 else f"  {kind} at {p} = {value:.7g}")
        if kind == BifurcationKind.GRAZING:
            line += f"; impacts per period {before} -> {after}"
        lines.append(line)
    if not branch.bifurcations:
        lines.append("  no bifurcation found")
    return lines


def _cmd_continue(args):
    out = os.fspath(args.output)
    check_output(out, args.overwrite, "output file")
    switch_out = _switch_path(out, args.period) if args.switch else None
    if switch_out:
        check_output(switch_out, args.overwrite, "--switch output file")
    check_distinct(("-o", out), ("--switch's output", switch_out))
    system, steps = _inputs(args)

    from ..analysis.continuation import StartFailed
    from ..continuation.branches import branch_to_dataset, follow_branch

    t0 = time.perf_counter()
    try:
        branch, x0 = follow_branch(system, stop=args.stop, param=args.param,
                                   n=args.period, state0=args.state0,
                                   transient=args.transient, approach=args.approach,
                                   steps=steps, refine=args.refine)
    except StartFailed as exc:  # the API's argument state0: say it in the CLI's words
        raise UsageError(f"no period-{args.period} orbit found at {args.param} = "
                         f"{system.param(args.param):g}: Newton shooting from the state "
                         f"reached failed ({exc.reason}); try --approach, a longer "
                         "--transient, --state0 or another --period") from None
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    elapsed = time.perf_counter() - t0
    command = shlex.join(["vibimpact"] + list(args.argv))
    ds = branch_to_dataset(branch, system, start_state=x0, command=command,
                           attrs={"preset": args.preset, "wall_time_s": round(elapsed, 3)})
    # --switch before anything is written: both files or neither
    doubled = _switch(args, system, branch, steps, command) if args.switch else None
    _write(args, (out, ds), *([(switch_out, doubled[0])] if doubled else []))
    print("\n".join(_summary(branch)))
    print(f"wrote {out} ({elapsed:.1f} s)")
    if doubled:
        _, seconds, switched = doubled
        print(f"switched at the period doubling, {args.param} = "
              f"{switched.values[0]:.8g}:")
        print("\n".join(_summary(switched)))
        print(f"wrote {switch_out} ({seconds:.1f} s)")
    return 0


def _write(args, *outputs):
    """Write the ``(path, dataset)`` ``outputs`` together or not at all."""
    from .. import io
    from .common.files import write_outputs

    write_outputs(*((path, lambda path=path, ds=ds: io.write_netcdf(
        ds, path, overwrite=args.overwrite)) for path, ds in outputs))


def _switch_path(out, n):
    """Where ``--switch`` writes the doubled branch: beside ``out``, ``_P<2n>`` added."""
    stem, ext = os.path.splitext(out)
    return f"{stem}_P{2 * n}{ext or '.nc'}"


def _switch(args, system, branch, steps, command):
    """``--switch``: ``(dataset, seconds, branch)`` of the period-2n branch from the first
    period doubling of ``branch`` (:func:`vibimpact.analysis.switch_branch`);
    UsageError, before anything is written, when there is none."""
    from ..analysis import switch_branch
    from ..continuation.branches import branch_to_dataset

    from ..base.bifurcation_kinds import BifurcationKind

    t0 = time.perf_counter()
    why = f"the period-{branch.n} branch holds no period doubling"
    try:
        if not any(kind is BifurcationKind.PERIOD_DOUBLING
                   for _, kind, _ in branch.bifurcations):
            raise ValueError(why)
        doubled = switch_branch(system, branch, stop=args.stop, steps=steps,
                                refine=args.refine)
    except ValueError as exc:
        raise UsageError(f"--switch: {error_text(exc)}; nothing written (without "
                         f"--switch the period-{branch.n} branch is written)") from None
    seconds = time.perf_counter() - t0
    ds = branch_to_dataset(doubled, system, command=command,
                           attrs={"preset": args.preset, "switched_from_period": branch.n,
                                  "wall_time_s": round(seconds, 3)})
    return ds, seconds, doubled


def add_parser(sub, fmt):
    """Add ``continue`` to the subparsers ``sub``."""
    c = sub.add_parser("continue", help="follow a periodic orbit in a parameter "
                       "(stability, bifurcations)", formatter_class=fmt,
                       epilog=_CONTINUE_EPILOG,
                       description="Find a periodic orbit and follow it in one parameter "
                                   "by pseudo-arclength continuation,\nstable and "
                                   "unstable parts, with its Floquet multipliers and the "
                                   "bifurcations\nwhere it changes stability; write a "
                                   "NetCDF file and print what was found.")
    c.add_argument("--preset", default=DEFAULT_PRESET, type=preset_name,
                   help=f"parameter set (default: {DEFAULT_PRESET_HELP}); see "
                        "'vibimpact presets'")
    c.add_argument("--set", action="append", metavar="NAME=VALUE", default=[],
                   help="change a parameter of the preset, e.g. BT=0.05 (repeatable)")
    c.add_argument("--eta", type=number, default=None,
                   help="forcing frequency eta of the start (default: the preset's, 1.0)")
    c.add_argument("--param", default=None, metavar="NAME",
                   help="parameter continued (default: the model's forcing frequency, "
                        "what --eta sets); its start value is the preset's after --set")
    c.add_argument("--stop", type=number, required=True, metavar="VALUE",
                   help="other end of the parameter window (above or below the start)")
    c.add_argument("--period", type=positive_int(1), default=1, metavar="N",
                   help="period of the orbit in forcing periods (default: 1)")
    c.add_argument("--state0", type=number, nargs="+", metavar="X",
                   help="where the integration towards the orbit starts, one value per "
                        "state of the model (default: rest)")
    c.add_argument("--approach", type=number, default=None, metavar="ETA0",
                   help="reach the start by stepping eta from ETA0, as a sweep does")
    c.add_argument("--transient", type=positive_int(0), default=500, metavar="N",
                   help="forcing periods integrated before shooting, per --approach step "
                        "(default: 500)")
    c.add_argument("--ds", type=number, default=0.005, help="first arclength step "
                   "(default: 0.005; at least the corrector's tolerance times the "
                   "start value's magnitude, where it is above 1)")
    c.add_argument("--ds-max", type=number, default=0.02, help="largest arclength step "
                   "(default: 0.02)")
    c.add_argument("--max-points", type=positive_int(2), default=400, metavar="N",
                   help="orbits on the branch at most (default: 400)")
    c.add_argument("--refine", type=number, default=1e-6, metavar="TOL",
                   help="narrow every stability change and grazing to this width "
                        "(default: 1e-6)")
    c.add_argument("-o", "--output", default="branch.nc", metavar="OUT.nc",
                   help="NetCDF file to write (default: branch.nc)")
    c.add_argument("--switch", action="store_true",
                   help="also follow the period-2N orbit born at the first period "
                        "doubling found; written to OUT_P<2N>.nc")
    c.add_argument("--overwrite", action="store_true", help="replace an existing file")
    c.set_defaults(func=_cmd_continue)


__all__ = ["add_parser"]
