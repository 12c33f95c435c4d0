"""The attractors a census has found, as data: clouds of stroboscopic points.

An attractor is known by its *cloud*, the stroboscopic points that represent it:

* a periodic orbit of period ``n``: its ``n`` cycle points (the same set whatever phase
  of the cycle a start meets first, so an orbit met at another phase is the same
  attractor);
* a non-periodic attractor (chaotic, quasi-periodic, or a motion no evidence settled):
  ``cloud`` consecutive stroboscopic points of a trajectory on it.

A trajectory *enters* a known attractor (:func:`entered`) when ``hold`` consecutive
stroboscopic points lie within the attractor's radius of its cloud (for a periodic orbit
``hold >= n`` and the last distance at most the first: the points close in on the
cycle), the recurrence criterion of Datseris & Wagemakers (2022).  Two results are the
same attractor (:func:`same`) when their periodic cycles coincide to ``dedup_tol``, or,
for non-periodic ones, when most points of one cloud lie within the other's radius.

References
----------
.. [1] G. Datseris, A. Wagemakers, "Effortless estimation of basins of attraction",
   Chaos 32, 023104 (2022) (Attractors.jl's ``AttractorsViaRecurrences``).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Attractor", "entered", "same", "nearest_distances", "cloud_radius"]

#: a non-periodic cloud is the same attractor as another when at least this fraction of
#: its points lie within the other's radius
OVERLAP = 0.5


@dataclass(frozen=True, eq=False)
class Attractor:
    """One attractor of a census point.

    Attributes
    ----------
    cloud : ndarray, shape (m, d)
        Its stroboscopic points (module docstring).
    period : int
        The period ``n`` (T = n 2 pi / omega) of a periodic orbit; 0 otherwise.
    radius : float
        The distance within which a point counts as on it.
    hold : int
        Consecutive points within ``radius`` that make a trajectory enter it.
    result : dict
        The full analysis of the start that found it (:func:`vibimpact.points.point.
        analyse_point`'s fields: regime, period, impacts per period, arcs, Floquet
        multipliers or Lyapunov exponent, Poincare samples, final state).
    first : int
        The position of the start that found it.
    """

    cloud: np.ndarray
    period: int
    radius: float
    hold: int
    result: dict = field(repr=False)
    first: int = 0

    @property
    def periodic(self) -> bool:
        return self.period > 0

    def distances(self, points) -> np.ndarray:
        """Distance of every row of ``points`` (k, d) to the nearest cloud point."""
        cloud = self.cloud
        if cloud.shape[0] <= 64:
            return nearest_distances(points, cloud)
        tree = self.__dict__.get("_tree")
        if tree is None:
            from scipy.spatial import cKDTree  # noqa: PLC0415 -- large clouds only

            tree = cKDTree(cloud)
            object.__setattr__(self, "_tree", tree)
        return tree.query(np.asarray(points, dtype=np.float64), k=1)[0]


def nearest_distances(points, cloud):
    """Euclidean distance of every row of ``points`` (k, d) to its nearest row of
    ``cloud`` (m, d): shape (k,)."""
    points = np.asarray(points, dtype=np.float64)
    cloud = np.asarray(cloud, dtype=np.float64)
    if cloud.shape[0] <= 64:
        diff = points[:, None, :] - cloud[None, :, :]
        return np.sqrt((diff * diff).sum(axis=2).min(axis=1))
    from scipy.spatial import cKDTree  # noqa: PLC0415 -- large clouds only

    return cKDTree(cloud).query(points, k=1)[0]


def cloud_radius(cloud, floor):
    """The radius of a non-periodic cloud: twice the median distance of its points to
    their nearest neighbour in it (the cloud's own resolution), at least ``floor``."""
    cloud = np.asarray(cloud, dtype=np.float64)
    if cloud.shape[0] < 2:
        return float(floor)
    from scipy.spatial import cKDTree  # noqa: PLC0415

    d = cKDTree(cloud).query(cloud, k=2)[0][:, 1]
    d = d[np.isfinite(d)]
    return max(float(floor), 2.0 * float(np.median(d)) if d.size else 0.0)


def entered(points, attractors, streaks):
    """The first known attractor the trajectory ``points`` enters, or -1.

    Parameters
    ----------
    points : ndarray, shape (k, d)
        The trajectory's newest stroboscopic points, in order.
    attractors : sequence of Attractor
    streaks : (ndarray of int64, ndarray of float64), each shape (len(attractors),)
        Per attractor: consecutive points within its radius so far, and the distance at
        the streak's start; updated in place.

    Returns
    -------
    int
        Index into ``attractors`` (the first to reach its ``hold``), or -1.
    """
    counts, first = streaks
    k = points.shape[0]
    idx = np.arange(k)
    best_k, best_a = k, -1
    for a, att in enumerate(attractors):
        dist = att.distances(points)
        inside = dist < att.radius
        # the last point outside the radius at or before each point (-1: none)
        last_out = np.maximum.accumulate(np.where(inside, -1, idx))
        fresh = last_out < 0
        streak = np.where(fresh, counts[a] + idx + 1, idx - last_out)
        start = np.minimum(last_out + 1, k - 1)
        start_dist = np.where(fresh, first[a] if counts[a] > 0 else dist[0], dist[start])
        hit = inside & (streak >= att.hold)
        if att.periodic:
            hit &= dist <= start_dist
        where = np.flatnonzero(hit)
        if where.size and where[0] < best_k:
            best_k, best_a = int(where[0]), a
        if inside[-1]:
            first[a] = float(start_dist[-1])
            counts[a] = int(streak[-1])
        else:
            counts[a] = 0
    return best_a


def same(a: Attractor, b: Attractor, dedup_tol: float) -> bool:
    """Whether ``a`` and ``b`` are one attractor (module docstring)."""
    if a.periodic != b.periodic:
        return False
    if a.periodic:
        if a.period != b.period:
            return False
        return float(nearest_distances(a.cloud, b.cloud).max()) <= dedup_tol and \
            float(nearest_distances(b.cloud, a.cloud).max()) <= dedup_tol
    ab = np.mean(b.distances(a.cloud) < b.radius)
    ba = np.mean(a.distances(b.cloud) < a.radius)
    return bool(max(ab, ba) >= OVERLAP)
