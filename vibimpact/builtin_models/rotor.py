"""The rotor of eq. (5) of Pust & Kozanek: a rotor on magnetic bearings that hits its
retainer (backup) bearing, a circle of radius 1 in the clearance plane.

Kernel: :mod:`vibimpact._kernel.rotor`.  Parameters: :class:`vibimpact.Params`.  Presets:
the paper's figures (:mod:`vibimpact.models.presets`).  Contact: Hertz contact with material
damping, Coulomb friction and viscous tangential damping at ``R = sqrt(X^2 + Y^2) = 1``;
its angle is ``atan2(Y, X)`` (+90 degrees: the bottom, where the weight pulls).
"""
import numpy as np

from ..models import presets as _presets
from ..models.contact import Contact, ContactLaw
from ..models import Model, PlotSpec
from ..models.params import Params


def penetration(states, p):
    """``R - 1`` of states (rows): the retainer circle's gap, negative outside contact."""
    return np.hypot(states[:, 0], states[:, 1]) - 1.0


def normal_speed(states, p):
    """``R'``: the speed along the retainer's normal."""
    X, Y, U, V = (states[:, j] for j in range(4))
    return (X * U + Y * V) / np.hypot(X, Y)


def angle(states, p):
    """``atan2(Y, X)`` in degrees: where on the retainer circle."""
    return np.degrees(np.arctan2(states[:, 1], states[:, 0]))


MODEL = Model.builtin_model(
    "rotor", "rotor", ("X", "Y", "dX", "dY"), omega_index=9, param_set=Params, bound=1e3,
    contact=Contact(switch=0, mode=0, penetration=penetration, normal_speed=normal_speed,
                    angle=angle, extremum=2, positions=(0, 1),
                    law=ContactLaw(stiffness="kh", exponent=1.5, damping="Bh", friction="f",
                                   tangential_damping="BT")),
    plot=PlotSpec(xy=("X", "Y"), circle=1.0),
    presets={name: (_presets.paper_values(name), _presets.describe(name))
             for name in _presets.paper_names()})
