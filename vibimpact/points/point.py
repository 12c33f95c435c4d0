"""One point of a sweep: settle the transient, then measure only what is asked.

:func:`analyse_point` is a pure function of ``(system, state0, settings)``: the same
input gives the same numbers in any process, which makes parallel sweeps and resumed
sweeps bit-identical to serial, uninterrupted ones.  It is two steps:
:func:`vibimpact.points.transient.settle` (the transient, ended early, and the record) and
:func:`vibimpact.points.measure.measure` (the analyses the request asks for), and it
returns a typed :class:`PointResult`.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import logging
from dataclasses import asdict, dataclass, field, fields

import numpy as np

from ..base._fill import not_computed
from ..analysis.classify import DecisionRule, Label
from ..core.system import System
from .codes import (CONTACT_FLAGS, CONTACT_IMPACTING, CONTACT_NONE, CONTACT_PERMANENT,
                    REGIME_CODES, REGIME_FLAGS)
from .logtext import Lazy, point as point_text
from .measure import measure
from .settle import MAX_SHOTS
from .transient import settle

_log = logging.getLogger(__name__)

if TYPE_CHECKING:  # names of the annotations only
    from typing import Any

    from numpy.typing import ArrayLike

    from ..models.params import DuffingParams, Params
    from ..core.run import Status

__all__ = ["ANALYSES", "SweepSettings", "PointResult", "SCALARS", "analyse_point",
           "point_system", "REGIME_CODES", "REGIME_FLAGS", "CONTACT_FLAGS",
           "CONTACT_NONE", "CONTACT_IMPACTING", "CONTACT_PERMANENT"]

#: analyses a sweep can compute ("period" always runs: it ends the transient)
ANALYSES = ("period", "impacts", "response", "poincare", "lyapunov", "test01", "floquet")


@dataclass(frozen=True)
class SweepSettings:
    """What each sweep point computes, and how long it integrates.

    Attributes
    ----------
    analyses : tuple of str
        Subset of :data:`ANALYSES`.
    transient_max : int
        Longest transient in forcing periods; it ends earlier as soon as the stroboscopic
        points repeat with a period ``n`` (checked every ``chunk`` periods).
    chunk : int
        Periods between convergence checks; after an extrapolation jump the next check
        comes as soon as the period test's shortest window is full
        (:data:`CHUNK_AFTER_JUMP` periods).
    extrapolate : int
        Jumps of the transient at most: when the stroboscopic points of a chunk close in
        geometrically on an ``n``-cycle (every ``n``-th point, ``n <= 4``, moving less than
        1 % of the orbit's magnitude and its steps shrinking), the transient restarts from
        their limit by minimal polynomial extrapolation
        (:func:`vibimpact.analysis.extrapolate_limit`) instead of waiting for the slowest
        Floquet mode to decay.  The period is still only accepted from integrated points
        repeating to the rule's tolerance, and, since extrapolation finds saddles as
        readily as attractors, only if the orbit's Floquet multipliers lie inside the
        unit circle (otherwise the transient resumes from before the jump, without
        further jumps); 0 turns this off.
    shoot : int
        Newton-shooting attempts at most per point (:mod:`vibimpact.points.settle`):
        where the transient's stroboscopic points contract too slowly to settle within
        ``transient_max``, the orbit they approach is sought by shooting and accepted on
        evidence, confirmed by integrating from it; 0 turns this off.
    predict : int
        Continuation's predictor (:mod:`vibimpact.points.predict`): after this many
        consecutive period-1 points, a point is first tried from the polynomial
        extrapolation of their states (``guess`` of :func:`analyse_point`); 0 turns this
        off.  The default, 4 (a cubic), lands close enough for the first record to be
        periodic at about 2 of 3 points of a period-1 branch.
    record : int
        Periods recorded where the transient did not converge to a periodic orbit (0-1
        test, impacts per period, Poincaré samples): the transient's last chunks, logged
        with their events as they are integrated and still checked for a period, at least
        ``record`` periods of one trajectory (130 of the 200 with the defaults; the
        exponent then starts where they end).  Only when an extrapolation jump cut them
        short are they recorded after the transient instead.
    record_periodic : int
        At least this many periods (and at least 4 motion periods) recorded on a
        converged periodic orbit.
    n_samples : int
        Poincaré samples stored per point (a periodic orbit's cycle is repeated to fill).
    dense : int
        Samples per period used, and discarded, to find the response maxima X_m, Y_m.
    lyapunov : {"auto", "always"}
        "auto": the largest exponent only where no period is found.
    lyap_min, lyap_max, lyap_target : int, int, float
        Periods and target standard error (per unit tau) of the largest exponent.
    rule : DecisionRule
    method, rtol, atol : integrator settings
        ``rtol = 1e-8`` by default: the period test's tolerance (1e-6 of the orbit's size)
        is met with margin, and a sweep runs about 15 % faster than at 1e-9.
    """

    analyses: tuple = ANALYSES
    transient_max: int = 200
    chunk: int = 10
    extrapolate: int = 5
    shoot: int = MAX_SHOTS
    predict: int = 4
    record: int = 128
    record_periodic: int = 8
    n_samples: int = 64
    dense: int = 48
    lyapunov: str = "auto"
    lyap_min: int = 100
    lyap_max: int = 600
    lyap_target: float = 3e-3
    rule: DecisionRule = DecisionRule()
    method: str = "dop853"
    rtol: float = 1e-8
    atol: float = 1e-11

    def as_attrs(self) -> dict[str, Any]:
        """Flat dict for dataset attributes."""
        d = asdict(self)
        rule = d.pop("rule")
        d["analyses"] = ",".join(self.analyses)
        d.update({f"rule_{k}": v for k, v in rule.items()})
        return d


def _nan(n):
    return not_computed(n)


@dataclass
class PointResult:
    """The results of one point (NaN, or the integer fill, where not computed).

    The scalar fields are what datasets store per point (:data:`SCALARS` gives their
    fill values); ``arcs`` and ``reason`` are text; the arrays have the model's state
    size ``d`` (:meth:`empty`; a bare ``PointResult()`` has arrays of no state, as it
    knows no model).

    Attributes
    ----------
    regime : int
        :data:`REGIME_CODES` of the label (0: not decided).
    period : int
        Period in forcing periods (0: none).
    confidence, impacts_per_period, impacts_constant, contact, lyapunov, lyapunov_err,
    k01, X_m, Y_m, R_m, min_gap, n_arcs, v_impact_max, v_impact_mean, penetration_max,
    transient, recorded, floquet_abs_max, stable, floquet_exponent, contraction,
    settle_periods, shoot_residual, orbit_distance
        See the dataset variables of :func:`vibimpact.sweep`.
    arcs : str
        Loaded arcs of the contact (where on the obstacle the contacts fall), e.g. "2
        small arcs".
    reason : str
        Why the label (or why the run stopped).
    arc_table : ndarray, shape (n_arcs, 4)
        Loaded arcs: start, end, width (degrees) and loaded share
        (:meth:`vibimpact.analysis.ContactArcs.table`).
    samples : ndarray, shape (n_samples, d)
        Poincaré points.
    final_state : ndarray, shape (d,)
        Where the point ended: the next point of a continuation starts there.
    orbit_point : ndarray, shape (d,)
        The fixed point of a period-1 orbit (the continuation's predictor).
    multipliers : ndarray of complex, shape (d,)
        Floquet multipliers of a periodic point.
    """

    regime: int = 0
    period: int = 0
    confidence: float = np.nan
    impacts_per_period: float = np.nan
    impacts_constant: int = 0
    contact: int = -1
    lyapunov: float = np.nan
    lyapunov_err: float = np.nan
    k01: float = np.nan
    X_m: float = np.nan
    Y_m: float = np.nan
    R_m: float = np.nan
    min_gap: float = np.nan
    n_arcs: int = 0
    v_impact_max: float = np.nan
    v_impact_mean: float = np.nan
    penetration_max: float = np.nan
    transient: int = 0
    recorded: int = 0
    floquet_abs_max: float = np.nan
    stable: int = -1
    floquet_exponent: float = np.nan
    contraction: float = np.nan
    settle_periods: float = np.nan
    shoot_residual: float = np.nan
    orbit_distance: float = np.nan
    arcs: str = ""
    reason: str = ""
    arc_table: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))
    samples: np.ndarray = field(default_factory=lambda: not_computed((0, 0)))
    final_state: np.ndarray = field(default_factory=lambda: _nan(0))
    orbit_point: np.ndarray = field(default_factory=lambda: _nan(0))
    multipliers: np.ndarray = field(default_factory=lambda: not_computed(0, complex))

    @classmethod
    def empty(cls, n_state: int, n_samples: int) -> PointResult:
        """Nothing computed yet, for a model of ``n_state`` variables."""
        return cls(samples=not_computed((n_samples, n_state)), final_state=_nan(n_state),
                   orbit_point=_nan(n_state),
                   multipliers=not_computed(n_state, complex))

    def update(self, **values) -> None:
        """Set several fields."""
        for k, v in values.items():
            setattr(self, k, v)

    def diverged(self, status: Status, reason: str, where: str) -> PointResult:
        """Mark the point diverged: the integration stopped ``where``."""
        self.regime = REGIME_CODES[Label.DIVERGED]
        self.confidence = 1.0
        self.reason = f"{where}: {status.value}, {reason}"
        return self

    def as_dict(self) -> dict[str, Any]:
        """``{field: value}``: what checkpoints and datasets store."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


_ARRAYS = ("arcs", "reason", "samples", "final_state", "orbit_point", "multipliers",
           "arc_table")
#: scalar result fields of a point, with their fill value
SCALARS = {f.name: f.default for f in fields(PointResult) if f.name not in _ARRAYS}


def point_system(p, settings):
    """``p`` (Params or System) as the System a point is analysed with: the solver
    settings of ``settings`` for those a System leaves None."""
    system = p if isinstance(p, System) else System(p)
    return system.resolved(method=settings.method, rtol=settings.rtol, atol=settings.atol)


def analyse_point(p: Params | DuffingParams | System, state0: ArrayLike | None,
                  settings: SweepSettings, guess: ArrayLike | None = None) -> PointResult:
    """Analyse one parameter point.

    Parameters
    ----------
    p : Params or System
        A System's own solver settings take precedence over those of ``settings``.
    state0 : ndarray, shape (4,) or None
        Initial state at tau = 0 (rest when None).
    settings : SweepSettings
    guess : ndarray, shape (4,), optional
        A predicted point of a period-1 orbit (a continuation's predictor,
        :func:`vibimpact.points.predict.extrapolate_branch`).  The record is integrated
        from it first; when its stroboscopic points already repeat (period 1 or 2, to the
        rule's tolerance, over the whole record) and the orbit attracts (Floquet
        multipliers inside the unit circle), that run is the record and the transient is
        0.  Otherwise the transient goes on from the run's end like after an extrapolation
        jump: a period found later is accepted only on an attracting orbit, or the
        transient restarts from ``state0`` with neither guess nor jumps.

    Returns
    -------
    PointResult

    Notes
    -----
    The transient's budget and its "has it settled?" test follow the motion's own
    contraction.  Points that repeat to the period test's tolerance have settled only
    when the geometric tail of their steps (the distance still to go, from the measured
    rate) is within that tolerance too; otherwise the orbit is refined by shooting (the
    period test's ``n`` stands when shooting fails).  At every check where
    the points neither repeat nor allow an extrapolation jump, their contraction rate
    (:func:`vibimpact.analysis.settling.contraction_rate`) says how many periods they
    still need; when that exceeds what is left of ``transient_max``, the attractor is
    sought by Newton shooting instead (:mod:`vibimpact.points.settle`) and accepted only
    on evidence, confirmed by integrating from it.  A motion that no evidence decides is
    labelled UNSETTLED with its contraction rate and the periods it would need.
    """
    system = point_system(p, settings)
    res = PointResult.empty(system.n_state, settings.n_samples)
    x = np.zeros(system.n_state) if state0 is None else \
        np.asarray(state0, dtype=np.float64).copy()
    settled = settle(system, x, settings, guess)
    if settled.failure is not None:
        res = res.diverged(*settled.failure)
    else:
        res = measure(system, settled, settings, res)
    _log.debug("%s", Lazy(point_text, system.omega, res))
    return res
