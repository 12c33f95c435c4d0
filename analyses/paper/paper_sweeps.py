"""The paper report's sweeps: one up-and-down sweep of a preset on eta = 0.9:1.5:STEP
with pure continuation and every analyser the report reads, cached in the paper cache
(``.paper-cache/``) under a key of its parameters, step, analyses and version.

Shared by ``paper.py`` (the report), ``census_claims.py`` (the census section) and
``transitions.py``, so that all three read the same sweeps.
"""
from __future__ import annotations

import hashlib
import json
import os
import time
from pathlib import Path

import numpy as np

import vibimpact as vi

ANALYSES = ("period", "impacts", "response", "poincare", "lyapunov")
#: read sweeps from the cache only (``paper.py --render-only``): a missing one is an error
CACHE_ONLY = False


class NotCached(LookupError):
    """A render-only run needs a sweep (or result) that the cache does not hold."""


def cache_path(name, step, cache, overrides, suffix=""):
    """``(params, path)``: the preset ``name`` with ``overrides``, and its cache file."""
    p = vi.presets.get(name).replace(**overrides)
    key = hashlib.sha1(json.dumps([p.as_dict(), step, ANALYSES, vi.__version__],
                                  sort_keys=True).encode()).hexdigest()[:12]
    return p, Path(cache) / f"{name}_{key}{suffix}.nc"


def sweep_one(task):
    """``(name, dataset, seconds)`` of ``task = (name, step, cache, fresh, overrides)``:
    read from the cache, or swept (0 seconds when read)."""
    name, step, cache, fresh, overrides = task
    import xarray as xr

    p, path = cache_path(name, step, cache, overrides)
    if path.exists() and not fresh:
        return name, xr.load_dataset(path), 0.0
    if CACHE_ONLY:
        raise NotCached(f"{path} is not in the cache (run without --render-only)")
    t = time.perf_counter()
    eta = np.round(np.arange(0.9, 1.5 + 1e-9, step), 6)
    ds = vi.sweep(p, eta, direction="both", analyses=ANALYSES,
                  continuation=vi.Continuation(blocks=1))
    ds.attrs.update(command=f"analyses/paper/paper.py ({name})", preset=name)
    tmp = path.with_suffix(".tmp")
    ds.to_netcdf(tmp)
    os.replace(tmp, path)
    return name, ds, time.perf_counter() - t
