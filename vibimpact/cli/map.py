"""The ``vibimpact map`` command: a regime map over eta and one other parameter.

Like :mod:`vibimpact.cli`, this module imports only the standard library at module level;
numpy, xarray, dask and matplotlib are imported inside the commands, so ``--help`` stays
instant.
"""
import os

from .common.args import (DEFAULT_PRESET, DEFAULT_PRESET_HELP, MAP_FREQUENCIES, swept,
                          parse_analyses, parse_sets,
                          positive_int, preset_name, with_sets, MAX_WORKERS)
from .common.checkpoints import (check_checkpoint, checkpoint_of, finish_checkpointed,
                                 run_checkpointed)
from .common.errors import error_text, UsageError
from .common.figures import add_figure_options, figure_options, image_ext_ok
from .common.files import check_output, sweep_file_bytes
from ..engine.leftovers import output_of
from ..base._text import count

_MAP_EPILOG = """\
examples:
  vibimpact map --eta 0.9:1.5:0.005 --vary kh=10:120:10 -o map.zarr
  vibimpact map --eta 0.9:1.5:0.005 --vary f=0:0.1:0.01 --preset fig11 \\
      --direction both -o f.nc --plot f.png
  vibimpact map --eta 0.9:1.5:0.002 --vary kh=10:120:1 \\
      --scheduler tcp://scheduler-host:8786 -o fine.zarr
  vibimpact plot map.zarr --kind map -o map.png

Every row (one value of the varied parameter) is an eta sweep with continuation, as in
'vibimpact classify --blocks 1'; rows are independent tasks.  Without --scheduler they run
on a local Dask cluster of --workers processes (1: in this process); with --scheduler on
the workers of a running Dask cluster (an address, or a scheduler file as written by
'dask scheduler --scheduler-file', dask-jobqueue or dask-mpi).  The result never depends
on where or in which order rows run.

Each finished row is saved at once in the checkpoint directory OUT.partial (one file
per row, the format of a classify checkpoint; 'vibimpact plot OUT.partial --kind map'
draws the map so far).  After Ctrl-C, a kill or a lost cluster, run the same command
again with --resume: the saved rows are loaded, not recomputed, and the map is identical
to an uninterrupted run.

OUT.zarr is a Zarr store, OUT.nc a NetCDF file; dims (PARAM, eta) or, with --direction
both, (direction, PARAM, eta); variables as in a classify file (regime, label, period,
impacts_per_period, lyapunov, ...).  --vary takes START:STOP:STEP (STOP included when on
the grid) or a comma-separated list of values.

exit status: 0 written, 2 bad input (nothing computed) or Dask workers died more
often than Dask retries (checkpoint kept), 130 interrupted (Ctrl-C), 143
terminated (SIGTERM).
"""


def parse_vary(text, preset_params):
    """``NAME=START:STOP:STEP`` or ``NAME=V1,V2,...`` -> ``(name, values)``.

    Raises
    ------
    UsageError
        Naming the problem (the size check and the parameter's domain included).
    """
    import numpy as np

    from ..maps.map2d import check_vary, parameter_names
    from ..sweeps import parse_range

    name, sep, spec = str(text).partition("=")
    name = name.strip()
    if not sep or not name or not spec.strip():
        raise UsageError(f"--vary expects NAME=START:STOP:STEP or NAME=V1,V2,..., "
                          f"got {text!r}")
    if name == "eta":
        raise UsageError("--vary: eta is the map's other axis; set its grid with --eta")
    known = parameter_names(preset_params)  # the preset's model's parameters
    if name not in known:
        raise UsageError(f"--vary: unknown parameter {name!r}; choose one of "
                          f"{', '.join(known)}")
    try:
        values = parse_range(spec, name=name, positive=False)
    except ValueError as exc:
        raise UsageError(f"--vary: {error_text(exc)}") from None
    try:  # the values in the parameter's domain; the message names the option itself
        check_vary(preset_params, {name: values}, label="--vary")
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    return name, np.asarray(values, dtype=float)


def _check_map_output(out, overwrite, size):
    from ..maps.store import output_format

    try:
        fmt = output_format(out)
    except ValueError as exc:
        raise UsageError(f"-o: {error_text(exc)}") from None
    if fmt == "netcdf":
        return check_output(out, overwrite, "output file", size=size)
    if os.path.lexists(out):
        if not overwrite:
            raise UsageError(f"output {out!r} exists; pass --overwrite to replace it")
        from ..maps.store import check_replaceable

        try:  # only what vibimpact wrote is replaced, never a user's directory
            check_replaceable(out)
        except ValueError as exc:
            raise UsageError(error_text(exc)) from None
    return check_output(out, True, "output", store=True, size=size)


def _inputs(args):
    """Parameters, eta grid, (name, values) from the parsed arguments."""
    from ..models import presets
    from ..maps.map2d import check_size
    from ..sweeps import parse_range

    try:
        etas = parse_range(swept(args))
    except ValueError as exc:
        raise UsageError(f"--eta: {exc}") from None
    sets = parse_sets(args.set)
    try:
        base = presets.get(args.preset)
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    params = with_sets(base, sets)
    if len(args.vary) != 1:
        raise UsageError("give exactly one --vary NAME=START:STOP:STEP (a map varies eta "
                          "and one other parameter)")
    name, values = parse_vary(args.vary[0], params)
    if name in sets:
        raise UsageError(f"{name} is both --set and --vary; give it only with --vary")
    rows = values.size * (2 if args.direction == "both" else 1)
    try:
        check_size(etas.size, rows, name)
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    return params, etas, name, values


def _cmd_map(args):
    import shlex
    import time

    out = os.fspath(args.output)
    params, etas, name, values = _inputs(args)
    analyses = parse_analyses(args.analyses)
    if args.scheduler is not None and args.workers is not None:
        raise UsageError("--workers is for local runs; the workers of --scheduler are "
                         "the cluster's")
    ckpt = checkpoint_of(os.fspath(args.output).rstrip("/" + os.sep))
    resuming = args.resume and ckpt.exists()
    size = sweep_file_bytes(params, etas.size * values.size, args.direction)
    out = _check_map_output(out, args.overwrite or (resuming and output_of(ckpt, out)), size)
    resumable = not getattr(args, "rerun_of", None)  # rerun has no --resume
    fig_kw = figure_options(args, drawing=args.plot is not None)
    if args.plot is not None:
        image_ext_ok(args.plot, "--plot")
        check_output(args.plot, args.overwrite, "plot file")
    from .common.inputs import check_distinct

    check_distinct(("-o", out), ("--plot", args.plot), ("the checkpoint", ckpt.path))
    check_checkpoint(ckpt, args.resume)

    from ..engine import cluster
    from ..engine.execution import Execution
    from ..maps import store
    from ..maps.map2d import map2d

    scheduler = None
    if args.scheduler is not None:
        try:
            scheduler, _ = cluster.connect(args.scheduler)
        except ValueError as exc:
            raise UsageError(f"--scheduler: {error_text(exc)}") from None
    workers = args.workers if args.workers is not None else min(2, os.cpu_count() or 1)
    t0 = time.perf_counter()
    try:
        run = Execution(workers=1 if scheduler is not None else workers,
                        scheduler=scheduler, task_points=args.task_points,
                        checkpoint=ckpt.path, resume=args.resume,
                        progress=not args.no_progress and "map")
        ds, status = run_checkpointed(ckpt, "rows", lambda: map2d(
            params, etas, {name: values}, direction=args.direction, analyses=analyses,
            execution=run), resumable=resumable)
    finally:
        if scheduler is not None:
            scheduler.close()
    if ds is None:
        return status
    elapsed = time.perf_counter() - t0
    ds.attrs.update(command=shlex.join(["vibimpact"] + list(args.argv)), preset=args.preset,
                    eta_range=args.eta, vary_range=args.vary[0])
    # with --plot the checkpoint goes only once the image is written too
    loaded = finish_checkpointed(ds, out, ckpt, store.write_map, resuming=resuming,
                                 keep=args.keep_checkpoint or args.plot is not None,
                                 overwrite=args.overwrite, unit="rows",
                                 resumable=resumable)
    _summary(ds, elapsed, computed=ds["regime"].size - loaded)
    if args.plot is not None:
        _plot_or_undo(ds, out, ckpt, args, fig_kw)
    return 0


def _plot_or_undo(ds, out, ckpt, args, fig_kw):
    """Draw the map's --plot image; if that fails, remove ``out`` again (the outputs
    succeed or fail together) and keep the checkpoint, so that --resume loses nothing."""
    import shutil

    from ..plotting.map2d import plot_map

    try:
        plot_map(ds, path=args.plot, **fig_kw)
    except (ValueError, OSError) as exc:
        if os.path.isdir(out):
            shutil.rmtree(out, ignore_errors=True)
        elif os.path.exists(out):
            os.unlink(out)
        raise UsageError(f"--plot: {error_text(exc)} ({out!r} removed again; the computed "
                         f"rows stay in {os.fspath(ckpt.path)}: fix the problem and rerun "
                         "with --resume)") from None
    if not args.keep_checkpoint:
        ckpt.remove()
    print(f"wrote {args.plot}")


def _summary(ds, elapsed, computed):
    import numpy as np

    reg = np.asarray(ds["regime"].values)
    counts = ", ".join(f"{k} {int((reg == c).sum())}" for k, c in
                       (("periodic", 1), ("quasi-periodic", 2), ("chaotic", 3),
                        ("diverged", 4), ("unsettled", 5)))
    # a count of directions is a noun's; kh, eta, ... are the parameters' symbols
    shape = " x ".join(count(ds.sizes[d], d) if d == "direction" else f"{ds.sizes[d]} {d}"
                       for d in ds["regime"].dims)
    print(f"map {shape} = {count(reg.size, 'point')}: {counts} ({computed} computed in "
          f"{elapsed:.1f} s, {computed / max(elapsed, 1e-9):.1f} points/s)")


def add_parser(sub, fmt):
    """Add ``map`` to the subparsers ``sub``."""
    m = sub.add_parser("map", help="regime map over eta and one other parameter (Dask)",
                       formatter_class=fmt, epilog=_MAP_EPILOG,
                       description="Sweep eta with continuation for every value of one "
                                   "other parameter and classify\nevery point; rows run "
                                   "as tasks on local processes or a Dask cluster.")
    m.add_argument("--eta", default=MAP_FREQUENCIES, metavar="START:STOP:STEP|V1,V2,...",
                   help="grid of the forcing frequency: a range or a list of "
                        f"increasing values (default: {MAP_FREQUENCIES})")
    m.add_argument("--vary", action="append", default=[], required=True,
                   metavar="NAME=START:STOP:STEP",
                   help="the other axis: a parameter and its values, e.g. kh=10:120:10 or "
                        "f=0,0.02,0.05")
    m.add_argument("--preset", default=DEFAULT_PRESET, type=preset_name,
                   help=f"parameter set (default: {DEFAULT_PRESET_HELP}); see "
                        "'vibimpact presets'")
    m.add_argument("--set", action="append", metavar="NAME=VALUE", default=[],
                   help="change a parameter of the preset, e.g. BT=0.05 (repeatable)")
    m.add_argument("--direction", choices=("up", "down", "both"), default="up",
                   help="continuation direction along eta (default: up)")
    m.add_argument("--analyses", default="period,impacts,lyapunov", metavar="A,B,...",
                   help="what to compute (default: period,impacts,lyapunov: regime, "
                        "period, impacts per period, and the largest exponent only where "
                        "no period is found); see 'vibimpact classify --help'")
    m.add_argument("--workers", type=positive_int(1, MAX_WORKERS), default=None, metavar="N",
                   help="local processes (default: min(2, CPUs)); 1 runs in this process")
    m.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="run the rows on a Dask cluster: scheduler address "
                        "(tcp://host:8786) or scheduler file")
    m.add_argument("--task-points", type=positive_int(1), default=300, metavar="N",
                   help="least points per task: short rows are grouped (default: 300)")
    m.add_argument("-o", "--output", default="map.zarr", metavar="OUT.zarr|OUT.nc",
                   help="Zarr store or NetCDF file to write (default: map.zarr)")
    m.add_argument("--plot", metavar="FIG.png", default=None,
                   help="also draw the map (as 'vibimpact plot OUT --kind map')")
    add_figure_options(m, "the --plot image")
    m.add_argument("--resume", action="store_true",
                   help="continue an interrupted run from its checkpoint OUT.partial")
    m.add_argument("--keep-checkpoint", action="store_true",
                   help="keep OUT.partial after OUT is written")
    m.add_argument("--overwrite", action="store_true", help="replace existing output files")
    m.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")
    m.set_defaults(func=_cmd_map)


__all__ = ["add_parser", "parse_vary"]
