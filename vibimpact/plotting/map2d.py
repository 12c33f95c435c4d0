"""The regime map of :func:`vibimpact.map2d`: regimes, periods, impacts and the largest
exponent over (eta, parameter), with the interval boundaries drawn as lines."""
from __future__ import annotations

import numpy as np

from ._sweep import REGIME_NAMES, title

#: regime code -> colour (0: not computed)
MAP_REGIME_COLORS = {0: "0.85", 1: "#31a354", 2: "tab:orange", 3: "tab:red", 4: "0.15",
                     5: "tab:purple"}
#: colour of points where a quantity was not computed or does not exist
MISSING = "0.9"


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
        Labels of the points (rows: the varied parameter, columns: eta).
    xe, ye : ndarray
        Cell edges along eta (nx + 1) and along the parameter (ny + 1).

    Returns
    -------
    list of ((x0, y0), (x1, y1))
        Vertical segments are the interval boundaries of each row (as
        :func:`vibimpact.intervals` finds them); horizontal ones separate rows whose labels
        differ at the same eta.
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
        ax.add_collection(LineCollection(segs, colors="k", linewidths=0.6, zorder=3))


def _regime_panel(ax, xe, ye, reg):
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    codes = len(MAP_REGIME_COLORS)
    cmap = ListedColormap([MAP_REGIME_COLORS[c] for c in range(codes)])
    ax.pcolormesh(xe, ye, reg, cmap=cmap,
                  norm=BoundaryNorm(np.arange(-0.5, codes + 0.5), codes))
    present = [c for c in range(codes) if np.any(reg == c)]
    ax.legend(handles=[Patch(facecolor=MAP_REGIME_COLORS[c], edgecolor="0.5",
                             label=REGIME_NAMES[c]) for c in present],
              loc="upper left", fontsize="x-small", framealpha=0.85)
    ax.set_title("regime", fontsize="medium")


def _period_panel(fig, ax, xe, ye, period, reg):
    from matplotlib.colors import BoundaryNorm, ListedColormap

    per = np.where(reg == 1, period, 0).astype(int)
    values = sorted(int(v) for v in np.unique(per) if v > 0)
    if len(values) > 19:  # the 18 most frequent periods, the rest as one colour
        counts = {v: int((per == v).sum()) for v in values}
        keep = sorted(sorted(values, key=lambda v: -counts[v])[:18])
        per = np.where(np.isin(per, keep) | (per == 0), per, -1)
        values = keep + [-1]
    codes = np.full(per.shape, 0)
    for k, v in enumerate(values, start=1):
        codes[per == v] = k
    palette = [MISSING] + [_tab20(k) for k in range(len(values))]
    cmap = ListedColormap(palette)
    norm = BoundaryNorm(np.arange(-0.5, len(values) + 1.5), len(palette))
    m = ax.pcolormesh(xe, ye, codes, cmap=cmap, norm=norm)
    cb = fig.colorbar(m, ax=ax, ticks=np.arange(len(values) + 1), shrink=0.9)
    cb.ax.set_yticklabels(["none"] + [f"P{v}" if v > 0 else "other" for v in values],
                          fontsize="x-small")
    ax.set_title("period n (T = n 2π/η; none: not periodic or too long)",
                 fontsize="medium")


def _tab20(k):
    from matplotlib import colormaps

    order = (0, 2, 4, 6, 8, 10, 12, 16, 18, 1, 3, 5, 7, 9, 11, 13, 17, 19, 15)
    return colormaps["tab20"](order[k % len(order)])


def _masked_panel(fig, ax, xe, ye, z, cmap, norm, label):
    from matplotlib import colormaps

    cm = colormaps[cmap].with_extremes(bad=MISSING)
    m = ax.pcolormesh(xe, ye, np.ma.masked_invalid(z), cmap=cm, norm=norm)
    cb = fig.colorbar(m, ax=ax, shrink=0.9)
    cb.set_label(label, fontsize="small")


def plot_map(ds, direction=None, path=None):
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

    Returns
    -------
    matplotlib.figure.Figure

    Notes
    -----
    Every point is a cell reaching half-way to its neighbours.  Black lines separate
    neighbouring points with different labels (kind of motion, period, impacts per
    period, loaded arcs): the vertical ones are the boundaries of the frequency intervals
    of each row, the horizontal ones where a row's label differs from the next row's.
    Grey: not computed (the exponent is computed only where no period is found) or, for
    the period, no period.
    """
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure

    from ._sweep import check_dataset

    check_dataset(ds, "a map (vibimpact.map2d)")
    for v in ("regime", "period", "label", "impacts_per_period", "lyapunov"):
        if v not in ds:
            raise ValueError(f"the map dataset has no {v}")
    name = _vary_name(ds)
    if "direction" in ds.dims:
        dirs = [str(d) for d in ds["direction"].values]
        if direction is not None:
            if direction not in dirs:
                raise ValueError(f"direction must be one of {', '.join(dirs)}")
            dirs = [direction]
        subs = [(d, ds.sel(direction=d)) for d in dirs]
    else:
        d = str(ds.attrs.get("sweep_direction", ds.attrs.get("direction", "up")))
        subs = [(d, ds)]
    xe = _edges(ds["eta"].values)
    ye = _edges(ds[name].values)
    fig = Figure(figsize=(12, 8 * len(subs)), layout="constrained")
    grid = fig.subplots(2 * len(subs), 2, sharex=True, sharey=True, squeeze=False)
    for k, (d, sub) in enumerate(subs):
        sub = sub.transpose(name, "eta", ...)
        reg = np.asarray(sub["regime"].values, dtype=int)
        segs = boundaries(sub["label"].values, xe, ye)
        (a, b), (c, e) = grid[2 * k], grid[2 * k + 1]
        _regime_panel(a, xe, ye, reg)
        _period_panel(fig, b, xe, ye, np.asarray(sub["period"].values), reg)
        ipp = np.asarray(sub["impacts_per_period"].values, dtype=float)
        finite = ipp[np.isfinite(ipp)]
        _masked_panel(fig, c, xe, ye, ipp, "viridis",
                      Normalize(0.0, max(1.0, float(finite.max()) if finite.size else 1.0)),
                      "contacts per motion period")
        c.set_title("impacts per period", fontsize="medium")
        lam = np.asarray(sub["lyapunov"].values, dtype=float)
        fin = lam[np.isfinite(lam)]
        top = float(np.abs(fin).max()) if fin.size else 1.0
        _masked_panel(fig, e, xe, ye, lam, "RdBu_r", Normalize(-top or -1.0, top or 1.0),
                      "λ₁ per unit τ")
        e.set_title("largest Lyapunov exponent" + ("" if fin.size else
                                                    " (none computed: all periodic)"),
                    fontsize="medium")
        for ax in (a, b, c, e):
            _draw_boundaries(ax, segs)
            ax.set_xlim(xe[0], xe[-1])
            ax.set_ylim(ye[0], ye[-1])
        for ax in (a, c):
            ax.set_ylabel(name)
        grid[2 * k, 0].annotate(f"sweep {d}", (0.0, 1.0), xycoords="axes fraction",
                                xytext=(0, 14), textcoords="offset points",
                                fontsize="medium", fontweight="bold")
    for ax in grid[-1]:
        ax.set_xlabel("η")
    fig.suptitle(f"parameter map over η and {name}: {title(ds)}", fontsize="medium")
    if path is not None:
        from .xy import save_figure

        save_figure(fig, path)
    return fig
