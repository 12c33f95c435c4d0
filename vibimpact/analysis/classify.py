"""The classifier: periodic (with its period), quasi-periodic, chaotic, or diverged.

The decision combines three independent tests -- the period test on the stroboscopic
points, the largest Lyapunov exponent with its standard error, and the 0-1 test -- by the
rule written out once, in :class:`DecisionRule` and :func:`decide`.  Everything else in
vibimpact (sweeps, interval maps, the CLI) calls :func:`classify`.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import enum
import math
from dataclasses import dataclass

import numpy as np

from ..base._text import count
from ..base import _validate as _v
from ..base._validate import WrongType
from .chaos01 import test01
from .period import detect_period

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike


class Label(str, enum.Enum):
    """What kind of motion a point is."""

    PERIODIC = "periodic"
    QUASIPERIODIC = "quasi-periodic"
    CHAOTIC = "chaotic"
    DIVERGED = "diverged"
    UNSETTLED = "unsettled"


@dataclass(frozen=True)
class DecisionRule:
    """Thresholds of the classifier, in one documented place.

    Attributes
    ----------
    period_tol : float
        Relative tolerance of the period test (:func:`detect_period`).
    max_period : int
        Longest period looked for, in forcing periods.
    z : float
        An exponent is *significantly* positive (negative) when it exceeds ``+zero``
        (falls below ``-zero``) by ``z`` standard errors.
    zero : float
        Half-width of the band around 0 in which the largest exponent counts as zero, per
        forcing period (a map exponent ``lambda T``): a stable long-period orbit and a
        torus both have exponents within a few 1e-3 of 0 per period close to their
        bifurcations.
    k_chaos : float
        The 0-1 test's ``K`` above this reads "chaotic", below it "regular"
        (Gottwald & Melbourne 2009 recommend a threshold between the limits 0 and 1).
    min_points_01 : int
        Fewest stroboscopic points on which the 0-1 test is run.

    Notes
    -----
    The rule, applied by :func:`decide` in this order; every label needs positive
    evidence, and a motion the evidence does not decide is UNSETTLED, never guessed:

    1. a non-finite or diverged run is DIVERGED;
    2. a period ``n`` found by the period test (or by Newton shooting confirmed by
       integration, :mod:`vibimpact.points.settle`) is PERIODIC with that ``n``;
       confidence 1, lowered to 0.5 if a significantly positive exponent contradicts it;
    3. with an exponent ``lambda`` (per forcing period ``lambda T``, error ``sigma T``):
       significantly positive -> CHAOTIC; significantly negative -> UNSETTLED (an
       attracting motion whose period was not found: a recurrence found by a longer
       search would have been step 2); in the zero band -> QUASIPERIODIC only with the
       0-1 test's ``K < k_chaos`` and Poincaré points that neither contract nor stop
       recurring (``torus``); UNSETTLED otherwise (a slowly contracting transient, or a
       chaotic-looking 0-1 test without a positive exponent);
    4. without an exponent the 0-1 test decides with confidence ``|2K - 1|``: CHAOTIC if
       ``K > k_chaos``, QUASIPERIODIC if ``K < k_chaos`` and the torus evidence (when
       given) holds;
    5. with no test available (or contracting points without a shooting result),
       UNSETTLED.

    Confidence is 1 when every available test agrees with the label, 0.5 when one
    disagrees or the exponent sits in the zero band, and ``|2K - 1|`` when ``K`` alone
    decided.
    """

    period_tol: float = 1e-6
    max_period: int = 64
    z: float = 3.0
    zero: float = 5e-3
    k_chaos: float = 0.5
    min_points_01: int = 100


DEFAULT_RULE = DecisionRule()


@dataclass(frozen=True)
class Regime:
    """The classifier's answer for one parameter point.

    Attributes
    ----------
    label : Label
    n : int
        Period in forcing periods (``T_motion = n 2 pi / eta``) for PERIODIC; 0 when
        unknown or not periodic.
    impacting : bool or None
        Whether the motion has contacts with the model's obstacle (None: not known, or
        a model without a contact).
    impacts_per_period : float
        Contacts per motion period (per forcing period when ``n = 0``); NaN if unknown.
    confidence : float
        In [0, 1]: how well the tests agree (see :class:`DecisionRule`).
    lyapunov, lyapunov_err : float
        Largest exponent per unit ``tau`` and its standard error (NaN: not computed).
    k01 : float
        The 0-1 test's ``K`` (NaN: not computed).
    reason : str
        The rule's branch, in words.
    """

    label: Label
    n: int = 0
    impacting: bool | None = None
    impacts_per_period: float = math.nan
    confidence: float = 1.0
    lyapunov: float = math.nan
    lyapunov_err: float = math.nan
    k01: float = math.nan
    reason: str = ""

    PERIODIC = Label.PERIODIC
    QUASIPERIODIC = Label.QUASIPERIODIC
    CHAOTIC = Label.CHAOTIC
    DIVERGED = Label.DIVERGED
    UNSETTLED = Label.UNSETTLED

    def __str__(self):
        if self.label is Label.PERIODIC:
            text = f"P{self.n}" if self.n else "periodic (long period)"
        else:
            text = self.label.value
        if self.impacting is False:
            text += " impactless"
        elif self.impacting and math.isfinite(self.impacts_per_period):
            k = self.impacts_per_period
            text += f", {count(k, 'impact')}" if k == round(k) else \
                f", {k:.2f} impacts/period"
        return text


def _finite_number(name, value, allow_nan=True):
    if value is None:
        return math.nan
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if math.isnan(v) and allow_nan:
        return v
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return v


def decide(n, lam_map, err_map, k01, rule=DEFAULT_RULE, torus=None):
    """Apply the decision rule (see :class:`DecisionRule`).

    Parameters
    ----------
    n : int
        Detected period, 0 if none.
    lam_map, err_map : float
        Largest exponent and its error per forcing period (NaN: not computed).
    k01 : float
        0-1 test ``K`` (NaN: not computed).
    torus : bool, optional
        Whether the Poincaré points neither contract nor stop recurring
        (:attr:`vibimpact.analysis.settling.TorusEvidence.torus`); None: not examined
        (array-level callers), which does not block a quasi-periodic label.

    Returns
    -------
    (Label, n, confidence, reason)
    """
    have_lam = math.isfinite(lam_map)
    err = err_map if math.isfinite(err_map) else 0.0
    pos = have_lam and lam_map - rule.z * err > rule.zero
    neg = have_lam and lam_map + rule.z * err < -rule.zero
    have_k = math.isfinite(k01)
    if n >= 1:
        if pos:
            return Label.PERIODIC, n, 0.5, "period found, but the exponent is positive"
        return Label.PERIODIC, n, 1.0, "period found"
    if have_lam:
        if pos:
            conf = 1.0 if (not have_k or k01 > rule.k_chaos) else 0.5
            return Label.CHAOTIC, 0, conf, "largest exponent significantly positive"
        if neg:
            return (Label.UNSETTLED, 0, 0.0,
                    "largest exponent negative, but no period found")
        if torus is False:
            return (Label.UNSETTLED, 0, 0.0, "exponent near zero, but the Poincaré "
                    "points contract or do not recur (no torus)")
        if not have_k or k01 < rule.k_chaos:
            return Label.QUASIPERIODIC, 0, 1.0 if have_k else 0.5, \
                "largest exponent zero within its error, points on a torus"
        return (Label.UNSETTLED, 0, 0.0,
                "exponent near zero, but the 0-1 test reads chaotic")
    if have_k:
        if k01 > rule.k_chaos:
            return Label.CHAOTIC, 0, abs(2.0 * k01 - 1.0), "0-1 test only"
        if torus is False:
            return (Label.UNSETTLED, 0, 0.0, "0-1 test regular, but the Poincaré points "
                    "contract or do not recur (no torus)")
        return Label.QUASIPERIODIC, 0, abs(2.0 * k01 - 1.0), "0-1 test only"
    return Label.UNSETTLED, 0, 0.0, "no period found and no other test available"


@_v.checks_flags
def classify(points: ArrayLike, *, lyapunov: float | None = None,
             lyapunov_err: float | None = None, period: float = 1.0,
             k01: float | None = None, impacts_per_period: float | None = None,
             diverged: bool = False, rule: DecisionRule = DEFAULT_RULE) -> Regime:
    """Classify a motion from its stroboscopic (Poincaré) points.

    Array-level: works on points from any system.

    Parameters
    ----------
    points : array_like, shape (m, d) or (m,)
        Stroboscopic samples after the transient, one per forcing period.
    lyapunov, lyapunov_err : float, optional
        Largest Lyapunov exponent per unit time and its standard error
        (e.g. from :func:`~vibimpact.analysis.lyapunov_spectrum`).
    period : float
        Time between points (forcing period ``T``), to express the exponent per period.
    k01 : float, optional
        The 0-1 test's ``K``; computed from ``points`` when omitted, no period is found
        and there are at least ``rule.min_points_01`` points.
    impacts_per_period : float, optional
        Contacts per forcing period (``impacting`` is derived from it).
    diverged : bool
        The run blew up; the label is DIVERGED whatever the points say.
    rule : DecisionRule

    Returns
    -------
    Regime

    Examples
    --------
    >>> import numpy as np
    >>> from vibimpact.analysis import classify
    >>> str(classify(np.tile([[0.0], [1.0], [2.0]], (30, 1))))
    'P3'
    """
    if hasattr(points, "strobe"):  # a Run (or anything holding stroboscopic samples)
        raise TypeError(f"points must be an array of stroboscopic samples, got "
                        f"{type(points).__name__}; pass its .strobe")
    if points is None or isinstance(points, (str, bytes, dict)):
        raise WrongType(f"points must be an array of stroboscopic samples, got "
                        f"{type(points).__name__}")
    if diverged:
        return Regime(Label.DIVERGED, confidence=1.0, reason="the run diverged")
    pts = _v.numeric("points", points, "an array of stroboscopic samples")
    if pts.ndim == 1:
        pts = pts[:, None]
    if pts.ndim != 2 or pts.shape[0] < 2:
        raise ValueError(f"points must have shape (m >= 2, d), got {np.shape(points)}")
    if not np.all(np.isfinite(pts)):
        return Regime(Label.DIVERGED, confidence=1.0, reason="non-finite points")
    period = _finite_number("period", period, allow_nan=False)
    if period <= 0.0:
        raise ValueError(f"period must be > 0, got {period}")
    lam = _finite_number("lyapunov", lyapunov)
    err = _finite_number("lyapunov_err", lyapunov_err)
    k = _finite_number("k01", k01)
    ipp = _finite_number("impacts_per_period", impacts_per_period)
    n = detect_period(pts, tol=rule.period_tol, max_period=rule.max_period)
    if n == 0 and math.isnan(k) and pts.shape[0] >= rule.min_points_01:
        k = test01(pts[:, int(np.argmax(np.ptp(pts, axis=0)))])
    label, n, conf, reason = decide(n, lam * period, err * period, k, rule)
    impacting = None if math.isnan(ipp) else bool(ipp > 0.0)
    per = ipp * n if (n >= 1 and math.isfinite(ipp)) else ipp
    return Regime(label, n, impacting, per, conf, lam, err, k, reason)
