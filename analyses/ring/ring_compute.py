"""What the ring study computes, each piece cached on its own: the parameter variants, the
up-and-down sweeps, the attractor census, the simulation from rest, the orbit hunt and the
regime map over (eta, Jr).

Shared settings with the paper report: the sweeps run every analyser of
``analyses/paper/paper_sweeps.py`` (:data:`paper_sweeps.ANALYSES`) with pure
continuation; the census, the hunt and the simulation from rest take the settings of
``analyses/paper/census_claims.py`` (starts, seed, hunt seeds and options), so that a
claim is decided by the same rules as in ``reports/paper.md``.  The functions of
``census_claims`` build ``vi.Params`` (eq. (5)); these take any built-in parameter set,
the ring's :class:`RingParams` included.

Everything is kept under the paper cache (``.paper-cache/ring/``, ignored by git), keyed
by the request, the package version and the sources it depends on
(:func:`census_claims.code_hash`).
"""
from __future__ import annotations

import hashlib
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

import vibimpact as vi

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "paper"))
import census_claims as K  # noqa: E402
from paper_sweeps import ANALYSES  # noqa: E402

#: sources whose change recomputes a sweep or a map, a census and a hunt (the ring's
#: model module lives in builtin_models)
SWEEP_CODE = ("_kernel", "builtin_models", "points", "sweeps", "engine", "analysis")
CENSUS_CODE = K.CENSUS_CODE + ("builtin_models",)
HUNT_CODE = K.HUNT_CODE + ("builtin_models",)
#: the figures whose claims the study scores; eq. (5)'s presets and their ring versions
FIGURES = ("fig6", "fig8", "fig10", "fig11")


def model_of(p):
    """The built-in model's name of a parameter set (``"rotor"``, ``"ring"``)."""
    return vi.models.of_params(p).name


def ring_params(fig, **ring):
    """Figure ``fig`` with a turning ring: its ``-ring`` preset when there is one, else
    the paper's values of ``fig`` with the ring of ``fig8-ring``; ``ring`` overrides
    ``Jr``, ``cr``, ``Mr``."""
    names = vi.presets.names()
    base = vi.presets.get(f"{fig}-ring") if f"{fig}-ring" in names else \
        vi.presets.get("fig8-ring").replace(**vi.presets.get(fig).as_dict())
    return base.replace(**ring)


def variant_params(fig, variant):
    """The parameters of ``fig`` under a variant ``{"model": "eq5"}`` (the held ring) or
    ``{"model": "ring", "Jr": .., "Mr": ..}`` (omitted: the preset's)."""
    if variant["model"] == "eq5":
        return vi.presets.get(fig)
    ring = {k: variant[k] for k in ("Jr", "cr", "Mr") if variant.get(k) is not None}
    return ring_params(fig, **ring)


def _key(*parts):
    return hashlib.sha1(json.dumps(parts, sort_keys=True).encode()).hexdigest()[:12]


def eta_grid(step, lo=0.9, hi=1.5):
    """``lo:hi:step`` rounded as the paper report's grid."""
    return np.round(np.arange(lo, hi + 1e-9, step), 6)


def _write(ds, path):
    tmp = path.with_suffix(".tmp")
    ds.to_netcdf(tmp)
    os.replace(tmp, path)


def sweep(task):
    """``(tag, dataset, seconds)`` of ``task = (tag, params, step, cache, fresh)``: the
    up-and-down sweep on :func:`eta_grid`, read from the cache or computed; ``seconds``
    is what computing it took (kept with it as the attribute ``compute_seconds``)."""
    tag, p, step, cache, fresh = task
    import xarray as xr

    key = _key(model_of(p), p.as_dict(), step, ANALYSES, vi.__version__,
               K.code_hash(SWEEP_CODE))
    path = Path(cache) / f"sweep_{model_of(p)}_{key}.nc"
    if path.exists() and not fresh:
        ds = xr.load_dataset(path)
        return tag, ds, float(ds.attrs.get("compute_seconds", 0.0))
    t = time.perf_counter()
    ds = vi.sweep(p, eta_grid(step), direction="both", analyses=ANALYSES,
                  continuation=vi.Continuation(blocks=1), execution=vi.Execution(workers=1))
    ds.attrs.update(command=f"analyses/ring/ring_study.py ({tag})",
                    compute_seconds=time.perf_counter() - t)
    path.parent.mkdir(parents=True, exist_ok=True)
    _write(ds, path)
    return tag, ds, ds.attrs["compute_seconds"]


def census(p, eta, starts, cache, fresh=False):
    """The census at one eta as :func:`census_claims.census` computes it (``rows``,
    ``seeds``, ``seconds``), for any built-in parameter set."""
    def make():
        ds = vi.attractors(vi.System(p.replace(eta=float(eta))), eta=[float(eta)],
                           starts=starts, seed=K.SEED, execution=vi.Execution(workers=1))
        pts = [np.asarray(ds["representative"].values[0], float)]
        smp = np.asarray(ds["samples"].values[0], float)  # (attractor, sample, state)
        pick = np.linspace(0, smp.shape[1] - 1, K.SEED_SAMPLES).astype(int)
        pts.append(smp[:, pick].reshape(-1, smp.shape[-1]))
        pts = np.concatenate(pts)
        pts = np.unique(pts[np.all(np.isfinite(pts), axis=1)], axis=0)
        return dict(rows=K._attractor_rows(ds, 0), seeds=pts.tolist(),
                    box=str(ds.attrs.get("box", "")))

    return K._memo(cache, "census", [model_of(p), p.as_dict(), float(eta), int(starts),
                                     K.SEED], fresh, make, CENSUS_CODE)


def hunt(p, eta, periods, seeds, cache, fresh=False):
    """The orbit hunt at one eta as :func:`census_claims.hunt` runs it, for any built-in
    parameter set."""
    from vibimpact.orbits import hunt_orbits

    def make():
        h = hunt_orbits(vi.System(p.replace(eta=float(eta))), periods=periods,
                        seeds=np.asarray(seeds) if len(seeds) else None,
                        random=K.HUNT_RANDOM, seed=K.SEED, continuation=False, **K.HUNT)
        return dict(orbits=[dict(period=int(o.period), impacts=int(o.impacts),
                                 stable=bool(o.stable), abs_mu=float(o.abs_max),
                                 arcs=o.arcs, label=o.label) for o in h.orbits],
                    shots=int(h.counts.get("shots", 0)), seeds=int(len(h.seeds)))

    return K._memo(cache, "hunt", [model_of(p), p.as_dict(), float(eta), list(periods),
                                   seeds, K.HUNT_RANDOM, K.HUNT, K.SEED], fresh, make,
                   HUNT_CODE)


def census_task(task):
    """Pool task ``(tag, params, eta, starts, cache, fresh)`` -> ``(tag, eta, result)``."""
    tag, p, eta, starts, cache, fresh = task
    return tag, eta, census(p, eta, starts, cache, fresh)


def hunt_task(task):
    """Pool task ``(tag, params, eta, periods, seeds, cache, fresh)`` ->
    ``(tag, eta, result)``."""
    tag, p, eta, periods, seeds, cache, fresh = task
    return tag, eta, hunt(p, eta, periods, seeds, cache, fresh)


def map_rows(task):
    """Pool task ``(params, step, jr)`` -> the map of those rows, in this process, with
    its computing time as the attribute ``compute_seconds``."""
    p, step, jr = task
    t = time.perf_counter()
    ds = vi.map2d(p, eta_grid(step), {"Jr": list(jr)}, direction="both",
                  execution=vi.Execution(workers=1))
    ds.attrs["compute_seconds"] = time.perf_counter() - t
    return ds


def regime_map(p, step, jr, cache, fresh=False, run=None):
    """``(dataset, path, seconds)``: the map over (eta, Jr) of ``p`` in both directions
    with the map's analysers, kept as NetCDF in the cache; ``seconds``: the computing
    time of its chunks, summed (kept as the attribute ``compute_seconds``).

    ``run(fn, tasks)`` maps :func:`map_rows` over chunks of the Jr values (a process
    pool: rows are independent, so the chunks joined along Jr are the one map); by
    default one chunk in this process.
    """
    import xarray as xr
    from vibimpact.maps import open_map, write_map

    jr = [float(v) for v in jr]
    key = _key(model_of(p), p.as_dict(), step, jr, vi.__version__, K.code_hash(SWEEP_CODE))
    path = Path(cache) / f"map_Jr_{model_of(p)}_{key}.nc"
    if path.exists() and not fresh:
        ds = open_map(path).load()
        return ds, path, float(ds.attrs.get("compute_seconds", 0.0))
    chunks = [tuple(jr[k::2]) for k in range(2)] if len(jr) > 1 else [tuple(jr)]
    parts = (run or (lambda f, ts: [f(x) for x in ts]))(map_rows,
                                                       [(p, step, c) for c in chunks])
    ds = xr.concat(parts, dim="Jr", combine_attrs="override").sortby("Jr")
    ds.attrs.update(command="analyses/ring/ring_study.py (map)", map_rows=len(jr),
                    compute_seconds=sum(d.attrs["compute_seconds"] for d in parts))
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.exists():
        path.unlink()
    write_map(ds, path)
    return ds, path, ds.attrs["compute_seconds"]
