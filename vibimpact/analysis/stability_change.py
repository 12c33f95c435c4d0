"""Where exactly a branch of periodic orbits changes: bisection between two of its orbits
for a change of stability (:func:`refine_stability_change`) or of its impacts per period,
a grazing (:func:`refine_grazing`); used by
:func:`~vibimpact.analysis.continuation.continue_orbit` with ``refine``.

References
----------
.. [1] Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., Springer
   (2004), ch. 4.
.. [2] M. di Bernardo, C. J. Budd, A. R. Champneys, P. Kowalczyk, *Piecewise-smooth
   Dynamical Systems*, Springer (2008), ch. 8 (grazing of periodic orbits).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from dataclasses import dataclass

import numpy as np

from ..core.run import Status
from ..base import _validate as _v
from ..base.bifurcation_kinds import BifurcationKind
from ..core.system import as_system
from .bifurcation import CONTINUATION_SOLVER
from .shooting import critical_multiplier, shoot_periodic_orbit

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

    from ..core.system import System


def param_name(system, param):
    """The name of parameter ``param`` (a name, or an index of a user model's vector)."""
    if isinstance(param, str):
        return param
    return system.model.param_names[int(param)]


@dataclass(frozen=True)
class StabilityChange:
    """Where a branch changes stability (:func:`refine_stability_change`).

    Attributes
    ----------
    value : float
        ``|mu|max - 1`` interpolated linearly to zero in ``bracket``.
    kind : BifurcationKind
        :meth:`BifurcationKind.by_multiplier` of the unstable end's multipliers
        (:attr:`~BifurcationKind.UNKNOWN` if none fits).
    bracket : (float, float)
        The final interval, its first end on the side of the first given end.
    states : ndarray, shape (2, d)
        The orbit's stroboscopic point at each end of ``bracket``.
    multipliers : ndarray of complex, shape (2, d)
        Its Floquet multipliers there.
    """

    value: float
    kind: BifurcationKind
    bracket: tuple
    states: np.ndarray
    multipliers: np.ndarray


def multiplier_crossing(lo, hi, mu_lo, mu_hi):
    """Where ``|mu|max - 1`` crosses zero between ``lo`` and ``hi``, by linear
    interpolation of its values ``mu_lo``, ``mu_hi`` (multipliers) at the two ends."""
    g0 = float(np.abs(mu_lo).max()) - 1.0
    g1 = float(np.abs(mu_hi).max()) - 1.0
    w = g0 / (g0 - g1) if g0 != g1 else 0.5
    return float(lo + w * (hi - lo))


def refine_stability_change(system: System, param: str | int, n: int, values: tuple,
                            states: tuple, *, tol: float = 1e-6,
                            newton_tol: float = 1e-9) -> StabilityChange:
    """Narrow the parameter interval in which a period-``n`` orbit changes stability.

    Bisection: the orbit is shot (:func:`shoot_periodic_orbit`) at the midpoint from the
    state interpolated linearly between the two ends; the end with the same stability
    (``|mu|max < 1``) as the midpoint's orbit moves there.  It stops when the interval
    is at most ``tol`` wide, or keeps the last interval when Newton fails at a midpoint,
    lands more than a quarter of the orbit's size away from the guess (another orbit)
    or on a lower period.  The interval must not contain a turning point (there are two
    orbits at the midpoint).  Both ends must lie in the parameter's domain
    (:meth:`vibimpact.System.param_domain`); every midpoint then does too.

    Parameters
    ----------
    system : System
        Model, parameters and solver settings (defaults :data:`CONTINUATION_SOLVER`).
    param : str or int
    n : int
    values : (float, float)
        The parameter at the two ends: two neighbouring points of a
        :class:`Branch` of different stability.
    states : (array_like, array_like)
        The orbit's stroboscopic point at each end.
    tol : float
        Width of the final interval.
    newton_tol : float
        Newton's tolerance of the shootings.

    Returns
    -------
    StabilityChange
        The value, kind and final interval, with the orbits at its ends.

    Raises
    ------
    ValueError
        Naming the argument; ``values`` when both ends have the same stability or an end
        lies outside the parameter's domain (:meth:`vibimpact.System.param_domain`).
    """
    system = as_system(system).resolved(**CONTINUATION_SOLVER)
    tol = _v.positive("tol", tol)
    n = _v.count("n", n, 1)
    lo, hi = (float(_v.finite("values", v)) for v in values)
    dom = system.param_domain(param)
    for v in (lo, hi):  # the midpoints lie between the two: inside the domain too
        if v not in dom:
            raise ValueError(f"values: {dom.rule(param_name(system, param))}, got {v!r}")
    xs = [_v.state("states", x, system.n_state) for x in states]
    mus = [shoot_periodic_orbit(system.with_param(param, v), x, n, tol=newton_tol)
           for v, x in zip((lo, hi), xs)]
    stable = [bool(m.abs_max < 1.0) for m in mus]
    if not all(m.converged for m in mus) or stable[0] == stable[1]:
        raise ValueError(f"values: no change of stability between {param} = {lo} and "
                         f"{hi} (orbits found {[m.converged for m in mus]}, stable "
                         f"{stable})")
    mults = [m.multipliers for m in mus]
    while abs(hi - lo) > tol:
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):  # a tol below the float resolution: as narrow as it gets
            break
        guess = xs[0] + (xs[1] - xs[0]) * ((mid - lo) / (hi - lo))
        orb = shoot_periodic_orbit(system.with_param(param, mid), guess, n, tol=newton_tol)
        scale = max(1.0, float(np.abs(guess).max()))
        if not orb.converged or orb.minimal_period < n or \
                float(np.abs(orb.state - guess).max()) > 0.25 * scale:
            break
        side = 0 if bool(orb.abs_max < 1.0) == stable[0] else 1
        (lo, hi) = (mid, hi) if side == 0 else (lo, mid)
        xs[side], mults[side] = orb.state, orb.multipliers
    unstable = mults[1] if stable[0] else mults[0]
    kind = BifurcationKind.by_multiplier(critical_multiplier(unstable))
    return StabilityChange(multiplier_crossing(lo, hi, mults[0], mults[1]), kind, (lo, hi),
                           np.array(xs), np.array(mults))


def impacts_per_period(system: System, state: ArrayLike, n: int) -> int:
    """Contacts (impacts) per period of the period-``n`` orbit through ``state``.

    The contact entries in the event log of one run over the orbit's ``n`` forcing
    periods from ``state`` (:attr:`vibimpact.Run.impacts`: 0 for a model without
    contacts); -1 where the run stops.  ``system``'s solver settings default to
    :data:`CONTINUATION_SOLVER`.
    """
    system = as_system(system)
    run = system.simulate(periods=n, state0=state, solver=system.settings(**CONTINUATION_SOLVER))
    if run.status is not Status.OK:
        return -1
    return int(run.impacts.size)


@dataclass(frozen=True)
class Grazing:
    """Where a branch's impacts per period change (:func:`refine_grazing`).

    Attributes
    ----------
    value : float
        Midpoint of ``bracket``.
    bracket : (float, float)
        The final interval, its first end on the side of the first given end.
    impacts : (int, int)
        Impacts per period of the orbit at each end of ``bracket``
        (:func:`impacts_per_period`).
    states : ndarray, shape (2, d)
        The orbit's stroboscopic point at each end of ``bracket``.
    """

    value: float
    bracket: tuple
    impacts: tuple
    states: np.ndarray

    @property
    def kind(self) -> BifurcationKind:
        """:attr:`BifurcationKind.GRAZING`."""
        return BifurcationKind.GRAZING


def refine_grazing(system: System, param: str, n: int, values: tuple, states: tuple, *,
                   tol: float = 1e-6, newton_tol: float = 1e-9) -> Grazing:
    """Narrow the parameter interval in which a period-``n`` orbit's impacts per period
    change: where it grazes the contact surface (touches it with zero normal velocity).

    Bisection on the parameter: the orbit is shot (:func:`shoot_periodic_orbit`) at the
    midpoint from the state interpolated linearly between the two ends, and its impacts
    per period counted (:func:`impacts_per_period`); the end with the same count moves
    there.  It stops when the interval is at most ``tol`` wide, or keeps the last
    interval when Newton fails at a midpoint, lands more than a quarter of the orbit's
    size away from the guess (another orbit) or on a lower period, or the midpoint's
    count is neither end's (two grazings in the interval).  A grazing moves no
    Floquet multiplier through the unit circle: the stability need not change.

    Parameters
    ----------
    system : System
        Model, parameters and solver settings (defaults :data:`CONTINUATION_SOLVER`).
    param : str or int
    n : int
    values : (float, float)
        The parameter at the two ends: two neighbouring points of a :class:`Branch`.
    states : (array_like, array_like)
        The orbit's stroboscopic point at each end.
    tol : float
        Width of the final interval.
    newton_tol : float
        Newton's tolerance of the shootings.

    Returns
    -------
    Grazing
        The final interval, its midpoint, and the impacts per period at its ends.

    Raises
    ------
    ValueError
        Naming the argument; ``values`` when an end lies outside the parameter's domain
        or both ends have the same impacts per period (or a run from an end stops).
    """
    system = as_system(system).resolved(**CONTINUATION_SOLVER)
    tol = _v.positive("tol", tol)
    n = _v.count("n", n, 1)
    lo, hi = (float(_v.finite("values", v)) for v in values)
    dom = system.param_domain(param)
    for v in (lo, hi):
        if v not in dom:
            raise ValueError(f"values: {dom.rule(param_name(system, param))}, got {v!r}")
    xs = [_v.state("states", x, system.n_state) for x in states]
    ends = tuple(impacts_per_period(system.with_param(param, v), x, n)
                 for v, x in zip((lo, hi), xs))
    if ends[0] == ends[1] or min(ends) < 0:
        raise ValueError(f"values: no change of impacts per period between {param} = "
                         f"{lo} and {hi} (impacts {ends[0]} and {ends[1]})")
    while abs(hi - lo) > tol:
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):  # a tol below the float resolution: as narrow as it gets
            break
        guess = xs[0] + (xs[1] - xs[0]) * ((mid - lo) / (hi - lo))
        q = system.with_param(param, mid)
        orb = shoot_periodic_orbit(q, guess, n, tol=newton_tol)
        scale = max(1.0, float(np.abs(guess).max()))
        if not orb.converged or orb.minimal_period < n or \
                float(np.abs(orb.state - guess).max()) > 0.25 * scale:
            break
        count = impacts_per_period(q, orb.state, n)
        if count not in ends:
            break
        side = ends.index(count)
        (lo, hi) = (mid, hi) if side == 0 else (lo, mid)
        xs[side] = orb.state
    return Grazing(0.5 * (lo + hi), (lo, hi), ends, np.array(xs))


def branch_grazings(system, param, n, vals, states, impacts, refine, newton_tol):
    """The grazings along a branch of period-``n`` orbits.

    ``(index, BifurcationKind.GRAZING, value, bracket, (before, after))`` wherever the
    impacts per period (``impacts``) of the points ``index - 1`` and ``index`` differ
    (both counted): ``bracket`` the two points' parameter ``vals``, or, with ``refine``
    (a width), narrowed to it by :func:`refine_grazing` from their ``states`` (where
    that fails, the two points stay the bracket); ``value`` its midpoint; ``before``,
    ``after`` the two counts.  ``newton_tol`` is the shootings' tolerance.
    """
    out = []
    for i in range(1, vals.size):
        before, after = int(impacts[i - 1]), int(impacts[i])
        if before == after or min(before, after) < 0:
            continue
        bracket = (float(vals[i - 1]), float(vals[i]))
        if refine is not None:
            try:
                bracket = refine_grazing(system, param, n, bracket,
                                         (states[i - 1], states[i]), tol=refine,
                                         newton_tol=newton_tol).bracket
            except ValueError:  # an end's count not reproduced: the two points stay
                pass
        out.append((i, BifurcationKind.GRAZING, 0.5 * (bracket[0] + bracket[1]),
                    bracket, (before, after)))
    return out
