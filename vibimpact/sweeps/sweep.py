"""`sweep`: the forcing frequency swept up and/or down with continuation, into an xarray Dataset.

Continuation and parallelism
----------------------------
Each point starts from the previous point's final state (in sweep order) inside each of
``blocks`` blocks (16 by default), so hysteresis and jumps show as in the paper; every
block but the first starts from a short seeding pass, and ``blocks=1`` is one unbroken
continuation.  The sweep order is cut into ``blocks`` contiguous blocks
(``vi.Continuation(blocks=...)``) to use several cores.  Block ``b`` starts from a
*seed*: the state reached by a cheap serial pass that continues through every grid point
before it (``seed_periods`` forcing periods per point, no analyses).  Blocks then run
independently, so the executor (``vi.Execution(workers=...)`` or any other) only decides
where and when they run: the result depends on ``blocks`` (1 = pure serial
continuation), never on the execution, and serial and parallel runs on one machine are
bit-identical (the conditions: the user guide's reproducibility page).  With
``direction="both"`` the up and down sweeps are independent streams as well.

The work is done by :mod:`vibimpact.engine` (a sweep is the one-row case of a map): the
request is planned into tasks (:mod:`vibimpact.engine.plan`) under a continuation policy
(:mod:`vibimpact.engine.policy`), run by the executor of its
:class:`~vibimpact.Execution` (this process, local processes, Dask or a user's:
:mod:`vibimpact.engine.executors`), every finished point saved at once in the checkpoint
(:mod:`vibimpact.engine.store`).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import math

import numpy as np

from ..base import _limits
from ..base import _validate as _v
from ..base._text import count, parse_real
from .. import models
from ..core.system import System, param_dict, to_system, with_frequency
from ..points.point import ANALYSES, SweepSettings
from ..engine.execution import Execution, as_execution, refuse_moved
from ..engine.policy import Continuation, Independent, as_policy

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Sequence

    import xarray as xr
    from numpy.typing import ArrayLike
    from ..models.params import DuffingParams, Params

DIRECTIONS = ("up", "down", "both")


#: the forcing frequencies a grid may hold (:data:`vibimpact.base._limits.ETA_RANGE`)
ETA_RANGE = _limits.ETA_RANGE


def check_frequency(values, name, text=None):
    """``values`` (forcing frequencies) unless one lies outside :data:`ETA_RANGE`: a
    ValueError naming ``name`` (the argument, or the option), with ``text`` as given."""
    arr = np.atleast_1d(np.asarray(values, dtype=np.float64))
    lo, hi = ETA_RANGE
    if arr.size and (arr.min() < lo or arr.max() > hi):
        got = repr(text) if text is not None else (
            f"{arr.min():.6g}" if arr.size == 1 else
            f"values from {arr.min():.6g} to {arr.max():.6g}")
        raise ValueError(f"{name} must lie in [{lo:g}, {hi:g}] (a forcing period 2 pi / "
                         f"eta the solver can resolve against the model's own time scale), "
                         f"got {got}")
    return values


def check_grid(eta):
    """``eta`` as a validated, strictly increasing float64 grid (ValueError naming it)."""
    size = np.size(eta) if isinstance(eta, np.ndarray) else None
    if size is not None:
        _limits.check_points(size)  # before copying a huge array
    arr = _v.array1d("eta", eta)
    if arr.size == 0:
        raise ValueError("eta must not be empty")
    _limits.check_points(arr.size)
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0.0):
        raise ValueError("eta must be finite and > 0")
    check_frequency(arr, "eta")
    if arr.size > 1 and not (np.all(np.diff(arr) > 0.0)):
        raise ValueError("eta must be strictly increasing (the direction is a separate "
                         "argument)")
    return snap_grid(arr)


#: a value of an ``eta`` array within this many units in the last place of its 12-decimal
#: rounding is taken as that rounding (:func:`snap_grid`)
SNAP_ULPS = 8


def snap_grid(arr):
    """``arr`` with every value within :data:`SNAP_ULPS` units in the last place of its
    rounding to 12 decimals replaced by that rounding (the rounding :func:`grid` and the
    command line give a range), values of :data:`ROUND_BELOW` and more, values whose
    rounding is 0 and any other value left as given; ``arr`` unchanged if the snapped
    grid would not be strictly increasing.

    So ``np.arange(0.9, 1.5 + 1e-12, 0.002)``, whose values differ from ``0.9 + k
    0.002`` typed by about 1e-16 (the arithmetic's error), becomes ``grid("0.9:1.5:0.002")``
    exactly, while a value meant to have more than 12 decimals (further away than the
    arithmetic's error) is kept.
    """
    small = np.abs(arr) < ROUND_BELOW
    rounded = arr.copy()
    rounded[small] = np.round(arr[small], 12)
    near = (small & (rounded != 0.0)
            & (np.abs(rounded - arr) <= SNAP_ULPS * np.spacing(np.abs(rounded))))
    out = np.where(near, rounded, arr)
    if out.size > 1 and not np.all(np.diff(out) > 0.0):
        return arr
    return out


def continued_state(p: object, eta: float, *,
                    eta_start: float = 1.0, step: float = 0.02, transient: int = 200,
                    state0: ArrayLike | None = None) -> np.ndarray:
    """State on the branch reached by sweeping the forcing frequency from ``eta_start``
    to ``eta`` (up, or down when ``eta < eta_start``).

    ``transient`` forcing periods at every grid point ``eta_start, eta_start ± step,
    ...`` up (down) to ``eta`` (and at ``eta`` itself when it is off that grid), each
    starting from the previous point's final state (rest, or ``state0``, at the first):
    one unbroken serial pass, not cut into blocks as :func:`sweep` is.
    A branch that coexists with the one a start from rest reaches (a hysteresis loop's
    other side) is reached this way.

    Parameters
    ----------
    p : Params, DuffingParams, System or str
        The parameters (any built-in model's parameter set), a System (run with its own
        solver settings), or a preset's name (:func:`vibimpact.models.presets.get`).
    eta : float
        The forcing frequency of the returned state (the model's frequency parameter,
        e.g. the built-in rotor's ``eta``), > 0.
    eta_start : float
        Where the sweep starts, > 0.
    step : float
        The grid's spacing, > 0.
    transient : int
        Forcing periods at each grid point, >= 0.
    state0 : array_like, optional
        The state at the first point (rest by default).

    Returns
    -------
    ndarray, shape (n_state,)
        The state at the start of a forcing period at ``eta``.

    Raises
    ------
    ValueError
        Naming ``p`` (not a parameter set, System or preset name; an unknown preset),
        ``eta``, ``eta_start``, ``step``, ``transient`` or ``state0``.
    """
    if isinstance(p, str):
        from ..models import presets

        try:
            p = presets.get(p)
        except ValueError as exc:
            raise ValueError(f"p: {exc}") from None
    elif not isinstance(p, System):
        try:
            p = to_system(p)
        except ValueError:
            raise _v.WrongType(f"p must be a parameter set ({models.param_set_names()}), "
                               f"a vibimpact.System or a preset's name, got "
                               f"{type(p).__name__}") from None
    system = to_system(p)
    eta = _v.positive("eta", eta)
    eta_start = _v.positive("eta_start", eta_start)
    step = _v.positive("step", step)
    transient = _v.count("transient", transient, 0)
    x = None if state0 is None else _v.state("state0", state0, system.n_state)
    last = eta_start
    sign = 1.0 if eta >= eta_start else -1.0
    for e in np.arange(eta_start, eta + sign * 1e-9, sign * step):
        x = with_frequency(system, float(e)).simulate(periods=1, transient=transient,
                                                      state0=x).final_state
        last = e
    if abs(eta - last) > 1e-9:
        x = with_frequency(system, eta).simulate(periods=1, transient=transient,
                                                 state0=x).final_state
    assert x is not None  # the loop ran at least once (its range holds eta_start)
    return x


def check_request(direction, analyses, settings, state0,
                  n_state=4) -> tuple[SweepSettings, np.ndarray | None]:
    """Validated ``(settings, state0)`` of a sweep or map request.

    ``settings`` (default :class:`SweepSettings`) gets ``analyses`` (in canonical order,
    "period" always included); ``state0`` becomes a float64 array of ``n_state`` or
    stays None.

    Raises
    ------
    ValueError
        Naming ``direction``, ``analyses``, ``settings`` or ``state0``.
    """
    _v.choice("direction", direction, DIRECTIONS)
    analyses = _v.names("analyses", analyses, ANALYSES)
    analyses = tuple(a for a in ANALYSES if a in analyses or a == "period")
    settings = SweepSettings() if settings is None else settings
    if not isinstance(settings, SweepSettings):
        raise _v.WrongType(f"settings must be a SweepSettings, got "
                           f"{type(settings).__name__}")
    settings = SweepSettings(**{**settings.__dict__, "analyses": analyses})
    if state0 is not None:
        state0 = _v.state("state0", state0, n_state)
    return settings, state0


@refuse_moved
def sweep(p: Params | DuffingParams | System, eta: ArrayLike, direction: str = "up",
          analyses: Sequence[str] = ANALYSES, *, state0: ArrayLike | None = None,
          settings: SweepSettings | None = None,
          continuation: bool | Continuation | Independent = True,
          execution: Execution | None = None) -> xr.Dataset:
    """Sweep the forcing frequency ``eta`` and classify the motion at every point.

    Parameters
    ----------
    p : System, Params or DuffingParams
        The system (any model, a user model too; its solver settings, where set,
        override ``settings``'), or the parameters of a built-in model; its forcing
        frequency is ignored.
    eta : array_like, shape (n,)
        Strictly increasing grid of the forcing frequency (the model's frequency
        parameter, e.g. the built-in rotor's ``eta``); ``direction`` decides the order it is
        swept in.  A value within a few units in the last place of its rounding to 12
        decimals is taken as that rounding (:func:`snap_grid`), so that
        ``np.arange(0.9, 1.5 + 1e-12, 0.002)`` is swept (and stored) as
        ``vi.grid("0.9:1.5:0.002")``, the command line's grid; other values are kept.
    direction : {"up", "down", "both"}
    analyses : sequence of str
        Subset of ``("period", "impacts", "response", "poincare", "lyapunov", "test01",
        "floquet")``; only these are computed ("period" always runs, it ends the
        transients: an empty sequence asks for the period analysis alone).  ``period``: the period
        in forcing periods and the regime;
        ``impacts``: contacts per period and contact statistics; ``response``: the
        amplitudes ``X_m``, ``Y_m`` from dense samples; ``poincare``: stroboscopic
        samples for bifurcation diagrams; ``lyapunov``: the largest Lyapunov exponent;
        ``test01``: the 0-1 test for chaos; ``floquet``: the Floquet multipliers of
        each periodic point by Newton shooting (``floquet_abs_max``, ``stable``,
        ``floquet_exponent``, the multipliers).
    state0 : array_like, shape (d,), optional
        State at the first point of each direction (rest by default).
    settings : SweepSettings, optional
        Transient, record length, Lyapunov and classifier settings.
    continuation : bool, Continuation or Independent
        The continuation policy (:mod:`vibimpact.engine.policy`).  True (default):
        ``vi.Continuation()``, each point starts from the previous point's final state
        inside each of ``blocks`` blocks (16 by default); every block but the first
        starts from a short seeding pass, and ``blocks=1`` is one unbroken continuation
        (see the module docstring; the result depends on ``blocks``).
        ``vi.Continuation(blocks=1, seed_periods=10)`` sets them.  False
        (``vi.Independent()``): every point starts from ``state0``.
    execution : Execution, optional
        Where and how it runs, none of which changes a number (:class:`vibimpact.
        Execution`: ``workers``, ``executor``, ``scheduler``, ``checkpoint``,
        ``resume``, ``progress``).  With a ``checkpoint`` every finished point is saved
        at once; SIGINT and SIGTERM stop the workers and raise
        :class:`vibimpact.Interrupted`, and ``resume=True`` then completes the same
        result.

    Returns
    -------
    xarray.Dataset
        See :func:`vibimpact.sweeps.dataset.to_dataset`; its ``command`` attribute is
        this process's command line (set another after the call).

    Raises
    ------
    ValueError
        Naming the argument; a ``TypeError`` (also a ``ValueError``) for the keywords
        of the former signature (``workers=``, ``blocks=``, ``checkpoint=``, ...), saying
        where each went.

    Examples
    --------
    >>> import numpy as np, vibimpact as vi
    >>> ds = vi.sweep(vi.presets.get("fig8"), eta=np.arange(1.0, 1.1, 0.02))
    >>> ds.regime.dims
    ('eta',)
    >>> run = vi.Execution(workers=2)
    >>> ds = vi.sweep(vi.presets.get("fig8"), np.arange(1.0, 1.1, 0.02),
    ...               continuation=vi.Continuation(blocks=2), execution=run)
    """
    from ..engine import plan, progress as prog
    from ..engine.compute import compute
    from .dataset import to_dataset

    if not isinstance(p, System) and models.of_params(p) is None:
        raise _v.WrongType(f"p must be a vibimpact.System or the parameter set of a "
                           f"built-in model ({models.param_set_names()}), got "
                           f"{type(p).__name__}")
    policy = as_policy(continuation)
    execution = as_execution(execution)
    etas = check_grid(eta)
    settings, state0 = check_request(direction, analyses, settings, state0,
                                     to_system(p).n_state)
    blocks = policy.blocks
    seed_periods = getattr(policy, "seed_periods", 10)
    dirs = plan.directions(direction)
    n = etas.size
    _limits.check_memory(_limits.points_bytes(n * len(dirs), settings.n_samples,
                                              to_system(p).n_state),
                         f"a sweep of {count(n * len(dirs), 'point')} with "
                         f"{count(settings.n_samples, 'Poincare sample')} each")
    request = dict(params=param_dict(with_frequency(p, 1.0)), eta=etas.tolist(),
                   directions=dirs, settings=settings.as_attrs(),
                   state0=None if state0 is None else state0.tolist(),
                   continuation=bool(getattr(policy, "continued", True)), blocks=blocks,
                   seed_periods=seed_periods)
    store, done = execution.open_checkpoint("sweep", request, dict(
        rows=1, directions=list(dirs), points=n))
    tasks = plan.plan([p], etas, dirs, settings, state0, policy, done=done)
    results = {d: [None] * n for d in dirs}
    for (_, d), points in done.items():
        for i, res in points.items():
            results[d][i] = res

    def on_task(task, points):
        for i, res in points:
            results[task.direction][i] = res

    with prog.callback(execution.progress, sum(t.todo for t in tasks), "sweep") as report:
        compute(tasks, execution.sweep_executor(len(tasks)), on_task, store=store,
                progress=report, stream=True)
    return to_dataset(p, etas, dirs, results, settings, direction=direction,
                      continuation=bool(getattr(policy, "continued", True)),
                      blocks=blocks, command=None)


@_v.checks_flags
def parse_range(text: str, name: str = "eta", positive: bool = True) -> np.ndarray:
    """``"START:STOP:STEP"`` or ``"V1,V2,..."`` -> a strictly increasing grid.

    A range includes STOP when it lies on the grid (its values are rounded to 12 decimals,
    so that ``0.9 + k * 0.002`` prints as typed; a range whose values that rounding
    would change by more than the arithmetic's own error, such as a START with 13
    decimals, is refused rather than changed, and values of 10^4 and more, where 12
    decimals are below a float's resolution, are not rounded); a list is taken as
    written.

    Parameters
    ----------
    text : str
    name : str
        The quantity, named in error messages.
    positive : bool
        A forcing frequency: refuse values ``<= 0`` and outside :data:`ETA_RANGE`.

    Returns
    -------
    numpy.ndarray
        Shape ``(n,)``, float64.

    Raises
    ------
    ValueError
        Naming ``name``, for anything else, and for a grid of more than
        :data:`vibimpact.base._limits.MAX_POINTS` points (with the estimated time).
    """
    text = str(text)
    if ":" not in text:
        grid = _parse_list(text, name, positive)
        return check_frequency(grid, name, text) if positive else grid
    parts = text.split(":")
    if len(parts) != 3:
        raise ValueError(f"{name} must be START:STOP:STEP or V1,V2,..., got {text!r}")
    try:
        a, b, h = (parse_real(x) for x in parts)
    except ValueError:
        raise ValueError(f"{name} must be three numbers START:STOP:STEP, got "
                         f"{text!r}") from None
    if not all(math.isfinite(v) for v in (a, b, h)):
        raise ValueError(f"{name} must be finite, got {text!r}")
    if h <= 0.0:
        raise ValueError(f"{name} STEP must be > 0, got {text!r}")
    if b < a:
        raise ValueError(f"{name} STOP must be >= START, got {text!r}")
    if positive and a <= 0.0:
        raise ValueError(f"{name} START must be > 0, got {text!r}")
    approx = (b - a) / h + 1.0
    if approx > 1e15:  # beyond exact integers (or inf): refuse without converting
        _limits.check_points(approx, name=name)
    count = int(math.floor((b - a) / h + 1e-9)) + 1
    _limits.check_points(count, name=name)
    raw, grid = _rounded_grid(a, h, count)
    if positive and grid[0] <= 0.0:
        raise ValueError(f"{name} START must be >= 1e-12 (the grid is rounded to 12 "
                         f"decimals), got {text!r}")
    if np.any(np.diff(grid) <= 0.0):  # a STEP below the rounding repeats values
        if max(abs(a), abs(b)) >= ROUND_BELOW:
            raise ValueError(f"{name} STEP {h:g} is below a float's resolution at "
                             f"{max(abs(a), abs(b)):g}: values would repeat, got {text!r}")
        raise ValueError(f"{name} STEP must be >= 1e-12 (the grid is rounded to 12 "
                         f"decimals), got {text!r}")
    grid = _check_unchanged(raw, grid, name, text)
    return check_frequency(grid, name, text) if positive else grid


@_v.checks_flags
def grid(text: str, name: str = "eta", positive: bool | None = None) -> np.ndarray:
    """The grid of ``"START:STOP:STEP"`` (or ``"V1,V2,..."``) exactly as the command line
    parses it (:func:`parse_range`).

    ``positive`` refuses values ``<= 0``; by default only for ``eta`` (a forcing
    frequency), so that a grid of another parameter may cross zero.

    Parameters
    ----------
    text : str
        ``"START:STOP:STEP"`` or ``"V1,V2,..."``.
    name : str
        The parameter the grid is of (in the messages).
    positive : bool, optional

    Raises
    ------
    ValueError
        Naming ``text`` (as ``name``), ``name`` or ``positive``; a ``TypeError`` (also
        a ``ValueError``) for a wrong type.

    Where attractors coexist a grid built by hand (``np.arange(0.9, 1.5 + 1e-12,
    0.002)``, which differs from the command line's by about 1e-16) can make a sweep's
    continuation land on another attractor; this one gives the command line's numbers.

    Examples
    --------
    >>> import vibimpact as vi
    >>> vi.grid("0.9:1.0:0.05").tolist()
    [0.9, 0.95, 1.0]
    >>> vi.grid("-0.002:0:0.001", name="k3").tolist()
    [-0.002, -0.001, 0.0]
    """
    if not isinstance(name, str) or not name.strip():
        raise _v.WrongType(f"name must be a non-empty str (the parameter the grid is of), "
                           f"got {type(name).__name__} {name!r}"[:200])
    if not isinstance(text, str):
        raise _v.WrongType(f"text must be a str 'START:STOP:STEP' or 'V1,V2,...' (the "
                           f"grid of {name}), got {type(text).__name__}")
    if positive is None:
        positive = name == "eta"
    return parse_range(text, name=name, positive=_v.flag("positive", positive))


#: range values from this magnitude on are not rounded to 12 decimals (below a float's
#: resolution there: the rounding would change nothing, or overflow)
ROUND_BELOW = 1e4


def _rounded_grid(a, h, n):
    """``(raw, rounded)``: ``a + h k`` (k < n), and rounded to 12 decimals where that is
    below :data:`ROUND_BELOW`."""
    raw = a + h * np.arange(n)
    small = np.abs(raw) < ROUND_BELOW
    grid = raw.copy()
    grid[small] = np.round(raw[small], 12)
    return raw, grid


def _check_unchanged(raw, grid, name, text):
    """ValueError naming ``name`` when the rounding changed a value of the grid by more
    than the arithmetic's own error (a value typed with more than 12 decimals); ``grid``
    otherwise."""
    noise = 8.0 * np.finfo(float).eps * max(1.0, abs(raw[0]), abs(raw[-1]))
    changed = np.flatnonzero(np.abs(grid - raw) > noise)
    if changed.size:
        k = int(changed[0])
        which = "START" if k == 0 else f"value {k + 1}"
        raise ValueError(f"{name} {which} {float(raw[k])!r} has more than 12 decimals (the "
                         f"grid is rounded to 12 decimals: it would become "
                         f"{float(grid[k])!r}); give "
                         f"START and STEP with at most 12 decimals, got {text!r}")
    return grid


def _parse_list(text, name, positive):
    """``"V1,V2,..."`` -> strictly increasing float64 values (ValueError naming ``name``)."""
    items = text.split(",")
    _limits.check_points(len(items), name=name)
    try:
        values = np.array([parse_real(x) for x in items], dtype=np.float64)
    except ValueError:
        raise ValueError(f"{name} values must be numbers (START:STOP:STEP or a list "
                         f"V1,V2,...), got {text!r}") from None
    if not np.all(np.isfinite(values)):
        raise ValueError(f"{name} values must be finite, got {text!r}")
    if positive and np.any(values <= 0.0):
        raise ValueError(f"{name} values must be > 0, got {text!r}")
    if np.any(np.diff(values) <= 0.0):
        raise ValueError(f"{name} values must be strictly increasing, got {text!r}")
    return values
