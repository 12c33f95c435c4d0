"""How fast a stroboscopic sequence settles: contraction rates and torus evidence.

A trajectory approaching a stable period-``n`` orbit has stroboscopic points whose every
``n``-th differences ``u_j = z_{j+1} - z_j`` (``z_j = x_{jn}``) shrink like ``|mu|^j``, with
``mu`` the orbit's leading Floquet multiplier.  Fitting ``ln |u_j|`` against ``j`` by least
squares gives the contraction rate ``ln|mu| / n`` per forcing period without knowing the
orbit -- for a complex pair of multipliers the differences also rotate, which scatters
``ln |u_j|`` about the line but leaves its slope.  On a torus or a chaotic set the points
keep moving: the slope is zero within its error.

At low damping ``B`` the slowest mode of an impactless motion is the free oscillation,
which decays like ``exp(-B tau / 2)``: ``ln|mu| = -B T / 2`` per forcing period ``T`` (about
-0.005 at ``B = 0.002``), so a transient needs ``ln(tol) / ln|mu|`` periods (about 3000 for a
1e-6 tolerance) to settle.  :func:`contraction_rate` measures that rate from a short
record; :func:`settling_periods` turns it into the periods the sequence would still need.
:func:`torus_evidence` gathers what a quasi-periodic label needs: points that neither
contract nor repeat, but recur (come back close to earlier points).

These are array-level analysers: they take stroboscopic points from any system.

References
----------
.. [1] T. S. Parker, L. O. Chua, *Practical Numerical Algorithms for Chaotic Systems*,
   Springer (1989), ch. 6 (Poincaré maps, periodic and quasi-periodic steady states).
.. [2] A. Sidi, *Vector Extrapolation Methods with Applications*, SIAM (2017), ch. 1
   (geometric convergence of fixed-point iterations).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Contraction", "contraction_rate", "settling_periods", "TorusEvidence",
           "torus_evidence"]

#: fewest differences a rate is fitted to
MIN_DIFFS = 8
#: a rate is significant when it lies beyond ``Z`` standard errors and beyond ``FLOOR``
#: (per forcing period) from zero: the free oscillation at ``B = 0.001`` and ``eta = 1.5``
#: decays at about -2e-3 per period, ten times the floor
Z = 3.0
FLOOR = 2e-4


@dataclass(frozen=True)
class Contraction:
    """The geometric rate at which every ``n``-th stroboscopic point settles.

    Attributes
    ----------
    n : int
        Sub-sampling: the rate of ``z_j = x_{jn}``.
    rate : float
        Slope of ``ln |z_{j+1} - z_j|`` per *forcing period* (``ln|mu| / n`` on the
        approach to a period-``n`` orbit); negative when the points contract.
    stderr : float
        Standard error of ``rate``.
    step : float
        ``|z_{j+1} - z_j|`` at the end of the sequence, from the fitted line.
    scale : float
        Largest ``|x|`` of the points (what tolerances are relative to).
    """

    n: int
    rate: float
    stderr: float
    step: float
    scale: float

    @property
    def contracting(self):
        """The rate is significantly negative (``rate + Z stderr < -FLOOR``)."""
        return bool(self.rate + Z * self.stderr < -FLOOR)

    @property
    def expanding(self):
        """The rate is significantly positive."""
        return bool(self.rate - Z * self.stderr > FLOOR)

    @property
    def multiplier(self):
        """``exp(rate n)``: the modulus of the leading multiplier of the period-``n`` map."""
        return math.exp(self.rate * self.n)

    @property
    def distance(self):
        """Estimated distance of the last point from the limit: the geometric tail
        ``step rho / (1 - rho)`` of the remaining steps (inf when not contracting)."""
        rho = self.multiplier
        return self.step * rho / (1.0 - rho) if self.contracting and rho < 1.0 else math.inf


def _points(points):
    try:
        z = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError("points must be an array of numbers of shape (m, d)") from None
    if z.ndim == 1:
        z = z[:, None]
    if z.ndim != 2 or not np.all(np.isfinite(z)):
        raise ValueError(f"points must be a finite array of shape (m, d), got shape {z.shape}")
    return z


def _int(name, value, minimum):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def contraction_rate(points, n=1):
    """Contraction rate of every ``n``-th stroboscopic point, per forcing period.

    Parameters
    ----------
    points : array_like, shape (m, d)
        Successive stroboscopic points, one per forcing period.
    n : int
        Sub-sampling (the candidate period).

    Returns
    -------
    Contraction or None
        None when fewer than :data:`MIN_DIFFS` differences of the sub-sampled sequence
        exist, or when the points already repeat (a difference of exactly 0).

    Raises
    ------
    ValueError
        Naming ``points`` or ``n``.

    Examples
    --------
    >>> import numpy as np
    >>> z = 1.0 + 0.9 ** np.arange(40)[:, None] * np.array([[1.0, -2.0]])
    >>> c = contraction_rate(z)
    >>> round(c.multiplier, 6), c.contracting
    (0.9, True)
    """
    z = _points(points)
    n = _int("n", n, 1)
    sub = z[::-1][::n][::-1]
    u = np.sqrt((np.diff(sub, axis=0) ** 2).sum(axis=1))
    if u.size < MIN_DIFFS or not np.all(u > 0.0):
        return None
    y = np.log(u)
    j = np.arange(u.size, dtype=np.float64)
    jc = j - j.mean()
    sxx = float(jc @ jc)
    slope = float(jc @ (y - y.mean())) / sxx
    resid = y - y.mean() - slope * jc
    se = math.sqrt(float(resid @ resid) / (u.size - 2) / sxx)
    step = math.exp(y.mean() + slope * jc[-1])
    scale = max(float(np.abs(z).max()), 1e-300)
    return Contraction(n, slope / n, se / n, step, scale)


def settling_periods(contraction, tol):
    """Forcing periods the sequence still needs to settle to ``tol`` of its scale.

    Parameters
    ----------
    contraction : Contraction
    tol : float
        Relative tolerance (e.g. the period test's, 1e-6).

    Returns
    -------
    float
        ``ln(tol scale / distance) / rate``; 0 when already within ``tol``; inf when the
        sequence does not contract.
    """
    if contraction is None or not contraction.contracting:
        return math.inf
    target = tol * contraction.scale
    d = contraction.distance
    if d <= target:
        return 0.0
    return math.log(target / d) / contraction.rate


@dataclass(frozen=True)
class TorusEvidence:
    """What the stroboscopic points say about an invariant torus.

    Attributes
    ----------
    contraction : Contraction or None
        Rate of the points themselves (``n = 1``).
    spread_rate : float
        Slope per forcing period of the log of the set's size (RMS distance from the
        centroid) over the record's quarters: a torus keeps its size, a slowly settling
        spiral shrinks.
    spread_stderr : float
    recurrence : float
        Median distance from each point of the record's second half to its nearest point of
        the first half, divided by the set's size: small for a curve or surface that the
        points keep visiting, about 1 for a set that drifts away.
    """

    contraction: Contraction | None
    spread_rate: float
    spread_stderr: float
    recurrence: float

    @property
    def non_contracting(self):
        """Neither the steps nor the set's size shrink significantly."""
        c_ok = self.contraction is None or not self.contraction.contracting
        s_ok = not (self.spread_rate + Z * self.spread_stderr < -FLOOR)
        return bool(c_ok and s_ok)

    @property
    def recurrent(self):
        """The second half of the points returns close to the first (within 0.25 of the
        set's size)."""
        return bool(self.recurrence < 0.25)

    @property
    def torus(self):
        """Both: a non-contracting set that the points keep coming back to."""
        return self.non_contracting and self.recurrent


def torus_evidence(points):
    """Evidence of an invariant torus in stroboscopic points.

    A quasi-periodic motion's Poincaré points lie on a closed curve (two frequencies) or
    a torus surface (three): they do not repeat, do not contract (a torus keeps its
    size), and come back arbitrarily close to earlier points.  A slowly settling transient
    (low damping) also fills a spiral that looks like a closed curve over a short record,
    but it shrinks: :attr:`TorusEvidence.non_contracting` tells the two apart.

    Parameters
    ----------
    points : array_like, shape (m, d), m >= 16

    Returns
    -------
    TorusEvidence

    Raises
    ------
    ValueError
        Naming ``points``.
    """
    z = _points(points)
    m = z.shape[0]
    if m < 16:
        raise ValueError(f"points must hold at least 16 points, got {m}")
    con = contraction_rate(z, 1)
    q = m // 4
    c = z.mean(axis=0)
    spreads = np.array([math.sqrt(float(((z[i * q:(i + 1) * q] - c) ** 2).sum(axis=1).mean()))
                        for i in range(4)])
    size = max(math.sqrt(float(((z - c) ** 2).sum(axis=1).mean())), 1e-300)
    if np.all(spreads > 0.0):
        t = (np.arange(4) + 0.5) * q
        tc = t - t.mean()
        y = np.log(spreads)
        slope = float(tc @ (y - y.mean())) / float(tc @ tc)
        res = y - y.mean() - slope * tc
        se = math.sqrt(float(res @ res) / 2.0 / float(tc @ tc))
    else:
        slope, se = 0.0, 0.0
    a, b = z[: m // 2], z[m // 2:]
    d2 = ((b[:, None, :] - a[None, :, :]) ** 2).sum(axis=2)
    rec = float(np.median(np.sqrt(d2.min(axis=1)))) / size
    return TorusEvidence(con, slope, se, rec)
