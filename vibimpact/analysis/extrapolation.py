"""Fixed points of a converging map iteration by minimal polynomial extrapolation.

A stroboscopic sequence ``x_{j+1} = P^n(x_j)`` that converges to a stable period-``n``
orbit approaches its point ``x*`` like ``x_j - x* ~ sum_i a_i mu_i^j`` (the Floquet
multipliers ``mu_i``, ``|mu_i| < 1``).  Waiting for the slowest mode to decay below a
tolerance takes ``log(tol) / log|mu|`` periods: about 130 for ``|mu| = 0.9`` and a
``1e-6`` tolerance.  For a *linear* iteration in ``d`` dimensions the minimal polynomial of
the map has degree ``<= d``, so ``d + 2`` iterates determine ``x*`` exactly; for the
non-linear map the error of the extrapolated point is of second order in the error of the
iterates, and repeating it (a restart from ``x*``) converges quadratically, like Newton's
method, without any Jacobian (Skelboe 1980 used it for the periodic steady state of
circuits).

References
----------
.. [1] S. Cabay, L. W. Jackson, "A polynomial extrapolation method for finding limits and
   antilimits of vector sequences", *SIAM J. Numer. Anal.* 13 (1976) 734-752.
.. [2] S. Skelboe, "Computation of the periodic steady-state response of nonlinear
   networks by extrapolation methods", *IEEE Trans. Circuits Syst.* 27 (1980) 161-175.
.. [3] A. Sidi, *Vector Extrapolation Methods with Applications*, SIAM (2017), ch. 1-2.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..base import _validate as _v
from .._kernel.boundary import lstsq, matmul

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

__all__ = ["extrapolate_limit"]


def extrapolate_limit(seq: ArrayLike, order: int | None = None) -> np.ndarray:
    """Limit of a converging vector sequence by minimal polynomial extrapolation (MPE).

    Parameters
    ----------
    seq : array_like, shape (m, d)
        Successive iterates ``x_0 .. x_{m-1}`` of one map (e.g. every ``n``-th
        stroboscopic point of a transient approaching a period-``n`` orbit).
    order : int, optional
        Degree ``k`` of the extrapolating polynomial, ``1 <= k <= m - 2``; uses the last
        ``k + 2`` iterates.  Default ``min(d, m - 2)``: exact for a linear iteration.

    Returns
    -------
    ndarray, shape (d,)
        The extrapolated limit, or NaNs when the sequence does not determine one (a
        singular least-squares problem, a non-finite result).

    Raises
    ------
    ValueError
        Naming ``seq`` (not a finite 2-D array, or fewer than 3 iterates) or ``order``.

    Notes
    -----
    With differences ``u_j = x_{j+1} - x_j``, ``c`` solves ``min |sum_{j<k} c_j u_j +
    u_k|`` (least squares), ``c_k = 1`` and ``x* = sum_j c_j x_j / sum_j c_j`` (Cabay &
    Jackson 1976; Sidi 2017, sec. 1.3).

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[0.5, 0.3], [-0.2, 0.8]]); b = np.array([1.0, 2.0])
    >>> xs = [np.zeros(2)]
    >>> for _ in range(4):
    ...     xs.append(A @ xs[-1] + b)
    >>> np.allclose(extrapolate_limit(xs), np.linalg.solve(np.eye(2) - A, b))
    True
    """
    x = _v.numeric("seq", seq, "an array of shape (m, d)")
    if x.ndim != 2 or not np.all(np.isfinite(x)):
        raise ValueError(f"seq must be a finite array of shape (m, d), got shape {x.shape}")
    m, d = x.shape
    if m < 3:
        raise ValueError(f"seq must hold at least 3 iterates (shape (m, d) with m >= 3), "
                         f"got shape {x.shape}")
    k = min(d, m - 2) if order is None else order
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 1 <= k <= m - 2:
        raise ValueError(f"order must be an integer in 1 .. {m - 2}, got {order!r}")
    x = x[-(k + 2):]
    factor = _v.power_of_two(x)  # exact: the same limit at every magnitude
    x = x / factor
    u = np.diff(x, axis=0)                       # (k + 1, d)
    c, rank = lstsq(np.ascontiguousarray(u[:k].T), -u[k][:, None], -1.0)
    c = c[:, 0]
    if rank < k:
        return np.full(d, np.nan)
    c = np.append(c, 1.0)
    s = c.sum()
    if not np.isfinite(s) or abs(s) < 1e-12 * np.abs(c).sum():
        return np.full(d, np.nan)
    out = matmul((c / s)[None, :], np.ascontiguousarray(x[:k + 1]))[0] * factor
    return out if np.all(np.isfinite(out)) else np.full(d, np.nan)
