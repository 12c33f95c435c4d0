"""Following a periodic orbit in a parameter: where and how it ends, and its whole branch.

Two tools on top of :func:`~vibimpact.analysis.shooting.shoot_periodic_orbit`:

* :func:`locate_bifurcation` (in :mod:`.bifurcation`, re-exported here) -- natural-
  parameter stepping with bisection to where a stable orbit stops persisting, and the
  kind of that event from its Floquet multipliers or its switching events.
* :func:`continue_orbit` -- pseudo-arclength continuation (Keller 1977; Seydel 2010,
  sec. 4.4; Allgower & Georg 2003) of ``G(x, lambda) = P^n(x; lambda) - x = 0`` in
  ``(x, lambda)``.  It goes round folds, so it follows the *unstable* branches that a
  brute-force sweep, which only ever sees attractors, misses; along the branch it finds
  the stability changes, the turning points and the grazings (the orbit's impacts per
  period change; no multiplier crosses the unit circle there).

Every kind is a :class:`~vibimpact.base.bifurcation_kinds.BifurcationKind`.

References
----------
.. [1] H. B. Keller, "Numerical solution of bifurcation and nonlinear eigenvalue
   problems", in *Applications of Bifurcation Theory*, Academic Press (1977) 359-384.
.. [2] R. Seydel, *Practical Bifurcation and Stability Analysis*, 3rd ed., Springer
   (2010), ch. 4 and 7.
.. [3] E. L. Allgower, K. Georg, *Introduction to Numerical Continuation Methods*, SIAM
   (2003), ch. 2.
.. [4] Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., Springer
   (2004), ch. 4.
.. [5] R. I. Leine, H. Nijmeijer, *Dynamics and Bifurcations of Non-Smooth Mechanical
   Systems*, Springer (2004), ch. 7.
.. [6] M. di Bernardo, C. J. Budd, A. R. Champneys, P. Kowalczyk, *Piecewise-smooth
   Dynamical Systems*, Springer (2008), ch. 8 (grazing of periodic orbits).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import math
from dataclasses import dataclass

import numpy as np

from ..base.bifurcation_kinds import BifurcationKind
from ..core.run import Status
from ..base import _validate as _v
from ..core.system import as_system
from .._kernel.boundary import dot, solve
from .bifurcation import (CONTINUATION_SOLVER, Bifurcation, locate_bifurcation,
                          orbit_signature, grazing_gap)
from .shooting import critical_multiplier, floquet_multipliers, shoot_periodic_orbit
# STEP_ULPS, smallest_step: imported from here by the command line (cli.continue_, continue2)
from .continuation_steps import STEP_ULPS, Steps, check_steps, smallest_step  # noqa: F401
from .stability_change import (Grazing, StabilityChange, branch_grazings,
                               impacts_per_period, multiplier_crossing, param_name,
                               refine_grazing, refine_stability_change)

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

    from ..core.system import System

__all__ = ["Bifurcation", "Branch", "Steps", "locate_bifurcation", "continue_orbit",
           "refine_stability_change", "StabilityChange", "refine_grazing", "Grazing",
           "impacts_per_period", "orbit_signature", "grazing_gap", "CONTINUATION_SOLVER",
           "StartFailed"]

@dataclass(frozen=True)
class Branch:
    """A branch of period-``n`` orbits followed in one parameter.

    Attributes
    ----------
    param : str or int
    values : ndarray, shape (k,)
        Parameter at each point, in continuation order (not monotonic past a fold).
    states : ndarray, shape (k, d)
        A stroboscopic point of each orbit.
    multipliers : ndarray of complex, shape (k, d)
    stable : ndarray of bool, shape (k,)
    amplitude : dict of str -> ndarray, shape (k,)
        Response measures of each orbit, from densely sampled motion: for a model with a
        planar contact (two :attr:`~vibimpact.Contact.positions`), ``<position>_m``, the
        largest ``|position|``, of each and ``R_m``, the largest distance from the origin
        in their plane (the built-in rotor's ``X_m``, ``Y_m``, ``R_m``); for any other
        model, ``<state>_m`` of its first two states.
    n : int
    bifurcations : tuple of (int, BifurcationKind, float)
        ``(index, kind, value)``: between point ``index - 1`` and ``index`` the stability
        changed (kind from the multiplier crossing,
        :meth:`BifurcationKind.by_multiplier`; value by linear interpolation of
        ``|mu|max - 1``, so to about the square of the step; refine with
        :func:`locate_bifurcation`), or the impacts per period changed
        (:attr:`BifurcationKind.GRAZING`; value the midpoint of its bracket), or at
        point ``index`` the parameter turned (:attr:`BifurcationKind.TURNING_POINT`).
        In order of ``index`` (then kind).
    status : str
        Why the continuation stopped: the end of the parameter window reached (or left,
        when the last step could not be shortened to end there), a bound of the
        parameter's domain reached (``"reached the bound BT = 0 (BT must be >= 0)"``:
        the last orbit lies on it; next to an open bound such as ``eta > 0``,
        ``"reached eta = 1e-05, next to the bound (eta must be > 0)"``), ``max_points``
        orbits, or a step below ``ds_min``.
    brackets : tuple of (float, float)
        For each of ``bifurcations``, the parameter interval it lies in: the two branch
        points around a stability change (with ``refine``, the two orbits inserted at the
        ends of the narrowed interval), or around a grazing (with ``refine``, narrowed by
        :func:`refine_grazing`; no orbit inserted), ``(value, value)`` at a turning point.
    impacts_per_period : ndarray of int, shape (k,)
        Impacts (contact entries) per period of each orbit, from the event log of one
        run over its ``n`` forcing periods (:func:`impacts_per_period`; 0 for a model
        without contacts, -1 where the run stopped or the branch was read from a file
        that did not hold them).
    event_impacts : tuple of (int, int)
        For each of ``bifurcations``, the impacts per period before and after it (at
        the two points around it; at the ends of a grazing's bracket).
    """

    param: str | int
    values: np.ndarray
    states: np.ndarray
    multipliers: np.ndarray
    stable: np.ndarray
    amplitude: dict
    n: int
    bifurcations: tuple = ()
    status: str = ""
    brackets: tuple = ()
    impacts_per_period: np.ndarray | None = None
    event_impacts: tuple = ()


class StartFailed(ValueError):
    """No periodic orbit at the start of a continuation: Newton shooting from ``state0``
    failed.  ``reason`` says why (the shooting's own reason), so that a caller can say
    it in its own words without reading the message."""

    def __init__(self, reason: str) -> None:
        self.reason = str(reason)
        super().__init__(f"state0: shooting failed at the start ({self.reason})")


def _amplitude(system, x, n, names, dense=96):
    run = system.simulate(periods=n, state0=x, dense=dense)
    out = {}
    if run.status is not Status.OK or run.dense is None:
        return {k: math.nan for k in names}
    D = run.dense
    contact = system.model.contact
    cols = contact.positions if "R_m" in names else (0, 1)
    for j, name in zip(cols, names[:2]):
        out[name] = float(np.abs(D[:, j]).max())
    if "R_m" in names:  # a planar contact: the radius, exact at the logged extrema
        a, b = cols
        R = np.hypot(D[:, a], D[:, b])
        ext = np.asarray(run.events["which"]) == contact.extremum
        Rm = float(R.max())
        if np.any(ext):
            at = np.asarray(run.events["state"])[ext]
            Rm = max(Rm, float(np.hypot(at[:, a], at[:, b]).max()))
        out["R_m"] = Rm
    return out


class _Arclength:
    """The pseudo-arclength problem of :func:`continue_orbit`: ``G(x, lambda) = P^n(x;
    lambda) - x``, its Jacobian, the tangent, the corrector and the march along the
    branch, inside ``window`` (the parameter window cut to the parameter's domain,
    :func:`_limits`)."""

    def __init__(self, system, param, n, window, steps, bounds=(None, None)):
        self.system, self.param, self.n = system, param, n
        self.window, self.steps = window, steps
        self.d = system.n_state
        self.domain = system.param_domain(param)
        self.bounds = bounds  # per end of window: the domain's rule if it ends there

    def jac(self, x, lam):
        """``(Monodromy, [G_x | G_lambda])`` at ``(x, lam)``; ``(None, None)`` where the
        map cannot be evaluated (an integration that stopped, a parameter outside its
        domain)."""
        window, steps, n = self.window, self.steps, self.n
        if not window[0] - 10.0 * steps.ds_max <= lam <= window[1] + 10.0 * steps.ds_max:
            return None, None  # a corrector iterate far outside the window
        if lam not in self.domain:  # a corrector iterate past a bound (e.g. eta <= 0)
            return None, None
        m = self.system.with_param(self.param, lam).monodromy(x, n)
        if m.status is not Status.OK:
            return None, None
        return self.bordered(m, x, lam)

    def bordered(self, m, x, lam):
        """``(m, [M - I | G_lambda])`` with the monodromy ``m`` at ``(x, lam)``;
        ``(None, None)`` where ``G_lambda`` cannot be evaluated."""
        Gl = _map_derivative(self.system, self.param, self.domain, x, lam, self.n,
                             self.steps.fd_step * max(1.0, abs(lam)))
        if Gl is None:
            return None, None
        return m, np.hstack([m.matrix - np.eye(self.d), Gl[:, None]])

    def tangent(self, Jg, t_prev):
        """Unit null vector of ``Jg``, oriented along ``t_prev``."""
        A = np.vstack([Jg, t_prev[None, :]])
        rhs = np.zeros(self.d + 1)
        rhs[-1] = 1.0
        t, ok = solve(A, rhs)
        if not ok:
            raise np.linalg.LinAlgError("singular matrix")
        t /= math.sqrt(dot(t, t))
        return t if dot(t, t_prev) >= 0.0 else -t

    def correct(self, u_pred, t):
        """Newton on ``G = 0``, ``t . (u - u_pred) = 0`` from ``u_pred``: ``(ok, u,
        Monodromy, Jacobian, iterations)``."""
        window, tol = self.window, self.steps.newton_tol
        u = u_pred.copy()
        mm = J = None
        for it in range(self.steps.max_newton):
            if not window[0] - 1e-12 <= u[-1] <= window[1] + 1e-12 and it == 0:
                break
            mm, J = self.jac(u[:-1], u[-1])
            if mm is None:
                break
            G = mm.end - mm.start
            r = np.append(G, dot(t, u - u_pred))
            if np.abs(G).max() <= tol * max(1.0, np.abs(u[:-1]).max()) and it > 0:
                return True, u, mm, J, it
            du, ok = solve(np.vstack([J, t[None, :]]), -r)
            if not ok:
                break
            u = u + du
            if not np.all(np.isfinite(u)):
                break
        return False, u, mm, J, self.steps.max_newton

    def onto_bound(self, x, lam, t, edge, ds):
        """The step from ``(x, lam)`` that ends on the domain's bound ``lambda = edge``:
        the predictor along ``t`` to where it meets the bound (at most ``ds``), then
        Newton in ``x`` at ``lambda = edge`` exactly (``G_x = M - I``), so that no
        iterate leaves the domain.  Returns as :meth:`correct`."""
        tol, d = self.steps.newton_tol, self.d
        s = (edge - lam) / t[-1] if t[-1] * (edge - lam) > 0.0 else ds
        xk = x + min(s, ds) * t[:-1]
        at_edge = self.system.with_param(self.param, edge)
        for it in range(self.steps.max_newton):
            mm = at_edge.monodromy(xk, self.n)
            if mm.status is not Status.OK:
                break
            G = mm.end - mm.start
            if np.abs(G).max() <= tol * max(1.0, np.abs(xk).max()) and it > 0:
                mm, J = self.bordered(mm, xk, edge)
                return mm is not None, np.append(xk, edge), mm, J, it
            dx, ok = solve(mm.matrix - np.eye(d), -G)
            if not ok:
                break
            xk = xk + dx
            if not np.all(np.isfinite(xk)):
                break
        return False, np.append(xk, edge), None, None, self.steps.max_newton

    def march(self, x, lam, t, record, count):
        """Step along the branch from the point ``(x, lam)`` with tangent ``t``,
        ``record(x, lam, M)`` at every new orbit, while ``count() < max_points``; the
        status (why it stopped).

        The step adapts (x1.5 after a fast corrector, /2 after a failure); a step that
        would leave the window is shortened to end at its edge (at most 3 times); one
        that would pass a bound of the parameter's domain ends on the bound
        (:meth:`onto_bound`), where the branch ends."""
        steps, (lo, hi) = self.steps, self.window
        status = f"max_points ({steps.max_points}) reached"
        ds = steps.ds
        edge_tries = 0  # steps shortened to end at the window's edge
        while count() < steps.max_points:
            u_pred = np.append(x, lam) + ds * t
            ok, u, mm, J, it = self.correct(u_pred, t)
            lam_out = u[-1] if ok else u_pred[-1]
            if not lo <= lam_out <= hi:
                edge = hi if lam_out > hi else lo
                rule = self.bounds[1 if lam_out > hi else 0]
                if rule is not None:  # the domain's bound: end on it
                    if lam == edge:
                        status = _bound_status(self.param, edge, rule, self.domain)
                        break
                    ok, u, mm, J, it = self.onto_bound(x, lam, t, edge, ds)
                else:
                    # shorten the step to end at the edge (at most 3 times), so that the
                    # branch reaches it and no change of stability before it is missed
                    frac = (edge - lam) / (lam_out - lam) if lam_out != lam else 0.0
                    if edge_tries < 3 and ds * frac >= steps.ds_min:
                        ds *= frac
                        edge_tries += 1
                        continue
                    status = (f"reached the end of the window, {self.param} = {edge:.6g}"
                              if abs(edge - lam) <= steps.ds_min else
                              "left the parameter window")
                    break
            if not ok:
                ds *= 0.5
                if ds < steps.ds_min:
                    status = (f"step below ds_min ({steps.ds_min}) at {self.param} = "
                              f"{lam:.6g}")
                    break
                continue
            x, lam = u[:-1], u[-1]
            t = self.tangent(J, t)
            record(x, lam, mm.matrix)
            ds = min(steps.ds_max, ds * 1.5) if it <= 3 else ds
        return status


def _map_derivative(system, param, domain, x, lam, n, h):
    """``G_lambda = dP^n(x; lambda) / d lambda`` at ``lam`` by finite differences of
    step ``h``: central, ``(P(lam + h) - P(lam - h)) / 2h``, where both values lie in the
    parameter's ``domain``; else one-sided of the same (second) order,
    ``s (-3 P(lam) + 4 P(lam + s h) - P(lam + 2 s h)) / 2h`` with ``s = +1`` (or ``-1``)
    into the domain.  None where a run stops or the domain is narrower than ``2 h``."""
    def final(value):
        run = system.with_param(param, value).simulate(periods=n, state0=x)
        return run.final_state if run.status is Status.OK else None

    if lam - h in domain and lam + h in domain:
        a, b = final(lam + h), final(lam - h)
        if a is None or b is None:
            return None
        return (a - b) / (2.0 * h)
    for s in (1.0, -1.0):
        if lam + s * h in domain and lam + 2.0 * s * h in domain:
            p0, p1, p2 = final(lam), final(lam + s * h), final(lam + 2.0 * s * h)
            if p0 is None or p1 is None or p2 is None:
                return None
            return s * (-3.0 * p0 + 4.0 * p1 - p2) / (2.0 * h)
    return None


def _bound_status(param, edge, rule, domain):
    """:attr:`Branch.status` of a branch that ended on a bound of ``param``'s domain
    (``rule`` says it in words)."""
    if edge in (domain.lo, domain.hi):
        return f"reached the bound {param} = {edge:g} ({rule})"
    return f"reached {param} = {edge:.6g}, next to the bound ({rule})"


def _usable_bound(bound, closed, inward, ds_min):
    """How far towards ``bound`` the branch may go: the bound itself when it is closed
    (or infinite), ``ds_min`` (relative to ``max(1, |bound|)``) inside an open one."""
    if closed or not math.isfinite(bound):
        return bound
    return bound + inward * ds_min * max(1.0, abs(bound))


def _limits(system, param, window, lam0, ds_min):
    """The window cut to the domain of ``param``, and for each end the domain's rule
    (:meth:`~vibimpact.models.params.Domain.rule`) if the domain ends the window there, else
    None: ``((lo, hi), (rule or None, rule or None))``."""
    dom = system.param_domain(param)
    rule = dom.rule(param_name(system, param))
    lo = min(lam0, _usable_bound(dom.lo, dom.lo_closed, 1.0, ds_min))
    hi = max(lam0, _usable_bound(dom.hi, dom.hi_closed, -1.0, ds_min))
    return ((max(window[0], lo), min(window[1], hi)),
            (rule if lo >= window[0] else None, rule if hi <= window[1] else None))


def _window(stop, lam0):
    """The parameter window ``(lo, hi)`` of :func:`continue_orbit`."""
    if np.ndim(stop) == 0:
        s = _v.finite("stop", stop)
        return (min(lam0, s), max(lam0, s))
    if len(stop) != 2:
        raise ValueError(f"stop must be a float or (lo, hi), got {stop!r}")
    return tuple(sorted((_v.finite("stop", stop[0]), _v.finite("stop", stop[1]))))


@_v.checks_flags
def continue_orbit(system: System, state0: ArrayLike, n: int = 1, *,
                   param: str | int = "eta", stop: float | tuple[float, float],
                   steps: Steps = Steps(), direction: int = 1,
                   amplitude: bool = True, refine: float | None = None) -> Branch:
    """Pseudo-arclength continuation of a period-``n`` orbit in one parameter.

    Unknowns ``u = (x, lambda)``; equations ``G(u) = P^n(x; lambda) - x = 0`` and the
    arclength condition ``t . (u - u_pred) = 0`` with the unit tangent ``t`` of the
    previous point (Keller 1977).  ``G_x = M - I`` comes from the variational equations
    (:func:`~vibimpact.analysis.monodromy`), ``G_lambda`` from central differences of the
    map in the parameter.  The tangent is the null vector of ``[G_x | G_lambda]``, oriented
    to keep the direction of travel, so the continuation goes round folds onto the
    unstable branch.  The step adapts (x1.5 after a fast corrector, /2 after a failure);
    a step that would leave the parameter window is shortened to end at its edge.

    No orbit is computed outside the parameter's domain
    (:meth:`vibimpact.System.param_domain`: e.g. ``BT >= 0``, ``eta > 0``).  A branch
    may start on a bound (``BT = 0``, as in every preset) or run towards one: where
    ``lambda - h`` would leave the domain, ``G_lambda`` is the one-sided second-order
    difference ``(-3 P(lambda) + 4 P(lambda + h) - P(lambda + 2h)) / 2h`` into it; a step
    whose predicted or corrected parameter would pass the bound is shortened to end on
    it, and its orbit is found there by Newton in the state at the bound's value (no
    iterate leaves the domain).  The branch then ends there, with the reason in
    :attr:`Branch.status`.  An open bound (``eta > 0``) is not reached: the branch ends
    ``ds_min`` (times ``max(1, |bound|)``) inside it.

    Parameters
    ----------
    system : System
        Model, parameters (its value of ``param`` is the starting value) and solver
        settings of every integration (defaults DOP853, ``rtol = 1e-10``, ``atol =
        1e-12``: :data:`CONTINUATION_SOLVER`).
    state0 : array_like, shape (d,)
        A guess of the orbit at the start (shot first).
    n : int
    param : str or int
        Any parameter name (e.g. ``"eta"``, the built-in rotor's forcing frequency), or
        an index of a user model's vector.
    stop : (float, float) or float
        The parameter window ``(lo, hi)`` (a single float: from the start value to it);
        the continuation ends when it leaves the window.  A window past a bound of the
        parameter's domain (``stop=-0.1`` for ``B >= 0``) is cut there: the branch ends
        on the bound.
    steps : Steps
        Arclength steps, points at most, the corrector's tolerance and iterations, the
        finite-difference step (:class:`Steps`).
    direction : {1, -1}
        Initial direction in the parameter (from a start on a bound, into the domain:
        pointing out of it, the branch ends at once, on the bound).
    amplitude : bool
        Compute the response amplitudes of every orbit (one dense run each).
    refine : float, optional
        Narrow the interval of every stability change (not at a turning point) to this
        width by bisection: Newton shooting at the midpoint from the state interpolated
        between the two ends, the side kept by whether ``|mu|max < 1`` there
        (:func:`refine_stability_change`); the orbits at the two ends of the final
        interval join the branch as points.  Without it the value is interpolated
        between two branch points a step apart, which can be off by up to the step
        where the multipliers move non-smoothly (at grazing).  Every grazing (two
        neighbouring orbits with different impacts per period) is narrowed to this
        width too, by bisection on the impacts per period of orbits shot in between
        (:func:`refine_grazing`; no orbit joins the branch); without it its bracket is
        the two points.

    Returns
    -------
    Branch

    Raises
    ------
    ValueError
        Naming the argument.
    StartFailed
        A ValueError naming ``state0``: the shooting at the start failed (its reason in
        ``reason``).

    Examples
    --------
    >>> import vibimpact as vi
    >>> from vibimpact.analysis import Steps, continue_orbit
    >>> sys = vi.System(vi.DuffingParams(delta=0.1, alpha=1.0, beta=0.05, gamma=0.5,
    ...                                  omega=0.9))
    >>> br = continue_orbit(sys, [0.0, 0.0], param="omega", stop=(0.9, 1.0),
    ...                     steps=Steps(max_points=5), amplitude=False)
    >>> br.values.size
    5
    """
    system = as_system(system).resolved(**CONTINUATION_SOLVER)
    n = _v.count("n", n, 1)
    lam0 = system.param(param)
    window = _window(stop, lam0)
    if not isinstance(steps, Steps):
        raise ValueError(f"steps must be a vibimpact.analysis.Steps, got "
                         f"{type(steps).__name__}")
    if direction not in (1, -1):
        raise ValueError(f"direction must be 1 or -1, got {direction!r}")
    if refine is not None:
        refine = _v.positive("refine", refine)
    check_steps(steps, lam0, names=("steps.ds", "steps.ds_min", "steps.ds_max"))
    orb = shoot_periodic_orbit(system, state0, n, tol=steps.newton_tol)
    if not orb.converged:
        raise StartFailed(orb.reason)
    check_steps(steps, lam0, *orb.state, names=("steps.ds", "steps.ds_min",
                                                "steps.ds_max"))
    mdl = system.model
    contact = mdl.contact
    planar = contact is not None and len(contact.positions) == 2
    names = (tuple(f"{mdl.state_names[i]}_m" for i in contact.positions) + ("R_m",)
             if planar and contact is not None else tuple(f"{s}_m" for s in mdl.state_names[:2]))
    window, bounds = _limits(system, param, window, lam0, steps.ds_min)
    arc = _Arclength(system, param, n, window, steps, bounds)
    points = []  # (lambda, x, multipliers)

    def record(x, lam, M):
        points.append((lam, x.copy(), floquet_multipliers(M)))

    x, lam = orb.state.copy(), lam0
    m, Jg = arc.jac(x, lam)
    t = np.zeros(system.n_state + 1)
    t[-1] = float(direction)
    t = arc.tangent(Jg, t)
    record(x, lam, m.matrix)
    status = arc.march(x, lam, t, record, lambda: len(points))
    if refine is not None:
        points = _refined(system, param, n, points, refine, steps.newton_tol)
    vals = np.array([q[0] for q in points])
    mults = np.array([q[2] for q in points])
    stab = np.array([bool(np.abs(mu).max() < 1.0) for mu in mults])
    amp = {}
    if amplitude:
        amps = [_amplitude(system.with_param(param, q[0]), q[1], n, names) for q in points]
        amp = {k: np.array([a[k] for a in amps]) for k in names}
    states = np.array([q[1] for q in points])
    impacts = np.array([impacts_per_period(system.with_param(param, q[0]), q[1], n)
                        for q in points], dtype=np.int64)
    rows = [(i, kind, v, (v, v) if kind is BifurcationKind.TURNING_POINT else
             (float(vals[i - 1]), float(vals[i])),
             (int(impacts[i - 1]), int(impacts[min(i + 1, vals.size - 1)]))
             if kind is BifurcationKind.TURNING_POINT else
             (int(impacts[i - 1]), int(impacts[i])))
            for i, kind, v in _branch_events(vals, stab, mults)]
    rows += branch_grazings(system, param, n, vals, states, impacts, refine,
                            steps.newton_tol)
    rows.sort(key=lambda row: row[:3])
    return Branch(param, vals, states, mults, stab, amp, n,
                  tuple(row[:3] for row in rows), status, tuple(row[3] for row in rows),
                  impacts, tuple(row[4] for row in rows))


def _refined(system, param, n, points, tol, newton_tol):
    """``points`` with the two orbits of :func:`refine_stability_change` inserted at
    every stability change that is not a turning point (a refinement that fails inserts
    nothing)."""
    vals = np.array([q[0] for q in points])
    mults = np.array([q[2] for q in points])
    stab = np.array([bool(np.abs(mu).max() < 1.0) for mu in mults])
    out = list(points)
    for i, kind, _ in reversed(_branch_events(vals, stab, mults)):
        if kind is BifurcationKind.TURNING_POINT:
            continue
        try:
            ch = refine_stability_change(system, param, n, (vals[i - 1], vals[i]),
                                         (points[i - 1][1], points[i][1]), tol=tol,
                                         newton_tol=newton_tol)
        except ValueError:  # an end not shot again: the interpolated value stays
            continue
        new = [(float(v), x, mu) for v, x, mu in zip(ch.bracket, ch.states, ch.multipliers)
               if v not in (vals[i - 1], vals[i])]
        out[i:i] = new
    return out


def _branch_events(vals, stab, mults):
    """``(index, kind, value)`` of the turning points and stability changes of a branch
    (:attr:`Branch.bifurcations`)."""
    turns = [i for i in range(1, vals.size - 1)
             if (vals[i] - vals[i - 1]) * (vals[i + 1] - vals[i]) < 0]
    bif = [(i, BifurcationKind.TURNING_POINT, float(vals[i])) for i in turns]
    for i in range(1, vals.size):
        # a change between two points at one parameter value brackets nothing (steps
        # lost in rounding): not a bifurcation in the parameter
        if stab[i] != stab[i - 1] and vals[i] != vals[i - 1]:
            unstable = mults[i] if not stab[i] else mults[i - 1]
            kind = BifurcationKind.by_multiplier(critical_multiplier(unstable))
            if kind is BifurcationKind.FOLD and any(abs(i - j) <= 1 for j in turns):
                continue  # the turning point itself is listed
            bif.append((i, kind, multiplier_crossing(vals[i - 1], vals[i], mults[i - 1], mults[i])))
    bif.sort()
    return bif
