"""Lyapunov-exponent loops over forcing periods (``@njit``).

The Benettin loop (the variational model one forcing period at a time, its tangent
vectors re-orthonormalised by QR after each: Benettin, Galgani, Giorgilli & Strelcyn
1980, Meccanica 15, 9-30; Shimada & Nagashima 1979, Prog. Theor. Phys. 61, 1605) is a
mode of :func:`.driver.integrate` itself (its ``renorm`` argument, with
:func:`.renormalise.renormalise`): a separate loop calling the integrator would compile
the whole integrator once more inside it.  :func:`two_trajectory` follows a reference and a
perturbed trajectory and renormalises their separation after each period (Benettin,
Galgani & Strelcyn 1976, Phys. Rev. A 14, 2338).  Both write one row of logarithmic growth
factors per period; the caller turns them into exponents and error bars.
"""
import math

import numpy as np
from numba import njit

from .driver import integrate
from .integrator import DIVERGED_BOUND, OK
from .jitopts import ALLOC, PIECE
from .linalg import matmul, qr
from .noevents import integrate_noevents
from .tableaux import RK4_NOEVENTS


@njit(**PIECE)
def _one_period(problem, method, opts, ws, y, mode, ks, k_next, strobe, log, none, dense,
                counters, plain):
    """One forcing period of a plain run, on the method's loop (the driver's, or the era
    integrator's, :mod:`.noevents`)."""
    if method[0] == RK4_NOEVENTS:
        return integrate_noevents(problem, method, opts, ws, y, mode, ks, k_next, k_next,
                                  strobe, log, none, none, dense, counters, plain)
    return integrate(problem, method, opts, ws, y, mode, ks, k_next, k_next, strobe, log,
                     none, none, dense, counters, plain)


@njit(inline="always", **ALLOC)
def _period_buffers(n, n_mode):
    """What one forcing period of :func:`.driver.integrate` needs besides the state and
    the workspace: a stroboscopic row, an event log (nothing is recorded before the
    period's end, so it never fills) and a dense row."""
    log = (np.empty(64), np.empty(64, dtype=np.int64),
           np.empty((64, 2 * n_mode), dtype=np.int64), np.empty((64, n)))
    return np.empty((1, n)), log, np.empty((1, n))


@njit(cache=True, error_model="numpy")
def two_trajectory(problem, method, opts, ws, y, mode, ks, y2, mode2, ks2, d0, scale,
                   bound, n_periods, logs, counters):
    """Reference ``y`` and perturbed ``y2`` over ``n_periods`` periods, renormalised to ``d0``.

    ``problem``, ``method``, ``opts``, ``ws`` as in :func:`.driver.integrate`.  The separation is
    measured in the norm ``|(y2 - y) / scale|``.  After each period the perturbed state is
    put back at distance ``d0`` along the current separation and takes the reference's
    mode; in the rare case that the two lie on different sides of a switching surface,
    the driver's first step finds the switching function negative and corrects the mode
    (an immediate event).  ``logs[j, 0]`` receives ``log(d_j / d0)``.
    """
    n = y.size
    strobe, log, dense = _period_buffers(n, mode.size)
    none = strobe.shape[0] - 1  # 0, not a literal (one compiled integrate for every caller)
    plain = (none, 0.0, np.empty((0, 0)), np.empty((0, 0)))  # no renormalisation
    for j in range(n_periods):
        k_next = int(ks[0]) + 1
        status, _, _ = _one_period(problem, method, opts, ws, y, mode, ks, k_next, strobe,
                                   log, none, dense, counters, plain)
        if status != OK:
            return status, j
        status, _, _ = _one_period(problem, method, opts, ws, y2, mode2, ks2, k_next, strobe,
                                   log, none, dense, counters, plain)
        if status != OK:
            return status, j
        d = 0.0
        for i in range(n):
            if abs(y[i]) > bound:
                return DIVERGED_BOUND, j
            e = (y2[i] - y[i]) / scale[i]
            d += e * e
        d = math.sqrt(d)
        logs[j, 0] = math.log(d / d0) if d > 0.0 else -np.inf
        if d == 0.0:
            d = d0
            y2[0] = y[0] + d0 * scale[0]
            for i in range(1, n):
                y2[i] = y[i]
        else:
            for i in range(n):
                y2[i] = y[i] + (y2[i] - y[i]) * (d0 / d)
        for i in range(mode.size):
            mode2[i] = mode[i]
        ks2[2] = ks[2]
    return OK, n_periods


@njit(cache=True, error_model="numpy")
def qr_growth(J, logs):
    """``log |R_ii|`` of the QR re-orthonormalised product of map Jacobians.

    ``J`` has shape (N, d, d); row ``k`` of ``logs`` (shape (N, d)) receives the growth
    factors of step ``k`` (Eckmann & Ruelle 1985, Rev. Mod. Phys. 57, 617, sec. III.B).
    """
    N = J.shape[0]
    d = J.shape[1]
    Q = np.eye(d)
    for k in range(N):
        q, r = qr(matmul(J[k], Q))
        for c in range(d):
            rc = r[c, c]
            logs[k, c] = math.log(abs(rc)) if rc != 0.0 else -np.inf
            sg = 1.0 if rc >= 0.0 else -1.0
            for i in range(d):
                Q[i, c] = sg * q[i, c]
