"""Impacts of the rotor on its retainer: counts per period, loaded arcs, wear statistics.

The paper [1] describes its regimes by impacts per period ("period 3 with 8 impacts") and
where they fall ("bottom half", "two small loaded arcs", "whole circle"); :func:`impact_count`
and :func:`contact_arcs` turn :attr:`vibimpact.Run.impacts` into those words, and
:func:`impact_statistics` gives the speeds and penetrations that govern retainer wear.
Angles are ``theta = atan2(Y, X)`` in degrees in (-180, 180]; gravity acts along +Y, so the
bottom of the retainer is theta = +90 deg and the top -90 deg (gravity acts along +Y).

References
----------
.. [1] L. Pust, J. Kozanek, "Vibrations of rotor supported in magnetic bearings with
   impacts", Institute of Thermomechanics AS CR (the paper this project implements).
.. [2] F. Peterka, "Bifurcations and transition phenomena in an impact oscillator", Chaos
   Solitons Fractals 7 (1996) 1635-1647 (impact motions labelled by impacts per period).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numbers
from dataclasses import asdict, dataclass

import numpy as np

from .. import _validate as _v
from .._text import count

if TYPE_CHECKING:  # names of the annotations only
    from typing import Any

    from numpy.typing import ArrayLike

__all__ = ["ImpactCount", "impact_count", "ContactArcs", "contact_arcs", "ImpactStatistics",
           "impact_statistics", "SMALL_ARC_WIDTH", "MAX_SMALL_ARCS", "HALF_TOLERANCE",
           "WHOLE_CIRCLE_GAP"]

#: an arc narrower than this (degrees) is "small"
SMALL_ARC_WIDTH = 30.0
#: at most this many small arcs are reported as "k small arcs"
MAX_SMALL_ARCS = 4
#: tolerance (degrees) of "all angles within the bottom / top half"
HALF_TOLERANCE = 2.0
#: the contacts cover the "whole circle" when no empty gap is this wide (degrees)
WHOLE_CIRCLE_GAP = 90.0


def _frozen_array(values, dtype=np.float64):
    a = np.array(values, dtype=dtype)
    a.flags.writeable = False
    return a


@dataclass(frozen=True, eq=False)
class ImpactCount:
    """Impacts per window of ``period`` forcing periods.

    Attributes
    ----------
    counts : ndarray of int, shape (n_windows,)
        Impacts in each complete window ``[w * period, (w + 1) * period)``.
    per_period, per_forcing_period : float
        Mean of ``counts`` (impacts per period of the motion), and ``per_period / period``.
    constant : bool
        All windows hold the same number of impacts (as on an orbit of this period).
    period : int
        Window length in forcing periods.
    """

    counts: np.ndarray
    per_period: float
    per_forcing_period: float
    constant: bool
    period: int


def impact_count(impact_period: ArrayLike, n_periods: int, period: int = 1) -> ImpactCount:
    """Count impacts in consecutive windows of ``period`` forcing periods.

    Parameters
    ----------
    impact_period : array_like of int, shape (n_impacts,)
        Forcing period index of each impact, from 0 at the recorded start
        (:attr:`vibimpact.Run.impacts` ``["period"]``).
    n_periods : int
        Forcing periods recorded (``len(run.strobe) - 1``), ``>= period``.
    period : int
        Window length, e.g. the period ``n`` of :func:`detect_period`; ``>= 1``.

    Returns
    -------
    ImpactCount
        Only the ``n_periods // period`` complete windows are counted; impacts with an index
        at or beyond their end (an incomplete last window) are left out.

    Raises
    ------
    ValueError
        Naming the argument: ``impact_period`` not 1-D integers >= 0, ``n_periods`` or
        ``period`` not integers >= 1, ``n_periods < period``.

    Examples
    --------
    >>> c = impact_count([0, 0, 0, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 5, 5, 5, 6], 7, period=3)
    >>> c.per_period, c.constant
    (8.0, True)
    """
    idx = np.asarray(impact_period)
    if idx.dtype.kind not in "iuf":  # None, text, a Run's impact records, booleans
        raise _v.WrongType(f"impact_period must be a 1-D array of integer period "
                           f"indices >= 0, got {type(impact_period).__name__} of "
                           f"dtype {idx.dtype}")
    integral = idx.size == 0 or idx.dtype.kind in "iu" or (
        idx.dtype.kind == "f" and np.all(np.isfinite(idx)) and np.all(idx == np.round(idx)))
    if idx.ndim != 1 or not integral or np.any(idx < 0):
        raise ValueError("impact_period must be a 1-D array of integer period indices >= 0")
    idx = idx.astype(np.int64)
    n_periods, period = _v.count("n_periods", n_periods, 1), _v.count("period", period, 1)
    if n_periods < period:
        raise ValueError(f"n_periods must be >= period ({period}), got {n_periods}")
    n_windows = n_periods // period
    window = idx[idx < n_windows * period] // period
    counts = np.bincount(window, minlength=n_windows)
    return ImpactCount(_frozen_array(counts, np.int64), float(counts.mean()),
                       float(counts.mean() / period), bool(counts.min() == counts.max()), period)


@dataclass(frozen=True, eq=False)
class ContactArcs:
    """Arcs of the retainer circle where the rotor hits it.

    Attributes
    ----------
    start, end : ndarray, shape (n_arcs,)
        First and last angle of each arc, degrees in (-180, 180]; the arc runs in the
        direction of increasing theta from ``start`` to ``end``, so an arc through 180 deg
        has ``start > end``.  Sorted by ``start``.
    width : ndarray, shape (n_arcs,)
        Angular extent ``(end - start) mod 360`` (0 for a single point).
    share : ndarray, shape (n_arcs,)
        Fraction of the angles in each arc (sums to 1).
    n_arcs : int
    largest_gap : float
        Widest empty circular gap between contacts, degrees (360 without angles).
    summary : str
        The paper's words, see :func:`summarize_arcs`.
    """

    start: np.ndarray
    end: np.ndarray
    width: np.ndarray
    share: np.ndarray
    n_arcs: int
    largest_gap: float
    summary: str

    def to_text(self) -> str:
        """E.g. ``"2 small arcs (84..97°, 120..131°)"``; ``"none"`` without contacts."""
        deg = [(f"{s:.0f}".replace("-0", "0"), f"{e:.0f}".replace("-0", "0"))
               for s, e in zip(self.start, self.end)]   # "-0" only: no zero padding
        arcs = ", ".join(f"{s}°" if s == e else f"{s}..{e}°" for s, e in deg)
        return f"{self.summary} ({arcs})" if self.n_arcs else self.summary
    __str__ = to_text


def summarize_arcs(theta, width, largest_gap):
    """The paper's words for a set of contact angles (the one place they are decided).

    ``theta`` (m,) are the angles in (-180, 180], ``width`` (n_arcs,) the arc widths and
    ``largest_gap`` the widest empty gap, all in degrees.  First matching rule wins:

    1. no angles: ``"none"``;
    2. at most :data:`MAX_SMALL_ARCS` arcs, each narrower than :data:`SMALL_ARC_WIDTH`:
       ``"1 small arc"`` / ``"k small arcs"``;
    3. all angles in the bottom half [0, 180] deg (+-:data:`HALF_TOLERANCE`):
       ``"bottom half"``; in the top half [-180, 0]: ``"top half"``;
    4. largest empty gap narrower than :data:`WHOLE_CIRCLE_GAP`: ``"whole circle"``;
    5. otherwise ``"1 arc"`` / ``"k arcs"``.
    """
    k, tol = len(width), HALF_TOLERANCE
    if theta.size == 0:
        return "none"
    if k <= MAX_SMALL_ARCS and np.all(np.asarray(width) < SMALL_ARC_WIDTH):
        return count(k, "small arc")
    for half, t in (("bottom half", theta), ("top half", -theta)):
        if np.all((t >= -tol) | (t <= -180.0 + tol) | (t >= 180.0 - tol)):
            return half
    if largest_gap < WHOLE_CIRCLE_GAP:
        return "whole circle"
    return count(k, "arc")


def contact_arcs(angles: ArrayLike, gap: float = 10.0) -> ContactArcs:
    """Group contact angles into arcs of the retainer circle and describe them.

    Angles are sorted on the circle and split wherever the circular gap between neighbours
    exceeds ``gap``; a cluster across +-180 deg is one arc.

    Parameters
    ----------
    angles : array_like, shape (m,)
        Contact angles ``theta`` in degrees (:attr:`vibimpact.Run.impacts` ``["theta"]``);
        any finite value, wrapped to (-180, 180].
    gap : float
        Largest gap (degrees) inside one arc, in (0, 360).

    Returns
    -------
    ContactArcs

    Raises
    ------
    ValueError
        Naming the argument: ``angles`` not 1-D or not finite, ``gap`` outside (0, 360).

    Examples
    --------
    >>> str(contact_arcs([175.0, 179.0, -178.0, -176.0]))
    '1 small arc (175..-176°)'
    """
    theta = _v.array1d("angles", angles)
    if np.ndim(angles) != 1 or not np.all(np.isfinite(theta)):
        raise ValueError(f"angles must be 1-D and finite, got shape {theta.shape}")
    if isinstance(gap, bool) or not isinstance(gap, numbers.Real) or not 0.0 < gap < 360.0:
        raise ValueError(f"gap must be a number in (0, 360) degrees, got {gap!r}")
    if theta.size == 0:
        return ContactArcs(*[_frozen_array([])] * 4, 0, 360.0, "none")
    theta = np.mod(theta + 180.0, 360.0) - 180.0          # wrap to (-180, 180]
    theta[theta <= -180.0] = 180.0
    s = np.sort(theta)
    # gaps[i]: empty arc after s[i] going up to the next angle (the last one wraps round)
    gaps = np.append(np.diff(s), s[0] + 360.0 - s[-1])
    largest = int(np.argmax(gaps))
    # walk the circle starting just after the largest gap, so no arc straddles the start
    ring, ring_gaps = np.roll(s, -(largest + 1)), np.roll(gaps, -(largest + 1))
    cut = np.flatnonzero(ring_gaps[:-1] > gap)          # arc ends inside the walk
    first, last = np.r_[0, cut + 1], np.r_[cut, s.size - 1]
    inner = np.concatenate([[0.0], np.cumsum(ring_gaps[:-1])])   # angle walked from start
    width, share = inner[last] - inner[first], (last - first + 1) / s.size
    start, end = ring[first], ring[last]
    o = np.argsort(start, kind="stable")
    largest_gap = float(gaps[largest])
    return ContactArcs(*(_frozen_array(a[o]) for a in (start, end, width, share)),
                       n_arcs=int(first.size), largest_gap=largest_gap,
                       summary=summarize_arcs(theta, width, largest_gap))


@dataclass(frozen=True)
class ImpactStatistics:
    """Wear-relevant statistics of a set of contacts (NaN where there are none).

    Attributes
    ----------
    count : int
    mean_speed, max_speed : float
        Mean and largest normal impact speed ``dR/dtau`` at entry.
    max_penetration : float
        Largest ``R - 1`` reached, in clearances.
    mean_duration : float
        Mean contact duration in ``tau``; contacts still open at the end (NaN) left out.
    """

    count: int
    mean_speed: float
    max_speed: float
    max_penetration: float
    mean_duration: float

    def as_dict(self) -> dict[str, Any]:
        """The statistics as a plain ``{name: value}`` dict."""
        return asdict(self)


def impact_statistics(impacts: np.ndarray) -> ImpactStatistics:
    """Count, impact speeds, penetration and duration of contacts.

    Parameters
    ----------
    impacts : ndarray of :data:`vibimpact.run.IMPACT_DTYPE`, shape (n,)
        :attr:`vibimpact.Run.impacts`; needs the fields ``v_impact``, ``penetration`` and
        ``duration``.

    Returns
    -------
    ImpactStatistics
        ``count = 0`` and NaN statistics for no contacts.

    Raises
    ------
    TypeError
        When ``impacts`` lacks those fields (:class:`vibimpact._validate.WrongType`).
    """
    a, needed = np.asarray(impacts), {"v_impact", "penetration", "duration"}
    if not needed <= set(a.dtype.names or ()):
        raise _v.WrongType(f"impacts must be a structured array with fields v_impact, "
                           f"penetration and duration (vibimpact.run.IMPACT_DTYPE), got "
                           f"{type(impacts).__name__}")
    a, nan = a.ravel(), float("nan")
    if a.size == 0:
        return ImpactStatistics(0, nan, nan, nan, nan)
    speed, duration = a["v_impact"].astype(np.float64), a["duration"].astype(np.float64)
    closed = duration[np.isfinite(duration)]
    return ImpactStatistics(int(a.size), float(np.mean(speed)), float(np.max(speed)),
                            float(np.max(a["penetration"])),
                            float(np.mean(closed)) if closed.size else nan)
