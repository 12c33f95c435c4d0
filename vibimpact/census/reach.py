"""Where one start goes: integrate until it is known which attractor it reaches.

:func:`reach` integrates a starting state chunk by chunk and stops as soon as

1. its stroboscopic points *enter* an attractor already found at this parameter point
   (:func:`vibimpact.census.library.entered`: ``hold`` consecutive points within the
   attractor's radius, as Attractors.jl's recurrence algorithm decides), or
2. failing that within ``max_periods``, the sweep's own settling evidence decides
   (:func:`vibimpact.points.point.analyse_point` from where the start has got to: the
   period test on recurring stroboscopic points, contraction and Newton shooting, the
   Lyapunov exponent and the 0-1 test).  A new periodic orbit is recognised there by
   recurrence; a non-periodic motion gets a cloud of ``cloud`` further stroboscopic
   points to be known by.

:class:`CensusRound` is the engine's policy that runs a task's starts this way, each
against the library of its parameter point as it stood before the round (so the result
never depends on which process runs which start).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..base import _limits
from ..base import _validate as _v
from ..points.point import ANALYSES, REGIME_CODES, SweepSettings, analyse_point, \
    point_system
from ..analysis.classify import Label
from ..analysis.period import detect_period
from ..core.run import Status
from ..core.solver import Solver
from ..core.system import with_frequency
from .library import entered

__all__ = ["CensusSettings", "CensusRound", "reach", "ENTERED", "ANALYSED", "DIVERGED",
           "FAILED", "FAILED_LABEL", "ESCAPED_LABEL", "failed_integration"]

#: how a start's attractor was decided (``decided_by`` of a census): it entered one
#: found already, the settling evidence decided, the motion diverged (the state left the
#: solver's bound or became non-finite: an escape, counted as the pseudo-attractor
#: "diverged"), or the integration failed (the solver could not go on: step-size
#: underflow, the step limit, Zeno events; no attractor at all, counted apart)
ENTERED, ANALYSED, DIVERGED, FAILED = 0, 1, 2, 3
DECIDED_FLAGS = "entered_known_attractor settled_by_analysis diverged integration_failed"
#: the label of a start whose integration failed (on no attractor; a census dataset
#: keeps it) and, until the dataset gives it the "diverged" pseudo-attractor's index, of
#: a start whose motion diverged
FAILED_LABEL, ESCAPED_LABEL = -1, -3

PERIODIC = REGIME_CODES[Label.PERIODIC]


def _point_settings():
    return SweepSettings(analyses=tuple(a for a in ANALYSES if a != "response"),
                         transient_max=3000, predict=0)


#: most stroboscopic points that represent one non-periodic attractor (``cloud``)
MAX_CLOUD = 100_000


@dataclass(frozen=True)
class CensusSettings:
    """How a census decides where each start goes.

    Attributes
    ----------
    max_periods : int
        Forcing periods a start is integrated against the known attractors before the
        settling evidence decides (:func:`reach`).
    chunk : int
        Periods between checks.
    radius : float
        A periodic orbit's radius, in units of the start box's scale: a point this close
        to one of its cycle points counts as on it (at most half its distance to
        the nearest other attractor, so that no radius reaches another attractor).
    hold : int
        Consecutive points within the radius that enter a periodic orbit (at least its
        period ``n``).
    hold_chaotic : int
        The same for a non-periodic attractor.
    cloud : int
        Stroboscopic points that represent a non-periodic attractor.
    dedup_tol : float
        Periodic cycles closer than this (units of the box's scale) are one orbit.
    point : SweepSettings
        The settling evidence's settings (a transient of up to 3000 periods, no
        continuation predictor).

    Raises
    ------
    ValueError
        Naming the field: the counts are at least 1 and at most the period limit of a
        run (``vibimpact.base._limits.MAX_PERIODS``; ``cloud`` at most :data:`MAX_CLOUD`).
    """

    max_periods: int = 600
    chunk: int = 16
    radius: float = 0.05
    hold: int = 8
    hold_chaotic: int = 64
    cloud: int = 1000
    dedup_tol: float = 1e-4
    point: SweepSettings = field(default_factory=_point_settings)

    def __post_init__(self):
        for name in ("max_periods", "chunk", "hold", "hold_chaotic", "cloud"):
            top = MAX_CLOUD if name == "cloud" else _limits.MAX_PERIODS
            object.__setattr__(self, name, _v.count(name, getattr(self, name), 1, top))
        for name in ("radius", "dedup_tol"):
            value = getattr(self, name)
            if isinstance(value, (bool, np.bool_)) or not isinstance(
                    value, (int, float, np.floating, np.integer)) or \
                    not np.isfinite(value) or value <= 0:
                raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
            object.__setattr__(self, name, float(value))
        if not isinstance(self.point, SweepSettings):
            raise _v.WrongType(f"point must be a vibimpact.SweepSettings, got "
                               f"{type(self.point).__name__}")

    def as_attrs(self) -> dict:
        """Flat attributes (the point settings prefixed ``point_``)."""
        out = {k: getattr(self, k) for k in ("max_periods", "chunk", "radius", "hold",
                                             "hold_chaotic", "cloud", "dedup_tol")}
        out.update({f"point_{k}": v for k, v in self.point.as_attrs().items()})
        return out


#: the end of a stop's reason when the run's very first step stopped it (the state
#: was inside the bound at the start: one step cannot be an escape of the motion)
FIRST_STEP = "at t = 0 (forcing period 0)"


def failed_integration(status, reason) -> bool:
    """Whether a run that stopped with ``status`` and ``reason`` is a failure of the
    solver rather than an escape of the motion: ``Status.FAILED`` (step-size underflow,
    the step limit, Zeno events), or a divergence on the run's very first step (the state
    left the bound or became non-finite in one step from a start inside it: the
    equations are too stiff for the solver, their parameters too extreme)."""
    return status is Status.FAILED or (status is Status.DIVERGED
                                       and str(reason).endswith(FIRST_STEP))


def _stopped(status, reason, periods):
    """The result of a start whose integration stopped with ``status`` (not OK): diverged
    (an escape of the motion) or failed (the solver's failure,
    :func:`failed_integration`), with the reason."""
    how = FAILED if failed_integration(status, reason) else DIVERGED
    if how == FAILED and status is Status.DIVERGED:
        reason = f"{reason}: on the first step, too stiff or extreme for the solver"
    return dict(decided_by=how, entered=-1, periods=int(periods),
                regime=REGIME_CODES[Label.DIVERGED], reason=str(reason))


def _status_of_point(reason):
    """The :class:`Status` of a point the settling evidence marked diverged, from its
    reason (``"<where>: <status>, <why>"``, :meth:`vibimpact.points.point.PointResult.
    diverged`)."""
    head = str(reason).split(", ", 1)[0]
    return Status.FAILED if head.endswith(f": {Status.FAILED.value}") else \
        Status.DIVERGED


def reach(system, x0, library, cs: CensusSettings) -> dict:
    """Integrate ``x0`` until it is known which attractor it reaches.

    Parameters
    ----------
    system : System
        At the census point (its solver settings resolved).
    x0 : ndarray, shape (d,)
    library : sequence of Attractor
        The attractors known at this point before the start's round.
    cs : CensusSettings

    Returns
    -------
    dict
        ``decided_by`` (:data:`ENTERED`, :data:`ANALYSED`, :data:`DIVERGED` or
        :data:`FAILED`, with the solver's ``reason`` for the last two),
        ``entered`` (index into ``library``, or -1), ``periods`` (forcing periods
        integrated), and for an analysed start the fields of
        :func:`vibimpact.points.point.analyse_point` plus ``cloud`` (its cycle points,
        or ``cs.cloud`` stroboscopic points of a non-periodic motion).
    """
    x = np.array(x0, dtype=np.float64)
    periods = 0
    if library:
        solver = Solver(system, x, check=False)
        counts = np.zeros(len(library), dtype=np.int64)
        first = np.zeros(len(library))
        while periods < cs.max_periods:
            step = min(cs.chunk, cs.max_periods - periods)
            seg = solver.advance(step, events=False)
            if seg.status is not Status.OK:
                return _stopped(seg.status, f"entering an attractor: {seg.status.value}, "
                                f"{seg.reason}", periods + step)
            periods += step
            assert seg.strobe is not None  # step >= 1 periods
            hit = entered(seg.strobe[1:], library, (counts, first))
            if hit >= 0:
                return dict(decided_by=ENTERED, entered=int(hit), periods=periods)
        x = solver.y[:x.size].copy()
    res, cloud, used = _settled(system, x, cs, periods)
    if res is None:
        status, reason = cloud
        return _stopped(status, reason, used)
    res.update(decided_by=ANALYSED, entered=-1, periods=used, cloud=cloud)
    return res


#: a motion the settling evidence finds non-periodic is watched for this many clouds
#: (``cloud`` periods each) for a period it comes to (transient chaos ending on a periodic
#: orbit, long at low damping) before it stands as non-periodic, and the evidence is asked
#: again at most this many times
SETTLE_AGAIN = 3
#: relative tolerance of that look: the cloud's last 193 points repeating to 1 % of
#: their magnitude (no chaotic or quasi-periodic motion does so for that long; an orbit
#: still closing in slowly does, and the settling evidence then finds it to the period
#: test's own tolerance)
CLOUD_PERIOD_TOL = 1e-2


def _settled(system, x, cs, periods):
    """``(result, cloud, periods used)`` of the settling evidence from ``x``; ``(None,
    (status, reason), periods)`` when the integration stopped (diverged or failed).

    A motion the evidence finds non-periodic is watched for :data:`SETTLE_AGAIN` clouds of
    ``cs.cloud`` stroboscopic points; when the end of one repeats with a period (a
    chaotic transient, long at low damping, has ended on a periodic orbit), the evidence
    is asked again from there, at most :data:`SETTLE_AGAIN` times, so that a transient is
    not taken for an attractor.  The last cloud represents a non-periodic attractor."""
    used = periods
    for _ in range(SETTLE_AGAIN + 1):
        res = analyse_point(system, x, cs.point).as_dict()
        used += int(res.get("transient") or 0) + int(res.get("recorded") or 0)
        if res["regime"] == REGIME_CODES[Label.DIVERGED]:
            why = res.get("reason", "")
            return None, (_status_of_point(why), why), used
        n = int(res["period"]) if res["regime"] == PERIODIC else 0
        if n > 0:
            return res, np.asarray(res["samples"])[:n].copy(), used
        cloud, used, periodic = _watch(system, np.asarray(res["final_state"]), cs, used)
        if cloud is None:
            return None, periodic, used
        if not periodic:
            return res, cloud, used
        x = cloud[-1].copy()
    return res, cloud, used


@dataclass(frozen=True, eq=False)
class CensusRound:
    """The engine policy of one census round: every start of a task from its own state,
    decided by :func:`reach` against its point's library as it stood before the round.

    Attributes
    ----------
    libraries : tuple of tuple of Attractor
        One per parameter point (the task's ``row``).
    census : CensusSettings
    """

    libraries: tuple
    census: CensusSettings
    blocks: int = 1

    continued = False

    def seeds(self, p: Any, etas: np.ndarray, starts, state0) -> dict:
        return {a: state0 for a in starts}

    def run(self, task: Any, on_point=None) -> list:
        """The task's starts in order (see :func:`vibimpact.engine.plan.run_task`)."""
        out = []
        system = None
        for i in range(task.start, task.stop):
            res = task.done.get(i)
            if res is None:
                if system is None:
                    system = point_system(with_frequency(task.p, float(task.etas[i])),
                                          self.census.point)
                res = reach(system, task.state_at(i), self.libraries[task.row],
                            self.census)
                if on_point is not None:
                    on_point(task, i, res)
            out.append((i, res))
        return out


def _watch(system, x, cs, used):
    """``(cloud, periods used, periodic)``: up to :data:`SETTLE_AGAIN` clouds integrated
    from ``x``, stopping at the first whose end repeats with a period (``cloud`` None:
    the run stopped, ``periodic`` then its ``(status, reason)``)."""
    tail_len = 3 * cs.point.rule.max_period + 1
    solver = Solver(system, x, check=False)
    cloud = None
    for _ in range(SETTLE_AGAIN):
        seg = solver.advance(cs.cloud, events=False)
        used += cs.cloud
        if seg.status is not Status.OK:
            return None, used, (seg.status, f"cloud: {seg.status.value}, {seg.reason}")
        assert seg.strobe is not None  # cs.cloud >= 1 periods
        cloud = seg.strobe[1:].copy()
        if detect_period(cloud[-min(cloud.shape[0], tail_len):], tol=CLOUD_PERIOD_TOL,
                         max_period=cs.point.rule.max_period):
            return cloud, used, True
    return cloud, used, False
