"""The kernel's built-in models, found by name: one kernel module each.

A built-in model is one module of this package (``rotor``, ``duffing``, ``soft_impact``,
...) that ends with a :class:`KernelModel` named ``KERNEL_MODEL``: its ``@njit``
right-hand side, Jacobian, switching functions, mode transition, initial mode, the
variational versions of the right-hand side and the transition (tangent vectors and
saltation matrices; :mod:`.variational` builds them from the model's functions when the
module has no hand-written ones), an optional step cap, and its sizes.  The model's
*family* is the module's name.  :mod:`.dispatch` reads the entry at compile time, so
adding a built-in model touches no other kernel module.

Nothing here is jitted; the entries hold numba dispatchers.
"""
from __future__ import annotations

import importlib
import re
from typing import NamedTuple
from collections.abc import Callable

import numpy as np


class KernelModel(NamedTuple):
    """What the kernel calls for one built-in model (a module's ``KERNEL_MODEL``).

    Attributes
    ----------
    rhs, jac, switches, transition, init_mode : numba dispatchers
        With the signatures of :mod:`vibimpact._kernel.integrator` (``rhs(s, y, p, mode,
        out)``, ``jac(s, y, p, mode, J)``, ``switches(s, y, p, mode, g)``,
        ``transition(s, y, p, mode, which)``, ``init_mode(s, y, p, mode)``).
    var_rhs, var_transition : numba dispatchers
        The variational versions: state followed by tangent vectors
        (:func:`.variational.tangent_rhs`, :func:`.variational.saltation_transition`).
    step_cap : numba dispatcher or None
        ``step_cap(y, p, mode, f0, at_event, rtol, atol, n_norm, g_in, g_out)``: the
        largest step the model's non-smooth force allows (``None``: no cap).
    n_state, n_mode : int
    terminal : ndarray of int64, shape (n_switch,)
        1 for a mode-changing switch, 0 for an observer.
    param_names : tuple of str
        The parameter vector's layout.
    """

    rhs: Callable
    jac: Callable
    switches: Callable
    transition: Callable
    init_mode: Callable
    var_rhs: Callable
    var_transition: Callable
    step_cap: Callable | None
    n_state: int
    n_mode: int
    terminal: np.ndarray
    param_names: tuple

    @property
    def sizes(self):
        """``(n_state, n_param, n_mode, n_switch)``."""
        return (self.n_state, len(self.param_names), self.n_mode, int(self.terminal.size))


def kernel_model(rhs, jac, switches, transition, init_mode, n_state, n_mode, terminal,
                 param_names, step_cap=None) -> KernelModel:
    """The :class:`KernelModel` of a module whose variational equations are the generic
    ones: :func:`.variational.tangent_rhs` over ``rhs`` and ``jac``, and
    :func:`.variational.saltation_transition` (the one saltation) over ``rhs``,
    ``switches`` and ``transition``.

    Parameters
    ----------
    rhs, jac, switches, transition, init_mode : numba dispatchers
    n_state, n_mode : int
    terminal : ndarray of int64, shape (n_switch,)
    param_names : tuple of str
    step_cap : numba dispatcher, optional
    """
    from .variational import saltation_transition, tangent_rhs

    return KernelModel(rhs=rhs, jac=jac, switches=switches, transition=transition,
                       init_mode=init_mode, var_rhs=tangent_rhs(rhs, jac, n_state),
                       var_transition=saltation_transition(rhs, switches, transition,
                                                           n_state, terminal.size),
                       step_cap=step_cap, n_state=n_state, n_mode=n_mode,
                       terminal=terminal, param_names=tuple(param_names))


def families() -> list[str]:
    """The names of every built-in family: the modules of this package that declare a
    ``KERNEL_MODEL`` (each imported to see)."""
    import pkgutil

    found = []
    for info in pkgutil.iter_modules(importlib.import_module(__package__).__path__):
        if info.ispkg or not _FAMILY_NAME.match(info.name):
            continue
        module = importlib.import_module(f"{__package__}.{info.name}")
        if isinstance(getattr(module, "KERNEL_MODEL", None), KernelModel):
            found.append(info.name)
    return sorted(found)


_FAMILY_NAME = re.compile(r"[a-z][a-z0-9_]*\Z")
_LOADED: dict[str, KernelModel] = {}


def family(name: str) -> KernelModel:
    """The :class:`KernelModel` of the built-in family ``name`` (its module's name).

    Raises
    ------
    ValueError
        When no module of this package of that name declares ``KERNEL_MODEL``.
    """
    entry = _LOADED.get(name)
    if entry is not None:
        return entry
    if not isinstance(name, str) or not _FAMILY_NAME.match(name):
        raise ValueError(f"kernel: no built-in model family {name!r}")
    try:
        module = importlib.import_module(f"{__package__}.{name}")
    except ModuleNotFoundError:
        raise ValueError(f"kernel: no built-in model family {name!r}") from None
    entry = getattr(module, "KERNEL_MODEL", None)
    if not isinstance(entry, KernelModel):
        raise ValueError(f"kernel: module {name!r} declares no KERNEL_MODEL")
    _LOADED[name] = entry
    return entry
