"""Recurrence residuals of a point sequence for the period test (``@njit``).

:func:`suffix_lag_residuals` fills, for every lag ``n`` and start ``k``, the largest
recurrence residual ``max_j |x[k' + n, j] - x[k', j]|`` over ``k' >= k``: the residual of
lag ``n`` over every trailing window at once (the window starting at ``k``).  The period
test of :func:`vibimpact.analysis.period.detect_period_windows` reads its decisions from
this table.
"""
import numpy as np
from numba import njit


@njit(cache=True)
def suffix_lag_residuals(x, n_max, res, hi, lo, mag):
    """Suffix maxima of lag residuals, and of the data's range and magnitude.

    Parameters
    ----------
    x : float64 array, shape (W, d)
        Finite points.
    n_max : int
        Largest lag, ``1 <= n_max < W``.
    res : float64 array, shape (W, n_max)
        Receives ``res[k, n - 1] = max_{k <= k' < W - n} max_j |x[k' + n, j] - x[k', j]|``
        (``-inf`` where ``k >= W - n``).
    hi, lo : float64 arrays, shape (W, d)
        Receive the largest and smallest value of each component over ``x[k:]``.
    mag : float64 array, shape (W,)
        Receives ``max |x[k:]|``.
    """
    W, d = x.shape
    for n in range(1, n_max + 1):
        run = -np.inf
        for k in range(W - 1, -1, -1):
            if k + n < W:
                r = 0.0
                for j in range(d):
                    v = abs(x[k + n, j] - x[k, j])
                    if v > r:
                        r = v
                if r > run:
                    run = r
            res[k, n - 1] = run
    m = 0.0
    for k in range(W - 1, -1, -1):
        for j in range(d):
            v = x[k, j]
            if k == W - 1:
                hi[k, j] = v
                lo[k, j] = v
            else:
                hi[k, j] = max(v, hi[k + 1, j])
                lo[k, j] = min(v, lo[k + 1, j])
            if abs(v) > m:
                m = abs(v)
        mag[k] = m
