"""Private numba kernel: models, Runge--Kutta tableaux, event location, integration loop.

Everything below this package is ``@njit`` code over plain float64/int64 arrays; the
validated public API lives in :mod:`vibimpact.simulate`.  Importing the package first
drops numba's disk cache of it when any of its sources changed (:mod:`.cache_guard`).
"""
from .cache_guard import drop_stale_cache as _drop_stale_cache

_drop_stale_cache()
