"""Which census attractor a sweep followed: a sweep's label placed in the census.

A sweep with continuation shows one attractor at each eta; where a census of the same
parameters lists several, :func:`locate` says which of them it is (the census attractor
whose stroboscopic samples the sweep's own Poincare samples lie on), so that a sweep's
label belongs to a named attractor with its basin fraction.  :func:`unreached_orbits`
does the same for the stable orbits of an orbit hunt: those that are on none of the
census' attractors are attractors no start of the census reached.
"""
from __future__ import annotations

import numpy as np
import xarray as xr

from .library import nearest_distances

__all__ = ["locate", "LOCATE_TOL", "unreached_orbits", "name_after", "orbits_named_after"]

#: the sweep's samples lie on a census attractor when their mean distance to its samples
#: is below this many box scales
LOCATE_TOL = 0.05


def _cloud(census, i, a):
    """The finite stroboscopic samples of attractor ``a`` of the census at eta index
    ``i`` (shape (m, d))."""
    cloud = census.samples.values[i, a]
    return cloud[np.all(np.isfinite(cloud), axis=1)]


def _sweep_points(sweep, names):
    """``(direction, eta, sample, state)`` Poincare samples of every state of a sweep."""
    cols = []
    for j, name in enumerate(names):
        var = {0: "poincare_X", 1: "poincare_Y"}.get(j) if f"poincare_{name}" not in sweep \
            else f"poincare_{name}"
        if var is None or var not in sweep:
            raise ValueError(f"sweep has no Poincare samples of {name} (poincare_{name}); "
                             "run it with the poincare analysis")
        cols.append(sweep[var].transpose("direction", "eta", "sample").values)
    return np.stack(cols, axis=-1)


def locate(census: xr.Dataset, sweep: xr.Dataset, tol: float = LOCATE_TOL) -> xr.DataArray:
    """The census attractor each point of ``sweep`` is on.

    Parameters
    ----------
    census : xarray.Dataset
        :func:`vibimpact.attractors` of the sweep's parameters.
    sweep : xarray.Dataset
        :func:`vibimpact.sweep` (with the poincare analysis).
    tol : float
        Mean distance of the sweep's samples to the attractor's, in box scales.

    Returns
    -------
    xarray.DataArray
        ``(direction, eta)`` over the etas both hold: the attractor's ``global_id``
        (-1: on none of the census' attractors, e.g. one no start reached).

    Raises
    ------
    ValueError
        When the two share no eta or the sweep has no Poincare samples.
    """
    if census.attrs.get("kind") != "census":
        raise ValueError("census is not an attractor census (vi.attractors)")
    if "eta" not in sweep.dims:
        raise ValueError("sweep is not a sweep dataset (vi.sweep): it has no eta")
    if "direction" not in sweep.dims:  # a one-direction sweep
        sweep = sweep.expand_dims(direction=[str(sweep.attrs.get("direction", "up"))])
    names = [str(s) for s in census.state.values]
    common = np.intersect1d(np.round(census.eta.values, 12), np.round(sweep.eta.values, 12))
    if common.size == 0:
        raise ValueError("census and sweep share no eta")
    pts = _sweep_points(sweep, names)
    scale = float(census.attrs.get("box_scale", 1.0))
    ce = np.round(census.eta.values, 12)
    se = np.round(sweep.eta.values, 12)
    out = np.full((pts.shape[0], common.size), -1, dtype=np.int64)
    for k, eta in enumerate(common):
        i = int(np.flatnonzero(ce == eta)[0])
        j = int(np.flatnonzero(se == eta)[0])
        for r in range(pts.shape[0]):
            p = pts[r, j]
            p = p[np.all(np.isfinite(p), axis=1)]
            if p.size == 0:
                continue
            best, best_d = -1, np.inf
            for a in range(census.sizes["attractor"]):
                cloud = _cloud(census, i, a)
                if cloud.size == 0:
                    continue
                dist = float(nearest_distances(p, cloud).mean())
                if dist < best_d:
                    best, best_d = a, dist
            if best >= 0 and best_d <= tol * scale:
                out[r, k] = int(census.global_id.values[i, best])
    return xr.DataArray(out, dims=("direction", "eta"),
                        coords=dict(direction=sweep.direction.values, eta=common),
                        name="attractor", attrs=dict(
                            valid_min=out.dtype.type(0),
                            long_name="census attractor (global_id) the sweep is on; -1: "
                                      "none of the census' attractors"))


def _census_point(census, value):
    """The census' index of the eta ``value`` (None where it holds none)."""
    if census.attrs.get("kind") != "census":
        raise ValueError("census is not an attractor census (vi.attractors)")
    hit = np.flatnonzero(np.round(census.eta.values.astype(float), 12)
                         == round(float(value), 12))
    return int(hit[0]) if hit.size else None


def orbits_named_after(orbits: xr.Dataset, census: xr.Dataset,
                       tol: float = LOCATE_TOL) -> xr.Dataset | None:
    """``orbits`` with the ``global_id`` of each stable orbit taken from ``census``, so
    that an attractor has the same name (A<id>) and colour in the census, basins and
    orbits files, figures and tables.

    A stable orbit is the census attractor whose samples its cycle points lie on (mean
    nearest distance within ``tol`` box scales, the nearest first, each attractor named
    once); a stable orbit on none of them -- an attractor no start of the census reached
    -- gets a new id after the census' largest; an unstable orbit is no attractor:
    ``global_id`` -1.

    Parameters
    ----------
    orbits : xarray.Dataset
        :func:`vibimpact.orbits.hunt_to_dataset` (``stable``, ``orbit_point (orbit,
        phase, state)``, attribute ``forcing_value``).
    census : xarray.Dataset
        :func:`vibimpact.attractors` of the same model and parameters.
    tol : float

    Returns
    -------
    xarray.Dataset or None
        ``orbits`` with ``global_id (orbit)`` and the attributes ``named_after_census``
        and ``census_ids`` (the census' ids at that eta, so that a reader tells an
        attractor of the census from a new one); None when the census holds no point at
        the hunt's forcing frequency.

    Raises
    ------
    ValueError
        When ``census`` is no census.
    """
    i = _census_point(census, orbits.attrs.get("forcing_value", np.nan))
    if i is None:
        return None
    scale = float(census.attrs.get("box_scale", 1.0))
    ids = census.global_id.values[i]
    clouds = [_cloud(census, i, a) for a in range(census.sizes["attractor"])]
    n = orbits.sizes.get("orbit", 0)
    out = np.full(n, -1, dtype=np.int32)
    pairs = []  # (distance, orbit, attractor) within tol, nearest first
    for o in range(n):
        if int(orbits.stable.values[o]) != 1:
            continue
        pts = orbits.orbit_point.values[o]
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        for a, cloud in enumerate(clouds):
            if pts.size and cloud.size and int(ids[a]) >= 0:
                d = float(nearest_distances(pts, cloud).mean())
                if d <= tol * scale:
                    pairs.append((d, o, a))
    taken: set[int] = set()
    for _, o, a in sorted(pairs):
        if out[o] < 0 and a not in taken:
            out[o] = int(ids[a])
            taken.add(a)
    new = int(np.max(census.global_id.values, initial=-1)) + 1
    for o in range(n):
        if int(orbits.stable.values[o]) == 1 and out[o] < 0:
            out[o], new = new, new + 1
    named = orbits.copy()
    named["global_id"] = ("orbit", out, dict(
        long_name="the stable orbit's attractor id in the census it is named after "
                  "(A<id>; -1: unstable, no attractor)", valid_min=np.int32(0)))
    named.attrs["named_after_census"] = 1
    named.attrs["census_ids"] = np.array(sorted(int(g) for g in ids if g >= 0),
                                         dtype=np.int32)
    return named


def unreached_orbits(orbits: xr.Dataset, census: xr.Dataset,
                     tol: float = LOCATE_TOL) -> list[tuple[int, str]] | None:
    """The stable orbits of a hunt that no start of a census at the same point reached.

    Parameters
    ----------
    orbits : xarray.Dataset
        :func:`vibimpact.orbits.hunt_to_dataset` (``stable``, ``period``, ``label``,
        ``orbit_point (orbit, phase, state)``, attribute ``forcing_value``).
    census : xarray.Dataset
        :func:`vibimpact.attractors` of the same model and parameters.
    tol : float
        Mean distance of the orbit's cycle points to an attractor's samples, in box
        scales, within which the orbit is that attractor.

    Returns
    -------
    list of (int, str) or None
        ``(orbit index, label)`` of every stable orbit on none of the census' attractors
        at the hunt's forcing frequency (:func:`orbits_named_after` gives it a new id);
        None when the census holds no point there.
    """
    named = orbits_named_after(orbits, census, tol)
    if named is None:
        return None
    known = set(int(g) for g in named.attrs["census_ids"])
    return [(o, str(orbits.label.values[o])) for o in range(named.sizes.get("orbit", 0))
            if int(named.global_id.values[o]) >= 0
            and int(named.global_id.values[o]) not in known]


def name_after(basins: xr.Dataset, census: xr.Dataset,
               tol: float = LOCATE_TOL) -> xr.Dataset:
    """``basins`` with the ``global_id`` of each attractor taken from ``census``, so that
    the same attractor has the same name (A<id>) and colour in both figures and tables.

    An attractor of the basin image is the census attractor of its period whose samples
    lie within ``tol`` box scales of its own (mean nearest distance) at the image's
    eta; one that matches none gets a new id after the census' largest.

    Raises
    ------
    ValueError
        When ``census`` is no census or holds no point at the image's eta.
    """
    eta = float(basins["eta"].values) if "eta" in basins.coords else np.nan
    i = _census_point(census, eta)
    if i is None:
        raise ValueError(f"census holds no point at the basins' eta {eta:g}")
    scale = float(census.attrs.get("box_scale", 1.0))
    ids = census.global_id.values[i]
    taken, new = set(), int(census.global_id.values.max()) + 1
    out = np.full(basins.sizes["attractor"], -1, dtype=np.int32)
    for a in range(basins.sizes["attractor"]):
        mine = basins.samples.values[a]
        mine = mine[np.all(np.isfinite(mine), axis=1)]
        best, best_d = -1, np.inf
        for b in range(census.sizes["attractor"]):
            cloud = _cloud(census, i, b)
            if not (mine.size and cloud.size) or b in taken or \
                    int(census.period.values[i, b]) != int(basins.period.values[a]):
                continue
            dist = float(nearest_distances(mine, cloud).mean())
            if dist < best_d:
                best, best_d = b, dist
        if best >= 0 and best_d <= tol * scale:
            taken.add(best)
            out[a] = int(ids[best])
        else:
            out[a], new = new, new + 1
    named = basins.copy()
    named["global_id"] = ("attractor", out, dict(basins.global_id.attrs, long_name=(
        "attractor's id in the census it is named after (A<id>)")))
    named.attrs["named_after_census"] = 1
    return named
