"""An independent SciPy integration of a built-in model, for cross-checks only.

:func:`solve_reference` integrates the model of its parameters (eq. (5) for
:class:`~vibimpact.Params`) with :func:`scipy.integrate.solve_ivp`, one discrete mode at a
time, and restarts at every switch.  It shares only the model functions of the model's
kernel module (right-hand side, switching functions, mode transitions, initial mode:
e.g. :mod:`vibimpact._kernel.rotor` for the built-in rotor) with the production integrator
:func:`vibimpact.simulate`; the Runge--Kutta steps, the step-size control and the event
location are SciPy's.  It is the *cross-check* of the kernel and the fair SciPy
baseline of the benchmarks (compiled right-hand side, restarted at switches), **not** the
production integrator: it is one to two orders of magnitude slower and keeps no impact
log.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from .._kernel.boundary import kernel_family

#: consecutive zero-length segments tolerated before giving up (accumulating switches)
_MAX_ZENO = 50


@dataclass
class ReferenceSolution:
    """Result of :func:`solve_reference`.

    Attributes
    ----------
    t : ndarray, shape (m,)
        The output times (``t_eval``).
    y : ndarray, shape (m, n_state)
        States at ``t``.
    events : list of tuple
        ``(t, which, mode_before, mode_after)`` for every switch, in time order; ``which``
        is the index of the switching function (the built-in rotor's: 0 contact, 1
        friction).
    nfev : int
        Right-hand-side evaluations (SciPy's count, summed over segments).
    nsteps : int
        Accepted steps, summed over segments.
    segments : int
        Calls of ``solve_ivp``.
    """

    t: np.ndarray
    y: np.ndarray
    events: list
    nfev: int
    nsteps: int
    segments: int

    @property
    def event_times(self):
        """Times of the switches, ndarray."""
        return np.array([e[0] for e in self.events])

    @property
    def event_which(self):
        """Switch indices of the switches, int ndarray."""
        return np.array([e[1] for e in self.events], dtype=np.int64)


def _switch_events(km, pa, mode, t0, y0):
    """Terminal event functions of the switches in ``mode`` for a segment from ``t0``.

    A switching function is positive while the mode is consistent; the event is its
    crossing to negative values (``direction = -1``).  At a restart the function is zero
    to rounding (the state is the previous event's): if it starts at ``g0 <= 0`` it is
    shifted by ``2|g0|`` (by the smallest subnormal when ``g0 = 0``) so that the restart
    point itself is never a root.  A mode that really is inconsistent there still
    switches at once: the shifted function goes negative within a time ``~|g0|/|g'|``.
    ``km``: the model's kernel module (:class:`~vibimpact._kernel.registry.KernelModel`).
    """
    g = np.empty(km.terminal.size)
    km.switches(t0, y0, pa, mode, g)
    cache = {"t": None, "y0": None, "g": np.empty(km.terminal.size)}

    def values(t, y):
        if cache["t"] != t or cache["y0"] is None or not np.array_equal(cache["y0"], y):
            km.switches(t, y, pa, mode, cache["g"])
            cache["t"] = t
            cache["y0"] = np.array(y, dtype=np.float64)
        return cache["g"]

    funcs = []
    for i in _terminal(km):
        g0 = g[i]
        shift = 0.0 if g0 > 0.0 else (2.0 * -g0 if g0 < 0.0 else 5e-324)

        def ev(t, y, i=i, shift=shift):
            return values(t, y)[i] + shift
        ev.terminal = True  # type: ignore[attr-defined]  # an attribute of a function
        ev.direction = -1  # type: ignore[attr-defined]  # an attribute of a function
        funcs.append(ev)
    return funcs


def _terminal(km):
    """Indices of the terminal (mode-changing) switching functions of kernel ``km``."""
    return tuple(int(i) for i in np.flatnonzero(km.terminal))


def _kernel(p, model):
    """``(kernel module, parameter vector)`` of ``p``: a built-in model's parameter set,
    or a vector of the built-in ``model``."""
    from .. import models

    mdl, pa = models.resolve(p, model)
    if not mdl.builtin:
        raise ValueError(f"model: the reference integrates built-in models only, not "
                         f"{mdl.name!r}")
    return kernel_family(mdl.kernel_model.family), np.ascontiguousarray(pa, np.float64)


def solve_reference(p, t_end, state0, rtol=1e-12, atol=1e-12, method="DOP853",
                    t_eval=None, max_step=np.inf, model=None):
    """Integrate a built-in model with SciPy ``solve_ivp``, restarted at every switch.

    A cross-check of :func:`vibimpact.simulate`, not the production integrator.  Within
    one discrete mode (for the built-in rotor: ``mode[0]`` contact flag, ``mode[1]``
    friction state +1/-1/0, see :mod:`vibimpact._kernel.rotor`) the field is smooth and
    ``solve_ivp`` integrates the compiled ``rhs`` of the model's kernel module (e.g.
    :func:`~vibimpact._kernel.rotor.rhs`).  The terminal switching functions (the built-in
    rotor's: contact, friction) are SciPy events (crossing to negative,
    ``direction=-1``); at an event the module's ``transition`` (e.g.
    :func:`~vibimpact._kernel.rotor.transition`) gives the new mode and ``solve_ivp`` is
    restarted from the event state.  Integration also stops exactly at every output
    time, so the returned states are step end points, not interpolated.

    Parameters
    ----------
    p : a built-in model's parameter set, or array_like with ``model``
        Parameters (e.g. :class:`vibimpact.Params` for the built-in rotor of eq. (5)).
    t_end : float
        Final dimensionless time; integration starts at ``tau = 0`` (forcing phase 0).
    state0 : array_like, shape (n_state,)
        The model's state at ``tau = 0`` (the built-in rotor's ``(X, Y, X', Y')``).
    rtol, atol : float
        Tolerances passed to ``solve_ivp``.
    method : str
        A ``solve_ivp`` explicit method ("DOP853", "RK45", "RK23").
    t_eval : array_like, optional
        Increasing output times in ``[0, t_end]``; ``[0, t_end]`` by default.
    max_step : float
        Passed to ``solve_ivp``.
    model : vibimpact.models.Model, optional
        The built-in model of a plain parameter vector ``p`` (a parameter set names its
        own).

    Returns
    -------
    ReferenceSolution
        States at ``t_eval`` (shape (m, n_state)), the switch log and the work counters.

    Raises
    ------
    RuntimeError
        When ``solve_ivp`` fails, or switches accumulate at one instant (Zeno).

    Notes
    -----
    SciPy samples the events only at step ends: a contact that begins and ends inside one
    step would be missed.  At the tight tolerances this routine is meant for, steps are far
    shorter than any contact.

    Examples
    --------
    >>> import numpy as np, vibimpact as vi
    >>> from vibimpact.testing.reference import solve_reference
    >>> p = vi.presets.get("fig8").replace(eta=1.0)
    >>> T = 2 * np.pi / p.eta
    >>> ref = solve_reference(p, 2 * T, [0.0, 1.05, 0.0, 0.0], t_eval=[0.0, T, 2 * T])
    >>> ref.y.shape
    (3, 4)
    """
    km, pa = _kernel(p, model)
    terminal = _terminal(km)
    y = np.array(state0, dtype=np.float64).reshape(-1)
    if y.size != km.n_state:
        raise ValueError(f"state0 must have {km.n_state} entries")
    t_end = float(t_end)
    t_out = np.array([0.0, t_end] if t_eval is None else t_eval, dtype=np.float64)
    if t_out.size and (np.any(np.diff(t_out) < 0) or t_out[0] < 0 or t_out[-1] > t_end):
        raise ValueError("t_eval must be increasing and within [0, t_end]")
    mode = np.zeros(km.n_mode, dtype=np.int64)
    km.init_mode(0.0, y, pa, mode)
    out = np.full((t_out.size, y.size), np.nan)

    def fun(t, yy, mode=mode):
        f = np.empty(km.n_state)
        km.rhs(t, yy, pa, mode, f)
        return f

    t = 0.0
    j = 0
    while j < t_out.size and t_out[j] <= t:
        out[j] = y
        j += 1
    events = []
    nfev = nsteps = segments = zeno = 0
    while t < t_end:
        target = t_out[j] if j < t_out.size else t_end
        sol = solve_ivp(fun, (t, target), y, method=method, rtol=rtol, atol=atol,
                        max_step=max_step, events=_switch_events(km, pa, mode, t, y))
        segments += 1
        nfev += sol.nfev
        nsteps += sol.t.size - 1
        if sol.status < 0:
            raise RuntimeError(f"solve_ivp failed at tau = {t:.17g}: {sol.message}")
        if sol.status == 1:
            hits = [(sol.t_events[k][0], k) for k in range(len(terminal))
                    if sol.t_events[k].size]
            t_ev, k = min(hits)
            which = terminal[k]
            y_new = np.array(sol.y_events[k][0], dtype=np.float64)
            zeno = zeno + 1 if t_ev - t <= 1e-12 * (1.0 + abs(t)) else 0
            if zeno > _MAX_ZENO:
                raise RuntimeError(f"accumulating switches (Zeno) at tau = {t_ev:.17g}")
            before = mode.copy()
            km.transition(t_ev, y_new, pa, mode, which)
            events.append((float(t_ev), which, before, mode.copy()))
            t, y = float(t_ev), y_new
            while j < t_out.size and t_out[j] == t:
                out[j] = y
                j += 1
        else:
            t, y = float(target), np.array(sol.y[:, -1], dtype=np.float64)
            zeno = 0
            while j < t_out.size and t_out[j] <= t:
                out[j] = y
                j += 1
    return ReferenceSolution(t=t_out, y=out, events=events, nfev=int(nfev),
                             nsteps=int(nsteps), segments=segments)


def strobe_times(eta, periods):
    """Stroboscopic times ``2 pi k / eta``, ``k = 0..periods`` (the forcing's phase is zero
    at ``tau = 0``)."""
    return 2.0 * math.pi * np.arange(periods + 1) / float(eta)
