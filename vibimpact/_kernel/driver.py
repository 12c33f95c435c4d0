"""The integration loop: steps, events, stroboscopic and dense samples (``@njit``).

:func:`integrate` is generic over the model: an integer for a built-in model (cached on
disk) or a tuple of numba functions for a user model (see :mod:`.dispatch`).
"""
import math

import numpy as np
from numba import njit

from .dispatch import model_rhs, model_step_cap, model_switches, model_transition
from .events import BRACKETED, IMMEDIATE, detect, locate, retake
from .integrator import (C_EVENTS, C_OBSERVED, C_REJECTED, C_RHS, C_STEPS,
                         DIVERGED_BOUND, DIVERGED_NONFINITE, LOG_FULL, MAX_STEPS, O_ATOL,
                         O_BOUND, O_EVTOL, O_FIXED, O_GIN, O_GOUT, O_HFIX, O_HMAX, O_MAXSTEPS,
                         O_NBOUND, O_NERR, O_RTOL, O_TFAC, OK, STEP_UNDERFLOW, ZENO,
                         error_norm, interpolate, prepare_dense, rk_step)
from .tableaux import RK4


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
def _log(n_ev, t, which, mode_before, mode_after, y, ev_t, ev_which, ev_mode, ev_y):
    nm = mode_before.size
    ev_t[n_ev] = t
    ev_which[n_ev] = which
    for m in range(nm):
        ev_mode[n_ev, m] = mode_before[m]
        ev_mode[n_ev, nm + m] = mode_after[m]
    for m in range(y.size):
        ev_y[n_ev, m] = y[m]
    return n_ev + 1


@njit(cache=True, error_model="numpy")
def integrate(model, terminal, method, A, B, C, E, E3, D, P, order,
              n_stages, p, omega, y, mode, ks, opts, k_end, k_record, strobe, ev_t,
              ev_which, ev_mode, ev_y, n_ev, dense_m, dense, counters):
    """Integrate from ``(k, s) = ks[:2]`` until the start of forcing period ``k_end``.

    Parameters
    ----------
    model : int or tuple
        A built-in model id (:mod:`.dispatch`) or ``(rhs, switches, transition)``.
    terminal : int64 array, shape (n_switch,)
        1 for a terminal (mode-changing) switch, 0 for an observer.
    method, A, B, C, E, E3, D, P, order, n_stages
        The Runge--Kutta method as data (:mod:`.tableaux`).
    p : float64 array
        Model parameters.
    omega : float
        Forcing frequency; the period is ``T = 2 pi / omega``.
    y : float64 array, shape (n,)
        State at ``(k, s)``; overwritten with the final state.
    mode : int64 array
        Discrete mode, consistent with ``y``; overwritten.
    ks : float64 array, shape (3,) or (4,)
        ``(k, s, h[, steps])``: period index, local time, next step size and, when given,
        the steps taken so far in period ``k`` (kept across LOG_FULL restarts);
        overwritten.
    opts : float64 array
        ``(rtol, atol, h_fixed, h_max, bound, event_tol, max_steps_per_period, fixed,
        n_bound)`` (:mod:`.integrator`).
    k_end, k_record : int
        Stop at ``tau = k_end T``; record samples and events from ``tau = k_record T``.
    strobe : float64 array, shape (k_end - k_record + 1, n)
        Row ``j`` receives the state at ``tau = (k_record + j) T`` (row 0 by the caller
        when the run starts there).
    ev_t, ev_which, ev_mode, ev_y : arrays, shapes (cap,), (cap,), (cap, 2 n_mode), (cap, n)
        Event log: absolute time, switch index, mode before and after, state.
    n_ev : int
        Entries of the log already used.
    dense_m : int
        Dense samples per period (0: none); ``dense`` has shape
        ``((k_end - k_record) dense_m + 1, n)``.
    counters : int64 array, shape (5,)
        Accumulates steps, RHS evaluations, rejected steps, events, observed crossings.

    Returns
    -------
    status : int
        OK, or why the run stopped (see :mod:`.integrator`); LOG_FULL asks the caller to
        empty the log and call again.
    n_ev : int
        Entries of the log used.
    """
    T = 2.0 * math.pi / omega
    n = y.size
    nsw = terminal.size
    nm = mode.size
    K = np.zeros((16, n))
    Kr = np.zeros((16, n))
    F = np.zeros((7, n))
    ytmp = np.empty(n)
    y1 = np.empty(n)
    yev = np.empty(n)
    yint = np.empty(n)
    f0 = np.empty(n)
    f1r = np.empty(n)
    G = np.empty((5, nsw))
    gbuf = np.empty(nsw)
    gobs = np.empty(nsw)
    flag = np.zeros(nsw, dtype=np.int64)
    lo = np.zeros(nsw)
    hi = np.zeros(nsw)
    obs_th = np.empty(nsw)
    obs_i = np.empty(nsw, dtype=np.int64)
    mode_old = mode.copy()
    # G[0] already holds the switching functions at the step's start (copied from the end
    # of the step before when nothing changed in between: one evaluation fewer per step)
    g0_ok = False
    rtol = opts[O_RTOL]
    atol = opts[O_ATOL]
    bound = opts[O_BOUND]
    evtol = opts[O_EVTOL]
    fsal = method != RK4
    fixed = method == RK4 or opts[O_FIXED] > 0.0
    expo = -1.0 / order
    cap = ev_t.size
    n_bound = n if opts[O_NBOUND] <= 0.0 else min(n, int(opts[O_NBOUND]))
    n_err = n if opts[O_NERR] <= 0.0 else min(n, int(opts[O_NERR]))
    tfac = opts[O_TFAC]
    # steps touching a contact's end are sized from the method's constants there
    g_in = opts[O_GIN]
    g_out = opts[O_GOUT] if not fixed else 0.0
    n_norm = n if tfac > 0.0 else n_err
    at_event = False  # the step starts at a terminal event just located
    retry = False  # the step is retried shorter from the same state and mode (its cap holds)

    k = int(ks[0])
    s = ks[1]
    h = ks[2]
    model_rhs(model, s, y, p, mode, f0)
    counters[C_RHS] += 1
    status = OK
    # carried across calls in ks[3] when the caller provides it (a LOG_FULL restart
    # must not reset the per-period step limit)
    steps_in_period = int(ks[3]) if ks.size > 3 else 0
    zeno = 0
    t_since_event = 1e300
    h_cap = 1e300
    t_to_switch = 1e300
    while k < k_end:
        if n_ev + nsw + 2 > cap:
            status = LOG_FULL
            break
        if steps_in_period > opts[O_MAXSTEPS]:
            status = MAX_STEPS
            break
        if fixed:
            hf = opts[O_HFIX]
            h = (math.floor(s / hf + 1e-9) + 1.0) * hf - s
            h = min(h, graded_step(hf, min(t_since_event, t_to_switch), order))
        h = min(h, opts[O_HMAX], h_cap)
        if g_out > 0.0 and not retry:
            h = min(h, model_step_cap(model, y, p, mode, f0, at_event, rtol, atol, n_norm,
                                      g_in, g_out))
        retry = False
        h_prop = h
        lands = False
        if s + h >= T * (1.0 - 1e-12) and (k == k_end - 1 or s + h <= T * (1.0 + 1e-12)):
            h = T - s
            lands = True
        if h < 1e-13 * T and not lands:
            status = STEP_UNDERFLOW
            break
        for m in range(n):
            K[0, m] = f0[m]
        counters[C_RHS] += rk_step(model, p, mode, A, B, C, n_stages, fsal, s, y, h, K, ytmp,
                                   y1)
        h_next = h
        if fsal and not fixed:
            err = error_norm(method, E, E3, K, n_stages, h, y, y1, rtol, atol, n_err, tfac)
            if not np.isfinite(err) or err > 1.0:
                counters[C_REJECTED] += 1
                fac = 0.2 if not np.isfinite(err) else max(0.2, 0.9 * err ** expo)
                h = h * fac
                if h < 1e-13 * T:
                    status = STEP_UNDERFLOW
                    break
                retry = True
                continue
            fac = 10.0 if err == 0.0 else min(10.0, max(0.2, 0.9 * err ** expo))
            h_next = h * fac
            if lands and h_prop > h_next:
                h_next = h_prop
        if fsal:
            for m in range(n):
                f1r[m] = K[n_stages, m]
        else:
            model_rhs(model, s + h, y1, p, mode, f1r)
            counters[C_RHS] += 1
        finite = True
        big = 0.0
        for m in range(n):
            if not np.isfinite(y1[m]):
                finite = False
            elif m < n_bound and abs(y1[m]) > big:
                big = abs(y1[m])
        if not finite:
            status = DIVERGED_NONFINITE
            break
        if big > bound:
            status = DIVERGED_BOUND
            break
        counters[C_STEPS] += 1
        steps_in_period += 1
        at_event = False

        # --- events ------------------------------------------------------------------
        dense_ready = False
        th_end = 1.0
        which = -1
        n_obs = 0
        event_seen = detect(model, p, mode, terminal, s, h, y, f0, y1, f1r, G, ytmp, flag,
                            lo, hi, g0_ok)
        g0_ok = True
        if event_seen:
            imm = -1
            for i in range(nsw):
                if flag[i] == IMMEDIATE:
                    imm = i
                    break
            if imm >= 0:
                zeno += 1
                if zeno > 50:
                    status = ZENO
                    break
                if abs(G[0, imm]) <= evtol and h > 1e-6 * T:
                    # the state sits on the surface (an event just put it there) and the
                    # switch is negative at the first sample: a crossing back shorter
                    # than a quarter step (a shallow contact), not an inconsistent mode.
                    # Retry with a shorter step so the samples resolve it.
                    h_cap = 0.125 * h
                    retry = True
                    continue
                for m in range(nm):
                    mode_old[m] = mode[m]
                model_transition(model, s, y, p, mode, imm)
                g0_ok = False
                same = True
                for m in range(nm):
                    if mode[m] != mode_old[m]:
                        same = False
                if same:
                    # the mode is right at the start: the switch value sits within rounding
                    # of zero and the crossing back happens before the first sample.
                    # Retry with a shorter step so the samples resolve it.
                    h_cap = 0.125 * h
                    retry = True
                    continue
                counters[C_EVENTS] += 1
                if k >= k_record:
                    n_ev = _log(n_ev, k * T + s, imm, mode_old, mode, y, ev_t, ev_which,
                                ev_mode, ev_y)
                model_rhs(model, s, y, p, mode, f0)
                counters[C_RHS] += 1
                at_event = True
                continue
            counters[C_RHS] += prepare_dense(model, p, mode, method, A, C, D, P, n_stages, s,
                                             y, h, K, y1, ytmp, F)
            dense_ready = True
            th_term = 2.0
            for i in range(nsw):
                if flag[i] == BRACKETED and terminal[i] == 1:
                    th = locate(model, p, mode, i, method, s, h, y, f0, y1, f1r, F, lo[i],
                                hi[i], ytmp, gbuf)
                    if th >= 0.0 and th < th_term:
                        th_term = th
                        which = i
            for i in range(nsw):
                if flag[i] == BRACKETED and terminal[i] == 0:
                    th = locate(model, p, mode, i, method, s, h, y, f0, y1, f1r, F, lo[i],
                                hi[i], ytmp, gbuf)
                    if th >= 0.0 and th <= th_term:
                        obs_th[n_obs] = th
                        obs_i[n_obs] = i
                        n_obs += 1
            if which < 0 and n_obs > 0:
                # a shallow crossing that begins and ends between the samples (a grazing
                # contact) still shows at an observer point: the peak of R lies beyond the
                # surface.  Locate the entry before that point.
                for a in range(n_obs):
                    interpolate(method, obs_th[a], h, y, f0, y1, f1r, F, yint)
                    model_switches(model, s + obs_th[a] * h, yint, p, mode, gobs)
                    for i in range(nsw):
                        # deeper than the event tolerance: a shallower one is at the
                        # resolution of the event location itself (it would flip the
                        # mode back and forth: a false Zeno stop)
                        if terminal[i] == 1 and gobs[i] < -10.0 * evtol:
                            th = locate(model, p, mode, i, method, s, h, y, f0, y1, f1r, F,
                                        0.0, obs_th[a], ytmp, gbuf)
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
            if which >= 0:
                hs, nr = retake(model, p, mode, which, method, A, B, C, n_stages,
                                fsal, s, y, f0, h, y1, f1r, F, th_term, evtol, Kr, ytmp,
                                gbuf, yev)
                counters[C_RHS] += nr
                th_end = hs / h
                lands = False
        if th_end > 0.0:
            zeno = 0
        else:
            # an event located at the very start of the step: time does not advance, so
            # it counts towards the Zeno guard like an immediate switch
            zeno += 1
            if zeno > 50:
                status = ZENO
                break
        h_cap = 1e300
        # distance in time to the nearest terminal surface (for the graded RK4 steps)
        t_since_event = 0.0 if which >= 0 else t_since_event + h
        t_to_switch = 1e300
        if which < 0:
            for i in range(nsw):
                if terminal[i] == 1 and G[0, i] > G[4, i] > 0.0:
                    t_to_switch = min(t_to_switch, G[4, i] * h / (G[0, i] - G[4, i]))

        # --- observer crossings, in time order ------------------------------------------
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
                interpolate(method, th, h, y, f0, y1, f1r, F, yint)
                n_ev = _log(n_ev, t_abs, i, mode, mode, yint, ev_t, ev_which, ev_mode,
                            ev_y)

        # --- dense and stroboscopic samples -----------------------------------------------
        s_abs_end = T if lands else s + th_end * h
        y_end = y1 if which < 0 else yev
        if dense_m > 0 and k + 1 >= k_record:
            # samples at local times j T / dense_m inside this step; j >= dense_m belong to
            # the next period (a step may run past the period's end)
            dt = T / dense_m
            j = int(math.floor(s / dt)) + 1
            while j * dt <= s_abs_end or (lands and j == dense_m):
                kk = k + j // dense_m
                idx = (kk - k_record) * dense_m + j % dense_m
                if kk >= k_record and idx < dense.shape[0]:
                    if lands and j == dense_m:
                        for m in range(n):
                            dense[idx, m] = y_end[m]
                    else:
                        if not dense_ready:
                            counters[C_RHS] += prepare_dense(model, p, mode, method, A, C, D,
                                                             P, n_stages, s, y, h, K, y1,
                                                             ytmp, F)
                            dense_ready = True
                        interpolate(method, min((j * dt - s) / h, th_end), h, y, f0, y1,
                                    f1r, F, yint)
                        for m in range(n):
                            dense[idx, m] = yint[m]
                if lands and j == dense_m:
                    break
                j += 1
        k_start = k
        s_start = s
        if lands or s_abs_end >= T:
            k += 1
            steps_in_period = 0
            if k >= k_record and k - k_record < strobe.shape[0]:
                row = k - k_record
                if lands:
                    for m in range(n):
                        strobe[row, m] = y_end[m]
                else:
                    if not dense_ready:
                        counters[C_RHS] += prepare_dense(model, p, mode, method, A, C, D, P,
                                                         n_stages, s, y, h, K, y1, ytmp, F)
                        dense_ready = True
                    interpolate(method, (T - s) / h, h, y, f0, y1, f1r, F, yint)
                    for m in range(n):
                        strobe[row, m] = yint[m]
            s = 0.0 if lands else s_abs_end - T
        else:
            s = s_abs_end
        for m in range(n):
            y[m] = y_end[m]
        # the step's end is the next step's start: its switching functions are known
        # unless the mode changes there or the local time wraps round to 0
        g0_ok = which < 0 and k == k_start
        if g0_ok:
            for i in range(nsw):
                G[0, i] = G[4, i]
        if which >= 0:
            for m in range(nm):
                mode_old[m] = mode[m]
            model_transition(model, s, y, p, mode, which)
            counters[C_EVENTS] += 1
            t_abs = k_start * T + s_start + th_end * h
            if t_abs >= k_record * T:
                n_ev = _log(n_ev, t_abs, which, mode_old, mode, y, ev_t, ev_which, ev_mode,
                            ev_y)
            model_rhs(model, s, y, p, mode, f0)
            counters[C_RHS] += 1
            at_event = True
        else:
            for m in range(n):
                f0[m] = f1r[m]
        h = h_next
    ks[0] = k
    ks[1] = s
    ks[2] = h
    if ks.size > 3:
        ks[3] = steps_in_period
    return status, n_ev
