"""Starting states of an attractor census: random in a box, a grid, or the user's.

The default box (:func:`default_box`) is documented per model:

* a model whose contact declares two position states (a planar contact): those two
  positions uniform in the disk centred at 0 of the radius of the model's circular
  obstacle (:attr:`vibimpact.models.PlotSpec.circle`; radius 1 for a model that declares
  none; for the built-in rotor of eq. (5): inside its retainer's clearance, the contact
  circle ``R = 1``), every other state uniform in ``[-1, 1]``;
* any other model: every state uniform in ``[-1, 1]``.

Random starts are drawn from :func:`numpy.random.default_rng` seeded with ``seed``, so
the same ``(n, seed, box)`` gives the same states in every process, on the same CPU type
and library versions.
"""
from __future__ import annotations

import numpy as np

from ..base import _limits
from ..base import _validate as _v

__all__ = ["Box", "default_box", "random_starts", "grid_starts", "as_starts"]

#: most starts of one census point
MAX_STARTS = 1_000_000


class Box:
    """A box of starting states: ``lo <= x <= hi``, with an optional disk.

    Parameters
    ----------
    lo, hi : array_like, shape (d,)
    disk : tuple of int, optional
        Two different state indices (each in ``0 .. len(lo) - 1``) whose values are
        drawn uniformly in the disk of radius ``radius`` (centred at 0) instead of the
        square ``lo..hi``.
    radius : float
        Finite and > 0.

    Raises
    ------
    ValueError
        Naming ``lo``, ``hi``, ``disk`` or ``radius`` (a ``TypeError``, also a
        ``ValueError``, for a wrong type).
    """

    def __init__(self, lo, hi, disk=None, radius=1.0):
        self.lo = _v.numeric("lo", lo, "a vector of numbers").astype(np.float64)
        self.hi = _v.numeric("hi", hi, "a vector of numbers").astype(np.float64)
        if self.lo.shape != self.hi.shape or self.lo.ndim != 1 or self.lo.size == 0 or \
                not np.all(np.isfinite(self.lo)) or not np.all(np.isfinite(self.hi)) or \
                np.any(self.hi < self.lo):
            raise ValueError(f"lo and hi must be two finite vectors lo <= hi of one "
                             f"length, got {self.lo!r}, {self.hi!r}"[:300])
        self.disk = None if disk is None else _disk(disk, self.lo.size)
        self.radius = _v.positive("radius", radius)

    @property
    def scale(self) -> float:
        """The box's largest magnitude (the unit of the census' distances), >= 1e-12."""
        return max(float(np.abs(np.r_[self.lo, self.hi]).max()), 1e-12)

    def describe(self) -> str:
        """The box in words (stored with a census)."""
        parts = []
        for i, (a, b) in enumerate(zip(self.lo, self.hi)):
            if self.disk and i in self.disk:
                continue
            parts.append(f"x[{i}] in [{a:g}, {b:g}]")
        if self.disk:
            parts.insert(0, f"(x[{self.disk[0]}], x[{self.disk[1]}]) uniform in the disk "
                            f"of radius {self.radius:g}")
        return "; ".join(parts)


def _disk(disk, d):
    """``disk`` as two different state indices in ``0 .. d - 1`` (ValueError naming it)."""
    try:
        items = list(disk)
    except TypeError:
        raise _v.WrongType(f"disk must be two state indices, got {type(disk).__name__} "
                           f"{disk!r}"[:200]) from None
    if len(items) != 2:
        raise ValueError(f"disk must be two state indices, got {disk!r}"[:200])
    out = tuple(_v.count("disk", i, 0) for i in items)
    if out[0] == out[1] or max(out) >= d:
        raise ValueError(f"disk must be two different state indices in 0 .. {d - 1}, got "
                         f"{disk!r}"[:200])
    return out


def default_box(model) -> Box:
    """The documented default box of ``model`` (module docstring)."""
    d = len(model.state_names)
    contact = getattr(model, "contact", None)
    positions = tuple(getattr(contact, "positions", ())) if contact is not None else ()
    disk = positions if len(positions) == 2 else None
    circle = getattr(getattr(model, "plot", None), "circle", None)
    return Box(-np.ones(d), np.ones(d), disk=disk,
               radius=float(circle) if circle is not None else 1.0)


def random_starts(box: Box, n: int, seed: int = 0) -> np.ndarray:
    """``n`` states drawn uniformly in ``box`` with ``default_rng(seed)``.

    Returns
    -------
    ndarray, shape (n, d)
    """
    n = _v.count("starts", n, 1, MAX_STARTS)
    seed = _v.count("seed", seed, 0)
    rng = np.random.default_rng(seed)
    d = box.lo.size
    x = box.lo + (box.hi - box.lo) * rng.random((n, d))
    if box.disk is not None:
        r = box.radius * np.sqrt(rng.random(n))
        th = 2.0 * np.pi * rng.random(n)
        x[:, box.disk[0]] = r * np.cos(th)
        x[:, box.disk[1]] = r * np.sin(th)
    return x


def grid_starts(base, axes, ranges, shape) -> np.ndarray:
    """States on a regular grid in a plane of two state components.

    Parameters
    ----------
    base : array_like, shape (d,)
        Values of the other components.
    axes : tuple of int
        The two components varied (``(i, j)``: ``i`` along columns, ``j`` along rows).
    ranges : tuple of (float, float)
        ``((lo_i, hi_i), (lo_j, hi_j))``: cell centres span these, ends included.
    shape : tuple of int
        ``(rows, columns)``.

    Returns
    -------
    ndarray, shape (rows * columns, d)
        Row-major: start ``r * columns + c`` is at row ``r``, column ``c``.
    """
    base = np.asarray(base, dtype=np.float64)
    rows, cols = (int(v) for v in shape)
    _limits.check_points(rows * cols, name="grid")
    (x_lo, x_hi), (y_lo, y_hi) = ranges[0], ranges[1]
    xi = np.linspace(x_lo, x_hi, cols)
    yj = np.linspace(y_lo, y_hi, rows)
    out = np.tile(base, (rows * cols, 1))
    out[:, axes[0]] = np.tile(xi, rows)
    out[:, axes[1]] = np.repeat(yj, cols)
    return out


def as_starts(starts, d: int, box: Box, seed: int) -> np.ndarray:
    """The census' starting states from its ``starts`` argument: a count (random in
    ``box``) or an array of shape ``(m, d)`` (ValueError naming ``starts`` otherwise)."""
    if isinstance(starts, (bool, np.bool_)):
        raise _v.WrongType(f"starts must be a count or an array of states, got {starts!r}")
    if isinstance(starts, (int, np.integer)):
        return random_starts(box, int(starts), seed)
    arr = _v.numeric("starts", starts, f"a count or an array of shape (m, {d})")
    arr = np.array(arr, dtype=np.float64, ndmin=2)
    if arr.ndim != 2 or arr.shape[1] != d or arr.shape[0] < 1:
        raise ValueError(f"starts must have shape (m, {d}), got {np.shape(starts)}")
    if not np.all(np.isfinite(arr)):
        raise ValueError("starts must be finite")
    if arr.shape[0] > MAX_STARTS:
        raise ValueError(f"starts: at most {MAX_STARTS} states, got {arr.shape[0]}")
    return arr
