"""Validated, immutable model parameters.

:class:`Params` holds the ten dimensionless parameters of eq. (5) of Pust & Kozanek
("Vibrations of rotor supported in magnetic bearings with impacts"), with the conventions the paper leaves open fixed below.
:class:`DuffingParams` holds the forced Duffing oscillator, the kernel's second model.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, fields

import numpy as np

from . import _validate as _v

#: Default linear damping of the magnetic support.  NOT from the paper (which omits it; it
#: says only that passive magnetic bearings have very low radial damping): the converged
#: optimum of ``analyses/calibrate.py`` against the paper's interval claims of figs 8, 10
#: and 11, over B = 0 and B log-spaced from 0.001 to 0.1 and over the readings of the
#: paper's contact dampings (``reports/calibration.md`` gives the grid, the objective and
#: the claims that agree; ``tests/test_report_sources.py`` checks these values against it).
DEFAULT_B = 0.01468
#: Default unbalance eccentricity / clearance.  NOT from the paper (which omits it):
#: calibrated with :data:`DEFAULT_B`.
DEFAULT_EC = 0.059

_NONNEGATIVE = ("B", "kh", "Bh", "BT", "f", "Rr", "Ec", "eps")


def _check_finite(name, value):
    return _v.finite(name, value)


class _ParamsMixin:
    """`replace`, `as_array`, `as_dict` for the frozen parameter dataclasses."""

    def replace(self, **changes):
        """A copy with some parameters changed (validated again).

        Raises
        ------
        ValueError
            For an unknown parameter name or an invalid value.
        """
        names = {f.name for f in fields(self)}
        for key in changes:
            if key not in names:
                raise ValueError(f"unknown parameter {key!r}; known: {', '.join(sorted(names))}")
        return dataclasses.replace(self, **changes)

    def as_dict(self):
        """Parameters as an ordered ``{name: float}`` dict."""
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def as_array(self):
        """Parameters as the float64 vector the kernel reads (order of the fields)."""
        return np.array([getattr(self, f.name) for f in fields(self)], dtype=np.float64)


@dataclass(frozen=True)
class Params(_ParamsMixin):
    """Dimensionless parameters of the rotor model, eq. (5) of the paper.

    Parameters
    ----------
    B : float
        Linear viscous damping of the magnetic support, ``b / sqrt(k m)``.  The paper does
        not state it; the default :data:`DEFAULT_B` is calibrated against the paper's
        intervals (``analyses/calibrate.py``), not a value from the paper.
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

    def __post_init__(self):
        for fld in fields(self):
            value = _check_finite(fld.name, getattr(self, fld.name))
            object.__setattr__(self, fld.name, value)
        for name in _NONNEGATIVE:
            if getattr(self, name) < 0.0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)!r}")
        if self.eta <= 0.0:
            raise ValueError(f"eta must be > 0, got {self.eta!r}")

    @property
    def period(self):
        """Forcing period ``2 pi / eta`` in dimensionless time."""
        return 2.0 * math.pi / self.eta

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
            vals[name] = _check_finite(name, value)
        for name in ("m", "k", "rh"):
            if vals[name] <= 0.0:
                raise ValueError(f"{name} must be > 0, got {vals[name]!r}")
        m, k, rh = vals["m"], vals["k"], vals["rh"]
        skm = math.sqrt(k * m)
        eta = 1.0
        if omega is not None:
            eta = _check_finite("omega", omega) * math.sqrt(m / k)
        return cls(B=vals["b"] / skm, k3=rh * rh * vals["k2"], kh=math.sqrt(rh) * vals["kh"] / k,
                   Bh=vals["bh"] / skm, BT=vals["bt"] / skm, f=vals["f"], Rr=vals["R1"] / rh,
                   Ec=vals["e"] / rh, G=m * vals["g"] / (k * rh), eta=eta, eps=eps)


@dataclass(frozen=True)
class DuffingParams(_ParamsMixin):
    """Forced Duffing oscillator ``x'' + delta x' + alpha x + beta x^3 = gamma cos(omega t)``.

    Raises
    ------
    ValueError
        Naming the parameter, for a non-finite value, ``delta < 0`` or ``omega <= 0``.
    """

    delta: float = 0.3
    alpha: float = -1.0
    beta: float = 1.0
    gamma: float = 0.5
    omega: float = 1.2

    def __post_init__(self):
        for fld in fields(self):
            object.__setattr__(self, fld.name, _check_finite(fld.name, getattr(self, fld.name)))
        if self.delta < 0.0:
            raise ValueError(f"delta must be >= 0, got {self.delta!r}")
        if self.omega <= 0.0:
            raise ValueError(f"omega must be > 0, got {self.omega!r}")

    @property
    def period(self):
        """Forcing period ``2 pi / omega``."""
        return 2.0 * math.pi / self.omega
