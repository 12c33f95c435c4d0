"""The kernel compiled ahead of the first run, and what a run is told about it.

Compiling the integration loop with numba takes most of a first run (timed in
``reports/performance.md``, section first_run).  Every kernel function is cached by numba on disk
(``cache=True``,
:mod:`.jitopts`), so the install fills that cache (:mod:`.aot_build`, run by ``setup.py``
for an editable install, or by hand: ``python -m vibimpact._kernel.aot_build``), and the
first run loads the machine code instead of compiling it.  This is numba's own cache and
JIT: the same code, the same bits, and no C compiler.  When the cache does not fit
(other kernel sources, numba, llvmlite, NumPy or Python versions, another processor),
numba compiles on first use and caches the result, as it would without the fill; it
never runs code compiled for anything else (numba keys its cache on the function's
bytecode, its own version and the processor).

Whether the filled cache is in use is :mod:`.cache_stamp`'s to say.  :func:`routine` wraps a kernel
function called from
Python with its argument check: numba's compiled code checks no array sizes or indices,
so every call is checked first by :mod:`.argcheck` (the array routines by the
:class:`Routine` itself, the integration loop where :mod:`.boundary` builds its
arguments), and a wrong shape, dtype or memory order is a ``ValueError``.
"""
from __future__ import annotations

import numpy as np

from .argcheck import check_of
from .dispatch import BuiltinModel


class Routine:
    """A kernel function called from Python: its argument check (:mod:`.argcheck`),
    then the compiled code.

    numba's dispatcher types every argument of every call (some 60 µs for the
    integration loop's twenty arguments) before it finds the compiled overload.  A
    Routine asks the dispatcher once per *kind* of arguments (:func:`type_key`: dtypes,
    dimensions, memory order and flags of the arrays, the Python types of the scalars, the
    family of a built-in model, the identity of a user model's functions) and then calls
    that overload's entry point directly, which is what the dispatcher calls after
    typing.  The arguments are checked as before: the check comes first, and an array
    of another kind is another key, so it goes through the dispatcher.

    Attribute access falls through to the dispatcher (``.py_func``, ``.signatures``).
    """

    __slots__ = ("name", "jit", "check", "entries")

    def __init__(self, name, jit):
        self.name = name
        self.jit = jit
        # the shapes and sizes its loops use (the compiled code checks no index)
        self.check = check_of(name)
        # type_key(args) -> entry point (a key holds a user model's functions themselves,
        # never their ids: a function that goes away cannot lend its id to another)
        self.entries = {}

    def __call__(self, *args):
        if self.check is not None:
            self.check(*args)
        return self.call_keyed(type_key(args), *args)

    def call_keyed(self, key, *args):
        """Call with arguments already checked whose numba types ``key`` determines
        (:meth:`__call__`: :func:`type_key`; :mod:`.boundary`'s integration loop: the
        model's family, as its checks pin every array's dtype, dimensions and order)."""
        entry = self.entries.get(key)
        if entry is not None:
            return entry(*args)
        out = self.jit(*args)  # compiles or loads the overload for these types
        found = self.jit.overloads.get(tuple(self.jit.typeof_pyval(a) for a in args))
        if found is not None:  # None: the dispatcher converted an argument; ask it again
            self.entries[key] = found.entry_point
        return out

    def __getattr__(self, attr):
        if attr in Routine.__slots__:  # not set yet (unpickling)
            raise AttributeError(attr)
        return getattr(self.jit, attr)

    def __reduce__(self):
        return routine, (self.name, self.jit)

    def __repr__(self):
        return f"Routine({self.name!r})"


_SCALARS = (bool, int, float, complex)


def type_key(value):
    """What numba's type of ``value`` depends on, as plain Python values: for an array
    its dtype, dimensions, memory order, and writeable and aligned flags; for a tuple its
    items' keys; for a built-in model its family (:class:`.dispatch.BuiltinModel`: a
    model and its variational equations are one type); for a Python or NumPy scalar its
    type (an integer also whether it fits int64); for anything else (a user model's
    numba functions) the object itself, compared by identity where it has no equality
    of its own (an unhashable one: its id)."""
    if isinstance(value, tuple):
        return tuple([type_key(v) for v in value])
    if isinstance(value, np.ndarray):
        f = value.flags
        return (value.dtype.str, value.ndim, f.c_contiguous, f.f_contiguous, f.writeable,
                f.aligned)
    kind = type(value)
    if kind is int:
        return int, -(2**63) <= value < 2**63
    if kind in _SCALARS or isinstance(value, np.generic):
        return kind
    if kind is BuiltinModel:
        return BuiltinModel, value.family
    try:
        hash(value)
    except TypeError:
        return kind, id(value)
    return kind, value


def routine(name, jit):
    """The :class:`Routine` of the kernel function ``jit``, named ``name`` (the name its
    argument check has in :data:`.argcheck.ROUTINES`)."""
    return Routine(name, jit)
