"""How fast a stroboscopic sequence settles: contraction rates and torus evidence.

A trajectory approaching a stable period-``n`` orbit has stroboscopic points whose every
``n``-th steps ``u_j = z_{j+1} - z_j`` (``z_j = x_{jn}``) obey the linearised map: ``u_{j+1}
= M u_j`` with ``M`` the orbit's monodromy matrix.  A linear map fitted to the steps by
least squares (a dynamic mode decomposition) has the orbit's Floquet multipliers as
eigenvalues, so its spectral radius gives the contraction rate ``ln|mu|max / n`` per
forcing period without knowing the orbit -- complex pairs of multipliers included, whose
rotation makes the step lengths ripple.  On a torus the fitted map is a rotation
(``rho = 1``); on a chaotic set no linear map fits the steps (a large residual).

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
.. [3] P. J. Schmid, "Dynamic mode decomposition of numerical and experimental data",
   *J. Fluid Mech.* 656 (2010) 5-28.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import math
from dataclasses import dataclass

import numpy as np

from ..base import _validate as _v
from .._kernel.boundary import dot, eigvals, lstsq, matmul

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

#: the set's size shrinks significantly when its log-slope per period lies ``Z`` standard
#: errors below ``-SPREAD_FLOOR``
Z = 3.0
SPREAD_FLOOR = 2e-4

__all__ = ["Contraction", "contraction_rate", "contraction_rates", "settling_periods",
           "TorusEvidence", "torus_evidence"]

#: fewest steps a linear map is fitted to, and the most (the latest) it uses
MIN_STEPS = 12
MAX_STEPS = 96
#: a rate is significant below ``-FLOOR`` per forcing period: the free oscillation at
#: ``B = 0.001`` and ``eta = 1.5`` decays at about -2e-3 per period; the estimate's scatter
#: on a torus (``B = 0``) is a few 1e-4
FLOOR = 1e-3
#: and when a linear map reproduces the steps to this relative residual (the approach
#: to an orbit is linear near it; a chaotic or quasi-periodic sequence's is not)
RES_MAX = 0.05


@dataclass(frozen=True)
class Contraction:
    """The geometric rate at which every ``n``-th stroboscopic point settles.

    Attributes
    ----------
    n : int
        The lag: the map fitted is ``P^n``.
    rate : float
        ``ln rho / n`` per *forcing period*, ``rho`` the spectral radius of the linear map
        fitted to the steps (``|mu|max`` of the orbit approached); negative when the
        points contract.
    residual : float
        Relative residual of the fit, ``|U1 - U0 A| / |U1|``.
    step : float
        ``|z_{j+1} - z_j|`` of the last step.
    scale : float
        Largest ``|x|`` of the points (what tolerances are relative to).
    """

    n: int
    rate: float
    residual: float
    step: float
    scale: float

    @property
    def contracting(self):
        """A linear map fits (``residual < RES_MAX``) and contracts (``rate < -FLOOR``)."""
        return bool(self.rate < -FLOOR and self.residual < RES_MAX)

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


def _fit(sub, scale, n):
    """Linear map of the steps of ``sub`` (the last ``MAX_STEPS``) -> Contraction."""
    u = np.diff(sub, axis=0)[-MAX_STEPS:]
    u0, u1 = np.ascontiguousarray(u[:-1]), np.ascontiguousarray(u[1:])
    # minimum-norm least squares: steps spanning fewer modes than dimensions are fine
    a = lstsq(u0, u1, 1e-10)[0]
    r = u1 - matmul(u0, a)
    den = dot(u1.ravel(), u1.ravel())
    if not den > 0.0 or not np.all(np.isfinite(a)):
        return None
    res = math.sqrt(dot(r.ravel(), r.ravel()) / den)
    rho = float(np.abs(eigvals(a)).max())
    if not rho > 0.0:
        return None
    return Contraction(n, math.log(rho) / n, res, math.sqrt(dot(u1[-1], u1[-1])), scale)


def contraction_rates(points, lags):
    """Contraction of every ``n``-th point for each ``n`` of ``lags``.

    The unchecked form of :func:`contraction_rate`, for screening the candidate periods of
    a transient at every check.

    Parameters
    ----------
    points : ndarray, shape (m, d)
        Finite stroboscopic points (not validated: the sweep's own arrays).
    lags : iterable of int
        The candidate periods ``n >= 1``.

    Returns
    -------
    list of Contraction or None
        One entry per lag (None where there are fewer than :data:`MIN_STEPS` steps, or
        the steps do not determine a map: repeating or degenerate points).
    """
    z = np.asarray(points, dtype=np.float64)
    scale = max(float(np.abs(z).max(initial=0.0)), 1e-300)
    out = []
    for n in lags:
        sub = z[::-1][::n][::-1]
        out.append(_fit(sub, scale, n) if sub.shape[0] > MIN_STEPS + 1 else None)
    return out


def contraction_rate(points: ArrayLike, n: int = 1) -> Contraction | None:
    """Contraction rate of every ``n``-th stroboscopic point, per forcing period.

    The steps ``u_j = z_{j+1} - z_j`` of ``z_j = x_{jn}`` are fitted by a linear map,
    ``u_{j+1} = A^T u_j`` (least squares over the last :data:`MAX_STEPS` steps, a dynamic
    mode decomposition of the steps): near an orbit of period ``n`` the steps obey the
    linearised map ``P^n``, whose eigenvalues are the orbit's Floquet multipliers, so the
    spectral radius of ``A`` is ``|mu|max`` -- complex pairs included, whose rotation
    makes the step lengths themselves ripple.  ``rate = ln rho / n`` per forcing period.

    Parameters
    ----------
    points : array_like, shape (m, d)
        Successive stroboscopic points, one per forcing period.
    n : int
        The candidate period.

    Returns
    -------
    Contraction or None
        None when fewer than :data:`MIN_STEPS` + 1 steps exist or they do not determine a
        map (points that already repeat).

    Raises
    ------
    ValueError
        Naming ``points`` or ``n``.

    Examples
    --------
    >>> import numpy as np
    >>> A = 0.9 * np.array([[np.cos(0.5), -np.sin(0.5)], [np.sin(0.5), np.cos(0.5)]])
    >>> z = [np.array([1.0, 0.0])]
    >>> for _ in range(40):
    ...     z.append(A @ z[-1] + np.array([0.3, 0.1]))
    >>> c = contraction_rate(np.array(z))
    >>> round(c.multiplier, 6), c.contracting
    (0.9, True)
    """
    z = _v.points(points)
    n = _v.count("n", n)
    return contraction_rates(z, (n,))[0]


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
        s_ok = not (self.spread_rate + Z * self.spread_stderr < -SPREAD_FLOOR)
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


def torus_evidence(points: ArrayLike) -> TorusEvidence:
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
    z = _v.points(points)
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
        slope = dot(tc, y - y.mean()) / dot(tc, tc)
        res = y - y.mean() - slope * tc
        se = math.sqrt(dot(res, res) / 2.0 / dot(tc, tc))
    else:
        slope, se = 0.0, 0.0
    a, b = z[: m // 2], z[m // 2:]
    d2 = ((b[:, None, :] - a[None, :, :]) ** 2).sum(axis=2)
    rec = float(np.median(np.sqrt(d2.min(axis=1)))) / size
    return TorusEvidence(con, slope, se, rec)
