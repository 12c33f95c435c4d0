"""Solver settings and the solver object: the one place the numba kernel is entered.

In the shape of SciPy's ``integrate.OdeSolver``, a :class:`Solver` holds what one
integration of a :class:`~vibimpact.System` needs -- the kernel's problem, the
Runge--Kutta method, the kernel options, and the state, discrete mode, clock and counters
it advances -- and :meth:`Solver.advance` integrates whole forcing periods, recording what
it is asked for (stroboscopic samples, dense samples, events).  The Lyapunov loops are
its other two moves: :meth:`Solver.benettin` (tangent vectors re-orthonormalised after
each period) and :meth:`Solver.two_trajectory` (a reference and a perturbed copy).

:class:`SolverSettings` is the one object of solver settings a System carries; a field
left ``None`` is "the analysis' default" (:data:`SIMULATE_DEFAULTS` last), and
:meth:`SolverSettings.options` is the one place the kernel's options are built.

Every call of :func:`vibimpact._kernel.boundary.integrate`, ``benettin`` and
``two_trajectory`` above the kernel is in this module.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

import math
from dataclasses import dataclass, fields, replace

import logging

import numpy as np

from ..base import _limits
from ..base import _validate as _v
from .._kernel import boundary as _kb
from .run import Run, Status, impacts_of, status_of

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

    from .._kernel.boundary import Method, Options
    from ..models import Model



class SystemLike(Protocol):
    """What a solver reads of the system it integrates (a :class:`vibimpact.System`):
    its model, parameters (the set and its vector), solver settings, forcing period and
    state size.  The solver stands below System and does not import it."""

    @property
    def model(self) -> Model:
        """The model."""

    @property
    def params(self) -> object:
        """The parameter set."""

    @property
    def p(self) -> np.ndarray:
        """The parameter vector."""

    @property
    def solver(self) -> SolverSettings:
        """The solver settings."""

    @property
    def period(self) -> float:
        """The forcing period."""

    @property
    def n_state(self) -> int:
        """The state's length."""


_logger = logging.getLogger(__name__)
#: method names, in the order the kernel numbers them
METHODS = _kb.METHODS

#: what a setting left ``None`` becomes when no analysis says otherwise (the defaults of
#: :func:`vibimpact.simulate`); ``max_step`` None is a quarter period, ``bound`` None the
#: model's own
SIMULATE_DEFAULTS = dict(method="dop853", rtol=1e-9, atol=1e-12, steps_per_period=400,
                         adaptive=True, max_step=None, bound=None, event_tol=1e-12,
                         max_steps_per_period=1_000_000)


@dataclass(frozen=True)
class SolverSettings:
    """The settings of the kernel's integrator, as a System carries them.

    A setting left ``None`` takes the default of the analysis that runs the system (for
    example ``rtol = 1e-10`` for the variational equations), then
    :data:`SIMULATE_DEFAULTS`.

    Parameters
    ----------
    method : {"dop853", "dp5", "rk4", "rk4-fixed-noevents"}, optional
        Dormand--Prince 8(5,3) or 5(4), adaptive; the classical RK4 at a fixed step, with
        located events; or ``"rk4-fixed-noevents"``, the era's integrator: RK4 at exactly
        ``steps_per_period`` steps per period, every stage in the mode its own state
        implies (the contact switch inside the right-hand side), switches applied at the
        end of the step that crossed them, no event location
        (:mod:`vibimpact._kernel.noevents`).  It exists to measure how much the labels
        depend on an accurate integration (order 1 through contacts), not to be used.
    rtol, atol : float, optional
        Tolerances of the adaptive methods.
    steps_per_period : int, optional
        Fixed-step runs (the RK4 methods, or ``adaptive=False``): steps per forcing
        period.  With ``"rk4"`` steps are also cut at events and graded next to contact
        surfaces; ``"rk4-fixed-noevents"`` keeps its grid.
    adaptive : bool, optional
        False runs DP5 or DOP853 with fixed steps, no error control (to measure orders).
    max_step : float, optional
        Largest step; a quarter period by default.
    bound : float, optional
        A state component beyond this ends the run as DIVERGED (the model's own by
        default: e.g. 1e3 clearances for the built-in rotor).
    event_tol : float, optional
        Switching functions are zero to this at every located event.
    max_steps_per_period : int, optional

    Raises
    ------
    ValueError
        Naming the offending setting (a ``TypeError`` too for a value of the wrong type).

    Examples
    --------
    >>> import vibimpact as vi
    >>> s = vi.SolverSettings(method="dp5", rtol=1e-8)
    >>> s.filled().atol
    1e-12
    """

    method: str | None = None
    rtol: float | None = None
    atol: float | None = None
    steps_per_period: int | None = None
    adaptive: bool | None = None
    max_step: float | None = None
    bound: float | None = None
    event_tol: float | None = None
    max_steps_per_period: int | None = None

    def __post_init__(self):
        for name in SETTINGS:
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, _checked(name, value))

    def _with(self, changes):
        """A copy with ``changes`` checked (only they: the rest was checked when made)."""
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        new.__dict__.pop("_filled", None)
        for name, value in changes.items():
            object.__setattr__(new, name, None if value is None else _checked(name, value))
        return new

    def replace(self, **changes) -> SolverSettings:
        """A copy with some settings changed; ``ValueError`` for an unknown name."""
        unknown = set(changes) - set(SETTINGS)
        if unknown:
            raise ValueError(f"solver settings are {', '.join(SETTINGS)}, got "
                             f"{', '.join(sorted(unknown))}")
        return replace(self, **changes)

    def over(self, base: SolverSettings | None) -> SolverSettings:
        """These settings, each ``None`` taken from ``base`` (these win)."""
        if base is None:
            return self
        return base._with({k: v for k, v in self.as_dict().items() if v is not None})

    def filled(self, **defaults) -> SolverSettings:
        """Every setting fixed: ``None`` replaced by the caller's ``defaults``, then by
        :data:`SIMULATE_DEFAULTS` (``max_step`` and ``bound`` may stay None: a quarter
        period and the model's bound)."""
        if not defaults:  # the common case, kept: a System's settings fill every run
            done = self.__dict__.get("_filled")
            if done is None:
                done = self._fill(SIMULATE_DEFAULTS)
                object.__setattr__(self, "_filled", done)
            return done
        return self._fill(dict(SIMULATE_DEFAULTS, **defaults))

    def _fill(self, base):
        changes = {k: base[k] for k in SETTINGS
                   if getattr(self, k) is None and base[k] is not None}
        return self._with(changes) if changes else self

    def as_dict(self, names: tuple[str, ...] | None = None) -> dict[str, object]:
        """``{name: value}`` of the settings ``names`` (all by default), in order."""
        return {k: getattr(self, k) for k in (SETTINGS if names is None else names)}

    def kernel_method(self) -> Method:
        """The Runge--Kutta method (:class:`vibimpact._kernel.boundary.Method`)."""
        return _kb.Method.named(self.filled().method)

    def options(self, period: float, bound: float, *, n_bound: int = 0, n_err: int = 0,
                tangent_factor: float = 1.0) -> Options:
        """The kernel's options of a run with forcing period ``period``: the one place
        they are built.

        Parameters
        ----------
        period : float
            The forcing period ``T`` (fixed step ``T / steps_per_period``; ``max_step``
            ``T / 4`` when None).
        bound : float
            The model's divergence bound, used when ``bound`` is None.
        n_bound, n_err, tangent_factor
            As :class:`vibimpact._kernel.boundary.Options` (the variational runs).
        """
        s = self.filled()
        # filled() leaves only max_step and bound None
        assert (s.rtol is not None and s.atol is not None and s.steps_per_period is not None
                and s.event_tol is not None and s.max_steps_per_period is not None
                and s.adaptive is not None)
        T = period
        return _kb.Options(rtol=s.rtol, atol=s.atol, h_fixed=T / s.steps_per_period,
                           max_step=T / 4.0 if s.max_step is None else s.max_step,
                           bound=bound if s.bound is None else s.bound,
                           event_tol=s.event_tol,
                           max_steps_per_period=s.max_steps_per_period,
                           adaptive=s.adaptive, n_bound=n_bound, n_err=n_err,
                           tangent_factor=tangent_factor)


#: the settings' names, in order
SETTINGS = tuple(f.name for f in fields(SolverSettings))
#: no setting given: every analysis' defaults
NO_SETTINGS = SolverSettings()

#: the check of each setting that is not a positive number
_CHECKS = dict(method=lambda n, v: _v.choice(n, v, _kb.METHODS),
               steps_per_period=_v.count, max_steps_per_period=_v.count, adaptive=_v.flag)


def _checked(name, value):
    """``value`` of setting ``name`` validated (``ValueError`` or ``TypeError`` naming
    it)."""
    return _CHECKS.get(name, _v.positive)(name, value)


def as_settings(solver, name="solver"):
    """``solver`` (a :class:`SolverSettings` or None) checked; ``TypeError`` naming
    ``name`` otherwise."""
    if solver is None or isinstance(solver, SolverSettings):
        return solver
    raise _v.WrongType(f"{name} must be a vibimpact.SolverSettings "
                       f"(e.g. vi.SolverSettings(rtol=1e-10)) or None, got "
                       f"{type(solver).__name__}")


def _tangent_factor(tangent_tol):
    try:
        f = float(tangent_tol)
    except (TypeError, ValueError):
        f = float("nan")
    if not f >= 1.0:
        raise ValueError(f"tangent_tol must be a number >= 1 or inf, got {tangent_tol!r}")
    return 0.0 if math.isinf(f) else f


@dataclass(frozen=True, eq=False)
class Segment:
    """What one :meth:`Solver.advance` recorded.

    Attributes
    ----------
    code : int
        The kernel's status code.
    status : Status
    reason : str
        Why the run stopped, with the time (empty when it did not).
    strobe : ndarray, shape (rows, n) or None
        The state at each recorded period's start, rows computed only.
    dense : ndarray or None
        ``dense`` evenly spaced samples per recorded period, samples computed only.
    log : EventLog or None
        The events of the recorded periods.
    """

    code: int
    status: Status
    reason: str
    strobe: np.ndarray | None = None
    dense: np.ndarray | None = None
    log: _kb.EventLog | None = None

    @property
    def events(self):
        """``{"t", "which", "mode_before", "mode_after", "state"}`` of the events."""
        assert self.log is not None  # recorded periods whose events were kept
        return self.log.events()


class Solver:
    """An integration of one :class:`~vibimpact.System` from one state, advanced period
    by period.

    Parameters
    ----------
    system : System
    state0 : array_like, shape (n,), optional
        State at ``tau = 0``; the rest state by default.
    settings : SolverSettings, optional
        The settings to run with (``None`` entries: :data:`SIMULATE_DEFAULTS`); the
        system's own by default.
    check : bool
        False takes ``state0`` as it is (a state of the loops of sweeps, already checked;
        the kernel still checks its size).

    Attributes
    ----------
    problem, method, options
        The kernel's problem, Runge--Kutta method and options.
    y : ndarray
        The current state (with tangent vectors after :meth:`variational`).
    mode, clock, counters : ndarray
        Discrete mode, ``(k, s, h[, steps, j])`` and the counters (steps, RHS
        evaluations, rejected steps, events, observed).

    Examples
    --------
    >>> import vibimpact as vi
    >>> solver = vi.Solver(vi.System(vi.presets.get("fig8")), [0.0, 0.0, 0.5, 0.0])
    >>> solver.advance(3).strobe.shape
    (4, 4)
    """

    def __init__(self, system: SystemLike, state0: ArrayLike | None = None,
                 settings: SolverSettings | None = None, *, check: bool = True):
        if check is not True and check is not False:  # cheap: the loops pass a bool
            _v.flag("check", check)
        settings = (system.solver if settings is None else settings).filled()
        y = _v.state("state0", state0, system.n_state) if check else \
            np.array(state0, dtype=np.float64)
        self._start(system, settings, settings.options(system.period, system.model.bound),
                    y, variational=False)
        self.clock = _kb.new_clock(self.problem, self.options)

    @classmethod
    def variational(cls, system: SystemLike, state0: ArrayLike, settings: SolverSettings, *,
                    tangents: int, tangent_tol: float | None = None,
                    first_step: float | None = None) -> Solver:
        """A solver of the variational equations: the state and ``tangents`` tangent
        vectors (the first columns of the identity), mapped by saltation matrices at
        every switch.

        DP5 and DOP853 take adaptive steps here whatever ``adaptive`` says; a fixed-step
        method its own steps.  The bound applies to the model state only; the tangent
        entries' local errors are tested at ``tangent_tol`` times the tolerances
        (``inf``: not tested; None: as the state's).  ``first_step``: the first step
        size trial (``min(T / 50, max_step)`` by default).
        """
        self = cls.__new__(cls)
        n = system.n_state
        settings = cls._adaptive(settings)
        options = settings.options(system.period, system.model.bound, n_bound=n)
        if tangent_tol is not None:
            options = options.with_(n_err=n, tangent_factor=_tangent_factor(tangent_tol))
        x0 = _v.state("state0", state0, n)
        y = np.zeros(n * (1 + tangents))
        y[:n] = x0
        for c in range(tangents):
            y[n + c * n + c] = 1.0
        # a built-in model's init_mode sees the tangent vectors, to project those that a
        # start in a sliding mode annihilates (the ring model's stuck bearing)
        self._start(system, settings, options, y, variational=True,
                    x0=None if system.model.builtin else x0)
        self.clock = _kb.new_clock(self.problem, options, h0=first_step, steps=False)
        return self

    @classmethod
    def pair(cls, system: SystemLike, state0: ArrayLike, state1: ArrayLike,
             settings: SolverSettings, *,
             first_step: float | None = None) -> tuple[Solver, Solver]:
        """Two solvers of ``system`` started at ``state0`` and ``state1`` with the same
        clock, for :meth:`two_trajectory` (DP5 and DOP853 with adaptive steps, a
        fixed-step method on its own steps)."""
        settings = cls._adaptive(settings)
        options = settings.options(system.period, system.model.bound)
        out = []
        for y in (state0, state1):
            self = cls.__new__(cls)
            self._start(system, settings, options, _v.state("state0", y, system.n_state),
                        variational=False)
            out.append(self)
        out[0].clock = _kb.new_clock(out[0].problem, options, h0=first_step, steps=False)
        out[1].clock = out[0].clock.copy()
        return out[0], out[1]

    @staticmethod
    def check_tangents(settings: SolverSettings, tangent_tol: float | None = None) -> None:
        """Check that ``settings`` and ``tangent_tol`` can run the variational equations
        or a pair (:meth:`variational`, :meth:`pair`): ``ValueError`` naming
        ``tangent_tol`` for one below 1 (every method runs them)."""
        Solver._adaptive(settings)
        if tangent_tol is not None:
            _tangent_factor(tangent_tol)

    @staticmethod
    def _adaptive(settings):
        """``settings`` filled, with adaptive steps for an embedded method (the
        variational and two-trajectory runs of DP5 and DOP853 always take them:
        ``adaptive=False`` is for measuring orders of plain runs).  A fixed-step method
        (``"rk4"``, ``"rk4-fixed-noevents"``) runs them on its own steps, so that every
        analysis runs on the method a study measures."""
        s = settings.filled()
        if s.method not in ("dop853", "dp5"):
            return s
        return s if s.adaptive else s._with({"adaptive": True})

    def _start(self, system, settings, options, y, *, variational, x0=None):
        self.system, self.settings, self.options = system, settings, options
        self.method = settings.kernel_method()
        self.problem = system.model.problem(system.p, variational=variational)
        self.y = y
        self.mode = self.problem.initial_mode(y if x0 is None else x0)
        self.counters = _kb.counters()

    @property
    def period(self) -> float:
        """The forcing period ``T``."""
        return self.problem.period

    @_v.checks_flags
    def advance(self, periods: int, *, skip: int = 0, dense: int = 0,
                events: bool = True) -> Segment:
        """Integrate ``skip`` forcing periods unrecorded, then ``periods`` recorded ones.

        Parameters
        ----------
        periods : int
            Periods recorded: their ``periods + 1`` stroboscopic samples (the first is
            NaN until the kernel reaches it, or the current state without ``skip``),
            ``dense`` samples each (and the last), their events.
        skip : int
        dense : int
            Evenly spaced samples per recorded period.
        events : bool
            Whether the events are kept (they are always logged; without ``periods``
            nothing is).

        Returns
        -------
        Segment
            Rows and samples of the periods computed only, when the run stopped early.
        """
        y, n = self.y, self.y.size
        k0 = int(self.clock[0])
        strobe = np.empty((periods + 1, n)) if periods else None
        if strobe is not None:
            strobe[0] = y if skip == 0 else np.nan
        dense_arr = np.full((periods * dense + 1, n) if dense else (1, n), np.nan)
        if dense and skip == 0:
            dense_arr[0] = y
        # nothing is recorded without periods: a small log never fills
        log = None if periods else _kb.EventLog(64, n, self.problem.n_mode)
        code, log = _kb.integrate(self.problem, self.method, self.options, y, self.mode,
                                  self.clock, k0 + skip + periods, k_record=k0 + skip,
                                  strobe=strobe, dense_m=dense, dense=dense_arr,
                                  count=self.counters, log=log)
        status, reason = status_of(code)
        if status is not Status.OK:
            reason = self.stopped(reason)
        if not periods:
            return Segment(code, status, reason)
        assert strobe is not None  # allocated for periods > 0
        rows = periods + 1
        if status is not Status.OK:
            k_done = int(self.clock[0]) - k0
            rows = max(0, min(periods, k_done - skip)) + (1 if k_done >= skip else 0)
        if dense:
            n_dense = periods * dense + 1 if status is Status.OK else \
                max(0, rows - 1) * dense + (1 if rows else 0)
            dense_arr = dense_arr[:n_dense]
        return Segment(code, status, reason, strobe[:rows], dense_arr if dense else None,
                       log if events else None)

    def stopped(self, reason: str) -> str:
        """``reason`` with the time the run stopped at."""
        k_done = int(self.clock[0])
        return f"{reason} at t = {k_done * self.period + self.clock[1]:.6g} " \
               f"(forcing period {k_done})"

    def benettin(self, n_periods: int, logs: np.ndarray,
                 states: np.ndarray) -> tuple[int, int]:
        """``n_periods`` periods of the variational equations with QR
        re-orthonormalisation after each: ``logs`` (rows >= n_periods) receives
        ``log |R_ii|`` per period, ``states`` the state at each period's end.

        Returns ``(code, done)``: the kernel's status and the periods done.
        """
        return _kb.benettin(self.problem, self.method, self.options, self.y, self.mode,
                            self.clock, self.system.n_state, self.options.bound, n_periods,
                            logs, states, self.counters)

    def two_trajectory(self, other: Solver, d0: float, scale: np.ndarray, n_periods: int,
                       logs: np.ndarray) -> tuple[int, int]:
        """This (reference) and ``other`` (perturbed) solver over ``n_periods`` periods,
        ``other`` put back at distance ``d0`` after each (log separations into ``logs``).

        Returns ``(code, done)``.
        """
        return _kb.two_trajectory(self.problem, self.method, self.options, self.y,
                                  self.mode, self.clock, other.y, other.mode, other.clock,
                                  d0, scale, self.options.bound, n_periods, logs,
                                  self.counters)


def run_system(system: SystemLike, periods: int, transient: int, state0: ArrayLike | None,
               dense: int, solver: SolverSettings | None) -> Run:
    """One validated run of ``system`` as a :class:`~vibimpact.Run`: the body of
    :func:`vibimpact.simulate` and :meth:`vibimpact.System.simulate` (which document the
    arguments); ``solver``'s settings that are not None replace the system's."""
    solver = as_settings(solver)
    mdl = system.model
    periods = _v.count("periods", periods, 1)
    transient = _v.count("transient", transient, 0)
    dense = _v.count("dense", dense, 0)
    settings = system.solver if solver is None else solver.over(system.solver)
    n = system.n_state
    _limits.check_run(periods, transient, dense, n)
    y0 = _v.state("state0", state0, n)
    run = Solver(system, y0, settings, check=False)  # it advances run.y, a copy of y0
    seg = run.advance(periods, skip=transient, dense=dense)
    st, reason, strobe = seg.status, seg.reason, seg.strobe
    assert strobe is not None  # periods >= 1
    T = run.period
    rows = strobe.shape[0]
    events = seg.events
    impacts = impacts_of(mdl.contact, system.p, events, transient * T, T)
    if dense:
        dense_out = seg.dense
        assert dense_out is not None  # dense > 0
        t_dense = transient * T + np.arange(dense_out.shape[0]) * (T / dense)
    else:
        dense_out = None
        t_dense = None
    _logger.debug("simulate %s: %d periods after %d, status %s, %d steps, %d events",
                  mdl.name, periods, transient, st.value, int(run.counters[0]),
                  int(run.counters[3]))
    return Run(
        params=system.params, model=mdl.name, strobe=strobe,
        t_strobe=(transient + np.arange(rows)) * T, impacts=impacts, events=events,
        dense=dense_out, t_dense=t_dense, status=st, reason=reason,
        counters=dict(zip(("steps", "rhs_evals", "rejected", "events", "observed"),
                          (int(c) for c in run.counters))),
        final_state=strobe[-1].copy() if rows else run.y.copy(),
        solver=dict(method=run.settings.method,
                    adaptive=bool(run.settings.adaptive and run.method.adaptive),
                    rtol=run.settings.rtol, atol=run.settings.atol,
                    steps_per_period=run.settings.steps_per_period,
                    max_step=float(run.options.max_step), event_tol=run.settings.event_tol,
                    bound=float(run.options.bound)),
        state0=y0, periods=periods, transient=transient, dense_per_period=dense,
        contact=mdl.contact,
    )


__all__ = ["SolverSettings", "Solver", "Segment", "SETTINGS", "SIMULATE_DEFAULTS",
           "METHODS", "NO_SETTINGS", "as_settings", "run_system"]
