"""The words of the ``-v`` log (Python's ``logging``, logger ``vibimpact``): what a run
does, in one line per step, built only when the record is written.

``vibimpact -v COMMAND`` shows the INFO records (the request, each block as it finishes,
the files), ``-vv`` the DEBUG ones too (each point's transient and decision).
"""
from __future__ import annotations

from collections import Counter

import numpy as np

from ..points.logtext import OVER_ATTEMPTS, Lazy, kind, parameters

__all__ = ["BUDGET", "Lazy", "block", "parameters", "request"]

#: the plan's words on ``transient_max``: a budget that each attempt of a point gets
#: afresh (a point whose start from the neighbouring point's orbit fails, or lands on a
#: saddle, starts its plain transient over with the whole budget), so a point's
#: transient, counted over its attempts (:data:`OVER_ATTEMPTS`), may exceed it
BUDGET = "transient budget {} periods per attempt"


def request(rows, etas, dirs, tasks, settings):
    """One line on a planned request: grid, directions, blocks, points to compute."""
    etas = np.asarray(etas, dtype=float)
    span = (f"eta {etas.min():.6g}..{etas.max():.6g} ({etas.size} points)" if etas.size
            else "no eta")
    todo = sum(t.todo for t in tasks)
    loaded = sum(len(t.done) for t in tasks)
    analyses = ",".join(getattr(settings, "analyses", ()) or ())
    return (f"{len(rows)} row(s) x {span} x {'/'.join(dirs)}: {len(tasks)} blocks, "
            f"{todo} points to compute, {loaded} loaded from the checkpoint; analyses "
            f"{analyses or '-'}, {BUDGET.format(getattr(settings, 'transient_max', '?'))}")


def block(task, results, k, n, elapsed):
    """One line on a finished block: where, its points, what they are, their
    transients (each counted over all of the point's attempts, :data:`OVER_ATTEMPTS`)."""
    etas = [float(task.etas[i]) for i, _ in results]
    where = (f"row {task.row} {task.direction}, eta {min(etas):.6g}..{max(etas):.6g}"
             if etas else f"row {task.row} {task.direction}")
    res = [r for _, r in results if isinstance(r, dict) and "regime" in r]  # a point's
    kinds = Counter(kind(r) for r in res)
    trans = [int(r.get("transient", 0)) for r in res]
    computed = len(results) - len(task.done)
    text = ": " + ", ".join(f"{c} {w}" for w, c in kinds.most_common()) if res else ""
    settle = (f"; transients {min(trans)}..{max(trans)} periods {OVER_ATTEMPTS}"
              if trans else "")
    return (f"block {k}/{n} done ({where}): {len(results)} points ({computed} computed)"
            f"{text}{settle}; {elapsed:.1f} s since the start")
