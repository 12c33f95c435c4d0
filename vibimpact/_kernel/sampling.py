"""Samples of the integration loop: dense and stroboscopic output (``@njit`` pieces).

Pieces of :func:`.driver.integrate`, inlined into it by numba (:data:`.jitopts.PIECE`):
the dense grid of a period (``dense_m`` samples at ``j T / dense_m``) and the
stroboscopic sample at its end, both taken from the step's continuous extension; and
the bookkeeping that carries the next dense index across calls (:func:`resume`,
:func:`suspend`) and into a new period (:func:`next_period_sample`).
"""
import math

import numpy as np
from numba import njit

from .integrator import C_RHS, interpolate, prepare_dense
from .jitopts import PIECE

@njit(**PIECE)
def _dense_ready(problem, method, ws, mode, s, y, h, ready, counters):
    """Prepare the continuous extension of the step unless ``ready``; returns True."""
    if not ready:
        model, terminal, p, omega = problem
        mid, A, B, C, E, E3, D, P, order, n_stages = method
        counters[C_RHS] += prepare_dense(model, p, mode, mid, A, C, D, P, n_stages, s, y,
                                         h, ws.K, ws.y1, ws.ytmp, ws.F)
    return True


@njit(**PIECE)
def _sample_time(j, dense_m, dt, T):
    """Local time of dense sample ``j`` of a period: ``j T / dense_m``, the period's end
    ``T`` itself for ``j = dense_m`` (the stroboscopic sample's time)."""
    return T if j == dense_m else j * dt


@njit(**PIECE)
def _first_sample(s, dense_m, T):
    """Index of the first dense sample after local time ``s`` (samples up to and
    including ``s`` belong to the steps before) when no index is carried in."""
    dt = T / dense_m
    j = max(int(math.floor(s / dt)), 0)
    while j > 0 and _sample_time(j - 1, dense_m, dt, T) > s:
        j -= 1
    while _sample_time(j, dense_m, dt, T) <= s:
        j += 1
    return j


@njit(**PIECE)
def resume(ks, s, dense_m, T):
    """The steps taken in the current period and the next dense sample's index there,
    carried across calls in ``ks[3]`` and ``ks[4]`` when the caller provides them (a
    LOG_FULL restart must not reset the per-period step limit nor re-derive the index);
    otherwise 0 and the index derived from the local time ``s``."""
    steps_in_period = int(ks[3]) if ks.size > 3 else 0
    j_dense = np.int64(0)
    if dense_m > 0:
        if ks.size > 4 and ks[4] >= 0.0:
            j_dense = np.int64(ks[4])
        else:
            j_dense = np.int64(_first_sample(s, dense_m, T))
    return steps_in_period, j_dense


@njit(**PIECE)
def suspend(ks, k, s, h, steps_in_period, j_dense, dense_m):
    """Write the clock ``(k, s, h[, steps[, j]])`` back for the next call."""
    ks[0], ks[1], ks[2] = k, s, h
    if ks.size > 3:
        ks[3] = steps_in_period
    if ks.size > 4:
        ks[4] = j_dense if dense_m > 0 else -1.0


@njit(**PIECE)
def next_period_sample(j_dense, k, k_record, lands, s_end, dense_m, T):
    """The dense index carried into the new period ``k`` (less ``dense_m``); before the
    recorded periods it is derived afresh from the new local time (none of those samples
    is kept)."""
    if k >= k_record:
        return j_dense - dense_m
    if dense_m > 0:
        return np.int64(_first_sample(0.0 if lands else s_end - T, dense_m, T))
    return j_dense


@njit(**PIECE)
def _dense_samples(problem, method, cfg, ws, mode, k, k_record, s, y, h, s_end, lands,
                   th_end, y_end, dense_m, dense, j, ready, counters):
    """Dense samples at local times ``j T / dense_m`` inside the step ``[s, s_end]``
    (``j >= dense_m`` belong to the next period: a step may run past the period's end),
    from the index ``j``, the first not yet taken, on; returns whether the continuous
    extension is prepared and the next index to take.

    The index is carried from step to step (and across the period's end, less
    ``dense_m``) rather than derived from ``s``: a sample time that equals a step's end up
    to rounding is then taken by exactly one of the two steps.  The sample at the
    period's end (``j = dense_m``) is taken where the stroboscopic one is and equals it."""
    n = y.size
    T = cfg.T
    dt = T / dense_m
    while _sample_time(j, dense_m, dt, T) <= s_end or (lands and j == dense_m):
        kk = k + j // dense_m
        idx = (kk - k_record) * dense_m + j % dense_m
        if kk >= k_record and idx < dense.shape[0]:
            if lands and j == dense_m:
                for m in range(n):
                    dense[idx, m] = y_end[m]
            else:
                ready = _dense_ready(problem, method, ws, mode, s, y, h, ready, counters)
                th = (T - s) / h if j == dense_m else min((j * dt - s) / h, th_end)
                interpolate(method[0], th, h, y, ws.f0, ws.y1, ws.f1r, ws.F, ws.yint)
                for m in range(n):
                    dense[idx, m] = ws.yint[m]
        j += 1
        if lands and j > dense_m:
            break
    return ready, j


@njit(**PIECE)
def _strobe_sample(problem, method, cfg, ws, mode, s, y, h, lands, y_end, row, strobe,
                   ready, counters):
    """Stroboscopic sample at the period's end (``s = T``) inside the step, into
    ``strobe[row]``; returns whether the continuous extension is prepared."""
    n = y.size
    if lands:
        for m in range(n):
            strobe[row, m] = y_end[m]
        return ready
    ready = _dense_ready(problem, method, ws, mode, s, y, h, ready, counters)
    interpolate(method[0], (cfg.T - s) / h, h, y, ws.f0, ws.y1, ws.f1r, ws.F, ws.yint)
    for m in range(n):
        strobe[row, m] = ws.yint[m]
    return ready


@njit(**PIECE)
def samples(problem, method, cfg, ws, mode, k, k_record, s, y, h, s_end, lands, th_end,
             y_end, dense_m, dense, j_dense, strobe, ready, counters):
    """The dense samples inside the step ``[s, s_end]`` of period ``k`` (from index
    ``j_dense`` on, see :func:`_dense_samples`) and, when it reaches the period's end, the
    stroboscopic sample there.  Returns the next dense index (of period ``k``)."""
    if dense_m > 0 and k + 1 >= k_record:
        ready, j_dense = _dense_samples(problem, method, cfg, ws, mode, k, k_record, s, y,
                                        h, s_end, lands, th_end, y_end, dense_m, dense,
                                        j_dense, ready, counters)
    row = k + 1 - k_record
    if (lands or s_end >= cfg.T) and row >= 0 and row < strobe.shape[0]:
        _strobe_sample(problem, method, cfg, ws, mode, s, y, h, lands, y_end, row, strobe,
                       ready, counters)
    return j_dense
