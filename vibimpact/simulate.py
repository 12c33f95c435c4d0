"""`simulate`: validated public wrapper around the numba kernel."""
from __future__ import annotations

import math
import numbers

import numpy as np

from ._kernel import integrator as _k
from ._kernel import tableaux as _tab
from ._kernel.driver import integrate as _integrate
from . import _limits
from .models import DUFFING, ROTOR, Model
from .params import DuffingParams, Params
from .run import IMPACT_DTYPE, Run, Status, impacts_from_events, status_of

METHODS = tuple(_tab.METHOD_IDS)

_EMPTY2 = np.zeros((1, 1))

#: defaults of :func:`simulate` that :func:`strobe_only` shares
STEPS_PER_PERIOD = 400
EVENT_TOL = 1e-12
MAX_STEPS_PER_PERIOD = 1_000_000


def _options(rtol, atol, h_fixed, max_step, bound, event_tol, max_steps_per_period,
             adaptive, method, n_bound=0):
    """The kernel's option vector (layout in :mod:`vibimpact._kernel.integrator`), with
    the method's error constants at Hertz contact ends (adaptive methods)."""
    g_in, g_out = _tab.HERTZ_ERROR.get(_tab.METHOD_IDS[method], (0.0, 0.0))
    return np.array([rtol, atol, h_fixed, max_step, bound, event_tol,
                     float(max_steps_per_period), 0.0 if adaptive else 1.0, float(n_bound),
                     0.0, 1.0, g_in, g_out])


def _tableau(method):
    """Kernel arguments ``(id, A, B, C, E, E3, D, P, order, n_stages)`` of a method."""
    mid = _tab.METHOD_IDS[method]
    if mid == _tab.RK4:
        return (mid, _tab.RK4_A, _tab.RK4_B, _tab.RK4_C, np.zeros(1), np.zeros(1), _EMPTY2,
                _EMPTY2, 4, 4)
    if mid == _tab.DP5:
        return (mid, _tab.DP5_A, _tab.DP5_B, _tab.DP5_C, _tab.DP5_E, np.zeros(1), _EMPTY2,
                _tab.DP5_P, 5, 6)
    return (mid, _tab.DOP853_A, _tab.DOP853_B, _tab.DOP853_C, _tab.DOP853_E5, _tab.DOP853_E3,
            _tab.DOP853_D, _EMPTY2, 8, _tab.DOP853_NSTAGES)


def _model_and_vector(p, model):
    if model is not None:
        if not isinstance(model, Model):
            raise ValueError("model must be a vibimpact.models.Model")
        vec = np.ascontiguousarray(p.as_array() if hasattr(p, "as_array") else p,
                                   dtype=np.float64)
        if vec.ndim != 1 or vec.size != len(model.param_names):
            raise ValueError(f"p must have {len(model.param_names)} parameters "
                             f"{model.param_names}")
        return model, vec
    if isinstance(p, Params):
        return ROTOR, p.as_array()
    if isinstance(p, DuffingParams):
        return DUFFING, p.as_array()
    raise ValueError(f"p must be vibimpact.Params or DuffingParams, got {type(p).__name__}")


def _state0(state0, n):
    """A validated copy of an initial state of ``n`` entries (rest when None)."""
    if state0 is None:
        return np.zeros(n)
    try:
        y = np.array(state0, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"state0 must be {n} numbers, got {state0!r}") from None
    if y.size != n or not np.all(np.isfinite(y)):
        raise ValueError(f"state0 must be {n} finite numbers, got {state0!r}")
    return y


def _count(name, value, minimum):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value!r}")
    return int(value)


def _positive(name, value, allow_none=False):
    if value is None and allow_none:
        return None
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    return v


def _run_kernel(mdl, pvec, omega, tab, opts, y, mode, ks, k_end, k_record, strobe, dense,
                dense_arr):
    """The kernel call of :func:`simulate`, repeated while the event log is full.

    Returns ``(status, chunks, counters)``: ``chunks`` the filled parts of the event logs
    as ``(t, which, mode, state)`` arrays.
    """
    n = y.size
    counters = np.zeros(_k.N_COUNTERS, dtype=np.int64)
    cap = int(min(max(64 * (k_end - k_record), 1024), 262_144))
    chunks = []
    status = _k.LOG_FULL
    while status == _k.LOG_FULL:
        ev_t = np.empty(cap)
        ev_which = np.empty(cap, dtype=np.int64)
        ev_mode = np.empty((cap, 2 * mdl.n_mode), dtype=np.int64)
        ev_y = np.empty((cap, n))
        status, n_ev = _integrate(mdl.kernel_model, mdl.terminal, *tab, pvec, omega, y, mode,
                                  ks, opts, k_end, k_record, strobe, ev_t, ev_which, ev_mode,
                                  ev_y, 0, dense, dense_arr, counters)
        chunks.append((ev_t[:n_ev], ev_which[:n_ev], ev_mode[:n_ev], ev_y[:n_ev]))
    return status, chunks, counters


def strobe_only(p, periods, state0, method, rtol, atol):
    """Stroboscopic points of a rotor run, for the loops of sweeps (not validated).

    The same kernel call, with the same numbers, as ``simulate(p, periods,
    state0=state0, method=method, rtol=rtol, atol=atol)``, without the argument checks
    and the event records: a transient chunk needs neither.

    Returns
    -------
    status : Status
    reason : str
    strobe : ndarray, shape (rows, 4)
        Rows 0..periods (fewer when the run stopped early).
    """
    pvec = p.as_array()
    omega = float(pvec[ROTOR.omega_index])
    T = 2.0 * math.pi / omega
    y = np.array(state0, dtype=np.float64)
    opts = _options(rtol, atol, T / STEPS_PER_PERIOD, T / 4.0, ROTOR.bound, EVENT_TOL,
                    MAX_STEPS_PER_PERIOD, True, method)
    mode = np.zeros(ROTOR.n_mode, dtype=np.int64)
    ROTOR.init_mode(0.0, y, pvec, mode)
    ks = np.array([0.0, 0.0, min(T / 50.0, opts[_k.O_HMAX]), 0.0])
    strobe = np.empty((periods + 1, y.size))
    strobe[0] = y
    status, _, _ = _run_kernel(ROTOR, pvec, omega, _tableau(method), opts, y, mode, ks,
                               periods, 0, strobe, 0, _EMPTY2)
    st, reason = status_of(status)
    if st is not Status.OK:
        k_done = int(ks[0])
        reason = f"{reason} at tau = {k_done * T + ks[1]:.6g} (forcing period {k_done})"
        return st, reason, strobe[:min(periods, k_done) + 1]
    return st, reason, strobe


def simulate(p, periods=100, transient=0, state0=None, method="dop853", rtol=1e-9,
             atol=1e-12, *, steps_per_period=STEPS_PER_PERIOD, adaptive=True, dense=0,
             max_step=None, bound=None, event_tol=EVENT_TOL,
             max_steps_per_period=MAX_STEPS_PER_PERIOD, model=None):
    """Integrate the model and sample it stroboscopically.

    Parameters
    ----------
    p : Params or DuffingParams (or a parameter vector with ``model``)
    periods : int
        Forcing periods recorded after the transient (``>= 1``).
    transient : int
        Forcing periods integrated first and discarded (``>= 0``).
    state0 : array_like, shape (n,), optional
        Initial state at ``tau = 0``; the rest state ``0`` by default.
    method : {"dop853", "dp5", "rk4"}
        Dormand--Prince 8(5,3) or 5(4), adaptive, or the classical fixed-step RK4.
    rtol, atol : float
        Tolerances of the adaptive methods.
    steps_per_period : int
        Fixed-step runs (RK4, or ``adaptive=False``): steps per forcing period.  Steps are
        also cut at events and graded next to contact surfaces (see
        ``vibimpact._kernel.driver.graded_step``).
    adaptive : bool
        False runs DP5 or DOP853 with fixed steps, no error control (to measure orders).
    dense : int
        Evenly spaced samples per period to keep (0: none; memory stays flat).
    max_step : float, optional
        Largest step; a quarter period by default.
    bound : float, optional
        A state component beyond this ends the run as DIVERGED (model default: 1e3 for the
        rotor, i.e. a thousand clearances).
    event_tol : float
        Switching functions are zero to this at every located event (``|R - 1|`` at a
        contact entry).
    max_steps_per_period : int
    model : Model, optional
        A user model; ``p`` is then its parameter vector.

    Returns
    -------
    Run
        ``strobe`` (periods + 1, n), ``impacts``, ``events``, counters and status.
        A blow-up returns ``status = DIVERGED`` with a reason and only the rows computed.

    Raises
    ------
    ValueError
        Naming the offending argument; also for more than
        :data:`vibimpact._limits.MAX_PERIODS` forcing periods (``periods + transient``),
        with the estimated time.

    Examples
    --------
    >>> import vibimpact as vi
    >>> run = vi.simulate(vi.presets.get("fig8").replace(eta=1.185), periods=50,
    ...                   transient=300)
    >>> run.strobe.shape
    (51, 4)
    """
    mdl, pvec = _model_and_vector(p, model)
    periods = _count("periods", periods, 1)
    transient = _count("transient", transient, 0)
    _limits.check_periods(periods, transient)
    steps_per_period = _count("steps_per_period", steps_per_period, 1)
    dense = _count("dense", dense, 0)
    max_steps_per_period = _count("max_steps_per_period", max_steps_per_period, 1)
    if method not in _tab.METHOD_IDS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    rtol = _positive("rtol", rtol)
    atol = _positive("atol", atol)
    event_tol = _positive("event_tol", event_tol)
    max_step = _positive("max_step", max_step, allow_none=True)
    bound = _positive("bound", bound, allow_none=True)
    n = len(mdl.state_names)
    y = _state0(state0, n)

    omega = float(pvec[mdl.omega_index])
    T = 2.0 * math.pi / omega
    tab = _tableau(method)
    h_fixed = T / steps_per_period
    opts = _options(rtol, atol, h_fixed, T / 4.0 if max_step is None else max_step,
                    mdl.bound if bound is None else bound, event_tol, max_steps_per_period,
                    adaptive, method)
    mode = np.zeros(mdl.n_mode, dtype=np.int64)
    mdl.init_mode(0.0, y, pvec, mode)
    ks = np.array([0.0, 0.0, min(T / 50.0, opts[_k.O_HMAX]), 0.0])
    k_end = transient + periods
    strobe = np.empty((periods + 1, n))
    strobe[0] = y if transient == 0 else np.nan
    dense_arr = np.empty((periods * dense + 1, n) if dense else (1, n))
    if dense and transient == 0:
        dense_arr[0] = y
    status, chunks, counters = _run_kernel(mdl, pvec, omega, tab, opts, y, mode, ks, k_end,
                                           transient, strobe, dense, dense_arr)
    st, reason = status_of(status)
    k_done = int(ks[0])
    rows = max(0, min(periods, k_done - transient)) + (1 if k_done >= transient else 0)
    if st is Status.OK:
        rows = periods + 1
    strobe = strobe[:rows]
    if st is not Status.OK:
        reason = f"{reason} at tau = {k_done * T + ks[1]:.6g} (forcing period {k_done})"
    modes = np.concatenate([c[2] for c in chunks])
    events = {
        "t": np.concatenate([c[0] for c in chunks]),
        "which": np.concatenate([c[1] for c in chunks]),
        "mode_before": modes[:, :mdl.n_mode],
        "mode_after": modes[:, mdl.n_mode:],
        "state": np.concatenate([c[3] for c in chunks]),
    }
    if mdl is ROTOR:
        impacts = impacts_from_events(events["t"], events["which"], events["mode_before"],
                                      events["state"], transient * T, T)
    else:
        impacts = np.zeros(0, dtype=IMPACT_DTYPE)
    if dense:
        n_dense = periods * dense + 1 if st is Status.OK else max(0, rows - 1) * dense + (
            1 if rows else 0)
        dense_out = dense_arr[:n_dense]
        t_dense = transient * T + np.arange(n_dense) * (T / dense)
    else:
        dense_out = None
        t_dense = None
    return Run(
        params=p, model=mdl.name, strobe=strobe,
        t_strobe=(transient + np.arange(rows)) * T, impacts=impacts, events=events,
        dense=dense_out, t_dense=t_dense, status=st, reason=reason,
        counters=dict(zip(("steps", "rhs_evals", "rejected", "events", "observed"),
                          (int(c) for c in counters))),
        final_state=strobe[-1].copy() if rows else y.copy(),
        solver=dict(method=method, adaptive=bool(adaptive and method != "rk4"), rtol=rtol, atol=atol, steps_per_period=steps_per_period,
                    max_step=float(opts[_k.O_HMAX]), event_tol=event_tol,
                    bound=float(opts[_k.O_BOUND])),
    )
