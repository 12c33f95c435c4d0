"""Where exactly a branch of periodic orbits changes stability: bisection between two
of its orbits (:func:`refine_stability_change`), used by
:func:`~vibimpact.analysis.continuation.continue_orbit` with ``refine``.

References
----------
.. [1] Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., Springer
   (2004), ch. 4.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from dataclasses import dataclass

import numpy as np

from .. import _validate as _v
from ..system import as_system
from .bifurcation import CONTINUATION_SOLVER, KIND_BY_MULTIPLIER
from .shooting import critical_multiplier, shoot_periodic_orbit

if TYPE_CHECKING:  # names of the annotations only
    from ..system import System


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
    kind : str
        :data:`KIND_BY_MULTIPLIER` of the unstable end's multipliers (``"?"`` if none
        fits).
    bracket : (float, float)
        The final interval, its first end on the side of the first given end.
    states : ndarray, shape (2, d)
        The orbit's stroboscopic point at each end of ``bracket``.
    multipliers : ndarray of complex, shape (2, d)
        Its Floquet multipliers there.
    """

    value: float
    kind: str
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


def refine_stability_change(system: System, param: str, n: int, values: tuple,
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
    mus = [m.multipliers for m in mus]
    while abs(hi - lo) > tol:
        mid = 0.5 * (lo + hi)
        guess = xs[0] + (xs[1] - xs[0]) * ((mid - lo) / (hi - lo))
        orb = shoot_periodic_orbit(system.with_param(param, mid), guess, n, tol=newton_tol)
        scale = max(1.0, float(np.abs(guess).max()))
        if not orb.converged or orb.minimal_period < n or \
                float(np.abs(orb.state - guess).max()) > 0.25 * scale:
            break
        side = 0 if bool(orb.abs_max < 1.0) == stable[0] else 1
        (lo, hi) = (mid, hi) if side == 0 else (lo, mid)
        xs[side], mus[side] = orb.state, orb.multipliers
    unstable = mus[1] if stable[0] else mus[0]
    kind = KIND_BY_MULTIPLIER.get(critical_multiplier(unstable), "?")
    return StabilityChange(multiplier_crossing(lo, hi, mus[0], mus[1]), kind, (lo, hi),
                           np.array(xs), np.array(mus))
