"""The plan: a request cut into independent tasks, and how a task runs.

A task is parameter points x starting states x a continuation policy
(:mod:`vibimpact.engine.policy`).  Two kinds of request are planned here:

* :func:`plan`: a stack of *rows* (one :class:`~vibimpact.Params` each; a sweep is the
  one-row case of a map), every row swept along eta in one or two *directions*: each
  ``(row, direction)`` is a *stream* of points.  With the :class:`~vibimpact.engine.
  policy.Continuation` policy every point starts from the previous point's final state
  and the stream is cut into ``blocks`` contiguous blocks, each starting from a *seed*,
  the state a cheap serial pass reaches at its first point, so blocks do not depend on
  each other; with :class:`~vibimpact.engine.policy.Independent` every point starts from
  ``state0``.
* :func:`plan_states`: many starting states at one parameter point (an attractor
  census), every state its own point, with the :class:`~vibimpact.engine.policy.
  Independent` policy.

A :class:`Task` is one block: what an executor runs (:func:`run_task`).  Tasks are pure
functions of their fields, so which process runs them, in which order and in which group
never changes a number.

Positions along a stream are in sweep order (position ``i`` of a "down" stream is grid
point ``n - 1 - i``).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from ..analysis.classify import DecisionRule
from ..points.point import SweepSettings
from . import warmup
from .logtext import Lazy, parameters, request
from .policy import Continuation, Independent

log = logging.getLogger(__name__)

#: the direction of the streams of :func:`plan_states` (positions are states, not a
#: sweep of eta)
STATES = "states"


@dataclass(frozen=True, eq=False)
class Task:
    """One block of one stream: positions ``start .. stop - 1``.

    Attributes
    ----------
    row : int
        Index of the row (0 for a sweep).
    direction : {"up", "down", "states"}
    start, stop : int
        The block's positions (sweep order for "up" and "down").
    p : Params or System
        The row's parameters (the forcing frequency is set per point).
    etas : ndarray
        The forcing frequency at every position of the stream.
    settings : SweepSettings
    seed : ndarray or None
        State at ``start`` (None: rest).
    policy : Continuation, Independent or a user's policy
        How the points follow each other (:mod:`vibimpact.engine.policy`).
    done : dict
        ``{position: result}`` loaded from a checkpoint: not recomputed.
    states : ndarray or None
        Shape ``(positions, d)``: the starting state of every position of the stream,
        for a policy without continuation (None: every point starts from ``seed``).
    """

    row: int
    direction: str
    start: int
    stop: int
    p: object
    etas: np.ndarray
    settings: object
    seed: np.ndarray | None
    policy: object
    done: dict = field(default_factory=dict)
    states: np.ndarray | None = None

    @property
    def stream(self):
        """``(row, direction)``."""
        return (self.row, self.direction)

    @property
    def size(self):
        return self.stop - self.start

    @property
    def todo(self):
        """Points this task computes (the others are loaded)."""
        return self.size - len(self.done)

    @property
    def fixed(self):
        """True when every point starts from its own given state (no continuation)."""
        return not getattr(self.policy, "continued", True)

    def state_at(self, position):
        """The given starting state of ``position`` (policies without continuation)."""
        return self.seed if self.states is None else self.states[position]


def settings_from_attrs(attrs):
    """The :class:`SweepSettings` whose :meth:`~SweepSettings.as_attrs` is ``attrs`` (as
    a dataset or a checkpoint records them); TypeError for unknown fields."""
    rule = {k[5:]: v for k, v in attrs.items() if k.startswith("rule_")}
    rest = {k: v for k, v in attrs.items() if not k.startswith("rule_")}
    rest["analyses"] = tuple(str(rest.get("analyses", "")).split(","))
    return SweepSettings(**{**rest, "rule": DecisionRule(**rule)})


def directions(direction):
    """The streams' directions of a request's ``direction`` ("up", "down" or "both")."""
    return ("up", "down") if direction == "both" else (direction,)


def sweep_order(etas, direction):
    """The grid in the order a stream of ``direction`` sweeps it."""
    return etas if direction == "up" else etas[::-1]


def grid_index(n, direction, positions):
    """Grid indices of sweep-order ``positions`` of a stream of ``n`` points."""
    positions = np.asarray(positions, dtype=np.int64)
    return positions if direction == "up" else n - 1 - positions


def block_starts(n, blocks):
    """First positions of ``blocks`` contiguous, nearly equal blocks of ``n`` points, and
    ``n`` at the end."""
    blocks = max(1, min(blocks, n))
    return [int(round(b * n / blocks)) for b in range(blocks)] + [n]


def plan(rows, etas, dirs, settings, state0, policy=None, *, done=None):
    """The tasks of a request of rows swept along eta.

    Parameters
    ----------
    rows : sequence of Params or System
        One per row.
    etas : ndarray
        The increasing grid.
    dirs : tuple of str
        Directions of every row's streams.
    settings : SweepSettings
    state0 : ndarray or None
        State at the first point of every stream (every point's, without continuation).
    policy : Continuation, Independent or a user's policy
        :class:`~vibimpact.engine.policy.Continuation` by default (16 blocks).
    done : dict, optional
        ``{(row, direction): {position: result}}`` loaded from a checkpoint.

    Returns
    -------
    list of Task
        In row, direction, block order; blocks whose points are all in ``done`` are left
        out (and need no seed).
    """
    warmup.start()  # the points' array routines compile on another core meanwhile
    policy = Continuation() if policy is None else policy
    done = done or {}
    n = etas.size
    starts = block_starts(n, policy.blocks)
    tasks = []
    for r, p in enumerate(rows):
        for d in dirs:
            order = sweep_order(etas, d)
            have = done.get((r, d), {})
            spans = [(a, b) for a, b in zip(starts[:-1], starts[1:])
                     if any(i not in have for i in range(a, b))]
            if spans and any(a > 0 for a, _ in spans):
                seeds = policy.seeds(p, order, starts, state0)
            else:
                seeds = {a: state0 for a in starts}
            for a, b in spans:
                tasks.append(Task(r, d, a, b, p, order, settings, seeds.get(a), policy,
                                  {i: have[i] for i in range(a, b) if i in have}))
    log.info("parameters%s: %s", " of row 0" if len(rows) > 1 else "",
             Lazy(parameters, rows[0]) if len(rows) else "none")
    log.info("plan: %s", Lazy(request, rows, etas, dirs, tasks, settings))
    return tasks


def plan_states(p, eta, states, settings, *, blocks=1, done=None):
    """The tasks of many starting states at one parameter point (an attractor census).

    Every state is its own point (policy :class:`~vibimpact.engine.policy.Independent`),
    position ``k`` starting from ``states[k]``; the stream ``(0, "states")`` is cut into
    ``blocks`` tasks, which never changes a number.

    Parameters
    ----------
    p : Params or System
    eta : float
        The forcing frequency of every point.
    states : array_like, shape (m, d)
    settings : SweepSettings
    blocks : int
    done : dict, optional
        ``{position: result}`` loaded from a checkpoint.

    Returns
    -------
    list of Task
    """
    warmup.start()
    states = np.array(states, dtype=np.float64, ndmin=2)
    m = states.shape[0]
    etas = np.full(m, float(eta))
    policy = Independent(blocks=blocks)
    starts = block_starts(m, policy.blocks)
    have = done or {}
    tasks = [Task(0, STATES, a, b, p, etas, settings, states[a], policy,
                  {i: have[i] for i in range(a, b) if i in have}, states)
             for a, b in zip(starts[:-1], starts[1:])
             if any(i not in have for i in range(a, b))]
    log.info("parameters: %s", Lazy(parameters, p))
    log.info("plan: %d starting states at eta %.6g in %d blocks, %d to compute", m,
             float(eta), len(tasks), sum(t.todo for t in tasks))
    return tasks


def run_task(task, on_point=None):
    """Compute one task's points in order (its policy decides how they follow).

    Parameters
    ----------
    task : Task
    on_point : callable, optional
        ``on_point(task, position, result)`` after every point computed here (not for the
        points loaded from ``task.done``).

    Returns
    -------
    list of (int, dict)
        ``(position, result)`` of every point of the block, loaded ones included.
    """
    return task.policy.run(task, on_point)


def run_job(job, on_point=None):
    """Run a group of tasks one after the other: ``[(task index in job, results)]``."""
    return [run_task(task, on_point) for task in job]


def group(tasks, task_points, slots=None):
    """Tasks grouped into jobs of at least ``task_points`` points (whole tasks, in order).

    ``slots`` (worker threads of a cluster) caps the group size so that every worker gets
    at least two jobs; grouping never changes a number.
    """
    if not tasks:
        return []
    size = max(t.size for t in tasks)
    per = max(1, -(-task_points // max(1, size)))
    if slots:
        per = min(per, max(1, len(tasks) // (2 * slots)))
    return [tasks[k:k + per] for k in range(0, len(tasks), per)]
