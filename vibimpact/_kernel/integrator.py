"""Explicit Runge--Kutta integration of a piecewise-smooth model with event location.

Everything here is ``@njit``; plain float64/int64 arrays in and out.  A *model* is four
jitted functions with a common signature (see a kernel family's, e.g. the built-in
rotor's :mod:`vibimpact._kernel.rotor`)::

    model_rhs(model, s, y, p, mode, out)          # writes dy/ds into out
    model_switches(model, s, y, p, mode, g)       # writes the switching functions into g
    model_transition(model, s, y, p, mode, which) # updates mode at an event of
                                                  # terminal switch `which`
    (+ an int64 array `terminal`: 1 for a mode-changing switch, 0 for an observer)

Time is kept as ``(k, s)``: the forcing period index ``k`` and the local time
``s in [0, T)``, ``T = 2 pi / omega``.  The model sees the local time (it is forced with
period ``T``), so the phase of the forcing stays exact over 1e5 periods.

Algorithm of one step (methods as data; tableaux in :mod:`.tableaux`):

1. one Runge--Kutta step of size ``h`` (:func:`rk_step`), error estimate and step-size
   control for the embedded pairs (Hairer, Norsett & Wanner 1993, II.4 and II.10);
2. every switching function is sampled at the step's start, at three interior points of
   the cubic Hermite interpolant and at the step's end.  The first sample where a function is
   negative brackets its crossing, so a contact that begins and ends inside one step is
   found when it lasts longer than a quarter step; a shorter (grazing) one shows at the
   located extremum of an observer (the peak of the penetration lies beyond the
   surface), and the entry is located before it; a step that starts on a surface and
   sees the switch negative at its first sample is retried shorter instead of flipping
   the mode;
3. the crossing is refined on the method's own continuous extension (Illinois method),
   then the step is *retaken* from its start to the event time and the time corrected by
   Newton iterations on the retaken step until ``|g| <= event_tol``: the state at the event
   has the full order of the method, and the next step restarts there in the new mode
   (Hairer et al. 1993, II.6; Shampine & Thompson 2000, "Event location for ordinary
   differential equations", Comput. Math. Appl. 39, 43-54);
4. observer crossings before the event are refined and logged without a restart;
5. stroboscopic samples at ``s = T`` and optional dense samples are taken from the
   continuous extension.
"""
import math
from collections import namedtuple

import numpy as np
from numba import njit

from .dispatch import model_rhs
from .jitopts import INNER, PIECE
from .tableaux import DOP853, DP5, RK4, RK4_NOEVENTS

# status codes (mirrored in vibimpact.core.run.Status)
OK = 0
DIVERGED_NONFINITE = 1
DIVERGED_BOUND = 2
STEP_UNDERFLOW = 3
MAX_STEPS = 4
ZENO = 5
LOG_FULL = 6

# option vector layout
#: O_NBOUND: how many leading state entries the bound applies to (0: all; the model
#: state of a variational run, not its tangent vectors)
#: O_NERR, O_TFAC: the local error test measures the first O_NERR entries (0: all) at the
#: tolerances, the others (the tangent vectors of a variational run) at O_TFAC times the
#: tolerances (0: not at all)
#: O_GIN, O_GOUT: the method's local error constants of steps at a Hertz contact's entry
#: and exit (:func:`.tableaux.hertz_error_constants`; 0: steps not capped there)
(O_RTOL, O_ATOL, O_HFIX, O_HMAX, O_BOUND, O_EVTOL, O_MAXSTEPS, O_FIXED, O_NBOUND,
 O_NERR, O_TFAC, O_GIN, O_GOUT) = range(13)
N_OPTS = 13

# counters layout
C_STEPS, C_RHS, C_REJECTED, C_EVENTS, C_OBSERVED = range(5)
N_COUNTERS = 5

#: the option vector read once per call, by name (built by :func:`settings`)
Settings = namedtuple("Settings", (
    "T",          # forcing period 2 pi / omega
    "rtol", "atol", "h_fixed", "h_max", "bound", "event_tol", "max_steps",
    "fsal",       # the method evaluates f at the step's end (DP5, DOP853)
    "fixed",      # fixed steps (RK4, or an embedded method with O_FIXED)
    "expo",       # -1 / order: the step-size controller's exponent
    "order",
    "n_bound", "n_err", "tfac", "g_in", "g_out",
    "n_norm",     # entries the error norm divides by
))

_SAMPLES = (0.25, 0.5, 0.75)


@njit(**INNER)
def rk_step(model, p, mode, A, B, C, n_stages, fsal, s0, y0, h, K, ytmp, y1):
    """One explicit Runge--Kutta step.

    ``K[0]`` must hold ``f(s0, y0)`` on entry.  Fills ``K[1:n_stages]``, writes the new
    state into ``y1`` and, for FSAL methods, ``f(s0 + h, y1)`` into ``K[n_stages]``.
    Returns the number of right-hand-side evaluations made.
    """
    n = y0.size
    for i in range(1, n_stages):
        for m in range(n):
            acc = 0.0
            for j in range(i):
                acc += A[i, j] * K[j, m]
            ytmp[m] = y0[m] + h * acc
        model_rhs(model, s0 + C[i] * h, ytmp, p, mode, K[i])
    for m in range(n):
        acc = 0.0
        for j in range(n_stages):
            acc += B[j] * K[j, m]
        y1[m] = y0[m] + h * acc
    if fsal:
        model_rhs(model, s0 + h, y1, p, mode, K[n_stages])
        return n_stages
    return n_stages - 1


@njit(**INNER)
def error_norm(method, E, E3, K, n_stages, h, y0, y1, rtol, atol, n_err, tfac):
    """Scaled error norm of an embedded pair (<= 1 means the step is accepted).

    The first ``n_err`` entries are measured against ``atol + rtol |y|``, the others
    against ``tfac`` times that, or not at all when ``tfac <= 0``.
    """
    n = y0.size if tfac > 0.0 else n_err
    if method == DP5:
        acc = 0.0
        for m in range(n):
            e = 0.0
            for j in range(n_stages + 1):
                e += E[j] * K[j, m]
            sc = atol + rtol * max(abs(y0[m]), abs(y1[m]))
            if m >= n_err:
                sc *= tfac
            acc += (h * e / sc) ** 2
        return math.sqrt(acc / n)
    # DOP853: Hairer's combination of the 5th- and 3rd-order estimators
    e5 = 0.0
    e3 = 0.0
    for m in range(n):
        a5 = 0.0
        a3 = 0.0
        for j in range(n_stages + 1):
            a5 += E[j] * K[j, m]
            a3 += E3[j] * K[j, m]
        sc = atol + rtol * max(abs(y0[m]), abs(y1[m]))
        if m >= n_err:
            sc *= tfac
        e5 += (a5 / sc) ** 2
        e3 += (a3 / sc) ** 2
    den = e5 + 0.01 * e3
    if den == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt(den * n)


@njit(**INNER)
def prepare_dense(model, p, mode, method, A, C, D, P, n_stages, s0, y0, h, K, y1, ytmp, F):
    """Coefficients of the continuous extension of the last step into ``F``.

    DP5: ``F[0:4]`` = ``h K^T P``.  DOP853: three extra stages, then ``F[0:7]`` as in
    Hairer's CONTD8.  RK4 uses the cubic Hermite interpolant and needs nothing.
    Returns the number of right-hand-side evaluations made.
    """
    n = y0.size
    if method == DP5:
        for r in range(4):
            for m in range(n):
                acc = 0.0
                for j in range(n_stages + 1):
                    acc += K[j, m] * P[j, r]
                F[r, m] = h * acc
        return 0
    if method == DOP853:
        for i in range(n_stages + 1, n_stages + 4):
            for m in range(n):
                acc = 0.0
                for j in range(i):
                    acc += A[i, j] * K[j, m]
                ytmp[m] = y0[m] + h * acc
            model_rhs(model, s0 + C[i] * h, ytmp, p, mode, K[i])
        for m in range(n):
            dy = y1[m] - y0[m]
            bspl = h * K[0, m] - dy
            F[0, m] = dy
            F[1, m] = bspl
            F[2, m] = dy - h * K[n_stages, m] - bspl
            for r in range(4):
                acc = 0.0
                for j in range(n_stages + 4):
                    acc += D[r, j] * K[j, m]
                F[3 + r, m] = h * acc
        return 3
    return 0


@njit(**INNER)
def hermite(theta, h, y0, f0, y1, f1, out):
    """Cubic Hermite interpolant between two states with their derivatives."""
    t2 = theta * theta
    t3 = t2 * theta
    a = 2.0 * t3 - 3.0 * t2 + 1.0
    b = t3 - 2.0 * t2 + theta
    c = -2.0 * t3 + 3.0 * t2
    d = t3 - t2
    for m in range(y0.size):
        out[m] = a * y0[m] + h * b * f0[m] + c * y1[m] + h * d * f1[m]


@njit(**INNER)
def interpolate(method, theta, h, y0, f0, y1, f1, F, out):
    """State at ``s0 + theta h`` from the method's continuous extension."""
    n = y0.size
    if method == DP5:
        for m in range(n):
            out[m] = y0[m] + theta * (F[0, m] + theta * (F[1, m] + theta * (
                F[2, m] + theta * F[3, m])))
    elif method == DOP853:
        x = theta
        x1 = 1.0 - theta
        for m in range(n):
            acc = F[6, m]
            acc = F[5, m] + x * acc
            acc = F[4, m] + x1 * acc
            acc = F[3, m] + x * acc
            acc = F[2, m] + x1 * acc
            acc = F[1, m] + x * acc
            acc = F[0, m] + x1 * acc
            out[m] = y0[m] + x * acc
    else:
        hermite(theta, h, y0, f0, y1, f1, out)


@njit(**INNER)
def settings(opts, method_id, order, omega, n):
    """The option vector ``opts`` (layout above) as a :data:`Settings` for a method and a
    state of ``n`` entries."""
    fixed = method_id == RK4 or method_id == RK4_NOEVENTS or opts[O_FIXED] > 0.0
    tfac = opts[O_TFAC]
    n_bound = n if opts[O_NBOUND] <= 0.0 else min(n, int(opts[O_NBOUND]))
    n_err = n if opts[O_NERR] <= 0.0 else min(n, int(opts[O_NERR]))
    # steps touching a contact's end are sized from the method's constants there
    g_out = opts[O_GOUT] if not fixed else 0.0
    n_norm = n if tfac > 0.0 else n_err
    return Settings(2.0 * math.pi / omega, opts[O_RTOL], opts[O_ATOL], opts[O_HFIX],
                    opts[O_HMAX], opts[O_BOUND], opts[O_EVTOL], opts[O_MAXSTEPS],
                    method_id == DP5 or method_id == DOP853, fixed, -1.0 / order, order,
                    n_bound, n_err, tfac,
                    opts[O_GIN], g_out, n_norm)


@njit(**PIECE)
def log_event(log, n_ev, t, which, mode_before, mode_after, y):
    """Write one entry of the event log ``(t, which, mode, state)``; returns the count."""
    ev_t, ev_which, ev_mode, ev_y = log
    nm = mode_before.size
    ev_t[n_ev] = t
    ev_which[n_ev] = which
    for m in range(nm):
        ev_mode[n_ev, m] = mode_before[m]
        ev_mode[n_ev, nm + m] = mode_after[m]
    for m in range(y.size):
        ev_y[n_ev, m] = y[m]
    return n_ev + 1


@njit(**PIECE)
def check_state(y1, n_bound, bound):
    """OK, or DIVERGED_NONFINITE / DIVERGED_BOUND (the first ``n_bound`` entries beyond
    ``bound``) for a new state."""
    finite = True
    big = 0.0
    for m in range(y1.size):
        if not np.isfinite(y1[m]):
            finite = False
        elif m < n_bound and abs(y1[m]) > big:
            big = abs(y1[m])
    if not finite:
        return DIVERGED_NONFINITE
    if big > bound:
        return DIVERGED_BOUND
    return OK
