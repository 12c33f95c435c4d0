"""The validated public wrapper of the numba kernel: :func:`simulate` (and
:func:`strobe_only`, its unvalidated stroboscopic-only form for the loops of sweeps)."""
from __future__ import annotations

from typing import TYPE_CHECKING

import logging

import numpy as np

from . import _limits
from . import _validate as _v
from ._kernel import boundary as _kb
from .models import ROTOR, resolve
from .run import IMPACT_DTYPE, Run, Status, impacts_from_events, status_of

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

    from .models import Model
    from .params import DuffingParams, Params

_logger = logging.getLogger(__name__)

METHODS = _kb.METHODS

#: defaults of :func:`simulate` that :func:`strobe_only` shares
STEPS_PER_PERIOD = 400
EVENT_TOL = 1e-12
MAX_STEPS_PER_PERIOD = 1_000_000


def solver_options(T, rtol, atol, *, steps_per_period=STEPS_PER_PERIOD,
                   max_step=None, bound, event_tol=EVENT_TOL,
                   max_steps_per_period=MAX_STEPS_PER_PERIOD, adaptive=True, n_bound=0):
    """The kernel's :class:`~vibimpact._kernel.boundary.Options` of a run with forcing
    period ``T`` (``max_step`` a quarter period by default); not validated."""
    return _kb.Options(rtol=rtol, atol=atol, h_fixed=T / steps_per_period,
                       max_step=T / 4.0 if max_step is None else max_step, bound=bound,
                       event_tol=event_tol, max_steps_per_period=max_steps_per_period,
                       adaptive=adaptive, n_bound=n_bound)


def _stopped(reason, clock, T):
    k_done = int(clock[0])
    return f"{reason} at tau = {k_done * T + clock[1]:.6g} (forcing period {k_done})"


def strobe_only(model, p, periods, state0, method, rtol, atol):
    """Stroboscopic points of a run, for the loops of sweeps (not validated).

    The same kernel call, with the same numbers, as ``simulate(p, periods,
    state0=state0, method=method, rtol=rtol, atol=atol, model=model)``, without the
    argument checks and the event records: a transient chunk needs neither.

    Parameters
    ----------
    model : Model
    p : ndarray of float64
        The model's parameter vector.

    Returns
    -------
    status : Status
    reason : str
    strobe : ndarray, shape (rows, n)
        Rows 0..periods (fewer when the run stopped early).
    """
    problem = model.problem(p)
    T = problem.period
    y = np.array(state0, dtype=np.float64)
    options = solver_options(T, rtol, atol, bound=model.bound)
    mode = problem.initial_mode(y)
    clock = _kb.new_clock(problem, options)
    strobe = np.empty((periods + 1, y.size))
    strobe[0] = y
    status, _ = _kb.integrate(problem, _kb.Method.named(method), options, y, mode, clock,
                              periods, strobe=strobe)
    st, reason = status_of(status)
    if st is not Status.OK:
        return st, _stopped(reason, clock, T), strobe[:min(periods, int(clock[0])) + 1]
    return st, reason, strobe


def simulate(p: Params | DuffingParams | ArrayLike, periods: int = 100,
             transient: int = 0, state0: ArrayLike | None = None, method: str = "dop853",
             rtol: float = 1e-9, atol: float = 1e-12, *,
             steps_per_period: int = STEPS_PER_PERIOD, adaptive: bool = True,
             dense: int = 0, max_step: float | None = None, bound: float | None = None,
             event_tol: float = EVENT_TOL, max_steps_per_period: int = MAX_STEPS_PER_PERIOD,
             model: Model | str | None = None) -> Run:
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
        with the estimated time, and for arrays (``periods`` stroboscopic and
        ``periods * dense`` dense samples) over :data:`vibimpact._limits.MAX_BYTES`.

    Examples
    --------
    >>> import vibimpact as vi
    >>> run = vi.simulate(vi.presets.get("fig8").replace(eta=1.185), periods=50,
    ...                   transient=300)
    >>> run.strobe.shape
    (51, 4)
    """
    mdl, pvec = resolve(p, model)
    periods = _v.count("periods", periods, 1)
    transient = _v.count("transient", transient, 0)
    steps_per_period = _v.count("steps_per_period", steps_per_period, 1)
    dense = _v.count("dense", dense, 0)
    max_steps_per_period = _v.count("max_steps_per_period", max_steps_per_period, 1)
    meth = _kb.Method.named(_v.choice("method", method, METHODS))
    rtol = _v.positive("rtol", rtol)
    atol = _v.positive("atol", atol)
    event_tol = _v.positive("event_tol", event_tol)
    max_step = _v.positive("max_step", max_step, allow_none=True)
    bound = _v.positive("bound", bound, allow_none=True)
    n = len(mdl.state_names)
    _limits.check_run(periods, transient, dense, n)
    y = _v.state("state0", state0, n)
    y0 = y.copy()  # the kernel advances y in place

    problem = mdl.problem(pvec)
    T = problem.period
    options = solver_options(T, rtol, atol, steps_per_period=steps_per_period,
                             max_step=max_step, bound=mdl.bound if bound is None else bound,
                             event_tol=event_tol, max_steps_per_period=max_steps_per_period,
                             adaptive=adaptive)
    mode = problem.initial_mode(y)
    clock = _kb.new_clock(problem, options)
    k_end = transient + periods
    strobe = np.empty((periods + 1, n))
    strobe[0] = y if transient == 0 else np.nan
    dense_arr = np.full((periods * dense + 1, n) if dense else (1, n), np.nan)
    if dense and transient == 0:
        dense_arr[0] = y
    counters = _kb.counters()
    status, log = _kb.integrate(problem, meth, options, y, mode, clock, k_end,
                                k_record=transient, strobe=strobe, dense_m=dense,
                                dense=dense_arr, count=counters)
    st, reason = status_of(status)
    k_done = int(clock[0])
    rows = max(0, min(periods, k_done - transient)) + (1 if k_done >= transient else 0)
    if st is Status.OK:
        rows = periods + 1
    strobe = strobe[:rows]
    if st is not Status.OK:
        reason = _stopped(reason, clock, T)
    events = log.events()
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
    _logger.debug("simulate %s: %d periods after %d, status %s, %d steps, %d events",
                  mdl.name, periods, transient, st.value, int(counters[0]), int(counters[3]))
    return Run(
        params=p, model=mdl.name, strobe=strobe,
        t_strobe=(transient + np.arange(rows)) * T, impacts=impacts, events=events,
        dense=dense_out, t_dense=t_dense, status=st, reason=reason,
        counters=dict(zip(("steps", "rhs_evals", "rejected", "events", "observed"),
                          (int(c) for c in counters))),
        final_state=strobe[-1].copy() if rows else y.copy(),
        solver=dict(method=method, adaptive=bool(adaptive and meth.adaptive), rtol=rtol,
                    atol=atol, steps_per_period=steps_per_period,
                    max_step=float(options.max_step), event_tol=event_tol,
                    bound=float(options.bound)),
        state0=y0, periods=periods, transient=transient, dense_per_period=dense,
    )
