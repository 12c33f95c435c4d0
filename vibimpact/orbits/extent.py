"""Where a periodic orbit exists and where it is stable: its branch in the forcing
frequency, both ways from where it was found (:func:`orbit_extent`).

The orbit is followed by pseudo-arclength continuation
(:func:`vibimpact.analysis.continue_orbit`; Keller 1977, Seydel 2010 sec. 4.4) up and down
from the hunt's value, inside a window.  On each side the orbit is the branch up to its
first turning point: at a fold (saddle-node) two orbits meet and end, and past the turn
the branch is the other one.  The continuation also stops where it cannot go on (a step
below its minimum, typically at a grazing where the map is not smooth, or an
integration that stopped).  Along the part kept, the stable stretches (every ``|mu| <
1``) are the stable sub-intervals, their ends at the stability changes interpolated by
the continuation.

References
----------
.. [1] H. B. Keller, "Numerical solution of bifurcation and nonlinear eigenvalue
   problems", in *Applications of Bifurcation Theory*, Academic Press (1977) 359-384.
.. [2] R. Seydel, *Practical Bifurcation and Stability Analysis*, 3rd ed., Springer
   (2010), ch. 4 and 7.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import math

import numpy as np

from ..base import _validate as _v
from ..analysis.continuation import Steps, continue_orbit
from ..analysis.stability_change import multiplier_crossing
from ..base.bifurcation_kinds import BifurcationKind
from ..core.run import Status
from ..core.system import to_system
from .found import Extent

if TYPE_CHECKING:  # names of the annotations only
    from ..core.system import System
    from .found import FoundOrbit

__all__ = ["orbit_extent", "HUNT_STEPS"]

#: step controls of the hunt's continuations (a window of +-0.05 needs few points)
HUNT_STEPS = Steps(ds=0.004, ds_max=0.01, max_points=150)
#: a branch point whose stroboscopic points return after a divisor ``m`` of its period to
#: this (relative) distance lies on the period-``m`` orbit
LOWER_TOL = 1e-6


def _lower_period(system, param, n, value, x):
    """The minimal period of the period-``n`` orbit through ``x`` at ``param = value``:
    a divisor of ``n`` after which its stroboscopic points return (to 1e-6 relative);
    ``n`` when none does or the run stops."""
    if n == 1:
        return 1
    status, _, pts = system.with_param(param, value).strobe(n, x)
    if status is not Status.OK or pts.shape[0] < n + 1:
        return n
    scale = max(1.0, float(np.abs(pts).max()))
    for m in range(1, n):
        if n % m == 0 and float(np.abs(pts[m] - pts[0]).max()) <= LOWER_TOL * scale:
            return m
    return n


def _side(system, param, branch):
    """``(values, stable, impacts, multipliers, reason)`` of one branch up to its first
    turning point, or up to where it meets an orbit of lower period (the branch of
    period-``n`` points runs through a period doubling onto the orbit it doubled), the
    start included."""
    vals = np.asarray(branch.values, dtype=float)
    end, reason = vals.size, _reason(branch.status)
    for i, kind, value in branch.bifurcations:
        # a lookup by value (EnumMeta.__call__), not a call of __new__
        if BifurcationKind(kind) is BifurcationKind.TURNING_POINT:  # type: ignore[call-arg]
            end, reason = i + 1, f"fold (turning point) at {value:.6g}"
            break
    n = int(branch.n)
    for i in range(1, end):
        m = _lower_period(system, param, n, vals[i], branch.states[i])
        if m < n:  # the points from i on are the period-m orbit's
            mid = 0.5 * (vals[i - 1] + vals[i])
            end, reason = i, f"period doubling: meets the P{m} orbit near {mid:.6g}"
            break
    return (vals[:end], np.asarray(branch.stable[:end], dtype=bool),
            np.asarray(branch.impacts_per_period[:end], dtype=np.int64),
            np.asarray(branch.multipliers[:end]), reason)


def _reason(status):
    """The continuation's status in the words of an existence interval's end."""
    if status.startswith(("reached the end of the window", "left the parameter window")):
        return "end of the window"
    return status


def _stable_intervals(vals, stable, mults):
    """The stable sub-intervals of a branch part with increasing ``vals``."""
    out, start = [], None
    for i in range(vals.size):
        if stable[i] and start is None:
            start = vals[0] if i == 0 else multiplier_crossing(
                vals[i - 1], vals[i], mults[i - 1], mults[i])
        if not stable[i] and start is not None:
            out.append((float(start), float(multiplier_crossing(
                vals[i - 1], vals[i], mults[i - 1], mults[i]))))
            start = None
    if start is not None:
        out.append((float(start), float(vals[-1])))
    return tuple(out)


def _same_impacts(vals, impacts, i0):
    """The interval about point ``i0`` with its impacts per period (ends between
    points: midpoints)."""
    lo = hi = i0
    while lo > 0 and impacts[lo - 1] == impacts[i0]:
        lo -= 1
    while hi < vals.size - 1 and impacts[hi + 1] == impacts[i0]:
        hi += 1
    a = vals[lo] if lo == 0 else 0.5 * (vals[lo - 1] + vals[lo])
    b = vals[hi] if hi == vals.size - 1 else 0.5 * (vals[hi] + vals[hi + 1])
    return float(a), float(b)


def orbit_extent(system: System, orbit: FoundOrbit, window: float = 0.05,
                 steps: Steps | None = None) -> Extent:
    """The existence and stability intervals of a periodic orbit in the forcing
    frequency.

    Parameters
    ----------
    system : System or parameter set
        The model at the frequency where ``orbit`` was found.
    orbit : FoundOrbit
    window : float
        Half-width of the window about the frequency, ``> 0``.
    steps : Steps, optional
        Step controls of :func:`vibimpact.analysis.continue_orbit` (default
        :data:`HUNT_STEPS`).

    Returns
    -------
    Extent
        Where the continuation could not start (Newton failed at the start), the
        interval is the hunt's value alone, with the reason at both ends.

    Raises
    ------
    ValueError
        Naming ``window`` or ``steps``.
    """
    system = to_system(system, "system")
    window = _v.positive("window", window)
    steps = HUNT_STEPS if steps is None else steps
    if not isinstance(steps, Steps):
        raise _v.WrongType(f"steps must be a vibimpact.analysis.Steps, got "
                           f"{type(steps).__name__}")
    mdl = system.model
    param = mdl.param_names[mdl.omega_index]
    lam0 = system.omega
    parts = []
    for direction in (-1, 1):
        try:
            br = continue_orbit(system, orbit.state, orbit.period, param=param,
                                stop=(lam0 - window, lam0 + window), steps=steps,
                                direction=direction, amplitude=False)
        except ValueError as exc:
            why = f"continuation failed: {getattr(exc, 'reason', exc)}"
            one = np.array([lam0])
            return Extent(lam0, lam0, why, why, ((lam0, lam0),) if orbit.stable else (),
                          one, np.array([orbit.stable]), np.array([orbit.impacts]),
                          np.array([orbit.abs_max]), (lam0, lam0))
        parts.append(_side(system, param, br))
    (dv, ds_, di, dm, dr), (uv, us, ui, um, ur) = parts
    vals = np.concatenate([dv[::-1], uv[1:]])
    stable = np.concatenate([ds_[::-1], us[1:]])
    impacts = np.concatenate([di[::-1], ui[1:]])
    mults = np.concatenate([dm[::-1], um[1:]])
    i0 = dv.size - 1
    abs_max = np.abs(mults).max(axis=1) if mults.size else np.zeros(0)
    return Extent(float(vals[0]), float(vals[-1]), dr, ur,
                  _stable_intervals(vals, stable, mults), vals, stable, impacts, abs_max,
                  _same_impacts(vals, impacts, i0) if math.isfinite(lam0) else
                  (math.nan, math.nan))
