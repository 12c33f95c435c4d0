"""Where the orbit hunt starts Newton's method: seed states and close returns.

Seeds are states at the start of a forcing period (``tau = 0 mod T``): the user's own
(census representatives, sweep final states, points of a run: :func:`seeds_from_dataset`)
and random ones drawn reproducibly in a documented box (:func:`random_seeds`).  From each
seed a short trajectory of stroboscopic points is integrated; the starts of Newton's
method for period ``n`` are its *close returns*, the points ``x_k`` where
``|P^n(x_k) - x_k| = |x_{k+n} - x_k|`` is smallest (:func:`close_returns`).  A chaotic or
transient trajectory passes close to the unstable periodic orbits embedded in it, and
lingers there; its near-recurrences of length ``n`` are good guesses of the period-``n``
orbits, stable or not (Auerbach et al. 1987; Lathrop & Kostelich 1989).

References
----------
.. [1] D. Auerbach, P. Cvitanovic, J.-P. Eckmann, G. Gunaratne, I. Procaccia,
   "Exploring chaotic motion through periodic orbits", Phys. Rev. Lett. 58 (1987)
   2387-2389.
.. [2] D. P. Lathrop, E. J. Kostelich, "Characterization of an experimental strange
   attractor by periodic orbits", Phys. Rev. A 40 (1989) 4028-4031.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..base import _validate as _v

if TYPE_CHECKING:  # names of the annotations only
    import xarray as xr
    from numpy.typing import ArrayLike

    from ..models import Model

__all__ = ["random_seeds", "seed_box", "seeds_from_dataset", "close_returns", "user_seeds"]


def seed_box(model: Model) -> tuple[np.ndarray, tuple[int, int] | None]:
    """The box random seeds are drawn in: the attractor census' documented box
    (:func:`vibimpact.census.starts.default_box`), one box for both.

    Every state variable is uniform in ``[-1, 1]``, except that for a model with a
    planar contact (two position coordinates, :attr:`vibimpact.Contact.positions`: the
    built-in rotor's ``X, Y``) those two are uniform in the unit disk (for the built-in
    rotor, the clearance).

    Parameters
    ----------
    model : Model

    Returns
    -------
    (ndarray, tuple or None)
        ``bounds`` of shape (d, 2) (low, high of each state variable), and the indices of
        the two positions drawn in the disk (None: none).
    """
    from ..census.starts import default_box

    box = default_box(model)
    return np.column_stack([box.lo, box.hi]), box.disk


def random_seeds(model: Model, count: int, seed: int = 0,
                 box: ArrayLike | None = None) -> np.ndarray:
    """Random states, reproducibly, drawn as the attractor census draws its starts
    (:func:`vibimpact.census.starts.random_starts`, ``numpy.random.default_rng(seed)``).

    Parameters
    ----------
    model : Model
        Its state layout and contact say the box (:func:`seed_box`).
    count : int
        Seeds drawn, ``>= 0``.
    seed : int
        Seed of the generator, ``>= 0``: the same seed gives the same states.
    box : array_like, shape (d, 2), optional
        Low and high of each state variable, uniform in each (replaces the default box,
        disk included).

    Returns
    -------
    ndarray, shape (count, d)

    Raises
    ------
    ValueError
        Naming ``random``, ``seed`` or ``box``.
    """
    from ..census.starts import MAX_STARTS, Box, default_box, random_starts

    count = _v.count("random", count, 0, MAX_STARTS)
    seed = _v.count("seed", seed, 0)
    d = len(model.state_names)
    if box is None:
        where = default_box(model)
    else:
        bounds = _v.numeric("box", box, "low and high of each state variable")
        if bounds.shape != (d, 2) or not np.all(np.isfinite(bounds)) or \
                np.any(bounds[:, 1] < bounds[:, 0]):
            raise ValueError(f"box must be ({d}, 2) finite (low, high) pairs with low <= "
                             f"high, got shape {bounds.shape}")
        where = Box(bounds[:, 0], bounds[:, 1])
    return random_starts(where, count, seed) if count else np.zeros((0, d))


def user_seeds(seeds: ArrayLike | None, d: int) -> np.ndarray:
    """The user's seeds as a (k, d) float array (none: shape (0, d)); ValueError naming
    ``seeds``."""
    if seeds is None:
        return np.zeros((0, d))
    x = _v.numeric("seeds", seeds, f"states of {d} numbers (an array of shape (k, {d}))")
    if x.ndim == 1:
        x = x[None, :]
    if x.ndim != 2 or x.shape[1] != d:
        raise ValueError(f"seeds must have shape (k, {d}) (states of {d} numbers), got "
                         f"shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError("seeds must be finite (no NaN or inf)")
    return x


def seeds_from_dataset(ds: xr.Dataset, n_state: int) -> np.ndarray:
    """Every state a dataset holds, as seeds.

    Each data variable whose last dimension is ``state`` of length ``n_state`` (a sweep's
    ``final_state``, a run's ``strobe``, an orbit file's ``orbit_point``) gives its rows;
    rows with a NaN are left out.  Of a census (:func:`vibimpact.attractors`) only its
    attractors' ``representative`` states are taken.

    Parameters
    ----------
    ds : xarray.Dataset
    n_state : int

    Returns
    -------
    ndarray, shape (k, n_state)
        In the order of the variables' names, then of the rows.

    Raises
    ------
    ValueError
        Naming ``ds`` when it holds no state.
    """
    _v.dataset("ds", ds)
    rows = []
    names = sorted(map(str, ds.data_vars))
    if ds.attrs.get("kind") == "census" and "representative" in ds:
        # a census: its attractors' states (not its starting states, nor the samples
        # along each attractor, which lead to the same orbits hundreds of times)
        names = ["representative"]
    for name in names:
        var = ds[name]
        if var.dims and var.dims[-1] == "state" and var.shape[-1] == n_state and \
                var.dtype.kind == "f":
            a = np.asarray(var.values, dtype=np.float64).reshape(-1, n_state)
            rows.append(a[np.all(np.isfinite(a), axis=1)])
    if not rows or sum(r.shape[0] for r in rows) == 0:
        raise ValueError(f"ds holds no state: no variable with a last dimension 'state' "
                         f"of {n_state} finite numbers")
    return np.concatenate(rows)


def close_returns(points: np.ndarray, n: int, starts: int, max_return: float) -> list[int]:
    """Indices ``k`` of the best close returns of period ``n`` along a trajectory.

    Parameters
    ----------
    points : ndarray, shape (m, d)
        Stroboscopic points ``x_0, x_1, ...`` of one trajectory.
    n : int
        Period looked for.
    starts : int
        Returns wanted at most.
    max_return : float
        Only returns with ``max |x_{k+n} - x_k| <= max_return * max(1, max |x_k|)``.

    Returns
    -------
    list of int
        Local minima of the return distance over ``k``, the smallest first (ties: the
        earlier ``k``), at least ``n`` apart (so not twice the same visit).
    """
    m = points.shape[0] - n
    if m <= 0:
        return []
    dist = np.abs(points[n:] - points[:m]).max(axis=1)
    scale = np.maximum(1.0, np.abs(points[:m]).max(axis=1))
    rel = dist / scale
    order = np.lexsort((np.arange(m), rel))
    out: list[int] = []
    for k in order:
        if rel[k] > max_return or len(out) >= starts:
            break
        if all(abs(int(k) - j) >= n for j in out):
            out.append(int(k))
    return out
