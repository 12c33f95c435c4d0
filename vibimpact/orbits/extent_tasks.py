"""The orbits' existence and stability intervals as engine tasks.

Continuing every found orbit in the forcing frequency (:func:`.extent.orbit_extent`) is
most of an orbit hunt's time and each orbit's continuation is independent of the
others', so they run as tasks of :mod:`vibimpact.engine`: one orbit a point, on local
worker processes or Dask, every finished orbit saved in a checkpoint and loaded again on
a resume.  An orbit's extent is a function of the orbit alone, so serial, parallel and
resumed hunts give the same bits.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ..engine.plan import STATES, Task
from .extent import orbit_extent
from .found import Extent

__all__ = ["ExtentPolicy", "extent_to_result", "result_to_extent", "run_extents"]


def extent_to_result(e: Extent) -> dict:
    """An :class:`Extent` as a checkpoint's point result (arrays, numbers, words)."""
    return dict(lo=float(e.lo), hi=float(e.hi), lo_reason=str(e.lo_reason),
                hi_reason=str(e.hi_reason),
                stable=np.array(e.stable, dtype=np.float64).reshape(-1, 2),
                values=np.asarray(e.values, dtype=np.float64),
                stable_points=np.asarray(e.stable_points, dtype=bool),
                impacts=np.asarray(e.impacts, dtype=np.int64),
                abs_max=np.asarray(e.abs_max, dtype=np.float64),
                same_impacts=np.array(e.same_impacts, dtype=np.float64))


def result_to_extent(r: dict) -> Extent:
    """The :class:`Extent` of :func:`extent_to_result`'s dict (as saved or loaded)."""
    stable = np.asarray(r["stable"], dtype=np.float64).reshape(-1, 2)
    same = np.asarray(r["same_impacts"], dtype=np.float64).ravel()
    return Extent(float(r["lo"]), float(r["hi"]), str(r["lo_reason"]), str(r["hi_reason"]),
                  tuple((float(a), float(b)) for a, b in stable),
                  np.asarray(r["values"], dtype=np.float64),
                  np.asarray(r["stable_points"], dtype=bool),
                  np.asarray(r["impacts"], dtype=np.int64),
                  np.asarray(r["abs_max"], dtype=np.float64),
                  (float(same[0]), float(same[1])) if same.size == 2 else
                  (math.nan, math.nan))


@dataclass(frozen=True, eq=False)
class ExtentPolicy:
    """The engine policy of the orbits' extents: position ``j`` continues orbit ``j``.

    Attributes
    ----------
    orbits : tuple of FoundOrbit
    window : float
    steps : Steps or None
    """

    orbits: tuple
    window: float
    steps: Any = None
    blocks: int = 1

    continued = False

    def seeds(self, p: Any, etas: np.ndarray, starts, state0) -> dict:
        return {a: state0 for a in starts}

    def run(self, task: Any, on_point=None) -> list:
        """The task's orbits in order (see :func:`vibimpact.engine.plan.run_task`)."""
        out = []
        for j in range(task.start, task.stop):
            res = task.done.get(j)
            if res is None:
                res = extent_to_result(orbit_extent(task.p, self.orbits[j], self.window,
                                                    self.steps))
                if on_point is not None:
                    on_point(task, j, res)
            out.append((j, res))
        return out


def run_extents(system, orbits, window, steps, execution) -> list[Extent]:
    """The extents of ``orbits`` (in order), as engine tasks on ``execution``.

    The checkpoint (``execution.checkpoint``) is keyed by the model, its parameters, the
    orbits' cycles, the window and the steps, so a resume never mixes two hunts.
    """
    from ..engine import progress as prog
    from ..engine.compute import compute
    from ..core.system import param_dict

    m = len(orbits)
    if m == 0:
        return []
    request = dict(kind="orbit extents", model=system.model.name,
                   params=param_dict(system), window=float(window),
                   steps=None if steps is None else asdict(steps),
                   orbits=[[int(o.period), np.asarray(o.cycle).tolist()] for o in orbits])
    store, done = execution.open_checkpoint("orbits", request, dict(
        rows=1, directions=[STATES], points=m))
    have = dict(done.get((0, STATES), {}))
    policy = ExtentPolicy(tuple(orbits), float(window), steps)
    etas = np.full(m, system.omega)
    tasks = [Task(0, STATES, j, j + 1, system, etas, None, None, policy, {}, None)
             for j in range(m) if j not in have]
    results = dict(have)

    def on_task(task, points):
        results.update(points)

    with prog.callback(execution.progress, len(tasks), "orbits") as report:
        if tasks:
            compute(tasks, execution.sweep_executor(len(tasks)), on_task, store=store,
                    progress=report, stream=True)
    return [result_to_extent(results[j]) for j in range(m)]
