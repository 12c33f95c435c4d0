"""The integration loop: steps, events, stroboscopic and dense samples (``@njit``).

:func:`integrate` is the entry point (called by :mod:`.boundary` and :mod:`.lyapunov`),
with scratch arrays from :func:`workspace` that the caller may keep across calls.  The
loop's pieces, in the order of a step (inlined into it by numba: :data:`.jitopts.PIECE`):

* :func:`_step_size` -- the size of the next step (fixed-step grid and grading, maximum
  step, the model's cap at a non-smooth force, landing on the period's end);
* :func:`_attempt` -- one Runge--Kutta step with the error test;
* :func:`_check_state` -- divergence of the new state;
* :func:`.events.detect`, then :func:`_switch_now` for an inconsistent mode at the step's
  start or :func:`_locate` (with :func:`_grazing` and :func:`.events.retake`) for
  crossings inside it;
* :func:`_log_observers` -- observer crossings before the event, in time order;
* :func:`.sampling.samples` -- dense and stroboscopic samples from the continuous
  extension (:mod:`.sampling`);
* :func:`_next_start` -- the step's end as the next step's start (the mode change at a
  located event).

Arguments are packed (see :func:`integrate`): the problem ``(model, terminal, p,
omega)``, the Runge--Kutta method ``(id, A, B, C, E, E3, D, P, order, n_stages)``, the
event log ``(t, which, mode, state)``, the options as a :data:`.integrator.Settings` and
the scratch arrays as a :data:`Workspace`.  The model is a built-in model (a
:func:`.dispatch.builtin` marker, cached on disk) or a tuple of numba functions for a user
model (see :mod:`.dispatch`).
"""
import math
from collections import namedtuple

import numpy as np
from numba import njit

from .dispatch import model_rhs, model_step_cap, model_switches, model_transition
from .events import BRACKETED, IMMEDIATE, detect, locate, retake
from .integrator import (C_EVENTS, C_OBSERVED, C_REJECTED, C_RHS, C_STEPS, LOG_FULL,
                         MAX_STEPS, OK, STEP_UNDERFLOW, ZENO, error_norm, interpolate,
                         prepare_dense, rk_step, settings)
from .integrator import check_state as _check_state
from .integrator import log_event as _log
from .jitopts import LEAF, PIECE
from .renormalise import renormalise
from .sampling import next_period_sample, resume, samples, suspend

#: scratch arrays of the loop (allocated by :func:`workspace`)
Workspace = namedtuple("Workspace", (
    "K", "Kr", "F",                      # stages of the step and of a retaken step;
                                         # continuous extension
    "ytmp", "y1", "yev", "yint", "f0", "f1r",  # states and derivatives, shape (n,)
    "G", "gbuf", "gobs",                 # switching functions: samples over a step
    "flag", "lo", "hi",                  # detection: kind and bracket of each switch
    "obs_th", "obs_i",                   # located observer crossings
    "mode_old",                          # the mode before a transition
    "mode_stage",                        # a stage's mode (:mod:`.noevents`)
))

#: outcomes of :func:`_switch_now`
_RETRY_SAME_START = 0   # retry shorter; the switching functions at the start still hold
_RETRY_NEW_START = 1    # retry shorter; the mode was touched: re-evaluate them
_SWITCHED = 2           # the mode changed at the step's start

#: consecutive events without time advancing before the run stops as ZENO
_ZENO_LIMIT = 50


def workspace(n, n_switch, n_mode):
    """Scratch arrays of :func:`integrate` for a state of ``n`` entries, ``n_switch``
    switching functions and ``n_mode`` mode entries (plain Python: allocated by the
    caller, reusable across calls)."""
    return Workspace(np.zeros((16, n)), np.zeros((16, n)), np.zeros((7, n)),
                     np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n),
                     np.empty(n), np.empty((5, n_switch)), np.empty(n_switch),
                     np.empty(n_switch), np.zeros(n_switch, dtype=np.int64),
                     np.zeros(n_switch), np.zeros(n_switch), np.empty(n_switch),
                     np.empty(n_switch, dtype=np.int64), np.zeros(n_mode, dtype=np.int64),
                     np.zeros(n_mode, dtype=np.int64))


@njit(**PIECE)
def graded_step(hf, t, order):
    """Fixed-step size graded towards a switching surface ``t`` time units away.

    The Hertz force ``(R-1)^{3/2}`` makes the solution behave like ``t^{7/2}`` next to a
    contact entry or exit, so a step of order ``q`` and size ``h`` a time ``t`` away from the
    surface has a local error ``~h^{q+1} t^{-3/2}`` (``~h^{5/2}`` when it touches it).
    Steps of ``max(hf^{(q+1)/2.5}, hf t^{1.5/(q+1)})`` (``t`` in units of ``tau = 1``) keep
    those errors at the ``hf^{q+1}`` of the regular steps.  Measured global order of RK4 on
    contact trajectories: about 3.6, against 2.7 without grading
    (tests/test_kernel_accuracy.py).  Used by fixed-step runs only: adaptive runs grade
    their steps by their error estimate.
    """
    tau = 1.0
    return max(hf * (hf / tau) ** ((order + 1.0) / 2.5 - 1.0),
               hf * (t / tau) ** (1.5 / (order + 1.0)))


@njit(**PIECE)
def _room(n_ev, n_switch, cap, steps_in_period, max_steps):
    """OK, or LOG_FULL when the event log may not hold the events of one more step, or
    MAX_STEPS when the period has taken too many."""
    if n_ev + n_switch + 2 > cap:
        return LOG_FULL
    if steps_in_period > max_steps:
        return MAX_STEPS
    return OK


@njit(**PIECE)
def _step_size(problem, cfg, y, mode, f0, k, k_end, s, h, h_cap, t_near, at_event, retry):
    """Size of the next step from ``(k, s)``: ``h`` (the controller's proposal) within the
    fixed-step grid (graded towards a surface ``t_near`` away), the maximum step,
    ``h_cap`` and the model's cap at a non-smooth force (not on a retry: its cap holds),
    stretched or shortened to land on the period's end.

    Returns ``(h, h_prop, lands)``: the step, the step before landing, whether it lands.
    """
    model, terminal, p, omega = problem
    if cfg.fixed:
        hf = cfg.h_fixed
        h = (math.floor(s / hf + 1e-9) + 1.0) * hf - s
        h = min(h, graded_step(hf, t_near, cfg.order))
    h = min(h, cfg.h_max, h_cap)
    if cfg.g_out > 0.0 and not retry:
        h = min(h, model_step_cap(model, y, p, mode, f0, at_event, cfg.rtol, cfg.atol,
                                  cfg.n_norm, cfg.g_in, cfg.g_out))
    h_prop = h
    T = cfg.T
    if s + h >= T * (1.0 - 1e-12) and (k == k_end - 1 or s + h <= T * (1.0 + 1e-12)):
        return T - s, h_prop, True
    return h, h_prop, False


@njit(**PIECE)
def _attempt(problem, method, cfg, ws, mode, s, y, h, h_prop, lands, counters):
    """One Runge--Kutta step of size ``h`` from ``(s, y)`` into ``ws.y1`` (``ws.f0``: the
    derivative at the start), with the error test of the embedded methods.

    Returns ``(accepted, h, h_next)``: an accepted step leaves the derivative at its end
    in ``ws.f1r`` and proposes ``h_next``; a rejected one returns the shorter step to try.
    """
    model, terminal, p, omega = problem
    mid, A, B, C, E, E3, D, P, order, n_stages = method
    n = y.size
    K = ws.K
    f0 = ws.f0
    for m in range(n):
        K[0, m] = f0[m]
    counters[C_RHS] += rk_step(model, p, mode, A, B, C, n_stages, cfg.fsal, s, y, h, K,
                               ws.ytmp, ws.y1)
    h_next = h
    if cfg.fsal and not cfg.fixed:
        err = error_norm(mid, E, E3, K, n_stages, h, y, ws.y1, cfg.rtol, cfg.atol,
                         cfg.n_err, cfg.tfac)
        if not np.isfinite(err) or err > 1.0:
            counters[C_REJECTED] += 1
            fac = 0.2 if not np.isfinite(err) else max(0.2, 0.9 * err ** cfg.expo)
            return False, h * fac, h_next
        fac = 10.0 if err == 0.0 else min(10.0, max(0.2, 0.9 * err ** cfg.expo))
        h_next = h * fac
        if lands and h_prop > h_next:
            h_next = h_prop
    f1r = ws.f1r
    if cfg.fsal:
        for m in range(n):
            f1r[m] = K[n_stages, m]
    else:
        model_rhs(model, s + h, ws.y1, p, mode, f1r)
        counters[C_RHS] += 1
    return True, h, h_next


@njit(**PIECE)
def _first_immediate(flag):
    """The first switch flagged IMMEDIATE by :func:`.events.detect`, or -1."""
    for i in range(flag.size):
        if flag[i] == IMMEDIATE:
            return i
    return -1


@njit(**PIECE)
def _switch_now(problem, cfg, ws, log, n_ev, mode, k, k_record, s, y, h, imm, counters):
    """A terminal switch ``imm`` negative at the step's start and at its first sample.

    Either the state sits on the surface (an event just put it there) and the crossing
    back is shorter than a quarter step (a shallow contact), or the mode is right and the
    switch value sits within rounding of zero: both retry a shorter step so the samples
    resolve the crossing.  Otherwise the mode is inconsistent: it changes at once, is
    logged, and ``ws.f0`` is re-evaluated.

    Returns ``(outcome, n_ev)``: :data:`_RETRY_SAME_START`, :data:`_RETRY_NEW_START` or
    :data:`_SWITCHED`.
    """
    model, terminal, p, omega = problem
    T = cfg.T
    if abs(ws.G[0, imm]) <= cfg.event_tol and h > 1e-6 * T:
        return _RETRY_SAME_START, n_ev
    mode_old, y_old = ws.mode_old, ws.yint
    for m in range(mode.size):
        mode_old[m] = mode[m]
    for m in range(y.size):
        y_old[m] = y[m]
    model_transition(model, s, y, p, mode, imm)
    same = True
    for m in range(mode.size):
        if mode[m] != mode_old[m]:
            same = False
    for m in range(y.size):
        if y[m] != y_old[m]:
            same = False
    if same:
        return _RETRY_NEW_START, n_ev
    counters[C_EVENTS] += 1
    if k >= k_record:
        n_ev = _log(log, n_ev, k * T + s, imm, mode_old, mode, y_old)
    model_rhs(model, s, y, p, mode, ws.f0)
    counters[C_RHS] += 1
    return _SWITCHED, n_ev


@njit(**PIECE)
def _locate(problem, method, cfg, ws, mode, s, y, h, counters):
    """Crossings inside an accepted step whose samples bracketed some (after
    :func:`.events.detect`): the first terminal crossing, and the observer crossings up
    to it, refined on the continuous extension (prepared here into ``ws.F``); the step
    is retaken to the terminal event (:func:`.events.retake`, state into ``ws.yev``).

    Returns ``(which, th_end, n_obs)``: the terminal switch (-1: none), the fraction of
    the step taken, and the observer crossings in ``ws.obs_th``, ``ws.obs_i``.
    """
    model, terminal, p, omega = problem
    mid, A, B, C, E, E3, D, P, order, n_stages = method
    f0, y1, f1r, F, ytmp, gbuf = ws.f0, ws.y1, ws.f1r, ws.F, ws.ytmp, ws.gbuf
    flag, lo, hi, obs_th, obs_i = ws.flag, ws.lo, ws.hi, ws.obs_th, ws.obs_i
    nsw = terminal.size
    counters[C_RHS] += prepare_dense(model, p, mode, mid, A, C, D, P, n_stages, s, y, h,
                                     ws.K, y1, ytmp, F)
    # not a literal: the functions it reaches would compile twice; a switch index (int)
    # once one is found
    which: np.int64 | int = np.int64(-1)
    n_obs = 0
    th_term = 2.0
    for i in range(nsw):
        if flag[i] == BRACKETED and terminal[i] == 1:
            th = locate(model, p, mode, i, mid, s, h, y, f0, y1, f1r, F, lo[i], hi[i],
                        ytmp, gbuf)
            if th >= 0.0 and th < th_term:
                th_term = th
                which = i
    for i in range(nsw):
        if flag[i] == BRACKETED and terminal[i] == 0:
            th = locate(model, p, mode, i, mid, s, h, y, f0, y1, f1r, F, lo[i], hi[i],
                        ytmp, gbuf)
            if th >= 0.0 and th <= th_term:
                obs_th[n_obs] = th
                obs_i[n_obs] = i
                n_obs += 1
    if which < 0 and n_obs > 0:
        which, th_term, n_obs = _grazing(problem, method, cfg, ws, mode, s, y, h, n_obs,
                                         th_term)
    if which < 0:
        return which, 1.0, n_obs
    hs, nr = retake(model, p, mode, which, mid, A, B, C, n_stages, cfg.fsal, s, y, f0, h,
                    y1, f1r, F, th_term, cfg.event_tol, ws.Kr, ytmp, gbuf, ws.yev)
    counters[C_RHS] += nr
    return which, hs / h, n_obs


@njit(**PIECE)
def _grazing(problem, method, cfg, ws, mode, s, y, h, n_obs, th_term):
    """A shallow crossing that begins and ends between the samples (a grazing contact)
    still shows at an observer point: the peak of R lies beyond the surface.  Locate the
    entry before that point; drop the observer crossings after it.

    Returns ``(which, th_term, n_obs)``.
    """
    model, terminal, p, omega = problem
    mid = method[0]
    f0, y1, f1r, F, ytmp, gbuf = ws.f0, ws.y1, ws.f1r, ws.F, ws.ytmp, ws.gbuf
    obs_th, obs_i, yint, gobs = ws.obs_th, ws.obs_i, ws.yint, ws.gobs
    which: np.int64 | int = np.int64(-1)  # a switch index (int) once one is found
    for a in range(n_obs):
        interpolate(mid, obs_th[a], h, y, f0, y1, f1r, F, yint)
        model_switches(model, s + obs_th[a] * h, yint, p, mode, gobs)
        for i in range(terminal.size):
            # deeper than the event tolerance: a shallower one is at the resolution of
            # the event location itself (it would flip the mode back and forth: a false
            # Zeno stop)
            if terminal[i] == 1 and gobs[i] < -10.0 * cfg.event_tol:
                th = locate(model, p, mode, i, mid, s, h, y, f0, y1, f1r, F, 0.0,
                            obs_th[a], ytmp, gbuf)
                if th >= 0.0 and th < th_term:
                    th_term = th
                    which = i
    if which >= 0:  # drop the observer crossings after the event
        kept = 0
        for a in range(n_obs):
            if obs_th[a] <= th_term:
                obs_th[kept] = obs_th[a]
                obs_i[kept] = obs_i[a]
                kept += 1
        n_obs = kept
    return which, th_term, n_obs


@njit(**PIECE)
def _time_to_switch(terminal, G, h):
    """Time to the nearest terminal surface the step's end approaches (for the graded
    RK4 steps), from the switching functions at its start and end; 1e300: none."""
    t_to_switch = 1e300
    for i in range(terminal.size):
        if terminal[i] == 1 and G[0, i] > G[4, i] > 0.0:
            t_to_switch = min(t_to_switch, G[4, i] * h / (G[0, i] - G[4, i]))
    return t_to_switch


@njit(**PIECE)
def _log_observers(problem, method, cfg, ws, log, n_ev, mode, k, k_record, s, y, h, n_obs,
                   counters):
    """Log the observer crossings of the step in time order (those from ``tau = k_record
    T``); returns the log's count."""
    model, terminal, p, omega = problem
    obs_th, obs_i, yint = ws.obs_th, ws.obs_i, ws.yint
    T = cfg.T
    for a in range(n_obs):
        best = a
        for b in range(a + 1, n_obs):
            if obs_th[b] < obs_th[best]:
                best = b
        th = obs_th[best]
        i = obs_i[best]
        obs_th[best] = obs_th[a]
        obs_i[best] = obs_i[a]
        t_abs = k * T + s + th * h
        counters[C_OBSERVED] += 1
        if t_abs >= k_record * T:
            interpolate(method[0], th, h, y, ws.f0, ws.y1, ws.f1r, ws.F, yint)
            n_ev = _log(log, n_ev, t_abs, i, mode, mode, yint)
    return n_ev


@njit(**PIECE)
def _next_start(problem, cfg, ws, log, n_ev, mode, k_record, t_abs, s, y, y_end, which,
                g0_ok, counters):
    """Make the step's end ``y_end`` the next step's start: with the switching functions
    at the end (``g0_ok``: nothing changes in between) and the derivative there, or, at a
    located event of switch ``which`` (absolute time ``t_abs``), the mode change, logged,
    and the derivative in the new mode.  Returns the log's count."""
    model, terminal, p, omega = problem
    f0, G = ws.f0, ws.G
    for m in range(y.size):
        y[m] = y_end[m]
    if g0_ok:
        for i in range(terminal.size):
            G[0, i] = G[4, i]
    if which < 0:
        for m in range(y.size):
            f0[m] = ws.f1r[m]
        return n_ev
    mode_old, y_old = ws.mode_old, ws.yint
    for m in range(mode.size):
        mode_old[m] = mode[m]
    for m in range(y.size):
        y_old[m] = y[m]
    model_transition(model, s, y, p, mode, which)
    counters[C_EVENTS] += 1
    if t_abs >= k_record * cfg.T:  # the state before the event (before an impact's jump)
        n_ev = _log(log, n_ev, t_abs, which, mode_old, mode, y_old)
    model_rhs(model, s, y, p, mode, f0)
    counters[C_RHS] += 1
    return n_ev


@njit(**PIECE)
def _enter(model, p, mode, ks, y, f0, dense_m, T, nsw, counters):
    """The start of :func:`integrate`'s loop (of each period of a Benettin run).

    Returns the clock ``(k, s, h, steps in period, next dense sample)`` from ``ks`` and
    the state flags' initial value False; the derivative at the start goes into ``f0``.
    The flags (``at_event``: the step starts at a terminal event just located;
    ``retry``: the step is retried shorter from the same state and mode; ``g0_ok``:
    ``G[0]`` already holds the switching functions at the step's start, copied from the
    end of the step before when nothing changed in between) start from a comparison, not
    from the literal False: numba compiles the functions they are passed to once more
    for a literal argument.
    """
    k, s, h = int(ks[0]), ks[1], ks[2]
    model_rhs(model, s, y, p, mode, f0)
    counters[C_RHS] += 1
    steps_in_period, j_dense = resume(ks, s, dense_m, T)
    return k, s, h, steps_in_period, j_dense, nsw < 0


@njit(**LEAF)
def integrate(problem, method, opts, ws, y, mode, ks, k_end, k_record, strobe, log, n_ev,
              dense_m, dense, counters, renorm):
    """Integrate from ``(k, s) = ks[:2]`` until the start of forcing period ``k_end``.

    Parameters
    ----------
    problem : tuple ``(model, terminal, p, omega)``
        ``model``: a built-in model (:func:`.dispatch.builtin`) or ``(rhs, switches,
        transition)``; ``terminal``: int64 array, shape (n_switch,), 1 for a terminal
        (mode-changing) switch, 0 for an observer; ``p``: float64 parameter vector;
        ``omega``: forcing frequency, the period is ``T = 2 pi / omega``.
    method : tuple ``(id, A, B, C, E, E3, D, P, order, n_stages)``
        The Runge--Kutta method as data (:mod:`.tableaux`); not ``RK4_NOEVENTS``, whose
        loop is :func:`.noevents.integrate_noevents`.
    opts : float64 array
        ``(rtol, atol, h_fixed, h_max, bound, event_tol, max_steps_per_period, fixed,
        n_bound, n_err, tfac, g_in, g_out)`` (:mod:`.integrator`, read through
        :func:`.integrator.settings`).
    ws : Workspace
        Scratch arrays (:func:`workspace`), reusable across calls.
    y : float64 array, shape (n,)
        State at ``(k, s)``; overwritten with the final state.
    mode : int64 array
        Discrete mode, consistent with ``y``; overwritten.
    ks : float64 array, shape (3,), (4,) or (5,)
        ``(k, s, h[, steps[, j]])``: period index, local time, next step size and, when
        given, the steps taken so far in period ``k`` and the index of the next dense
        sample of period ``k`` (negative: derived from ``s``), both kept across LOG_FULL
        restarts; overwritten.
    k_end, k_record : int
        Stop at ``tau = k_end T``; record samples and events from ``tau = k_record T``.
    strobe : float64 array, shape (k_end - k_record + 1, n)
        Row ``j`` receives the state at ``tau = (k_record + j) T`` (row 0 by the caller
        when the run starts there).
    log : tuple ``(t, which, mode, state)``
        Event log, shapes (cap,), (cap,), (cap, 2 n_mode), (cap, n): absolute time,
        switch index, mode before and after, state.
    n_ev : int
        Entries of the log already used.
    dense_m : int
        Dense samples per period (0: none); ``dense`` has shape
        ``((k_end - k_record) dense_m + 1, n)``.
    counters : int64 array, shape (5,)
        Accumulates steps, RHS evaluations, rejected steps, events, observed crossings.
    renorm : tuple ``(n_state, bound, logs, states)``
        A Benettin run when ``logs`` (float64, shape (N, m)) has rows: the model is a
        variational model with ``m`` tangent columns, and ``N`` periods are integrated one
        at a time (``k_end``, ``k_record``, ``n_ev`` and ``dense_m`` are ignored; ``s``
        must be 0), each ended by :func:`.renormalise.renormalise` (its ``log |R_ii|``
        into ``logs``, the state into ``states``, shape (N, n_state), checked against
        ``bound``).  ``logs`` of shape (0, 0): a plain run.

    Returns
    -------
    status : int
        OK, or why the run stopped (see :mod:`.integrator`); LOG_FULL asks the caller to
        empty the log and call again.
    n_ev : int
        Entries of the log used.
    done : int
        Periods renormalised (a Benettin run; 0 otherwise).
    """
    model, terminal, p, omega = problem
    cfg = settings(opts, method[0], method[8], omega, y.size)
    T = cfg.T
    nsw = terminal.size
    cap = log[0].size
    f0, y1, G = ws.f0, ws.y1, ws.G
    n_periods = renorm[2].shape[0]
    done = n_periods - n_periods  # 0, not a literal (see the state flags below)
    while True:  # one pass for a plain run, one per period for a Benettin run
        if n_periods > 0:
            k_end = int(ks[0]) + 1
            k_record = k_end
            n_ev = done - done
        k, s, h, steps_in_period, j_dense, at_event = _enter(model, p, mode, ks, y, f0,
                                                             dense_m, T, nsw, counters)
        status, zeno = OK, 0
        t_since_event = h_cap = t_to_switch = 1e300
        retry = g0_ok = at_event  # (see _enter)
        while k < k_end:
            status = _room(n_ev, nsw, cap, steps_in_period, cfg.max_steps)
            if status != OK:
                break
            h, h_prop, lands = _step_size(problem, cfg, y, mode, f0, k, k_end, s, h, h_cap,
                                          min(t_since_event, t_to_switch), at_event, retry)
            retry = False
            if h < 1e-13 * T and not lands:
                status = STEP_UNDERFLOW
                break
            accepted, h, h_next = _attempt(problem, method, cfg, ws, mode, s, y, h, h_prop,
                                           lands, counters)
            if not accepted:
                if h < 1e-13 * T:
                    status = STEP_UNDERFLOW
                    break
                retry = True
                continue
            status = _check_state(y1, cfg.n_bound, cfg.bound)
            if status != OK:
                break
            counters[C_STEPS] += 1
            steps_in_period += 1
            at_event = False

            # --- events ------------------------------------------------------------------
            ready = False  # the continuous extension of the step is prepared
            th_end = 1.0
            which = np.int64(-1)  # not literals: the functions they reach would compile twice
            n_obs = np.int64(0)
            seen = detect(model, p, mode, terminal, s, h, y, f0, y1, ws.f1r, G, ws.ytmp,
                          ws.flag, ws.lo, ws.hi, g0_ok)
            g0_ok = True
            if seen:
                imm = _first_immediate(ws.flag)
                if imm >= 0:
                    zeno += 1
                    if zeno > _ZENO_LIMIT:
                        status = ZENO
                        break
                    outcome, n_ev = _switch_now(problem, cfg, ws, log, n_ev, mode, k, k_record,
                                                s, y, h, imm, counters)
                    g0_ok = outcome == _RETRY_SAME_START
                    if outcome == _SWITCHED:
                        at_event = True
                    else:
                        h_cap = 0.125 * h
                        retry = True
                    continue
                which, th_end, n_obs = _locate(problem, method, cfg, ws, mode, s, y, h,
                                               counters)
                ready = True
                if which >= 0:
                    lands = False
            if th_end > 0.0:
                zeno = 0
            else:
                # an event located at the very start of the step: time does not advance, so
                # it counts towards the Zeno guard like an immediate switch
                zeno += 1
                if zeno > _ZENO_LIMIT:
                    status = ZENO
                    break
            h_cap = 1e300
            # distance in time to the nearest terminal surface (for the graded RK4 steps)
            t_since_event = 0.0 if which >= 0 else t_since_event + h
            t_to_switch = 1e300 if which >= 0 else _time_to_switch(terminal, G, h)
            n_ev = _log_observers(problem, method, cfg, ws, log, n_ev, mode, k, k_record, s, y,
                                  h, n_obs, counters)

            # --- samples, the step's end is the next step's start --------------------------
            s_end = T if lands else s + th_end * h
            y_end = y1 if which < 0 else ws.yev
            j_dense = samples(problem, method, cfg, ws, mode, k, k_record, s, y, h, s_end,
                               lands, th_end, y_end, dense_m, dense, j_dense, strobe, ready,
                               counters)
            t_event = k * T + s + th_end * h
            k_start = k
            if lands or s_end >= T:
                k += 1
                j_dense = next_period_sample(j_dense, k, k_record, lands, s_end, dense_m, T)
                steps_in_period = 0
                s = 0.0 if lands else s_end - T
            else:
                s = s_end
            # the switching functions at the step's end are the next step's unless the mode
            # changes there or the local time wraps round to 0
            g0_ok = which < 0 and k == k_start
            n_ev = _next_start(problem, cfg, ws, log, n_ev, mode, k_record, t_event, s, y, y_end,
                               which, g0_ok, counters)
            at_event = which >= 0
            h = h_next
        suspend(ks, k, s, h, steps_in_period, j_dense, dense_m)
        if n_periods == 0 or status != OK:
            break
        status = renormalise(y, renorm[0], renorm[1], renorm[2], renorm[3], done)
        done += 1
        if status != OK or done == n_periods:
            break
    return status, n_ev, done
