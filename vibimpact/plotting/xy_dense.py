"""A trajectory sampled finely enough for the eye, for the XY plots.

A trajectory is drawn as straight segments between its samples.  Sampled a few dozen times
per forcing period, a chaotic impact motion (sharp turns at every contact) shows as a
polygon.  :func:`fine_trajectory` gives the samples of a run with segments no longer than
:data:`MAX_SEGMENT_PX` pixels of the figure: the run's own when they are fine enough, else
the same run integrated again with more dense samples per period.  Dense samples are taken
from the steps' continuous extension and do not change the steps, so the run made again
from the recorded start, transient and solver settings is the same motion; that is checked
(its stroboscopic samples must equal the recorded ones) before its samples are used.
"""
from __future__ import annotations

import logging
from typing import Any

import numpy as np

_logger = logging.getLogger(__name__)

#: the longest straight segment of a drawn trajectory, in pixels of the figure
MAX_SEGMENT_PX = 2.0
#: fewest and most samples per forcing period a trajectory is integrated again with
MIN_PER_PERIOD, MAX_PER_PERIOD = 64, 16384
#: most samples of one redrawn trajectory in all (the memory of a long run's redraw)
MAX_SAMPLES = 4_000_000
#: a run longer than this (transient and recorded forcing periods) is not integrated
#: again for a figure: its own samples are drawn
MAX_REDRAW_PERIODS = 5000


#: the last this many forcing periods of a trajectory are drawn prominently, the earlier
#: ones faint (:func:`split_recent`): two hundred periods of a chaotic motion on top of
#: each other bury the attractor
LAST_PERIODS = 10


def split_recent(traj, n_periods, last=LAST_PERIODS):
    """``(earlier, recent)``: the samples of the last ``last`` of the trajectory's
    ``n_periods`` forcing periods and those before them (sharing the sample between, so
    that the curve is unbroken; None when the run has no more than ``last`` periods).

    The samples are evenly spaced in time from the first stroboscopic sample to the last,
    ``len(traj) - 1`` intervals over ``n_periods`` periods."""
    traj = np.asarray(traj)
    if n_periods <= last or len(traj) < 2:
        return None, traj
    cut = int(round((len(traj) - 1) * (n_periods - last) / n_periods))
    return traj[:cut + 1], traj[cut:]


def pixels_per_unit(ax, span, dpi=None):
    """Pixels of ``ax`` per data unit for a square view ``span`` units across, at the
    larger of its figure's resolution and ``dpi`` (the one it is saved at)."""
    fig = ax.figure
    pos = ax.get_position()
    w, h = fig.get_size_inches()
    dpi = max(float(fig.dpi), float(dpi or 0.0))
    return min(pos.width * w, pos.height * h) * dpi / float(span)


#: the segments aimed at are this many times shorter than :data:`MAX_SEGMENT_PX`: the
#: axes' size before the figure's layout is an estimate of the drawn one
MARGIN = 2.0
#: most times a run is integrated again to reach :data:`MAX_SEGMENT_PX`
MAX_REFINES = 4


def per_period_needed(xy, per_period, px_per_unit):
    """Samples per forcing period for segments of at most :data:`MAX_SEGMENT_PX` /
    :data:`MARGIN` pixels: the samples are evenly spaced in time, so a segment's length
    scales with the time step; the longest segment of the samples ``xy`` (at
    ``per_period`` a period) sets the factor.  Bounded by :data:`MIN_PER_PERIOD` and
    :data:`MAX_PER_PERIOD`; ``per_period`` itself when its segments are short enough."""
    seg = np.hypot(*np.diff(xy, axis=0).T) * px_per_unit
    seg = seg[np.isfinite(seg)]
    if seg.size == 0:
        return MIN_PER_PERIOD
    longest = float(seg.max())
    if longest <= MAX_SEGMENT_PX / MARGIN:
        return int(per_period)
    need = int(np.ceil(per_period * MARGIN * longest / MAX_SEGMENT_PX))
    return int(min(max(need, MIN_PER_PERIOD, per_period + 1), MAX_PER_PERIOD))


def _system_and_start(value, ds):
    """``(params, state0, transient, periods, solver)`` of the recorded run, or None."""
    from .. import models
    from ..core.solver import SolverSettings

    a = ds.attrs
    if str(a.get("status", "ok")) != "ok" or "state0" not in ds:
        return None
    if hasattr(value, "strobe") and not hasattr(value, "data_vars"):   # a Run
        if value.state0 is None or value.periods is None or \
                not hasattr(value.params, "as_array"):
            return None
        params, solver = value.params, dict(value.solver or {})
        state0, transient, periods = value.state0, value.transient, value.periods
    else:
        name = a.get("model")  # none: the plot refused the dataset already
        if name not in models.names() or "periods" not in a:
            return None
        spec = {k[6:]: a[k] for k in a if k.startswith("param_")}
        param_set = models.get(name).param_set
        if param_set is None:  # no parameter set to rebuild
            return None
        try:
            params = param_set(**spec)
        except (TypeError, ValueError):
            return None
        solver = {k[7:]: a[k] for k in a if k.startswith("solver_")}
        state0 = ds["state0"].values
        transient, periods = int(a.get("transient", 0)), int(a["periods"])
    fields = set(SolverSettings.__dataclass_fields__)
    try:
        given: dict[str, Any] = {k: (bool(v) if k == "adaptive" else v)
                                 for k, v in solver.items() if k in fields}
        settings = SolverSettings(**given)
    except (TypeError, ValueError):
        return None
    return params, np.asarray(state0, float), int(transient), int(periods), settings


def fine_trajectory(value, ds, per_period):
    """``(times, states)`` of the recorded run with ``per_period`` samples per forcing
    period, integrated again; None when it cannot be made the same motion (a user
    model, a run that stopped, no recorded start, too many samples, other strobes)."""
    from ..core.simulation import simulate

    got = _system_and_start(value, ds)
    if got is None:
        return None
    params, state0, transient, periods, settings = got
    if transient + periods > MAX_REDRAW_PERIODS:
        _logger.info("xy plot: the run's %d periods are not integrated again (over %d); "
                     "its own samples are drawn", transient + periods, MAX_REDRAW_PERIODS)
        return None
    per_period = int(min(per_period, max(MIN_PER_PERIOD, MAX_SAMPLES // max(periods, 1))))
    try:
        run = simulate(params, periods=periods, transient=transient, state0=state0,
                       dense=per_period, solver=settings)
    except (TypeError, ValueError, MemoryError):
        return None
    strobe = ds["strobe"].values
    if run.dense is None or run.strobe.shape != strobe.shape or \
            not np.allclose(run.strobe, strobe, rtol=1e-9, atol=1e-12):
        _logger.info("xy plot: the run integrated again is not the recorded one; its own "
                     "samples are drawn")
        return None
    _logger.info("xy plot: trajectory integrated again with %d samples per period",
                 per_period)
    return run.t_dense, run.dense


def trajectory_for(value, ds, ax, cols, span, dpi=None):
    """The samples to draw of the trajectory (``(m, n_state)``): the dataset's
    ``trajectory``, or the run integrated again with enough samples per period for
    segments of at most :data:`MAX_SEGMENT_PX` pixels in ``ax`` saved at ``dpi``
    (``cols``: the two states drawn, ``span``: data units across the view).  None
    without a trajectory."""
    if "trajectory" not in ds:
        return None
    traj = ds["trajectory"].values
    per = int(ds.attrs.get("dense", 0) or 0)
    if per <= 0 and "time" in ds and "t_strobe" in ds and ds["t_strobe"].size > 1:
        T = float(ds["t_strobe"].values[1] - ds["t_strobe"].values[0])
        per = int(round(T / float(np.diff(ds["time"].values[:2])[0]))) \
            if ds["time"].size > 1 else 0
    if per <= 0:
        return traj
    ppu = pixels_per_unit(ax, span, dpi)
    need = per_period_needed(traj[:, cols], per, ppu)
    if need <= per:
        return traj
    fine = fine_trajectory(value, ds, need)
    if fine is None:
        return traj
    for _ in range(MAX_REFINES):   # measured on the fine curve: a corner the coarse
        again = per_period_needed(fine[1][:, cols], need, ppu)   # samples cut short
        if again <= need:
            break
        finer = fine_trajectory(value, ds, again)
        if finer is None:
            break
        fine, need = finer, again
    return fine[1]
