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
from typing import TYPE_CHECKING, Callable

import numpy as np

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Sequence

    from numpy.typing import ArrayLike

#: fields of an impact record, one per contact entered (the rotor's words in brackets)
IMPACT_DTYPE = np.dtype([
    ("t_entry", "f8"),      # dimensionless time of contact entry (R = 1)
    ("theta", "f8"),        # contact angle at entry, degrees (atan2(Y, X); +90 = bottom)
    ("v_impact", "f8"),     # normal impact speed at entry (dR/dtau > 0)
    ("penetration", "f8"),  # maximum penetration during the contact (R - 1)
    ("duration", "f8"),     # t_exit - t_entry; NaN while the contact is still open at the end
    ("t_exit", "f8"),       # time of contact exit (R = 1); NaN: still open at the end
    ("period", "i8"),       # forcing period of the entry, counted from the recorded start
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
    law : ContactLaw
        The contact law.
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
    law: ContactLaw
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
        if not isinstance(self.law, ContactLaw):
            raise ValueError("contact: law must be a vibimpact.contact.ContactLaw")
        for role, name in self.law.parameters().items():
            if name not in param_names:
                raise ValueError(f"contact: the law's {role} {name!r} is not a parameter "
                                 f"({', '.join(param_names)})")


def impacts_from_events(contact, p, t, which, mode_before, state, t0, period):
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

    Returns
    -------
    ndarray of :data:`IMPACT_DTYPE`
        One record per contact entered: its entry and exit (the first exit event after the
        entry; NaN when the window ends first), angle, normal speed at entry, the forcing
        period it started in, duration and peak penetration (the largest penetration at
        the extremum events inside the contact).
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
    return out
