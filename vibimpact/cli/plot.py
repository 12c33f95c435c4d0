"""The sweep commands of the ``vibimpact`` command line: ``classify``, ``bifurcation`` and
``plot``.

Like :mod:`vibimpact.cli`, this module imports only the standard library at module level;
numpy, numba, xarray and matplotlib are imported inside the commands, so ``--help`` stays
instant.
"""
import os

from .common.args import parse_analyses, parse_sets, positive_int, with_sets, MAX_WORKERS
from .common.checkpoints import (check_checkpoint, checkpoint_of, finish_checkpointed,
                              run_checkpointed)
from .common.errors import error_text, reason, UsageError
from .common.figures import add_figure_options, figure_options, image_ext_ok
from .common.files import check_output, is_store, read_input, sweep_file_bytes, write_outputs
from .common.inputs import check_distinct
from ..engine.leftovers import output_of
from ..base._limits import MAX_POINTS

#: the main job
DEFAULT_ETA = "0.9:1.5:0.002"
DEFAULT_PRESET = "fig8"
PLOT_KINDS = ("response", "bifurcation", "intervals", "xy", "map", "branch", "poincare",
              "lyapunov", "census")

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

_BIFURCATION_EPILOG = """\
example:
  vibimpact bifurcation --eta 0.9:1.5:0.002 --preset fig8 -o bif.png

Sweeps eta up and down (--direction both by default) computing only the period and the
Poincare (stroboscopic) points, draws X and Y of the Poincare points against eta (up and
down sweeps in two colours) and writes the data next to the image (bif.png -> bif.nc);
'vibimpact plot bif.nc --kind bifurcation' redraws it.

exit status: 0 written, 2 bad input (nothing computed) or a worker process died
(nothing written), 130 interrupted (Ctrl-C), 143 terminated (SIGTERM).
"""

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
  vibimpact plot ring.nc --kind bifurcation --state Vr -o vr.png

kinds:
  response     X_m and Y_m against eta, up/down sweeps, chaotic points marked (classify)
  bifurcation  Poincare X and Y against eta (classify with poincare, or bifurcation);
               --state NAME[,NAME...] draws those states instead (a ring's speed Vr)
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


def _default_workers():
    return min(2, os.cpu_count() or 1)


def _sweep_inputs(args):
    """Grid, parameters from the parsed arguments; UsageError for bad input."""
    from ..models import presets
    from ..sweeps import parse_range

    try:
        etas = parse_range(args.eta)
    except ValueError as exc:
        raise UsageError(f"--eta: {exc}") from None
    try:
        base = presets.get(args.preset)
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    return etas, with_sets(base, parse_sets(args.set))


def _command_line(args):
    import shlex

    return shlex.join(["vibimpact"] + list(args.argv))


def _cmd_classify(args):
    out = os.fspath(args.output)
    etas, params = _sweep_inputs(args)
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
    ds.attrs.update(command=_command_line(args), preset=args.preset, eta_range=args.eta)
    finish_checkpointed(ds, out, ckpt, io.write_netcdf, resuming=resuming,
                        keep=args.keep_checkpoint, overwrite=args.overwrite, unit="points",
                        resumable=resumable)
    print(format_intervals(vi.intervals(ds)))
    print(f"wrote {out}")
    return 0


def _cmd_bifurcation(args):
    # ``vibimpact rerun`` sets ``data_only`` to the .nc path: no image is drawn then
    data_only = getattr(args, "data_only", None)
    image = os.fspath(args.output)
    if data_only is None:
        image_ext_ok(image, "-o")
        data = os.path.splitext(image)[0] + ".nc"
    else:
        data = os.fspath(data_only)
    etas, params = _sweep_inputs(args)
    if data_only is None:
        check_output(image, args.overwrite, "image file")
    check_output(data, args.overwrite, "data file",
                 size=sweep_file_bytes(params, etas.size, args.direction))
    check_distinct(("-o", None if data_only is not None else image), ("its data file", data))

    import vibimpact as vi
    from .. import io
    from ..plotting import plot_bifurcation

    run = vi.Execution(workers=args.workers,
                       progress=not args.no_progress and "bifurcation")
    ds, status = run_checkpointed(None, "points", lambda: vi.sweep(
        params, etas, direction=args.direction, analyses=("period", "poincare"),
        continuation=vi.Continuation(blocks=args.blocks), execution=run))
    if ds is None:
        return status
    ds.attrs.update(command=_command_line(args), preset=args.preset, eta_range=args.eta)
    writes = [(data, lambda: io.write_netcdf(ds, data, overwrite=args.overwrite))]
    if data_only is None:
        writes.append((image, lambda: plot_bifurcation(ds, path=image,
                                                       **figure_options(args))))
    write_outputs(*writes)  # both or neither
    if data_only is not None:
        print(f"wrote {data}")
        return 0
    print(f"wrote {image} and {data}")
    return 0


#: what each kind of file is, in the refusals of ``plot``
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

    from ..base._json import loads
    from ..base._text import count
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
    try:
        asked = analysis in loads(ds.attrs.get("settings", "{}"), "settings").get("analyses", "")
    except (ValueError, AttributeError):
        asked = False
    if asked:
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
    store or checkpoint directory (:func:`vibimpact.cli.map.plot_command` reads it)."""
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
    for given, option in ((args.branch, "--branch"), (args.state, "--state")):
        if given and what != "sweep":
            raise UsageError(f"{option} is for the figures of a sweep file; {path!r} is "
                             f"{FILE_KINDS[what]}")
    out = os.fspath(args.output if args.output is not None else
                    os.path.splitext(path.rstrip("/" + os.sep))[0] + f"_{kind}.png")
    check_distinct(("-o", out), inputs=(("FILE", path),
                                        *(("--branch", b) for b in args.branch)))
    args.output = out
    if what == "map":
        from .map import plot_command
        return plot_command(args, ds)
    if what == "branch":
        from .continue_ import plot_command
        return plot_command(args, ds)
    if what == "census":
        from .attractors import plot_command
        return plot_command(args, ds)
    if kind == "response" and not _has(ds, "X_m"):
        raise _missing(ds, path, "response data (X_m)", "response")
    if kind in ("bifurcation", "poincare") and not _has(ds, "poincare_X"):
        raise _missing(ds, path, "Poincare points", "poincare")
    if kind == "lyapunov" and not (_has(ds, "lyapunov") or _has(ds, "floquet_exponent")):
        raise _missing(ds, path, "Lyapunov exponents", "lyapunov")
    if args.branch and kind != "response":
        raise UsageError(f"--branch draws over response curves, not --kind {kind}")
    states = _states(args, ds, kind)
    branches = []
    if args.branch:
        from .continue_ import read_branches
        branches = read_branches(args.branch)
    image_ext_ok(out, "-o")
    check_output(out, args.overwrite, "image file")

    from .. import plotting

    try:
        if kind == "xy":
            plotting.plot_xy(ds, out, **figure_options(args))
        else:
            draw = {"response": plotting.plot_response,
                    "bifurcation": plotting.plot_bifurcation,
                    "intervals": plotting.plot_intervals,
                    "poincare": plotting.plot_poincare,
                    "lyapunov": plotting.plot_lyapunov}[kind]
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


def _add_sweep_options(s, direction):
    s.add_argument("--eta", default=DEFAULT_ETA, metavar="START:STOP:STEP|V1,V2,...",
                   help="grid of the forcing frequency ratio: a range (STOP is included "
                        "when it lies on the grid) or a list of increasing values, e.g. "
                        f"1.0,1.1,1.25 (default: {DEFAULT_ETA})")
    s.add_argument("--preset", default=DEFAULT_PRESET, help="parameter set (default: "
                   f"{DEFAULT_PRESET}); see 'vibimpact presets'")
    s.add_argument("--set", action="append", metavar="NAME=VALUE", default=[],
                   help="change a parameter of the preset, e.g. BT=0.05 (repeatable)")
    s.add_argument("--direction", choices=("up", "down", "both"), default=direction,
                   help=f"sweep direction (default: {direction})")
    s.add_argument("--workers", type=positive_int(1, MAX_WORKERS), default=_default_workers(),
                   metavar="N", help="processes computing at once (default: min(2, CPUs) "
                   f"= {_default_workers()}); does not change the result")
    s.add_argument("--blocks", type=positive_int(1, MAX_POINTS), default=16, metavar="N",
                   help="seeded blocks per direction, 1 = pure serial continuation "
                        "(default: 16)")
    s.add_argument("--overwrite", action="store_true", help="replace existing output files")
    s.add_argument("--no-progress", action="store_true",
                   help="no progress bar on stderr")


def add_parsers(sub, fmt):
    """Add ``classify``, ``bifurcation`` and ``plot`` to the subparsers ``sub``."""
    c = sub.add_parser("classify", help="sweep eta, classify every point, print the "
                       "intervals", formatter_class=fmt, epilog=_CLASSIFY_EPILOG,
                       description="Sweep the forcing frequency eta with continuation, "
                                   "classify the motion at every point\n(period, impacts, "
                                   "Lyapunov exponent, 0-1 test, Floquet multipliers), write a NetCDF file and "
                                   "print the\nlabelled frequency intervals.")
    _add_sweep_options(c, "up")
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

    b = sub.add_parser("bifurcation", help="sweep eta and draw the bifurcation diagram",
                       formatter_class=fmt, epilog=_BIFURCATION_EPILOG,
                       description="Sweep eta up and down and draw the Poincare points "
                                   "against eta; the data is written\nnext to the image "
                                   "as NetCDF.")
    _add_sweep_options(b, "both")
    b.add_argument("-o", "--output", default="bifurcation.png", metavar="FILE.png",
                   help="image to write (default: bifurcation.png); the data goes to "
                        "FILE.nc")
    add_figure_options(b, "the image")
    b.set_defaults(func=_cmd_bifurcation)

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


__all__ = ["add_parsers", "DEFAULT_ETA", "PLOT_KINDS"]
