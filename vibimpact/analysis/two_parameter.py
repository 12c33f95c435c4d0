"""Two-parameter continuation of a fold, a period doubling or a grazing of a periodic orbit.

:func:`continue_bifurcation` traces the curve in a parameter plane ``(p1, p2)`` on which a
period-``n`` orbit has a given codimension-one bifurcation.  The scheme is the simple,
robust one: **natural-parameter stepping in** ``p2`` (a secant predictor of the orbit's
point and of ``p1`` from the last two curve points, the step in ``p2`` adapted), and at
each value of ``p2`` the bifurcation is *located in* ``p1`` from that predictor:

* fold and period doubling: Newton's method on the augmented system (Seydel 2010,
  sec. 5.4 and 7.6; Kuznetsov 2004, sec. 10.3)

      P^n(x; p1) - x = 0,      tau(x, p1) = det(M(x; p1) -+ I) = 0,

  in the ``d + 1`` unknowns ``(x, p1)``; ``M = D P^n`` from the variational equations
  (saltation matrices at every switch), ``G_p1`` and the gradient of the test function
  ``tau`` by forward differences.  ``det(M - I)`` vanishes where a multiplier is ``+1``
  (fold), ``det(M + I)`` where one is ``-1`` (period doubling).  The Jacobian is regular
  at a generic fold, so Newton converges there although the orbit does not exist on one
  side of it.
* grazing: the orbit exists on both sides, but the map is not smooth at the grazing (the
  impacts per period change there), so no derivative is used: a bracketing root search
  (secant steps to a sign change, then the Illinois variant of regula falsi; Dowell &
  Jarratt 1971) in ``p1`` of the orbit's **signed gap** ``g`` -- the penetration of the
  contact surface at the extremum of the penetration nearest in phase to the grazing one
  (negative: a free-flight closest approach, positive: the deepest point of a contact;
  :func:`signed_gap`), each value from the period-``n`` orbit shot at that ``p1``.  ``g = 0``
  is the grazing condition (di Bernardo et al. 2008, ch. 8; the minimum gap of
  :func:`~vibimpact.analysis.bifurcation.grazing_gap` with its sign).

The curve is a graph over ``p2``: it ends (``status``) where the location fails with the
smallest step, e.g. where the curve turns back in ``p2`` (swap ``pair`` to follow it
there) or the bifurcation ends in a codimension-two point.  Pseudo-arclength in both
parameters is not attempted.

References
----------
.. [1] R. Seydel, *Practical Bifurcation and Stability Analysis*, 3rd ed., Springer
   (2010), ch. 5 and 7.
.. [2] Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., Springer
   (2004), ch. 10 (two-parameter continuation of codimension-one bifurcations).
.. [3] M. di Bernardo, C. J. Budd, A. R. Champneys, P. Kowalczyk, *Piecewise-smooth
   Dynamical Systems*, Springer (2008), ch. 8 (grazing of periodic orbits).
.. [4] M. Dowell, P. Jarratt, "A modified regula falsi method for computing the root of
   an equation", BIT 11 (1971) 168-174.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import math
from dataclasses import dataclass

import numpy as np

from ..base import _validate as _v
from ..base.bifurcation_kinds import BifurcationKind
from ..core.run import Status
from ..core.system import as_system
from .._kernel.boundary import solve
from .bifurcation import CONTINUATION_SOLVER
from .shooting import floquet_multipliers, shoot_periodic_orbit
from .stability_change import impacts_per_period, param_name

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

    from ..core.system import System

__all__ = ["BifurcationCurve", "CURVE_KINDS", "continue_bifurcation", "signed_gap",
           "curve_kind"]

#: the kinds :func:`continue_bifurcation` follows
CURVE_KINDS = (BifurcationKind.FOLD, BifurcationKind.PERIOD_DOUBLING,
               BifurcationKind.GRAZING)


def curve_kind(kind: str | BifurcationKind) -> BifurcationKind:
    """The :class:`BifurcationKind` of ``kind`` (its value, its flag word, or
    ``"pd"``); ValueError naming ``kind`` unless it is one of :data:`CURVE_KINDS`."""
    words = {k.value: k for k in CURVE_KINDS}
    words.update({k.flag: k for k in CURVE_KINDS})
    words.update({"pd": BifurcationKind.PERIOD_DOUBLING,
                  "period-doubling": BifurcationKind.PERIOD_DOUBLING})
    if isinstance(kind, str) and kind.strip().lower() in words:
        return words[kind.strip().lower()]
    raise ValueError(f"kind must be one of {', '.join(k.value for k in CURVE_KINDS)}, "
                     f"got {kind!r}")


@dataclass(frozen=True)
class BifurcationCurve:
    """A curve of one bifurcation of a period-``n`` orbit in a parameter plane.

    Attributes
    ----------
    kind : BifurcationKind
        :attr:`~BifurcationKind.FOLD`, :attr:`~BifurcationKind.PERIOD_DOUBLING` or
        :attr:`~BifurcationKind.GRAZING`.
    params : (str, str)
        ``(p1, p2)``: the bifurcation is located in ``p1`` at each value of ``p2``.
    values : ndarray, shape (k, 2)
        ``(p1, p2)`` of each curve point, ordered by ``p2``.
    states : ndarray, shape (k, d)
        The orbit's stroboscopic point there.
    multipliers : ndarray of complex, shape (k, d)
        Its Floquet multipliers (one is ``+1`` on a fold curve, ``-1`` on a period-doubling
        curve).
    test : ndarray, shape (k,)
        The test function at the point: ``det(M - I)``, ``det(M + I)`` or the signed gap
        (:func:`signed_gap`); zero to the tolerance.
    impacts_per_period : ndarray of int, shape (k,)
        Of the orbit at the point (at a grazing the count of either side).
    n : int
    status : str
        Why the curve ends, at each end: ``"<p2> = lo: ...; <p2> = hi: ..."``.
    """

    kind: BifurcationKind
    params: tuple
    values: np.ndarray
    states: np.ndarray
    multipliers: np.ndarray
    test: np.ndarray
    impacts_per_period: np.ndarray
    n: int
    status: str = ""


def _extrema(system, state, n):
    """``(phase, penetration)`` of the contact extrema of ``n`` periods from ``state``:
    phase as a fraction of ``n T`` in [0, 1); None where the run stops or the model has
    no contact extremum observer."""
    contact = system.model.contact
    if contact is None or contact.extremum is None:
        return None
    run = system.simulate(periods=n, state0=state,
                          solver=system.settings(**CONTINUATION_SOLVER))
    if run.status is not Status.OK:
        return None
    ext = np.asarray(run.events["which"]) == contact.extremum
    if not np.any(ext):
        return None
    period = n * 2.0 * math.pi / system.omega
    phase = np.mod(np.asarray(run.events["t"])[ext] / period, 1.0)
    depth = contact.penetration(np.asarray(run.events["state"])[ext], system.p)
    return phase, np.asarray(depth, dtype=float)


def signed_gap(system: System, state: ArrayLike, n: int = 1,
               phase: float | None = None) -> tuple[float, float]:
    """The signed gap of the period-``n`` orbit through ``state``: the penetration of
    the contact surface at one extremum of the penetration along the orbit.

    Parameters
    ----------
    system : System
        Model with a contact and its extremum observer (solver defaults
        :data:`~vibimpact.analysis.bifurcation.CONTINUATION_SOLVER`).
    state : array_like, shape (d,)
    n : int
    phase : float, optional
        Which extremum: the one nearest this phase (fraction of ``n T``, circular
        distance); by default the one of smallest ``|penetration|`` (the closest to
        grazing).

    Returns
    -------
    (float, float)
        ``(gap, phase)``: the penetration there (< 0 a free-flight closest approach,
        > 0 the deepest point of a contact, 0 at grazing) and the extremum's phase.
        ``(nan, nan)`` for a model without contact extrema or a run that stopped.
    """
    system = as_system(system)
    found = _extrema(system, _v.state("state", state, system.n_state),
                     _v.count("n", n, 1))
    if found is None:
        return math.nan, math.nan
    ph, depth = found
    if phase is None:
        i = int(np.argmin(np.abs(depth)))
    else:
        dist = np.abs(np.mod(ph - float(phase) + 0.5, 1.0) - 0.5)
        i = int(np.argmin(dist))
    return float(depth[i]), float(ph[i])


class _Locator:
    """Locate the bifurcation in ``p1`` at a fixed ``p2``: :meth:`fold_pd` (augmented
    Newton) and :meth:`grazing` (bracketing root search)."""

    def __init__(self, system, kind, p1, n, tol, max_iter):
        self.system, self.kind, self.p1, self.n = system, kind, p1, n
        self.tol, self.max_iter = tol, max_iter
        self.sign = -1.0 if kind is BifurcationKind.FOLD else 1.0
        self.d = system.n_state
        self.phase = None  # the grazing extremum's phase, tracked along the curve

    def _tau(self, M):
        return float(np.linalg.det(M + self.sign * np.eye(self.d)))

    def fold_pd(self, sys2, x, v):
        """Newton on ``(P^n(x; v) - x, tau) = 0`` from ``(x, v)``; ``(x, v, M, tau)`` or
        None."""
        d, n, p1 = self.d, self.n, self.p1
        dom = sys2.param_domain(p1)
        x = np.array(x, dtype=float)
        for _ in range(self.max_iter):
            if v not in dom:
                return None
            m = sys2.with_param(p1, v).monodromy(x, n)
            if m.status is not Status.OK:
                return None
            G, tau = m.end - m.start, self._tau(m.matrix)
            hx = 1e-6 * max(1.0, float(np.abs(x).max()))
            hv = 1e-6 * max(1.0, abs(v))
            if v + hv not in dom:
                hv = -hv
            mv = sys2.with_param(p1, v + hv).monodromy(x, n)
            if mv.status is not Status.OK:
                return None
            row = np.empty(d + 1)
            for j in range(d):
                e = np.zeros(d)
                e[j] = hx
                mj = sys2.with_param(p1, v).monodromy(x + e, n)
                if mj.status is not Status.OK:
                    return None
                row[j] = (self._tau(mj.matrix) - tau) / hx
            row[d] = (self._tau(mv.matrix) - tau) / hv
            J = np.zeros((d + 1, d + 1))
            J[:d, :d] = m.matrix - np.eye(d)
            J[:d, d] = (mv.end - m.end) / hv
            J[d] = row
            du, ok = solve(J, -np.append(G, tau))
            if not ok or not np.all(np.isfinite(du)):
                return None
            x, v = x + du[:d], v + float(du[d])
            small = float(np.abs(du[:d]).max()) <= self.tol * max(1.0, float(np.abs(x).max()))
            if small and abs(du[d]) <= self.tol * max(1.0, abs(v)):
                orb = shoot_periodic_orbit(sys2.with_param(p1, v), x, n, tol=self.tol)
                if not orb.converged and float(np.abs(G).max()) > 1e3 * self.tol:
                    return None
                m = sys2.with_param(p1, v).monodromy(x, n)
                return x, v, m.matrix, self._tau(m.matrix)
        return None

    def _gap(self, sys2, v, guess):
        """``(g, x)`` of the orbit shot at ``p1 = v`` from ``guess``; None if not."""
        if v not in sys2.param_domain(self.p1):
            return None
        q = sys2.with_param(self.p1, v)
        orb = shoot_periodic_orbit(q, guess, self.n, tol=min(self.tol, 1e-9))
        if not orb.converged or orb.minimal_period < self.n:
            return None
        g, ph = signed_gap(q, orb.state, self.n, self.phase)
        if not math.isfinite(g):
            return None
        return g, orb.state, ph

    def grazing(self, sys2, x, v, dv, slope=None):
        """The root of the signed gap in ``p1`` near ``v`` (first trial step ``dv``);
        ``(x, v, M, g)`` or None."""
        a = self._gap(sys2, v, x)
        if a is None:
            return None
        ga, xa, pha = a
        if self.phase is None:
            self.phase = pha
        step = dv if slope is None or slope == 0.0 else -ga / slope
        if step == 0.0:
            step = dv
        step = math.copysign(min(abs(step), 8.0 * abs(dv)), step) if step else dv
        va = v
        for _ in range(self.max_iter):  # secant steps until the sign changes
            vb = va + step
            b = self._gap(sys2, vb, xa)
            if b is None:
                step *= 0.5
                if abs(step) < 1e-14 * max(1.0, abs(va)):
                    return None
                continue
            gb, xb, _ = b
            if ga == 0.0 or gb == 0.0 or (ga < 0.0) != (gb < 0.0):
                break
            sec = -gb * (vb - va) / (gb - ga) if gb != ga else step
            if not math.isfinite(sec):
                sec = 2.0 * step
            va, ga, xa = vb, gb, xb
            step = math.copysign(min(abs(sec), 4.0 * abs(step)), sec)
        else:
            return None
        lo, hi = (va, ga, xa), (vb, gb, xb)
        side = 0
        for _ in range(4 * self.max_iter):  # Illinois
            (v0, g0, x0), (v1, g1, x1) = lo, hi
            if g1 == 0.0 or abs(v1 - v0) <= self.tol * max(1.0, abs(v1)):
                break
            vm = v1 - g1 * (v1 - v0) / (g1 - g0)
            guess = x0 + (x1 - x0) * ((vm - v0) / (v1 - v0))
            c = self._gap(sys2, vm, guess)
            if c is None:
                vm = 0.5 * (v0 + v1)
                c = self._gap(sys2, vm, 0.5 * (x0 + x1))
                if c is None:
                    return None
            gm, xm, _ = c
            if (gm < 0.0) == (g1 < 0.0):
                hi = (vm, gm, xm)
                if side == 1:
                    lo = (v0, 0.5 * g0, x0)
                side = 1
            else:
                lo, hi = hi, (vm, gm, xm)
                side = 0
        v1, _, x1 = hi if abs(hi[1]) <= abs(lo[1]) else lo
        final = self._gap(sys2, v1, x1)  # the gap itself (lo's may be a halved one)
        if final is None:
            return None
        g1, x1, self.phase = final
        m = sys2.with_param(self.p1, v1).monodromy(x1, self.n)
        return x1, v1, m.matrix, g1


def _window2(stop, start):
    if np.ndim(stop) == 0:
        s = _v.finite("stop", stop)
        return (min(start, s), max(start, s))
    if len(stop) != 2:
        raise ValueError(f"stop must be a float or (lo, hi), got {stop!r}")
    lo, hi = sorted((_v.finite("stop", stop[0]), _v.finite("stop", stop[1])))
    if not lo <= start <= hi:
        raise ValueError(f"stop: the window ({lo:g}, {hi:g}) must contain the start "
                         f"value {start:g}")
    return lo, hi


def continue_bifurcation(system: System, state0: ArrayLike, n: int = 1,
                         kind: str | BifurcationKind = "fold", *,
                         pair: tuple, stop: float | tuple,
                         step: float | None = None, min_step: float | None = None,
                         max_points: int = 200, tol: float = 1e-10,
                         max_iter: int = 12, dp1: float | None = None) -> BifurcationCurve:
    """Follow a fold, period doubling or grazing of a period-``n`` orbit in two
    parameters.

    Parameters
    ----------
    system : System
        Model, parameters and solver settings (defaults
        :data:`~vibimpact.analysis.bifurcation.CONTINUATION_SOLVER`); its values of
        ``pair`` are the start: ``p1`` a guess of the bifurcation's value at ``p2``.
    state0 : array_like, shape (d,)
        A guess of the orbit's stroboscopic point there.
    n : int
        The orbit's period in forcing periods.
    kind : str or BifurcationKind
        ``"fold"``, ``"period doubling"`` (or ``"pd"``) or ``"grazing"``.
    pair : (str, str)
        ``(p1, p2)``: the bifurcation is located in ``p1`` at every ``p2`` (module
        docstring); two parameters of the system's model, required (no model's pair is
        assumed).
    stop : float or (float, float)
        The window of ``p2``: from the start value to ``stop``, or ``(lo, hi)`` around
        the start (followed both ways).
    step : float, optional
        First step in ``p2`` (default a 40th of the window); it grows x1.5 after a point
        found in at most 4 iterations, up to 4 times the first, and is halved after a
        failure down to ``min_step``.
    min_step : float, optional
        Smallest step in ``p2`` after halvings (default ``step / 64``); the march stops
        below it.
    max_points : int
        Curve points at most per direction.
    tol : float
        Newton's (and the root search's) tolerance on the step in ``x`` and ``p1``,
        relative to ``max(1, |.|)``.
    max_iter : int
        Iterations per location.
    dp1 : float, optional
        First trial step in ``p1`` of the grazing's root search (default ``1e-3 *
        max(1, |p1|)``).

    Returns
    -------
    BifurcationCurve

    Raises
    ------
    ValueError
        Naming the argument: ``kind``, ``pair`` (unknown, equal, or a model without a
        contact for grazing), ``state0`` (the bifurcation not found at the start).

    Examples
    --------
    >>> import vibimpact as vi
    >>> from vibimpact.analysis import continue_bifurcation
    >>> sys = vi.System(vi.presets.get("soft-impact").replace(eta=0.83))
    >>> c = continue_bifurcation(sys, [0.8, 0.0], 1, "grazing", pair=("eta", "A"),
    ...                          stop=0.31, step=0.01)
    >>> c.values.shape
    (2, 2)
    """
    system = as_system(system).resolved(**CONTINUATION_SOLVER)
    kind = curve_kind(kind)
    n = _v.count("n", n, 1)
    if isinstance(pair, str) or len(pair) != 2:
        raise ValueError(f"pair must be two parameter names, got {pair!r}")
    p1, p2 = pair
    v1, v2 = system.param(p1), system.param(p2)  # ValueError naming param otherwise
    if param_name(system, p1) == param_name(system, p2):
        raise ValueError(f"pair must be two different parameters, got {pair!r}")
    if kind is BifurcationKind.GRAZING and (system.model.contact is None or
                                            system.model.contact.extremum is None):
        raise ValueError(f"pair: the model {system.model.name!r} has no contact, so "
                         "no grazing")
    lo, hi = _window2(stop, v2)
    if lo == hi:
        raise ValueError(f"stop must differ from the start value {p2} = {v2:g}")
    step = (hi - lo) / 40.0 if step is None else _v.positive("step", step)
    min_step = step / 64.0 if min_step is None else _v.positive("min_step", min_step)
    if v2 + min_step == v2 or v2 - min_step == v2:
        raise ValueError(f"min_step {min_step:g} is below the float resolution at "
                         f"{p2} = {v2:g} (give a larger step or min_step)")
    max_points = _v.count("max_points", max_points, 1)
    tol = _v.positive("tol", tol)
    max_iter = _v.count("max_iter", max_iter, 2)
    dp1 = 1e-3 * max(1.0, abs(v1)) if dp1 is None else _v.positive("dp1", dp1)
    x0 = _v.state("state0", state0, system.n_state)
    loc = _Locator(system, kind, p1, n, tol, max_iter)

    def locate(sys2, x, v, slope=None):
        if kind is BifurcationKind.GRAZING:
            return loc.grazing(sys2, x, v, dp1, slope)
        return loc.fold_pd(sys2, x, v)

    if kind is not BifurcationKind.GRAZING:  # start from the orbit near the guess
        orb = shoot_periodic_orbit(system, x0, n, tol=1e-9)
        x0 = orb.state if orb.converged else x0
    first = locate(system, x0, v1)
    if first is None:
        raise ValueError(f"state0: no {kind.value} of the period-{n} orbit found near "
                         f"{p1} = {v1:g} at {p2} = {v2:g}")
    point0 = (first[1], v2, first[0], first[2], first[3])
    phase0 = loc.phase
    halves, statuses = [], []
    for sense, end in ((-1.0, lo), (1.0, hi)):
        if end == v2:
            continue
        pts, status = _march(system, p2, point0, sense, end, step, min_step, max_points,
                             locate, kind, loc, phase0)
        halves.append((sense, pts))
        statuses.append(f"{p2} = {end:g}: {status}")
    pts = [point0]
    for sense, h in halves:
        pts = (h[::-1] + pts) if sense < 0 else (pts + h)
    vals = np.array([[q[0], q[1]] for q in pts])
    states = np.array([q[2] for q in pts])
    mults = np.array([floquet_multipliers(q[3]) for q in pts])
    test = np.array([q[4] for q in pts])
    imp = np.array([impacts_per_period(system.with_param(p2, q[1]).with_param(p1, q[0]),
                                       q[2], n) for q in pts], dtype=np.int64)
    return BifurcationCurve(kind, (param_name(system, p1), param_name(system, p2)), vals,
                            states, mults, test, imp, n, "; ".join(statuses))


def _march(system, p2, point0, sense, end, step, min_step, max_points, locate, kind, loc,
           phase0):
    """Curve points from ``point0`` towards ``p2 = end``: ``(points, status)``."""
    pts: list[tuple] = []
    prev, cur = None, point0
    h = step
    loc.phase = phase0  # the grazing extremum of the start, each direction
    while len(pts) < max_points:
        left = (end - cur[1]) * sense
        if left <= 1e-12 * max(1.0, abs(end)):
            return pts, "reached the end of the window"
        dh = min(h, left)
        w2 = end if dh == left else cur[1] + sense * dh
        if prev is None:
            xp, vp, slope = cur[2], cur[0], None
        else:
            r = (w2 - cur[1]) / (cur[1] - prev[1])
            xp = cur[2] + r * (cur[2] - prev[2])
            vp = cur[0] + r * (cur[0] - prev[0])
            slope = None
        got = locate(system.with_param(p2, w2), xp, vp, slope)
        if got is None:
            h *= 0.5
            if h < min_step:
                return pts, f"no {kind.value} found with the smallest step at {p2} = " \
                            f"{cur[1]:.6g}"
            continue
        prev, cur = cur, (got[1], w2, got[0], got[2], got[3])
        pts.append(cur)
        h = min(1.5 * h, 4.0 * step)
    return pts, f"max_points ({max_points}) reached"
