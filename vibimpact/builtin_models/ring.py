"""The rotor of eq. (5) with a turning retainer ring: the retainer bearing's inner ring as a
degree of freedom.

The paper's retainer is a ball bearing "whose inner ring sets into rotation after oblique
impacts"; eq. (5) leaves the ring out (its friction acts as if the ring never turned).
Here the ring turns about the retainer's centre with inertia ``Jr`` against its bearing's
viscous (``cr``) and Coulomb (``Mr``) drag, and the contact's friction and tangential
damping act on the slip velocity between the shaft's surface and the ring's.  State
``(X, Y, dX, dY, Vr)`` with ``Vr`` the ring's surface speed.  Kernel:
:mod:`vibimpact._kernel.ring`; the derivation, the energy balance and the parameters'
ranges are in the documentation's model page.

A large ``Jr`` (or a ring whose bearing holds it) gives eq. (5) back; the presets
``fig8-ring``, ``fig10-ring`` and ``fig11-ring`` are the paper's figures with a light ring
(``Jr = 0.05``, ``cr = 1e-4``, ``Mr = 1e-3``: a small ball bearing's inner ring on the
paper's rig, inside the ranges the model page justifies).
"""
import dataclasses

from ..models.contact import Contact, ContactLaw
from ..models import Model
from ..models.params import Domain, param_set
from .rotor import Params, describe, paper_values  # the paper's presets, with a ring
from .rotor import PLOT, STATE_TEXT, angle, normal_speed, penetration  # the same circle

_ROTOR_ROWS = [
    ("B", "linear viscous damping of the magnetic support"),
    ("k3", "cubic magnetic stiffness (negative: softening)"),
    ("kh", "Hertz contact stiffness"),
    ("Bh", "Hertz material (radial) damping"),
    ("BT", "viscous damping of the slip velocity, in contact"),
    ("f", "Coulomb friction coefficient of the slip velocity"),
    ("Rr", "shaft radius / clearance (0 for a mass point)"),
    ("Ec", "unbalance eccentricity / clearance"),
    ("G", "weight m g / (k r_h), along +Y"),
    ("eta", "forcing (rotor speed) frequency ratio"),
    ("eps", "friction regularisation (0: exact Coulomb friction with stick/slip)"),
]
_DEFAULTS = Params()

#: the ring of the presets: inertia, viscous and Coulomb drag of its bearing
RING_DEFAULTS = {"Jr": 0.05, "cr": 1e-4, "Mr": 1e-3}

RingParams = param_set(
    "RingParams",
    [(n, getattr(_DEFAULTS, n), Params.domain(n) if n in Params._DOMAINS else None, text)
     for n, text in _ROTOR_ROWS]
    + [("Jr", RING_DEFAULTS["Jr"], Domain.above(0.0),
        "the ring's moment of inertia / (m r_i^2): its effective mass at the contact "
        "relative to the rotor's"),
       ("cr", RING_DEFAULTS["cr"], Domain.at_least(0.0),
        "viscous drag of the ring's bearing, as a force at the inner surface per unit "
        "surface speed"),
       ("Mr", RING_DEFAULTS["Mr"], Domain.at_least(0.0),
        "Coulomb drag torque of the ring's bearing, as a force at the inner surface")],
    omega="eta", module=__name__,
    doc="Dimensionless parameters of the rotor with a turning retainer ring.")


def _preset(name):
    return {**paper_values(name), "eps": 0.0, **RING_DEFAULTS}


MODEL = Model.builtin_model(
    "ring", "ring", ("X", "Y", "dX", "dY", "Vr"), omega_index=9, param_set=RingParams,
    bound=1e3,
    contact=Contact(switch=0, mode=0, penetration=penetration, normal_speed=normal_speed,
                    angle=angle, extremum=3, positions=(0, 1),
                    law=ContactLaw(stiffness="kh", exponent=1.5, damping="Bh", friction="f",
                                   tangential_damping="BT")),
    plot=dataclasses.replace(PLOT, preset_columns=(), preset_marked=(), preset_note=""),
    state_text={**STATE_TEXT,
                "Vr": "speed of the retainer ring's inner surface / (clearance omega0), "
                      "positive along e_t = (-Y, X)/R (the ring's angular speed is "
                      "Vr / (Rr + 1) in units of omega0)"},
    presets={f"{fig}-ring": (_preset(fig), f"{describe(fig)}; with a light "
                             "turning retainer ring (Jr 0.05)")
             for fig in ("fig8", "fig10", "fig11")},
    references="L. Půst, J. Kozánek: Vibrations of rotor supported in magnetic bearings "
               "with impacts (the rotor model, eq. 5), with the retainer as a turning ring",
    # the rotor's frequency range and census point, with the ring turning
    defaults={"frequencies": "0.9:1.5:0.002", "map_frequencies": "0.9:1.5:0.005",
              "census_preset": "fig11-ring",
              "census_frequency": 1.06})
