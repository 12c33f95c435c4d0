"""Continuation policies: how the points of a task follow each other, and where each
one starts.

A task (:class:`vibimpact.engine.plan.Task`) is parameter points x starting states x a
policy.  Two policies cover what the package computes:

* :class:`Continuation`: a stream of parameter points swept with continuation, every
  point starting from the previous point's final state (the predictor of the period-1
  branch helping), cut into ``blocks`` seeded blocks that run independently (the
  eta sweeps of :func:`vibimpact.sweep` and the rows of :func:`vibimpact.map2d`).
* :class:`Independent`: every point starts from its own given state, no continuation
  (a sweep with ``continuation=False``; many starting states at one parameter point, as
  an attractor census asks, see :func:`vibimpact.engine.plan.plan_states`).

A policy is a small frozen object with two methods, ``seeds(p, etas, starts, state0)``
(the states at the block starts) and ``run(task, on_point)`` (the task's points in
order); the engine and its executors call nothing else, so a new policy needs no change
to them or to :mod:`vibimpact.points`.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Callable, Sequence

import numpy as np

from ..base import _limits
from ..base import _validate as _v
from ..analysis.classify import Label
from ..points.point import REGIME_CODES, analyse_point
from ..points.predict import extrapolate_branch
from ..core.run import Status
from ..core.system import to_system, with_frequency

PERIODIC = REGIME_CODES[Label.PERIODIC]

#: the predictor is used only when its step is at most this many times the branch's last
#: step (beyond a fold the extrapolated branch has no orbit to land on)
PREDICT_MAX_STEP = 2.0


def seed_states(p, etas, starts, state0, seed_periods):
    """States at the block starts from a cheap continuation pass over the grid ``etas``
    (sweep order): ``seed_periods`` forcing periods per point, no analyses."""
    seeds = {0: None if state0 is None else np.array(state0, dtype=np.float64)}
    x = seeds[0]
    last = max(starts[:-1])
    for i in range(1, last + 1):
        run = to_system(with_frequency(p, etas[i - 1])).simulate(
            periods=1, transient=seed_periods - 1, state0=x)
        x = run.final_state if run.status is Status.OK else None
        if i in starts[:-1]:
            seeds[i] = None if x is None else x.copy()
    return seeds


def predicted(branch, eta, m):
    """The continuation predictor's guess at ``eta`` from the last ``m`` period-1 points
    of ``branch`` (``[(eta, orbit_point)]``), or None (fewer points, or a step out of line
    with the branch's)."""
    if m < 2 or len(branch) < m:
        return None
    e, xs = zip(*branch[-m:])
    guess = extrapolate_branch(e, xs, eta)
    last = float(np.abs(xs[-1] - xs[-2]).max())
    if not np.all(np.isfinite(guess)) or \
            float(np.abs(guess - xs[-1]).max()) > PREDICT_MAX_STEP * last:
        return None
    return guess


@dataclass(frozen=True)
class Continuation:
    """Points swept in order, each starting from the previous point's final state.

    Parameters
    ----------
    blocks : int
        Contiguous blocks per stream; block ``b`` starts from the state a cheap serial
        pass reaches at its first point (``seed_periods`` forcing periods per grid point
        before it, no analyses), so blocks run independently.  The result depends on
        ``blocks`` (1 = pure serial continuation), never on where or in which order the
        blocks run.  At most :data:`vibimpact.base._limits.MAX_POINTS` (more blocks than
        points are as many blocks as points).
    seed_periods : int
        Forcing periods per grid point of the seeding pass.

    Raises
    ------
    ValueError
        Naming ``blocks`` or ``seed_periods``.
    """

    blocks: int = 16
    seed_periods: int = 10

    def __post_init__(self):
        object.__setattr__(self, "blocks",
                           _v.count("blocks", self.blocks, 1, _limits.MAX_POINTS))
        object.__setattr__(self, "seed_periods", _v.count(
            "seed_periods", self.seed_periods, 1, _limits.MAX_PERIODS))

    continued = True

    def seeds(self, p: Any, etas: np.ndarray, starts: Sequence[int],
              state0: np.ndarray | None) -> dict:
        """``{start: state}`` of the blocks beginning at ``starts`` (last entry: the
        stream's length)."""
        seeds = {0: state0}
        if any(a > 0 for a in starts[:-1]):
            seeds.update(seed_states(p, etas, starts, state0, self.seed_periods))
        return seeds

    def run(self, task: Any, on_point: Callable | None = None) -> list:
        """The points of ``task`` in order, with continuation (see
        :func:`vibimpact.engine.plan.run_task`)."""
        return _run(task, on_point, continued=True)


@dataclass(frozen=True)
class Independent:
    """Every point starts from its own given state (no continuation, no seeding pass).

    ``blocks`` only cuts a stream into tasks (which never changes a number; a sweep
    records it as it records a continuation's).
    """

    blocks: int = 16

    def __post_init__(self):
        object.__setattr__(self, "blocks",
                           _v.count("blocks", self.blocks, 1, _limits.MAX_POINTS))

    continued = False

    def seeds(self, p: Any, etas: np.ndarray, starts: Sequence[int],
              state0: np.ndarray | None) -> dict:
        return {a: state0 for a in starts}

    def run(self, task: Any, on_point: Callable | None = None) -> list:
        """The points of ``task`` in order, each from its own starting state."""
        return _run(task, on_point, continued=False)


def as_policy(continuation):
    """The policy of a ``continuation`` argument: a policy as is, True the default
    :class:`Continuation`, False :class:`Independent` (ValueError naming it
    otherwise)."""
    if isinstance(continuation, (Continuation, Independent)):
        return continuation
    if continuation is True or continuation is False:
        return Continuation() if continuation else Independent()
    if callable(getattr(continuation, "run", None)) and \
            callable(getattr(continuation, "seeds", None)):
        return continuation  # a user's policy
    raise _v.WrongType(f"continuation must be True, False, a vibimpact.Continuation or "
                       f"a vibimpact.Independent, got {type(continuation).__name__}")


def _run(task, on_point, continued):
    settings = task.settings
    out = []
    x = task.seed
    # (eta, orbit_point) of the latest consecutive period-1 points
    branch: list[tuple[float, Any]] = []
    for i in range(task.start, task.stop):
        res = task.done.get(i)
        if res is None:
            eta = float(task.etas[i])
            s0 = x if continued else task.state_at(i)
            guess = predicted(branch, eta, settings.predict) if continued else None
            res = analyse_point(with_frequency(task.p, eta), s0, settings,
                                guess=guess).as_dict()
            if on_point is not None:
                on_point(task, i, res)
        out.append((i, res))
        fs = res["final_state"]
        x = None if not np.all(np.isfinite(fs)) else np.asarray(fs)
        orbit = res.get("orbit_point")
        if res["regime"] == PERIODIC and res["period"] == 1 and orbit is not None \
                and np.all(np.isfinite(orbit)) and settings.predict > 1:
            branch = branch[-(settings.predict - 1):] + [(float(task.etas[i]), orbit)]
        else:
            branch = []
    return out
