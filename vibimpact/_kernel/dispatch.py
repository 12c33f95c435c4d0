"""Calls from the generic kernel into a model's functions (resolved at compile time).

The kernel's functions take a ``model`` argument.  For a built-in model it is a
:class:`BuiltinModel` (:func:`builtin` of a family name), which numba types by its
*family*: a model and its variational equations are one type (e.g. the built-in rotor
and its variational equations), each family another.  A family is a module of this
package with a ``KERNEL_MODEL`` (:mod:`.registry`): the calls below read its entry at
compile time (a run of one family compiles no other family's code) and branch at run time
on the model's id within the family, 0 for the model and 1 for its variational equations
(a classify run integrates a model and its variational equations with one compiled
loop).  The signatures hold no function objects, so numba caches them on disk.  For a
user model ``model`` is a tuple ``(USER_TAG, rhs, switches, transition)`` of numba
functions behind a number (:func:`kernel_model`), called directly (compiled per process:
numba cannot cache functions passed as arguments).

The *variational* versions of the models (state followed by tangent vectors, saltation at
every switch; :mod:`.variational`) are models too: ``builtin(family, variational=True)``,
or the tuple
``(USER_TAG, rhs, switches, transition, jac, n_state, n_switch)`` for a user model.  Their
switching functions are the base model's (they read the first ``n_state`` entries only).
"""
from typing import Any

from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import (NativeValue, intrinsic, models, overload, register_model,
                             typeof_impl, unbox)

from . import registry, variational
from .jitopts import ALLOC, LEAF, USER_ALLOC

#: overloads take numba's options less ``cache`` (they are cached with their callers)
#: (Any: numba's stubs type jit_options as a TypedDict of the public options, without _nrt)
_LEAF: Any = {k: v for k, v in LEAF.items() if k != "cache"}
_ALLOC: Any = {k: v for k, v in ALLOC.items() if k != "cache"}

@njit(**USER_ALLOC)
def _user_call(f, s, y, p, mode, arg):
    """Call a user model's function with the runtime on, so that it may allocate (it
    would otherwise be compiled with the calling kernel's options)."""
    f(s, y, p, mode, arg)


class BuiltinModel:
    """A built-in model as the kernel receives it: its family and its id within the
    family, 0 (the model) or 1 (its variational equations).  Use :func:`builtin`."""

    __slots__ = ("id", "family")

    def __init__(self, model_id, family):
        self.id = int(model_id)
        self.family = family

    @property
    def variational(self):
        """Whether this is the variational version of the model."""
        return self.id == 1

    def __reduce__(self):
        return builtin, (self.family, self.variational)

    def __repr__(self):
        return f"BuiltinModel({self.id}, {self.family!r})"

    def __eq__(self, other):
        return (type(other) is BuiltinModel and other.id == self.id
                and other.family == self.family)

    def __hash__(self):
        return hash((self.id, self.family))


_BUILTIN: dict[tuple[str, bool], BuiltinModel] = {}


def builtin(family, variational=False):
    """The :class:`BuiltinModel` of the built-in family ``family`` (a module of this
    package with a ``KERNEL_MODEL``), or of its variational equations.

    Raises
    ------
    ValueError
        For an unknown family.
    """
    key = (family, bool(variational))
    model = _BUILTIN.get(key)
    if model is None:
        registry.family(family)
        model = _BUILTIN[key] = BuiltinModel(int(bool(variational)), family)
    return model



#: the first entry of a user model's tuple as the kernel receives it.  numba tries to
#: unify a tuple whose first entry is a function into one first-class function type, and
#: warns (NumbaExperimentalFeatureWarning, "First-class function type feature is
#: experimental") every time it types such a tuple, even where it does not unify it; a
#: tuple that starts with a number is an ordinary heterogeneous tuple, whose functions
#: numba calls as the dispatchers they are
USER_TAG = 0


def kernel_model(model):
    """What the kernel receives for ``model``: a :class:`BuiltinModel` unchanged, a user
    model's tuple of functions behind :data:`USER_TAG` (``(0, rhs, switches, transition)``
    and ``(0, rhs, switches, transition, jac, n_state, n_switch)``)."""
    if isinstance(model, BuiltinModel):
        return model
    return (USER_TAG,) + tuple(model)


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
    """Largest step the model's non-smooth force allows from ``y`` (``1e300``: none):
    its family's ``step_cap`` (:class:`.registry.KernelModel`; e.g. the built-in rotor's
    Hertz contact, :func:`.rotor.step_cap`), none for a family without one or a user
    model."""


def _entry(model):
    """The :class:`.registry.KernelModel` of a built-in family type (None: a user model)."""
    fam = _family(model)
    return None if fam is None else registry.family(fam)


@overload(model_rhs, jit_options=_LEAF)
def _ol_rhs(model, s, y, p, mode, out):
    entry = _entry(model)
    if entry is not None:
        base, var = entry.rhs, entry.var_rhs

        def impl_builtin(model, s, y, p, mode, out):
            if model_id(model) == 0:  # type: ignore[call-arg]  # numba: no typingctx here
                base(s, y, p, mode, out)
            else:
                var(s, y, p, mode, out)
        return impl_builtin
    if len(model.types) == 7:
        def impl_var(model, s, y, p, mode, out):
            variational.user_rhs(model[1], model[4], model[5], s, y, p, mode, out)
        return impl_var

    def impl_user(model, s, y, p, mode, out):
        _user_call(model[1], s, y, p, mode, out)
    return impl_user


@overload(model_switches, jit_options=_LEAF)
def _ol_switches(model, s, y, p, mode, g):
    entry = _entry(model)
    if entry is not None:
        switches = entry.switches

        def impl_builtin(model, s, y, p, mode, g):
            switches(s, y, p, mode, g)
        return impl_builtin

    def impl_user(model, s, y, p, mode, g):
        _user_call(model[2], s, y, p, mode, g)
    return impl_user


@overload(model_transition, jit_options=_ALLOC)
def _ol_transition(model, s, y, p, mode, which):
    entry = _entry(model)
    if entry is not None:
        base, var = entry.transition, entry.var_transition

        def impl_builtin(model, s, y, p, mode, which):
            if model_id(model) == 0:  # type: ignore[call-arg]  # numba: no typingctx here
                base(s, y, p, mode, which)
            else:
                var(s, y, p, mode, which)
        return impl_builtin
    if len(model.types) == 7:
        body = variational.user_transition(model.types[1].dispatcher,
                                           model.types[2].dispatcher,
                                           model.types[3].dispatcher)

        def impl_var(model, s, y, p, mode, which):
            body(model[5], model[6], s, y, p, mode, which)
        return impl_var

    def impl_user(model, s, y, p, mode, which):
        _user_call(model[3], s, y, p, mode, which)
    return impl_user


@overload(model_step_cap, jit_options=_LEAF)
def _ol_step_cap(model, y, p, mode, f0, at_event, rtol, atol, n_norm, g_in, g_out):
    entry = _entry(model)
    if entry is not None and entry.step_cap is not None:
        cap = entry.step_cap

        def impl_capped(model, y, p, mode, f0, at_event, rtol, atol, n_norm, g_in, g_out):
            return cap(y, p, mode, f0, at_event, rtol, atol, n_norm, g_in, g_out)
        return impl_capped

    def impl_none(model, y, p, mode, f0, at_event, rtol, atol, n_norm, g_in, g_out):
        return 1e300
    return impl_none
