"""The largest Lyapunov exponent of a sweep against eta, with its standard error, and the
Floquet exponent of its periodic points.

A sweep estimates the largest exponent (``lyapunov``, per unit tau, with its standard
error ``lyapunov_err``) by the tangent-map method of Benettin et al. (1980) where no
period is found (and everywhere with ``lyapunov="always"``); a periodic orbit gets the
exact exponent of its largest Floquet multiplier instead, ``ln|mu|max / (n T)``
(``floquet_exponent``, the ``floquet`` analysis; Parker & Chua 1989, sec. 3.2).  Above
zero: chaos; zero: quasi-periodic motion or a bifurcation; below: a stable orbit.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._sweep import axes_of, check_sweep, directions, frequency_label, new_figure, title
from .needs import require
from .style import look, width

if TYPE_CHECKING:  # names of the annotations only
    import os

    import xarray as xr
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["plot_lyapunov", "regime_color"]

#: legend label of the exponents' scatter, and of the Floquet exponents' (tests and
#: callers find the collections by them)
LYAPUNOV_LABEL = "largest Lyapunov exponent ± standard error"
FLOQUET_LABEL = "Floquet exponent (periodic orbit, exact)"

_PERIODIC, _DIVERGED = 1, 4


def regime_color(regime: int, period: int) -> tuple[str, str, tuple[int, int]]:
    """Colour, name and legend order of a point's regime, as the regime bands of
    :func:`vibimpact.plotting.plot_intervals` and :func:`~vibimpact.plotting.plot_response`
    colour them: periodic in shades of green by period (yellow-green: too long to
    resolve), quasi-periodic orange, chaotic red, diverged black, unsettled purple."""
    from .style import class_color
    return class_color(regime, period)


def _column(sub, name, n):
    """Variable ``name`` of one direction as floats (all NaN when absent)."""
    if name not in sub:
        return np.full(n, np.nan)
    return np.asarray(sub[name].values, dtype=float).reshape(n)


def exponent_points(ds: xr.Dataset) -> dict[str, np.ndarray]:
    """The points :func:`plot_lyapunov` draws for one sweep direction.

    Parameters
    ----------
    ds : xarray.Dataset
        One direction of a sweep (no ``direction`` dim).

    Returns
    -------
    dict of ndarray
        ``lyapunov``: boolean mask (eta,) of the points with a finite exponent, not
        diverged; ``error``: mask of those with a finite standard error too;
        ``floquet``: mask of the periodic points with a finite Floquet exponent.
    """
    n = ds.sizes["eta"]
    lam = _column(ds, "lyapunov", n)
    err = _column(ds, "lyapunov_err", n)
    fe = _column(ds, "floquet_exponent", n)
    reg = np.asarray(ds["regime"].values, dtype=int).reshape(n)
    live = reg != _DIVERGED
    ok = np.isfinite(lam) & live
    return {"lyapunov": ok, "error": ok & np.isfinite(err),
            "floquet": np.isfinite(fe) & live & (reg == _PERIODIC)}


def plot_lyapunov(ds: xr.Dataset, ax: Axes | None = None,
                  path: str | os.PathLike[str] | None = None, *,
                  figsize: tuple[float, float] | None = None, dpi: float | None = None,
                  style: str | None = None) -> Figure:
    """Draw the largest Lyapunov exponent of a sweep against eta, one panel per direction.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset (:func:`vibimpact.sweep` with the ``lyapunov`` and/or ``floquet``
        analysis, a file of ``vibimpact classify``), of any model: uses ``lyapunov``,
        ``regime``, ``period`` and, where present, ``lyapunov_err`` and
        ``floquet_exponent``.
    ax : matplotlib.axes.Axes or sequence of them, optional
        One Axes per sweep direction (up, then down); a new figure otherwise, the panels
        stacked and sharing eta (8 inches wide; one column, 3.5 wide, in the paper style).
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
        Naming ``ax``, ``figsize``, ``dpi`` or ``style``, or a dataset without
        ``lyapunov``.

    Notes
    -----
    Circles are the estimated exponents (:data:`LYAPUNOV_LABEL`), with error bars where
    the standard error is finite; diamonds the Floquet exponents of periodic points
    (:data:`FLOQUET_LABEL`), exact, so without bars.  Each marker has its point's regime
    colour (:func:`regime_color`); the legend lists the regimes drawn.  The dashed line
    is zero.  Diverged points are left out.
    """
    check_sweep(ds, "lyapunov", "regime", "period")
    lk = look(figsize, dpi, style, ax)
    require(ds, "lyapunov")  # after the options' checks
    dirs = directions(ds)
    with lk.context():
        own = ax is None
        if own:
            fig, axes = new_figure(lk, len(dirs), 1.8 + 2.4 * len(dirs),
                                   1.3 + 1.3 * len(dirs))
            for a in axes[1:]:
                a.sharey(axes[0])
        else:
            fig, axes = axes_of(ax, len(dirs), "one per sweep direction")
        used = {}
        for a, (d, sub) in zip(axes, dirs):
            used.update(_panel(a, sub, d, lk))
            if len(dirs) > 1:
                a.set_title(f"sweep {d}", loc="left", fontsize="small")
        axes[-1].set_xlabel(frequency_label(ds))
        _legend(axes[-1], own, used, lk)
        if own:
            lk.title(fig, title(ds))
        return lk.finish(fig, path)


def _panel(a, sub, d, lk):
    """One direction's exponents on ``a``; returns ``{order: (name, colour)}`` of the
    regimes drawn."""
    n = sub.sizes["eta"]
    eta = np.asarray(sub["eta"].values, dtype=float)
    lam = _column(sub, "lyapunov", n)
    err = _column(sub, "lyapunov_err", n)
    fe = _column(sub, "floquet_exponent", n)
    reg = np.asarray(sub["regime"].values, dtype=int).reshape(n)
    per = np.asarray(sub["period"].values, dtype=int).reshape(n)
    sel = exponent_points(sub)
    styles = [regime_color(r, p) for r, p in zip(reg, per)]
    colors = np.array([s[0] for s in styles], dtype=object)
    used = {}
    a.axhline(0.0, color="0.4", lw=width(0.53), ls="--", zorder=1)
    if sel["error"].any():
        k = sel["error"]
        a.errorbar(eta[k], lam[k], yerr=err[k], fmt="none", ecolor="0.35",
                   elinewidth=width(0.5), capsize=2.0, zorder=2)
    ms = 9.0 if lk.paper else 22.0
    for key, values, marker in (("lyapunov", lam, "o"), ("floquet", fe, "D")):
        k = sel[key]
        a.scatter(eta[k], values[k], c=list(colors[k]), marker=marker,
                  s=ms * (0.8 if marker == "D" else 1.0), edgecolors="0.15",
                  linewidths=width(0.3), zorder=3,
                  label=LYAPUNOV_LABEL if key == "lyapunov" else FLOQUET_LABEL)
        for i in np.flatnonzero(k):
            used[styles[i][2]] = (styles[i][1], styles[i][0])
    a.set_ylabel("exponent  (per unit τ)")
    a.grid(True, alpha=0.5)
    return used


def _legend(ax, own, used, lk):
    """The markers' meaning, the zero line and the regimes drawn, below the axes."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles: list[Artist] = [Line2D([], [], ls="none", marker="o", color="0.5", mec="0.15",
                      label=LYAPUNOV_LABEL),
               Line2D([], [], ls="none", marker="D", color="0.5", mec="0.15",
                      label=FLOQUET_LABEL),
               Line2D([], [], color="0.4", lw=width(0.53), ls="--", label="zero")]
    handles += [Patch(facecolor=c, edgecolor="0.15", label=name)
                for _, (name, c) in sorted(used.items())]
    lk.legend_below(ax, own, handles, ncol=min(len(handles), 3 if lk.paper else 4))
