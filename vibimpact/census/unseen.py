"""How much basin a census may not have seen: the Good–Turing estimate and the resolution
of ``N`` starts.

A census draws ``N`` starting states and counts how many reach each attractor.  An
attractor whose basin is small may be reached by none of them.  Two numbers bound what
was missed:

* the **Good–Turing estimate** of the missing mass, ``f1 / N`` with ``f1`` the number of
  attractors reached by exactly one start (Good, *Biometrika* 40, 237 (1953)): the
  share of the starting box whose attractor was not found, nearly unbiased for any basin
  fractions (its mean is the missing mass of ``N - 1`` starts);
* the **resolution** ``1 - (1 - c) ** (1 / N)`` (``c = 0.95``: about ``3 / N``): an
  attractor whose basin fraction exceeds it is reached by at least one of ``N``
  independent starts with probability ``c`` or more, so that ``N`` starts cannot tell
  an attractor below it from none.

:func:`unseen_mass` reports the larger of the two, never 0: a census of few starts, all
on one attractor, has ``f1 = 0`` and would otherwise claim to have seen everything.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["good_turing", "resolution", "unseen_mass", "CONFIDENCE"]

#: the probability with which the resolution's basins are reached
CONFIDENCE = 0.95


def good_turing(counts, n: int) -> float:
    """The Good–Turing estimate ``f1 / n`` of the mass of the classes not seen.

    Parameters
    ----------
    counts : array_like of int, shape (k,)
        Starts per attractor (zeros are ignored).
    n : int
        Starts drawn (>= 1; starts on no attractor count here, not in ``counts``).

    Returns
    -------
    float
        In ``[0, 1]``.
    """
    c = np.asarray(counts, dtype=np.int64).ravel()
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    return float(np.count_nonzero(c == 1)) / float(n)


def resolution(n: int, confidence: float = CONFIDENCE) -> float:
    """The basin fraction above which one attractor is reached by one of ``n`` uniform
    starts at least with probability ``confidence``: ``1 - (1 - confidence) ** (1 / n)``."""
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence must be in (0, 1), got {confidence}")
    return -math.expm1(math.log1p(-confidence) / n)


def unseen_mass(counts, n: int) -> tuple[float, float, int]:
    """``(unseen, good_turing, singletons)`` of a census point: ``unseen`` is the larger
    of the Good–Turing estimate and the resolution of ``n`` starts (module docstring)."""
    c = np.asarray(counts, dtype=np.int64).ravel()
    gt = good_turing(c, n)
    return max(gt, resolution(n)), gt, int(np.count_nonzero(c == 1))
