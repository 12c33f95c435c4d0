"""Validated, immutable model parameters: the machinery every model's parameter set uses.

A built-in model declares its parameter set in its own module
(:mod:`vibimpact.builtin_models`), either as a frozen dataclass over :class:`ParamsMixin`
or with :func:`param_set` from a table.  The values each parameter may take are stated
once, as a :class:`Domain` per parameter (``<set>.domain(name)``): the sets validate
against them, and the continuation reads them (:meth:`vibimpact.System.param_domain`) to
step up to a bound but never past it.

The parameter sets that once lived here (``Params``, ``DuffingParams``, ``DEFAULT_B``,
...) are still importable from this module: any name a built-in model's module defines is
found through the registry (:func:`__getattr__`), so old imports and old pickles work.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from ..base import _validate as _v



def _check_finite(name, value):
    return _v.finite(name, value)


@dataclass(frozen=True)
class Domain:
    """The values a parameter may take: the interval from ``lo`` to ``hi``.

    The one statement of a parameter's domain: every model's parameter set validates
    against it, and
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


class ParamsMixin:
    """`replace`, `as_array`, `as_dict`, `domain` for the frozen parameter dataclasses."""

    #: {name: Domain} of the parameters that have one (the others: any finite number)
    _DOMAINS: ClassVar[dict[str, Domain]] = {}
    #: the name of the forcing frequency's field (the set's :attr:`period` is
    #: ``2 pi`` over it)
    _FREQUENCY: ClassVar[str] = ""

    if TYPE_CHECKING:  # every class that mixes it in is a dataclass
        __dataclass_fields__: ClassVar[dict[str, dataclasses.Field[Any]]]

    @classmethod
    def domain(cls, name: str) -> Domain:
        """The :class:`Domain` of parameter ``name`` (unbounded if it has none).

        Raises
        ------
        ValueError
            Naming ``name`` when it is not a parameter of this model.
        """
        names = [f.name for f in fields(cls)]
        if name not in names:
            raise ValueError(f"name must be one of {', '.join(names)}, got {name!r}")
        return cls._DOMAINS.get(name, Domain())

    def __post_init__(self):
        self._check_domains()

    @property
    def period(self) -> float:
        """Forcing period ``2 pi / omega`` (``omega``: the set's forcing frequency,
        :attr:`_FREQUENCY`)."""
        return 2.0 * math.pi / getattr(self, self._FREQUENCY)

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
        A frozen dataclass with :class:`ParamsMixin`'s methods (``replace``, ``as_array``,
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
        "_FREQUENCY": omega,
        "__doc__": "\n".join(lines) + "\n",
        "__module__": module,
    }
    cls = dataclasses.make_dataclass(
        name, [(n, float, dataclasses.field(default=v)) for n, v, _, _ in rows],
        bases=(ParamsMixin,), namespace=namespace, frozen=True)
    return cls


def __getattr__(name):
    """A name that moved into a built-in model's module (``Params``, ``DuffingParams``,
    ``DEFAULT_B``, ...): the first registered model whose module defines it."""
    if name.startswith("__"):
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib
    import sys

    from .. import models

    for mname in models.names():
        pset = models.get(mname).param_set
        if pset is None:
            continue
        module = sys.modules.get(pset.__module__) or importlib.import_module(pset.__module__)
        if name in vars(module):
            return vars(module)[name]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
