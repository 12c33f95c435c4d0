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
scheduling cost per task stays negligible.  A map with ``direction="both"`` has
two rows per parameter value, computed independently.  Which rows share a task, how
many workers there are and in which order tasks finish never change a number: serial,
local-process and cluster maps are bit-identical.

Engine and checkpoints
----------------------
The work is done by :mod:`vibimpact.engine`: every ``(row, direction)`` is one task of
the plan (one block: ``blocks=1``), tasks are grouped into jobs of at least
``task_points`` points and run by the executor of the :class:`~vibimpact.Execution`: this
process, Dask (:class:`vibimpact.engine.cluster.Dask`) or a user's.  With
``vi.Execution(checkpoint=...)`` every finished row is saved at once as one entry of the
checkpoint (:mod:`vibimpact.engine.store`, the format of a sweep's checkpoint), by this
process as the results arrive, and ``resume=True`` loads the saved rows instead of
recomputing them.  :func:`partial_map` reads a checkpoint as
the map so far.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import json
import sys
from collections.abc import Mapping

import numpy as np

from ..base import _limits
from ..base._text import one_line
from ..base import _validate as _v
from .. import models
from ..core.system import (System, param_dict, to_system, varied_names, with_frequency,
                           with_values)
from ..sweeps.sweep import check_grid, check_request, snap_grid
from ..engine.execution import Execution, as_execution, refuse_moved

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Sequence

    import xarray as xr
    from numpy.typing import ArrayLike

    from ..points.point import SweepSettings
    from ..models.params import DuffingParams, Params

#: what a map computes by default: the regime, the period, the impacts per period, and
#: the largest Lyapunov exponent only where no period is found
MAP_ANALYSES = ("period", "impacts", "lyapunov")
#: most points of one map (hours on one core at the rate reports/performance.md, section
#: map, measures)
MAX_MAP_POINTS = 2_000_000
#: the flag variable of :func:`partial_map`
DONE = "row_done"


def parameter_names(p: Params | DuffingParams | System | None = None) -> list[str]:
    """Names of the parameters a map can vary: every parameter of ``p``'s model (by
    default the model of the default preset, :data:`vibimpact.models.presets.DEFAULT`) but
    the forcing frequency."""
    from ..models import presets

    return varied_names(presets.get() if p is None else p)


def check_vary(p, vary, label="vary"):
    """``(name, values)`` of a valid ``vary`` argument.

    Parameters
    ----------
    p : Params, DuffingParams or System
    vary : dict
        ``{name: values}``.
    label : str
        How the messages name ``vary``: the argument (``"vary"``), or the option of an
        interface that gives it otherwise (the command line's ``"--vary"``).

    Returns
    -------
    name : str
    values : ndarray, shape (m,)
        The values, each within a few units in the last place of its rounding to 12
        decimals taken as that rounding (as eta's, :func:`vibimpact.sweeps.sweep.
        snap_grid`), so that ``np.arange(0.02, 0.1 + 1e-12, 0.01)`` or ``0.02 + 0.01 * k``
        gives the command line's ``--vary f=0.02:0.1:0.01`` values.

    Raises
    ------
    ValueError
        Naming the problem: not one ``{name: values}`` entry, an unknown parameter or
        eta, values that are not finite numbers, not strictly increasing, too many, or
        outside the parameter's domain (as :class:`Params` checks it).
    """
    if not isinstance(vary, Mapping) or len(vary) != 1:
        raise ValueError(f"{label} must be a dict with one entry {{name: values}}, e.g. "
                         "{'NAME': [v1, v2, ...]}, got "
                         f"{vary!r}"[:200])
    (name, values), = vary.items()
    names = parameter_names(p)
    freq = to_system(p).model
    freq = freq.param_names[freq.omega_index]
    if name == freq:
        raise ValueError(f"{label}: {freq} is the map's other axis (eta=...); vary one "
                         f"of {', '.join(names)}")
    if name not in names:
        raise ValueError(f"{label}: unknown parameter {name!r}; choose one of "
                         f"{', '.join(names)}")
    if isinstance(values, np.ndarray):
        _limits.check_points(values.size, name=name)
    arr = _v.array1d(f"{label} {name}: values", values)
    if arr.size == 0:
        raise ValueError(f"{label} {name}: no values")
    _limits.check_points(arr.size, name=name)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{label} {name}: values must be finite")
    if arr.size > 1 and not np.all(np.diff(arr) > 0.0):
        raise ValueError(f"{label} {name}: values must be strictly increasing")
    arr = snap_grid(arr)  # an arange's values as the command line's range gives them
    for v in (arr[0], arr[-1]):  # the domains are intervals: the ends decide
        try:
            with_values(p, **{name: float(v)})
        except ValueError as exc:
            raise ValueError(f"{label} {name}: {exc}") from None
    return name, arr


def check_size(n_eta, n_rows, name):
    """ValueError when a map of ``n_eta x n_rows`` points is over :data:`MAX_MAP_POINTS`."""
    total = n_eta * n_rows
    if total > MAX_MAP_POINTS:
        cost = _limits.human_duration(total * _limits.SECONDS_PER_POINT)
        raise ValueError(f"map eta x {name} has {total} points (about {cost} on one core "
                         f"at ~{_limits.SECONDS_PER_POINT:g} s per point); at most "
                         f"{MAX_MAP_POINTS}")


def row_arrays(p, etas, direction, points, settings):
    """``{variable: values along eta}`` of one row from its points' results in sweep
    order: the data of the sweep dataset of the row (``blocks=1``)."""
    from ..sweeps.dataset import to_dataset

    ds = to_dataset(p, etas, (direction,), {direction: points}, settings,
                    direction=direction, continuation=True, blocks=1, command="")
    return {k: ds[k].values for k in ds.data_vars}


def _request(p, name, values, etas, dirs, settings, state0):
    """Everything a map's rows depend on, JSON-able (its checkpoint's fingerprint)."""
    return dict(kind="map", params=param_dict(p), vary=name, values=values.tolist(),
                eta=etas.tolist(), directions=list(dirs), settings=settings.as_attrs(),
                state0=None if state0 is None else state0.tolist())


class _Rows:
    """The map being filled: ``on_task`` writes a finished row into the dataset."""

    def __init__(self, ds, p, name, values, etas, dirs, settings, shapes):
        self.ds, self.p, self.name, self.values = ds, p, name, values
        self.etas, self.dirs, self.settings, self.shapes = etas, dirs, settings, shapes
        self.both = "direction" in ds.dims

    def at(self, d, i):
        return (self.dirs.index(d), i) if self.both else (i,)

    def fill(self, row, d, points):
        """``points``: ``{position: result}`` or ``[(position, result)]`` of a row."""
        points = dict(points)
        res = [points.get(i) for i in range(self.etas.size)]
        p = with_values(self.p, **{self.name: float(self.values[row])})
        arrays = row_arrays(p, self.etas, d, res, self.settings)
        for k in self.shapes:
            self.ds[k].values[self.at(d, row)] = arrays[k]  # the dataset's own arrays

    def on_task(self, task, points):
        try:
            self.fill(task.row, task.direction, points)
        except Exception as exc:
            v = self.values[task.row]
            raise RuntimeError(f"map row {self.name} = {v:g}, sweep {task.direction}: "
                               f"{one_line(exc)}") from exc


def _template(p, name, values, etas, dirs, direction, settings, command):
    """The map dataset with every point "not computed", and ``{var: (shape, dtype)}`` of
    one row."""
    import xarray as xr

    from ..sweeps.dataset import to_dataset

    base = to_dataset(p, etas, ("up",), {"up": [None] * etas.size}, settings,
                      direction="up", continuation=True, blocks=1, command="")
    if "poincare" not in settings.analyses:
        base = base.drop_vars([v for v in base.data_vars
                               if isinstance(v, str) and v.startswith("poincare_")])
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
    params = param_dict(p)
    mdl = to_system(p).model
    for k in (mdl.param_names[mdl.omega_index], name):
        params.pop(k, None)
    attrs.update(title="vibimpact parameter map", map_vary=name, sweep_direction=direction,
                 params=json.dumps(params, sort_keys=True), map_rows=int(values.size),
                 command=command if command is not None else " ".join(sys.argv))
    if direction != "both":
        ds = ds.isel(direction=0, drop=True)
        attrs["direction"] = direction
    ds.attrs = attrs
    shapes = {k: (var.shape, var.dtype) for k, var in base.data_vars.items()}
    return ds, shapes


@refuse_moved
def map2d(p: Params | DuffingParams | System, eta: ArrayLike, vary: Mapping[str, ArrayLike],
          direction: str = "up", analyses: Sequence[str] = MAP_ANALYSES, *,
          settings: SweepSettings | None = None, state0: ArrayLike | None = None,
          execution: Execution | None = None) -> xr.Dataset:
    """Regime map over eta and one other parameter, rows computed on Dask.

    Parameters
    ----------
    p : System or a built-in model's parameter set (Params, DuffingParams, ...)
        The system (any model, a user model too), or the parameters of a built-in model
        (its forcing frequency and its value of the varied parameter are ignored).
    eta : array_like, shape (n,)
        Strictly increasing grid of the forcing frequency ratio.  A value within a few
        units in the last place of its rounding to 12 decimals is taken as that rounding
        (:func:`vibimpact.sweeps.sweep.snap_grid`), so that ``np.arange(...)`` gives the
        command line's grid (``vi.grid``) and is stored so; other values are kept.
    vary : dict
        One entry ``{name: values}``: a parameter of the model other than its forcing
        frequency (:attr:`vibimpact.Model.param_names`) and its strictly increasing,
        finite values, e.g. ``{"kh": np.arange(10, 121, 10)}`` for the built-in rotor; snapped
        to their 12-decimal rounding as eta is, so ``np.arange`` gives the command
        line's ``--vary`` values.
    direction : {"up", "down", "both"}
        Direction of the continuation along eta in every row.
    analyses : sequence of str
        As in :func:`vibimpact.sweep`; by default what a map needs: regime, period,
        impacts per period, and the largest exponent only where no period is found.
    settings : SweepSettings, optional
        Transients, record lengths, exponent and classifier settings of every point.
    state0 : array_like, shape (n_state,), optional
        State at the first point of every row (rest by default).
    execution : Execution, optional
        Where and how it runs, none of which changes a number (:class:`vibimpact.
        Execution`).  ``workers`` (1: in this process; more: a Dask ``LocalCluster``),
        ``scheduler`` (a Dask address, scheduler file, ``distributed.Client`` or cluster
        object), or a user's ``executor``; ``task_points``: least points per job (rows
        are grouped up to this); ``checkpoint``: directory where every finished row is
        saved at once, and ``resume`` to load its rows instead of recomputing them;
        ``progress``: a bar named "map" (True) or by the text given, or a callable
        ``progress(k)``.  SIGINT and SIGTERM stop the workers and raise
        :class:`vibimpact.Interrupted`; the saved rows stay in the checkpoint.

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
        For invalid input (naming it), a scheduler that cannot be reached, or a
        checkpoint of a different request; a ``TypeError`` (also a ``ValueError``) for
        the keywords of the former signature (``workers=``, ``store=``, ...), saying
        where each went.

    Examples
    --------
    >>> import numpy as np, vibimpact as vi
    >>> ds = vi.map2d(vi.presets.get("fig8"), eta=np.arange(1.0, 1.1, 0.02),
    ...               vary={"kh": [40.0, 80.0]})                      # doctest: +SKIP
    >>> ds.regime.dims                                                # doctest: +SKIP
    ('kh', 'eta')
    """
    from ..engine import plan, progress as prog
    from ..engine.compute import compute
    from ..engine.policy import Continuation

    if not isinstance(p, System) and models.of_params(p) is None:
        raise _v.WrongType(f"p must be a vibimpact.System or the parameter set of a "
                           f"built-in model ({models.param_set_names()}), got "
                           f"{type(p).__name__}")
    execution = as_execution(execution)
    name, values = check_vary(p, vary)
    etas = check_grid(eta)
    settings, state0 = check_request(direction, analyses, settings, state0,
                                     to_system(p).n_state)
    check_size(etas.size, values.size * (2 if direction == "both" else 1), name)
    _limits.check_memory(_limits.points_bytes(
        etas.size * values.size * (2 if direction == "both" else 1), settings.n_samples,
        to_system(p).n_state), f"a map of eta x {name} with {settings.n_samples} "
        "Poincare samples per point")
    task_points = execution.task_points
    p = with_values(with_frequency(p, 1.0), **{name: float(values[0])})
    dirs = plan.directions(direction)

    ds, shapes = _template(p, name, values, etas, dirs, direction, settings, None)
    rows = _Rows(ds, p, name, values, etas, dirs, settings, shapes)
    ckpt, done = execution.open_checkpoint(
        "map", _request(p, name, values, etas, dirs, settings, state0),
        dict(rows=int(values.size), directions=list(dirs), points=int(etas.size)),
        what="map checkpoint")
    done = {k: v for k, v in done.items() if len(v) == etas.size}  # whole rows only
    for (r, d), points in done.items():
        rows.fill(r, d, points)
    params = [with_values(p, **{name: float(v)}) for v in values]
    tasks = plan.plan(params, etas, dirs, settings, state0, Continuation(blocks=1),
                      done=done)
    with prog.callback(execution.progress, sum(t.todo for t in tasks), "map") as report:
        compute(tasks, execution.map_executor(), rows.on_task, store=ckpt,
                progress=report, stream=False,
                make_jobs=lambda slots: plan.group(tasks, task_points, slots))
    return ds


def _recorded_set(values):
    """The parameter set of the built-in model whose parameters are exactly those a map's
    request records."""
    from .. import models

    for mname in models.names():
        model = models.get(mname)
        if model.param_set is not None and set(model.param_names) == set(values):
            return model.param_set(**values)
    raise ValueError(f"the map checkpoint's parameters ({', '.join(values)}) are no "
                     "built-in model's")


def partial_map(path):
    """The map so far in the checkpoint ``path`` of a running or interrupted map.

    Rows not saved yet hold the "not computed" values; the variable ``row_done`` (dims
    the rows', ``(direction, PARAM)`` or ``(PARAM,)``) is 1 for the saved rows.

    Raises
    ------
    ValueError
        ``path`` is not a map checkpoint.
    """
    from ..engine.plan import settings_from_attrs
    from ..engine.store import Checkpoint

    ckpt = Checkpoint(path, what="map checkpoint")
    record = ckpt.attach()
    req = record.get("request", {})
    if record.get("kind") != "map":
        raise ValueError(f"{path!r} is not a vibimpact map checkpoint")
    name, values = req["vary"], np.asarray(req["values"], dtype=float)
    etas, dirs = np.asarray(req["eta"], dtype=float), tuple(req["directions"])
    direction = "both" if len(dirs) == 2 else dirs[0]
    settings = settings_from_attrs(req["settings"])
    p = _recorded_set(req["params"])
    ds, shapes = _template(p, name, values, etas, dirs, direction, settings, "")
    rows = _Rows(ds, p, name, values, etas, dirs, settings, shapes)
    flags = np.zeros(ds["regime"].shape[:-1], dtype=np.int8)
    for (r, d), points in ckpt.load(resume=False).items():
        if len(points) == etas.size:
            rows.fill(r, d, points)
            flags[rows.at(d, r)] = 1
    ds[DONE] = (ds["regime"].dims[:-1], flags,
                dict(long_name="row completely saved",
                     flag_values=np.array([0, 1], dtype=np.int8),
                     flag_meanings="not_saved saved"))
    return ds
