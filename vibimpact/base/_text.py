"""Words for messages: a count and its noun made to agree (:func:`count`), an
exception said on one line (:func:`one_line`); and numbers as a user writes them
(:func:`parse_real`, :func:`parse_integer`): the one parser of every number given as text
(the command line's options, ``--set``, grids such as ``"0.9:1.5:0.002"``).

Python's ``float`` and ``int`` take more than a user means: digit separators (``"1_0"``
is 10), any Unicode digit (fullwidth ``"１"``), ``"nan"``, ``"inf"`` and ``"infinity"``.
Here a number is ASCII digits with an optional sign, decimal point and exponent (``12``,
``-0.5``, ``.25``, ``1e-3``, ``2.5E+4``), surrounded by nothing but blanks; anything else
is a ``ValueError``, as is a real number too large for a float.  Standard library only
(the command line imports it before numpy).
"""
from __future__ import annotations

import math
import numbers
import re


def count(n, noun, plural=None):
    """``n`` followed by ``noun``, singular for exactly one: ``"1 impact"``, ``"2 impacts"``,
    ``"0 impacts"``.

    Parameters
    ----------
    n : int or float
        A float that is a whole number prints without decimals (``2.0`` -> ``"2"``);
        another float with ``:g``.
    noun : str
        The singular.
    plural : str, optional
        The plural when it is not ``noun + "s"`` (``"boundaries"``).

    Returns
    -------
    str
    """
    if isinstance(n, numbers.Integral):
        text = str(int(n))
    elif float(n).is_integer():
        text = f"{float(n):.0f}"
    else:
        text = f"{float(n):g}"
    return f"{text} {noun if text == '1' else (plural or noun + 's')}"


def one_line(exc):
    """What an exception says, on one line (its text with every run of white space one
    blank), or its class name when it says nothing (a message never shows Python's
    class name otherwise)."""
    return " ".join(str(exc).split()) or type(exc).__name__


#: what a number looks like, in words (for messages)
FORM = "digits 0-9 with an optional sign, decimal point and exponent, e.g. 1.25 or 2e-3"

_REAL = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?", re.ASCII)
_INTEGER = re.compile(r"[+-]?[0-9]+", re.ASCII)
_BLANKS = " \t"


def parse_real(text):
    """``text`` as a finite float, written as a user writes a number.

    Parameters
    ----------
    text : str

    Returns
    -------
    float

    Raises
    ------
    ValueError
        For anything but ASCII digits with an optional sign, point and exponent (no
        ``_``, no non-ASCII digits, no ``nan`` or ``inf``), or a value beyond a float's
        range (``1e999``).

    Examples
    --------
    >>> parse_real("2.5e-3"), parse_real(" -1 ")
    (0.0025, -1.0)
    """
    if not isinstance(text, str) or not _REAL.fullmatch(text.strip(_BLANKS)):
        raise ValueError(f"{text!r} is not a number ({FORM})")
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(f"{text!r} is beyond the range of a floating-point number")
    return value


def parse_integer(text):
    """``text`` as an int: ASCII digits with an optional sign (no ``_``, no point, no
    exponent, no non-ASCII digits); ``ValueError`` otherwise.

    Examples
    --------
    >>> parse_integer("+42")
    42
    """
    if not isinstance(text, str) or not _INTEGER.fullmatch(text.strip(_BLANKS)):
        raise ValueError(f"{text!r} is not an integer (digits 0-9 with an optional sign)")
    return int(text)
