"""Two-parameter bifurcation curves (:func:`vibimpact.analysis.continue_bifurcation`,
written by :func:`vibimpact.continuation.curves.curve_to_dataset`) drawn in their parameter plane,
over the regime map of :func:`vibimpact.map2d` when one is given.

The map's regime cells (as the first panel of :func:`vibimpact.plotting.map2d.plot_map`,
with the boundaries between different regimes as thin black lines) lie under the curves:
a fold, period doubling or grazing curve of a periodic orbit should run along a boundary
where the regime map's cells change (Kuznetsov 2004, ch. 10; di Bernardo et al. 2008, ch. 8).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..base.bifurcation_kinds import BifurcationKind

if TYPE_CHECKING:  # names of the annotations only
    import os
    from collections.abc import Sequence

    import xarray as xr
    from matplotlib.figure import Figure

__all__ = ["plot_bifurcation_curves", "check_over", "CURVE_STYLES"]

#: line of each curve kind: (colour, line style)
CURVE_STYLES = {BifurcationKind.FOLD: ("k", "-"),
                BifurcationKind.PERIOD_DOUBLING: ("tab:blue", "--"),
                BifurcationKind.GRAZING: ("tab:red", "-.")}


def _curves(curves):
    import xarray as xr

    from ..continuation.curves import is_curve_dataset

    items = [curves] if isinstance(curves, xr.Dataset) else list(curves)
    if not items:
        raise ValueError("curves must hold at least one curve dataset")
    for ds in items:
        if not isinstance(ds, xr.Dataset) or not is_curve_dataset(ds):
            raise ValueError("curves must be datasets of "
                             "vibimpact.continuation.curves.curve_to_dataset "
                             "('vibimpact continue2' files)")
    return items


def _axes_names(items, over):
    """``(x, y)``: the parameters on the axes (the map's eta and its varied parameter
    when ``over`` is given, else the first curve's two)."""
    if over is not None:
        x, y = "eta", _map_param(over)
    else:
        x, y = items[0].attrs["curve_params"].split(",")
    for ds in items:
        if set(ds.attrs["curve_params"].split(",")) != {x, y}:
            raise ValueError(f"curves: a curve in ({ds.attrs['curve_params']}) cannot be "
                             f"drawn in the plane ({x}, {y})")
    return x, y


def _map_param(over):
    """The parameter a map varies besides eta (its ``map_vary`` attribute, else the one
    other dimension of ``regime``)."""
    if "regime" not in over or "label" not in over or "eta" not in over.dims:
        raise ValueError("over must be a map dataset of vibimpact.map2d")
    name = over.attrs.get("map_vary")
    if name in over.dims:
        return str(name)
    others = [d for d in over["regime"].dims if d not in ("eta", "direction")]
    if len(others) != 1:
        raise ValueError("over must be a map dataset: regime over (PARAM, eta)")
    return str(others[0])


def check_over(over: xr.Dataset, params: Sequence[str]) -> str:
    """Raise ValueError unless ``over`` is a map of :func:`vibimpact.map2d` over eta and
    the other of the two parameters ``params`` of a curve, whose regime cells can be
    drawn (they are, once, into a figure that is thrown away); the map's parameter.

    A command checks its ``--over`` map so before it computes the curve."""
    from matplotlib.figure import Figure

    name = _map_param(over)
    if {"eta", name} != set(params):
        raise ValueError(f"over is a map over (eta, {name}); the curve is in "
                         f"({', '.join(params)})")
    _draw_map(Figure().subplots(), over, name, None)
    return name


def _cell_edges(v):
    """Edges of the cells around the points ``v`` (midpoints; half a step beyond)."""
    v = np.asarray(v, dtype=float)
    if v.size == 1:
        h = 0.5 * abs(v[0]) if v[0] != 0.0 else 0.5
        return np.array([v[0] - h, v[0] + h])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def _draw_map(ax, over, name, direction):
    from matplotlib.collections import LineCollection

    from .map2d import boundaries
    from .map_panels import regime_panel

    if "direction" in over.dims:
        dirs = [str(d) for d in over["direction"].values]
        if direction is not None and direction not in dirs:
            raise ValueError(f"direction must be one of {', '.join(dirs)}, got "
                             f"{direction!r}")
        over = over.sel(direction=direction or dirs[0])
    sub = over.transpose(name, "eta", ...)
    xe, ye = _cell_edges(over["eta"].values), _cell_edges(over[name].values)
    reg = np.asarray(sub["regime"].values, dtype=int)
    regime_panel(ax, xe, ye, reg)
    segs = boundaries(reg, xe, ye)  # between different regimes only, as plot_map's
    if segs:
        ax.add_collection(LineCollection(segs, colors="k", linewidths=0.4, zorder=3))
    ax.set_xlim(xe[0], xe[-1])
    ax.set_ylim(ye[0], ye[-1])


def plot_bifurcation_curves(curves: xr.Dataset | Sequence[xr.Dataset],
                            over: xr.Dataset | None = None,
                            path: str | os.PathLike[str] | None = None, *,
                            direction: str | None = None,
                            figsize: tuple[float, float] | None = None,
                            dpi: float | None = None, style: str | None = None) -> Figure:
    """Bifurcation curves in their parameter plane, over a regime map.

    Parameters
    ----------
    curves : xarray.Dataset or sequence of them
        From :func:`vibimpact.continuation.curves.curve_to_dataset` (or ``vibimpact continue2``
        files read back); each drawn as a line in the style of its kind
        (:data:`CURVE_STYLES`), with its start marked.
    over : xarray.Dataset, optional
        A map of :func:`vibimpact.map2d` over (eta, PARAM): its regime cells and the
        boundaries between different regimes are drawn underneath, and every curve must
        lie in (eta, PARAM).
    path : str or os.PathLike, optional
        Save the figure there.
    direction : {"up", "down"}, optional
        Which sweep of a ``direction="both"`` map (default: the first).
    figsize, dpi, style
        As :func:`vibimpact.plotting.plot_map`'s.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        Naming ``curves`` (no curve dataset, or one in another plane than the map's) or
        a figure option.
    """
    from ._sweep import spec
    from .style import look

    items = _curves(curves)
    x, y = _axes_names(items, over)
    lk = look(figsize, dpi, style)
    with lk.context():
        fig = lk.figure((8, 5.5), 3.5)
        ax = fig.subplots()
        if over is not None:
            _draw_map(ax, over, y, direction)
        handles = []
        for ds in items:
            kind = BifurcationKind.from_code(int(ds["bifurcation_kind"].values))
            color, ls = CURVE_STYLES.get(kind, ("0.3", ":"))
            label = f"P{int(ds.attrs['period'])} {kind.value}"
            (line,) = ax.plot(ds[x].values, ds[y].values, color=color, ls=ls, lw=2.0,
                              label=label, zorder=4)
            handles.append(line)
        symbols = spec(items[0])  # the model's symbols for its parameters
        ax.set_xlabel(symbols.symbol(x))
        ax.set_ylabel(symbols.symbol(y))
        if over is None:
            ax.grid(True, alpha=0.3)
        regimes = ax.get_legend()  # regime_panel's, upper right beside the axes
        lk.legend(ax, handles=handles, loc="lower left", bbox_to_anchor=(1.01, 0.0))
        if regimes is not None:
            ax.add_artist(regimes)
        lk.title(ax, "bifurcation curves" + (" over the regime map" if over is not None
                                             else ""))
        return lk.finish(fig, path)
