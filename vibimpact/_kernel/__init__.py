"""Private numba kernel: models, Runge--Kutta tableaux, event location, integration loop.

Everything below this package is ``@njit`` code over plain float64/int64 arrays; the
validated public API lives in :mod:`vibimpact.simulate`.
"""
