"""The Gottwald--Melbourne 0-1 test for chaos (correlation method).

A scalar observable ``phi(j)``, ``j = 1 .. N``, drives the translation variables

.. math::

    p_c(n) = \\sum_{j=1}^{n} \\phi(j) \\cos jc, \\qquad
    q_c(n) = \\sum_{j=1}^{n} \\phi(j) \\sin jc ,

which stay bounded for regular (periodic or quasi-periodic) dynamics and behave like a
Brownian motion for chaotic dynamics.  Their mean-square displacement ``M_c(n)`` therefore
stays bounded, or grows linearly in ``n``; the asymptotic growth rate ``K`` is 0 or 1.
Following [2] it is computed by the correlation method: ``K_c = corr(n, D_c(n))`` for
``n = 1 .. n_cut`` with the modified displacement ``D_c = M_c - V_osc``, and ``K`` is the
median of ``K_c`` over random ``c`` in ``(pi/5, 4pi/5)`` (away from the resonances at 0 and
pi; the median discards the isolated resonant ``c``).

The data must not be oversampled: use Poincare (e.g. stroboscopic) samples, not a densely
sampled continuous trajectory [3].

References
----------
.. [1] G. A. Gottwald, I. Melbourne, "A new test for chaos in deterministic systems",
   Proc. R. Soc. Lond. A 460 (2004) 603-611.
.. [2] G. A. Gottwald, I. Melbourne, "On the implementation of the 0-1 test for chaos",
   SIAM J. Appl. Dyn. Syst. 8 (2009) 129-145.
.. [3] G. A. Gottwald, I. Melbourne, "The 0-1 test for chaos: a review", in *Chaos
   Detection and Predictability*, Lect. Notes Phys. 915, Springer (2016) 221-247.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numbers

import numpy as np

from ..base import _validate as _v
from .._kernel.boundary import matmul

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

__all__ = ["test01", "mean_square_displacement", "C_RANGE", "MIN_LENGTH"]

#: interval of the frequencies ``c`` (radians), as recommended in [2]
C_RANGE = (np.pi / 5.0, 4.0 * np.pi / 5.0)
#: shortest series accepted
MIN_LENGTH = 20


def _series(series):
    x = _v.array1d("series", series)
    if np.ndim(series) != 1:
        raise ValueError(f"series must be 1-D, got shape {x.shape}")
    if x.size < MIN_LENGTH:
        raise ValueError(f"series must have at least {MIN_LENGTH} values, got {x.size}")
    if not np.all(np.isfinite(x)):
        raise ValueError("series must be finite (no NaN or inf)")
    # above 2 in magnitude, divided by a power of two (exact; K is scale-free): values
    # near 1e308 would overflow the squares
    return x / _v.power_of_two(x, shrink_only=True)


def _frequencies(c, n_c, seed):
    if c is None:
        n_c = _v.count("n_c", n_c, 1)
        rng = np.random.default_rng(seed)
        return rng.uniform(C_RANGE[0], C_RANGE[1], size=n_c)
    try:
        c = np.atleast_1d(np.asarray(c, dtype=np.float64))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"c must be a 1-D array of frequencies: {exc}") from None
    if c.ndim != 1 or c.size == 0 or not np.all(np.isfinite(c)):
        raise ValueError("c must be a non-empty 1-D array of finite frequencies")
    if np.any(np.abs(np.cos(c) - 1.0) < 1e-12):
        raise ValueError("c must avoid multiples of 2 pi (resonant: 1 - cos c = 0)")
    return c


def mean_square_displacement(x, c, n_cut):
    """``M_c(n)`` for ``n = 1 .. n_cut`` and every ``c``, by FFT autocorrelation.

    ``M_c(n) = 1/(N-n) sum_{j=1}^{N-n} |z(j+n) - z(j)|^2`` with ``z = p_c + i q_c``, expanded
    as ``|z(j+n)|^2 + |z(j)|^2 - 2 Re z(j+n) conj z(j)``: the squares by cumulative sums, the
    cross term by one zero-padded FFT per ``c``.  Cost O(n_c N log N).

    Parameters
    ----------
    x : ndarray, shape (N,)
    c : ndarray, shape (n_c,)
    n_cut : int
        ``1 <= n_cut < N``.

    Returns
    -------
    ndarray, shape (n_c, n_cut)
    """
    N = x.size
    j = np.arange(1, N + 1)
    z = np.cumsum(x[None, :] * np.exp(1j * c[:, None] * j[None, :]), axis=1)   # (n_c, N)
    size = 1 << int(np.ceil(np.log2(2 * N)))
    Z = np.fft.fft(z, n=size, axis=1)
    cross = np.fft.ifft(Z * np.conj(Z), axis=1)[:, 1:n_cut + 1].real   # sum_j z(j+n) z*(j)
    sq = np.concatenate([np.zeros((c.size, 1)), np.cumsum(np.abs(z) ** 2, axis=1)], axis=1)
    n = np.arange(1, n_cut + 1)
    upper = sq[:, N:N + 1] - sq[:, n]       # sum_{j >= n} |z_j|^2
    lower = sq[:, N - n]                    # sum_{j < N - n} |z_j|^2
    return (upper + lower - 2.0 * cross) / (N - n)[None, :]


def test01(series: ArrayLike, c: ArrayLike | None = None, n_c: int = 100,
           n_cut: int | None = None, seed: int = 0, *,
           constant_tol: float = 1e-12) -> float:
    """Gottwald--Melbourne 0-1 test for chaos: ``K`` near 0 regular, near 1 chaotic.

    Parameters
    ----------
    series : array_like, shape (N,)
        Observable sampled once per Poincare crossing (e.g. one component of
        :attr:`vibimpact.Run.strobe`), ``N >= 20`` finite values; ``N`` of order 1000 or
        more for a reliable answer.
    c : array_like, shape (n_c,), optional
        Frequencies to use; by default ``n_c`` values drawn uniformly in
        :data:`C_RANGE` ``= (pi/5, 4 pi/5)`` by ``numpy.random.default_rng(seed)``, so the
        result is deterministic for a given seed.
    n_c : int
        Number of random frequencies when ``c`` is not given.
    n_cut : int, optional
        Largest displacement lag, ``N // 10`` by default [2] (at least 2, below ``N``).
    seed : int or numpy.random.Generator seed
        Seed of the frequency draw.
    constant_tol : float
        A series whose standard deviation is ``<= constant_tol * max(1, |mean|)`` is taken
        as constant (a fixed point) and gives 0.0.  The test itself has no tolerance: it
        calls noise chaotic (``K`` near 1), so the integration noise of a converged fixed
        point (relative size about the integrator's ``rtol``) reads as chaos unless
        ``constant_tol`` is raised above it, or the caller checks :func:`detect_period`
        first.

    Returns
    -------
    float
        ``K = median_c K_c`` with ``K_c = corr(n, D_c(n))`` over ``n = 1 .. n_cut``.  A
        ``c`` whose ``D_c`` is constant has ``K_c = 0``.  A constant series (standard
        deviation ``<= constant_tol max(1, |mean|)``) returns 0.0.

    Raises
    ------
    ValueError
        Naming the argument: ``series`` not 1-D, shorter than 20 or not finite; bad
        ``c``, ``n_c``, ``n_cut`` or ``constant_tol``.

    Notes
    -----
    The mean is subtracted first.  ``D_c(n) = M_c(n) - V_osc(c, n)`` with
    ``V_osc = (E phi)^2 (1 - cos nc) / (1 - cos c)`` [2] removes the bounded
    oscillation a non-zero mean adds to ``M_c``; after centring ``E phi`` is zero up to
    rounding, so the two steps are the same correction, kept both for fidelity to [2].

    Examples
    --------
    >>> import numpy as np
    >>> x = np.empty(2000); x[0] = 0.3
    >>> for k in range(1999): x[k + 1] = 4.0 * x[k] * (1.0 - x[k])
    >>> test01(x) > 0.9
    True
    >>> test01(np.tile([0.1, 0.5, 0.9], 700)) < 0.1
    True
    """
    x = _series(series)
    N = x.size
    if n_cut is None:
        n_cut = max(2, N // 10)
    else:
        n_cut = _v.count("n_cut", n_cut, 2, N - 1)
    c = _frequencies(c, n_c, seed)
    if (isinstance(constant_tol, bool) or not isinstance(constant_tol, numbers.Real)
            or not 0.0 <= constant_tol < np.inf):
        raise ValueError(f"constant_tol must be a finite number >= 0, got {constant_tol!r}")
    mean = float(np.mean(x))
    if float(np.std(x)) <= constant_tol * max(1.0, abs(mean)):
        return 0.0
    phi = x - mean
    M = mean_square_displacement(phi, c, n_cut)
    n = np.arange(1, n_cut + 1, dtype=np.float64)
    e_phi = float(np.mean(phi))
    V_osc = e_phi ** 2 * (1.0 - np.cos(np.outer(c, n))) / (1.0 - np.cos(c))[:, None]
    D = M - V_osc
    # Pearson correlation of (n, D_c(n)) for every c at once
    dn = n - n.mean()
    dD = D - D.mean(axis=1, keepdims=True)
    norm = np.sqrt(np.sum(dn ** 2) * np.sum(dD ** 2, axis=1))
    cov = matmul(np.ascontiguousarray(dD), dn[:, None])[:, 0]
    tiny = norm <= 1e-300 + 1e-12 * np.abs(D).max(axis=1) * np.sqrt(np.sum(dn ** 2))
    K_c = np.where(tiny, 0.0, cov / np.where(tiny, 1.0, norm))
    return float(np.median(K_c))


# not a pytest test, although its name (fixed by the public API) starts with "test": tell
# pytest so, for test modules that import it by name
test01.__test__ = False  # type: ignore[attr-defined]  # an attribute of a function
