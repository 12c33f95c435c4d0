"""``vibimpact plot``: a figure drawn from a file any command wrote (a run, a sweep, a map,
a branch, a census).

Only the standard library and the command line's shared parts are imported at module
level; numpy, numba, xarray and matplotlib inside the command.
"""
from __future__ import annotations

import os
from typing import TYPE_CHECKING

from .common.errors import error_text, reason, UsageError
from .common.figures import add_figure_options, figure_options, image_ext_ok
from .common.files import check_output, is_store, read_input
from .common.inputs import check_distinct

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Callable

    from matplotlib.figure import Figure

PLOT_KINDS = ("response", "bifurcation", "intervals", "xy", "map", "branch", "poincare",
              "lyapunov", "census")

_PLOT_EPILOG = """\
examples:
  vibimpact plot fig8.nc --kind response -o response.png
  vibimpact plot fig8.nc --kind intervals -o intervals.png
  vibimpact plot run.nc --kind xy -o xy.png
  vibimpact plot fig8.nc --kind poincare -o poincare.png
  vibimpact plot fig8.nc --kind lyapunov -o lyapunov.png
  vibimpact plot fig8.nc --kind intervals --style paper -o intervals.pdf
  vibimpact plot p1.nc -o p1.png                 # a 'vibimpact continue' branch
  vibimpact plot fig8.nc --kind response --branch p1.nc -o overlay.png
  vibimpact plot sweep.nc --kind bifurcation --state Vr -o vr.png

kinds:
  response     X_m and Y_m against eta, up/down sweeps, chaotic points marked (classify)
  bifurcation  Poincare X and Y against eta (classify with poincare, or bifurcation);
               --state NAME[,NAME...] draws those states instead (e.g. Vr)
  intervals    coloured bands per regime along eta, one row per direction (classify)
  xy           the orbit in the (X, Y) clearance plane (a 'vibimpact simulate' file)
  map          regime, period, impacts, exponent over (eta, PARAM) ('vibimpact map';
               .zarr or .nc)
  branch       a continued branch: X_m, Y_m and |mu|max against the parameter, stable
               solid, unstable dashed, bifurcations marked ('vibimpact continue')
  poincare     the Poincare section: every point's samples, first state against its
               velocity (X, X'; x, dx), coloured by eta; one panel per direction
               (classify with poincare)
  lyapunov     largest Lyapunov exponent against eta with its error bars, periodic
               points by their Floquet exponent, coloured by regime; zero line; one
               panel per direction (classify with lyapunov or floquet)
  census       basin fractions against eta above every attractor's own bifurcation
               diagram ('vibimpact attractors')

--branch BRANCH.nc (repeatable) draws branches continued in eta over the response
curves: stable parts solid, unstable dashed, each kind of bifurcation with its own
open marker, every line and marker in the legend.

Without --kind: xy for a simulate file, branch for a continue file, response (or
bifurcation when the file has no response data) for a sweep file.  Without -o:
FILE_KIND.png next to FILE.
"""


FILE_KINDS = {
    "run": "a 'vibimpact simulate' file",
    "sweep": "a sweep file ('vibimpact classify' or 'bifurcation')",
    "map": "a parameter map ('vibimpact map')",
    "branch": "a continued branch ('vibimpact continue')",
    "census": "an attractor census ('vibimpact attractors')",
    "basins": "a basins file ('vibimpact basins')",
    "orbits": "an orbit hunt ('vibimpact orbits')",
    "curve": "a two-parameter curve ('vibimpact continue2')",
}

#: the one table of ``plot``: the --kind figures each kind of file holds the data of
#: (the first is the default; basins, orbits and curves are drawn by their command's
#: --plot)
DRAWS = {
    "run": ("xy",),
    "sweep": ("response", "bifurcation", "intervals", "poincare", "lyapunov"),
    "map": ("map",),
    "branch": ("branch",),
    "census": ("census",),
    "basins": (), "orbits": (), "curve": (),
}

#: a word more where a figure's data is held otherwise by a file of another kind
_HINTS = {("lyapunov", "map"): "; its exponent over (eta, PARAM) is a panel of it",
          ("poincare", "map"): "; a map stores no Poincare samples"}


#: --kind -> (what it draws, its analysis, the variables of which one must be finite)
_DRAWN = {"response": ("response data (X_m)", "response", ("X_m",)),
          "bifurcation": ("Poincare points", "poincare", ("poincare_X",)),
          "poincare": ("Poincare points", "poincare", ("poincare_X",)),
          "lyapunov": ("Lyapunov exponents", "lyapunov", ("lyapunov", "floquet_exponent"))}


def _kind_of(ds):
    """The kind of vibimpact file ``ds`` is (a key of :data:`FILE_KINDS`), or None."""
    from ..continuation.branches import is_branch_dataset
    from ..continuation.curves import is_curve_dataset
    from ..orbits.dataset import is_orbit_dataset

    if "map_vary" in ds.attrs:
        return "map"
    if is_branch_dataset(ds):
        return "branch"
    if is_curve_dataset(ds):
        return "curve"
    if is_orbit_dataset(ds):
        return "orbits"
    if ds.attrs.get("kind") in ("census", "basins"):
        return str(ds.attrs["kind"])
    if "regime" in ds and "eta" in ds.dims:
        return "sweep"
    if "strobe" in ds and "state" in ds.dims:
        return "run"
    return None


def check_kind(kind, what, path):
    """UsageError unless a file of kind ``what`` (:data:`FILE_KINDS`) holds the data of
    ``--kind kind`` (:data:`DRAWS`); the message names the kind of file the figure needs
    and the kind the file is."""
    if what is None:
        raise UsageError(f"{path!r} is not a file plot draws: not written by vibimpact "
                         "simulate, classify, bifurcation, map, continue or attractors")
    if kind in DRAWS[what]:
        return
    use = (f" (use --kind {_alternatives(DRAWS[what])}{_HINTS.get((kind, what), '')})"
           if DRAWS[what] else ", which plot does not draw (the command's --plot draws it)")
    if kind is None:
        raise UsageError(f"{path!r} is {FILE_KINDS[what]}{use}")
    needs = " or ".join(FILE_KINDS[w] for w, kinds in DRAWS.items() if kind in kinds)
    raise UsageError(f"--kind {kind} needs {needs}; {path!r} is {FILE_KINDS[what]}{use}")


def _alternatives(words):
    """``a``, ``a or b``, ``a, b or c``."""
    return " or ".join(filter(None, (", ".join(words[:-1]), words[-1])))


def _default_kind(ds, what, args):
    """The figure of a file without --kind: its kind's first in :data:`DRAWS` (a sweep:
    bifurcation with --state or without response data, else response)."""
    if what != "sweep":
        return DRAWS[what][0] if DRAWS.get(what) else None
    if args.state is not None or (not _has(ds, "X_m") and _has(ds, "poincare_X")):
        return "bifurcation"
    return "response"


def _has(ds, name):
    import numpy as np

    return name in ds and bool(np.isfinite(ds[name].values).any())


def _missing(ds, path, what, analysis):
    """The UsageError for a sweep file without finite ``what`` to draw: every point
    diverged or not computed, or the analysis was not requested."""
    import numpy as np

    from ..base._text import count
    from ..plotting.needs import recorded_analyses
    from ..analysis.classify import Label
    from ..points.point import REGIME_CODES

    reg = ds["regime"].values if "regime" in ds else np.zeros(0)
    diverged = int(np.sum(reg == REGIME_CODES[Label.DIVERGED]))
    if reg.size and np.all((reg == REGIME_CODES[Label.DIVERGED]) | (reg == 0)):
        why = (f"every point ({reg.size}) diverged" if diverged == reg.size else
               f"{diverged} of {count(reg.size, 'point')} diverged, the others were not "
               "computed")
        return UsageError(f"{path!r} has no {what} to draw: {why} (its labels: --kind "
                          "intervals)")
    asked = recorded_analyses(ds)
    if asked is not None and analysis in asked:
        return UsageError(f"{path!r} has no {what} to draw: none of its points has a "
                          "finite value")
    return UsageError(f"{path!r} has no {what}: sweep with --analyses including {analysis}")


def _states(args, ds, kind):
    """``{"states": [...]}`` of ``--state`` for the bifurcation diagram, else ``{}``;
    UsageError for another kind or a name the file holds no samples of."""
    if args.state is None:
        return {}
    if kind != "bifurcation":
        raise UsageError(f"--state names the states of a bifurcation diagram, not of "
                         f"--kind {kind}")
    from ..plotting.poincare import poincare_variable

    try:
        names = [poincare_variable(ds, n)[1] for n in args.state.split(",")]
    except ValueError as exc:
        raise UsageError(f"--state: {error_text(exc)}") from None
    if len(set(names)) != len(names):
        raise UsageError(f"--state names a state twice: {args.state!r}")
    return {"states": names}


def _no_state(args, what):
    """``args``, or UsageError when --state is given for a figure of ``what``."""
    if args.state is not None:
        raise UsageError(f"--state names the states of a sweep's bifurcation diagram; "
                         f"{os.fspath(args.file)!r} is {what}")
    return args


def _read_plotted(path):
    """``(dataset, kind of file)`` of ``plot``'s FILE; the dataset None for a map's Zarr
    store or checkpoint directory (:func:`_plot_map` reads it)."""
    from ..engine.store import is_checkpoint

    if os.path.isdir(path) and (is_store(path) or is_checkpoint(path)):
        return None, "map"
    ds = read_input(path)
    try:
        return ds, _kind_of(ds)
    except Exception as exc:
        raise UsageError(f"{path!r} is not a vibimpact file: {exc}") from None


def _cmd_plot(args):
    path = os.fspath(args.file)
    if args.branch and args.kind not in (None, "response"):
        raise UsageError(f"--branch draws over response curves, not --kind {args.kind}")
    if args.state is not None and args.kind not in (None, "bifurcation"):
        raise UsageError(f"--state names the states of a bifurcation diagram, not of "
                         f"--kind {args.kind}")
    ds, what = _read_plotted(path)
    kind = args.kind or (_default_kind(ds, what, args) if what else None)
    check_kind(kind, what, path)
    assert kind is not None  # check_kind refuses none
    for given, option in ((args.branch, "--branch"), (args.state, "--state")):
        if given and what != "sweep":
            raise UsageError(f"{option} is for the figures of a sweep file; {path!r} is "
                             f"{FILE_KINDS[what]}")
    out = os.fspath(args.output if args.output is not None else
                    os.path.splitext(path.rstrip("/" + os.sep))[0] + f"_{kind}.png")
    check_distinct(("-o", out), inputs=(("FILE", path),
                                        *(("--branch", b) for b in args.branch)))
    args.output = out
    if what in ("map", "branch", "census"):
        return {"map": _plot_map, "branch": _plot_branch, "census": _plot_census}[what](
            args, ds)
    from ..plotting._sweep import check_contents
    from ..plotting.needs import missing

    try:  # a damaged file is said as such before what it lacks
        check_contents(ds)
    except ValueError as exc:
        raise UsageError(f"cannot draw {kind} from {path!r}: {reason(exc)}") from None
    gap = missing(ds, kind)  # the plotting functions' own test of what they draw
    if gap is not None:
        raise _missing(ds, path, *gap)
    if kind in _DRAWN and not any(_has(ds, v) for v in _DRAWN[kind][2]):
        # every point diverged or not computed: empty axes, which plot does not draw
        raise _missing(ds, path, *_DRAWN[kind][:2])
    if args.branch and kind != "response":
        raise UsageError(f"--branch draws over response curves, not --kind {kind}")
    states = _states(args, ds, kind)
    branches = []
    if args.branch:
        branches = _read_branches(args.branch)
    image_ext_ok(out, "-o")
    check_output(out, args.overwrite, "image file")

    from .. import plotting

    try:
        if kind == "xy":
            plotting.plot_xy(ds, out, **figure_options(args))
        else:
            draws: dict[str, Callable[..., Figure]] = {
                "response": plotting.plot_response,
                "bifurcation": plotting.plot_bifurcation,
                "intervals": plotting.plot_intervals,
                "poincare": plotting.plot_poincare,
                "lyapunov": plotting.plot_lyapunov}
            draw = draws[kind]
            fig = draw(ds, **figure_options(args), **states)
            if branches:
                from ..plotting.branch import overlay_branches
                overlay_branches(fig.axes[:2], branches,
                                 [os.path.basename(b) for b in args.branch],
                                 style=figure_options(args)["style"])
            plotting.save_figure(fig, out)
    except Exception as exc:  # a foreign or damaged file can fail anywhere in drawing;
        # save_figure writes atomically, so nothing partial is left
        raise UsageError(f"cannot draw {kind} from {path!r}: {reason(exc)}") from None
    print(f"wrote {out}")
    return 0


def _plot_map(args, ds=None):
    """``vibimpact plot FILE --kind map``: FILE is a map (.zarr store or .nc)."""
    from ..maps.store import open_map

    path = os.fspath(args.file)
    if ds is None:
        if not os.path.exists(path):
            raise UsageError(f"{path!r}: no such file or directory")
        from ..base._limits import DeclaredTooLarge

        try:
            ds = open_map(path)
        except DeclaredTooLarge as exc:  # names the store already
            raise UsageError(error_text(exc)) from None
        except Exception as exc:
            raise UsageError(f"cannot read {path!r} as a map (Zarr or NetCDF): "
                             f"{reason(exc)}") from None
    if "map_vary" not in ds.attrs:
        raise UsageError(f"--kind map needs a file of 'vibimpact map'; {path!r} is not "
                          "one")
    # its --kind checked by check_kind, from the table of plot
    from ..plotting.map2d import plot_map

    return _draw_file(args, ds, "a map", lambda ds, out, **kw: plot_map(ds, path=out, **kw))


def _plot_branch(args, ds):
    """``vibimpact plot BRANCH.nc [--kind branch]`` (its kind, --branch and the image
    path ``args.output`` checked by :func:`check_kind`)."""
    from ..plotting.branch import plot_branch_figure

    return _draw_file(args, ds, "a branch", plot_branch_figure)


def _frequency_of(ds):
    """The name of the forcing frequency of the model a file names (its registered
    model's; else the file's ``frequency_name``; else ``eta``, the coordinate's)."""
    from .. import models

    name = ds.attrs.get("model")
    if isinstance(name, str) and name in models.names():
        return models.get(name).frequency_name
    return str(ds.attrs.get("frequency_name", "eta"))


def _read_branches(paths):
    """The datasets of ``--branch`` files; UsageError unless each is a ``vibimpact
    continue`` file continued in its model's forcing frequency (the axis of a sweep)."""
    from ..continuation.branches import is_branch_dataset

    out = []
    for path in map(os.fspath, paths):
        ds = read_input(path, "--branch")
        if not is_branch_dataset(ds):
            raise UsageError(f"--branch {path!r} is not a 'vibimpact continue' file")
        freq = _frequency_of(ds)
        if ds.attrs.get("continuation_param") != freq:
            raise UsageError(f"--branch {path!r} is continued in "
                             f"{ds.attrs.get('continuation_param')}, not its model's "
                             f"forcing frequency {freq}")
        out.append(ds)
    return out


def _plot_census(args, ds):
    """``vibimpact plot CENSUS.nc [--kind census]`` (its kind, --branch and the image
    path ``args.output`` checked by :func:`check_kind`)."""
    from ..plotting.census import plot_census

    return _draw_file(args, ds, "a census", plot_census)


def _draw_file(args, ds, what, draw):
    """Draw ``ds``, the FILE of ``plot`` holding ``what`` ("a map", ...), into the image
    ``args.output`` with ``draw(ds, path, figsize=, dpi=, style=)``; exit status 0, or
    one line naming the file when drawing fails (the image is written atomically, so
    nothing partial is left)."""
    path, out = os.fspath(args.file), os.fspath(args.output)
    image_ext_ok(out, "-o")
    check_output(out, args.overwrite, "image file")
    try:
        draw(ds, out, **figure_options(args))
    except Exception as exc:  # a foreign or damaged file can fail anywhere in drawing
        raise UsageError(f"cannot draw {what} from {path!r}: {reason(exc)}") from None
    print(f"wrote {out}")
    return 0


def add_parser(sub, fmt):
    """Add ``plot`` to the subparsers ``sub``."""
    p = sub.add_parser("plot", help="draw a figure from a NetCDF file", formatter_class=fmt,
                       epilog=_PLOT_EPILOG,
                       description="Draw a figure from a file written by 'vibimpact "
                                   "classify', 'bifurcation', 'simulate', 'map' or\n"
                                   "'continue'.")
    p.add_argument("file", metavar="FILE.nc", help="NetCDF file to read")
    p.add_argument("--kind", choices=PLOT_KINDS, default=None,
                   help="figure to draw (default: from the file, see below)")
    p.add_argument("-o", "--output", metavar="FIG.png", default=None,
                   help="image to write (default: FILE_KIND.png)")
    p.add_argument("--branch", action="append", default=[], metavar="BRANCH.nc",
                   help="draw a branch of 'vibimpact continue' (in eta) over the response "
                        "curves (repeatable)")
    p.add_argument("--state", default=None, metavar="NAME[,NAME...]",
                   help="--kind bifurcation: the states drawn against eta, one panel each "
                        "(state names of the model, e.g. Vr or X,Vr; X' is dX; default: "
                        "the first two, X and Y)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing image")
    add_figure_options(p, "the image")
    p.set_defaults(func=_cmd_plot)


__all__ = ["add_parser", "PLOT_KINDS"]
