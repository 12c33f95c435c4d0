"""`System`: a model, its parameters and the solver settings, as the analysers take it.

As ChaosTools' analysers take a dynamical system, every analyser of
:mod:`vibimpact.analysis` (Lyapunov exponents, shooting, continuation, classification)
takes a :class:`System` and only the parameters of the analysis itself::

    sys = vi.System(vi.presets.get("fig8").replace(eta=1.25))
    sys.period                            # 2 pi / eta
    run = sys.simulate(periods=200, transient=500)
    lyapunov_spectrum(sys.with_params(eta=1.185))

The solver settings are one :class:`~vibimpact.SolverSettings` (``System(p,
solver=vi.SolverSettings(rtol=1e-10))``); a setting left ``None`` means "the analysis' own
default" (e.g. tolerances of 1e-9 for :meth:`System.simulate`, 1e-10 for the variational
equations), so that a default ``System`` runs every analysis as it was designed and
tested.  Runs go through a :class:`~vibimpact.Solver` (:mod:`vibimpact.core.solver`).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..base import _validate as _v
from ..models import Model, resolve
from ..models.params import Domain
from .run import Status, status_of
from .solver import (NO_SETTINGS, SETTINGS, Solver, SolverSettings, as_settings,
                     run_system)

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

    from .run import Run

#: the solver settings a System also takes as keywords (the rest only in ``solver``)
SOLVER_FIELDS = ("method", "rtol", "atol", "max_step", "event_tol")


#: the relative tolerance of :meth:`System.monodromy` when the system sets none
MONODROMY_RTOL = 1e-10


@dataclass(frozen=True, eq=False)
class Monodromy:
    """The ``n``-fold stroboscopic map and its Jacobian at one state.

    Attributes
    ----------
    matrix : ndarray, shape (d, d)
        ``M = D P^n(start)`` from the variational equations with saltation matrices; the
        monodromy matrix when ``start`` lies on a period-``n`` orbit.
    start, end : ndarray, shape (d,)
        ``x`` and ``P^n(x)``.
    n : int
        Forcing periods integrated.
    period : float
        ``n T``, the time integrated.
    status : Status
    reason : str
    """

    matrix: np.ndarray
    start: np.ndarray
    end: np.ndarray
    n: int
    period: float
    status: Status = Status.OK
    reason: str = ""

    @property
    def residual(self):
        """``P^n(x) - x``."""
        return self.end - self.start


@dataclass(frozen=True, eq=False)
class System:
    """A periodically forced piecewise-smooth system ready to be analysed.

    Parameters
    ----------
    params : Params, DuffingParams, mapping or array_like
        Parameters; a plain vector or a ``{name: value}`` mapping with ``model``.  Every
        form is checked the same way (:meth:`vibimpact.Model.check_params`): each value
        finite and inside its parameter's domain.
    model : Model, optional
        The model of a plain vector or mapping: a built-in one (``vi.ROTOR``, ...) or a
        user's (:meth:`vibimpact.Model.from_functions`); taken from the type of
        ``params`` otherwise.
    method : {"dop853", "dp5", "rk4"}, optional
    rtol, atol, max_step, event_tol : float, optional
        Solver settings as keywords; each given one replaces the same setting of
        ``solver``.
    solver : SolverSettings, optional
        The solver settings; ``None`` entries leave each analysis its own default.

    Raises
    ------
    ValueError
        Naming the offending argument or parameter (``"f must be >= 0, got -1.0"``).
    """

    params: object
    # model and solver: None in the constructor only; __post_init__ resolves both
    model: Model = None  # type: ignore[assignment]
    method: str | None = None
    rtol: float | None = None
    atol: float | None = None
    max_step: float | None = None
    event_tol: float | None = None
    solver: SolverSettings = None  # type: ignore[assignment]
    p: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        mdl, vec = resolve(self.params, self.model)
        object.__setattr__(self, "model", mdl)
        object.__setattr__(self, "p", vec)
        keywords = {k: v for k in SOLVER_FIELDS if (v := getattr(self, k)) is not None}
        settings = as_settings(self.solver) or NO_SETTINGS
        if keywords:
            settings = SolverSettings(**keywords).over(settings)
        object.__setattr__(self, "solver", settings)
        for name in SOLVER_FIELDS:  # the keywords' attributes say the settings
            object.__setattr__(self, name, getattr(settings, name))
        if not math.isfinite(self.omega) or self.omega <= 0.0:
            raise ValueError(f"the forcing frequency {mdl.param_names[mdl.omega_index]} "
                             f"must be finite and > 0, got {self.omega!r}")

    # --- what the system is ---------------------------------------------------------
    @property
    def omega(self):
        """The forcing frequency (the model's frequency parameter: ``eta`` for the
        built-in rotor)."""
        return float(self.p[self.model.omega_index])

    @property
    def period(self):
        """The forcing period ``T = 2 pi / omega``."""
        return 2.0 * math.pi / self.omega

    @property
    def n_state(self):
        """Length of the state vector."""
        return len(self.model.state_names)

    @property
    def builtin(self):
        """Whether the model is a built-in one (:func:`vibimpact.models.names`)."""
        return self.model.builtin

    @property
    def user_model(self):
        """The model as :func:`vibimpact.simulate` takes it (None for a built-in one)."""
        return None if self.builtin else self.model

    def param(self, name: str | int) -> float:
        """The value of parameter ``name`` (a field name, or an index of a user model's
        vector); ``ValueError`` naming ``param`` otherwise."""
        return float(self.p[self._index(name)])

    def param_domain(self, name: str | int) -> Domain:
        """The values parameter ``name`` may take.

        The built-in models' parameter sets state their domains
        (:meth:`vibimpact.Params.domain`: the dampings, stiffness, friction, radius,
        eccentricity and ``eps`` ``>= 0``, ``eta > 0``; :class:`vibimpact.DuffingParams`:
        ``delta >= 0``, ``omega > 0``); a user model's are those it declares
        (``Model.from_functions(..., domains=)``), any finite number otherwise, its
        forcing frequency ``> 0``.

        Parameters
        ----------
        name : str or int
            A parameter's name, or an index of a user model's vector.

        Returns
        -------
        Domain
            ``lo``, ``hi`` and whether each is allowed (:meth:`Domain.rule` says it in
            words, ``value in domain`` tests a value).

        Raises
        ------
        ValueError
            Naming ``param`` for an unknown parameter.

        Examples
        --------
        >>> import vibimpact as vi
        >>> vi.System(vi.presets.get("fig8")).param_domain("BT").rule("BT")
        'BT must be >= 0'
        """
        return self.model.domain(self._index(name))

    def _index(self, name):
        names = self.model.param_names
        if isinstance(name, str) and name in names:
            return names.index(name)
        if not isinstance(name, (str, int, np.integer)) or isinstance(name, bool):
            raise _v.WrongType(f"param must be a parameter's name (str), one of "
                               f"{', '.join(names)}, got {type(name).__name__} {name!r}")
        if self.builtin or not isinstance(name, (int, np.integer)) or \
                not 0 <= int(name) < len(names):
            raise ValueError(f"param must be one of {', '.join(names)}"
                             + ("" if self.builtin else " or an index") + f", got {name!r}")
        return int(name)

    # --- new systems from this one --------------------------------------------------------
    def with_params(self, **changes) -> System:
        """The same system with some parameters changed (by name)."""
        if not changes:
            return self
        if hasattr(self.params, "replace"):
            return replace(self, params=self.params.replace(**changes))
        vec = self.p.copy()
        for name, value in changes.items():
            i = self._index(name)
            vec[i] = _v.finite(self.model.param_names[i], value)
        return replace(self, params=vec)

    def with_param(self, name: str | int, value: float) -> System:
        """The same system with one parameter (name, or index of a user vector) set."""
        i = self._index(name)
        if hasattr(self.params, "replace"):
            return replace(self, params=self.params.replace(
                **{self.model.param_names[i]: value}))
        vec = self.p.copy()
        vec[i] = _v.finite(self.model.param_names[i], value)
        return replace(self, params=vec)

    def with_solver(self, **settings) -> System:
        """The same system with other solver settings (``method``, ``rtol``, ... of
        :class:`~vibimpact.SolverSettings`); ``ValueError`` for an unknown one."""
        return self._with_settings(self.solver.replace(**settings))

    def _with_settings(self, settings):
        cleared: dict[str, Any] = dict.fromkeys(SOLVER_FIELDS)  # the settings' keywords
        return replace(self, solver=settings, **cleared)

    def settings(self, **defaults) -> SolverSettings:
        """The solver settings, each ``None`` replaced by the caller's default (then by
        :func:`vibimpact.simulate`'s, :data:`vibimpact.core.solver.SIMULATE_DEFAULTS`)."""
        unknown = set(defaults) - set(SETTINGS)
        if unknown:
            raise ValueError(f"solver settings are {', '.join(SETTINGS)}, got "
                             f"{', '.join(sorted(unknown))}")
        return self.solver.filled(**defaults)

    # --- runs ---------------------------------------------------------------------------
    def simulate(self, periods: int = 100, transient: int = 0,
                 state0: ArrayLike | None = None, *, dense: int = 0,
                 solver: SolverSettings | None = None) -> Run:
        """:func:`vibimpact.simulate` of this system (the settings of ``solver`` that
        are not None replace the system's).

        Returns
        -------
        Run
        """
        return run_system(self, periods, transient, state0, dense, solver)

    def strobe(self, periods: int, state0: ArrayLike,
               **defaults) -> tuple[Status, str, np.ndarray | None]:
        """Stroboscopic points only, unvalidated (the loops of sweeps).

        Returns
        -------
        status : Status
        reason : str
        strobe : ndarray, shape (rows, n), or None
            Rows 0..periods, fewer when the run stopped early; None for ``periods`` 0.
        """
        seg = Solver(self, state0, self.settings(**defaults), check=False).advance(
            periods, events=False)
        return seg.status, seg.reason, seg.strobe

    def monodromy(self, state0: ArrayLike, n: int = 1, *,
                  tangent_tol: float = 1.0) -> Monodromy:
        """Jacobian of the ``n``-fold stroboscopic map by the variational equations.

        The state and ``d`` tangent vectors (the columns of the identity) are integrated
        together over ``n`` forcing periods from ``tau = 0``; at every switching event the
        tangent vectors are mapped by the saltation matrix (Leine & Nijmeijer 2004,
        *Dynamics and Bifurcations of Non-Smooth Mechanical Systems*, sec. 3.5), so the
        result is the Jacobian of the non-smooth map, not of a smoothed one.  Solver
        defaults: DOP853 (or DP5; adaptive only), ``rtol = 1e-10``.

        Parameters
        ----------
        state0 : array_like, shape (d,)
        n : int
        tangent_tol : float
            The tangent vectors' local errors are tested against ``tangent_tol`` times the
            tolerances (1: Newton's steps and multipliers near the unit circle need the
            matrix itself to the tolerance; ``inf``: not tested).

        Returns
        -------
        Monodromy
            ``status`` DIVERGED/FAILED with a NaN matrix when the integration stopped.
        """
        d = self.n_state
        if state0 is None:
            raise ValueError(f"state0 must be {d} finite numbers, got None")
        n = _v.count("n", n, 1)
        solver = Solver.variational(self, state0, self.settings(rtol=MONODROMY_RTOL),
                                    tangents=d, tangent_tol=tangent_tol)
        x0 = solver.y[:d].copy()
        seg = solver.advance(0, skip=n)
        T = self.period
        if seg.status is not Status.OK:
            return Monodromy(np.full((d, d), np.nan), x0, np.full(d, np.nan), n, n * T,
                             seg.status, f"{status_of(seg.code)[1]} in forcing period "
                                         f"{int(solver.clock[0])}")
        y = solver.y
        M = y[d:].reshape(d, d).T.copy()  # column c is the tangent vector started at e_c
        return Monodromy(M, x0, y[:d].copy(), n, n * T)

    def resolved(self, **defaults) -> System:
        """The same system with every solver setting fixed: the caller's ``defaults``
        (then :func:`vibimpact.simulate`'s) for those left None, so that the analyses it
        is passed on to use the caller's defaults, not their own."""
        return self._with_settings(self.settings(**defaults))


def as_system(system, name="system"):
    """``system`` if it is a :class:`System`; a ``ValueError`` naming ``name`` that says
    how to make one otherwise."""
    if isinstance(system, System):
        return system
    raise _v.WrongType(f"{name} must be a vibimpact.System (e.g. vi.System(params)), "
                       f"got {type(system).__name__}")


def to_system(p: object, name: str = "p") -> System:
    """``p`` as a :class:`System` (a parameter set of a built-in model becomes one with
    the default solver settings); a ``TypeError`` (also a ``ValueError``) naming ``name``,
    the caller's argument, for anything else."""
    if isinstance(p, System):
        return p
    from ..models import of_params, param_set_names

    if of_params(p) is None:
        raise _v.WrongType(f"{name} must be a vibimpact.System or the parameter set of a "
                           f"model ({param_set_names()}), got {type(p).__name__}")
    return System(p)


def with_frequency(p, value):
    """``p`` (a parameter set or a System) with its forcing frequency set to ``value``
    (the model's frequency parameter: e.g. ``eta`` of the built-in rotor, ``omega`` of the
    Duffing oscillator), of the same type."""
    mdl = p.model if isinstance(p, System) else resolve(p)[0]
    name = mdl.param_names[mdl.omega_index]
    if isinstance(p, System):
        return p.with_param(name, value)
    return p.replace(**{name: float(value)})


def param_dict(p):
    """``{name: value}`` of the parameters of ``p`` (a parameter set or a System)."""
    if hasattr(p, "as_dict"):
        return p.as_dict()
    s = to_system(p)
    if hasattr(s.params, "as_dict"):
        return s.params.as_dict()
    return {name: float(v) for name, v in zip(s.model.param_names, s.p)}


def with_values(p, **changes):
    """``p`` (a parameter set or a System) with parameters changed by name, of the same
    type."""
    if isinstance(p, System):
        return p.with_params(**changes)
    return p.replace(**changes)


def varied_names(p):
    """Names of the parameters of ``p``'s model other than the forcing frequency."""
    mdl = p.model if isinstance(p, System) else resolve(p)[0]
    return tuple(n for i, n in enumerate(mdl.param_names) if i != mdl.omega_index)
