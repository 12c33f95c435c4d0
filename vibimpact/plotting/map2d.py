"""The regime map of :func:`vibimpact.map2d`: regimes, periods, impacts and the largest
exponent over (eta, parameter), with the interval boundaries drawn as lines."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..base import _validate as _v
from ._sweep import frequency_label, title
from .map_panels import (MAP_REGIME_COLORS, MISSING, exponent_norm, exponent_panel,
                         impacts_keys, impacts_scale, period_keys, period_scale,
                         regime_panel)
from .style import look, width

if TYPE_CHECKING:  # names of the annotations only
    import os

    import xarray as xr
    from matplotlib.figure import Figure

__all__ = ["MAP_REGIME_COLORS", "MISSING", "boundaries", "is_listed", "plot_map", "tick_indices",
           "value_ticks"]


def _vary_name(ds):
    name = ds.attrs.get("map_vary")
    if name in ds.dims:
        return str(name)
    others = [d for d in ds["regime"].dims if d not in ("eta", "direction")]
    if len(others) != 1:
        raise ValueError("not a map dataset: regime must have dims (PARAM, eta) or "
                         "(direction, PARAM, eta)")
    return str(others[0])


def _edges(v):
    """Cell edges around the points ``v`` (midpoints; half a step beyond the ends)."""
    v = np.asarray(v, dtype=float)
    if v.size == 1:
        h = 0.5 * abs(v[0]) if v[0] != 0.0 else 0.5
        return np.array([v[0] - h, v[0] + h])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def boundaries(labels, xe, ye):
    """Line segments between neighbouring points of different label.

    Parameters
    ----------
    labels : ndarray, shape (ny, nx)
        Labels of the points (rows: the varied parameter, columns: eta); the map draws
        those of its regime codes.
    xe, ye : ndarray
        Cell edges along eta (nx + 1) and along the parameter (ny + 1).

    Returns
    -------
    list of ((x0, y0), (x1, y1))
        Vertical segments separate neighbouring points of a row whose labels differ;
        horizontal ones separate rows whose labels differ at the same eta.
    """
    lab = np.asarray(labels).astype(str)
    segs = []
    jj, ii = np.nonzero(lab[:, 1:] != lab[:, :-1])
    segs += [((xe[i + 1], ye[j]), (xe[i + 1], ye[j + 1])) for j, i in zip(jj, ii)]
    jj, ii = np.nonzero(lab[1:, :] != lab[:-1, :])
    segs += [((xe[i], ye[j + 1]), (xe[i + 1], ye[j + 1])) for j, i in zip(jj, ii)]
    return segs


def _draw_boundaries(ax, segs):
    from matplotlib.collections import LineCollection

    if segs:
        ax.add_collection(LineCollection(segs, colors="k", linewidths=width(0.4), zorder=3))


def is_listed(ds, values):
    """True when the map's parameter values were given as a list (``--vary f=0,0.05``,
    recorded in the attribute ``vary_range``), or, without that record, are not evenly
    spaced: the map then shows them as categories, one row each."""
    spec = str(ds.attrs.get("vary_range", "")).partition("=")[2].strip()
    if spec:
        return ":" not in spec
    v = np.asarray(values, dtype=float)
    if v.size < 3:
        return False
    step = np.diff(v)
    return not np.allclose(step, step[0], rtol=1e-9, atol=0.0)


#: most ticks on the axis of the varied parameter (its values thinned beyond)
MAX_VALUE_TICKS = 8


def tick_indices(n, most=MAX_VALUE_TICKS):
    """Indices of the values that get a tick: every value when ``n <= most``, else about
    ``most`` of them at one stride, always the first and the last (the last replacing the
    stride's last one when it would sit less than half a stride from it)."""
    if n <= most:
        return np.arange(n)
    stride = -(-(n - 1) // (most - 1))
    idx = list(range(0, n, stride))
    if idx[-1] != n - 1:
        if n - 1 - idx[-1] < stride / 2:
            idx[-1] = n - 1
        else:
            idx.append(n - 1)
    return np.asarray(idx)


def value_ticks(values, listed):
    """``(positions, labels)`` of the ticks on the varied parameter's axis: at the
    sampled values themselves (at the rows 0, 1, ... of a categorical axis), thinned by
    :func:`tick_indices`, each labelled with its value."""
    idx = tick_indices(len(values))
    where = idx.astype(float) if listed else np.asarray(values, dtype=float)[idx]
    return where, [f"{float(values[i]):g}" for i in idx]


@_v.checks_flags
def plot_map(ds: xr.Dataset, direction: str | None = None,
             path: str | os.PathLike[str] | None = None, *, categorical: bool | None = None,
             figsize: tuple[float, float] | None = None, dpi: float | None = None,
             style: str | None = None) -> Figure:
    """Four panels over (eta, parameter): regime, period, impacts per period, exponent.

    Parameters
    ----------
    ds : xarray.Dataset
        A map from :func:`vibimpact.map2d` (or read back by
        :func:`vibimpact.maps.open_map`).
    direction : {"up", "down"}, optional
        For a ``direction="both"`` map: draw only that sweep (default: every sweep, one
        block of panels each).
    path : str or os.PathLike, optional
        Save the figure there.
    categorical : bool, optional
        Draw the parameter's values as categories, one evenly spaced row each labelled
        with its value, instead of on a numeric axis; by default when they were listed
        (:func:`is_listed`).
    figsize : (float, float), optional
        Width and height in inches; 12 x 8 per sweep direction by default (two journal
        columns, 7 x 5 per direction, in the paper style).
    dpi : float, optional
        Resolution of the saved figure (default 150; 300 in the paper style).
    style : {"default", "paper"}, optional
        ``"paper"``: :data:`vibimpact.plotting.style.PAPER_STYLE`, a journal's look.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        Naming ``direction``, ``figsize``, ``dpi`` or ``style``, or a dataset that is no
        map.

    Notes
    -----
    Every point is a cell reaching half-way to its neighbours; the parameter's axis spans
    the cells and has its ticks at the sampled values (thinned when there are many,
    :func:`tick_indices`).  Black lines separate neighbouring points of different regime
    (kind of motion) only, in every panel: the vertical ones where a row's regime changes
    along eta, the horizontal ones where a row's regime differs from the next row's.
    Each quantity has one colour scale over all the panels of the figure (both sweep
    directions): the same colour is the same period, count or exponent everywhere.
    Period and impacts per period are integers, drawn with one colour per value present;
    grey: not computed (the exponent is computed only where no period is found; a grey
    swatch under the exponent's bar names the regimes of its grey points) or, for the
    period, no period.
    """
    from ._sweep import check_contents, check_dataset

    check_dataset(ds, "a map (vibimpact.map2d)")
    for v in ("regime", "period", "label", "impacts_per_period", "lyapunov"):
        if v not in ds:
            raise ValueError(f"the map dataset has no {v}")
    check_contents(ds, grids=("eta", _vary_name(ds)))
    lk = look(figsize, dpi, style)
    name = _vary_name(ds)
    subs = _directions(ds, direction)
    values = np.asarray(ds[name].values, dtype=float)
    listed = is_listed(ds, values) if categorical is None else categorical
    ye = np.arange(values.size + 1) - 0.5 if listed else _edges(values)
    with lk.context():
        fig = lk.figure((12, 8 * len(subs)), 5.0 * len(subs), columns=2)
        grid = fig.subplots(2 * len(subs), 2, sharex=True, sharey=True, squeeze=False)
        _panels(fig, grid, [s.transpose(name, "eta", ...) for _, s in subs],
                _edges(ds["eta"].values), ye)
        for k, (d, _) in enumerate(subs):
            grid[2 * k, 0].annotate(f"sweep {d}", (0.0, 1.0), xycoords="axes fraction",
                                    xytext=(0, 14), textcoords="offset points",
                                    fontweight="bold")
        where, labels = value_ticks(values, listed)
        for ax in grid[:, 0]:
            ax.set_ylabel(name)
            ax.set_yticks(where, labels)
        freq = frequency_label(ds)
        for ax in grid[-1]:
            ax.set_xlabel(freq)
        lk.title(fig, f"parameter map over {freq} and {name}: {title(ds)}")
        return lk.finish(fig, path)


def _directions(ds, direction):
    """``[(direction, dataset)]`` of the sweeps to draw."""
    if "direction" not in ds.dims:
        d = str(ds.attrs.get("sweep_direction", ds.attrs.get("direction", "up")))
        return [(d, ds)]
    dirs = [str(d) for d in ds["direction"].values]
    if direction is not None:
        if direction not in dirs:
            raise ValueError(f"direction must be one of {', '.join(dirs)}, got "
                             f"{direction!r}")
        dirs = [direction]
    return [(d, ds.sel(direction=d)) for d in dirs]


def _panels(fig, grid, subs, xe, ye):
    """The four panels of every sweep in ``subs`` (rows 2k, 2k + 1 of ``grid``), each
    quantity on one colour scale over all of them."""
    regs = [np.asarray(s["regime"].values, dtype=int) for s in subs]
    pscale, pkeys = period_scale([period_keys(s["period"].values, r)
                                  for s, r in zip(subs, regs)])
    iscale, ikeys = impacts_scale([impacts_keys(s["impacts_per_period"].values)
                                   for s in subs])
    lams = [np.asarray(s["lyapunov"].values, dtype=float) for s in subs]
    norm = exponent_norm(lams)
    for k in range(len(subs)):
        (a, b), (c, e) = grid[2 * k], grid[2 * k + 1]
        regime_panel(a, xe, ye, regs[k])
        pscale.draw(fig, b, xe, ye, pkeys[k], "T = n 2π/η")
        b.set_title("period n")
        # no side label: between the columns it would read as the exponent panel's
        # y-axis label; the panel's title names the quantity
        iscale.draw(fig, c, xe, ye, ikeys[k], None)
        c.set_title("impacts per period")
        exponent_panel(fig, e, xe, ye, lams[k], norm, regs[k])
        # between different regimes only: a line inside one regime (the label changes
        # with the period, impacts or arcs) reads as a regime boundary that is not
        segs = boundaries(regs[k], xe, ye)
        for ax in (a, b, c, e):
            _draw_boundaries(ax, segs)
            ax.set_xlim(xe[0], xe[-1])
            ax.set_ylim(ye[0], ye[-1])
