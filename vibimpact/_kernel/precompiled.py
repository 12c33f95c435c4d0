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

import importlib
import sys

from .argcheck import check_of


class Routine:
    """A kernel function called from Python: its argument check (:mod:`.argcheck`),
    then numba's dispatcher ``jit``; or, with a key, the compiled code directly.

    numba's dispatcher types every argument of every call before it finds the compiled
    overload: fast for a few arrays, slow for the integration loop's twenty arguments
    with their tuples and the model (the most of a short call; ``reports/performance.md``,
    section call_overhead, measures both).  :meth:`call_keyed` asks the dispatcher once
    per key the caller gives (what the arguments' types depend on once the caller has
    checked them) and then
    calls that overload's entry point, which is what the dispatcher calls after typing.

    Attribute access falls through to the dispatcher (``.py_func``, ``.signatures``).
    """

    __slots__ = ("name", "jit", "check", "entries")

    def __init__(self, name, jit):
        self.name = name
        self.jit = jit
        # the shapes and sizes its loops use (the compiled code checks no index)
        self.check = check_of(name)
        # key -> entry point (a key holds a user model's functions themselves, never
        # their ids: a function that goes away cannot lend its id to another)
        self.entries = {}

    def __call__(self, *args):
        if self.check is not None:
            self.check(*args)
        return self.jit(*args)

    def call_keyed(self, key, *args):
        """Call with arguments the caller has checked, whose numba types ``key``
        determines (:mod:`.boundary`'s integration loop: the model's family, as its checks
        pin every array's dtype, dimensions and memory order)."""
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
        # the kernel's own dispatcher by name: numba pickles a dispatcher as its Python
        # function and options, and a process that unpickles it (a worker) rebuilds one
        # without the on-disk cache -- compiling it again in every process -- unless it
        # already holds one of the same uuid
        if own_dispatcher(self.name, self.jit):
            return _named, (self.name, reference(self.jit))
        return routine, (self.name, self.jit)

    def __repr__(self):
        return f"Routine({self.name!r})"


def reference(jit):
    """``(module, name)`` of the module attribute that is the dispatcher ``jit``, or None
    (a function made inside another, a user model's function kept by no module)."""
    func = getattr(jit, "py_func", None)
    module, name = getattr(func, "__module__", None), getattr(func, "__qualname__", "")
    mod = sys.modules.get(module) if module else None
    if mod is None or "." in name or getattr(mod, name, None) is not jit:
        return None
    return module, name


def _family_init_mode(name):
    """The ``init_mode`` dispatcher of the built-in family of routine ``name``
    (``<family>_init_mode``), or None."""
    from . import registry

    if not name.endswith("_init_mode"):
        return None
    try:  # the family's own module, imported once (no scan of the package)
        return registry.family(name[:-len("_init_mode")]).init_mode
    except ValueError:  # no built-in family of that name
        return None


def own_dispatcher(name, jit):
    """Whether ``jit`` is the kernel's own dispatcher of routine ``name``: a kernel
    module's attribute, or a built-in family's ``init_mode`` (made by a factory)."""
    ref = reference(jit)
    if ref is not None:
        return ref[0].startswith(__package__ + ".")
    return _family_init_mode(name) is jit


def _named(name, ref):
    """The :class:`Routine` ``name`` of the kernel's own dispatcher: the module attribute
    ``ref`` (``(module, name)``), or with ``ref`` None the family's ``init_mode``
    (unpickling)."""
    jit = (getattr(importlib.import_module(ref[0]), ref[1]) if ref is not None
           else _family_init_mode(name))
    return routine(name, jit)


def routine(name, jit):
    """The :class:`Routine` of the kernel function ``jit``, named ``name`` (the name its
    argument check has in :data:`.argcheck.ROUTINES`)."""
    return Routine(name, jit)
