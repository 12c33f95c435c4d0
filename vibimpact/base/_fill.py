"""The value of an entry that was not computed: the one place it is made, for every dtype.

A float holds NaN, a complex number NaN in *both* parts (``complex(nan, nan)``: a result
split into real and imaginary parts must not read as a computed 0 in one of them), text the
empty string, and an integer or flag variable its declared fill value, which the caller
names (there is no integer NaN).
"""
from __future__ import annotations

import math

import numpy as np

#: the complex "not computed": NaN in both parts (``nan + 0j`` would store a 0 imaginary part)
COMPLEX_NAN = complex(math.nan, math.nan)


def fill_value(dtype, fill=None):
    """The "not computed" value of ``dtype``.

    Parameters
    ----------
    dtype : numpy dtype or type
    fill : int, optional
        The declared fill of an integer (or boolean) variable; required for those.

    Returns
    -------
    scalar
        NaN (float), ``complex(nan, nan)`` (complex), ``""`` (text, object), ``fill``
        (integer).

    Raises
    ------
    ValueError
        An integer dtype without ``fill``, or a NaN ``fill`` for it.
    """
    kind = np.dtype(dtype).kind
    if kind == "f":
        return math.nan
    if kind == "c":
        return COMPLEX_NAN
    if kind in "OUS":
        return ""
    if fill is None or (isinstance(fill, float) and math.isnan(fill)):
        raise ValueError(f"an integer variable ({np.dtype(dtype)}) needs its declared fill "
                         f"value, got {fill!r}")
    return fill


def not_computed(shape, dtype=np.float64, fill=None):
    """A new array of ``shape`` and ``dtype`` holding :func:`fill_value` everywhere."""
    return np.full(shape, fill_value(dtype, fill), dtype=dtype)


def complex_parts(values):
    """``(real, imag)`` float arrays of the complex ``values``, NaN in both parts wherever
    either part is NaN (a multiplier not computed is never stored as a computed 0)."""
    z = np.asarray(values, dtype=complex)
    bad = np.isnan(z.real) | np.isnan(z.imag)
    real, imag = z.real.copy(), z.imag.copy()
    real[bad] = np.nan
    imag[bad] = np.nan
    return real, imag
