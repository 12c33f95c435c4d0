"""Validated, immutable model parameters.

:class:`Params` holds the ten dimensionless parameters of eq. (5) of Pust & Kozanek
("Vibrations of rotor supported in magnetic bearings with impacts"), with the conventions the paper
leaves open fixed below.
:class:`DuffingParams` holds the forced Duffing oscillator, the kernel's second model.
The values each parameter may take are stated once, as a :class:`Domain` per parameter
(``Params.domain(name)``): the sets validate against them, and the continuation reads
them (:meth:`vibimpact.System.param_domain`) to step up to a bound but never past it.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, fields
from typing import ClassVar

import numpy as np

from ..base import _validate as _v

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

_NONNEGATIVE = ("B", "kh", "Bh", "BT", "f", "Rr", "Ec", "eps")


def _check_finite(name, value):
    return _v.finite(name, value)


@dataclass(frozen=True)
class Domain:
    """The values a parameter may take: the interval from ``lo`` to ``hi``.

    The one statement of a parameter's domain: :class:`Params` and
    :class:`DuffingParams` validate against it, and
    :meth:`vibimpact.System.param_domain` hands it to the continuation, which steps up to
    a bound but never past it.

    Parameters
    ----------
    lo, hi : float
        The bounds (``-inf``, ``inf``: none on that side).
    lo_closed, hi_closed : bool
        Whether the bound itself is allowed (``>= lo``) or not (``> lo``).

    Examples
    --------
    >>> d = Domain.at_least(0.0)
    >>> (0.0 in d, -1e-6 in d, d.rule("BT"))
    (True, False, 'BT must be >= 0')
    """

    lo: float = -math.inf
    hi: float = math.inf
    lo_closed: bool = False
    hi_closed: bool = False

    def __post_init__(self):
        for name in ("lo", "hi"):
            value = _v._real(name, getattr(self, name), "a real number (or +-inf)")
            if math.isnan(value):
                raise ValueError(f"{name} must be a number or +-inf, got nan")
            object.__setattr__(self, name, value)
        for name in ("lo_closed", "hi_closed"):
            object.__setattr__(self, name, _v.flag(name, getattr(self, name)))
        if self.lo > self.hi:
            raise ValueError(f"lo must be <= hi, got lo = {self.lo!r}, hi = {self.hi!r}")

    @classmethod
    def at_least(cls, lo: float) -> Domain:
        """``[lo, inf)``: the value ``>= lo``."""
        return cls(lo=float(lo), lo_closed=True)

    @classmethod
    def above(cls, lo: float) -> Domain:
        """``(lo, inf)``: the value ``> lo``."""
        return cls(lo=float(lo))

    def __contains__(self, value: float) -> bool:
        """Whether ``value`` is a finite number inside the domain."""
        v = float(value)
        if not math.isfinite(v):
            return False
        above = v >= self.lo if self.lo_closed else v > self.lo
        below = v <= self.hi if self.hi_closed else v < self.hi
        return above and below

    def rule(self, name: str) -> str:
        """What the domain asks of parameter ``name``, e.g. ``"eta must be > 0"``."""
        parts = []
        if math.isfinite(self.lo):
            parts.append(f"{'>=' if self.lo_closed else '>'} {self.lo:g}")
        if math.isfinite(self.hi):
            parts.append(f"{'<=' if self.hi_closed else '<'} {self.hi:g}")
        return f"{name} must be {' and '.join(parts) or 'finite'}"

    def check(self, name: str, value: float) -> float:
        """``value`` (a finite float); ``ValueError`` with :meth:`rule` otherwise."""
        if value not in self:
            raise ValueError(f"{self.rule(name)}, got {value!r}")
        return value


#: the domain of each rotor parameter that has one (validated in this order)
_ROTOR_DOMAINS = {**{name: Domain.at_least(0.0) for name in _NONNEGATIVE},
                  "eta": Domain.above(0.0)}
#: the domain of each Duffing parameter that has one (validated in this order)
_DUFFING_DOMAINS = {"delta": Domain.at_least(0.0), "omega": Domain.above(0.0)}


class _ParamsMixin:
    """`replace`, `as_array`, `as_dict`, `domain` for the frozen parameter dataclasses."""

    #: {name: Domain} of the parameters that have one (the others: any finite number)
    _DOMAINS: ClassVar[dict[str, Domain]] = {}

    @classmethod
    def domain(cls, name: str) -> Domain:
        """The :class:`Domain` of parameter ``name`` (unbounded if it has none).

        Raises
        ------
        ValueError
            Naming ``name`` when it is not a parameter of this model.
        """
        # cls: one of the frozen dataclasses that mix this class in
        names = [f.name for f in fields(cls)]  # type: ignore[arg-type]
        if name not in names:
            raise ValueError(f"name must be one of {', '.join(names)}, got {name!r}")
        return cls._DOMAINS.get(name, Domain())

    def _check_domains(self):
        """Validate every field: finite, and inside its domain (in ``_DOMAINS`` order)."""
        for fld in fields(self):
            object.__setattr__(self, fld.name, _check_finite(fld.name, getattr(self, fld.name)))
        for name, dom in self._DOMAINS.items():
            dom.check(name, getattr(self, name))

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

    def __post_init__(self):
        self._check_domains()

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

    _DOMAINS = _DUFFING_DOMAINS

    def __post_init__(self):
        self._check_domains()

    @property
    def period(self):
        """Forcing period ``2 pi / omega``."""
        return 2.0 * math.pi / self.omega


def param_set(name: str, table, omega: str, module: str, doc: str = "") -> type:
    """A frozen, validated parameter set made from a table (for a built-in model declared
    as data, :mod:`vibimpact.builtin_models`).

    Parameters
    ----------
    name : str
        The class's name.
    table : sequence of (str, float, Domain or None, str)
        One row per parameter, in the kernel's order: its name, default, domain (None:
        any finite number) and meaning.
    omega : str
        The forcing frequency's name (the set's ``period`` is ``2 pi / omega``).
    module : str
        The module that binds the class to ``name`` (so that it pickles, for worker
        processes).
    doc : str
        What the model is (the class's docstring; the table is appended to it).

    Returns
    -------
    type
        A frozen dataclass with :class:`Params`'s methods (``replace``, ``as_array``,
        ``as_dict``, ``domain``); a value outside its domain raises ``ValueError`` naming
        the parameter.
    """
    rows = [(n, float(v), d, text) for n, v, d, text in table]
    lines = [doc.rstrip(), "", "Parameters", "----------"]
    for n, v, d, text in rows:
        lines += [f"{n} : float", f"    {text} (default {v!r}"
                  + (f"; {d.rule(n).split(' must be ')[1]}" if d is not None else "") + ")."]
    namespace = {
        "_DOMAINS": {n: d for n, _, d, _ in rows if d is not None},
        "__post_init__": lambda self: self._check_domains(),
        "period": property(lambda self: 2.0 * math.pi / getattr(self, omega),
                           doc=f"Forcing period ``2 pi / {omega}``."),
        "__doc__": "\n".join(lines) + "\n",
        "__module__": module,
    }
    cls = dataclasses.make_dataclass(
        name, [(n, float, dataclasses.field(default=v)) for n, v, _, _ in rows],
        bases=(_ParamsMixin,), namespace=namespace, frozen=True)
    return cls
