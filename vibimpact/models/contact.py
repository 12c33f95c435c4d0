"""What a model declares about its contact: geometry and law, as data.

A vibro-impact model has a *contact*: a switching function of the kernel that marks where
a body meets an obstacle, and a mode entry that says whether it is in contact.  A
:class:`Contact` names both, and gives the contact's geometry as vectorised NumPy
functions of states (the gap, the speed along the normal, the angle of the contact point)
and its law (:class:`ContactLaw`: which parameters are the normal stiffness and its
exponent, the material damping, Coulomb friction and tangential damping, each optional).
From the kernel's event log (entry and exit of every contact, extrema of the
penetration) every analysis of impacts follows for any model that declares one: impact
records (:func:`impacts_from_events`), impacts per period, contact arcs, contact
statistics, and the saltation matrices the kernel applies at every switch.

References
----------
Pust, L., Kozanek, J. "Vibrations of rotor supported in magnetic bearings with impacts".
Leine, R. I., Nijmeijer, H. (2004). *Dynamics and Bifurcations of Non-Smooth Mechanical
Systems*. Springer, ch. 2-3 (contact laws, switching functions, saltation).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar
from collections.abc import Callable

import numpy as np

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Sequence

    from numpy.typing import ArrayLike

#: fields of an impact record, one per contact entered (in brackets, for example, the
#: built-in rotor's terms: its radius R, positions X, Y and time tau)
IMPACT_DTYPE = np.dtype([
    ("t_entry", "f8"),      # dimensionless time of contact entry (R = 1)
    ("theta", "f8"),        # contact angle at entry, degrees (atan2(Y, X); +90 = bottom)
    ("v_impact", "f8"),     # normal impact speed at entry (dR/dtau > 0)
    ("penetration", "f8"),  # maximum penetration during the contact (R - 1)
    ("duration", "f8"),     # t_exit - t_entry; NaN while the contact is still open at the end
    ("t_exit", "f8"),       # time of contact exit (R = 1); NaN: still open at the end
    ("period", "i8"),       # forcing period of the entry, counted from the recorded start
    # the contact's angular extent, degrees on the branch of ``theta`` (so they may leave
    # (-180, 180]): entry to exit with the sliding in between (see :func:`contact_spans`)
    ("theta_exit", "f8"),   # angle at exit, theta + the angle travelled; NaN: still open
    ("theta_min", "f8"),    # smallest angle reached in contact (<= theta)
    ("theta_max", "f8"),    # largest angle reached in contact (>= theta)
])

#: fields of a contact span: one interval of contact inside a recorded window, entered
#: there or already open at its start (:func:`contact_spans`)
SPAN_DTYPE = np.dtype([
    ("t_start", "f8"),      # entry, or the window's start for a contact open there
    ("t_end", "f8"),        # exit, or the window's end for a contact still open there
    ("theta_start", "f8"),  # angle at t_start, degrees in (-180, 180]
    ("theta_end", "f8"),    # angle at t_end on theta_start's branch (theta_start + travel)
    ("theta_min", "f8"),    # smallest angle reached on that branch
    ("theta_max", "f8"),    # largest angle reached on that branch
    ("entered", "?"),       # the span begins with an entry inside the window
    ("exited", "?"),        # the span ends with an exit inside the window
])

_NORMAL_LAWS = ("hertz", "linear")


@dataclass(frozen=True)
class ContactLaw:
    """The contact law of a model, by the names of the parameters that set it.

    The normal force is ``F = k d^e (1 + c d')`` for a penetration ``d > 0`` (``e`` =
    3/2: Hertz; ``e`` = 1: a linear spring stop), the tangential force Coulomb friction
    ``mu F`` against the slip plus a viscous ``b v_t``.  Each part is optional: ``None``
    leaves it out.

    Parameters
    ----------
    stiffness : str
        Parameter of the normal stiffness ``k``.
    exponent : float
        ``e``: 1.5 for Hertz contact, 1.0 for a linear spring.
    damping : str, optional
        Parameter of the material damping ``c``.
    friction : str, optional
        Parameter of the Coulomb friction coefficient ``mu``.
    tangential_damping : str, optional
        Parameter of the viscous tangential damping ``b``.
    """

    stiffness: str
    impulsive: ClassVar[bool] = False
    exponent: float = 1.5
    damping: str | None = None
    friction: str | None = None
    tangential_damping: str | None = None

    def parameters(self) -> dict:
        """``{role: parameter name}`` of the parts the law has."""
        roles = dict(stiffness=self.stiffness, damping=self.damping, friction=self.friction,
                     tangential_damping=self.tangential_damping)
        return {k: v for k, v in roles.items() if v is not None}

    def force(self, penetration: ArrayLike, normal_speed: ArrayLike, p: np.ndarray,
              names: Sequence[str]) -> np.ndarray:
        """Normal force ``k d^e (1 + c d')`` (0 out of contact), vectorised.

        Parameters
        ----------
        penetration, normal_speed : ndarray
        p : ndarray
            The parameter vector.
        names : sequence of str
            Its layout.
        """
        d = np.maximum(np.asarray(penetration, dtype=float), 0.0)
        k = p[list(names).index(self.stiffness)]
        c = p[list(names).index(self.damping)] if self.damping else 0.0
        return k * d ** self.exponent * (1.0 + c * np.asarray(normal_speed, dtype=float))


@dataclass(frozen=True)
class Restitution:
    """An impulsive contact law: a rigid stop and Newton's impact law ``v+ = -r v-``.

    The body does not penetrate the stop; at impact its normal velocity is reversed and
    reduced by the coefficient of restitution ``r`` in ``[0, 1]`` (the kernel's transition
    applies the jump, :mod:`vibimpact._kernel.impulsive`), a sequence of impacts that
    accumulates in finite time ends in sticking (Shaw & Holmes 1983, "A periodically
    forced piecewise linear oscillator", J. Sound Vib. 90, 129-155; Budd & Dux 1994,
    Phil. Trans. R. Soc. A 347, 365-389).  An impact record's duration is 0 unless the
    impact ends a chattering sequence: it then lasts until the body leaves the stop.

    Parameters
    ----------
    coefficient : str
        Parameter of the coefficient of restitution ``r`` (its domain is ``[0, 1]``).
    """

    coefficient: str
    impulsive: ClassVar[bool] = True

    def __post_init__(self):
        if not isinstance(self.coefficient, str) or not self.coefficient:
            raise ValueError(f"coefficient must name a parameter (a non-empty str), got "
                             f"{self.coefficient!r}"[:200])

    def parameters(self) -> dict:
        """``{"restitution": parameter name}``."""
        return {"restitution": self.coefficient}


@dataclass(frozen=True)
class Contact:
    """Where and how a model's body meets its obstacle.

    Parameters
    ----------
    switch : int
        Index of the kernel's switching function that is the contact (entry and exit).
    mode : int
        Index of the mode entry that is 1 in contact, 0 in free flight.
    penetration : callable
        ``penetration(states, p) -> (m,)``: depth of penetration, ``-gap`` (positive in
        contact), for states of shape ``(m, n_state)``.
    normal_speed : callable
        ``normal_speed(states, p) -> (m,)``: speed along the outward normal (the impact
        speed at entry; positive approaching the obstacle).
    angle : callable
        ``angle(states, p) -> (m,)``: where on the obstacle the contact is, in degrees
        (the angle of the contact normal in the plane of a two-dimensional contact; 0 or
        180 for a one-dimensional stop on the positive or negative side).
    law : ContactLaw or Restitution
        The contact law: a force (:class:`ContactLaw`) or an impact (:class:`Restitution`).
    extremum : int, optional
        Index of an observer switching function whose events in contact are the extrema
        of the penetration (for the peak penetration of each contact); without one the
        peak is the larger of entry and exit (0).
    positions : tuple of int
        Indices of the position coordinates (the plane drawn by XY plots).
    """

    switch: int
    mode: int
    penetration: Callable
    normal_speed: Callable
    angle: Callable
    law: ContactLaw | Restitution
    extremum: int | None = None
    positions: tuple = (0, 1)

    def check(self, n_state: int, n_switch: int, n_mode: int,
              param_names: Sequence[str]) -> None:
        """Raise ``ValueError`` naming ``contact`` when the declaration does not fit a
        model of these sizes."""
        for what, value, size, of in (("switch", self.switch, n_switch,
                                       "switching functions"),
                                      ("mode", self.mode, n_mode, "mode entries")):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or \
                    not 0 <= value < size:
                raise ValueError(f"contact: {what} must index the model's {size} {of}, "
                                 f"got {value!r}")
        if self.extremum is not None and not 0 <= self.extremum < n_switch:
            raise ValueError(f"contact: extremum must index the model's {n_switch} switching "
                             f"functions, got {self.extremum!r}")
        if not self.positions or any(not 0 <= i < n_state for i in self.positions):
            raise ValueError(f"contact: positions must index the model's {n_state} states, "
                             f"got {self.positions!r}")
        for fn in ("penetration", "normal_speed", "angle"):
            if not callable(getattr(self, fn)):
                raise ValueError(f"contact: {fn} must be a function of (states, p)")
        if not isinstance(self.law, (ContactLaw, Restitution)):
            raise ValueError("contact: law must be a vibimpact.models.contact.ContactLaw "
                             "or Restitution")
        for role, name in self.law.parameters().items():
            if name not in param_names:
                raise ValueError(f"contact: the law's {role} {name!r} is not a parameter "
                                 f"({', '.join(param_names)})")


@dataclass(frozen=True)
class _Column:
    """``states[:, index] - p[offset]`` (no offset: ``None``), a picklable function of
    ``(states, p)``."""

    index: int
    offset: int | None = None

    def __call__(self, states, p):
        column = np.array(states[:, self.index], dtype=float)
        return column - p[self.offset] if self.offset is not None else column


def _zero_angle(states, p):
    """The angle of a stop on the positive side of its coordinate: 0 degrees."""
    return np.zeros(np.shape(states)[0])


def stop_contact(law: ContactLaw | Restitution, position: int, velocity: int, stop: int,
                 switch: int = 0, mode: int = 0, extremum: int | None = None) -> Contact:
    """The :class:`Contact` of a one-dimensional stop at ``q = p[stop]`` above the
    coordinate ``q = states[:, position]`` (free while ``q < d``): penetration ``q - d``,
    normal speed ``q' = states[:, velocity]``, angle 0.

    Parameters
    ----------
    law : ContactLaw or Restitution
    position, velocity : int
        Indices of ``q`` and ``q'`` in the state.
    stop : int
        Index of the stop's position ``d`` in the parameter vector.
    switch, mode, extremum : int
        As :class:`Contact`'s.
    """
    return Contact(switch=switch, mode=mode, penetration=_Column(position, stop),
                   normal_speed=_Column(velocity), angle=_zero_angle, extremum=extremum,
                   positions=(position,), law=law)


def impacts_from_events(contact, p, t, which, mode_before, state, t0, period,
                        samples=None, mode_after=None):
    """Contact records from a run's event log (vectorised).

    Parameters
    ----------
    contact : Contact
        The model's contact.
    p : ndarray
        Parameter vector.
    t, which : ndarray, shape (m,)
    mode_before : ndarray, shape (m, n_mode)
    state : ndarray, shape (m, n_state)
    t0 : float
        Start of the recorded window.
    period : float
        Forcing period (for the ``period`` field).
    samples : (ndarray, ndarray), optional
        ``(times, states)`` of further states known in the window (stroboscopic, dense):
        points of the angle's path inside long contacts (:func:`contact_spans`).
    mode_after : ndarray, shape (m, n_mode), optional
        The modes after the events: with an impulsive law (:class:`Restitution`) an
        impact after which the body is not held on the stop lasts no time (its exit is
        its entry); without them every impact lasts until the next exit.

    Returns
    -------
    ndarray of :data:`IMPACT_DTYPE`
        One record per contact entered: its entry and exit (the first exit event after the
        entry; NaN when the window ends first), angle, normal speed at entry, the forcing
        period it started in, duration and peak penetration (the largest penetration at
        the extremum events inside the contact), and the angles it covers from entry to
        exit, sliding included (:func:`contact_spans`; the last known state for a
        contact still open).
    """
    in_contact = mode_before[:, contact.mode]
    switch = which == contact.switch
    entry = np.flatnonzero(switch & (in_contact == 0))
    exits = np.flatnonzero(switch & (in_contact == 1))
    out = np.zeros(entry.size, dtype=IMPACT_DTYPE)
    if entry.size == 0:
        return out
    at = state[entry]
    out["t_entry"] = t[entry]
    out["theta"] = contact.angle(at, p)
    out["v_impact"] = contact.normal_speed(at, p)
    out["period"] = np.floor((t[entry] - t0) / period + 1e-12).astype(np.int64)
    # the exit of each contact is the first exit event after its entry
    j = np.searchsorted(exits, entry)
    has_exit = j < exits.size
    t_exit = np.full(entry.size, np.nan)
    t_exit[has_exit] = t[exits[j[has_exit]]]
    instant = _instantaneous(contact, entry, mode_after)
    t_exit[instant] = t[entry[instant]]
    out["t_exit"] = t_exit
    out["duration"] = t_exit - out["t_entry"]
    pen = np.zeros(entry.size)
    if contact.extremum is not None:
        ext = np.flatnonzero((which == contact.extremum) & (in_contact == 1))
    else:
        ext = np.zeros(0, dtype=np.int64)
    if ext.size:
        owner = np.searchsorted(entry, ext) - 1
        keep = owner >= 0
        owner = owner[keep]
        ext = ext[keep]
        if exits.size:
            inside = ~(has_exit[owner] & (exits[np.minimum(j[owner], exits.size - 1)] < ext))
        else:  # no contact ends inside the window: every extremum is inside its contact
            inside = np.ones(owner.size, dtype=bool)
        depth = contact.penetration(state[ext], p)
        np.maximum.at(pen, owner[inside], depth[inside])
    out["penetration"] = pen
    spans = contact_spans(contact, p, t, which, mode_before, state, (t0, np.inf), samples,
                          mode_after=mode_after)
    spans = spans[spans["entered"]]                    # one per entry, in the same order
    out["theta_min"], out["theta_max"] = spans["theta_min"], spans["theta_max"]
    out["theta_exit"] = np.where(spans["exited"], spans["theta_end"], np.nan)
    return out


def _instantaneous(contact, entry, mode_after):
    """Which of the entries (event indices) are impacts that last no time: those of an
    impulsive law after which the mode is not in contact (none without ``mode_after``)."""
    if mode_after is None or not getattr(contact.law, "impulsive", False):
        return np.zeros(entry.size, dtype=bool)
    return np.asarray(mode_after)[entry, contact.mode] == 0


def wrap_degrees(angle):
    """``angle`` (degrees, array or number) wrapped to (-180, 180]."""
    return 180.0 - np.mod(180.0 - np.asarray(angle, dtype=float), 360.0)


def contact_spans(contact, p, t, which, mode_before, state, window, samples=None,
                  inside0=False, mode_after=None):
    """The intervals of contact in a recorded window, with the angles each one covers.

    A span runs from an entry to the next exit (the contact switch's events); a contact
    already open at the window's start begins there, one still open at its end ends
    there, and a window without contact events is one span when it starts in contact
    (``inside0``: a permanent contact).  The angles of every state known inside a span
    (its events: entry, exit, extrema of the penetration, friction switches; and the
    ``samples``: stroboscopic and dense samples) are joined into one continuous angle,
    each step taken the short way round; the span's extent is the least and largest of
    them.  That assumes the contact point moves less than 180 degrees between two known
    states of one contact: a run whose contact point goes round its obstacle (the
    built-in rotor rolling round its retainer) needs samples at least three times per
    turn (dense output) for its extent to be whole.

    Parameters
    ----------
    contact : Contact
        The model's contact.
    p : ndarray
        Parameter vector.
    t, which : ndarray, shape (m,)
        Event times (ascending) and switch indices (:attr:`vibimpact.Run.events`).
    mode_before : ndarray, shape (m, n_mode)
    state : ndarray, shape (m, n_state)
    window : (float, float)
        Start and end of the recorded window (``inf`` for an open end).
    samples : (ndarray, ndarray), optional
        ``(times, states)`` of further states known in the window.
    inside0 : bool
        In contact at the window's start (read only when the log has no contact event).
    mode_after : ndarray, shape (m, n_mode), optional
        The modes after the events: an impact of an impulsive law after which the body
        is not held on the stop is a span of no time (:func:`impacts_from_events`).

    Returns
    -------
    ndarray of :data:`SPAN_DTYPE`
        In time order; angles NaN for a span without any known state.

    Examples
    --------
    >>> from vibimpact.models import ROTOR
    >>> st = np.array([[np.cos(a), np.sin(a), 0.0, 0.0] for a in np.radians([30, 60])])
    >>> s = contact_spans(ROTOR.contact, None, np.array([1.0, 2.0]), np.array([0, 0]),
    ...                   np.array([[0, 0], [1, 0]]), st, (0.0, 3.0))
    >>> [round(float(s[f][0]), 9) for f in ("theta_min", "theta_max")]
    [30.0, 60.0]
    """
    t = np.asarray(t, dtype=float)
    t0, t1 = float(window[0]), float(window[1])
    sw = np.flatnonzero(np.asarray(which) == contact.switch)
    is_exit = np.asarray(mode_before)[sw, contact.mode] == 1
    entries, ends = list(t[sw[~is_exit]]), t[sw[is_exit]]
    opened = bool(is_exit[0]) if sw.size else bool(inside0)
    if opened:
        entries.insert(0, t0)
    starts = np.asarray(entries, dtype=float)
    j = np.searchsorted(ends, starts)            # each span ends at the next exit
    exited = j < ends.size
    stop = np.full(starts.size, t1)
    stop[exited] = ends[j[exited]]
    instant = np.r_[np.zeros(int(opened), dtype=bool),
                    _instantaneous(contact, sw[~is_exit], mode_after)]
    stop[instant] = starts[instant]
    exited |= instant
    out = np.zeros(starts.size, dtype=SPAN_DTYPE)
    out["t_start"], out["t_end"], out["exited"] = starts, stop, exited
    out["entered"] = True
    if opened and starts.size:
        out["entered"][0] = False
    for f in ("theta_start", "theta_end", "theta_min", "theta_max"):
        out[f] = np.nan
    if starts.size == 0:
        return out
    # every state known in the window, in time order (events first at equal times)
    times, states = [t], [np.asarray(state, dtype=float)]
    if samples is not None:
        times.append(np.asarray(samples[0], dtype=float).ravel())
        states.append(np.asarray(samples[1], dtype=float).reshape(times[-1].size, -1))
    tk, sk = np.concatenate(times), np.concatenate(states)
    o = np.argsort(tk, kind="stable")
    tk, sk = tk[o], sk[o]
    k = np.searchsorted(starts, tk, side="right") - 1
    member = (k >= 0) & (tk <= stop[np.maximum(k, 0)]) & (tk >= t0)
    if not np.any(member):
        return out
    k, theta = k[member], wrap_degrees(contact.angle(sk[member], p))
    step = wrap_degrees(np.diff(theta))
    step[k[1:] != k[:-1]] = 0.0
    walked = np.concatenate([[0.0], np.cumsum(step)])
    first = np.flatnonzero(np.r_[True, k[1:] != k[:-1]])
    last = np.r_[first[1:] - 1, k.size - 1]
    owner = np.repeat(np.arange(first.size), np.diff(np.r_[first, k.size]))
    u = theta[first][owner] + walked - walked[first][owner]
    span = k[first]
    out["theta_start"][span] = u[first]
    out["theta_end"][span] = u[last]
    out["theta_min"][span] = np.minimum.reduceat(u, first)
    out["theta_max"][span] = np.maximum.reduceat(u, first)
    return out
