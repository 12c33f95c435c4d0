"""Calls from the generic kernel into a model's functions (resolved at compile time).

The kernel's functions take a ``model`` argument.  For a built-in model it is a
:class:`BuiltinModel` (:func:`builtin` of :data:`ROTOR`, :data:`DUFFING`, ...), which numba
types by its *family*: the rotor and its variational equations are one type, the Duffing
oscillator and its variational equations another.  The calls below branch at compile time
on the family (a rotor run compiles no Duffing code) and at run time on the model id
within it (a classify run integrates the rotor and its variational equations with one
compiled loop).  The signatures hold no function objects, so numba caches them on disk.  For a
user model ``model`` is a tuple ``(rhs, switches, transition)`` of numba functions, called
directly (compiled per process: numba cannot cache functions passed as arguments).

The *variational* versions of the models (state followed by tangent vectors, saltation at
every switch; :mod:`.variational`) are models too: :data:`ROTOR_VAR` and
:data:`DUFFING_VAR`, or the tuple ``(rhs, switches, transition, jac, n_state, n_switch)``
for a user model.  Their switching functions are the base model's (they read the first
``n_state`` entries only).
"""
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import (NativeValue, intrinsic, models, overload, register_model,
                             typeof_impl, unbox)

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

#: the family of each built-in model id
FAMILY = {ROTOR: "rotor", ROTOR_VAR: "rotor", DUFFING: "duffing", DUFFING_VAR: "duffing"}


class BuiltinModel:
    """A built-in model as the kernel receives it: its id and its family (see the
    module's docstring).  Use :func:`builtin`."""

    __slots__ = ("id", "family")

    def __init__(self, model_id, family):
        self.id = int(model_id)
        self.family = family

    def __reduce__(self):
        return builtin, (self.id,)

    def __repr__(self):
        return f"BuiltinModel({self.id}, {self.family!r})"


_BUILTIN = {i: BuiltinModel(i, f) for i, f in FAMILY.items()}


def builtin(model_id):
    """The :class:`BuiltinModel` of a built-in model id."""
    return _BUILTIN[int(model_id)]


def kernel_model(model):
    """What the kernel receives for ``model``: the :class:`BuiltinModel` of a built-in
    model id, a user model's tuple unchanged."""
    if isinstance(model, (int, BuiltinModel)):
        return builtin(model.id if isinstance(model, BuiltinModel) else model)
    return model


class ModelFamily(types.Type):
    """numba's type of a :class:`BuiltinModel`: one per family; the value is the id."""

    def __init__(self, family):
        self.family = family
        super().__init__(name=f"vibimpact.ModelFamily({family})")


@typeof_impl.register(BuiltinModel)
def _typeof_builtin(val, c):
    return ModelFamily(val.family)


@register_model(ModelFamily)
class _ModelFamilyModel(models.PrimitiveModel):
    def __init__(self, dmm, fe_type):
        super().__init__(dmm, fe_type, ir.IntType(64))


@unbox(ModelFamily)
def _unbox_builtin(typ, obj, c):
    idobj = c.pyapi.object_getattr_string(obj, "id")
    val = c.pyapi.long_as_longlong(idobj)
    c.pyapi.decref(idobj)
    return NativeValue(val, is_error=cgutils.is_not_null(c.builder, c.pyapi.err_occurred()))


@intrinsic
def model_id(typingctx, model):
    """The id of a :class:`BuiltinModel` inside jitted code."""
    def codegen(context, builder, signature, args):
        return args[0]
    return types.int64(model), codegen


def _family(model):
    """A built-in model's family at compile time (None: a user model)."""
    return model.family if isinstance(model, ModelFamily) else None


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
    if _family(model) == "rotor":
        def impl_rotor(model, s, y, p, mode, out):
            if model_id(model) == ROTOR:
                rotor.rhs(s, y, p, mode, out)
            else:
                variational.rotor_rhs(s, y, p, mode, out)
        return impl_rotor
    if _family(model) == "duffing":
        def impl_duffing(model, s, y, p, mode, out):
            if model_id(model) == DUFFING:
                duffing.rhs(s, y, p, mode, out)
            else:
                variational.duffing_rhs(s, y, p, mode, out)
        return impl_duffing
    if len(model.types) == 6:
        def impl_var(model, s, y, p, mode, out):
            variational.user_rhs(model[0], model[3], model[4], s, y, p, mode, out)
        return impl_var

    def impl_user(model, s, y, p, mode, out):
        _user_call(model[0], s, y, p, mode, out)
    return impl_user


@overload(model_switches, jit_options=_LEAF)
def _ol_switches(model, s, y, p, mode, g):
    if _family(model) == "rotor":
        def impl_rotor(model, s, y, p, mode, g):
            rotor.switches(s, y, p, mode, g)
        return impl_rotor
    if _family(model) == "duffing":
        def impl_duffing(model, s, y, p, mode, g):
            duffing.switches(s, y, p, mode, g)
        return impl_duffing
    def impl_user(model, s, y, p, mode, g):
        _user_call(model[1], s, y, p, mode, g)
    return impl_user


@overload(model_transition, jit_options=_ALLOC)
def _ol_transition(model, s, y, p, mode, which):
    if _family(model) == "rotor":
        def impl_rotor(model, s, y, p, mode, which):
            if model_id(model) == ROTOR:
                rotor.transition(s, y, p, mode, which)
            else:
                variational.rotor_transition(s, y, p, mode, which)
        return impl_rotor
    if _family(model) == "duffing":
        def impl_duffing(model, s, y, p, mode, which):
            duffing.transition(s, y, p, mode, which)
        return impl_duffing
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
    if _family(model) == "rotor":
        def impl_rotor(model, y, p, mode, f0, at_event, rtol, atol, n_norm, g_in, g_out):
            return rotor.step_cap(y, p, mode, f0, at_event, rtol, atol, n_norm, g_in,
                                  g_out)
        return impl_rotor
    def impl_user(model, y, p, mode, f0, at_event, rtol, atol, n_norm, g_in, g_out):
        return 1e300
    return impl_user
