"""The built-in models, one module each.

Every module here declares one :class:`vibimpact.models.Model` named ``MODEL`` (made with
:meth:`~vibimpact.models.Model.builtin_model` over the kernel module of the same family)
and is found by :func:`load`: a new built-in model is its kernel module
(``vibimpact/_kernel/<family>.py``), its module here (parameter table, presets, contact,
plots) and its tests; nothing else names it.  ``docs/user_guide/models.rst`` walks through
adding one.
"""
from __future__ import annotations

import importlib
import pkgutil

#: the order of the first models (the others follow by name)
_FIRST = ("rotor", "duffing")


def load():
    """Import every module of this package; returns their ``MODEL``s in order (the
    registry, :func:`vibimpact.models.names`, registers them)."""
    found = sorted(m.name for m in pkgutil.iter_modules(__path__) if not m.ispkg)
    order = [n for n in _FIRST if n in found] + [n for n in found if n not in _FIRST]
    return [importlib.import_module(f"{__name__}.{name}").MODEL for name in order]
