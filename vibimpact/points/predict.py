"""Predictor of a continuation: the next periodic orbit's point from the branch so far.

Along a branch of period-1 orbits the orbit's stroboscopic point ``x*(eta)`` is a smooth
function of the frequency, so the polynomial through the last ``m`` converged points
predicts the next one with an error ``O(h^m x^(m))`` for a step ``h`` (the predictor of
numerical continuation, Allgower & Georg 2003, ch. 2; Seydel 2010, sec. 4.4).  On the
fig8 map (``h = 0.004``) the cubic predictor (``m = 4``) lands within ``1e-6`` of the
orbit's size at about 2 of 3 points, against ``7e-3`` for the previous point's state; a
sweep point then checks the prediction by integrating from it (see
:func:`vibimpact.sweeps.analyse_point`, ``guess``), so a poor prediction costs time, never
a wrong result.

References
----------
.. [1] E. L. Allgower, K. Georg, *Introduction to Numerical Continuation Methods*, SIAM
   (2003).
.. [2] R. Seydel, *Practical Bifurcation and Stability Analysis*, 3rd ed., Springer
   (2010).
"""
from __future__ import annotations

import numpy as np

from .._kernel.boundary import matmul

__all__ = ["extrapolate_branch"]


def extrapolate_branch(params, states, at):
    """Value at ``at`` of the interpolating polynomial through ``(params[j], states[j])``.

    Parameters
    ----------
    params : array_like, shape (m,)
        Distinct parameter values of the branch's points (any order, any spacing).
    states : array_like, shape (m, d)
        The points (e.g. stroboscopic states of period-1 orbits).
    at : float
        Where to predict.

    Returns
    -------
    ndarray, shape (d,)
        The Lagrange extrapolation (degree ``m - 1``).

    Raises
    ------
    ValueError
        Naming ``params`` (not distinct finite numbers) or ``states`` (shape).
    """
    e = np.asarray(params, dtype=np.float64).reshape(-1)
    x = np.asarray(states, dtype=np.float64)
    if x.ndim != 2 or x.shape[0] != e.size or e.size == 0:
        raise ValueError(f"states must have shape ({e.size}, d), got {x.shape}")
    if not np.all(np.isfinite(e)) or np.unique(e).size != e.size:
        raise ValueError("params must be distinct finite numbers")
    w = np.ones(e.size)
    for j in range(e.size):
        for i in range(e.size):
            if i != j:
                w[j] *= (at - e[i]) / (e[j] - e[i])
    return matmul(w[None, :], np.ascontiguousarray(x))[0]
