"""The census figure: basin fractions against eta above each attractor's bifurcation
diagram (reads a census dataset of :func:`vibimpact.attractors` only)."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .style import attractor_colour, look

if TYPE_CHECKING:
    import os

    import xarray as xr
    from matplotlib.figure import Figure

__all__ = ["plot_census"]


def _check(ds):
    if ds.attrs.get("kind") != "census" or "fraction" not in ds or "global_id" not in ds:
        raise ValueError("ds is not an attractor census (vibimpact attractors)")


def _attractor_names(ds):
    """``{global id: name}`` (the name where the attractor first appears)."""
    names = {}
    gid = ds.global_id.values
    for i in range(gid.shape[0]):
        for a in range(gid.shape[1]):
            g = int(gid[i, a])
            if g >= 0 and g not in names:
                names[g] = str(ds.name.values[i, a])
    return names


def _single_eta(ds, ax, ids, names, colors, fractions):
    """The basin fractions of a census of one eta as horizontal bars on a log axis (an
    attractor of 0.1 % is as visible as one of 50 %), each labelled with its fraction;
    the legend handles."""
    from matplotlib.patches import Patch

    n = int(ds.attrs.get("n_starts", ds.sizes.get("start", 1))) or 1
    floor = 0.5 / n  # half a start: the axis' lower end
    order = sorted(range(len(ids)), key=lambda k: -fractions[k])
    handles = []
    for row, k in enumerate(order):
        g, f = ids[k], float(fractions[k])
        ax.barh(row, max(f, floor), left=0.0, color=colors[g], height=0.7)
        ax.text(max(f, floor) * 1.15, row, f"{100 * f:.2g} %", va="center",
                fontsize="small")
        handles.append(Patch(facecolor=colors[g], label=f"A{g}: {names[g]}"))
    ax.set_xscale("log")
    ax.set_xlim(floor, 3.0)
    ax.set_yticks(range(len(order)), [f"A{ids[k]}" for k in order])
    ax.invert_yaxis()
    ax.set_xlabel("basin fraction (log)")
    ax.xaxis.set_tick_params(labelbottom=True)
    return handles


def plot_census(ds: xr.Dataset, path: str | os.PathLike[str] | None = None, *,
                component: int = 0, figsize: tuple[float, float] | None = None,
                dpi: float | None = None, style: str | None = None) -> Figure:
    """Basin fractions (stacked, with their standard errors) against eta, above every
    attractor's stroboscopic points against eta, one colour per attractor (its
    ``global_id``), so that one sees where each attractor is born and where it dies.

    Parameters
    ----------
    ds : xarray.Dataset
        A census (:func:`vibimpact.attractors`).
    path : str or os.PathLike, optional
        Save the figure there.
    component : int
        The state component of the bifurcation diagram (0: the model's first state, X
        for the built-in rotor).
    figsize, dpi, style
        As every plotting function of the package.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        Naming the argument, or a dataset that is no census.
    """
    _check(ds)
    d = ds.sizes["state"]
    if isinstance(component, (bool, np.bool_)) or not isinstance(
            component, (int, np.integer)) or not 0 <= component < d:
        raise ValueError(f"component must be an integer in [0, {d - 1}], got "
                         f"{component!r}")
    from ._sweep import check_contents

    check_contents(ds, grids=("eta",), codes=(), increasing=("eta",))
    lk = look(figsize, dpi, style)
    eta = ds.eta.values
    gid = ds.global_id.values
    frac = np.nan_to_num(ds.fraction.values)
    names = _attractor_names(ds)
    ids = sorted(names)
    state = str(ds.state.values[component])
    with lk.context():
        fig = lk.figure((10, 8), 7.0)
        top, bottom = fig.subplots(2, 1, sharex=eta.size > 1, height_ratios=(1, 2))
        colors = {g: attractor_colour(g) for g in ids}  # the basins figure's too
        stacked = np.zeros((len(ids), eta.size))
        for k, g in enumerate(ids):
            stacked[k] = np.where(gid == g, frac, 0.0).sum(axis=1)
        # one constant band per grid point (steps, not lines between the points: a
        # fraction is known at the grid's values only)
        if eta.size > 1:
            edges = np.r_[eta[0] - 0.5 * (eta[1] - eta[0]), 0.5 * (eta[1:] + eta[:-1]),
                          eta[-1] + 0.5 * (eta[-1] - eta[-2])]
        else:
            edges = np.array([eta[0] - 0.005, eta[0] + 0.005])
        xs = np.repeat(edges, 2)[1:-1]
        handles, below = [], np.zeros(eta.size)
        if eta.size == 1:  # one eta: a bar per attractor, small basins on a log axis
            handles = _single_eta(ds, top, ids, names, colors, stacked[:, 0])
            ids_drawn: list = []
        else:
            ids_drawn = ids
        for k, g in enumerate(ids_drawn):
            above = below + stacked[k]
            handles.append(top.fill_between(xs, np.repeat(below, 2), np.repeat(above, 2),
                                            color=colors[g], linewidth=0.0,
                                            label=f"A{g}: {names[g]}"))
            below = above
        failed = np.nan_to_num(ds.failed_fraction.values) if "failed_fraction" in ds \
            else np.zeros(eta.size)
        if failed.any() and eta.size > 1:  # failed starts: on no attractor, hatched
            handles.append(top.fill_between(
                xs, np.repeat(below, 2), np.repeat(below + failed, 2), facecolor="white",
                edgecolor="0.5", hatch="xx", linewidth=0.0,
                label="integration failed"))
        if eta.size > 1:
            top.set_ylim(0.0, 1.0)
            top.set_ylabel("basin fraction")
        samples = ds.samples.values[..., component]
        for g in ids:
            for i in range(eta.size):
                for a in np.flatnonzero(gid[i] == g):
                    y = samples[i, a]
                    y = y[np.isfinite(y)]
                    bottom.plot(np.full(y.size, eta[i]), y, ".", ms=2.0,
                                color=colors[g])
        bottom.set_xlabel("η")
        if eta.size == 1:  # the one eta, not ticks between values that were not run
            bottom.set_xticks([float(eta[0])], [f"{float(eta[0]):g}"])
            bottom.set_xlim(edges[0], edges[1])
        bottom.set_ylabel(f"{state} (stroboscopic)")
        lk.legend(top, handles=handles)
        lk.title(fig, f"attractor census, {int(ds.attrs.get('n_starts', 0))} starts "
                      f"per η")
        return lk.finish(fig, path)
