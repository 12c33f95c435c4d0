"""`map2d`: regime maps over the forcing frequency eta and one other parameter.

Rows
----
A map is a stack of *rows*: row ``j`` is the frequency sweep of :func:`vibimpact.sweep`
at ``{name: values[j]}``, swept up and/or down with pure serial continuation along eta
(``blocks=1``: every point starts from the previous point's final state, the first from
``state0``).  Rows do not depend on each other, so they are the unit of parallel work,
and a map's row equals the 1-D sweep with the same parameters, bit for bit.

Tasks
-----
Rows are grouped into tasks of at least ``task_points`` points (one row per task as soon
as a row has that many), so that every task runs for about a second or more and Dask's
scheduling cost (~1 ms per task) stays negligible.  A map with ``direction="both"`` has
two rows per parameter value, computed independently.  Which rows share a task, how
many workers there are and in which order tasks finish never change a number: serial,
local-process and cluster maps are bit-identical.

Checkpoints
-----------
With ``store=`` every finished row is written at once into a Zarr store laid out like
the map (:mod:`vibimpact.maps.checkpoint`), by this process as the results arrive, and
``resume=True`` loads the saved rows instead of recomputing them.
"""
from __future__ import annotations

import sys
import threading
from collections.abc import Mapping
from dataclasses import fields

import numpy as np

from .. import _limits
from ..params import Params
from .. import _validate as _v
from ..sweeps.sweep import _grid, check_request, sweep
from . import execute
from .checkpoint import RowStore

#: what a map computes by default: the regime, the period, the impacts per period, and
#: the largest Lyapunov exponent only where no period is found
MAP_ANALYSES = ("period", "impacts", "lyapunov")
#: most points of one map (about 2 hours on one core at ~3 ms per point)
MAX_MAP_POINTS = 2_000_000
#: least points per task (~1 s or more of work at 200-400 points per second and core,
#: reports/performance.md)
DEFAULT_TASK_POINTS = 300

#: one row at a time per process: the numba integrator holds the GIL (threads would not
#: run rows in parallel anyway), and threads of a multi-threaded worker must not share the
#: sweep module's global progress hook
_ROW_LOCK = threading.Lock()


def parameter_names():
    """Names of the parameters a map can vary (every field of :class:`Params` but eta)."""
    return tuple(f.name for f in fields(Params) if f.name != "eta")


def check_vary(p, vary):
    """``(name, values)`` of a valid ``vary`` argument.

    Raises
    ------
    ValueError
        Naming the problem: not one ``{name: values}`` entry, an unknown parameter or
        eta, values that are not finite numbers, not strictly increasing, too many, or
        outside the parameter's domain (as :class:`Params` checks it).
    """
    if not isinstance(vary, Mapping) or len(vary) != 1:
        raise ValueError("vary must be a dict with one entry {name: values}, e.g. "
                         "{'kh': [10, 20, 40]}, got "
                         f"{vary!r}"[:200])
    (name, values), = vary.items()
    names = parameter_names()
    if name == "eta":
        raise ValueError("vary: eta is the map's other axis (eta=...); vary one of "
                         f"{', '.join(names)}")
    if name not in names:
        raise ValueError(f"vary: unknown parameter {name!r}; choose one of "
                         f"{', '.join(names)}")
    if isinstance(values, np.ndarray):
        _limits.check_points(values.size, name=name)
    try:
        arr = np.array(values, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"vary {name}: values must be numbers, got {values!r}"[:200]) \
            from None
    if arr.size == 0:
        raise ValueError(f"vary {name}: no values")
    _limits.check_points(arr.size, name=name)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"vary {name}: values must be finite")
    if arr.size > 1 and not np.all(np.diff(arr) > 0.0):
        raise ValueError(f"vary {name}: values must be strictly increasing")
    for v in (arr[0], arr[-1]):  # the domains are intervals: the ends decide
        try:
            p.replace(**{name: float(v)})
        except ValueError as exc:
            raise ValueError(f"vary {name}: {exc}") from None
    return name, arr


def check_size(n_eta, n_rows, name):
    """ValueError when a map of ``n_eta x n_rows`` points is over :data:`MAX_MAP_POINTS`."""
    total = n_eta * n_rows
    if total > MAX_MAP_POINTS:
        cost = _limits.human_duration(total * _limits.SECONDS_PER_POINT)
        raise ValueError(f"map eta x {name} has {total} points (about {cost} on one core "
                         f"at ~{_limits.SECONDS_PER_POINT:g} s per point); at most "
                         f"{MAX_MAP_POINTS}")


def compute_rows(task):
    """Compute the rows of one task (this runs on a worker).

    Parameters
    ----------
    task : tuple
        ``(p, name, etas, settings, state0, rows)`` with ``rows`` a list of
        ``(direction, index, value)``.

    Returns
    -------
    list of (direction, index, dict)
        Per row, ``{variable: values along eta}`` of its sweep dataset.
    """
    p, name, etas, settings, state0, rows = task
    out = []
    with _ROW_LOCK:
        for d, i, v in rows:
            try:
                ds = sweep(p.replace(**{name: v}), etas, direction=d,
                           analyses=settings.analyses, settings=settings, state0=state0,
                           blocks=1, workers=1, command="")
            except Exception as exc:
                raise RuntimeError(f"map row {name} = {v:g}, sweep {d}: "
                                   f"{type(exc).__name__}: {exc}") from exc
            out.append((d, i, {k: ds[k].values for k in ds.data_vars}))
    return out


def _make_tasks(head, rows, n_eta, task_points, slots):
    per = max(1, -(-task_points // n_eta))
    if slots:  # keep every worker busy: at least two tasks per worker thread
        per = min(per, max(1, len(rows) // (2 * slots)))
    return [head + (rows[k:k + per],) for k in range(0, len(rows), per)]


def _template(p, name, values, etas, dirs, direction, settings, command):
    """The map dataset with every point "not computed", and ``{var: (shape, dtype)}`` of
    one row."""
    import xarray as xr

    from ..sweeps.dataset import to_dataset

    base = to_dataset(p, etas, ("up",), {"up": [None] * etas.size}, settings,
                      direction="up", continuation=True, blocks=1, command="")
    if "poincare" not in settings.analyses:
        base = base.drop_vars(["poincare_X", "poincare_Y"])
    lead = ("direction", name)
    data = {}
    for k, var in base.data_vars.items():
        arr = np.empty((len(dirs), values.size) + var.shape, dtype=var.dtype)
        arr[...] = var.values
        data[k] = (lead + var.dims, arr, var.attrs)
    ds = xr.Dataset(data, coords={
        "eta": base["eta"], "state": base["state"],
        name: (name, values, dict(units="1", long_name=f"varied parameter {name}")),
        "direction": ("direction", np.array(dirs, dtype=object),
                      dict(long_name="sweep direction"))})
    # the row template's own direction ("up") is not the map's: set below for a one-way map
    attrs = {k: v for k, v in base.attrs.items() if k not in (f"param_{name}", "direction")}
    params = p.as_dict()
    for k in ("eta", name):
        params.pop(k, None)
    attrs.update(title="vibimpact parameter map", map_vary=name, sweep_direction=direction,
                 params=_json(params), map_rows=int(values.size),
                 command=command if command is not None else " ".join(sys.argv))
    if direction != "both":
        ds = ds.isel(direction=0, drop=True)
        attrs["direction"] = direction
    ds.attrs = attrs
    shapes = {k: (var.shape, var.dtype) for k, var in base.data_vars.items()}
    return ds, shapes


def _json(obj):
    import json

    return json.dumps(obj, sort_keys=True)


def map2d(p, eta, vary, direction="up", analyses=MAP_ANALYSES, *, settings=None,
          state0=None, scheduler=None, workers=1, task_points=DEFAULT_TASK_POINTS,
          store=None, resume=False, progress=False, command=None):
    """Regime map over eta and one other parameter, rows computed on Dask.

    Parameters
    ----------
    p : Params
        All other parameters (its ``eta`` and its value of the varied one are ignored).
    eta : array_like, shape (n,)
        Strictly increasing grid of the forcing frequency ratio.
    vary : dict
        One entry ``{name: values}``: a :class:`Params` field other than ``eta`` and its
        strictly increasing, finite values, e.g. ``{"kh": np.arange(10, 121, 10)}``.
    direction : {"up", "down", "both"}
        Direction of the continuation along eta in every row.
    analyses : sequence of str
        As in :func:`vibimpact.sweep`; by default what a map needs: regime, period,
        impacts per period, and the largest exponent only where no period is found.
    settings : SweepSettings, optional
        Transients, record lengths, exponent and classifier settings of every point.
    state0 : array_like, shape (4,), optional
        State at the first point of every row (rest by default).
    scheduler : optional
        None: run here (``workers == 1``) or on a ``LocalCluster`` of ``workers``
        processes.  Otherwise a Dask scheduler address (``tcp://host:8786``), a scheduler
        file, a ``distributed.Client`` or a cluster object (``LocalCluster``,
        dask-jobqueue's ``SLURMCluster``, ...); ``workers`` is then ignored.
    workers : int
        Local processes when ``scheduler`` is None.
    task_points : int
        Least points per Dask task (rows are grouped up to this); never changes results.
    store : path, optional
        Row checkpoint, a Zarr store laid out like the map: every finished row is written
        into it at once (:mod:`vibimpact.maps.checkpoint`).
    resume : bool
        Continue the map saved in ``store``: its rows are loaded, not recomputed.
    progress : bool
        A progress bar (points) on stderr.
    command : str, optional
        The command line to record in the attributes.

    Returns
    -------
    xarray.Dataset
        Dims ``(name, eta)`` (``(direction, name, eta)`` for ``direction="both"``) with
        the variables of a sweep dataset (:func:`vibimpact.sweeps.to_dataset`): regime,
        label, period, impacts_per_period, lyapunov, ...  ``ds.sel({name: v})`` is a
        sweep dataset, so :func:`vibimpact.intervals` and the sweep plots work on a row.

    Raises
    ------
    ValueError
        For invalid input (naming it), a scheduler that cannot be reached, or a ``store``
        of a different request.

    Examples
    --------
    >>> import numpy as np, vibimpact as vi
    >>> ds = vi.map2d(vi.presets.get("fig8"), eta=np.arange(1.0, 1.1, 0.02),
    ...               vary={"kh": [40.0, 80.0]})                      # doctest: +SKIP
    >>> ds.regime.dims                                                # doctest: +SKIP
    ('kh', 'eta')
    """
    if not isinstance(p, Params):
        raise ValueError(f"p must be vibimpact.Params, got {type(p).__name__}")
    name, values = check_vary(p, vary)
    etas = _grid(eta)
    settings, state0 = check_request(direction, analyses, settings, state0)
    check_size(etas.size, values.size * (2 if direction == "both" else 1), name)
    workers = _v.count("workers", workers, 1)
    task_points = _v.count("task_points", task_points, 1)
    p = p.replace(eta=1.0, **{name: float(values[0])})
    dirs = ("up", "down") if direction == "both" else (direction,)

    ds, shapes = _template(p, name, values, etas, dirs, direction, settings, command)
    request = dict(kind="map", params=p.as_dict(), vary=name, values=values.tolist(),
                   eta=etas.tolist(), directions=dirs, settings=settings.as_attrs(),
                   state0=None if state0 is None else state0.tolist())
    rows = RowStore.open(store, ds, request, resume) if store is not None else None

    def at(d, i):
        return (i,) if direction != "both" else (dirs.index(d), i)

    results = {}
    todo = []
    for i, v in enumerate(values):
        for d in dirs:
            row = None if rows is None else rows.load(at(d, i), shapes)
            if row is None:
                todo.append((d, i, float(v)))
            else:
                results[(d, i)] = row
    if rows is not None and resume:
        rows.record_damaged()
    bar = None
    if progress and todo:
        from tqdm import tqdm
        bar = tqdm(total=len(todo) * etas.size, desc="map", unit="pt", file=sys.stderr)

    def on_result(out):
        for d, i, arrays in out:
            arrays = {k: arrays[k] for k in shapes}
            if rows is not None:
                rows.save(at(d, i), arrays)
            results[(d, i)] = arrays
            if bar is not None:
                bar.update(etas.size)

    head = (p, name, etas, settings, state0)
    try:
        if todo:
            execute.run_tasks(
                _call_compute_rows, lambda slots: _make_tasks(head, todo, etas.size,
                                                              task_points, slots),
                on_result, scheduler=scheduler, workers=workers)
    finally:
        if bar is not None:
            bar.close()

    for (d, i), arrays in results.items():
        for k, arr in arrays.items():
            ds[k].values[at(d, i)] = arr  # the dataset's own NumPy arrays, filled in place
    return ds


def _call_compute_rows(task):
    """Looked up by name at call time (tests count calls through the module attribute)."""
    return sys.modules[__name__].compute_rows(task)
