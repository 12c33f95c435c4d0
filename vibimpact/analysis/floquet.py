"""Exact Lyapunov (Floquet) exponents of a periodic orbit.

On a periodic orbit the Lyapunov exponents are the Floquet exponents ``ln|mu_i| / (n T)``
of the monodromy matrix (Parker & Chua 1989, ch. 6): exact, where a finite-time QR
estimate splits a complex pair of multipliers.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..core.run import Status
from ..base import _validate as _v
from ..core.system import as_system
from .exponents import KIND_FLOW, KIND_FLOW_PHASE, LyapunovResult
from .shooting import floquet_exponents, floquet_multipliers, shoot_periodic_orbit

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

    from ..core.system import System

__all__ = ["floquet_lyapunov"]


@_v.checks_flags
def floquet_lyapunov(system: System, state0: ArrayLike, n: int = 1, *,
                     n_exponents: int | None = None, include_phase: bool = False,
                     tol: float = 1e-9, max_iter: int = 20) -> LyapunovResult:
    """Lyapunov exponents of a periodic orbit: its Floquet exponents ``ln|mu| / (n T)``.

    The period-``n`` orbit through (near) ``state0`` is found by Newton shooting
    (:func:`~vibimpact.analysis.shooting.shoot_periodic_orbit`: variational equations with
    saltation matrices, so impacting orbits too).  The tangent map over ``k`` orbit
    periods is ``M^k``, whose singular values grow like ``|mu_i|^k``: ``ln|mu_i| / (n T)``
    are exactly the limits of :func:`lyapunov_spectrum`'s QR average (Parker & Chua 1989,
    ch. 4; Leine & Nijmeijer 2004, ch. 7), a complex pair two equal exponents.

    Parameters
    ----------
    system : System
        Solver settings as in :func:`~vibimpact.analysis.shoot_periodic_orbit` (defaults
        DOP853, ``rtol = 1e-10``, ``atol = 1e-12``).
    state0 : array_like, shape (d,)
        A point of the orbit at the start of a forcing period, or a guess close to one.
    n : int
        Period in forcing periods (a multiple of the minimal one gives the same).
    n_exponents, include_phase
        As in :func:`lyapunov_spectrum`.
    tol, max_iter
        Newton's relative residual tolerance and iteration limit.

    Returns
    -------
    LyapunovResult
        ``exponents`` shape (m,) per unit ``tau``, descending, of the orbit whether stable
        or not; ``stderr`` shape (m,) their numerical error, estimated as their change
        when the monodromy is recomputed at 100x looser ``rtol`` and ``atol`` (an upper
        estimate: the integration error dominates Newton's residual); ``floquet_n`` the
        minimal period; ``method`` "floquet"; ``periods`` 0.
        If Newton fails: NaN exponents, ``status`` FAILED (or DIVERGED), ``reason``.

    Examples
    --------
    >>> import vibimpact as vi
    >>> from vibimpact.analysis import floquet_lyapunov
    >>> p = vi.DuffingParams(delta=0.2, alpha=1.0, beta=0.0, gamma=0.0, omega=1.0)
    >>> res = floquet_lyapunov(vi.System(p), [0.0, 0.0])  # x'' + 0.2 x' + x = 0
    >>> bool(abs(res.exponents - (-0.1)).max() < 1e-8)  # -delta/2 twice
    True
    """
    system = as_system(system).resolved(rtol=1e-10)
    T = system.period
    d = system.n_state
    m = d if n_exponents is None else _v.count("n_exponents", n_exponents, 1)
    if m > d:
        raise ValueError(f"n_exponents must be <= {d}, got {n_exponents}")
    n = _v.count("n", n, 1)
    orb = shoot_periodic_orbit(system, state0, n, tol=tol, max_iter=max_iter)
    if orb.converged and orb.minimal_period < n:  # the shorter the map, the more accurate
        orb = shoot_periodic_orbit(system, orb.state, orb.minimal_period, tol=tol,
                                   max_iter=max_iter)
    kind = KIND_FLOW_PHASE if include_phase else KIND_FLOW
    k = m + bool(include_phase)
    if orb.status is not Status.OK or not orb.converged:
        st = orb.status if orb.status is not Status.OK else Status.FAILED
        return LyapunovResult(np.full(k, np.nan), np.full(k, np.nan), T, 0, False,
                              "floquet", kind, st, orb.reason or "shooting failed",
                              qr_exponents=np.full(k, np.nan))
    lam = orb.exponents[:m]
    assert system.rtol is not None and system.atol is not None  # resolved() above
    loose = system.with_solver(rtol=100 * system.rtol, atol=100 * system.atol).monodromy(
        orb.state, orb.n)
    err = np.full(m, np.inf)
    if loose.status is Status.OK and np.all(np.isfinite(loose.matrix)):
        lam_loose = floquet_exponents(floquet_multipliers(loose), orb.period)[:m]
        with np.errstate(invalid="ignore"):
            err = np.abs(lam_loose - lam)
        # a multiplier that is 0 at both tolerances (a direction a sliding surface
        # annihilates: a stuck ring, a rolling contact) is -inf exactly, with no error
        err[np.isneginf(lam) & np.isneginf(lam_loose)] = 0.0
    if include_phase:
        idx = np.argsort(-np.append(lam, 0.0), kind="stable")
        lam, err = np.append(lam, 0.0)[idx], np.append(err, 0.0)[idx]
    return LyapunovResult(lam, err, T, 0, True, "floquet", kind, Status.OK, "",
                          np.zeros((0, k)), int(orb.minimal_period), np.full(k, np.nan))
