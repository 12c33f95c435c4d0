"""Basins of attraction in a plane of states, and how tangled their boundary is.

:func:`basins` runs an attractor census (:func:`vibimpact.census.attractors`) whose
starts are a regular grid of cells in a plane of two state components (the others held
at ``base``, zero by default: in the built-in rotor's X, Y plane, starts at rest), and
returns the image of the attractor each cell reaches with the census' attractor table
and the boundary measures of :func:`boundary_measures`:

* the *boundary fraction*: the share of cells with a 4-neighbour (up, down, left,
  right) of another label;
* the *basin entropy* ``Sb`` and the *boundary basin entropy* ``Sbb`` of Daza et al.
  (2016): the image is cut into boxes of ``eps x eps`` cells; box ``i`` holding the
  attractors ``j`` in proportions ``p_ij`` has the Gibbs entropy
  ``S_i = -sum_j p_ij log p_ij``; ``Sb`` is the mean of ``S_i`` over all ``N`` boxes,
  ``Sbb`` its mean over the ``N_b`` boxes that hold more than one attractor.  ``Sbb >
  log 2`` is a sufficient condition for a fractal boundary (the "log 2 criterion").

References
----------
.. [1] A. Daza, A. Wagemakers, B. Georgeot, D. Guery-Odelin, M. A. F. Sanjuan, "Basin
   entropy: a new tool to analyze uncertainty in dynamical systems", Sci. Rep. 6, 31416
   (2016).
.. [2] G. Datseris, A. Wagemakers, "Effortless estimation of basins of attraction",
   Chaos 32, 023104 (2022).
"""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from typing import TYPE_CHECKING

from ..base import _validate as _v
from ..core.system import as_system
from .reach import DECIDED_FLAGS
from .starts import default_box, grid_starts

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

    from ..engine.execution import Execution
    from ..core.system import System
    from .reach import CensusSettings

__all__ = ["basins", "boundary_cells", "boundary_measures", "plane_axes", "write_basins",
           "started_cells", "EPS", "NOT_STARTED"]

#: side of the boxes of the basin entropy, in cells (Daza et al. 2016 use 5)
EPS = 5
#: the basin label of a cell not started: its start lies in penetration of the model's
#: contact (the built-in rotor's cells outside the retainer clearance, ``R > 1``)
NOT_STARTED = -2
#: its ``decided_by`` flag (after the census' own, :data:`.reach.DECIDED_FLAGS`)
NOT_STARTED_FLAG = 4
#: the attractor-table variables of the census carried into a basins dataset
_TABLE = ("fraction", "fraction_se", "regime", "period", "impacts_per_period", "n_arcs",
          "lyapunov", "floquet_abs_max", "multiplier_re", "multiplier_im",
          "representative", "samples", "name", "found_by", "global_id", "failed",
          "failed_fraction", "failure")


def default_plane(model) -> tuple[str, str]:
    """The plane of a model's basins when none is asked for: the states its XY plots draw
    (:class:`vibimpact.models.PlotSpec`), else its first two."""
    plot = getattr(model, "plot", None)
    return tuple(plot.xy) if plot is not None else tuple(model.state_names[:2])


def plane_axes(model, plane) -> tuple[int, int]:
    """The state indices of the two names of ``plane`` (None: :func:`default_plane`).

    A name is a state name of the model (``"X"``, ``"dY"``, ``"x"``), matched exactly or
    else ignoring case when that is unique; ``"X'"`` (a prime) stands for ``"dX"``.

    Raises
    ------
    ValueError
        Naming ``plane``: not two names, an unknown name, or the same state twice.
    """
    names = list(model.state_names)
    if plane is None:
        plane = default_plane(model)
    if isinstance(plane, str):
        plane = [p for p in plane.split(",")]
    plane = list(plane) if isinstance(plane, (list, tuple)) else None
    if plane is None or len(plane) != 2 or not all(isinstance(p, str) for p in plane):
        raise ValueError(f"plane must be two state names of the model ({', '.join(names)})"
                         f", got {plane!r}")
    out = []
    for text in plane:
        key = text.strip()
        if key.endswith("'"):
            key = "d" + key[:-1]
        if key in names:
            out.append(names.index(key))
            continue
        folded = [i for i, n in enumerate(names) if n.lower() == key.lower()]
        if len(folded) != 1:
            raise ValueError(f"plane: unknown state {text!r}; the model's states are "
                             f"{', '.join(names)} (X' stands for dX)")
        out.append(folded[0])
    if out[0] == out[1]:
        raise ValueError(f"plane must name two different states, got {plane!r}")
    return out[0], out[1]


def _grid(grid):
    if isinstance(grid, (int, np.integer)) and not isinstance(grid, (bool, np.bool_)):
        grid = (grid, grid)
    if not isinstance(grid, (tuple, list)) or len(grid) != 2:
        raise ValueError(f"grid must be (columns, rows): two counts >= 2, got {grid!r}")
    return tuple(_v.count("grid", g, 2) for g in grid)


def _ranges(ranges, axes, box, cells=None):
    """The plane's two ``(lo, hi)`` ranges (the box's, by default); ValueError naming
    ``ranges`` unless each is finite with ``lo < hi``, a finite width, and wide enough
    for its ``cells`` centres to differ in floats."""
    if ranges is None:
        return tuple((float(box.lo[i]), float(box.hi[i])) for i in axes)
    try:
        out = tuple((float(a), float(b)) for a, b in ranges)
    except (TypeError, ValueError):
        out = ()
    if len(out) != 2 or not all(math.isfinite(a) and math.isfinite(b) and a < b
                                and math.isfinite(b - a) for a, b in out):
        raise ValueError(f"ranges must be ((lo, hi), (lo, hi)) with finite lo < hi and a "
                         f"finite hi - lo, one per plane variable, got {ranges!r}")
    for (lo, hi), n in zip(out, cells or ()):
        if (hi - lo) / (n - 1) < 4.0 * max(math.ulp(lo), math.ulp(hi)):
            raise ValueError(f"ranges: ({lo!r}, {hi!r}) is too narrow for {n} cells: "
                             f"their centres would coincide in floats")
    return out


def started_cells(system, starts) -> np.ndarray:
    """Which starts a basin image integrates: those not in penetration of the model's
    contact (:class:`vibimpact.models.Contact`'s ``penetration`` > 0: the built-in
    rotor's states outside the retainer clearance, ``R > 1``, where it cannot be); every
    start of a model that declares no contact.

    Parameters
    ----------
    system : System
    starts : ndarray, shape (m, d)

    Returns
    -------
    ndarray of bool, shape (m,)
    """
    contact = getattr(system.model, "contact", None)
    starts = np.asarray(starts, dtype=np.float64)
    if contact is None or starts.shape[0] == 0:
        return np.ones(starts.shape[0], dtype=bool)
    with np.errstate(all="ignore"):  # a start of 1e300: not in contact if not > 0
        depth = np.asarray(contact.penetration(starts, system.p), dtype=np.float64)
    return ~(depth > 0.0)


def boundary_cells(image) -> np.ndarray:
    """Cells with a 4-neighbour (up, down, left or right) of another label; a cell not
    started (:data:`NOT_STARTED`) is on no boundary and counts as no neighbour.

    Parameters
    ----------
    image : array_like of int, shape (rows, columns)

    Returns
    -------
    ndarray of bool, shape (rows, columns)
    """
    a = np.asarray(image)
    if a.ndim != 2:
        raise ValueError(f"image must be 2-D (rows, columns), got shape {a.shape}")
    out = np.zeros(a.shape, dtype=bool)
    on = a != NOT_STARTED
    dv = (a[1:, :] != a[:-1, :]) & on[1:, :] & on[:-1, :]
    dh = (a[:, 1:] != a[:, :-1]) & on[:, 1:] & on[:, :-1]
    out[1:, :] |= dv
    out[:-1, :] |= dv
    out[:, 1:] |= dh
    out[:, :-1] |= dh
    return out


def boundary_measures(image, eps: int = EPS) -> dict:
    """Boundary fraction, basin entropy and boundary basin entropy of a basin image.

    Parameters
    ----------
    image : array_like of int, shape (rows, columns)
        One label per cell.
    eps : int
        Side of the entropy's boxes in cells (Daza et al. 2016); the boxes tile the
        image from its first row and column, and cells of an incomplete box at the far
        edges are left out.  Cells not started (:data:`NOT_STARTED`) are left out too:
        a box's proportions are over its started cells, a box of none is no box, and
        the boundary fraction is a share of the started cells.

    Returns
    -------
    dict
        ``boundary_fraction`` (share of :func:`boundary_cells`), ``basin_entropy``
        (``Sb``), ``boundary_basin_entropy`` (``Sbb``; NaN when no box holds two
        labels), ``boxes`` (``N``), ``boundary_boxes`` (``N_b``), ``fractal_by_log2``
        (``Sbb > log 2``, the sufficient criterion of a fractal boundary) and
        ``attractors`` (distinct labels in the image).

    References
    ----------
    A. Daza et al., Sci. Rep. 6, 31416 (2016), eqs. (1)-(4).
    """
    a = np.asarray(image)
    if a.ndim != 2 or a.dtype.kind not in "iub":
        raise ValueError(f"image must be a 2-D array of integer labels, got shape "
                         f"{a.shape}, dtype {a.dtype}")
    eps = _v.count("eps", eps, 1)
    rows, cols = a.shape
    nr, nc = rows // eps, cols // eps
    if nr < 1 or nc < 1:
        raise ValueError(f"eps: boxes of {eps} x {eps} cells do not fit in an image of "
                         f"{rows} x {cols}")
    on = a != NOT_STARTED
    if not on.any():
        raise ValueError("image: no cell was started")
    labels, codes = np.unique(a, return_inverse=True)
    codes = codes.reshape(a.shape)
    k = labels.size
    boxes: np.ndarray = codes[:nr * eps, :nc * eps].reshape(nr, eps, nc, eps).swapaxes(1, 2)
    boxes = boxes.reshape(nr * nc, eps * eps)
    counts = np.zeros((boxes.shape[0], k), dtype=np.int64)
    np.add.at(counts, (np.repeat(np.arange(boxes.shape[0]), eps * eps), boxes.ravel()), 1)
    if labels[0] == NOT_STARTED:  # np.unique sorts: the not-started code is the first
        counts = counts[:, 1:]
        k -= 1
    filled = counts.sum(axis=1)
    counts = counts[filled > 0]
    p = counts / filled[filled > 0, None].astype(float)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = -np.where(p > 0, p * np.log(p), 0.0).sum(axis=1)
    mixed = (counts > 0).sum(axis=1) > 1
    sbb = float(s[mixed].mean()) if mixed.any() else math.nan
    return dict(boundary_fraction=float(boundary_cells(a)[on].mean()),
                basin_entropy=float(s.mean()) if s.size else math.nan,
                boundary_basin_entropy=sbb,
                boxes=int(s.size), boundary_boxes=int(mixed.sum()),
                fractal_by_log2=bool(math.isfinite(sbb) and sbb > math.log(2.0)),
                attractors=k)


@_v.checks_flags
def basins(system: System, eta: float | None = None, grid: tuple[int, int] = (200, 200),
           plane: tuple[str, str] | None = None,
           ranges: tuple[tuple[float, float], tuple[float, float]] | None = None,
           base: ArrayLike | None = None, *, eps: int = EPS, everywhere: bool = False,
           settings: CensusSettings | None = None,
           execution: Execution | None = None) -> xr.Dataset:
    """The basins of attraction of every attractor in a plane of states.

    Parameters
    ----------
    system : System or parameter set
        The model and parameters (the forcing frequency replaced by ``eta``).
    eta : float, optional
        The forcing frequency (one value); the system's own by default.
    grid : (int, int)
        Cells along the first and the second plane variable (``(columns, rows)``).
    plane : (str, str) or str, optional
        Two state names of the model (``("X", "Y")``, ``"X,dX"``; ``"X'"`` stands for
        ``"dX"``): the first varies along the image's columns, the second along its rows;
        by default the states the model's XY plots draw (:func:`default_plane`).
    ranges : ((float, float), (float, float)), optional
        ``(lo, hi)`` of each plane variable: the cell centres span them, ends included;
        by default the census' box (:func:`vibimpact.census.starts.default_box`: ``[-1,
        1]`` for each state of a built-in model).
    base : array_like, shape (d,), optional
        The other state components (zero by default: for the built-in rotor's plane
        X, Y, at rest); its values in the plane's components are ignored.
    eps : int
        Box side of the basin entropy, in cells (:func:`boundary_measures`).
    everywhere : bool
        Start every cell.  By default a cell whose start lies in penetration of the
        model's contact is not started (:func:`started_cells`; ``basin``
        :data:`NOT_STARTED`): the built-in rotor's plane X, Y is then the disk inside
        the retainer clearance, the corners of the square range left out.
    settings : CensusSettings, optional
    execution : Execution, optional
        Workers, Dask, checkpoint and resume; none of them changes a number.

    Returns
    -------
    xarray.Dataset
        ``basin (row, column)``: the attractor index (along ``attractor``) each cell's
        start reaches, -1 where its integration failed (the solver could not go on:
        such a cell is on no attractor, and the boundary measures take it for a label
        of its own), -2 where it was not started (``everywhere``); ``started``
        ``(row, column)`` and the scalar ``not_started`` (their count); the census'
        fractions are shares of the started cells; ``failed``, ``failed_fraction``
        and ``failure`` (the count and share of the failed cells, the solver's first
        reason); the plane variables as coordinates (``<plane[0]> (column)``,
        ``<plane[1]> (row)``); ``boundary (row, column)`` (:func:`boundary_cells`),
        ``periods (row, column)`` and ``decided_by (row, column)`` of the census; the
        census' attractor table (``fraction``, ``fraction_se``, ``name``, ``period``,
        ``impacts_per_period``, ``samples``, ... over ``attractor``); the scalars
        ``boundary_fraction``, ``basin_entropy``, ``boundary_basin_entropy``,
        ``fractal_by_log2``, ``boxes``, ``boundary_boxes``.

    Raises
    ------
    ValueError
        Naming the argument.

    References
    ----------
    A. Daza et al., Sci. Rep. 6, 31416 (2016); G. Datseris, A. Wagemakers, Chaos 32,
    023104 (2022).

    Examples
    --------
    >>> import vibimpact as vi
    >>> p = vi.DuffingParams(delta=0.25, gamma=0.0, omega=1.0)
    >>> ds = vi.basins(vi.System(p), grid=(20, 20), plane=("x", "dx"),
    ...                ranges=((-2, 2), (-2, 2)))  # doctest: +SKIP
    >>> ds.basin.shape, float(ds.basin_entropy)  # doctest: +SKIP
    """
    from .census import attractors, census_etas

    system = as_system(system)
    model = system.model
    axes = plane_axes(model, plane)
    cols, rows = _grid(grid)
    eps = _v.count("eps", eps, 1)
    if rows < eps or cols < eps:
        raise ValueError(f"grid must be at least eps = {eps} cells each way, got "
                         f"{cols} x {rows}")
    if eta is not None and np.ndim(eta) != 0:
        raise ValueError(f"eta must be one number (a basin image is at one point), got "
                         f"{eta!r}")
    d = system.n_state
    box = default_box(model)
    rng = _ranges(ranges, axes, box, (cols, rows))
    base = np.zeros(d) if base is None else _v.state("base", base, d)
    starts = grid_starts(base, axes, rng, (rows, cols))
    started = np.ones(len(starts), dtype=bool) if everywhere \
        else started_cells(system, starts)
    if not started.any():
        census_etas(system, eta)  # a bad eta is said first, as where cells are started
        raise ValueError("ranges: every cell of the grid starts in penetration of the "
                         "model's contact (none would be started); start them with "
                         "everywhere=True (vibimpact basins --everywhere)")
    census = attractors(system, eta, starts[started], settings=settings,
                        execution=execution)
    return basins_dataset(census, model, axes, rng, (rows, cols), base, eps, started)


def _on_grid(values, started, fill):
    """``values`` of the started cells (1-D) spread over the whole grid, ``fill``
    elsewhere."""
    values = np.asarray(values)
    out = np.full(started.shape, fill, dtype=values.dtype)
    out[started] = values
    return out


def basins_dataset(census, model, axes, rng, shape, base, eps, started=None):
    """The basins Dataset (:func:`basins`) of a census over a grid of starts
    (``started``: which cells it started, all by default)."""
    rows, cols = shape
    names = list(model.state_names)
    xname, yname = names[axes[0]], names[axes[1]]
    started = np.ones(rows * cols, dtype=bool) if started is None \
        else np.asarray(started, dtype=bool)
    img = _on_grid(census.label.values[0], started, NOT_STARTED).reshape(rows, cols)
    decided = _on_grid(census.decided_by.values[0], started, NOT_STARTED_FLAG)
    measures = boundary_measures(img, eps)
    table = census[[v for v in _TABLE if v in census]].isel(eta=0)
    out = table.assign(
        basin=(("row", "column"), img, dict(
            long_name="attractor reached (index along attractor; -1: the integration "
                      "failed; -2: not started, in penetration of the contact)",
            valid_min=img.dtype.type(0))),
        started=(("row", "column"), started.reshape(rows, cols), dict(
            long_name="the cell was started (not in penetration of the contact)")),
        not_started=((), np.int32(rows * cols - int(started.sum())), dict(
            long_name="cells not started (in penetration of the contact)", units="1")),
        boundary=(("row", "column"), boundary_cells(img), dict(
            long_name="a 4-neighbour has another label")),
        periods=(("row", "column"), _on_grid(census.periods.values[0], started,
                                             0).reshape(rows, cols),
                 census.periods.attrs),
        decided_by=(("row", "column"), decided.reshape(rows, cols), dict(
            census.decided_by.attrs, flag_values=np.arange(NOT_STARTED_FLAG + 1,
                                                           dtype=decided.dtype),
            flag_meanings=DECIDED_FLAGS + " not_started")),
        boundary_fraction=((), measures["boundary_fraction"], dict(
            long_name="share of cells with a 4-neighbour of another label")),
        basin_entropy=((), measures["basin_entropy"], dict(
            long_name="basin entropy Sb (Daza et al. 2016)", units="nat")),
        boundary_basin_entropy=((), measures["boundary_basin_entropy"], dict(
            long_name="boundary basin entropy Sbb (Daza et al. 2016)", units="nat")),
        fractal_by_log2=((), bool(measures["fractal_by_log2"]), dict(
            long_name="Sbb > log 2: sufficient for a fractal boundary")),
        boxes=((), np.int32(measures["boxes"]), dict(
            long_name="boxes of the basin entropy (N)", units="1")),
        boundary_boxes=((), np.int32(measures["boundary_boxes"]), dict(
            long_name="boxes holding more than one attractor (N_b)", units="1")),
    )
    xs = np.linspace(rng[0][0], rng[0][1], cols)  # rng: the two (lo, hi) ranges
    ys = np.linspace(rng[1][0], rng[1][1], rows)
    out = out.assign_coords({xname: ("column", xs), yname: ("row", ys)})
    out[xname].attrs.update(long_name=f"start {xname}")
    out[yname].attrs.update(long_name=f"start {yname}")
    out.attrs = dict(census.attrs)
    out.attrs.update(kind="basins", frequency_name=model.frequency_name,
                     plane=f"{xname},{yname}", plane_x=xname,
                     plane_y=yname, grid_columns=int(cols), grid_rows=int(rows),
                     range_x=list(rng[0]), range_y=list(rng[1]),
                     base=np.asarray(base, dtype=np.float64), entropy_eps=int(eps))
    return out


@_v.checks_flags
def write_basins(ds: xr.Dataset, path, overwrite: bool = False) -> None:
    """Write a :func:`basins` dataset to NetCDF atomically
    (:func:`vibimpact.io.write_netcdf`: a temporary file renamed into place)."""
    from ..io import write_netcdf

    write_netcdf(ds, path, overwrite=overwrite)
