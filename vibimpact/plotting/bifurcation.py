"""Bifurcation diagram: the Poincaré (stroboscopic) points of a sweep against eta."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._sweep import DIRECTION_COLORS, axes_of, check_sweep, directions, new_figure, title
from .style import look

if TYPE_CHECKING:  # names of the annotations only
    import os

    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


def plot_bifurcation(ds: xr.Dataset, ax: Axes | None = None,
                     path: str | os.PathLike[str] | None = None, *,
                     figsize: tuple[float, float] | None = None, dpi: float | None = None,
                     style: str | None = None) -> Figure:
    """Draw the Poincaré points X and Y of a sweep against eta (two panels).

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset (:func:`vibimpact.sweep` with the ``poincare`` analysis, or a file
        of ``vibimpact classify`` / ``vibimpact bifurcation``); uses ``poincare_X``,
        ``poincare_Y`` (``eta``, ``sample`` [, ``direction``]).
    ax : pair of matplotlib.axes.Axes, optional
        Axes for X and Y; a new 8 x 6.5 inch figure otherwise (one column, 3.5 x 3.6
        inches, in the paper style).
    path : str or os.PathLike, optional
        Save the figure there (atomically, format from the extension).
    figsize : (float, float), optional
        Width and height of the new figure in inches (not with ``ax``).
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
        Naming ``ax``, ``figsize``, ``dpi`` or ``style``.

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
    lk = look(figsize, dpi, style, ax)
    with lk.context():
        if ax is None:
            fig, axes = new_figure(lk, 2, 6.5, 3.6)
        else:
            fig, axes = axes_of(ax, 2, "for X and for Y")
        _draw(ds, axes, lk)
        return lk.finish(fig, path)


def _draw(ds, axes, lk):
    """The Poincaré points of every direction on ``axes`` (X, Y)."""
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
        a.grid(True, alpha=0.5)
    leg = lk.legend(axes[0], markerscale=6)
    for h in leg.legend_handles:
        h.set_alpha(1.0)
    lk.title(axes[0], title(ds))
