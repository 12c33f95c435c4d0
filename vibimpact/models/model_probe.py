"""Probe calls that check a user model's declared sizes against what its functions do.

The kernel hands a user model's numba functions plain arrays of the sizes the model
declares -- the state (``state_names``), the parameter vector (``param_names``), the mode
vector (``n_mode``) and the switching functions (``terminal``) -- and compiled code does
not check indices.  A model that declares one state entry but whose right-hand side
writes ``out[1]`` would write past the kernel's arrays: memory corruption that can make
any later result wrong.

:func:`check_model` therefore calls every function once per probe state, *before* the
kernel ever runs it, on *guarded buffers*: each array is a view into a larger buffer
whose extra entries (the guard) hold a known fill.

* A **write** past an array changes its guard: the call is refused, naming the function,
  the array and the index written.
* A **read** past an array (``y[2]`` of a 2-entry state) is seen by calling again with
  another fill in that array's guard only: a function whose results change read the guard.

A read that never changes a result, or a branch the probe states never reach, cannot be
seen this way; the probe states (the rest state and three states of growing size, in the
mode the model's ``init_mode`` gives and after each terminal transition) reach the
contact branches of typical impact models.
"""
from __future__ import annotations

import re

import numpy as np
from numba.core.errors import NumbaError

#: entries of guard before and after every probed array
GUARD = 256
#: two fills of a float guard, and of an integer (mode) guard
_FILLS_F = (np.nan, 12345.678)
_FILLS_I = (-987_654_321, 123_456_789)
#: the arrays a function reads (guards with fill 0, then 1 to see reads past them); the
#: arrays it writes have guards with fill 1
_INPUTS = ("y", "p", "mode")
_ARRAYS = "y, p: float64 arrays, mode: int64 array"
#: the arguments the kernel calls each function with
_SIGNATURES = {
    "rhs": f"(s: float, {_ARRAYS}, out: float64 array)",
    "jac": f"(s: float, {_ARRAYS}, J: 2-D float64 array)",
    "switches": f"(s: float, {_ARRAYS}, g: float64 array)",
    "transition": f"(s: float, {_ARRAYS}, which: int)",
    "init_mode": f"(s: float, {_ARRAYS})",
}
#: numba colours its messages
_ANSI = re.compile(r"\x1b\[[0-9;]*m")


def _scale_states(n):
    """The probe states: rest, and three states of growing size with mixed signs."""
    base = np.array([(-1.0) ** i * (1.0 + 0.37 * i) for i in range(n)])
    return [np.zeros(n), 0.3 * base, 1.1 * base, 3.0 * base]


class _Guarded:
    """An array of ``shape`` inside a buffer with :data:`GUARD` entries either side."""

    def __init__(self, shape, dtype, content, fill):
        size = int(np.prod(shape))
        self.size, self.fill = size, fill
        self.buf = np.full(size + 2 * GUARD, fill, dtype=dtype)
        # an ndarray on the buffer, not a slice: numpy points an empty slice at the
        # buffer's start, and a write past an empty mode vector would seem to come first
        self.view = np.ndarray(shape, dtype=dtype, buffer=self.buf,
                               offset=GUARD * self.buf.itemsize)
        if content is not None:
            self.view[...] = content

    def written(self):
        """Offset (from the array's first entry) of the first guard entry changed, or
        None."""
        guard = np.concatenate([self.buf[:GUARD], self.buf[GUARD + self.size:]])
        same = (np.isnan(guard) & np.isnan(self.fill)) if self.buf.dtype.kind == "f" \
            and np.isnan(self.fill) else guard == self.fill
        if same.all():
            return None
        i = int(np.flatnonzero(~same)[0])
        return i - GUARD if i < GUARD else self.size + (i - GUARD)


def _call(fn_name, fn, args):
    """Call a user function; an exception it raises at run time is a result like any
    other, a failure to compile for the kernel's argument types a ``TypeError``."""
    try:
        fn(*args)
        return None
    except NumbaError as exc:
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
        raise TypeError(f"{fn_name} does not compile for the kernel's arguments "
                        f"{_SIGNATURES[fn_name]}: {_ANSI.sub('', first)}"[:400]) from None
    except Exception as exc:  # a user function may raise on a probe state
        return type(exc).__name__


class _Spec:
    """The declared sizes of a model and where each comes from (for the messages)."""

    def __init__(self, model):
        self.name = model.name
        self.n = len(model.state_names)
        self.n_p = len(model.param_names)
        self.n_mode = int(model.n_mode)
        self.n_switch = int(model.terminal.size)
        self.declared = {
            "y": f"{self.n} state entries (state_names={tuple(model.state_names)!r})",
            "out": f"{self.n} state entries (state_names={tuple(model.state_names)!r})",
            "J": f"a ({self.n}, {self.n}) Jacobian (state_names="
                 f"{tuple(model.state_names)!r})",
            "p": f"{self.n_p} parameters (param_names={tuple(model.param_names)!r})",
            "mode": f"{self.n_mode} mode entries (n_mode={self.n_mode})",
            "g": f"{self.n_switch} switching functions (terminal has {self.n_switch} "
                 "entries)",
        }


def _run(model, spec, p, y0, fills):
    """One pass of every function on guarded buffers.

    ``fills`` maps the input arrays ``y``, ``p``, ``mode`` to the index of their guard's
    fill (0 or 1).  Returns ``(results, writes)``: what every call produced, and the
    writes past an array as ``(function, array, offset)``.
    """
    n, writes, results = spec.n, [], []

    def guarded(role, shape, content, integer=False):
        # an output's guard holds a finite fill (a NaN written there would not show)
        fill = (_FILLS_I if integer else _FILLS_F)[fills.get(role, 0 if role in
                                                             _INPUTS else 1)]
        return _Guarded(shape, np.int64 if integer else np.float64, content, fill)

    y = guarded("y", (n,), y0)
    pv = guarded("p", (spec.n_p,), p)

    def check(fn_name, arrays):
        for role, arr in arrays.items():
            off = arr.written()
            if off is not None:
                writes.append((fn_name, role, off))

    mode = guarded("mode", (spec.n_mode,), 0, integer=True)
    results.append(("init_mode", _call("init_mode", model.init_mode,
                                       (0.0, y.view, pv.view, mode.view)),
                    mode.view.copy()))
    check("init_mode", {"mode": mode, "y": y, "p": pv})
    modes = [mode]
    for which in np.flatnonzero(model.terminal == 1):
        m2 = guarded("mode", (spec.n_mode,), mode.view, integer=True)
        err = _call("transition", model.transition, (0.0, y.view, pv.view, m2.view, int(which)))
        results.append(("transition", err, m2.view.copy()))
        check("transition", {"mode": m2, "y": y, "p": pv})
        modes.append(m2)
    for m in modes:
        out = guarded("out", (n,), 0.0)
        results.append(("rhs", _call("rhs", model.rhs, (0.25, y.view, pv.view, m.view, out.view)),
                        out.view.copy()))
        check("rhs", {"out": out, "y": y, "p": pv, "mode": m})
        J = guarded("J", (n, n), 0.0)
        results.append(("jac", _call("jac", model.jac, (0.25, y.view, pv.view, m.view, J.view)),
                        J.view.copy()))
        check("jac", {"J": J, "y": y, "p": pv, "mode": m})
        g = guarded("g", (spec.n_switch,), np.nan)  # NaN: an entry never set shows
        results.append(("switches", _call("switches", model.switches,
                                          (0.25, y.view, pv.view, m.view, g.view)),
                        g.view.copy()))
        check("switches", {"g": g, "y": y, "p": pv, "mode": m})
    return results, writes


def _same(a, b):
    return a[1] == b[1] and np.array_equal(a[2], b[2], equal_nan=a[2].dtype.kind == "f")


def _index_text(role, off, spec):
    if role == "J":
        return f"J[{off // spec.n}, {off % spec.n}]" if off >= 0 else f"J (offset {off})"
    return f"{role}[{off}]"


def check_model(model, p):
    """Check a user model's declared sizes against what its functions read and write.

    Parameters
    ----------
    model : vibimpact.models.Model
        A model built by :meth:`~vibimpact.models.Model.from_functions`.
    p : ndarray of float64, shape (len(model.param_names),)
        The parameter vector the kernel is about to run with.

    Raises
    ------
    ValueError
        Naming the model, the function and the array, when a function writes past an
        array of the declared size or reads past one (its results depend on what lies
        beyond it).
    """
    spec = _Spec(model)
    p = np.asarray(p, dtype=np.float64)
    unset = np.ones(spec.n_switch, dtype=bool)
    for y0 in _scale_states(spec.n):
        base, writes = _run(model, spec, p, y0, {})
        for fn, _, values in base:
            if fn == "switches":
                unset &= np.isnan(values)
        if writes:
            fn, role, off = writes[0]
            raise ValueError(
                f"model {spec.name!r}: {fn} writes {_index_text(role, off, spec)}, past "
                f"the {spec.declared[role]} it declares; declare the sizes the functions "
                "use")
        for role in _INPUTS:
            other, _ = _run(model, spec, p, y0, {role: 1})
            for a, b in zip(base, other):
                if not _same(a, b):
                    raise ValueError(
                        f"model {spec.name!r}: {a[0]} reads past {role}, beyond the "
                        f"{spec.declared[role]} it declares (its results depend on what "
                        "lies after the array); declare the sizes the functions use")
    if unset.any():
        set_ = np.flatnonzero(~unset)
        raise ValueError(
            f"model {spec.name!r}: terminal has {spec.n_switch} entries, but switches "
            f"never sets g[{int(np.flatnonzero(unset)[0])}] (it sets "
            f"{', '.join(f'g[{i}]' for i in set_) or 'no entry'}); terminal must have one "
            "entry per switching function")
