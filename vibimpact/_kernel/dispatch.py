"""Calls from the generic kernel into a model's functions (resolved at compile time).

The kernel's functions take a ``model`` argument.  For a built-in model it is an integer
(:data:`ROTOR` or :data:`DUFFING`) and the calls below branch to the model's functions, which
keeps every signature free of function objects so numba can cache it on disk.  For a user
model it is a tuple ``(rhs, switches, transition)`` of numba functions, called directly
(compiled per process: numba cannot cache functions passed as arguments).

The *variational* versions of the models (state followed by tangent vectors, saltation at
every switch; :mod:`.variational`) are models too: :data:`ROTOR_VAR` and
:data:`DUFFING_VAR`, or the tuple ``(rhs, switches, transition, jac, n_state, n_switch)``
for a user model.  Their switching functions are the base model's (they read the first
``n_state`` entries only).
"""
from numba import njit, types
from numba.extending import overload

from . import duffing, rotor, variational
from .jitopts import ALLOC, LEAF

#: overloads take numba's options less ``cache`` (they are cached with their callers)
_LEAF = {k: v for k, v in LEAF.items() if k != "cache"}
_ALLOC = {k: v for k, v in ALLOC.items() if k != "cache"}

@njit(error_model="numpy", _nrt=True)
def _user_call(f, s, y, p, mode, arg):
    """Call a user model's function with the runtime on, so that it may allocate (it
    would otherwise be compiled with the calling kernel's options)."""
    f(s, y, p, mode, arg)


ROTOR = 0
DUFFING = 1
ROTOR_VAR = 2
DUFFING_VAR = 3

#: offset from a built-in model id to the id of its variational version
VAR_OFFSET = 2


def model_rhs(model, s, y, p, mode, out):
    """Write the model's right-hand side into ``out``."""


def model_switches(model, s, y, p, mode, g):
    """Write the model's switching functions into ``g``."""


def model_transition(model, s, y, p, mode, which):
    """Apply the model's mode change at an event of switch ``which``."""


def model_step_cap(model, y, p, mode, f0, at_event, rtol, atol, n_norm, g_in, g_out):
    """Largest step the model's non-smooth force allows from ``y`` (``1e300``: none);
    the rotor's Hertz contact (:func:`.rotor.step_cap`), none for other models."""


@overload(model_rhs, jit_options=_LEAF)
def _ol_rhs(model, s, y, p, mode, out):
    if isinstance(model, types.Integer):
        def impl(model, s, y, p, mode, out):
            if model == ROTOR:
                rotor.rhs(s, y, p, mode, out)
            elif model == DUFFING:
                duffing.rhs(s, y, p, mode, out)
            elif model == ROTOR_VAR:
                variational.rotor_rhs(s, y, p, mode, out)
            else:
                variational.duffing_rhs(s, y, p, mode, out)
        return impl

    if len(model.types) == 6:
        def impl_var(model, s, y, p, mode, out):
            variational.user_rhs(model[0], model[3], model[4], s, y, p, mode, out)
        return impl_var

    def impl_user(model, s, y, p, mode, out):
        _user_call(model[0], s, y, p, mode, out)
    return impl_user


@overload(model_switches, jit_options=_LEAF)
def _ol_switches(model, s, y, p, mode, g):
    if isinstance(model, types.Integer):
        def impl(model, s, y, p, mode, g):
            if model == ROTOR or model == ROTOR_VAR:
                rotor.switches(s, y, p, mode, g)
            else:
                duffing.switches(s, y, p, mode, g)
        return impl

    def impl_user(model, s, y, p, mode, g):
        _user_call(model[1], s, y, p, mode, g)
    return impl_user


@overload(model_transition, jit_options=_ALLOC)
def _ol_transition(model, s, y, p, mode, which):
    if isinstance(model, types.Integer):
        def impl(model, s, y, p, mode, which):
            if model == ROTOR:
                rotor.transition(s, y, p, mode, which)
            elif model == ROTOR_VAR:
                variational.rotor_transition(s, y, p, mode, which)
            else:
                duffing.transition(s, y, p, mode, which)
        return impl

    if len(model.types) == 6:
        def impl_var(model, s, y, p, mode, which):
            variational.user_transition(model[0], model[1], model[2], model[4], model[5], s,
                                        y, p, mode, which)
        return impl_var

    def impl_user(model, s, y, p, mode, which):
        _user_call(model[2], s, y, p, mode, which)
    return impl_user


@overload(model_step_cap, jit_options=_LEAF)
def _ol_step_cap(model, y, p, mode, f0, at_event, rtol, atol, n_norm, g_in, g_out):
    if isinstance(model, types.Integer):
        def impl(model, y, p, mode, f0, at_event, rtol, atol, n_norm, g_in, g_out):
            if model == ROTOR or model == ROTOR_VAR:
                return rotor.step_cap(y, p, mode, f0, at_event, rtol, atol, n_norm, g_in,
                                      g_out)
            return 1e300
        return impl

    def impl_user(model, y, p, mode, f0, at_event, rtol, atol, n_norm, g_in, g_out):
        return 1e300
    return impl_user
