"""Cases of :mod:`reliability` from the fourth adversarial round: crafted input files, declared sizes checked before reading, and map --overwrite onto foreign directories (issue 44, classes 10, 11 and 12).

(Being written: this module's classes are filled in by the work on issue 44.)
"""
from __future__ import annotations

#: class -> the function that runs its cases: ``func(kit, base, timeout)`` -> Outcomes
CLASSES = {}


def shrink():
    """A smoke run: the first case of each table."""


def measure(kit, base, timeout, only=None):
    """The :class:`Outcome` of every case of these classes (of the classes ``only``)."""
    out = []
    for klass, func in CLASSES.items():
        if only and klass not in only:
            continue
        out += func(kit, base, timeout)
    return out
