"""Deciding a slowly settling transient by evidence: contraction rate and Newton shooting.

At the low damping of passive magnetic bearings a transient approaches its periodic
attractor at the rate of the orbit's leading Floquet multiplier, ``|mu| = exp(-B T / 2)``
for an impactless orbit: hundreds to thousands of forcing periods before the stroboscopic
points repeat to the period test's tolerance.  Instead of integrating that long (or
labelling the motion by default), a sweep point

1. measures the contraction rate of its stroboscopic points
   (:func:`vibimpact.analysis.settling.contraction_rate`) for ``n = 1 .. SHOOT_MAX_N`` and
   takes the smallest ``n`` whose points contract;
2. when the periods the transient would still need exceed what is left of its budget,
   solves ``P^n(x) = x`` by Newton shooting from the extrapolated limit of the points
   (:func:`vibimpact.analysis.shoot_periodic_orbit`);
3. accepts the orbit as the attractor only on evidence: Newton converged, every
   ``|mu| < 1`` (of its minimal period, a divisor of ``n``), the trajectory approaches it at least
   half as fast as its leading multiplier predicts and lies within the geometric tail of its
   own steps from it;
4. confirms it by integrating from the orbit: the record starts there, and the period
   test must find ``n`` on it.

The evidence is stored with the point (shooting residual, ``|mu|max``, distance of the
trajectory from the orbit, the measured rate).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analysis.extrapolation import extrapolate_limit
from ..analysis.period import detect_period
from ..analysis.settling import Contraction, contraction_rates, settling_periods
from ..core.run import Status

#: candidate periods of the shooting
SHOOT_MAX_N = 8
#: shooting attempts per point at most (in the transient and after the record)
MAX_SHOTS = 2
#: fewest periods since the transient's last restart before a contraction is trusted
MIN_SHOOT_PERIODS = 30
#: the trajectory must approach at least this fraction of the leading multiplier's rate
RATE_FRACTION = 0.5
#: and lie within this multiple of its geometric tail from the orbit
TAIL_FACTOR = 10.0


@dataclass(frozen=True)
class Evidence:
    """A periodic attractor found by shooting and confirmed by integration.

    Attributes
    ----------
    n : int
        Period in forcing periods.
    run : Run
        The confirming run, integrated from the orbit (the point's record).
    state : ndarray, shape (4,)
        The orbit's point where the run starts.
    residual : float
        Shooting residual ``max |P^n(x) - x|``.
    abs_max : float
        Largest ``|mu|``.
    multipliers : ndarray of complex, shape (4,)
    distance : float
        Distance of the trajectory's last point from the orbit, relative to the scale.
    rate : float
        Measured contraction rate per forcing period.
    """

    n: int
    run: object
    state: np.ndarray
    residual: float
    abs_max: float
    multipliers: np.ndarray
    distance: float
    rate: float


def find_contraction(strobe, max_n=SHOOT_MAX_N):
    """The smallest ``n <= max_n`` whose lag-``n`` steps contract, or None.

    Parameters
    ----------
    strobe : ndarray, shape (m, 4)
        Stroboscopic points of one trajectory, oldest first.
    """
    for c in contraction_rates(strobe, range(1, max_n + 1)):
        if c is not None and c.contracting:
            return c
    return None


def needs_shooting(con, tol, periods_left):
    """Whether the transient would still need more periods than it has left."""
    return con is not None and settling_periods(con, tol) > periods_left


def unsettled_repeat(strobe, n, tol):
    """The contraction of points that repeat with period ``n`` to ``tol`` but are still
    farther than ``tol`` (of their scale) from their limit, judged by the geometric tail
    of their lag-``n`` steps; None when they have settled (or do not contract)."""
    con = contraction_rates(strobe, (n,))[0]
    if con is None or not con.contracting or con.distance <= tol * con.scale:
        return None
    return con


def _guess(strobe, n):
    """Extrapolated limit of the last 6 iterates of ``P^n`` (the last point if the
    extrapolation leaves their neighbourhood)."""
    z = strobe[::-1][::n][:6][::-1]
    last = strobe[-1]
    if z.shape[0] < 3:
        return last.copy()
    xs = extrapolate_limit(z)
    spread = float(np.abs(z - last).max())
    if not np.all(np.isfinite(xs)) or float(np.abs(xs - last).max()) > 1e3 * max(spread, 1e-12):
        return last.copy()
    return xs


def shoot(p, strobe, con: Contraction, settings, need_dense=False):
    """Newton shooting from a contracting transient; :class:`Evidence` or None.

    Parameters
    ----------
    p : System
        With the sweep's solver settings (:func:`vibimpact.points.point.point_system`).
    strobe : ndarray, shape (m, 4)
        The transient's stroboscopic points (the last one is where it stands).
    con : Contraction
        Its contraction, from :func:`find_contraction`.
    settings : SweepSettings
    need_dense : bool
        Record dense samples on the confirming run (response maxima).
    """
    from ..analysis.shooting import shoot_periodic_orbit

    st = settings
    n = con.n
    orb = shoot_periodic_orbit(p, _guess(strobe, n), n, tol=10.0 * st.rtol, max_iter=8,
                               damping=True)
    if orb.status is not Status.OK or not orb.converged:
        return None
    if orb.minimal_period != n:  # the points contract onto an orbit of a divisor period:
        # the lag-n fit was the first to be linear enough, the orbit decides
        n = orb.minimal_period
        orb = shoot_periodic_orbit(p, orb.state, n, tol=10.0 * st.rtol, max_iter=4,
                                   damping=True)
        if orb.status is not Status.OK or not orb.converged or orb.minimal_period != n:
            return None
    amax = orb.abs_max
    if not amax < 1.0:
        return None
    predicted = math.log(amax) / n
    if not con.rate <= RATE_FRACTION * predicted:  # (both per forcing period)
        return None
    scale = con.scale
    dist = float(np.abs(strobe[-1] - orb.state).max())
    rho = con.multiplier
    tail = con.step / (1.0 - rho) if rho < 1.0 else math.inf
    if not dist <= TAIL_FACTOR * tail + 1e-9 * scale:
        return None
    rec = max(st.record_periodic, 4 * n)
    run = p.simulate(periods=rec, state0=orb.state, dense=st.dense if need_dense else 0)
    if run.status is not Status.OK:
        return None
    rule = st.rule
    found = detect_period(run.strobe, tol=rule.period_tol,
                          max_period=min(rule.max_period, rec // 3))
    if found != n:
        return None
    return Evidence(n, run, orb.state.copy(), orb.residual, amax, orb.multipliers,
                    dist / scale, con.rate)
