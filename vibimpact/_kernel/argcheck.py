"""Checks of the arguments of every call into the compiled kernel (plain Python).

Neither the precompiled functions (:mod:`.precompiled`) nor numba's JIT-compiled ones
check indices: an array shorter than the kernel's loops assume is written past, silently.
So every way into the kernel checks its arguments here first -- dtypes, dimensions,
memory order and the sizes the loops use -- and raises ``ValueError`` naming the kernel
argument.  The public functions validate their own arguments before (with the names a
user knows); these checks are the last line, in the one place where kernel calls are
built (:mod:`.boundary`).
"""
from __future__ import annotations

import functools
import numbers
from collections.abc import Callable

import numpy as np

from . import driver as _driver
from . import registry
from .dispatch import BuiltinModel
from .integrator import N_COUNTERS, N_OPTS


def array(name, a, dtype=np.float64, ndim=1, shape=None, writeable=False):
    """Check that ``a`` is a C-contiguous ndarray of ``dtype`` and ``ndim`` dimensions,
    of ``shape`` where given (``None`` entries: any size)."""
    if not isinstance(a, np.ndarray):
        raise ValueError(f"kernel argument {name} must be a numpy array, got "
                         f"{type(a).__name__}")
    if a.dtype != dtype or a.ndim != ndim:
        raise ValueError(f"kernel argument {name} must be a {ndim}-D "
                         f"{np.dtype(dtype).name} array, got a {a.ndim}-D {a.dtype} one")
    if not a.flags.c_contiguous:
        raise ValueError(f"kernel argument {name} must be C-contiguous")
    if writeable and not a.flags.writeable:
        raise ValueError(f"kernel argument {name} must be writeable")
    if shape is not None and any(want is not None and got != want
                                 for got, want in zip(a.shape, shape)):
        want = "(" + ", ".join("*" if w is None else str(w) for w in shape) + ")"
        raise ValueError(f"kernel argument {name} must have shape {want}, got {a.shape}")
    return a


def integer(name, value, minimum=0):
    """Check that ``value`` is an integer ``>= minimum``."""
    if type(value) is int and value >= minimum:  # the common case, without the ABC check
        return value
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or \
            value < minimum:
        raise ValueError(f"kernel argument {name} must be an integer >= {minimum}, got "
                         f"{value!r}")
    return int(value)


def problem(model, terminal, p, n_mode, omega, n_state):
    """Check a problem: its terminal flags and parameter vector, and, for a built-in
    model, the sizes its functions read and write."""
    array("terminal", terminal, np.int64)
    array("p", p)
    if terminal.size == 0:
        raise ValueError("kernel argument terminal must list at least one switch")
    integer("n_mode", n_mode)
    if not isinstance(omega, float) or not np.isfinite(omega) or omega <= 0.0:
        raise ValueError(f"kernel argument omega must be a finite float > 0, got {omega!r}")
    family = _family(model)
    if family is not None:
        n, n_p, n_m, n_sw = registry.family(family).sizes
        got = (n_state, p.size, n_mode, terminal.size)
        if got != (n, n_p, n_m, n_sw):
            raise ValueError(f"kernel: a {family} problem has (state, parameters, modes, "
                             f"switches) = {(n, n_p, n_m, n_sw)}, got {got}")
    elif n_state is not None:
        integer("n_state", n_state, 1)


def _family(model):
    if isinstance(model, BuiltinModel):
        return model.family
    if isinstance(model, tuple) and len(model) in (3, 6):
        return None
    raise ValueError(f"kernel argument model must be a built-in model or a user model's "
                     f"tuple of functions, got {type(model).__name__}")


def variational(model):
    """Whether ``model`` is the variational version of a model (built-in or tuple)."""
    if isinstance(model, BuiltinModel):
        return model.variational
    return len(model) == 6


def state(name, y, n_state, var):
    """Check a state: ``n_state`` entries, or ``n_state (1 + m)``, ``m >= 1``, of a
    variational model."""
    array(name, y, writeable=True)
    if n_state is None:
        return
    if var:
        if y.size < 2 * n_state or y.size % n_state:
            raise ValueError(f"kernel argument {name} of a variational run must have "
                             f"{n_state} (1 + m) entries, m >= 1, got {y.size}")
    elif y.size != n_state:
        raise ValueError(f"kernel argument {name} must have {n_state} entries, got "
                         f"{y.size}")


@functools.lru_cache(maxsize=64)
def _layout(n, n_switch, n_mode):
    """``(dtype, shape)`` of every array of a fresh :func:`.driver.workspace`."""
    return tuple((a.dtype, a.shape) for a in _driver.workspace(n, n_switch, n_mode))


def workspace(ws, n, n_switch, n_mode):
    """Check a :func:`.driver.workspace` for a state of ``n`` entries, ``n_switch``
    switching functions and ``n_mode`` mode entries: the dtypes and shapes of a fresh
    one, C-contiguous and writeable."""
    if type(ws) is not _driver.Workspace or \
            tuple((a.dtype, a.shape) for a in ws) != _layout(n, n_switch, n_mode) or \
            not all(a.flags.c_contiguous and a.flags.writeable for a in ws):
        raise ValueError(f"kernel argument ws must be a driver.workspace({n}, {n_switch}, "
                         f"{n_mode})")


def mode_vector(name, mode, n_mode):
    """Check a mode vector of ``n_mode`` int64 entries."""
    array(name, mode, np.int64, 1, (n_mode,), writeable=True)


def clock(name, ks):
    """Check a clock ``(k, s, h[, steps[, j]])``."""
    array(name, ks, writeable=True)
    if ks.size not in (3, 4, 5):
        raise ValueError(f"kernel argument {name} must have 3, 4 or 5 entries, got "
                         f"{ks.size}")


def options(opts):
    """Check the option vector."""
    array("opts", opts, shape=(N_OPTS,))


def counters(count):
    """Check the counters."""
    array("counters", count, np.int64, 1, (N_COUNTERS,), writeable=True)


def samples(strobe, dense, n, dense_m):
    """Check the stroboscopic and dense sample arrays of a state of ``n`` entries (the
    kernel bounds their rows itself)."""
    array("strobe", strobe, ndim=2, shape=(None, n), writeable=True)
    integer("dense_m", dense_m)
    array("dense", dense, ndim=2, shape=(None, n) if dense_m else None, writeable=True)


def event_log(log, n_ev, n, n_mode, n_switch):
    """Check an event log ``(t, which, mode, state)`` and its fill ``n_ev``."""
    if not isinstance(log, tuple) or len(log) != 4:
        raise ValueError("kernel argument log must be a tuple (t, which, mode, state)")
    cap = array("log.t", log[0], writeable=True).size
    array("log.which", log[1], np.int64, 1, (cap,), writeable=True)
    array("log.mode", log[2], np.int64, 2, (cap, 2 * n_mode), writeable=True)
    array("log.state", log[3], np.float64, 2, (cap, n), writeable=True)
    if integer("n_ev", n_ev) > cap or cap < n_switch + 2:
        raise ValueError(f"kernel argument log: {cap} entries cannot take n_ev = {n_ev} "
                         f"plus a step's {n_switch + 2} events")


def renorm(value, n):
    """Check the ``renorm`` argument ``(n_state, bound, logs, states)``."""
    if not isinstance(value, tuple) or len(value) != 4:
        raise ValueError("kernel argument renorm must be (n_state, bound, logs, states)")
    n_state = integer("renorm n_state", value[0])
    logs, states = value[2], value[3]
    array("renorm logs", logs, ndim=2, writeable=True)
    if logs.shape[0] == 0:
        return
    if n_state < 1 or n % n_state or n // n_state < 2:
        raise ValueError(f"kernel argument renorm: n_state {n_state} does not divide a "
                         f"variational state of {n} entries")
    array("renorm logs", logs, ndim=2, shape=(None, n // n_state - 1), writeable=True)
    array("renorm states", states, ndim=2, shape=(logs.shape[0], n_state),
          writeable=True)


# --- the array routines (called with the kernel's own names) ----------------------------

def _vector_pair(a, b):
    array("a", a)
    array("b", b, shape=(a.size,))


def _matmul(a, b):
    array("a", a, ndim=2)
    array("b", b, ndim=2, shape=(a.shape[1], None))


def _lstsq(a, b, rcond):
    array("a", a, ndim=2)
    array("b", b, ndim=2, shape=(a.shape[0], None))
    if not isinstance(rcond, float):
        raise ValueError(f"kernel argument rcond must be a float, got {rcond!r}")


def _square(name, a):
    array(name, a, ndim=2, shape=(a.shape[0] if isinstance(a, np.ndarray) and a.ndim
                                  else None, None))
    if a.shape[0] != a.shape[1]:
        raise ValueError(f"kernel argument {name} must be square, got shape {a.shape}")


def _solve(a, b):
    _square("a", a)
    array("b", b, shape=(a.shape[0],))


def _suffix_lag_residuals(x, n_max, res, hi, lo, mag):
    array("x", x, ndim=2)
    W, d = x.shape
    n_max = integer("n_max", n_max, 1)
    array("res", res, ndim=2, shape=(W, n_max), writeable=True)
    array("hi", hi, ndim=2, shape=(W, d), writeable=True)
    array("lo", lo, ndim=2, shape=(W, d), writeable=True)
    array("mag", mag, shape=(W,), writeable=True)


def _qr_growth(jacobians, logs):
    array("jacobians", jacobians, ndim=3)
    m, d, d2 = jacobians.shape
    if d != d2:
        raise ValueError(f"kernel argument jacobians must be (m, d, d), got "
                         f"{jacobians.shape}")
    array("logs", logs, ndim=2, shape=(m, d), writeable=True)


def init_mode_check(family):
    """The argument check of the built-in family's ``init_mode`` (its sizes from
    :mod:`.registry`)."""
    n, n_p, n_m, _ = registry.family(family).sizes

    def check(s, y, p, mode):
        array("y", y)
        if y.size < n or y.size % n:
            raise ValueError(f"kernel argument y of the {family} model must have {n} "
                             f"(1 + m) entries, got {y.size}")
        array("p", p, shape=(n_p,))
        mode_vector("mode", mode, n_m)
    return check


#: the argument check of each array routine, by its exported name
ROUTINES: dict[str, Callable[..., object]] = {
    "dot": _vector_pair,
    "matmul": _matmul,
    "lstsq": _lstsq,
    "solve": _solve,
    "eigvals": lambda a: _square("a", a),
    "suffix_lag_residuals": _suffix_lag_residuals,
    "qr_growth": _qr_growth,
}

_INIT_MODE = "_init_mode"


def check_of(name):
    """The argument check of the kernel routine ``name``: an array routine's from
    :data:`ROUTINES`; ``<family>_init_mode`` of every built-in family (made from its sizes
    on first use, so that a routine unpickled in a worker process is checked as in its
    parent); None for a name without one."""
    check = ROUTINES.get(name)
    if check is None and name.endswith(_INIT_MODE):
        family = name[:-len(_INIT_MODE)]
        try:
            check = ROUTINES[name] = init_mode_check(family)
        except ValueError:  # not a built-in family: no check of that name
            return None
    return check
