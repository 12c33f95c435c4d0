"""Argument checks shared by the public API: each raises ``ValueError`` naming the argument.

Every public function validates its arguments with these (and nothing else), so the
messages are the same everywhere: ``"<name> must be ..., got <value>"``.
"""
from __future__ import annotations

import math
import numbers

import numpy as np


def count(name, value, minimum=1, maximum=None):
    """``value`` as an ``int`` in ``[minimum, maximum]`` (booleans and floats refused)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    if maximum is not None and value > maximum:
        raise ValueError(f"{name} must be <= {maximum}, got {value!r}")
    return int(value)


def positive(name, value, allow_none=False):
    """``value`` as a finite ``float > 0`` (``None`` passes through with ``allow_none``)."""
    if value is None and allow_none:
        return None
    if isinstance(value, bool):
        raise ValueError(f"{name} must be a number, got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    return v


def finite(name, value):
    """``value`` as a finite ``float`` (anything ``float()`` takes)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return v


def real_positive(name, value):
    """``value`` as a finite ``float > 0``; only real numbers (no strings) accepted."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name} must be a real number > 0, got {value!r}")
    value = float(value)
    if not np.isfinite(value) or value <= 0.0:
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    return value


def state(name, value, n):
    """A validated float copy of a state of ``n`` finite entries (rest, zeros, when
    ``value`` is None)."""
    if value is None:
        return np.zeros(n)
    try:
        y = np.array(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be {n} numbers, got {value!r}") from None
    if y.size != n or not np.all(np.isfinite(y)):
        raise ValueError(f"{name} must be {n} finite numbers, got {value!r}")
    return y


def points(value, name="points"):
    """``value`` as a finite float array of shape (m, d) (a 1-D array is one column)."""
    try:
        x = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a numeric array: {exc}") from None
    if x.ndim == 1:
        x = x[:, None]
    if x.ndim != 2:
        raise ValueError(f"{name} must have shape (m,) or (m, d), got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError(f"{name} must be finite (no NaN or inf)")
    return x
