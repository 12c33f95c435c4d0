"""Argument checks shared by the public API: each raises an error naming the argument.

Every public function validates its arguments with these (and nothing else), so the
messages are the same everywhere: ``"<name> must be ..., got <value>"``.  A wrong *type*
(a string where a number belongs, a list for a method's name, ``None`` for an array)
raises :class:`WrongType`, a ``TypeError``; a wrong value or shape (out of range, not
finite, a (2, 2) array for a state) a ``ValueError``.  :class:`WrongType` is a
``ValueError`` as well, so that callers that turn bad input into one line (the command
line) catch both with ``except ValueError``.
"""
from __future__ import annotations

import functools
import inspect
import math
import numbers
import os
from collections.abc import Callable
from typing import Any, TypeVar, cast

import numpy as np

#: a function type, kept by a decorator
_F = TypeVar("_F", bound=Callable[..., Any])


class WrongType(TypeError, ValueError):
    """An argument of the wrong type (a ``TypeError``; also a ``ValueError``, see above)."""


def _real(name, value, what):
    """``value`` as a Python float: real numbers only (bool, str, None, complex, arrays
    of more than one element refused with :class:`WrongType`); a number too large for a
    float is a ``ValueError`` ("must be finite")."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        value = value[()]
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise WrongType(f"{name} must be {what}, got {type(value).__name__} {value!r}"[:200])
    try:
        return float(value)
    except OverflowError:
        raise ValueError(f"{name} must be finite, got {value!r}"[:200]) from None


def choice(name, value, options):
    """``value`` if it is one of the strings ``options`` (a non-string: WrongType)."""
    if not isinstance(value, str):
        raise WrongType(f"{name} must be a str, one of {', '.join(options)}, got "
                        f"{type(value).__name__} {value!r}"[:200])
    if value not in options:
        raise ValueError(f"{name} must be one of {', '.join(options)}, got {value!r}")
    return value


def names(name, value, options):
    """A tuple of strings from ``options``: ``value`` is an iterable of them or one string
    of comma-separated names (``"period,impacts"``; a string is never split into
    letters)."""
    if isinstance(value, str):
        value = [v.strip() for v in value.split(",") if v.strip()]
    try:
        items = tuple(value)
    except TypeError:
        raise WrongType(f"{name} must be a sequence of str (from {', '.join(options)}), "
                        f"got {type(value).__name__} {value!r}"[:200]) from None
    wrong = [v for v in items if not isinstance(v, str)]
    if wrong:
        raise WrongType(f"{name} must hold str, got {type(wrong[0]).__name__} "
                        f"{wrong[0]!r}"[:200])
    bad = [v for v in items if v not in options]
    if bad:
        raise ValueError(f"{name}: unknown {', '.join(bad)}; choose from "
                         f"{', '.join(options)}")
    return items


def numeric(name, value, what="a numeric array"):
    """``value`` as a new C-contiguous float64 array, from real numbers only.

    Integers and floats (Python's or numpy's) are taken; strings (also digits such as
    ``'0.1'``), bytes, ``None``, mappings, booleans, complex numbers (whose imaginary
    part would be dropped) and objects that are not real numbers are
    :class:`WrongType`.  Memory order and strides of the input do not matter."""
    if value is None or isinstance(value, (str, bytes, dict)):
        raise WrongType(f"{name} must be {what}, got {type(value).__name__} "
                        f"{value!r}"[:200])
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:  # ragged nested sequences
        raise WrongType(f"{name} must be {what}: {exc}"[:200]) from None
    if arr.dtype.kind == "O":
        flat = arr.reshape(-1)
        if not all(isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_))
                   for v in flat):
            bad = next(v for v in flat if not isinstance(v, numbers.Real)
                       or isinstance(v, (bool, np.bool_)))
            raise WrongType(f"{name} must be {what} of real numbers, got an element "
                            f"{type(bad).__name__} {bad!r}"[:200])
    elif arr.dtype.kind not in "iuf":
        kind = {"c": "complex", "b": "boolean", "U": "string", "S": "bytes"}.get(
            arr.dtype.kind, str(arr.dtype))
        raise WrongType(f"{name} must be {what} of real numbers, got {kind} values"
                        + (" (the imaginary part would be lost)" if kind == "complex"
                           else ""))
    try:
        return np.array(arr, dtype=np.float64, order="C")
    except OverflowError:
        raise ValueError(f"{name} must be finite") from None


def array1d(name, value, what="numbers"):
    """``value`` as a 1-D float64 array (a single number is one element): strings, None,
    mappings and other non-numeric values are :class:`WrongType`, more than one
    dimension a ``ValueError`` with the shape."""
    arr = numeric(name, value, f"{what} (a 1-D array)")
    if arr.ndim > 1:
        raise ValueError(f"{name} must be 1-D, got shape {arr.shape}")
    return arr.reshape(-1)


def count(name, value, minimum=1, maximum=None):
    """``value`` as an ``int`` in ``[minimum, maximum]`` (booleans and floats refused)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise WrongType(f"{name} must be an integer >= {minimum}, got "
                        f"{type(value).__name__} {value!r}"[:200])
    if value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    if maximum is not None and value > maximum:
        raise ValueError(f"{name} must be <= {maximum}, got {value!r}")
    return int(value)


def positive(name, value, allow_none=False):
    """``value`` as a finite ``float > 0`` (``None`` passes through with ``allow_none``)."""
    if value is None and allow_none:
        return None
    v = _real(name, value, "a number")
    if not math.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    return v


def finite(name, value):
    """``value`` as a finite ``float`` (a real number: no strings)."""
    v = _real(name, value, "a real number")
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return v


def real_positive(name, value):
    """``value`` as a finite ``float > 0``; only real numbers (no strings) accepted."""
    value = _real(name, value, "a real number > 0")
    if not np.isfinite(value) or value <= 0.0:
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    return value


def state(name, value, n):
    """A validated float copy of a state of ``n`` finite entries (rest, zeros, when
    ``value`` is None)."""
    if value is None:
        return np.zeros(n)
    y = array1d(name, value, f"{n} numbers")
    if np.ndim(value) != 1:
        raise ValueError(f"{name} must have shape ({n},), got shape {np.shape(value)}")
    if y.size != n or not np.all(np.isfinite(y)):
        raise ValueError(f"{name} must be {n} finite numbers, got {value!r}")
    return y


def points(value, name="points"):
    """``value`` as a finite float array of shape (m, d) (a 1-D array is one column)."""
    x = numeric(name, value)
    if x.ndim == 1:
        x = x[:, None]
    if x.ndim != 2:
        raise ValueError(f"{name} must have shape (m,) or (m, d), got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError(f"{name} must be finite (no NaN or inf)")
    return x


def flag(name, value):
    """``value`` as a ``bool``: only ``True``/``False`` (numpy's included); a string such as
    ``"no"`` (which Python would take as true) is :class:`WrongType`."""
    if not isinstance(value, (bool, np.bool_)):
        raise WrongType(f"{name} must be True or False, got {type(value).__name__} "
                        f"{value!r}"[:200])
    return bool(value)


def power_of_two(x, shrink_only=False):
    """The power of two ``2**k`` with ``1 <= max |x| / 2**k < 2`` (1.0 for an all-zero
    ``x``; with ``shrink_only``, 1.0 unless ``max |x| >= 2``).

    Dividing finite data by it is exact (only the exponent moves; values below about
    ``2**-1022`` times the largest lose bits and are negligible against it), so an
    analyser that divides its data by it first decides the same at every magnitude,
    without the overflow of squares, differences and ranges near ``1e308`` or the
    underflow of subnormal data.
    """
    peak = float(np.max(np.abs(x))) if np.size(x) else 0.0
    if peak == 0.0 or (shrink_only and peak < 2.0):
        return 1.0
    return float(np.ldexp(1.0, int(np.frexp(peak)[1]) - 1))  # at most 2**1023


_FLAG_ANNOTATIONS = {"bool": False, bool: False, "bool | None": True, bool | None: True,
                     "None | bool": True, None | bool: True,
                     "Optional[bool]": True, "typing.Optional[bool]": True}


def flag_annotation(annotation):
    """``None`` if ``annotation`` is not a flag's; ``False`` for ``bool``; ``True`` for
    ``bool | None`` (``Optional[bool]``), a flag whose ``None`` means "decide for me"."""
    try:
        return _FLAG_ANNOTATIONS.get(annotation)
    except TypeError:  # an unhashable annotation is not a flag's
        return None


def checks_flags(fn: _F) -> _F:
    """Decorate ``fn`` so that every argument annotated ``bool`` or ``bool | None`` is
    checked by :func:`flag` before ``fn`` runs: ``adaptive='no'``, ``1`` or a one-element
    array is :class:`WrongType` naming the argument, whatever else ``fn`` is given (a call
    that does not fit the signature is left to ``fn``'s own ``TypeError``). ``None`` is
    refused for ``bool`` and passed on for ``bool | None``."""
    sig = inspect.signature(fn)
    kinds = {n: flag_annotation(p.annotation) for n, p in sig.parameters.items()}
    names = tuple(n for n, k in kinds.items() if k is not None)
    # where each flag is found in a call, worked out once (no inspect in the call: the
    # kernel's hot paths go through here): its index among the positional arguments,
    # whether it may be given by keyword; and what makes a call not fit the signature
    params = list(sig.parameters.values())
    P = inspect.Parameter
    ordered = [p.name for p in params if p.kind in (P.POSITIONAL_ONLY,
                                                    P.POSITIONAL_OR_KEYWORD)]
    index = {n: ordered.index(n) for n in names if n in ordered}
    by_keyword = {p.name for p in params if p.kind in (P.POSITIONAL_OR_KEYWORD,
                                                       P.KEYWORD_ONLY)}
    more_args = any(p.kind is P.VAR_POSITIONAL for p in params)
    more_kwargs = any(p.kind is P.VAR_KEYWORD for p in params)

    def fits(args, kwargs):
        """Whether the call fits the signature as far as flags are concerned (as
        ``sig.bind_partial`` would: not too many positional arguments, no unknown or
        twice-given keyword)."""
        if len(args) > len(ordered) and not more_args:
            return False
        for key in kwargs:
            if key not in by_keyword:
                if not more_kwargs or key in ordered:
                    return False
            elif key in ordered and ordered.index(key) < len(args):
                return False
        return True

    @functools.wraps(fn)
    def checked(*args, **kwargs):
        if names and fits(args, kwargs):
            for name in names:
                if name in kwargs:
                    value = kwargs[name]
                elif index.get(name, len(args)) < len(args):
                    value = args[index[name]]
                else:
                    continue
                if not (kinds[name] and value is None):
                    flag(name, value)
        return fn(*args, **kwargs)

    checked.checked_flags = names  # type: ignore[attr-defined]  # an attribute of a function
    return cast(_F, checked)  # the same signature: a wrapper that checks, then calls fn


def path(name: str, value: object, allow_empty: bool = False) -> str:
    """``value`` as a ``str`` path: a ``str``, ``bytes`` (decoded as the file system
    does) or an ``os.PathLike``, anything else :class:`WrongType`; an empty path a
    ``ValueError`` unless ``allow_empty``."""
    if not isinstance(value, (str, bytes, os.PathLike)):
        raise WrongType(f"{name} must be a path (str or os.PathLike), got "
                        f"{type(value).__name__} {value!r}"[:200])
    text = os.fsdecode(os.fspath(value))
    if not text and not allow_empty:
        raise ValueError(f"{name} must be a non-empty path, got {value!r}")
    return text


def dataset(name, value, what="an xarray.Dataset", hint=""):
    """``value`` if it is an ``xarray.Dataset``; :class:`WrongType` naming ``name`` and
    saying what to pass (``what``, then ``hint``) otherwise."""
    import xarray as xr

    if not isinstance(value, xr.Dataset):
        raise WrongType(f"{name} must be {what}, got {type(value).__name__}{hint}")
    return value
