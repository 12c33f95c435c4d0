"""Bifurcation diagram: the Poincaré (stroboscopic) points of a sweep against eta."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._sweep import DIRECTION_COLORS, check_sweep, directions, new_figure, title

if TYPE_CHECKING:  # names of the annotations only
    import os

    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


def plot_bifurcation(ds: xr.Dataset, ax: Axes | None = None,
                     path: str | os.PathLike[str] | None = None) -> Figure:
    """Draw the Poincaré points X and Y of a sweep against eta (two panels).

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset (:func:`vibimpact.sweep` with the ``poincare`` analysis, or a file
        of ``vibimpact classify`` / ``vibimpact bifurcation``); uses ``poincare_X``,
        ``poincare_Y`` (``eta``, ``sample`` [, ``direction``]).
    ax : pair of matplotlib.axes.Axes, optional
        Axes for X and Y; a new 8 x 6.5 inch figure otherwise.
    path : str or os.PathLike, optional
        Save the figure there (atomically, format from the extension).

    Returns
    -------
    matplotlib.figure.Figure

    Notes
    -----
    The up and down sweeps are drawn as small dots in two colours: where they differ the
    motion depends on the history (hysteresis, coexisting attractors).  A periodic orbit
    of period n shows n dots above its eta, chaos a vertical smear.  Lengths are in
    clearances; +Y points down, along gravity.

    Examples
    --------
    >>> from vibimpact.io import read_netcdf
    >>> from vibimpact.plotting import plot_bifurcation
    >>> fig = plot_bifurcation(read_netcdf("bif.nc"), path="bif.png")  # doctest: +SKIP
    """
    check_sweep(ds, "poincare_X", "poincare_Y")
    if ax is None:
        fig, axes = new_figure(2, 6.5)
    else:
        axes = list(ax)
        if len(axes) != 2:
            raise ValueError("ax must be two Axes (for X and for Y)")
        fig = axes[0].figure
    for d, sub in directions(ds):
        eta = sub["eta"].values
        color = DIRECTION_COLORS.get(d, "tab:green")
        for a, name in zip(axes, ("poincare_X", "poincare_Y")):
            v = np.asarray(sub[name].transpose("eta", ...).values, dtype=float)
            v = v.reshape(eta.size, -1)
            e = np.broadcast_to(eta[:, None], v.shape)
            ok = np.isfinite(v)
            a.plot(e[ok], v[ok], ls="none", marker=".", ms=1.5, mew=0, color=color,
                   alpha=0.7, rasterized=True, label=f"sweep {d}")
    axes[0].set_ylabel("X  (Poincaré)")
    axes[1].set_ylabel("Y  (Poincaré, +Y down)")
    axes[-1].set_xlabel("η")
    for a in axes:
        a.grid(True, lw=0.4, alpha=0.5)
    leg = axes[0].legend(loc="best", fontsize="small", markerscale=6)
    for h in leg.legend_handles:
        h.set_alpha(1.0)
    axes[0].set_title(title(ds), fontsize="medium")
    if path is not None:
        from .xy import save_figure

        save_figure(fig, path)
    return fig
