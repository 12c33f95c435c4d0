"""The plan: a sweep or map request cut into independent tasks, and how a task runs.

A request is a stack of *rows* (one :class:`~vibimpact.Params` each; a sweep is the
one-row case of a map), every row swept along eta in one or two *directions*: each
``(row, direction)`` is a *stream* of points with continuation, every point starting from
the previous point's final state.  A stream is cut into ``blocks`` contiguous blocks; a
block starts from a *seed*, the state a cheap serial pass (:func:`seed_states`) reaches
at its first point, so blocks do not depend on each other.  A :class:`Task` is one block
with its seed: what an executor runs.  Tasks are pure functions of their fields, so which
process runs them, in which order and in which group never changes a number.

Positions along a stream are in sweep order (position ``i`` of a "down" stream is grid
point ``n - 1 - i``).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..analysis.classify import DecisionRule, Label
from ..run import Status
from ..points.point import REGIME_CODES, SweepSettings, analyse_point
from ..points.predict import extrapolate_branch
from ..system import to_system, with_frequency
from . import warmup

PERIODIC = REGIME_CODES[Label.PERIODIC]

#: the predictor is used only when its step is at most this many times the branch's last
#: step (beyond a fold the extrapolated branch has no orbit to land on)
PREDICT_MAX_STEP = 2.0


@dataclass(frozen=True, eq=False)
class Task:
    """One block of one stream: positions ``start .. stop - 1`` in sweep order.

    Attributes
    ----------
    row : int
        Index of the row (0 for a sweep).
    direction : {"up", "down"}
    start, stop : int
        The block's positions in sweep order.
    p : Params
        The row's parameters (``eta`` is set per point).
    etas : ndarray
        The row's grid in sweep order.
    settings : SweepSettings
    seed : ndarray or None
        State at ``start`` (None: rest).
    fixed : bool
        Every point starts from ``seed`` (no continuation).
    done : dict
        ``{position: result}`` loaded from a checkpoint: not recomputed.
    """

    row: int
    direction: str
    start: int
    stop: int
    p: object
    etas: np.ndarray
    settings: object
    seed: np.ndarray | None
    fixed: bool
    done: dict = field(default_factory=dict)

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


def plan(rows, etas, dirs, settings, state0, *, blocks=1, continuation=True,
         seed_periods=10, done=None):
    """The tasks of a request.

    Parameters
    ----------
    rows : sequence of Params
        One per row.
    etas : ndarray
        The increasing grid.
    dirs : tuple of str
        Directions of every row's streams.
    settings : SweepSettings
    state0 : ndarray or None
        State at the first point of every stream.
    blocks : int
        Blocks per stream.
    continuation : bool
        False: every point starts from ``state0`` (no seeds needed).
    seed_periods : int
    done : dict, optional
        ``{(row, direction): {position: result}}`` loaded from a checkpoint.

    Returns
    -------
    list of Task
        In row, direction, block order; blocks whose points are all in ``done`` are left
        out (and need no seed).
    """
    warmup.start()  # the points' array routines compile on another core meanwhile
    done = done or {}
    n = etas.size
    starts = block_starts(n, blocks)
    tasks = []
    for r, p in enumerate(rows):
        for d in dirs:
            order = sweep_order(etas, d)
            have = done.get((r, d), {})
            spans = [(a, b) for a, b in zip(starts[:-1], starts[1:])
                     if any(i not in have for i in range(a, b))]
            if not continuation:
                seeds = {a: state0 for a in starts}
            else:
                seeds = {0: state0}
                if any(a > 0 for a, _ in spans):
                    seeds.update(seed_states(p, order, starts, state0, seed_periods))
            for a, b in spans:
                tasks.append(Task(r, d, a, b, p, order, settings, seeds.get(a),
                                  not continuation,
                                  {i: have[i] for i in range(a, b) if i in have}))
    return tasks


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


def run_task(task, on_point=None):
    """Compute one task's points in order.

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
    settings = task.settings
    out = []
    x = task.seed
    branch = []  # (eta, orbit_point) of the latest consecutive period-1 points
    for i in range(task.start, task.stop):
        res = task.done.get(i)
        if res is None:
            eta = float(task.etas[i])
            s0 = task.seed if task.fixed else x
            guess = None if task.fixed else predicted(branch, eta, settings.predict)
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
