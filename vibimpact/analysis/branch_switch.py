"""Branch switching at a period doubling: follow the period-``2n`` orbit born there.

At a period doubling of a period-``n`` orbit ``x*`` (parameter ``lambda*``) a multiplier
of ``M_n = D P^n(x*)`` is ``-1``, with eigenvector ``v``.  For the doubled map ``P^{2n}``
the same point is a pitchfork: ``M_{2n} = M_n^2`` has the multiplier ``+1`` with the same
``v``, and the branch of period-``2n`` orbits leaves ``(x*, lambda*)`` tangent to
``(v, 0)`` (Kuznetsov 2004, sec. 4.4; Seydel 2010, sec. 5.6 and 7.6).
:func:`switch_branch` takes one predictor step ``x* + h v`` along that tangent and
corrects it by Newton on ``P^{2n}(x; lambda) - x = 0`` in the hyperplane through the
predictor orthogonal to ``v`` (the parameter free: the new branch bends to either side of
``lambda*``, supercritical or subcritical), checks that the orbit found has minimal
period ``2n`` (not the period-``n`` orbit, a fixed point of ``P^{2n}`` too), and continues
it with :func:`~vibimpact.analysis.continue_orbit` (``n = 2n``), away from ``lambda*``.
The returned branch starts with the period-doubling point itself (the degenerate
period-``2n`` orbit ``x*``, whose largest multiplier is ``+1``).

References
----------
.. [1] Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., Springer
   (2004), sec. 4.4 (flip bifurcation) and 10.2 (branch switching).
.. [2] R. Seydel, *Practical Bifurcation and Stability Analysis*, 3rd ed., Springer
   (2010), sec. 5.6 (branch switching) and 7.6 (period doubling of periodic orbits).
.. [3] E. J. Doedel, H. B. Keller, J. P. Kernevez, "Numerical analysis and control of
   bifurcation problems (II)", Int. J. Bifurcation Chaos 1 (1991) 745-772.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, cast

import dataclasses

import numpy as np

from ..base import _validate as _v
from ..base.bifurcation_kinds import BifurcationKind
from ..core.run import Status
from ..core.system import as_system
from .bifurcation import CONTINUATION_SOLVER
from .._kernel.boundary import solve
from .continuation import Branch, Steps, continue_orbit
from .shooting import floquet_multipliers, shoot_periodic_orbit
from .stability_change import impacts_per_period, refine_stability_change

if TYPE_CHECKING:  # names of the annotations only
    from ..core.system import System

__all__ = ["switch_branch", "period_doubling_point"]


def period_doubling_point(system: System, branch: Branch, index: int | None = None, *,
                          tol: float = 1e-9) -> tuple[float, np.ndarray, np.ndarray]:
    """The period-doubling point of ``branch`` and its critical eigenvector.

    Parameters
    ----------
    system : System
        The system ``branch`` was continued in.
    branch : Branch
        From :func:`~vibimpact.analysis.continue_orbit`.
    index : int, optional
        Which entry of ``branch.bifurcations`` (a period doubling); by default the first
        period doubling.
    tol : float
        Its bracket is narrowed to this width first (:func:`refine_stability_change`).

    Returns
    -------
    (float, ndarray shape (d,), ndarray shape (d,))
        ``lambda*`` (``|mu|max - 1`` interpolated to 0 in the bracket), ``x*`` (the
        bracket's orbits interpolated to it) and ``v``: the unit eigenvector of
        ``M_n(x*)`` of the real multiplier nearest ``-1``.

    Raises
    ------
    ValueError
        Naming ``branch`` (no period doubling) or ``index`` (not one).
    """
    system = as_system(system).resolved(**CONTINUATION_SOLVER)
    if not isinstance(branch, Branch):
        raise _v.WrongType(f"branch must be a vibimpact.analysis.Branch, got "
                           f"{type(branch).__name__}")
    pds = [k for k, b in enumerate(branch.bifurcations)
           if b[1] is BifurcationKind.PERIOD_DOUBLING]
    if index is None:
        if not pds:
            raise ValueError("branch: it holds no period doubling")
        index = pds[0]
    index = _v.count("index", index, 0, len(branch.bifurcations) - 1) \
        if branch.bifurcations else _v.count("index", index, 0, -1)
    if index not in pds:
        raise ValueError(f"index: bifurcation {index} of the branch is a "
                         f"{branch.bifurcations[index][1].value}, not a period doubling")
    i = branch.bifurcations[index][0]
    vals, states = np.asarray(branch.values), np.asarray(branch.states)
    xs: tuple | np.ndarray  # the bracket's two states: a pair, then refined ones
    lo, hi, xs = float(vals[i - 1]), float(vals[i]), (states[i - 1], states[i])
    try:
        ch = refine_stability_change(system, branch.param, branch.n, (lo, hi), xs,
                                     tol=tol)
        (lo, hi), xs, lam = ch.bracket, ch.states, ch.value
    except ValueError:  # the branch's two points stay the bracket
        lam = branch.bifurcations[index][2]
    w = (lam - lo) / (hi - lo) if hi != lo else 0.5
    x = xs[0] + w * (xs[1] - xs[0])
    m = system.with_param(branch.param, lam).monodromy(x, branch.n)
    if m.status is not Status.OK:
        raise ValueError(f"branch: the orbit at the period doubling cannot be integrated "
                         f"({m.reason})")
    mu, vec = np.linalg.eig(m.matrix)
    k = int(np.argmin(np.abs(mu + 1.0)))
    v = np.real(vec[:, k])
    return float(lam), np.asarray(x, dtype=float), v / np.linalg.norm(v)


@_v.checks_flags
def switch_branch(system: System, branch: Branch, index: int | None = None, *,
                  stop: float | tuple | None = None, h: float | None = None,
                  steps: Steps = Steps(), refine: float | None = None,
                  amplitude: bool = True) -> Branch:
    """Follow the period-``2n`` orbit born at a period doubling of a period-``n`` branch.

    Parameters
    ----------
    system : System
        The system ``branch`` was continued in (its other parameters).
    branch : Branch
        A period-``n`` branch from :func:`~vibimpact.analysis.continue_orbit` holding a
        period doubling.
    index : int, optional
        Which entry of ``branch.bifurcations``; by default the first period doubling.
    stop : float or (float, float), optional
        The parameter window of the doubled branch (as ``continue_orbit``'s); by default
        the span of ``branch``.
    h : float, optional
        Predictor step along the critical eigenvector; by default ``1e-2 * max(1,
        |x*|)``.  Tried again at ``h / 10``, ``h / 100`` and ``3 h`` when the corrector
        fails or lands on a period-``n`` orbit (the parent branch crosses the corrector's
        hyperplane too; a doubled branch that soon meets a grazing is short).
    steps, refine, amplitude
        As :func:`~vibimpact.analysis.continue_orbit`'s.

    Returns
    -------
    Branch
        ``n`` twice the parent's; its first point is the period-doubling point ``(x*,
        lambda*)`` with the multipliers of ``M_n(x*)^2`` (the largest ``+1`` up to the
        location's accuracy; ``stable`` as the next point's, as the orbit is neutral
        there), the rest the continued period-``2n`` orbits (minimal period ``2n``),
        moving away from ``lambda*``; ``bifurcations`` indices count that first point.

    Raises
    ------
    ValueError
        Naming ``branch`` or ``index`` (see :func:`period_doubling_point`), ``h`` when no
        period-``2n`` orbit is found from any predictor.

    Examples
    --------
    >>> import vibimpact as vi
    >>> from vibimpact.analysis import Steps, continue_orbit, switch_branch
    >>> s = vi.System(vi.DuffingParams(delta=0.3, alpha=-1.0, beta=1.0, gamma=0.25,
    ...                                omega=1.2))
    >>> x = s.simulate(periods=1, transient=300, state0=[1.0, 0.0]).final_state
    >>> p1 = continue_orbit(s, x, param="gamma", stop=0.28, refine=1e-7, amplitude=False)
    >>> p2 = switch_branch(s, p1, stop=0.28, steps=Steps(max_points=4), amplitude=False)
    >>> p2.n, round(float(p2.values[0]), 5)
    (2, 0.26558)
    """
    system = as_system(system).resolved(**CONTINUATION_SOLVER)
    lam, x, v = period_doubling_point(system, branch, index)
    n2 = 2 * branch.n
    param = branch.param
    vals = np.asarray(branch.values)
    if stop is None:
        stop = (float(vals.min()), float(vals.max()))
    if not isinstance(steps, Steps):
        raise ValueError(f"steps must be a vibimpact.analysis.Steps, got "
                         f"{type(steps).__name__}")
    scale = max(1.0, float(np.abs(x).max()))
    h = 1e-2 * scale if h is None else _v.positive("h", h)
    # np.ndim tells a number from a (lo, hi) pair, which mypy cannot follow: the casts
    lo, hi = (min(lam, cast(float, stop)), max(lam, cast(float, stop))) \
        if np.ndim(stop) == 0 else tuple(sorted(float(s) for s in cast(tuple, stop)))
    start = None
    tries = (h, 0.1 * h, 0.01 * h, 3.0 * h)
    for hh in tries:
        u = _correct(system, param, n2, x + hh * v, lam, v, steps)
        if u is None:
            continue
        orb = shoot_periodic_orbit(system.with_param(param, u[1]), u[0], n2,
                                   tol=steps.newton_tol)
        if orb.converged and orb.minimal_period == n2:
            start = (float(u[1]), orb.state)
            break
    if start is None:
        raise ValueError(f"h: no period-{n2} orbit found from x* + h v at {param} = "
                         f"{lam:.8g} (h = {', '.join(f'{t:g}' for t in tries)})")
    lam2, x2 = start
    direction = 1 if lam2 >= lam else -1
    child = continue_orbit(system.with_param(param, lam2), x2, n2, param=param,
                           stop=(min(lo, lam), max(hi, lam)),
                           steps=steps, direction=direction, amplitude=amplitude,
                           refine=refine)
    return _with_first(system, child, lam, x, param, branch)


def _correct(system, param, n, x_pred, lam, v, steps):
    """Newton on ``P^n(x; lambda) - x = 0``, ``v . (x - x_pred) = 0`` from ``(x_pred,
    lam)``; ``(x, lambda)`` or None.  ``G_lambda`` by central differences."""
    d = x_pred.size
    x, lam0 = x_pred.copy(), lam
    dom = system.param_domain(param)
    for it in range(steps.max_newton):
        if lam not in dom:
            return None
        q = system.with_param(param, lam)
        m = q.monodromy(x, n)
        if m.status is not Status.OK:
            return None
        G = m.end - m.start
        if it > 0 and np.abs(G).max() <= steps.newton_tol * max(1.0, np.abs(x).max()):
            return x, lam
        hl = steps.fd_step * max(1.0, abs(lam))
        ends = [system.with_param(param, lam + s * hl).simulate(periods=n, state0=x)
                for s in (1.0, -1.0)]
        if any(r.status is not Status.OK for r in ends) or \
                not (lam - hl in dom and lam + hl in dom):
            return None
        J = np.zeros((d + 1, d + 1))
        J[:d, :d] = m.matrix - np.eye(d)
        J[:d, d] = (ends[0].final_state - ends[1].final_state) / (2.0 * hl)
        J[d, :d] = v
        du, ok = solve(J, -np.append(G, v @ (x - x_pred)))
        if not ok or not np.all(np.isfinite(du)):
            return None
        x, lam = x + du[:d], lam + float(du[d])
        if abs(lam - lam0) > 10.0 * steps.ds_max:  # wandered off
            return None
    return None


def _parent_amplitude(parent, lam, key):
    """The parent branch's amplitude ``key`` at ``lam``, interpolated between its two
    points nearest ``lam`` (NaN where it has none)."""
    if key not in parent.amplitude:
        return np.nan
    pv = np.asarray(parent.values, dtype=float)
    j = np.argsort(np.abs(pv - lam))[:2]
    j = j[np.argsort(pv[j])]
    return float(np.interp(lam, pv[j], np.asarray(parent.amplitude[key])[j]))


def _with_first(system, child, lam, x, param, parent):
    """``child`` with the period-doubling point ``(x, lam)`` as its first point (its
    amplitudes those of the ``parent`` orbit there, interpolated)."""
    at = system.with_param(param, lam)
    m = at.monodromy(x, child.n // 2)
    mu = floquet_multipliers(m.matrix @ m.matrix)
    amp = {k: np.concatenate([[_parent_amplitude(parent, lam, k)], child.amplitude[k]])
           for k in child.amplitude}
    imp = impacts_per_period(at, x, child.n)
    shifted = tuple((i + 1, kind, value) for i, kind, value in child.bifurcations)
    return dataclasses.replace(
        child, values=np.concatenate([[lam], child.values]),
        states=np.vstack([x[None, :], child.states]),
        multipliers=np.vstack([mu[None, :], child.multipliers]),
        stable=np.concatenate([child.stable[:1], child.stable]),  # neutral: as its side
        amplitude=amp, bifurcations=shifted,
        impacts_per_period=np.concatenate([[imp], child.impacts_per_period]))
