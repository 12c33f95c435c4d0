"""Multi-start Newton shooting for the periodic orbits of the stroboscopic map:
:func:`hunt_orbits`.

A period-``n`` orbit of a model forced with period ``T`` is a fixed point of ``P^n``, the
``n``-fold stroboscopic map; :func:`vibimpact.analysis.shoot_periodic_orbit` finds one by
Newton's method from a guess, stable or not, with its Floquet multipliers (variational
equations with saltation matrices; Leine & Nijmeijer 2004, ch. 7).  The hunt runs it from
many guesses: the close returns of short trajectories from the user's seeds and from
random states (:mod:`vibimpact.orbits.seeds`), for every period asked.  What converges is
deduplicated (:func:`same_orbit`), described (impacts, arcs, multipliers:
:func:`vibimpact.orbits.found.describe_orbit`) and, unless asked not to, continued in the
forcing frequency to the interval where it exists and the one where it is stable
(:func:`vibimpact.orbits.orbit_extent`).

References
----------
.. [1] T. S. Parker, L. O. Chua, *Practical Numerical Algorithms for Chaotic Systems*,
   Springer (1989), ch. 5 (shooting for forced systems).
.. [2] D. Auerbach et al., "Exploring chaotic motion through periodic orbits", Phys. Rev.
   Lett. 58 (1987) 2387 (close returns as guesses of unstable periodic orbits).
.. [3] R. I. Leine, H. Nijmeijer, *Dynamics and Bifurcations of Non-Smooth Mechanical
   Systems*, Springer (2004), ch. 7.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

import time
from dataclasses import replace

import numpy as np

from ..base import _limits
from ..base import _validate as _v
from ..analysis.shooting import shoot_periodic_orbit
from ..census.reach import failed_integration
from ..sweeps.sweep import check_frequency
from ..core.run import Status
from ..core.system import to_system
from .found import OrbitHunt, describe_orbit
from .seeds import close_returns, random_seeds, user_seeds

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Callable, Iterable

    from numpy.typing import ArrayLike

    from ..analysis import Steps
    from ..engine.execution import Execution
    from ..models.params import DuffingParams, Params
    from ..core.system import System

__all__ = ["hunt_orbits", "same_orbit", "DEFAULT_RANDOM", "MAX_PERIOD"]

#: random seeds of a hunt by default
DEFAULT_RANDOM = 48
#: the longest period a hunt shoots for
MAX_PERIOD = 64
#: a Newton start this close (relative) to a point of an orbit already found whose period
#: divides ``n`` is not shot again
KNOWN_TOL = 1e-3
#: two converged orbits are the same when one's point lies this close (relative) to a
#: point of the other's cycle
SAME_TOL = 1e-6
#: Newton iterations of the first try; a start whose residual has not fallen below
#: PROMISING (relative) by then is given up
FIRST_TRY = 5
PROMISING = 1e-2


def same_orbit(a: np.ndarray, b: np.ndarray, tol: float = SAME_TOL) -> bool:
    """Whether two cycles of stroboscopic points are one orbit met at two phases.

    Parameters
    ----------
    a, b : ndarray, shape (m, d) and (m', d)
        Cycles of minimal periods ``m`` and ``m'``.
    tol : float
        Relative distance (to ``max(1, max |x|)``) within which two points are one.

    Returns
    -------
    bool
        ``m == m'`` and ``a[0]`` lies within ``tol`` of a point of ``b``.
    """
    if a.shape != b.shape:
        return False
    scale = max(1.0, float(np.abs(b).max()))
    return bool(np.min(np.abs(b - a[0]).max(axis=1)) <= tol * scale)


def _periods(periods: Any) -> tuple[int, ...]:
    """``periods`` as a sorted tuple of distinct ints in ``[1, MAX_PERIOD]``."""
    if isinstance(periods, (int, np.integer)) and not isinstance(periods, bool):
        periods = [periods]
    try:
        items = list(periods)
    except TypeError:
        raise _v.WrongType(f"periods must be an int or a sequence of ints, got "
                           f"{type(periods).__name__} {periods!r}"[:200]) from None
    if not items:
        raise ValueError("periods must name at least one period")
    out = sorted({_v.count("periods", p, 1, MAX_PERIOD) for p in items})
    return tuple(out)


class _Hunter:
    """The state of one hunt: orbits found so far and the counts."""

    def __init__(self, system, settings):
        self.system, self.st = system, settings
        self.orbits = []
        self.counts = dict(shots=0, converged=0, duplicates=0, known=0, failed=0,
                           diverged_seeds=0, failed_seeds=0, failed_shots=0)
        self.failure = ""

    def stopped(self, status, reason, what):
        """Count an integration that stopped with ``status``: a seed's trajectory
        (``what`` "seeds") or a Newton run's ("shots"); a diverged seed (an escape of the
        motion) apart from a solver failure, whose first reason is kept."""
        if what == "seeds" and not failed_integration(status, reason):
            self.counts["diverged_seeds"] += 1
            return
        self.counts[f"failed_{what}"] += 1
        if not self.failure:
            self.failure = f"{status.value}, {reason}"

    def known(self, x, n):
        """Whether ``x`` lies next to an orbit found already whose period divides n."""
        scale = max(1.0, float(np.abs(x).max()))
        for o in self.orbits:
            if n % o.period == 0 and \
                    np.min(np.abs(o.cycle - x).max(axis=1)) <= KNOWN_TOL * scale:
                return True
        return False

    def shoot(self, x, n):
        """Newton for period ``n`` from ``x``: a short first try, continued only where
        the residual fell; the PeriodicOrbit, or None when given up."""
        st = self.st
        self.counts["shots"] += 1
        first = min(FIRST_TRY, st["max_iter"])
        orb = shoot_periodic_orbit(self.system, x, n, tol=st["tol"], max_iter=first)
        if failed_integration(orb.status, orb.reason):
            self.stopped(orb.status, orb.reason, "shots")
        if orb.converged or first >= st["max_iter"] or orb.status is not Status.OK:
            return orb if orb.converged else None
        if not orb.residual <= PROMISING * max(1.0, float(np.abs(orb.state).max())):
            return None
        orb = shoot_periodic_orbit(self.system, orb.state, n, tol=st["tol"],
                                   max_iter=st["max_iter"] - first)
        if failed_integration(orb.status, orb.reason):
            self.stopped(orb.status, orb.reason, "shots")
        return orb if orb.converged else None

    def add(self, orb, seed):
        """Record a converged orbit unless it is one found already."""
        m = int(orb.minimal_period)
        cyc = orb.cycle[:m]
        if not np.all(np.isfinite(cyc)):
            return
        for o in self.orbits:
            if o.period == m and same_orbit(cyc, o.cycle):
                self.counts["duplicates"] += 1
                return
        found = describe_orbit(self.system, orb, seed, self.st["tol"])
        if found is None:
            self.counts["failed"] += 1
            return
        if any(o.period == found.period and same_orbit(found.cycle, o.cycle)
               for o in self.orbits):
            self.counts["duplicates"] += 1
            return
        self.orbits.append(found)

    def seed(self, index, x0, transient, periods, own):
        """Integrate from the seed ``x0`` and shoot from its close returns (a user's
        seed, ``own``: from the seed itself first)."""
        st = self.st
        status, reason, pts = self.system.strobe(transient + st["record"], x0)
        if status is not Status.OK:
            self.stopped(status, reason, "seeds")
            return
        pts = pts[transient:]
        for n in periods:
            shots = 0
            returns = close_returns(pts, n, pts.shape[0], st["max_return"])
            for k in ([0] if own else []) + [k for k in returns if not own or k]:
                if shots >= st["starts"]:
                    break
                if self.known(pts[k], n):
                    self.counts["known"] += 1
                    continue
                shots += 1
                orb = self.shoot(pts[k], n)
                if orb is None:
                    self.counts["failed"] += 1
                    continue
                self.counts["converged"] += 1
                self.add(orb, index)


#: most Newton iterations of one start (``max_iter``), and most Newton starts per seed
#: and period (``starts``)
MAX_ITER = 1000


def _settings(periods, transient, record, starts, max_return, max_iter, tol):
    """The checked settings of a hunt as a dict."""
    record = max(periods) * 3 if record is None else _v.count("record", record, 1)
    if record < max(periods):
        raise ValueError(f"record must be >= the longest period ({max(periods)}), got "
                         f"{record}")
    transient = _v.count("transient", transient, 0)
    if transient + record > _limits.MAX_PERIODS:
        raise ValueError(f"transient + record must be at most {_limits.MAX_PERIODS} "
                         f"forcing periods (one seed's run), got {transient} + {record}")
    return dict(transient=transient, record=record,
                starts=_v.count("starts", starts, 1, MAX_ITER),
                max_return=_v.positive("max_return", max_return),
                max_iter=_v.count("max_iter", max_iter, 1, MAX_ITER),
                tol=_v.positive("tol", tol))


@_v.checks_flags
def hunt_orbits(system: System | Params | DuffingParams,
                periods: int | Iterable[int] = range(1, 17), *,
                seeds: ArrayLike | None = None, random: int = DEFAULT_RANDOM,
                seed: int = 0, box: ArrayLike | None = None, transient: int = 5,
                record: int | None = None, starts: int = 2, max_return: float = 0.2,
                max_iter: int = 12, tol: float = 1e-9, continuation: bool = True,
                window: float = 0.05, steps: Steps | None = None,
                progress: Callable[[int, int], None] | None = None,
                execution: Execution | None = None) -> OrbitHunt:
    """Periodic orbits of the stroboscopic map, stable or not, by multi-start Newton
    shooting; each continued in the forcing frequency to where it exists and is stable.

    Method.  Every seed (the user's, then ``random`` states) is integrated over
    ``transient`` forcing periods (random seeds only: a user's seed is kept) and then
    ``record`` more; for each period ``n`` the ``starts`` best close returns of its
    stroboscopic points (``|x_{k+n} - x_k|`` smallest, at most ``max_return`` relative,
    :func:`vibimpact.orbits.seeds.close_returns`) start Newton shooting for ``P^n(x) =
    x`` (:func:`vibimpact.analysis.shoot_periodic_orbit`); a user's seed is itself the
    first start (then its trajectory's points, which are its other phases when it lies
    on an orbit).  A start within 1e-3
    (relative) of an orbit found already, whose period divides ``n``, is skipped; Newton
    is given up after 5 iterations unless its residual fell below 1e-2 (relative), and
    after ``max_iter`` in all.

    Deduplication.  A converged orbit's minimal period ``m`` is the smallest divisor of
    ``n`` after which its cycle returns (a period-``n`` shooting that lands on a
    period-``m`` orbit finds the period-``m`` orbit).  A period-``m`` orbit met at
    another phase of its cycle is the same orbit: two orbits are one when they have the
    same ``m`` and a point of one lies within 1e-6 (relative) of a point of the other
    (:func:`same_orbit`).  Each orbit is stored from a canonical phase: its cycle point
    with the largest first state variable.

    Parameters
    ----------
    system : System or parameter set
        The model at the forcing frequency of the hunt (in ``[1e-6, 1e6]``,
        :data:`vibimpact.sweeps.sweep.ETA_RANGE`); its solver settings serve the
        trajectories (shooting and the orbits' runs use ``rtol = 1e-10``).
    periods : int or iterable of int
        Periods to shoot for, each in ``[1, 64]``.
    seeds : array_like, shape (k, d), optional
        The user's seed states at the start of a forcing period (e.g. a census's
        representatives, :func:`vibimpact.orbits.seeds_from_dataset`).
    random : int
        Random seeds (default 48, at most 1,000,000), drawn by ``numpy.random.default_rng(seed)`` in
        the box of :func:`vibimpact.orbits.seeds.seed_box`: uniform in ``[-1, 1]`` for each state
        variable, except the two positions of a planar contact (the built-in rotor's
        ``X, Y``), uniform in the unit disk (for the built-in rotor, the clearance
        circle).
    seed : int
        Seed of the random generator, ``>= 0``: the same seed, the same result.
    box : array_like, shape (d, 2), optional
        Another box (low, high of each state variable).
    transient, record : int
        Forcing periods integrated from a random seed before its close returns are
        looked for, and over which they are (default three times the longest period);
        together at most the period limit of a run (10,000,000).
    starts : int
        Newton starts per seed and period, at most (``1 .. 1000``).
    max_return : float
        Largest relative return distance of a start.
    max_iter : int
        Newton iterations per start, at most (``1 .. 1000``).
    tol : float
        Newton's tolerance (relative residual).
    continuation : bool
        Continue each orbit in the forcing frequency (:func:`orbit_extent`).
    window : float
        Half-width of the parameter window of the continuation about the hunt's value.
    steps : Steps, optional
        Step controls of :func:`vibimpact.analysis.continue_orbit` (default
        ``Steps(max_points=60)``).
    progress : callable, optional
        ``progress(done, total)`` after each seed.
    execution : Execution, optional
        Where the orbits' continuations run (:class:`vibimpact.Execution`: ``workers``,
        ``scheduler``, ``checkpoint``, ``resume``, ``progress``), as engine tasks, one
        orbit each (:mod:`vibimpact.orbits.extent_tasks`); none of it changes a number.

    Returns
    -------
    OrbitHunt

    Raises
    ------
    ValueError
        Naming the argument.

    Examples
    --------
    >>> import vibimpact as vi
    >>> hunt = vi.hunt_orbits(vi.DuffingParams(gamma=0.1), periods=[1], random=4,
    ...                       continuation=False)
    >>> sorted(o.label for o in hunt.orbits)
    ['P1, 0 impacts, stable', 'P1, 0 impacts, stable', 'P1, 0 impacts, unstable']
    """
    system = to_system(system, "system")
    name = system.model.param_names[system.model.omega_index]
    check_frequency(system.omega, f"system's forcing frequency {name}")
    d = system.n_state
    periods = _periods(periods)
    st = _settings(periods, transient, record, starts, max_return, max_iter, tol)
    st["window"] = _v.positive("window", window)
    continuation = _v.flag("continuation", continuation)
    own = user_seeds(seeds, d)
    rnd = random_seeds(system.model, random, seed, box)
    from ..engine.execution import as_execution

    execution = as_execution(execution)
    if progress is not None and not callable(progress):
        raise _v.WrongType(f"progress must be callable, got {type(progress).__name__}")
    t0 = time.perf_counter()
    hunter = _Hunter(system, st)
    everything = np.concatenate([own, rnd])
    total = everything.shape[0]
    for i, x0 in enumerate(everything):
        mine = i < own.shape[0]
        hunter.seed(i, x0, 0 if mine else st["transient"], periods, mine)
        if progress is not None:
            progress(i + 1, total)
    orbits = sorted(hunter.orbits, key=lambda o: (o.period, o.impacts, -o.state[0]))
    t1 = time.perf_counter()
    if continuation:
        from .extent_tasks import run_extents

        extents = run_extents(system, orbits, st["window"], steps, execution)
        orbits = [replace(o, extent=e) for o, e in zip(orbits, extents)]
    mdl = system.model
    return OrbitHunt(tuple(orbits), mdl.param_names[mdl.omega_index], system.omega,
                     periods, everything, own.shape[0], int(seed), hunter.counts, st,
                     dict(hunt_s=t1 - t0, continuation_s=time.perf_counter() - t1),
                     hunter.failure)
