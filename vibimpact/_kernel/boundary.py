"""The one door into the numba kernel (plain Python, no ``@njit``).

Everything above :mod:`vibimpact._kernel` calls the kernel through this module: it holds
the kernel's inputs as frozen values and builds the jitted functions' argument lists in one
place (:func:`_leading`), in the spirit of SciPy's ``OdeSolver`` and ross's state
dataclasses.

* :class:`Method` -- a Runge--Kutta scheme as data (its tableau, order and dense-output
  coefficients, :mod:`.tableaux`);
* :class:`Options` -- the solver settings (tolerances, step limits, divergence bound, the
  error test of tangent entries);
* :class:`Problem` -- a model (built-in id or tuple of numba functions), its switching
  surfaces, its parameter vector and forcing frequency;
* :class:`EventLog` -- the preallocated event log, emptied into chunks when it fills;
* :func:`integrate` -- the integration call and its LOG_FULL restart loop;
  :func:`benettin` and :func:`two_trajectory` -- the Lyapunov loops;
  :func:`qr_growth` (QR growth factors of a product of Jacobians) and
  :func:`suffix_lag_residuals` (recurrence residuals of stroboscopic points) are the
  kernel's array routines, re-exported;
* :mod:`.linalg` -- small dense linear algebra with the same bits on every processor
  (``dot``, ``matmul``, ``lstsq``, ``solve``, ``eigvals``), re-exported.
"""
from __future__ import annotations

import math
import threading
from dataclasses import dataclass, field, replace
from collections.abc import Callable

import numpy as np

from . import argcheck as _check
from . import dispatch as _dispatch
from . import driver as _driver
from . import integrator as _integrator
from . import linalg as _linalg
from . import noevents as _noevents
from . import recurrence as _recurrence
from . import tableaux as _tab
from .driver import workspace as _workspace
from .lyapunov import qr_growth as _qr_growth
from .lyapunov import two_trajectory as _two_trajectory
from . import cache_stamp as _cache_stamp
from .precompiled import routine as _routine

#: the kernel functions called from Python: precompiled at install time where possible,
#: numba's JIT-compiled functions otherwise (:mod:`.precompiled`)
_integrate = _routine("integrate", _driver.integrate)
#: the era's integrator (method ``rk4-fixed-noevents``): a loop of its own
_integrate_noevents = _routine("integrate_noevents", _noevents.integrate_noevents)
dot = _routine("dot", _linalg.dot)
matmul = _routine("matmul", _linalg.matmul)
lstsq = _routine("lstsq", _linalg.lstsq)
solve = _routine("solve", _linalg.solve)
eigvals = _routine("eigvals", _linalg.eigvals)
suffix_lag_residuals = _routine("suffix_lag_residuals", _recurrence.suffix_lag_residuals)
#: whether the kernel compiled ahead of the first run (numba's cache, filled at install) is
#: in use, and why not: one line (``vibimpact --version``)
precompiled_status = _cache_stamp.status

#: method names, in the order the kernel numbers them
METHODS = tuple(_tab.METHOD_IDS)
#: status codes of the kernel (see :mod:`.integrator`)
OK = _integrator.OK
LOG_FULL = _integrator.LOG_FULL
N_COUNTERS = _integrator.N_COUNTERS

#: the ``renorm`` argument of a plain (not Benettin) run of :func:`.driver.integrate`
_PLAIN = (0, 0.0, np.empty((0, 0)), np.empty((0, 0)))

_EMPTY1 = np.zeros(1)
_EMPTY2 = np.zeros((1, 1))


@dataclass(frozen=True, eq=False)
class Method:
    """An explicit Runge--Kutta method as data.

    Attributes
    ----------
    name : {"rk4", "dp5", "dop853", "rk4-fixed-noevents"}
    id : int
        The kernel's number of the method (:mod:`.tableaux`).
    A, B, C, E, E3, D, P : ndarray
        Tableau, error weights (``E3``: DOP853's third-order estimate), dense-output
        coefficients (``D``: DOP853, ``P``: DP5); one-element placeholders where unused.
    order : int
    n_stages : int
    hertz : tuple of float
        Local error constants of steps at a Hertz contact's entry and exit
        (:func:`.tableaux.hertz_error_constants`; zeros for RK4).
    """

    name: str
    id: int
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    E: np.ndarray
    E3: np.ndarray
    D: np.ndarray
    P: np.ndarray
    order: int
    n_stages: int
    hertz: tuple = (0.0, 0.0)

    @classmethod
    def named(cls, name):
        """The method called ``name``; ``ValueError`` naming ``method`` otherwise."""
        try:
            return _BY_NAME[name]
        except (KeyError, TypeError):
            raise ValueError(f"method must be one of {', '.join(METHODS)}, "
                             f"got {name!r}") from None

    @property
    def adaptive(self):
        """Whether the method has an error estimate (DP5, DOP853)."""
        return self.id not in _tab.FIXED

    def kernel_args(self):
        """The tableau as the kernel's argument tuple."""
        return (self.id, self.A, self.B, self.C, self.E, self.E3, self.D, self.P,
                self.order, self.n_stages)


def _methods():
    out = {}
    for name, mid in _tab.METHOD_IDS.items():
        hertz = tuple(float(g) for g in _tab.HERTZ_ERROR.get(mid, (0.0, 0.0)))
        if mid in _tab.FIXED:
            out[name] = Method(name, mid, _tab.RK4_A, _tab.RK4_B, _tab.RK4_C, _EMPTY1,
                               _EMPTY1, _EMPTY2, _EMPTY2, 4, 4, hertz)
        elif mid == _tab.DP5:
            out[name] = Method(name, mid, _tab.DP5_A, _tab.DP5_B, _tab.DP5_C, _tab.DP5_E,
                               _EMPTY1, _EMPTY2, _tab.DP5_P, 5, 6, hertz)
        else:
            out[name] = Method(name, mid, _tab.DOP853_A, _tab.DOP853_B, _tab.DOP853_C,
                               _tab.DOP853_E5, _tab.DOP853_E3, _tab.DOP853_D, _EMPTY2, 8,
                               _tab.DOP853_NSTAGES, hertz)
    return out


_BY_NAME = _methods()


@dataclass(frozen=True)
class Options:
    """Solver settings of one kernel call.

    Attributes
    ----------
    rtol, atol : float
        Tolerances of the adaptive methods.
    h_fixed : float
        Step of fixed-step runs.
    max_step : float
    bound : float
        A state component beyond this ends the run as diverged.
    event_tol : float
        Switching functions are zero to this at a located event.
    max_steps_per_period : int
    adaptive : bool
        False runs an embedded method with fixed steps.
    n_bound : int
        Leading state entries the bound applies to (0: all).
    n_err : int
        Leading entries the local error test measures at the tolerances (0: all); the
        others (tangent vectors) at ``tangent_factor`` times them.
    tangent_factor : float
        0: the entries beyond ``n_err`` are not tested.
    """

    rtol: float
    atol: float
    h_fixed: float
    max_step: float
    bound: float
    event_tol: float
    max_steps_per_period: int
    adaptive: bool = True
    n_bound: int = 0
    n_err: int = 0
    tangent_factor: float = 1.0

    def with_(self, **changes):
        """A copy with some settings changed."""
        return replace(self, **changes)

    def vector(self, method):
        """The kernel's option vector (layout in :mod:`.integrator`)."""
        g_in, g_out = method.hertz if method.id not in _tab.FIXED else (0.0, 0.0)
        return np.array([self.rtol, self.atol, self.h_fixed, self.max_step, self.bound,
                         self.event_tol, float(self.max_steps_per_period),
                         0.0 if self.adaptive else 1.0, float(self.n_bound),
                         float(self.n_err), float(self.tangent_factor), g_in, g_out])


@dataclass(frozen=True, eq=False)
class Problem:
    """What the kernel integrates: a model, its parameters and its forcing.

    Attributes
    ----------
    model : int or tuple
        A built-in model id or a tuple of numba functions (:mod:`.dispatch`).
    terminal : ndarray of int64, shape (n_switch,)
        1 for a mode-changing switching function, 0 for an observer.
    n_mode : int
    p : ndarray of float64
        Parameter vector.
    omega : float
        Forcing frequency; the period is ``T = 2 pi / omega``.
    init_mode : callable
        ``init_mode(s, y, p, mode)``: the mode consistent with a state.
    n_state : int, optional
        Entries of the model's state (without tangent vectors); the states of every
        kernel call are checked against it.  Required by a built-in model's sizes, given
        by a user model's declaration (:class:`vibimpact.models.Model`).

    Raises
    ------
    ValueError
        For arrays of the wrong dtype, order or size (:mod:`.argcheck`).
    """

    model: object
    terminal: np.ndarray
    n_mode: int
    p: np.ndarray
    omega: float
    init_mode: Callable | None = field(repr=False, default=None)
    n_state: int | None = None

    def __post_init__(self):
        _check.problem(self.model, self.terminal, self.p, self.n_mode, self.omega,
                       self.n_state)

    @property
    def period(self):
        """The forcing period ``2 pi / omega``."""
        return 2.0 * math.pi / self.omega

    def initial_mode(self, y):
        """The mode consistent with state ``y`` (of the model; of a variational model
        also with its tangent vectors) at ``tau = 0``."""
        _check.state("y", y, self.n_state, self.variational and y.size != self.n_state)
        mode = np.zeros(self.n_mode, dtype=np.int64)
        assert self.init_mode is not None  # a problem built without one has no mode to ask
        self.init_mode(0.0, y, self.p, mode)
        return mode

    @property
    def variational(self):
        """Whether the model is the variational version of a model."""
        return _check.variational(self.model)


class EventLog:
    """The kernel's preallocated event log, emptied into chunks when it fills.

    Parameters
    ----------
    cap : int
        Entries per fill.
    n : int
        State size.
    n_mode : int
    """

    def __init__(self, cap, n, n_mode):
        self.cap, self.n, self.n_mode = int(cap), int(n), int(n_mode)
        self.chunks: list[tuple[np.ndarray, ...]] = []
        self._arrays: tuple[np.ndarray, ...] | None = None

    def arrays(self):
        """Fresh arrays ``(t, which, mode, state)`` for the next fill."""
        self._arrays = (np.empty(self.cap), np.empty(self.cap, dtype=np.int64),
                        np.empty((self.cap, 2 * self.n_mode), dtype=np.int64),
                        np.empty((self.cap, self.n)))
        return self._arrays

    def keep(self, n_ev):
        """Keep the first ``n_ev`` entries of the last fill."""
        assert self._arrays is not None  # a fill follows arrays()
        self.chunks.append(tuple(a[:n_ev] for a in self._arrays))

    def events(self):
        """All entries: ``{"t", "which", "mode_before", "mode_after", "state"}``."""
        modes = np.concatenate([c[2] for c in self.chunks]) if self.chunks else \
            np.zeros((0, 2 * self.n_mode), dtype=np.int64)

        def cat(i, empty):
            return np.concatenate([c[i] for c in self.chunks]) if self.chunks else empty
        return {"t": cat(0, np.zeros(0)),
                "which": cat(1, np.zeros(0, dtype=np.int64)),
                "mode_before": modes[:, :self.n_mode],
                "mode_after": modes[:, self.n_mode:],
                "state": cat(3, np.zeros((0, self.n)))}


def log_capacity(periods):
    """Event-log entries per fill for ``periods`` recorded periods."""
    return int(min(max(64 * periods, 1024), 262_144))


def new_clock(problem, options, h0=None, steps=True):
    """``(k, s, h[, steps, j])`` at ``tau = 0`` with the first step size trial ``h0``
    (``min(T / 50, max_step)`` by default); ``steps``: the clock carries the steps taken
    in the current period and the next dense sample's index (-1: not yet known) across
    calls (a run continued after LOG_FULL)."""
    h = min(problem.period / 50.0, options.max_step) if h0 is None else h0
    return np.array([0.0, 0.0, h, 0.0, -1.0]) if steps else np.array([0.0, 0.0, h])


def counters():
    """Zeroed counters: steps, RHS evaluations, rejected steps, events, observed."""
    return np.zeros(N_COUNTERS, dtype=np.int64)


def _leading(problem, method, options) -> tuple[
        tuple[object, np.ndarray, np.ndarray, float], tuple[object, ...], np.ndarray]:
    """The arguments every kernel entry point starts with, packed as the kernel takes
    them (:func:`.driver.integrate`): ``(model, terminal, p, omega)``, the method's
    tableau tuple and the option vector.  The one place a kernel call is built."""
    return ((_dispatch.kernel_model(problem.model), problem.terminal, problem.p,
             float(problem.omega)), method.kernel_args(), options.vector(method))


def integrate(problem, method, options, y, mode, clock, k_end, *, k_record=0, strobe=None,
              dense_m=0, dense=None, count=None, log=None):
    """Integrate from ``clock = (k, s, h, steps)`` until the start of forcing period
    ``k_end``, emptying the event log whenever it fills.

    Parameters
    ----------
    problem : Problem
    method : Method
    options : Options
    y : ndarray of float64, shape (n,)
        State at the clock's time; overwritten with the final state.
    mode : ndarray of int64
        Discrete mode consistent with ``y``; overwritten.
    clock : ndarray of float64, shape (3,), (4,) or (5,)
        ``(k, s, h[, steps[, j]])``: period index, local time, next step size, steps
        taken in period ``k``, next dense sample's index (:func:`new_clock`); overwritten.
    k_end : int
    k_record : int
        Samples and events are recorded from ``tau = k_record T``.
    strobe : ndarray, shape (k_end - k_record + 1, n), optional
        Row ``j`` receives the state at ``tau = (k_record + j) T``.
    dense_m : int
        Dense samples per period (``dense`` of shape ``((k_end - k_record) dense_m + 1,
        n)``).
    count : ndarray of int64, shape (5,), optional
        Counters to accumulate into.
    log : EventLog, optional
        Receives the events (a fresh one of :func:`log_capacity` entries by default).

    Returns
    -------
    status : int
        The kernel's status (:mod:`.integrator`), never LOG_FULL.
    log : EventLog
    """
    n = y.size
    if strobe is None:
        strobe = np.empty((1, n))
    if dense is None:
        dense = np.empty((1, n))
    if count is None:
        count = counters()
    if log is None:
        log = EventLog(log_capacity(k_end - k_record), n, problem.n_mode)
    ws = _scratch(n, problem.terminal.size, mode.size)
    status = LOG_FULL
    key = _run_key(problem)
    loop = _loop(method)
    while status == LOG_FULL:
        status, n_ev, _ = loop.call_keyed(key, *integrate_args(
            problem, method, options, ws, y, mode, clock, k_end, k_record, strobe,
            log.arrays(), dense_m, dense, count, checked_ws=True))
        log.keep(n_ev)
    return status, log


def _loop(method):
    """The integration loop of ``method``: the driver's, or the era integrator's."""
    return _integrate_noevents if method.id == _tab.RK4_NOEVENTS else _integrate


def integrate_args(problem, method, options, ws, y, mode, clock, k_end, k_record, strobe,
                   log_arrays, dense_m, dense, count, renorm=_PLAIN, checked_ws=False):
    """The argument tuple of the kernel's integration loop (:func:`.driver.integrate`),
    for :func:`integrate`, :func:`benettin` and the install-time build of the precompiled
    loop (:mod:`.aot_build`): ``ws`` a :func:`.driver.workspace`, ``log_arrays`` an
    :meth:`EventLog.arrays`, ``renorm`` ``(n_state, bound, logs, states)`` of a
    Benettin run (none by default); ``checked_ws``: ``ws`` is this thread's
    :func:`_scratch`, checked when it was made."""
    _check_run(problem, method, ws, y, mode, clock, count, checked_ws=checked_ws)
    n = y.size
    _check.integer("k_end", k_end)
    _check.integer("k_record", k_record)
    _check.samples(strobe, dense, n, dense_m)
    _check.event_log(log_arrays, 0, n, problem.n_mode, problem.terminal.size)
    _check.renorm(renorm, n)
    return (*_leading(problem, method, options), ws, y, mode, clock, k_end, k_record,
            strobe, log_arrays, 0, dense_m, dense, count, renorm)


def _run_key(problem):
    """What the numba types of the integration loop's arguments depend on once
    :func:`integrate_args` has checked them (every array's dtype, dimensions and memory
    order are pinned there, the method's tableau tuple has one layout for every method,
    a plain run's and a Benettin run's ``renorm`` one type): the model (a built-in
    family; a user model's functions themselves, held by the key) and whether
    ``p`` is writeable (numba types a read-only array apart).  The key of
    :meth:`.precompiled.Routine.call_keyed`."""
    km = _dispatch.kernel_model(problem.model)
    model = km.family if isinstance(km, BuiltinModel) else tuple(km)
    return model, bool(problem.p.flags.writeable)


def _scratch(n, n_switch, n_mode):
    """This thread's workspace for a state of ``n`` entries (:func:`.driver.workspace`:
    scratch arrays the loop overwrites before it reads them, reusable across calls),
    made and checked once per thread and size instead of at every call; a thread never
    runs two kernel calls at once, and no two threads share one."""
    cache = getattr(_SCRATCH, "cache", None)
    if cache is None:
        cache = _SCRATCH.cache = {}
    ws = cache.get((n, n_switch, n_mode))
    if ws is None:
        ws = _workspace(n, n_switch, n_mode)
        _check.workspace(ws, n, n_switch, n_mode)
        cache[(n, n_switch, n_mode)] = ws
    return ws


_SCRATCH = threading.local()


def _check_run(problem, method, ws, y, mode, clock, count, suffix="", checked_ws=False):
    """Check the arguments of a run of ``problem`` that every kernel entry point takes
    (:mod:`.argcheck`): the problem, the method, the workspace (unless ``checked_ws``),
    the state, the mode, the clock and the counters."""
    if not isinstance(problem, Problem) or not isinstance(method, Method):
        raise ValueError("the kernel takes a boundary.Problem and a boundary.Method")
    _check.state("y" + suffix, y, problem.n_state, problem.variational)
    _check.mode_vector("mode" + suffix, mode, problem.n_mode)
    _check.clock("clock" + suffix, clock)
    if not suffix:
        if not checked_ws:
            _check.workspace(ws, y.size, problem.terminal.size, problem.n_mode)
        _check.counters(count)


def benettin(problem, method, options, y, mode, clock, n_state, bound, n_periods, logs,
             states, count):
    """``n_periods`` periods of the variational model ``problem`` with QR
    re-orthonormalisation after each (the ``renorm`` mode of :func:`.driver.integrate`).

    ``logs`` (shape (>= n_periods, m)) receives ``log |R_ii|`` per period and ``states``
    (shape (>= n_periods, n_state)) the state at each period's end; ``clock`` must be at
    a period's start.  Returns ``(status, done)``.
    """
    n = y.size
    if n_periods <= 0:
        return OK, 0
    ws = _scratch(n, problem.terminal.size, mode.size)
    # nothing is recorded before a period's end: the log never fills
    log = EventLog(64, n, problem.n_mode)
    renorm = (int(n_state), float(bound), _rows(logs, n_periods), _rows(states, n_periods))
    status, _, done = _loop(method).call_keyed(_run_key(problem), *integrate_args(
        problem, method, options, ws, y, mode, clock, 0, 0, np.empty((1, n)), log.arrays(),
        0, np.empty((1, n)), count, renorm, checked_ws=True))
    return status, done


def _rows(a, n):
    """The first ``n`` rows of a C-contiguous float64 array, as a view (written to)."""
    if a.dtype != np.float64 or a.ndim != 2 or not a.flags.c_contiguous:
        raise ValueError("benettin's logs and states must be C-contiguous float64 arrays")
    return a[:n]


def two_trajectory(problem, method, options, y, mode, clock, y2, mode2, clock2, d0, scale,
                   bound, n_periods, logs, count):
    """A reference and a perturbed trajectory over ``n_periods`` periods, renormalised to
    ``d0`` after each (:func:`.lyapunov.two_trajectory`).  Returns ``(status, done)``."""
    ws = _workspace(y.size, problem.terminal.size, problem.n_mode)
    _check_run(problem, method, ws, y, mode, clock, count)
    _check_run(problem, method, ws, y2, mode2, clock2, count, suffix="2")
    _check.array("scale", scale, shape=(y.size,))
    n_periods = _check.integer("n_periods", n_periods)
    _check.array("logs", logs, ndim=2, writeable=True)
    if logs.shape[0] < n_periods or logs.shape[1] < 1:
        raise ValueError(f"kernel argument logs must have >= {n_periods} rows and a "
                         f"column, got shape {logs.shape}")
    return _two_trajectory(*_leading(problem, method, options), ws, y, mode, clock, y2,
                           mode2, clock2, float(d0), scale, float(bound), n_periods, logs,
                           count)


def qr_growth(J, logs):
    """``log |R_ii|`` of the QR re-orthonormalised product of map Jacobians ``J``
    (shape (N, d, d)) into ``logs`` (shape (N, d)) (:func:`.lyapunov.qr_growth`),
    arguments checked."""
    _check.ROUTINES["qr_growth"](J, logs)
    _qr_growth(J, logs)


def array_routine_calls():
    """``[(routine, example arguments)]``: the array routines the analyses call --
    :func:`dot`, :func:`matmul`, :func:`lstsq`, :func:`solve`, :func:`eigvals`,
    :func:`suffix_lag_residuals` -- with arguments of the types the analyses pass
    (C-contiguous float64 arrays, a float, an int).  What the warm-up compiles and the
    install precompiles (:mod:`.aot_build`)."""
    a, v = np.eye(2), np.ones(2)
    return [(dot, (v, v)), (matmul, (a, a)), (lstsq, (a, a, 1e-10)), (solve, (a, v)),
            (eigvals, (a,)),
            (suffix_lag_residuals, (np.zeros((3, 2)), 1, np.empty((3, 1)),
                                    np.empty((3, 2)), np.empty((3, 2)), np.empty(3)))]


def compile_array_routines():
    """Compile (or load from numba's disk cache) the routines of
    :func:`array_routine_calls` for their argument types."""
    for routine, args in array_routine_calls():
        routine(*args)


def array_routines_compiled():
    """True when this process has every routine of :func:`compile_array_routines`,
    precompiled or compiled."""
    return all(f.jit.signatures
               for f, _ in array_routine_calls())


__all__ = ["Method", "Options", "Problem", "EventLog", "integrate", "integrate_args",
           "benettin",
           "two_trajectory", "qr_growth", "suffix_lag_residuals", "new_clock",
           "counters", "log_capacity", "array_routine_calls", "compile_array_routines",
           "array_routines_compiled", "precompiled_status", "dot", "eigvals", "lstsq", "matmul",
           "solve", "METHODS", "OK", "LOG_FULL", "N_COUNTERS"]

# ---- the built-in models (issue 29, point 1): the model registry above the kernel reads
# each family's functions and sizes (:mod:`.registry`) and names built-in models
# (:func:`.dispatch.builtin`) through this boundary.
from .dispatch import BuiltinModel, builtin  # noqa: E402
from .registry import KernelModel, family as kernel_family  # noqa: E402
__all__ += ["BuiltinModel", "builtin", "KernelModel", "kernel_family"]
from .integrator import (DIVERGED_BOUND, DIVERGED_NONFINITE, MAX_STEPS,  # noqa: E402
                         STEP_UNDERFLOW, ZENO)
__all__ += ["DIVERGED_BOUND", "DIVERGED_NONFINITE", "MAX_STEPS", "STEP_UNDERFLOW", "ZENO"]


def initial_mode(family):
    """The ``init_mode`` of the built-in family ``family`` as a checked
    :class:`~.precompiled.Routine` (its argument sizes from :mod:`.registry`), for a
    model's :attr:`Problem.init_mode`."""
    return _routine(f"{family}_init_mode", kernel_family(family).init_mode)


__all__ += ["initial_mode"]
