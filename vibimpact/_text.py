"""Words for messages: a count and its noun made to agree (:func:`count`), an
exception said on one line (:func:`one_line`)."""
from __future__ import annotations

import numbers


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
