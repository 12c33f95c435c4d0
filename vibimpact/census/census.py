"""The attractor census: every attractor at a parameter point, with its basin fraction.

:func:`attractors` takes ``N`` starting states (random in a documented box, a grid, or
the user's; :mod:`.starts`) at every point of an eta grid and finds where each goes
(:func:`vibimpact.census.reach.reach`), in *rounds* of starts run as engine tasks
(:mod:`vibimpact.engine`): round 0 is the first 16 starts, decided by the settling
evidence alone; every later round (the next 48, 192, 768, ... starts) is decided against
the attractors the earlier rounds found, so most starts stop as soon as they enter a
known attractor.  The rounds are fixed by ``N`` alone, and a start's result depends only
on its state and on the library before its round, so serial, parallel, reordered and
resumed runs give the same bits.

Found attractors are deduplicated (:func:`vibimpact.census.library.same`), each gets
its label (period, impacts per period, contact arcs), its Floquet multipliers (periodic
orbits, from the shooting of the settling evidence) or largest Lyapunov exponent, a
representative state and its basin fraction ``k / N`` with the binomial standard error
``sqrt(f (1 - f) / N)``; every start gets its attractor's index.  Over an eta grid,
attractors are matched from one point to the next (:func:`vibimpact.census.dataset.
continue_attractors`, global continuation) so that one attractor keeps one ``global_id``.
"""
from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from ..base import _validate as _v
from ..engine.execution import as_execution
from ..engine.plan import STATES, Task, block_starts
from ..points.point import REGIME_CODES
from ..analysis.classify import Label
from ..core.system import System, as_system, param_dict, with_frequency
from .library import Attractor, cloud_radius, same
from .reach import DIVERGED, ENTERED, ESCAPED_LABEL, FAILED, FAILED_LABEL, \
    CensusRound, CensusSettings
from .starts import Box, as_starts, default_box
from .unseen import unseen_mass

if TYPE_CHECKING:  # names of the annotations only
    import xarray as xr
    from numpy.typing import ArrayLike

    from ..engine.execution import Execution

__all__ = ["attractors", "rounds", "census_points", "census_etas"]

#: starts of round 0 (decided by the settling evidence alone); round k > 0 ends at
#: ``PILOT * 4**k`` starts
PILOT = 16
#: starts per engine task
TASK_STARTS = 64


def rounds(n: int) -> list[tuple[int, int]]:
    """The rounds ``[(start, stop)]`` of ``n`` starts: 0..16, 16..64, 64..256, ..."""
    out, a, b = [], 0, min(n, PILOT)
    while a < n:
        out.append((a, b))
        a, b = b, min(n, b * 4)
    return out


def _attractor(res, position, cs, scale):
    """The library entry of an analysed start's result."""
    cloud = np.asarray(res["cloud"], dtype=np.float64)
    n = int(res["period"]) if int(res["regime"]) == REGIME_CODES[Label.PERIODIC] else 0
    if n > 0:
        return Attractor(cloud, n, cs.radius * scale, max(cs.hold, n), res, position)
    return Attractor(cloud, 0, cloud_radius(cloud, cs.radius * scale), cs.hold_chaotic,
                     res, position)


def census_points(results, library, cs, scale):
    """Labels of one round's results, and the library grown by what they found.

    Parameters
    ----------
    results : list of (int, dict)
        ``(position, reach result)`` in position order.
    library : list of Attractor
        Known before the round (append-only: indices stay).

    Returns
    -------
    labels : dict
        ``{position: attractor index}``; :data:`ESCAPED_LABEL` for a start whose
        motion diverged, :data:`FAILED_LABEL` for one whose integration failed.
    library : list of Attractor
    """
    library = list(library)
    labels = {}
    for i, res in results:
        how = int(res["decided_by"])
        if how == ENTERED:
            labels[i] = int(res["entered"])
        elif how == DIVERGED:
            labels[i] = ESCAPED_LABEL
        elif how == FAILED:
            labels[i] = FAILED_LABEL
        else:
            cand = _attractor(res, i, cs, scale)
            for k, att in enumerate(library):
                if same(cand, att, cs.dedup_tol * scale):
                    labels[i] = k
                    break
            else:
                library.append(cand)
                labels[i] = len(library) - 1
    return labels, separated(library)


def separated(library):
    """``library`` with every radius at most half the distance from the attractor's
    cloud to the nearest other cloud (two radii never overlap, so a trajectory is never
    counted on two attractors at once); a function of the library alone."""
    out = []
    for a, att in enumerate(library):
        gap = min((float(other.distances(att.cloud).min())
                   for b, other in enumerate(library) if b != a), default=np.inf)
        radius = min(att.radius, gap / 2.0)
        out.append(att if radius == att.radius else replace(att, radius=radius))
    return out


def _tasks(p, etas, states, libraries, cs, span, done):
    policy = CensusRound(tuple(tuple(lib) for lib in libraries), cs)
    a, b = span
    n = states.shape[0]
    cuts = block_starts(b - a, max(1, -(-(b - a) // TASK_STARTS)))
    tasks = []
    for row, eta in enumerate(etas):
        have = done.get((row, STATES), {})
        for lo, hi in zip(cuts[:-1], cuts[1:]):
            lo, hi = a + lo, a + hi
            if all(i in have for i in range(lo, hi)):
                continue
            tasks.append(Task(row, STATES, lo, hi, p, np.full(n, float(eta)), cs, None,
                              policy, {i: have[i] for i in range(lo, hi) if i in have},
                              states))
    return tasks


def census_etas(system, eta) -> np.ndarray:
    """The etas of a census: ``eta`` (a number or a grid) checked for the solver's range,
    or the system's own forcing frequency; ValueError naming ``eta`` or that frequency."""
    from ..sweeps.sweep import check_frequency, check_grid

    if eta is None:
        name = system.model.param_names[system.model.omega_index]
        etas = np.array([system.omega])
        check_frequency(etas, f"system's forcing frequency {name}")
        return etas
    return check_grid(eta if np.ndim(eta) else [eta])


def attractors(system: System, eta: float | ArrayLike | None = None,
               starts: int | ArrayLike = 400, *, seed: int = 0, box: Box | None = None,
               settings: CensusSettings | None = None,
               until_unseen: float | None = None,
               execution: Execution | None = None) -> xr.Dataset:
    """Every attractor at each point of an eta grid, with basin fractions.

    Parameters
    ----------
    system : System
        The model and parameters (its forcing frequency is replaced by each ``eta``).
    eta : float or array_like, optional
        The forcing frequencies (an increasing grid); the system's own by default.
    starts : int or array_like, shape (N, d)
        N random states in ``box`` (seeded by ``seed``), or the states themselves (a grid:
        :func:`vibimpact.census.starts.grid_starts`).  The same states at every eta.
    seed : int
    box : Box, optional
        Where random starts are drawn (:func:`vibimpact.census.starts.default_box`
        by default: the two positions of a planar contact in the unit disk, everything
        else in ``[-1, 1]``); its scale is the unit of the census' distances.
    settings : CensusSettings, optional
    until_unseen : float, optional
        Stop adding rounds of starts as soon as the unseen basin mass
        (:func:`vibimpact.census.unseen.unseen_mass`: the larger of the Good–Turing
        estimate and the resolution of the starts so far) is at most this level, in
        ``(0, 1)``, at every eta; ``starts`` (a count) is then the most starts.  The
        states are those of ``starts`` starts, cut after the last round run, so the
        result depends on ``starts``, ``seed`` and the level, never on the workers.
    execution : Execution, optional
        Workers, Dask, checkpoint and resume (none of which changes a number).

    Returns
    -------
    xarray.Dataset
        Dimensions ``eta``, ``start``, ``attractor``, ``state``, ``sample``,
        ``multiplier``: see :func:`vibimpact.census.dataset.census_dataset`; per eta
        ``unseen`` (the basin mass the census may have missed), ``unseen_good_turing``
        and ``singletons``.

    Raises
    ------
    ValueError
        Naming the argument.

    Examples
    --------
    >>> import vibimpact as vi
    >>> system = vi.System(vi.presets.get("fig11"))
    >>> census = vi.attractors(system.with_params(eta=1.06), starts=64)  # doctest: +SKIP
    >>> census.fraction.sel(eta=1.06).values  # doctest: +SKIP
    """
    from ..engine import progress as prog
    from ..engine.compute import compute
    from .dataset import census_dataset

    system = as_system(system)
    settings = CensusSettings() if settings is None else settings
    if not isinstance(settings, CensusSettings):
        raise _v.WrongType(f"settings must be a vibimpact.census.CensusSettings, got "
                           f"{type(settings).__name__}")
    if box is None:
        box = default_box(system.model)
    elif not isinstance(box, Box):
        raise _v.WrongType(f"box must be a vibimpact.census.Box, got "
                           f"{type(box).__name__}")
    d = system.n_state
    if box.lo.size != d:
        raise ValueError(f"box must have {d} components, got {box.lo.size}")
    seed = _v.count("seed", seed, 0)
    etas = census_etas(system, eta)
    states = as_starts(starts, d, box, seed)
    level = _until(until_unseen, starts)
    execution = as_execution(execution)
    scale = box.scale
    n = states.shape[0]
    request = dict(kind="census", params=param_dict(with_frequency(system, 1.0)),
                   model=system.model.name, eta=etas.tolist(),
                   starts=states.tolist() if n <= 64 else
                   [int(n), float(np.abs(states).sum()), states[:4].tolist()],
                   settings={k: v for k, v in settings.as_attrs().items()}, box=box.describe(),
                   **({} if level is None else dict(until_unseen=level)))
    store, done = execution.open_checkpoint("census", request, dict(
        rows=int(etas.size), directions=[STATES], points=int(n)))
    libraries: list[list] = [[] for _ in etas]
    labels = [np.full(n, -2, dtype=np.int64) for _ in etas]
    results = [[None] * n for _ in etas]
    todo = sum(1 for r in range(etas.size) for i in range(n)
               if i not in done.get((r, STATES), {}))
    with prog.callback(execution.progress, todo, "census") as report:
        for span in rounds(n):
            tasks = _tasks(system, etas, states, libraries, settings, span, done)
            got = {r: dict(done.get((r, STATES), {})) for r in range(etas.size)}

            def on_task(task, points, got=got):
                got[task.row].update(points)

            if tasks:
                compute(tasks, execution.sweep_executor(len(tasks)), on_task,
                        store=store, progress=report, stream=False)
            for r in range(etas.size):
                rows = [(i, got[r][i]) for i in range(*span)]
                lab, libraries[r] = census_points(rows, libraries[r], settings, scale)
                for i, res in rows:
                    results[r][i] = res
                    labels[r][i] = lab[i]
            if level is not None and seen_enough(labels, span[1], level):
                n = span[1]
                break
    states, labels = states[:n], [lab[:n] for lab in labels]
    results = [row[:n] for row in results]
    return census_dataset(system, etas, states, box, seed, settings, libraries, labels,
                          results, until_unseen=level)


def _until(level, starts):
    """``until_unseen`` checked (None, or a level in (0, 1) with a count of starts)."""
    if level is None:
        return None
    if isinstance(level, (bool, np.bool_)) or not isinstance(
            level, (int, float, np.integer, np.floating)):
        raise _v.WrongType(f"until_unseen must be a number in (0, 1), got {level!r}"[:200])
    if not 0.0 < float(level) < 1.0:
        raise ValueError(f"until_unseen must be in (0, 1), got {level!r}")
    if not isinstance(starts, (int, np.integer)) or isinstance(starts, (bool, np.bool_)):
        raise ValueError("until_unseen needs starts as a count (the most starts), not "
                         "an array of states")
    return float(level)


def point_counts(label) -> np.ndarray:
    """Starts per attractor of one eta's labels (the diverged starts as one more class;
    failed and not yet run starts on none)."""
    lab = np.asarray(label)
    found = np.bincount(lab[lab >= 0]) if np.any(lab >= 0) else np.zeros(0, np.int64)
    return np.r_[found, np.count_nonzero(lab == ESCAPED_LABEL)]


def seen_enough(labels, n, level) -> bool:
    """Whether the first ``n`` starts leave at most ``level`` unseen at every eta."""
    return all(unseen_mass(point_counts(lab[:n]), n)[0] <= level for lab in labels)
