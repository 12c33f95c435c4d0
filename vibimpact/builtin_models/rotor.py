"""The rotor of eq. (5) of Pust & Kozanek: a rotor on magnetic bearings that hits its
retainer (backup) bearing, a circle of radius 1 in the clearance plane.

Kernel: :mod:`vibimpact._kernel.rotor`.  Parameters: :class:`Params` (``vi.Params``).
Presets: the paper's figures (:data:`PAPER_TABLE`).  Contact: Hertz contact with material
damping, Coulomb friction and viscous tangential damping at ``R = sqrt(X^2 + Y^2) = 1``;
its angle is ``atan2(Y, X)`` (+90 degrees: the bottom, where the weight pulls).

The paper's presets
-------------------
All presets have ``k3 = -0.002``.  ``B`` and ``Ec`` are **not given in the paper**; every
preset uses :data:`DEFAULT_B` and :data:`DEFAULT_EC`, **calibrated** by
``analyses/paper/calibrate.py`` against the paper's interval claims
(``vibimpact.paper.claims``); they are not values from the paper, and the fit is partial: no
pair reproduces every claim (``reports/calibration.md``, ``reports/paper.md``).

Where the paper is silent about a figure's contact dampings, the presets switch ``Bh``,
``BT`` and ``f`` on one at a time on top of ``fig8`` (fig9: Bh, fig10: BT, fig11: f, each
0.05), as its discussion of "three kinds of damping" suggests.  The text can also be read
with dampings accumulating; the calibration scores every such reading, and this one
reproduces the most claims (reading (a) of ``reports/calibration.md``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..base import _validate as _v
from ..models.contact import Contact, ContactLaw
from ..models import Model, PlotSpec
from ..models.params import Domain, ParamsMixin

#: Default linear damping of the magnetic support.  NOT from the paper (which omits it; it
#: says only that passive magnetic bearings have very low radial damping): the converged
#: optimum of ``analyses/paper/calibrate.py`` against the paper's interval claims of figs 8, 10
#: and 11, over B = 0 and B log-spaced from 0.001 to 0.1 and over the readings of the
#: paper's contact dampings (``reports/calibration.md`` gives the grid, the objective and
#: the claims that agree; ``tests/test_report_sources.py`` checks these values against it).
DEFAULT_B = 0.01468
#: Default unbalance eccentricity / clearance.  NOT from the paper (which omits it):
#: calibrated with :data:`DEFAULT_B`.
DEFAULT_EC = 0.059

#: the parameters that may not be negative
_NONNEGATIVE = ("B", "kh", "Bh", "BT", "f", "Rr", "Ec", "eps")

#: the domain of each rotor parameter that has one (validated in this order)
_ROTOR_DOMAINS = {**{name: Domain.at_least(0.0) for name in _NONNEGATIVE},
                  "eta": Domain.above(0.0)}



@dataclass(frozen=True)
class Params(ParamsMixin):
    """Dimensionless parameters of the rotor model, eq. (5) of the paper.

    Parameters
    ----------
    B : float
        Linear viscous damping of the magnetic support, ``b / sqrt(k m)``.  The paper does
        not state it; the default :data:`DEFAULT_B` is calibrated against the paper's
        intervals (``analyses/paper/calibrate.py``), not a value from the paper.
    k3 : float
        Cubic magnetic stiffness ``kappa_3 = r_h^2 k_3 / k`` (negative: softening).
    kh : float
        Hertz contact stiffness ``kappa_h = sqrt(r_h) k_h / k``.
    Bh : float
        Hertz material (radial) damping.
    BT : float
        Viscous tangential damping, active only in contact.
    f : float
        Coulomb friction coefficient.
    Rr : float
        Shaft radius / clearance (0 for a mass point).
    Ec : float
        Unbalance eccentricity / clearance.  The paper does not state it; the default
        :data:`DEFAULT_EC` is calibrated with ``B``, not a value from the paper.
    G : float
        Weight ``m g / (k r_h)``, acting along +Y (0 for a vertical rotor).
    eta : float
        Forcing (rotor speed) frequency ratio ``omega sqrt(m / k)``; > 0.
    eps : float
        Friction regularisation: 0 (default) is exact Coulomb friction with Filippov
        stick/slip; ``eps > 0`` replaces ``sgn(v_t)`` by ``tanh(v_t / eps)``.

    Raises
    ------
    ValueError
        Naming the parameter, for a non-finite value, a negative damping, stiffness,
        friction, radius or eccentricity, or ``eta <= 0``.

    Examples
    --------
    >>> import vibimpact as vi
    >>> p = vi.presets.get("fig8").replace(eta=1.25)
    """

    B: float = DEFAULT_B
    k3: float = -0.002
    kh: float = 120.0
    Bh: float = 0.0
    BT: float = 0.0
    f: float = 0.0
    Rr: float = 0.0
    Ec: float = DEFAULT_EC
    G: float = 0.3
    eta: float = 1.2
    eps: float = 0.0

    _DOMAINS = _ROTOR_DOMAINS
    _FREQUENCY = "eta"

    @classmethod
    def from_dimensional(cls, m: float, k: float, k2: float, b: float, kh: float, bh: float,
                         bt: float, f: float, R1: float, e: float, rh: float,
                         g: float = 9.81, *, omega: float | None = None,
                         eps: float = 0.0) -> Params:
        """Dimensionless parameters from physical data by eq. (6) of the paper (SI units).

        Parameters
        ----------
        m : float
            Rotor mass [kg].
        k : float
            Linear magnetic stiffness [N/m].
        k2 : float
            Relative cubic stiffness of eq. (1), ``F_m = k r (1 + k2 r^2)`` [1/m^2].
        b : float
            Viscous damping of the support [N s/m].
        kh : float
            Hertz contact stiffness [N/m^{3/2}].
        bh : float
            Hertz material damping coefficient of eq. (2).
        bt : float
            Tangential viscous damping [N s/m].
        f : float
            Coulomb friction coefficient [-].
        R1 : float
            Shaft radius [m].
        e : float
            Unbalance eccentricity [m].
        rh : float
            Radial clearance of the retainer bearing [m].
        g : float
            Gravitational acceleration [m/s^2]; 0 for a vertical rotor.
        omega : float, optional
            Rotor speed [rad/s]; gives ``eta = omega sqrt(m/k)``.  Without it ``eta = 1``.
        eps : float
            Friction regularisation (see the class docstring).

        Notes
        -----
        Eq. (6) is applied as printed: ``B = b/sqrt(km)``, ``kappa_3 = r_h^2 k_3/k`` with
        ``k_3 = k k2``, ``kappa_h = sqrt(r_h) k_h / k``, ``B_h = b_h/sqrt(km)``,
        ``B_T = b_t/sqrt(km)``, ``R_r = R_1/r_h``, ``Ec = e/r_h``, ``G = m g/(k r_h)``.
        (For ``B_h`` the factor ``1 + b_h r'`` of eq. (2) would strictly give
        ``b_h r_h sqrt(k/m)``; we follow the paper's printed formula.)
        """
        vals = dict(m=m, k=k, k2=k2, b=b, kh=kh, bh=bh, bt=bt, f=f, R1=R1, e=e, rh=rh, g=g)
        for name, value in vals.items():
            vals[name] = _v.finite(name, value)
        for name in ("m", "k", "rh"):
            if vals[name] <= 0.0:
                raise ValueError(f"{name} must be > 0, got {vals[name]!r}")
        m, k, rh = vals["m"], vals["k"], vals["rh"]
        skm = math.sqrt(k * m)
        eta = 1.0
        if omega is not None:
            eta = _v.finite("omega", omega) * math.sqrt(m / k)
        return cls(B=vals["b"] / skm, k3=rh * rh * vals["k2"], kh=math.sqrt(rh) * vals["kh"] / k,
                   Bh=vals["bh"] / skm, BT=vals["bt"] / skm, f=vals["f"], Rr=vals["R1"] / rh,
                   Ec=vals["e"] / rh, G=m * vals["g"] / (k * rh), eta=eta, eps=eps)


#: the paper's presets, one per figure: ``{name: (kh, G, Bh, BT, f, Rr, what it shows)}``
PAPER_TABLE = {
    #         kh     G    Bh    BT    f    Rr   what the paper shows
    "fig4": (10.0, 0.0, 0.0, 0.0, 0.0, 0.0,
             "very weak impacts; X and Y response curves identical"),
    "fig5": (10.0, 0.3, 0.0, 0.0, 0.0, 0.0,
             "Y differs from X; rising part in (0.97, 1.12); double line near 1.2"),
    "fig6": (40.0, 0.3, 0.0, 0.0, 0.0, 0.0, "double line gone; chaotic motion near 1.2"),
    "fig7": (80.0, 0.3, 0.0, 0.0, 0.0, 0.0, "no considerable change from fig6"),
    "fig8": (120.0, 0.3, 0.0, 0.0, 0.0, 0.0,
             "two bottom impacts at 1.185; chaos in (1.21, 1.29)"),
    "fig9": (120.0, 0.3, 0.05, 0.0, 0.0, 0.0, "insignificant change from fig8"),
    "fig10": (120.0, 0.3, 0.0, 0.05, 0.0, 0.0,
              "chaos at 1.2 on the whole circle; period 3 with 8 impacts near 1.40"),
    "fig11": (120.0, 0.3, 0.0, 0.0, 0.05, 0.0,
              "period 6 with 8 bottom impacts in 1.05-1.07; period 10 in 1.3-1.33"),
    "rr10": (120.0, 0.3, 0.0, 0.0, 0.05, 10.0, "shaft radius 10 x clearance: like fig11"),
}

#: rotor speed of a preset until changed (resonance: the rotor reaches the retainer)
DEFAULT_ETA = 1.0


def paper_names() -> list[str]:
    """Names of the paper's presets, in figure order."""
    return list(PAPER_TABLE)


def paper_values(name: str) -> dict:
    """The parameters of the paper's preset ``name`` as ``{name: value}``."""
    kh, G, Bh, BT, f, Rr, _ = PAPER_TABLE[name]
    return dict(B=DEFAULT_B, k3=-0.002, kh=kh, Bh=Bh, BT=BT, f=f, Rr=Rr, Ec=DEFAULT_EC, G=G,
                eta=DEFAULT_ETA)


def describe(name: str) -> str:
    """One line on what the paper's preset ``name`` shows."""
    return PAPER_TABLE[name][6]


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


#: what the rotor's states are, in its files' words
STATE_TEXT = {"X": "horizontal displacement / clearance",
              "Y": "vertical displacement / clearance (+Y down, along gravity)",
              "dX": "horizontal velocity dX/dtau", "dY": "vertical velocity dY/dtau"}

#: what the rotor's plots and tables show
PLOT = PlotSpec(
    xy=("X", "Y"), circle=1.0, circle_label="retainer R = 1",
    circle_name="retainer clearance", y_down=True, y_note="+Y down, along gravity",
    length_unit="clearance",
    symbols={"eta": "η"}, title=("kh", "G", "B", "Ec"),
    title_nonzero=("Bh", "BT", "f", "Rr"), title_hidden=("k3", "eps"),
    preset_columns=("kh", "G", "Bh", "BT", "f", "Rr", "B", "Ec"), preset_marked=("B", "Ec"),
    frequency_text="forcing frequency ratio eta = omega sqrt(m/k)",
    obstacle="retainer", time_name="tau",
    angle_text="theta = atan2(Y, X) of the retainer circle, +90 = bottom",
    preset_note="B and Ec are our defaults, not values from the paper; all the paper's "
                "presets have k3 = -0.002 and eta is set per run (--eta).")


MODEL = Model.builtin_model(
    "rotor", "rotor", ("X", "Y", "dX", "dY"), omega_index=9, param_set=Params, bound=1e3,
    contact=Contact(switch=0, mode=0, penetration=penetration, normal_speed=normal_speed,
                    angle=angle, extremum=2, positions=(0, 1),
                    law=ContactLaw(stiffness="kh", exponent=1.5, damping="Bh", friction="f",
                                   tangential_damping="BT")),
    plot=PLOT, state_text=STATE_TEXT,
    presets={name: (paper_values(name), describe(name)) for name in paper_names()},
    default_preset="fig8",
    # the paper's frequency range; a census where attractors coexist: fig11 at 1.06
    # holds period-8 and period-14 orbits and two period-1 ones with small basins
    references="L. Půst, J. Kozánek: Vibrations of rotor supported in magnetic bearings "
               "with impacts (the rotor model, eq. 5)",
    defaults={"frequencies": "0.9:1.5:0.002", "map_frequencies": "0.9:1.5:0.005",
              "census_preset": "fig11",
              "census_frequency": 1.06})
