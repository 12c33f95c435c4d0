"""Compilation options of the kernel's ``@njit`` functions.

numba counts references to every array a function holds.  Around a call it cannot inline
(a model's right-hand side inside a Runge--Kutta stage, a step inside the driver loop) a
function compiled with the runtime (NRT) increments and decrements the count of each
array argument: atomic operations that cost more than a 4-state right-hand side itself.
Functions that allocate nothing are therefore compiled without the runtime
(:data:`LEAF`); numba compiles a callee that sets no such option with its caller's, so
the few functions below them that allocate (a saltation map, a user model's Jacobian)
ask for the runtime explicitly (:data:`ALLOC`).  A :data:`LEAF` function can call an
:data:`ALLOC` one; it cannot allocate itself.

Functions called only from other kernel functions (:data:`INNER`, :data:`INNER_ALLOC`)
get no CPython or C wrapper: numba would otherwise generate, optimise and cache an
argument-unboxing wrapper for each of them that nothing calls (a share of a cold
``classify``'s compilation).  They cannot be called from Python.

The options are typed ``dict[str, Any]``: numba's stubs list the public options of
``njit`` only, not ``_nrt``, ``no_cpython_wrapper`` or ``no_cfunc_wrapper``.
"""

from typing import Any

#: functions that allocate nothing (models, Runge--Kutta steps, event location)
LEAF: dict[str, Any] = dict(cache=True, error_model="numpy", _nrt=False)
#: pieces of a LEAF function, inlined into it by numba before typing (numba compiles a
#: function called from another as a library of its own, then links and optimises every
#: callee again inside each caller: one more level of calls costs a compilation of
#: everything below it)
PIECE: dict[str, Any] = dict(LEAF, inline="always")
#: functions that allocate, called from LEAF functions
ALLOC: dict[str, Any] = dict(cache=True, error_model="numpy", _nrt=True)
#: :data:`LEAF` functions called only from kernel functions (no wrapper for Python)
INNER: dict[str, Any] = dict(LEAF, no_cpython_wrapper=True, no_cfunc_wrapper=True)
#: :data:`ALLOC` functions called only from kernel functions
INNER_ALLOC: dict[str, Any] = dict(ALLOC, no_cpython_wrapper=True, no_cfunc_wrapper=True)
#: functions that take a user model's functions as arguments, with the runtime: not
#: cached (numba compiles them per process for the functions they are given)
USER_ALLOC: dict[str, Any] = dict(error_model="numpy", _nrt=True)
