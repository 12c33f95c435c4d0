"""The ``vibimpact attractors`` command: the attractor census over an eta grid.

Like :mod:`vibimpact.cli`, only the standard library is imported at module level.
"""
import os

from .common.args import (CENSUS_FREQUENCY, CENSUS_PRESET, parse_sets, positive_int,
                          with_sets, MAX_WORKERS, unit_fraction)
from .common.checkpoints import checkpoint_of
from .common.errors import error_text, UsageError
from .common.figures import add_figure_options

_EPILOG = """\
examples:
  vibimpact attractors --preset fig11 --eta 1.04:1.08:0.005 --starts 400 -o census.nc
  vibimpact attractors --preset fig11 --eta 1.06 --starts 1000 -o c.nc --plot c.png
  vibimpact attractors --preset fig8 --eta 1.25 --starts 200 --workers 2 -o fig8.nc
  vibimpact classify --preset fig11 --eta 1.04:1.08:0.01 -o sweep.nc
  vibimpact attractors --preset fig11 --eta 1.04:1.08:0.01 --sweep sweep.nc -o c.nc

At every eta the same --starts states (random in the model's box, seeded by --seed: a
planar contact's two positions uniform in the unit disk inside the clearance, the
velocities uniform in [-1, 1]) are integrated until it is known which attractor each reaches: as
soon as its stroboscopic points enter an attractor already found, or else by the
settling evidence of a sweep point (period test, contraction and shooting, Lyapunov
exponent).  Every attractor found gets its label, Floquet multipliers or Lyapunov
exponent and its basin fraction with a standard error; attractors are matched from one
eta to the next (global_id); --sweep says on which of them a sweep's points lie (a
sweep's label then belongs to a named attractor); --plot stacks the basin fractions against eta
above each attractor's own bifurcation diagram.

The census is checkpointed in OUT.partial as it goes; after Ctrl-C or a kill, run the
same command with --resume.  Serial, parallel (--workers) and resumed runs give the same
numbers.

exit status: 0 written, 2 bad input (nothing written), 130 interrupted (Ctrl-C), 143
terminated (SIGTERM); the checkpoint is kept for --resume.
"""


def _inputs(args):
    from ..models import presets
    from ..sweeps import parse_range
    from ..core.system import System

    try:
        base = presets.get(args.preset)
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    try:
        etas = parse_range(str(args.eta))
    except ValueError as exc:
        raise UsageError(f"--eta: {error_text(exc)}") from None
    system = System(with_sets(base, parse_sets(args.set), float(etas[0])))
    return system, etas


def _table(ds):
    from ..census.dataset import attractor_table

    lines = []
    for i, eta in enumerate(ds.eta.values):
        rows = attractor_table(ds, i)
        lines.append(f"eta = {float(eta):.6g}: {len(rows)} attractor"
                     f"{'' if len(rows) == 1 else 's'}")
        for _a, gid, name, f, se, _, extra in rows:
            lines.append(f"  A{gid:<3d} {f:6.3f} +- {se:.3f}  {name}"
                         + (f"  ({extra})" if extra else ""))
        if "failed" in ds and int(ds.failed.values[i]):
            lines.append(f"  --   {float(ds.failed_fraction.values[i]):6.3f}"
                         "           integration failed (on no attractor)")
        if "unseen" in ds:
            lines.append(_unseen_line(ds, i))
    return lines


def _unseen_line(ds, i):
    """The line of the basin mass the census at eta index ``i`` may have missed."""
    n = int(ds.attrs.get("n_starts", ds.sizes["start"]))
    k = int(ds.singletons.values[i])
    return (f"  ?    <= {float(ds.unseen.values[i]):.3f}      unseen (Good-Turing "
            f"{float(ds.unseen_good_turing.values[i]):.3f}: {k} attractor"
            f"{'' if k == 1 else 's'} reached by one start; {n} starts reach a basin "
            f"above {_resolution(n):.3f} with probability "
            f"{float(ds.attrs.get('unseen_confidence', 0.95)):.0%})")


def _resolution(n):
    from ..census.unseen import resolution

    return resolution(n)


def unseen_hint(ds, level=None):
    """The hint printed when some eta of the census may have missed more than ``level``
    of its basin (the census' own ``until_unseen``, else 0.01), or None."""
    import math

    goal = ds.attrs.get("until_unseen", math.nan) if level is None else level
    goal = 0.01 if not math.isfinite(float(goal)) else float(goal)
    worst = float(ds.unseen.values.max()) if "unseen" in ds else 0.0
    if worst <= goal:
        return None
    more = 1 << max(12, (int(ds.sizes["start"]) * 4 - 1).bit_length())
    return (f"hint: up to {worst:.3f} of the basin may lie on attractors no start "
            f"reached: add starts (--starts {more} --until-unseen {goal:g}); "
            "'vibimpact orbits' finds periodic orbits, stable or not, that no start "
            "reached")


def _sweep_file(args, system, etas):
    """The --sweep file, checked before any work, or None: a sweep of the census' model
    and parameters (eta aside) that shares an eta with it and holds the Poincare samples
    of every state the census places (see :func:`_sample_names`)."""
    if args.sweep is None:
        return None
    from .common.files import read_input

    path = os.fspath(args.sweep)
    ds = read_input(path, "--sweep")
    label = f"--sweep {path!r}"
    if "eta" not in ds.dims or "regime" not in ds or "map_vary" in ds.attrs:
        raise UsageError(f"{label} is not a sweep file ('vibimpact classify' or "
                         "'bifurcation')")
    _same_system(ds, label, system, args.preset)
    try:
        from ..plotting._sweep import check_contents

        check_contents(ds, grids=("eta",), codes=(), increasing=("eta",))
    except ValueError as exc:
        raise UsageError(f"{label}: {error_text(exc)}") from None
    common = _common_etas(ds, etas)
    if not common.size:
        raise UsageError(f"{label} shares no eta with --eta {args.eta}")
    _check_samples(ds, label, system.model.state_names, common)
    return ds


def _same_system(ds, label, system, preset):
    """UsageError unless the sweep ``ds`` is of ``system``'s model with its parameters
    (eta, the grid, aside): a sweep's points lie on the attractors of its own
    parameters, which a census of others does not list."""
    import math

    from ..sweeps.dataset import sweep_params
    from ..core.system import param_dict
    from ..io.recorded import model_name

    try:
        model = str(model_name(ds.attrs, label))
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    if model != system.model.name:
        raise UsageError(f"{label} is a sweep of the {model} model; the census is of the "
                         f"{system.model.name} model (--preset {preset}): give the "
                         "sweep's preset")
    try:
        theirs = param_dict(sweep_params(ds, name=label))
    except (TypeError, ValueError) as exc:
        raise UsageError(error_text(exc)) from None
    omega = system.model.param_names[system.model.omega_index]
    ours = param_dict(system)
    differ = [f"{k} = {theirs[k]:g} (the census: {v:g})" for k, v in ours.items()
              if k != omega and k in theirs
              and not math.isclose(float(theirs[k]), float(v), rel_tol=1e-12)]
    if differ:
        raise UsageError(f"{label} was swept with other parameters than the census': "
                         f"{', '.join(differ)}; give the census the sweep's (--preset, "
                         "--set NAME=VALUE)")


def _common_etas(ds, etas):
    """The etas (rounded to 12 decimals, as :func:`vibimpact.census.locate.locate`
    matches them) that the sweep ``ds`` and the census grid ``etas`` share."""
    import numpy as np

    return np.intersect1d(np.round(ds.eta.values.astype(float), 12), np.round(etas, 12))


def _sample_names(ds, names):
    """The sweep's variable of the Poincare samples of each state in ``names`` (as
    :func:`vibimpact.census.locate.locate` takes them: ``poincare_NAME``, else
    ``poincare_X`` and ``poincare_Y`` for the first two states); None where missing."""
    out = []
    for j, name in enumerate(names):
        var = f"poincare_{name}" if f"poincare_{name}" in ds else \
            {0: "poincare_X", 1: "poincare_Y"}.get(j)
        out.append(var if var in ds else None)
    return out


def _check_samples(ds, label, names, common):
    """UsageError unless the sweep holds numeric Poincare samples over (direction,) eta
    and sample of every state in ``names``, finite at one eta of ``common`` at least."""
    import numpy as np

    allowed = {"direction", "eta", "sample"}
    finite, first = None, None
    for name, var in zip(names, _sample_names(ds, names)):
        if var is None:
            raise UsageError(f"{label} has no Poincare samples of {name} "
                             f"(poincare_{name}): sweep with --analyses including "
                             "poincare")
        v = ds[var]
        if v.dtype.kind not in "iuf":
            raise UsageError(f"{label}: {var} must hold numbers, got {v.dtype} values")
        if not {"eta", "sample"} <= set(v.dims) <= allowed or \
                set(v.dims) != set(first or v.dims):
            raise UsageError(f"{label}: {var} must have the dimensions "
                             f"{first or '(direction,) eta, sample'}, got {v.dims}")
        first = first or v.dims
        at = v.sel(eta=v.eta.values[np.isin(np.round(v.eta.values.astype(float), 12),
                                            common)])
        ok = np.isfinite(at.transpose(..., "eta", "sample").values.astype(float))
        finite = ok if finite is None else finite & ok
    assert finite is not None  # names: the model's states, one at least
    if not finite.any():
        why = ("" if "poincare" in str(ds.attrs.get("settings", "")) else
               " (sweep with --analyses including poincare)")
        raise UsageError(f"{label} holds no finite Poincare samples at the etas it "
                         f"shares with --eta: nothing to place{why}")


def _located(ds, sweep, path):
    """Lines: which census attractor the sweep followed at every common eta."""
    import numpy as np

    from ..census.locate import locate

    try:
        where = locate(ds, sweep)
    except ValueError as exc:
        raise UsageError(f"--sweep: {error_text(exc)}") from None
    names: dict[int, str] = {}
    for i in range(ds.sizes["eta"]):
        for a in range(ds.sizes["attractor"]):
            names.setdefault(int(ds.global_id.values[i, a]), str(ds.name.values[i, a]))
    lines = [f"sweep {path}:"]
    for r, d in enumerate(where.direction.values):
        for k, eta in enumerate(where.eta.values):
            g = int(where.values[r, k])
            what = f"A{g} ({names.get(g, '?')})" if g >= 0 else \
                "none of the census' attractors"
            i = int(np.flatnonzero(np.round(ds.eta.values, 12) == round(float(eta), 12))[0])
            if g < 0 and "failed" in ds and int(ds.failed.values[i]):
                what += f" ({int(ds.failed.values[i])} starts failed to integrate there)"
            lines.append(f"  {d} eta = {float(eta):.6g}: on {what}")
    return lines


def _cmd_attractors(args):
    from .common.census_steps import check_outputs, draw, run_and_write

    out = os.fspath(args.output)
    system, etas = _inputs(args)
    ckpt = checkpoint_of(out)
    resuming, fig_kw = check_outputs(args, out, ckpt, inputs=(("--sweep", args.sweep),))
    sweep = _sweep_file(args, system, etas)

    from .. import io
    from ..census.census import attractors

    ds, status, elapsed = run_and_write(
        args, out, ckpt, resuming, "census", lambda run: attractors(
            system, etas, starts=args.starts, seed=args.seed,
            until_unseen=args.until_unseen, execution=run),
        io.write_netcdf)
    if ds is None:
        return status
    print("\n".join(_table(ds)))
    hint = unseen_hint(ds)
    if hint is not None:
        print(hint)
    if sweep is not None:
        print("\n".join(_located(ds, sweep, args.sweep)))
    print(f"wrote {out} ({ds.sizes['eta']} eta x {ds.sizes['start']} starts in "
          f"{elapsed:.1f} s)")
    from ..plotting.census import plot_census

    draw(args, ds, out, plot_census, fig_kw)
    return 0


def add_parser(sub, fmt):
    """Add ``attractors`` to the subparsers ``sub``."""
    a = sub.add_parser("attractors", help="attractor census: every attractor and its "
                       "basin fraction at each eta", formatter_class=fmt, epilog=_EPILOG,
                       description="Integrate many starting states at every eta until "
                                   "each is known to reach an attractor;\nlist every "
                                   "attractor with its basin fraction and write a NetCDF "
                                   "file.")
    a.add_argument("--preset", default=CENSUS_PRESET,
                   help=f"parameter set (default: {CENSUS_PRESET})")
    a.add_argument("--set", action="append", metavar="NAME=VALUE", default=[],
                   help="change a parameter of the preset, e.g. B=0.01 (repeatable)")
    a.add_argument("--eta", default=CENSUS_FREQUENCY, metavar="START:STOP:STEP",
                   help="forcing frequencies: a grid START:STOP:STEP, a list V1,V2,... or one "
                        f"value (default: {CENSUS_FREQUENCY})")
    a.add_argument("--starts", type=positive_int(1, 1_000_000), default=400, metavar="N",
                   help="starting states per eta (default: 400)")
    a.add_argument("--until-unseen", type=unit_fraction, default=None, metavar="LEVEL",
                   help="add rounds of starts (16, 64, 256, ...) until at most LEVEL of "
                        "the basin may be unseen at every eta; --starts is then the most "
                        "starts")
    a.add_argument("--seed", type=positive_int(0, 2**63 - 1), default=0,
                   help="seed of the random starts (default: 0)")
    a.add_argument("--workers", type=positive_int(1, MAX_WORKERS), default=1, metavar="N",
                   help="local processes (default: 1); never changes a number")
    a.add_argument("-o", "--output", default="census.nc", metavar="OUT.nc",
                   help="NetCDF file to write (default: census.nc)")
    a.add_argument("--sweep", default=None, metavar="SWEEP.nc",
                   help="say which attractor this sweep ('vibimpact classify') followed "
                        "at every eta the two share")
    a.add_argument("--plot", default=None, metavar="IMAGE",
                   help="also draw the basin fractions and bifurcation diagram per "
                        "attractor")
    add_figure_options(a)
    a.add_argument("--resume", action="store_true",
                   help="continue an interrupted run from its checkpoint OUT.partial")
    a.add_argument("--keep-checkpoint", action="store_true",
                   help="keep OUT.partial after the file is written")
    a.add_argument("--no-progress", action="store_true", help="no progress bar")
    a.add_argument("--overwrite", action="store_true", help="replace existing files")
    a.set_defaults(func=_cmd_attractors)


__all__ = ["add_parser"]
