"""Periodic orbits of the stroboscopic map by Newton shooting, monodromy matrices and
Floquet multipliers of the forced, piecewise-smooth models.

A period-``n`` orbit of a model forced with period ``T = 2 pi / eta`` is a fixed point of
the ``n``-fold stroboscopic map ``P^n``: ``P^n(x) = x``.  :func:`shoot_periodic_orbit`
solves it by Newton's method (single shooting; Seydel 2010, ch. 7; Parker & Chua 1989,
ch. 5),

    (M(x_k) - I) dx = -(P^n(x_k) - x_k),        x_{k+1} = x_k + dx,

with the *monodromy matrix* ``M = D P^n`` from the variational equations.  Inside a mode
the tangent vectors obey ``v' = J v``; at every switch (contact entry and exit, slip to
stick) they are mapped by the saltation matrix (Aizerman & Gantmacher 1958; Leine &
Nijmeijer 2004, sec. 3.5 and ch. 7; :mod:`vibimpact._kernel.variational`), so ``M`` is
the exact linearisation of the non-smooth flow (away from grazing, where the saltation
matrix is unbounded).  The eigenvalues of ``M`` are the Floquet multipliers ``mu``: the
orbit is asymptotically stable when every ``|mu| < 1``, and the way a multiplier leaves
the unit circle names the bifurcation (Kuznetsov 2004, sec. 4.5-4.7; Seydel 2010,
sec. 7.4): through ``-1`` a period doubling, through ``+1`` a fold (saddle-node), as a
complex pair a Neimark--Sacker bifurcation.  ``ln|mu| / (n T)`` are the orbit's Lyapunov
exponents per unit ``tau`` (the variational exponents of
:func:`vibimpact.analysis.lyapunov_spectrum` on a periodic attractor).

References
----------
.. [1] R. I. Leine, H. Nijmeijer, *Dynamics and Bifurcations of Non-Smooth Mechanical
   Systems*, Springer (2004), sec. 3.5 (saltation matrix), ch. 7 (Floquet multipliers
   of non-smooth periodic solutions).
.. [2] R. Seydel, *Practical Bifurcation and Stability Analysis*, 3rd ed., Springer
   (2010), ch. 7 (shooting, monodromy matrix, multipliers).
.. [3] Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., Springer
   (2004), ch. 4 (bifurcations of fixed points of maps).
.. [4] T. S. Parker, L. O. Chua, *Practical Numerical Algorithms for Chaotic Systems*,
   Springer (1989), ch. 5 (shooting for forced systems).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import math
from dataclasses import dataclass

import numpy as np

from ..core.run import Status
from ..base import _validate as _v
from ..core.system import Monodromy, as_system
from .._kernel.boundary import eigvals, solve

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

    from ..core.system import System

__all__ = ["Monodromy", "PeriodicOrbit", "monodromy", "floquet_multipliers",
           "floquet_exponents", "critical_multiplier", "shoot_periodic_orbit",
           "SHOOTING_SOLVER"]

#: solver defaults of shooting (the rest as :func:`vibimpact.simulate`): the tangent
#: vectors share the step-size control, so tighter than a plain run's
SHOOTING_SOLVER = dict(rtol=1e-10)


@dataclass(frozen=True)
class PeriodicOrbit:
    """A period-``n`` orbit found by shooting, with its Floquet multipliers.

    Attributes
    ----------
    state : ndarray, shape (d,)
        A point of the orbit at the start of a forcing period (``tau = 0 mod T``).
    n : int
        Forcing periods shot over.
    minimal_period : int
        The orbit's own period (a divisor of ``n``; smaller than ``n`` when the iteration
        found an orbit of lower period, e.g. a period-2 orbit collapsed onto the period-1
        orbit at a period doubling).
    period : float
        ``n T`` in units of ``tau``.
    cycle : ndarray, shape (n, d)
        The stroboscopic points ``x, P(x), ..., P^{n-1}(x)``.
    monodromy : ndarray, shape (d, d)
    multipliers : ndarray of complex, shape (d,)
        Eigenvalues of ``monodromy``, by decreasing modulus.
    converged : bool
        The residual ``|P^n(x) - x|`` met the tolerance.
    iterations : int
        Newton iterations (monodromy evaluations).
    residual : float
        ``max |P^n(x) - x|`` at ``state``.
    status : Status
    reason : str
    """

    state: np.ndarray
    n: int
    minimal_period: int
    period: float
    cycle: np.ndarray
    monodromy: np.ndarray
    multipliers: np.ndarray
    converged: bool
    iterations: int
    residual: float
    status: Status = Status.OK
    reason: str = ""

    @property
    def abs_max(self):
        """The largest ``|mu|``."""
        return float(np.abs(self.multipliers).max()) if self.multipliers.size else math.nan

    @property
    def stable(self):
        """Converged and every multiplier inside the unit circle."""
        return bool(self.converged and self.abs_max < 1.0)

    @property
    def exponents(self):
        """Floquet (Lyapunov) exponents ``ln|mu| / (n T)`` per unit ``tau``, descending."""
        return floquet_exponents(self.multipliers, self.period)

    @property
    def critical(self):
        """Kind of the largest multiplier: see :func:`critical_multiplier`."""
        return critical_multiplier(self.multipliers)


def floquet_multipliers(M: ArrayLike | Monodromy | PeriodicOrbit) -> np.ndarray:
    """Eigenvalues of a monodromy matrix, by decreasing modulus.

    Parameters
    ----------
    M : array_like, shape (d, d), or Monodromy or PeriodicOrbit

    Returns
    -------
    ndarray of complex, shape (d,)
        Sorted by decreasing ``|mu|``; of a complex-conjugate pair, the one with positive
        imaginary part first.

    Raises
    ------
    ValueError
        Naming ``M``: not square or not finite.

    Examples
    --------
    >>> floquet_multipliers([[0.0, 1.0], [-0.25, 0.0]])
    array([0.+0.5j, 0.-0.5j])
    """
    if isinstance(M, Monodromy):
        M = M.matrix
    elif isinstance(M, PeriodicOrbit):
        M = M.monodromy
    A = _v.numeric("M", M, "a real square matrix")
    if A.ndim != 2 or A.shape[0] != A.shape[1] or A.shape[0] == 0:
        raise ValueError(f"M must be a square matrix, got shape {A.shape}")
    if not np.all(np.isfinite(A)):
        raise ValueError("M must be finite")
    mu = eigvals(np.ascontiguousarray(A))
    order = np.lexsort((-mu.imag, -mu.real, -np.round(np.abs(mu), 12)))
    return mu[order]


def floquet_exponents(multipliers: ArrayLike, period: float) -> np.ndarray:
    """``ln|mu| / period``, descending: Lyapunov exponents of a periodic orbit.

    A multiplier within :data:`ZERO_MULTIPLIER` of the largest one's modulus (or of 1)
    is zero to the rounding of the monodromy matrix -- a direction that a sliding
    surface attracting in finite time annihilates (a rolling contact, a stuck ring) --
    and its exponent is ``-inf``, not a number that rounding sets.

    Parameters
    ----------
    multipliers : array_like of complex
    period : float
        The orbit's period in units of time (``n T``).
    """
    mu = np.abs(np.asarray(multipliers, dtype=complex).reshape(-1))
    period = _v.positive("period", period)
    scale = max(1.0, float(mu.max())) if mu.size else 1.0
    with np.errstate(divide="ignore"):
        lam = np.where(mu <= ZERO_MULTIPLIER * scale, -np.inf, np.log(mu)) / period
    return np.sort(lam)[::-1]


#: relative modulus below which a Floquet multiplier is zero to rounding (about 500
#: units in the last place of the monodromy's entries of order 1)
ZERO_MULTIPLIER = 1e-13


def critical_multiplier(multipliers, tol_imag=1e-6):
    """Kind of the multiplier of largest modulus (where it would leave the unit circle).

    Returns
    -------
    str
        ``"-1"`` (real negative: period doubling), ``"+1"`` (real positive: fold or
        symmetry breaking) or ``"complex"`` (a complex pair: Neimark--Sacker);
        ``""`` for no multipliers.
    """
    mu = np.asarray(multipliers, dtype=complex).reshape(-1)
    if mu.size == 0 or not np.all(np.isfinite(mu)):
        return ""
    top = mu[int(np.argmax(np.abs(mu)))]
    if abs(top.imag) > tol_imag * max(1.0, abs(top)):
        return "complex"
    return "-1" if top.real < 0.0 else "+1"


def monodromy(system: System, state0: ArrayLike, n: int = 1, *,
              tangent_tol: float = 1.0) -> Monodromy:
    """Jacobian of the ``n``-fold stroboscopic map by the variational equations:
    :meth:`vibimpact.System.monodromy`.

    The state and ``d`` tangent vectors (the columns of the identity) are integrated
    together over ``n`` forcing periods from ``tau = 0``; at every switching event the
    tangent vectors are mapped by the saltation matrix (Leine & Nijmeijer 2004, sec. 3.5),
    so the result is the Jacobian of the non-smooth map, not of a smoothed one.  One call
    costs about five state-only integrations.

    Parameters
    ----------
    system : System
        Solver defaults DOP853 (or DP5: adaptive methods only), ``rtol = 1e-10``,
        ``atol = 1e-12``, ``max_step = T / 4`` (tighter than a plain run's: the tangent
        vectors share the step-size control).
    state0 : array_like, shape (d,)
        State at the start of a forcing period.
    n : int
        Forcing periods, ``>= 1``.
    tangent_tol : float
        The tangent vectors' local errors are tested against ``tangent_tol`` times the
        tolerances (default 1: Newton's steps and multipliers near the unit circle need
        the matrix itself to the tolerance); see
        :func:`vibimpact.analysis.lyapunov_spectrum`.

    Returns
    -------
    Monodromy
        ``status`` DIVERGED/FAILED with a NaN matrix when the integration stopped.

    Raises
    ------
    ValueError
        Naming the argument.

    Examples
    --------
    >>> import vibimpact as vi
    >>> from vibimpact.analysis import monodromy
    >>> m = monodromy(vi.System(vi.DuffingParams()), [0.0, 0.0])
    >>> m.matrix.shape
    (2, 2)
    """
    return as_system(system).monodromy(state0, n, tangent_tol=tangent_tol)


def _cycle(system, x, n):
    """Stroboscopic points of ``n`` periods from ``x`` (rows 0..n), or None."""
    run = system.simulate(periods=n, state0=x, solver=system.settings(**SHOOTING_SOLVER))
    return run.strobe if run.status is Status.OK else None


def _minimal_period(strobe, n, tol):
    scale = max(1.0, float(np.abs(strobe).max()))
    for k in range(1, n):
        if n % k == 0 and np.max(np.abs(strobe[k] - strobe[0])) <= tol * scale:
            return k
    return n


@_v.checks_flags
def shoot_periodic_orbit(system: System, state0: ArrayLike, n: int = 1, *,
                         tol: float = 1e-9, max_iter: int = 20,
                         damping: bool = True) -> PeriodicOrbit:
    """A period-``n`` orbit by Newton shooting on the stroboscopic map, with its Floquet
    multipliers.

    Solves ``P^n(x) = x`` by Newton's method with the monodromy matrix of
    :func:`monodromy` (variational equations and saltation matrices, so the iteration
    converges quadratically also on impacting orbits).  A step that does not reduce the
    residual is halved (up to six times) when ``damping`` is on.  The multipliers are the
    eigenvalues of the monodromy matrix at the converged point.

    Parameters
    ----------
    system : System
        Solver settings as in :func:`monodromy` (defaults DOP853, ``rtol = 1e-10``,
        ``atol = 1e-12``), also for the run that gives the orbit's cycle.
    state0 : array_like, shape (d,)
        Initial guess at the start of a forcing period: e.g. a stroboscopic point of a
        sweep's detected orbit (``final_state``).
    n : int
        Period in forcing periods, ``>= 1``.
    tol : float
        Converged when ``max |P^n(x) - x| <= tol * max(1, max |x|)``.
    max_iter : int
        Newton iterations at most.
    damping : bool
        Halve steps that increase the residual.

    Returns
    -------
    PeriodicOrbit
        ``converged`` False (and the last iterate) when Newton failed: no orbit near the
        guess, a singular ``M - I`` (at a fold), or an integration that stopped.

    Raises
    ------
    ValueError
        Naming the argument.

    Notes
    -----
    The forcing fixes the phase, so no phase condition is needed (unlike autonomous
    shooting).  Near a fold ``M - I`` is nearly singular and convergence slows; near
    grazing the map is non-smooth (square-root or 3/2-power singularities) and the
    iteration may stall.  See the module references.

    Examples
    --------
    >>> import vibimpact as vi
    >>> from vibimpact.analysis import shoot_periodic_orbit
    >>> orb = shoot_periodic_orbit(vi.System(vi.DuffingParams(gamma=0.2)), [1.0, 0.0])
    >>> orb.converged, orb.stable
    (True, True)
    """
    system = as_system(system)
    d = system.n_state
    x = _v.state("state0", state0, d)
    n = _v.count("n", n, 1)
    tol = _v.positive("tol", tol)
    max_iter = _v.count("max_iter", max_iter, 1)

    def scale(v):
        return max(1.0, float(np.abs(v).max()))

    m = system.monodromy(x, n)
    it = 1
    converged = False
    while True:
        if m.status is not Status.OK:
            break
        F = m.residual
        res = float(np.abs(F).max())
        if res <= tol * scale(x):
            converged = True
            break
        if it >= max_iter:
            break
        A = m.matrix - np.eye(d)
        dx, ok = solve(A, -F)
        if not ok:
            break
        if not np.all(np.isfinite(dx)):
            break
        lam = 1.0
        accepted = None
        for _ in range(7 if damping else 1):
            trial = system.monodromy(x + lam * dx, n)
            it += 1
            if trial.status is Status.OK and (
                    not damping or float(np.abs(trial.residual).max()) < res):
                accepted = trial
                break
            lam *= 0.5
            if it >= max_iter:
                break
        if accepted is None:
            break
        m = accepted
        x = m.start
    period = m.period
    if m.status is not Status.OK:
        nan = np.full(d, np.nan)
        return PeriodicOrbit(x, n, n, period, np.full((n, d), np.nan),
                             np.full((d, d), np.nan), nan.astype(complex), False, it,
                             math.nan, m.status, m.reason)
    res = float(np.abs(m.residual).max())
    mu = floquet_multipliers(m.matrix)
    strobe = _cycle(system, x, n)
    if strobe is None:
        cycle = np.full((n, d), np.nan)
        nmin = n
    else:
        cycle = strobe[:n].copy()
        nmin = _minimal_period(strobe, n, max(1e3 * tol, 1e-7)) if converged else n
    reason = "" if converged else (f"Newton did not converge in {it} iterations "
                                   f"(residual {res:.3g})")
    return PeriodicOrbit(x.copy(), n, nmin, period, cycle, m.matrix, mu, converged, it, res,
                         Status.OK, reason)
