"""Event detection and location inside an accepted step (all ``@njit``).

See :mod:`vibimpact._kernel.integrator` for the algorithm.  A switching function is
positive while the current mode is consistent; an *event* is its crossing to negative values.
"""
import numpy as np
from numba import njit

from .dispatch import model_switches
from .integrator import hermite, interpolate, rk_step
from .jitopts import INNER

NO_EVENT = 0
BRACKETED = 1
IMMEDIATE = 2

#: sample points (fractions of the step) at which crossings are looked for
THETAS = np.array([0.0, 0.25, 0.5, 0.75, 1.0])


@njit(**INNER)
def detect(model, p, mode, terminal, s0, h, y0, f0, y1, f1, G, ytmp, flag, lo, hi, g0_known):
    """Sample every switching function over the step and bracket its first crossing.

    ``G`` (shape (5, n_switch)) receives the samples at :data:`THETAS` (cubic Hermite
    interpolant inside, exact at the ends); when ``g0_known`` the caller has already put
    the values at the step's start into ``G[0]``.  For each switch ``i``: ``flag[i]`` is
    NO_EVENT, BRACKETED (crossing in ``[lo[i], hi[i]]``) or IMMEDIATE (a terminal switch
    already negative at the start and still negative at the first sample: the mode is
    inconsistent, switch at once).
    """
    nsw = flag.size
    if not g0_known:
        model_switches(model, s0, y0, p, mode, G[0])
    for j in range(1, 4):
        hermite(THETAS[j], h, y0, f0, y1, f1, ytmp)
        model_switches(model, s0 + THETAS[j] * h, ytmp, p, mode, G[j])
    model_switches(model, s0 + h, y1, p, mode, G[4])
    any_event = False
    for i in range(nsw):
        flag[i] = NO_EVENT
        if terminal[i] == 1:
            for j in range(1, 5):
                if G[j, i] < 0.0:
                    if j == 1 and G[0, i] <= 0.0:
                        flag[i] = IMMEDIATE
                    elif G[j - 1, i] >= 0.0:
                        flag[i] = BRACKETED
                        lo[i] = THETAS[j - 1]
                        hi[i] = THETAS[j]
                    else:
                        # negative at j-1 too: only possible when j-1 == 0 (handled) or
                        # after a positive sample, which the loop would have stopped at
                        flag[i] = BRACKETED
                        lo[i] = 0.0
                        hi[i] = THETAS[j]
                    break
        else:
            for j in range(1, 5):
                if G[j - 1, i] > 0.0 and G[j, i] <= 0.0:
                    flag[i] = BRACKETED
                    lo[i] = THETAS[j - 1]
                    hi[i] = THETAS[j]
                    break
        if flag[i] != NO_EVENT:
            any_event = True
    return any_event


@njit(**INNER)
def _g_at(model, p, mode, i, method, theta, s0, h, y0, f0, y1, f1, F, ytmp, gbuf):
    interpolate(method, theta, h, y0, f0, y1, f1, F, ytmp)
    model_switches(model, s0 + theta * h, ytmp, p, mode, gbuf)
    return gbuf[i]


@njit(**INNER)
def locate(model, p, mode, i, method, s0, h, y0, f0, y1, f1, F, ta, tb, ytmp, gbuf):
    """Refine the crossing of switch ``i`` in ``[ta, tb]`` on the continuous extension.

    Illinois variant of regula falsi.  Returns the fraction ``theta`` of the step just past
    the crossing (``g < 0``), or -1.0 when the accurate interpolant shows no crossing in the
    bracket (the Hermite sample saw a dip that is not there).
    """
    ga = _g_at(model, p, mode, i, method, ta, s0, h, y0, f0, y1, f1, F, ytmp, gbuf)
    gb = _g_at(model, p, mode, i, method, tb, s0, h, y0, f0, y1, f1, F, ytmp, gbuf)
    if ga < 0.0 and ta > 0.0:
        # the accurate interpolant crosses before the Hermite bracket: bracket the first
        # crossing from the last non-negative point found by halving towards the start.
        # Falling straight back to 0 would locate a zero-length event whenever g(0) sits
        # a rounding error below zero (a state an event just put on the surface), and the
        # mode would flip back and forth without time advancing.
        tb = ta
        gb = ga
        ta = 0.0
        t = tb
        for _ in range(10):
            t *= 0.5
            gt = _g_at(model, p, mode, i, method, t, s0, h, y0, f0, y1, f1, F, ytmp, gbuf)
            if gt >= 0.0:
                ta = t
                break
            tb = t
            gb = gt
        ga = _g_at(model, p, mode, i, method, ta, s0, h, y0, f0, y1, f1, F, ytmp, gbuf)
    if gb >= 0.0:
        if tb < 1.0:
            tb = 1.0
            gb = _g_at(model, p, mode, i, method, tb, s0, h, y0, f0, y1, f1, F, ytmp,
                       gbuf)
        if gb >= 0.0:
            return -1.0
    if ga < 0.0:
        return 0.0
    side = 0
    for _ in range(200):
        if tb - ta <= 1e-15:
            break
        t = (ta * gb - tb * ga) / (gb - ga)
        if not (ta < t < tb):
            t = 0.5 * (ta + tb)
        gt = _g_at(model, p, mode, i, method, t, s0, h, y0, f0, y1, f1, F, ytmp, gbuf)
        if gt < 0.0:
            tb = t
            gb = gt
            if side == -1:
                ga *= 0.5
            side = -1
        else:
            ta = t
            ga = gt
            if side == 1:
                gb *= 0.5
            side = 1
            if gt == 0.0:
                break
    return tb


@njit(**INNER)
def retake(model, p, mode, i, method, A, B, C, n_stages, fsal, s0, y0, f0, h, y1,
           f1, F, theta, event_tol, Kr, ytmp, gbuf, yev):
    """Retake the step from ``s0`` to the event and correct its time by Newton iterations.

    The slope of ``g_i`` comes from the continuous extension of the original step; each
    iteration is one full step of the method from ``s0``, so the returned state ``yev`` has
    the method's full order.  Returns ``(h_event, n_rhs)``.
    """
    n_rhs = 0
    d = 1e-6
    ta = max(theta - d, 0.0)
    tb = min(theta + d, 1.0)
    ga = _g_at(model, p, mode, i, method, ta, s0, h, y0, f0, y1, f1, F, ytmp, gbuf)
    gb = _g_at(model, p, mode, i, method, tb, s0, h, y0, f0, y1, f1, F, ytmp, gbuf)
    slope = (gb - ga) / ((tb - ta) * h)
    hs = theta * h
    for m in range(y0.size):
        Kr[0, m] = f0[m]
    done = -1.0
    # not the literal False: numba would compile rk_step once more for it
    no_fsal = np.bool_(False)
    for _ in range(8):
        if hs <= 0.0:
            done = 0.0
            for m in range(y0.size):
                yev[m] = y0[m]
            break
        n_rhs += rk_step(model, p, mode, A, B, C, n_stages, no_fsal, s0, y0, hs, Kr, ytmp,
                         yev)
        done = hs
        model_switches(model, s0 + hs, yev, p, mode, gbuf)
        g = gbuf[i]
        if abs(g) <= event_tol or slope == 0.0 or not np.isfinite(g):
            break
        hs_new = min(max(hs - g / slope, 0.0), h)
        if hs_new == hs:
            break
        hs = hs_new
    return done, n_rhs
