"""The validated public wrapper of the numba kernel: :func:`simulate`, one run of a
:class:`~vibimpact.System` by its :class:`~vibimpact.Solver`."""
from __future__ import annotations

from typing import TYPE_CHECKING

from .solver import METHODS, SETTINGS, SIMULATE_DEFAULTS, SolverSettings
from .system import System

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

    from ..models import Model
    from ..models.params import DuffingParams, Params
    from .run import Run

__all__ = ["simulate", "METHODS"]

#: defaults of :func:`simulate` (:data:`vibimpact.core.solver.SIMULATE_DEFAULTS`)
STEPS_PER_PERIOD = SIMULATE_DEFAULTS["steps_per_period"]
EVENT_TOL = SIMULATE_DEFAULTS["event_tol"]
MAX_STEPS_PER_PERIOD = SIMULATE_DEFAULTS["max_steps_per_period"]


def _moved(moved):
    """The ``TypeError`` of keywords :func:`simulate` no longer takes."""
    settings = [k for k in moved if k in SETTINGS]
    if settings:
        given = ", ".join(f"{k}={moved[k]!r}" for k in settings)
        return TypeError(f"simulate() takes the solver settings {', '.join(settings)} in "
                         f"solver=vi.SolverSettings({given}) (or in the System's solver)")
    return TypeError(f"simulate() got an unexpected keyword argument "
                     f"{sorted(moved)[0]!r}")


def simulate(p: System | Params | DuffingParams | ArrayLike, periods: int = 100,
             transient: int = 0, state0: ArrayLike | None = None, *, dense: int = 0,
             solver: SolverSettings | None = None, model: Model | str | None = None,
             **moved) -> Run:
    """Integrate the model and sample it stroboscopically.

    Parameters
    ----------
    p : System, Params or DuffingParams (or a parameter vector with ``model``)
        A System runs with its solver settings.
    periods : int
        Forcing periods recorded after the transient (``>= 1``).
    transient : int
        Forcing periods integrated first and discarded (``>= 0``).
    state0 : array_like, shape (n,), optional
        Initial state at ``tau = 0``; the rest state ``0`` by default.
    dense : int
        Evenly spaced samples per period to keep (0: none; memory stays flat).
    solver : SolverSettings, optional
        Solver settings (method, tolerances, steps, bound, ...); those not None replace
        the System's; the rest default to DOP853, ``rtol = 1e-9``, ``atol = 1e-12``,
        ``max_step`` a quarter period, the model's ``bound`` (e.g. 1e3 clearances for
        the built-in rotor), ``event_tol = 1e-12``
        (:data:`vibimpact.core.solver.SIMULATE_DEFAULTS`).
    model : Model, optional
        A user model; ``p`` is then its parameter vector (not with a System).
    **moved
        No setting: a keyword the solver settings took before (``rtol=``, ``method=``,
        ...) raises ``TypeError`` saying where it went, any other keyword the usual
        ``TypeError``.

    Returns
    -------
    Run
        ``strobe`` (periods + 1, n), ``impacts``, ``events``, counters and status.
        A blow-up returns ``status = DIVERGED`` with a reason and only the rows computed.

    Raises
    ------
    ValueError
        Naming the offending argument; also for more than
        :data:`vibimpact.base._limits.MAX_PERIODS` forcing periods (``periods + transient``),
        with the estimated time, and for arrays (``periods`` stroboscopic and
        ``periods * dense`` dense samples) over :data:`vibimpact.base._limits.MAX_BYTES`.
    TypeError
        For the keywords the solver settings took before (``rtol=``, ``method=``, ...),
        saying where they went.

    Examples
    --------
    >>> import vibimpact as vi
    >>> run = vi.simulate(vi.presets.get("fig8").replace(eta=1.185), periods=50,
    ...                   transient=300, solver=vi.SolverSettings(method="dop853"))
    >>> run.strobe.shape
    (51, 4)
    """
    if moved:
        raise _moved(moved)
    if isinstance(p, System):
        if model is not None:
            raise ValueError("model must be None with a System (it carries its model)")
        system = p
    else:
        # a Model, a model's name or None: System.__post_init__ resolves it
        system = System(p, model=model)  # type: ignore[arg-type]
    return system.simulate(periods, transient, state0, dense=dense, solver=solver)
