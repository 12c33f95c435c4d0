"""Models known to the kernel: the rotor of eq. (5), the forced Duffing oscillator, and
user models built from numba functions.

A model is its right-hand side, Jacobian, switching surfaces and mode transitions (all
``@njit``, signatures in :mod:`vibimpact._kernel.integrator`) plus a little metadata.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from dataclasses import dataclass
from typing import Callable

import numpy as np
from numba.extending import is_jitted

from ._kernel import duffing as _duffing
from ._kernel import dispatch as _dispatch
from ._kernel import rotor as _rotor
from ._kernel.boundary import Problem
from ._kernel.precompiled import routine as _precompiled
from . import _validate as _v
from .model_probe import check_model
from .params import DuffingParams, Params

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Sequence

    from numpy.typing import ArrayLike


@dataclass(frozen=True)
class Model:
    """A piecewise-smooth, periodically forced model for :func:`vibimpact.simulate`.

    Attributes
    ----------
    name : str
    state_names : tuple of str
    param_names : tuple of str
        Order of the parameter vector the kernel reads.
    omega_index : int
        Index of the forcing frequency in the parameter vector.
    n_mode : int
        Length of the discrete-mode vector.
    terminal : ndarray of int64, shape (n_switch,)
        1 for a mode-changing switching function, 0 for an observer.
    kernel_model : int or tuple
        What the kernel receives as ``model``: a built-in id or ``(rhs, switches,
        transition)``.
    rhs, jac, switches, transition, init_mode : numba functions
    bound : float
        A state component larger than this in magnitude ends the run as DIVERGED.
    param_set : type, optional
        A built-in model's parameter set (:class:`~vibimpact.params.Params`,
        :class:`~vibimpact.params.DuffingParams`): where its parameters' domains are
        stated, also for a plain parameter vector of the model.
    """

    name: str
    state_names: tuple
    param_names: tuple
    omega_index: int
    n_mode: int
    terminal: np.ndarray
    kernel_model: object
    rhs: Callable
    jac: Callable
    switches: Callable
    transition: Callable
    init_mode: Callable
    bound: float = 1e3
    param_set: type = None

    def problem(self, p: ArrayLike, variational: bool = False) -> Problem:
        """The kernel's :class:`~vibimpact._kernel.boundary.Problem` for parameter vector
        ``p`` (of the variational equations with ``variational``)."""
        if not isinstance(self.kernel_model, int) and not self.__dict__.get("_probed"):
            # a user model: its sizes are checked on guarded buffers before the kernel
            # runs its functions (once per model object)
            check_model(self, p)
            object.__setattr__(self, "_probed", True)
        kmodel = self.variational_kernel_model if variational else self.kernel_model
        return Problem(kmodel, self.terminal, self.n_mode, p, float(p[self.omega_index]),
                       self.init_mode, n_state=len(self.state_names))

    @property
    def variational_kernel_model(self):
        """What the kernel receives for the variational equations of this model.

        The state followed by tangent vectors, mapped by saltation matrices at every
        switch (:mod:`vibimpact._kernel.variational`).
        """
        if isinstance(self.kernel_model, int):
            return self.kernel_model + _dispatch.VAR_OFFSET
        rhs, switches, transition = self.kernel_model
        return (rhs, switches, transition, self.jac, len(self.state_names),
                int(self.terminal.size))

    @classmethod
    def from_functions(cls, name: str, rhs: Callable, jac: Callable, switches: Callable,
                       transition: Callable, init_mode: Callable, terminal: Callable,
                       state_names: Sequence[str], param_names: Sequence[str],
                       omega_index: int, n_mode: int = 1, bound: float = 1e3) -> Model:
        """A user model from numba functions (compiled on first use, not cached on disk).

        Parameters
        ----------
        rhs, jac, switches, transition, init_mode : numba ``@njit`` functions
            With the signatures of :mod:`vibimpact._kernel.rotor`.
        terminal : sequence of int
            One entry per switching function: 1 terminal, 0 observer.  A smooth model
            gives one observer (e.g. a velocity) so that the array is never empty.
        state_names, param_names : sequence of str
        omega_index : int
            Index of the forcing frequency in the parameter vector.
        """
        if not isinstance(name, str) or not name:
            raise _v.WrongType(f"name must be a non-empty str, got {name!r}"[:200])
        for arg, fn in (("rhs", rhs), ("jac", jac), ("switches", switches),
                        ("transition", transition), ("init_mode", init_mode)):
            if not is_jitted(fn):
                what = ("a plain Python function" if callable(fn) else
                        f"{type(fn).__name__} {fn!r}"[:80])
                raise _v.WrongType(f"{arg} must be compiled with numba (decorate it with "
                                   f"@numba.njit), got {what}")
        states = _names("state_names", state_names)
        params = _names("param_names", param_names)
        term = _v.array1d("terminal", terminal, "0s and 1s")
        if term.size == 0 or not np.all((term == 0) | (term == 1)):
            raise ValueError(f"terminal must list at least one switching function, each 1 "
                             f"(terminal) or 0 (observer), got {terminal!r}"[:200])
        omega_index = _v.count("omega_index", omega_index, 0)
        if omega_index >= len(params):
            raise ValueError(f"omega_index must index param_names (0 to {len(params) - 1}), "
                             f"got {omega_index}")
        return cls(name=name, state_names=states, param_names=params,
                   omega_index=omega_index, n_mode=_v.count("n_mode", n_mode, 0),
                   terminal=term.astype(np.int64), kernel_model=(rhs, switches, transition),
                   rhs=rhs, jac=jac, switches=switches, transition=transition,
                   init_mode=init_mode, bound=_v.positive("bound", bound))


def _names(arg, value):
    """A non-empty tuple of distinct, non-empty names."""
    if isinstance(value, str):
        raise _v.WrongType(f"{arg} must be a sequence of str, got the str {value!r}"[:200])
    try:
        names = tuple(value)
    except TypeError:
        raise _v.WrongType(f"{arg} must be a sequence of str, got "
                           f"{type(value).__name__}") from None
    if not names or not all(isinstance(v, str) and v for v in names):
        raise ValueError(f"{arg} must be one or more non-empty str, got {names!r}"[:200])
    if len(set(names)) != len(names):
        raise ValueError(f"{arg} must be distinct, got {names!r}"[:200])
    return names


ROTOR = Model(name="rotor", state_names=("X", "Y", "dX", "dY"), param_names=_rotor.PARAM_NAMES,
              omega_index=_rotor.I_ETA, n_mode=_rotor.N_MODE, terminal=_rotor.TERMINAL,
              kernel_model=_dispatch.ROTOR, rhs=_rotor.rhs, jac=_rotor.jac,
              switches=_rotor.switches, transition=_rotor.transition,
              init_mode=_precompiled("rotor_init_mode", _rotor.init_mode), bound=1e3,
              param_set=Params)

DUFFING = Model(name="duffing", state_names=("x", "dx"), param_names=_duffing.PARAM_NAMES,
                omega_index=4, n_mode=_duffing.N_MODE, terminal=_duffing.TERMINAL,
                kernel_model=_dispatch.DUFFING, rhs=_duffing.rhs, jac=_duffing.jac,
                switches=_duffing.switches, transition=_duffing.transition,
                init_mode=_duffing.init_mode, bound=1e6, param_set=DuffingParams)


def resolve(p, model=None):
    """The model and the parameter vector of ``p``.

    Parameters
    ----------
    p : Params, DuffingParams or array_like
        Parameters; a plain vector needs ``model``.
    model : Model, optional
        A user model; ``p`` is then its parameter vector.

    Returns
    -------
    (Model, ndarray of float64)

    Raises
    ------
    ValueError
        Naming ``model`` or ``p``.
    """
    if model is not None:
        if not isinstance(model, Model):
            raise _v.WrongType(f"model must be a vibimpact.models.Model, got "
                               f"{type(model).__name__}")
        vec = np.ascontiguousarray(p.as_array() if hasattr(p, "as_array") else p,
                                   dtype=np.float64)
        if vec.ndim != 1 or vec.size != len(model.param_names):
            raise ValueError(f"p must have {len(model.param_names)} parameters "
                             f"{model.param_names}")
        return model, vec
    if isinstance(p, Params):
        return ROTOR, p.as_array()
    if isinstance(p, DuffingParams):
        return DUFFING, p.as_array()
    raise _v.WrongType(f"p must be vibimpact.Params or DuffingParams, got "
                       f"{type(p).__name__}")
