"""Impacts of a model on its obstacle: counts per period, loaded arcs, wear statistics.

The paper [1] describes the rotor's regimes by impacts per period ("period 3 with 8
impacts") and where they fall ("bottom half", "two small loaded arcs", "whole circle");
:func:`impact_count` and :func:`contact_arcs` turn the contacts of a run of any model that
declares one (:class:`vibimpact.Contact`) into those words (the loaded arcs are the angles
each contact covers from entry to exit, sliding included), and :func:`impact_statistics`
gives the speeds and penetrations that govern the wear of the contact surfaces.  Angles
are the contact's angle (:attr:`vibimpact.Contact.angle`) in degrees in (-180, 180]: 0 or
180 for a one-dimensional stop; for the built-in rotor ``theta = atan2(Y, X)``, and as
gravity acts along +Y the bottom of its retainer is theta = +90 deg and the top -90 deg
(the "bottom half" of :func:`summarize_arcs` is the angles [0, 180] for any model).

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

from ..base import _validate as _v
from ..base._text import count
from ..models.contact import wrap_degrees as _wrap

if TYPE_CHECKING:  # names of the annotations only
    from typing import Any

    import xarray as xr
    from numpy.typing import ArrayLike

    from ..core.run import Run

__all__ = ["ImpactCount", "impact_count", "ContactArcs", "contact_arcs", "contact_spans_of",
           "ImpactStatistics", "impact_statistics", "SMALL_ARC_WIDTH", "MAX_SMALL_ARCS",
           "HALF_TOLERANCE", "WHOLE_CIRCLE_GAP"]

#: an arc narrower than this (degrees, an eighth of the circle) is "small": a contact
#: slides while it lasts, and the paper's "two small segments" of a periodic impact motion
#: are about 35 degrees wide each (fig8 at eta = 1.185: 27..62 and 117..152 degrees)
SMALL_ARC_WIDTH = 45.0
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
    """Arcs of the obstacle, by the contact's angle, where the model is in contact (loaded).

    Attributes
    ----------
    start, end : ndarray, shape (n_arcs,)
        First and last angle of each arc, degrees in (-180, 180]; the arc runs in the
        direction of increasing theta from ``start`` to ``end``, so an arc through 180 deg
        has ``start > end``.  Sorted by ``start``.  The whole circle is one arc with
        ``start = end = 180`` and ``width = 360``.
    width : ndarray, shape (n_arcs,)
        Angular extent in degrees, ``(end - start) mod 360`` (0 for a single point, 360
        for the whole circle).
    share : ndarray, shape (n_arcs,)
        Share of the contact time spent on each arc (sums to 1); for contacts without
        duration (angles given as points) the share of the contacts.
    loaded : ndarray, shape (n_arcs,)
        Fraction of the recorded time the contact is on each arc (the arc is loaded that
        fraction of the time; the sum is the fraction of time in contact); NaN when the
        recorded time is unknown.
    n_arcs : int
    largest_gap : float
        Widest circular gap no contact covers, degrees (360 without contacts, 0 when the
        contacts cover the whole circle).
    summary : str
        The paper's words, see :func:`summarize_arcs`.
    """

    start: np.ndarray
    end: np.ndarray
    width: np.ndarray
    share: np.ndarray
    loaded: np.ndarray
    n_arcs: int
    largest_gap: float
    summary: str

    def to_text(self) -> str:
        """E.g. ``"2 arcs (27..62°, 117..152°)"``; ``"none"`` without contacts."""
        def deg(x):
            return f"{x:.0f}".replace("-0", "0")   # "-0" only: no zero padding
        parts = ["0..360°" if w >= 360.0 else f"{deg(s)}°" if deg(s) == deg(e) else
                 f"{deg(s)}..{deg(e)}°" for s, e, w in zip(self.start, self.end, self.width)]
        return f"{self.summary} ({', '.join(parts)})" if self.n_arcs else self.summary
    __str__ = to_text

    def table(self) -> np.ndarray:
        """The arcs as an ``(n_arcs, 4)`` array of ``start, end, width, loaded``."""
        return np.column_stack([self.start, self.end, self.width, self.loaded]) \
            if self.n_arcs else np.zeros((0, 4))


def summarize_arcs(start, width, largest_gap):
    """The paper's words for a set of loaded arcs (the one place they are decided).

    ``start`` and ``width`` (n_arcs,) are the arcs in degrees (start in (-180, 180]),
    ``largest_gap`` the widest uncovered gap.  First matching rule wins:

    1. no arcs: ``"none"``;
    2. at most :data:`MAX_SMALL_ARCS` arcs, each narrower than :data:`SMALL_ARC_WIDTH`:
       ``"1 small arc"`` / ``"k small arcs"``;
    3. every arc inside the bottom half [0, 180] deg (+-:data:`HALF_TOLERANCE`):
       ``"bottom half"``; inside the top half [-180, 0]: ``"top half"``;
    4. largest uncovered gap narrower than :data:`WHOLE_CIRCLE_GAP`: ``"whole circle"``;
    5. otherwise ``"1 arc"`` / ``"k arcs"``.
    """
    start, width = np.asarray(start, float), np.asarray(width, float)
    k, tol = len(width), HALF_TOLERANCE
    if k == 0:
        return "none"
    if k <= MAX_SMALL_ARCS and np.all(width < SMALL_ARC_WIDTH):
        return count(k, "small arc")
    for half, lo in (("bottom half", 0.0), ("top half", -180.0)):
        s = np.mod(start - (lo - tol), 360.0)          # start, from the half's low end
        if np.all(s + width <= 180.0 + 2.0 * tol):
            return half
    if largest_gap < WHOLE_CIRCLE_GAP:
        return "whole circle"
    return count(k, "arc")


def contact_spans_of(run) -> np.ndarray:
    """The contact intervals of a run, with the angles each covers.

    :func:`vibimpact.models.contact.contact_spans` on the run's event log over its recorded
    window (the stroboscopic times' first to last), with its stroboscopic and dense
    samples as further points of the angle's path; a run that starts in contact and
    never switches is one span over the whole window (a permanent contact).

    Parameters
    ----------
    run : Run
        A :class:`vibimpact.Run` of a model that declares a contact.

    Returns
    -------
    ndarray of :data:`vibimpact.models.contact.SPAN_DTYPE`
        Empty for a model without a contact.
    """
    from ..models.contact import SPAN_DTYPE, contact_spans

    contact = getattr(run, "contact", None)
    if contact is None or len(run.t_strobe) == 0:
        return np.zeros(0, dtype=SPAN_DTYPE)
    p = run.params.as_array() if hasattr(run.params, "as_array") else \
        np.asarray(run.params, float)
    times, states = [np.asarray(run.t_strobe, float)], [np.asarray(run.strobe, float)]
    if run.dense is not None and run.t_dense is not None:
        times.append(np.asarray(run.t_dense, float))
        states.append(np.asarray(run.dense, float))
    inside0 = bool(contact.penetration(states[0][:1], p)[0] > 0.0)
    ev = run.events
    return contact_spans(contact, p, ev["t"], ev["which"], ev["mode_before"], ev["state"],
                         (float(run.t_strobe[0]), float(run.t_strobe[-1])),
                         (np.concatenate(times), np.concatenate(states)), inside0,
                         mode_after=ev["mode_after"])


def _union(lo, width, gap):
    """Arcs ``(start in [0, 360), width, members)`` covering the intervals ``[lo, lo +
    width]`` on the circle, gaps of at most ``gap`` closed; ``members[i]`` is the arc of
    interval ``i``.  One arc of width 360 when they (with closed gaps) cover the circle."""
    s = np.mod(lo, 360.0)
    if np.any(width + gap >= 360.0):
        return np.array([0.0]), np.array([360.0]), np.zeros(s.size, dtype=np.int64)
    o = np.argsort(s, kind="stable")
    so, eo = s[o], s[o] + width[o]
    reach = np.maximum.accumulate(eo)
    new = np.r_[True, so[1:] > reach[:-1] + gap]
    grp = np.cumsum(new) - 1
    starts = so[new]
    ends = np.maximum.reduceat(eo, np.flatnonzero(new))
    # the last arc may run past 360 onto the first ones: merge them into it
    alias = np.arange(starts.size)
    first = 0
    while starts.size - first > 1 and starts[first] + 360.0 <= ends[-1] + gap:
        ends[-1] = max(ends[-1], ends[first] + 360.0)
        alias[first] = starts.size - 1
        first += 1
    if ends[-1] - starts[-1] + gap >= 360.0:
        return np.array([0.0]), np.array([360.0]), np.zeros(s.size, dtype=np.int64)
    keep = np.arange(first, starts.size)
    renum = np.full(starts.size, -1)
    renum[keep] = np.arange(keep.size)
    members = np.empty(s.size, dtype=np.int64)
    members[o] = renum[alias[grp]]
    return starts[keep], (ends - starts)[keep], members


def _largest_gap(lo, width):
    """Widest circular gap no interval covers (degrees)."""
    if lo.size == 0:
        return 360.0
    s, w, _ = _union(lo, width, 0.0)
    if w[0] >= 360.0:
        return 0.0
    gaps = np.r_[s[1:] - (s[:-1] + w[:-1]), s[0] + 360.0 - (s[-1] + w[-1])]
    return float(max(gaps.max(), 0.0))


def _intervals(contacts):
    """``(lo, width, duration, window)`` of the contacts: a Run, spans, impact records,
    a run's dataset, or angles (points, no duration, window unknown)."""
    if hasattr(contacts, "events") and hasattr(contacts, "strobe"):     # a Run
        spans = contact_spans_of(contacts)
        window = float(contacts.t_strobe[-1] - contacts.t_strobe[0]) \
            if len(contacts.t_strobe) > 1 else np.nan
        contacts = spans
    elif hasattr(contacts, "data_vars"):                                # a run's dataset
        return _dataset_intervals(contacts)
    else:
        window = np.nan
    names = getattr(getattr(contacts, "dtype", None), "names", None) or ()
    if "theta_min" in names:                    # spans or impact records
        lo, hi = contacts["theta_min"], contacts["theta_max"]
        if "t_start" in names:
            dur = contacts["t_end"] - contacts["t_start"]
        else:
            dur = np.where(np.isfinite(contacts["duration"]), contacts["duration"], 0.0)
        ok = np.isfinite(lo) & np.isfinite(hi)
        return lo[ok], (hi - lo)[ok], np.asarray(dur, float)[ok], window
    theta = _v.array1d("angles", contacts)
    if np.ndim(contacts) != 1 or not np.all(np.isfinite(theta)):
        raise ValueError(f"angles must be 1-D and finite, got shape {np.shape(contacts)}")
    return theta, np.zeros(theta.size), np.zeros(theta.size), np.nan


def _dataset_intervals(ds):
    """Intervals of a run's dataset: its ``impact_theta_min`` / ``impact_theta_max``
    (entry angles only, as points, in a file written before they were stored)."""
    if "impact_theta" not in ds:
        return np.zeros(0), np.zeros(0), np.zeros(0), np.nan
    t = ds["t_strobe"].values if "t_strobe" in ds else np.zeros(0)
    window = float(t[-1] - t[0]) if t.size > 1 else np.nan
    theta = np.asarray(ds["impact_theta"].values, float)
    if "impact_theta_min" in ds and "impact_theta_max" in ds:
        lo = np.asarray(ds["impact_theta_min"].values, float)
        hi = np.asarray(ds["impact_theta_max"].values, float)
    else:
        lo = hi = theta
    dur = np.asarray(ds["impact_duration"].values, float) if "impact_duration" in ds \
        else np.zeros(theta.size)
    ok = np.isfinite(lo) & np.isfinite(hi)
    return lo[ok], (hi - lo)[ok], np.where(np.isfinite(dur), dur, 0.0)[ok], window


def contact_arcs(angles: Run | xr.Dataset | ArrayLike,
                 gap: float = 10.0) -> ContactArcs:
    """The loaded arcs of the obstacle: where the contacts are, entry to exit.

    Each contact covers the angles from its entry to its exit with the sliding in between
    (:func:`vibimpact.models.contact.contact_spans`); the arcs are the union of those intervals
    on the circle over the whole record, every uncovered gap of at most ``gap`` degrees
    closed (the arcs' resolution: contacts of a chaotic motion that fall that close
    together load one arc).  An arc across +-180 deg is one arc.

    Parameters
    ----------
    angles : Run, Dataset, ndarray or array_like
        The contacts: a :class:`vibimpact.Run` (its contact intervals from the event
        log, with its stroboscopic and dense samples, including a contact open at the
        record's start and a permanent one); or a run's dataset (``impact_theta_min``
        / ``impact_theta_max``); or records of :data:`vibimpact.core.run.IMPACT_DTYPE` or
        :data:`vibimpact.models.contact.SPAN_DTYPE`; or plain contact angles in degrees (any
        finite values, each a point: the entry angles of older files).
    gap : float
        Widest uncovered gap (degrees) closed inside one arc, in (0, 360).

    Returns
    -------
    ContactArcs
        ``loaded`` is known for a Run and a run's dataset (their recorded time), NaN
        otherwise.

    Raises
    ------
    ValueError
        Naming the argument: ``angles`` not 1-D or not finite, ``gap`` outside (0, 360).

    Examples
    --------
    >>> str(contact_arcs([175.0, 179.0, -178.0, -176.0]))
    '1 small arc (175..-176°)'
    """
    if isinstance(gap, bool) or not isinstance(gap, numbers.Real) or not 0.0 < gap < 360.0:
        raise ValueError(f"gap must be a number in (0, 360) degrees, got {gap!r}")
    lo, width, dur, window = _intervals(angles)
    if lo.size == 0:
        return ContactArcs(*[_frozen_array([])] * 5, 0, 360.0, "none")
    lo = _wrap(lo)
    lo[lo <= -180.0] = 180.0
    s, w, members = _union(lo, width, float(gap))
    total = float(dur.sum())
    on = np.bincount(members, weights=dur, minlength=s.size)
    share = on / total if total > 0.0 else np.bincount(members, minlength=s.size) / lo.size
    loaded = on / window if np.isfinite(window) and window > 0.0 else np.full(s.size, np.nan)
    start = _wrap(s)
    start[start <= -180.0] = 180.0
    if w[0] >= 360.0:
        start = np.array([180.0])
    end = _wrap(start + w)
    end[end <= -180.0] = 180.0
    o = np.argsort(start, kind="stable")
    largest_gap = _largest_gap(lo, width)
    start, w = start[o], w[o]
    return ContactArcs(*(_frozen_array(a) for a in (start, end[o], w, share[o], loaded[o])),
                       n_arcs=int(s.size), largest_gap=largest_gap,
                       summary=summarize_arcs(start, w, largest_gap))


@dataclass(frozen=True)
class ImpactStatistics:
    """Wear-relevant statistics of a set of contacts (NaN where there are none).

    Attributes
    ----------
    count : int
    mean_speed, max_speed : float
        Mean and largest normal impact speed at entry (the contact's ``normal_speed``;
        ``dR/dtau`` for the built-in rotor).
    max_penetration : float
        Largest penetration reached (``R - 1``, in clearances, for the built-in rotor).
    mean_duration : float
        Mean contact duration in the model's time (``tau`` for the built-in rotor);
        contacts still open at the end (NaN) left out.
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
    impacts : ndarray of :data:`vibimpact.core.run.IMPACT_DTYPE`, shape (n,)
        :attr:`vibimpact.Run.impacts`; needs the fields ``v_impact``, ``penetration`` and
        ``duration``.

    Returns
    -------
    ImpactStatistics
        ``count = 0`` and NaN statistics for no contacts.

    Raises
    ------
    TypeError
        When ``impacts`` lacks those fields (:class:`vibimpact.base._validate.WrongType`).
    """
    a, needed = np.asarray(impacts), {"v_impact", "penetration", "duration"}
    if not needed <= set(a.dtype.names or ()):
        raise _v.WrongType(f"impacts must be a structured array with fields v_impact, "
                           f"penetration and duration (vibimpact.core.run.IMPACT_DTYPE), got "
                           f"{type(impacts).__name__}")
    a, nan = a.ravel(), float("nan")
    if a.size == 0:
        return ImpactStatistics(0, nan, nan, nan, nan)
    speed, duration = a["v_impact"].astype(np.float64), a["duration"].astype(np.float64)
    closed = duration[np.isfinite(duration)]
    return ImpactStatistics(int(a.size), float(np.mean(speed)), float(np.max(speed)),
                            float(np.max(a["penetration"])),
                            float(np.mean(closed)) if closed.size else nan)
