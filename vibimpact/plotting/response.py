"""Response curves and the regime map of a sweep."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._sweep import (DIRECTION_COLORS, REGIME_NAMES, check_sweep, directions, grid_step,
                     new_figure, title)

if TYPE_CHECKING:  # names of the annotations only
    import os

    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: regime code -> band colour of :func:`plot_intervals` (periodic: by period, below)
REGIME_COLORS = {0: "0.85", 2: "tab:orange", 3: "tab:red", 4: "0.15", 5: "tab:purple"}
PERIOD_COLORS = ("#a1d99b", "#31a354", "#74c476", "#006d2c", "#c7e9c0", "#41ab5d")
LONG_PERIOD_COLOR = "#d9ef8b"


def _save(fig, path):
    if path is not None:
        from .xy import save_figure

        save_figure(fig, path)
    return fig


def plot_response(ds: xr.Dataset, ax: Axes | None = None,
                  path: str | os.PathLike[str] | None = None, bands: bool = True) -> Figure:
    """Response amplitudes X_m and Y_m against eta, chaotic points marked.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset with the ``response`` analysis: ``X_m``, ``Y_m``, ``regime``.
    ax : pair of matplotlib.axes.Axes, optional
        Axes for X_m and Y_m; a new 8 x 6.5 inch figure otherwise.
    path : str or os.PathLike, optional
        Save the figure there.
    bands : bool
        Regime bands behind the curves (needs ``label``, ``period``,
        ``impacts_per_period``): the up sweep's in the upper half of each panel, the down
        sweep's in the lower half, coloured as in :func:`plot_intervals`.

    Returns
    -------
    matplotlib.figure.Figure

    Notes
    -----
    Up and down sweeps are drawn in two colours; chaotic points carry a black cross and
    quasi-periodic ones a plus.  Diverged points are left out.  The dashed line at 1 is the
    retainer clearance.
    """
    check_sweep(ds, "X_m", "Y_m", "regime")
    if ax is None:
        fig, axes = new_figure(2, 6.5)
    else:
        axes = list(ax)
        if len(axes) != 2:
            raise ValueError("ax must be two Axes (for X_m and for Y_m)")
        fig = axes[0].figure
    band_handles = []
    if bands and all(v in ds for v in ("label", "period", "impacts_per_period")):
        band_handles = _bands(ds, axes)
    marked = set()
    for d, sub in directions(ds):
        eta = sub["eta"].values
        reg = np.asarray(sub["regime"].values, dtype=int)
        color = DIRECTION_COLORS.get(d, "tab:green")
        for a, name in zip(axes, ("X_m", "Y_m")):
            v = np.asarray(sub[name].values, dtype=float).copy()
            v[reg == 4] = np.nan
            a.plot(eta, v, color=color, lw=0.9, marker=".", ms=3, label=f"sweep {d}")
            for code, marker, ms in ((3, "x", 5), (2, "+", 6), (5, "1", 6)):
                sel = (reg == code) & np.isfinite(v)
                if sel.any():
                    lab = REGIME_NAMES[code] if (a, code) not in marked else None
                    marked.add((a, code))
                    a.plot(eta[sel], v[sel], ls="none", marker=marker, ms=ms, mew=1.0,
                           color="k", label=lab)
    for a, name in zip(axes, ("X_m", "Y_m")):
        a.axhline(1.0, color="0.4", lw=0.8, ls="--",
                  label="retainer clearance" if a is axes[0] else None)
        a.set_ylabel(f"{name}  (max |{name[0]}| / clearance)")
        a.grid(True, lw=0.4, alpha=0.5)
    axes[0].legend(loc="best", fontsize="small")
    if band_handles:
        axes[-1].legend(handles=band_handles, loc="upper center", bbox_to_anchor=(0.5, -0.18),
                        ncol=min(len(band_handles), 6), fontsize="small", frameon=False,
                        title="bands: up sweep (upper half), down sweep (lower half)"
                        if len(directions(ds)) > 1 else None, title_fontsize="small")
    axes[-1].set_xlabel("η")
    axes[0].set_title(title(ds), fontsize="medium")
    return _save(fig, path)


def _band(iv, k, h):
    """Extent, colour, legend name and key, and hatch of interval ``k`` of ``iv``.

    Impactless intervals are hatched ``///``, permanent contact ``...``.
    """
    a = min(iv["start"].values[k], iv["end"].values[k]) - h / 2
    b = max(iv["start"].values[k], iv["end"].values[k]) + h / 2
    reg = int(iv["regime"].values[k])
    per = int(iv["period"].values[k])
    if reg == 1 and per:
        color = PERIOD_COLORS[(per - 1) % len(PERIOD_COLORS)]
        name, key = f"P{per}", (1, per)
    elif reg == 1:
        color, name, key = LONG_PERIOD_COLOR, "periodic, long period", (1, 10**6)
    else:
        color = REGIME_COLORS.get(reg, "0.85")
        name, key = REGIME_NAMES.get(reg, "?"), (reg if reg else 9, 0)
    hatch = None
    if float(iv["impacts"].values[k]) == 0.0:
        hatch = "..." if "permanent contact" in str(iv["label"].values[k]) else "///"
    return a, b, color, name, key, hatch


def _bands(ds, axes):
    """Regime bands behind response curves: the up sweep in the upper half of each axes,
    the down sweep in the lower half; returns legend handles of the colours used."""
    from matplotlib.patches import Patch

    from ..sweeps.dataset import intervals

    h = grid_step(ds["eta"].values)
    dirs = directions(ds)
    used = {}
    for row, (d, sub) in enumerate(dirs):
        sub = sub.copy()
        sub.attrs["sweep_direction"] = d
        iv = intervals(sub)
        lo, hi = (0.0, 1.0) if len(dirs) == 1 else ((0.5, 1.0) if row == 0 else (0.0, 0.5))
        for k in range(iv.sizes["interval"]):
            a, b, color, name, key, hatch = _band(iv, k, h)
            used.setdefault(key, (name, color))
            for ax in axes:
                ax.axvspan(a, b, ymin=lo, ymax=hi, facecolor=color, alpha=0.35, lw=0,
                           hatch=hatch, edgecolor="0.6" if hatch else None, zorder=0)
    return [Patch(facecolor=c, alpha=0.35, label=n) for _, (n, c) in sorted(used.items())]


def _short(label, regime, period):
    if regime == 1:
        return f"P{period}" if period else "P"
    return {2: "QP", 3: "C", 4: "D", 5: "U"}.get(regime, "")


def plot_intervals(ds: xr.Dataset, ax: Axes | None = None,
                   path: str | os.PathLike[str] | None = None) -> Figure:
    """The regime map: coloured bands along eta, one row per sweep direction.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset (``label``, ``regime``, ``period``, ``impacts_per_period``).
    ax : matplotlib.axes.Axes, optional
    path : str or os.PathLike, optional
        Save the figure there.

    Returns
    -------
    matplotlib.figure.Figure

    Notes
    -----
    Each interval of :func:`vibimpact.intervals` (consecutive points with the same label)
    is a band from half a grid step before its first point to half a step after its last.
    Periodic bands are green (shades by period; yellow-green: periodic with a period too
    long to resolve), quasi-periodic orange, chaotic red,
    diverged black; impactless bands are hatched.  Wide bands carry a short label (P1,
    P2, QP, C, D).
    """
    from matplotlib.patches import Patch

    from ..sweeps.dataset import intervals

    check_sweep(ds, "label", "regime", "period", "impacts_per_period")
    dirs = directions(ds)
    if ax is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=(9, 1.2 + 0.7 * len(dirs)), layout="constrained")
        ax = fig.add_subplot()
    fig = ax.figure
    eta = ds["eta"].values
    h = grid_step(eta)
    span = float(eta.max() - eta.min()) + h
    used = {}
    for row, (d, sub) in enumerate(dirs):
        sub = sub.copy()
        sub.attrs["sweep_direction"] = d
        iv = intervals(sub)
        for k in range(iv.sizes["interval"]):
            a, b, color, name, key, hatch = _band(iv, k, h)
            ax.broken_barh([(a, b - a)], (row - 0.4, 0.8), facecolors=color,
                           edgecolors="white", linewidth=0.3, hatch=hatch)
            used.setdefault(key, (name, color))
            if (b - a) > 0.035 * span:
                reg = int(iv["regime"].values[k])
                ax.text((a + b) / 2, row, _short(iv["label"].values[k], reg,
                                                 int(iv["period"].values[k])),
                        ha="center", va="center", fontsize="small",
                        color="white" if reg in (3, 4) else "black")
    ax.set_yticks(range(len(dirs)), [f"sweep {d}" for d, _ in dirs])
    ax.set_ylim(len(dirs) - 0.5, -0.5)
    ax.set_xlim(float(eta.min()) - h / 2, float(eta.max()) + h / 2)
    ax.set_xlabel("η")
    handles = [Patch(facecolor=c, label=n) for _, (n, c) in sorted(used.items())]
    handles += [Patch(facecolor="white", edgecolor="0.3", hatch="///", label="impactless"),
                Patch(facecolor="white", edgecolor="0.3", hatch="...",
                      label="permanent contact")]
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.35 if
              len(dirs) == 1 else -0.22), ncol=min(len(handles), 7), fontsize="small",
              frameon=False)
    ax.set_title(title(ds), fontsize="medium")
    return _save(fig, path)
