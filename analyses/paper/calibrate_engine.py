"""The calibration's rows on the map engine, cached by a hash of the package's sources.

A row is one up-and-down sweep of the fig8 rotor with a set of contact dampings on, at
one (B, Ec): a row of :func:`vibimpact.map2d`.  Missing rows are grouped by (dampings,
Ec) into maps whose varied parameter is B, and all the maps are submitted at once to one
Dask cluster (each from its own thread of this process), so the workers never wait for a
map's last row.  Every finished row is written to the cache as a NetCDF file named by
its dampings, B, Ec and eta step, in a directory named by the hash of the package's
sources: a rerun reuses it, a code change recomputes.
"""
from __future__ import annotations

import hashlib
import os
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

import vibimpact as vi
from vibimpact.paper import claims as C

from calibrate_search import DAMPINGS, FIT_PRESETS, ClaimResult, damping_values

#: what the claims need of a sweep
ANALYSES = ("period", "impacts")


def code_hash(root):
    """First 12 hex digits of the SHA-256 of the vibimpact package's Python sources."""
    h = hashlib.sha256()
    for f in sorted((Path(root) / "vibimpact").rglob("*.py")):
        h.update(f.relative_to(root).as_posix().encode())
        h.update(f.read_bytes())
    return h.hexdigest()[:12]


def fitted_claims():
    """The claims the calibration fits (figs 8, 10 and 11)."""
    return tuple(c for c in C.CLAIMS if c.preset in FIT_PRESETS)


def eta_grid(step, lo=0.9, hi=1.5):
    """The sweeps' grid ``lo:hi:step``, rounded to 6 decimals."""
    return np.round(np.arange(lo, hi + 1e-9, step), 6)


def row_params(key):
    """:class:`vibimpact.Params` of a row ``(variant, B, Ec)``."""
    name, B, Ec = key
    damp = () if name == "none" else tuple(name.split("+"))
    return vi.presets.get("fig8").replace(B=B, Ec=Ec, **damping_values(damp))


def row_results(ds, claims=None):
    """``{claim key: ClaimResult}`` of one row (a sweep dataset with both directions).

    The score is :func:`vibimpact.paper.claims.claim_score`; the claim agrees when a compared
    direction's detected interval has both ends within one sweep step of the paper's
    (:attr:`vibimpact.paper.claims.Detection.agree`); start and end are those of the best
    direction.
    """
    out = {}
    for c in claims or fitted_claims():
        dets = C.detect(ds, c)
        out[c.key] = ClaimResult(float(C.claim_score(ds, c)), any(d.agree for d in dets),
                                 float(dets[0].start), float(dets[0].end))
    return out


class Engine:
    """Computes, caches and scores rows.

    Parameters
    ----------
    eta : ndarray
        The sweeps' grid.
    cache : path
        Directory of the row files (already specific to the code's hash).
    scheduler : optional
        A ``distributed.Client`` shared by every map, or None to run in this process.
    """

    def __init__(self, eta, cache, scheduler=None):
        self.eta = np.asarray(eta, dtype=float)
        self.step = float(np.median(np.diff(self.eta))) if self.eta.size > 1 else 1.0
        self.cache = Path(cache)
        self.cache.mkdir(parents=True, exist_ok=True)
        self.scheduler = scheduler
        self.rows = {}
        self.stats = {"computed": 0, "cached": 0}
        self.claims = fitted_claims()

    def path(self, key):
        """Cache file of a row."""
        name, B, Ec = key
        return self.cache / (f"{name}_B{B:.6g}_Ec{Ec:.5f}_eta{self.eta[0]:g}-"
                             f"{self.eta[-1]:g}-{self.eta.size}.nc")

    def ensure(self, keys):
        """Make every row of ``keys`` available in :attr:`rows` (from the cache or
        computed)."""
        import xarray as xr

        todo = []
        for key in sorted(set(keys) - set(self.rows)):
            path = self.path(key)
            if path.exists():
                self.rows[key] = row_results(xr.load_dataset(path), self.claims)
                self.stats["cached"] += 1
            else:
                todo.append(key)
        groups = {}
        for name, B, Ec in todo:
            groups.setdefault((name, Ec), []).append(B)
        if not groups:
            return
        jobs = sorted(groups.items())
        total = len(todo)
        print(f"computing {total} rows in {len(jobs)} maps", file=sys.stderr, flush=True)
        if self.scheduler is None:
            for job in jobs:
                self._store(job, self._map(job))
        else:
            # the maps run from threads (all their tasks on the cluster at once); the
            # NetCDF files are written here, in this thread only (HDF5 is not thread-safe)
            from concurrent.futures import as_completed

            with ThreadPoolExecutor(max_workers=min(len(jobs), 32)) as pool:
                futures = {pool.submit(self._map, job): job for job in jobs}
                for fut in as_completed(futures):
                    self._store(futures[fut], fut.result())
        print(file=sys.stderr)

    def _map(self, job):
        (name, Ec), Bs = job
        ds = vi.map2d(row_params((name, min(Bs), Ec)), self.eta,
                      vary={"B": np.array(sorted(Bs))}, direction="both",
                      analyses=ANALYSES, execution=vi.Execution(scheduler=self.scheduler))
        ds.attrs["command"] = "analyses/paper/calibrate.py"
        return ds

    def _store(self, job, ds):
        (name, Ec), Bs = job
        for i, B in enumerate(sorted(Bs)):
            row = ds.isel(B=i)
            path = self.path((name, B, Ec))
            tmp = path.with_name(path.name + ".tmp")
            row.to_netcdf(tmp)
            os.replace(tmp, path)
            self.rows[(name, B, Ec)] = row_results(row, self.claims)
            self.stats["computed"] += 1
        print(f"\r{self.stats['computed']} rows computed", end="", file=sys.stderr,
              flush=True)


def local_client(workers):
    """A ``distributed.Client`` on a ``LocalCluster`` of ``workers`` single-threaded
    processes with the map engine's worker settings, and the cluster (close both)."""
    import logging

    import dask
    from distributed import Client, LocalCluster

    from vibimpact.engine.cluster import WORKER_CONFIG

    with dask.config.set(WORKER_CONFIG):
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=":0", silence_logs=logging.ERROR)
    client = Client(cluster, set_as_default=False)
    client.wait_for_workers(workers, timeout=60)
    return client, cluster


__all__ = ["ANALYSES", "DAMPINGS", "Engine", "code_hash", "eta_grid", "fitted_claims",
           "local_client", "row_params", "row_results"]
