"""Response curves and the regime map of a sweep."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..base import _validate as _v
from ._sweep import (DIRECTION_COLORS, REGIME_NAMES, axes_of, check_sweep, directions,
                     frequency_label, grid_step, new_figure, spec, title)
from .needs import require
from .style import (BAND_ALPHA, LONG_PERIOD_COLOR, PERIOD_COLORS, REGIME_COLORS, class_color,
                    look, text_color, width)

if TYPE_CHECKING:  # names of the annotations only
    import os

    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

# the band colours (REGIME_COLORS, PERIOD_COLORS, LONG_PERIOD_COLOR, imported above and
# kept importable from here) are the regime classes' of vibimpact.plotting.style
__all__ = ["LONG_PERIOD_COLOR", "PERIOD_COLORS", "REGIME_COLORS", "band_legend",
           "plot_intervals", "plot_response"]
#: the response curves' marker sizes in the paper style, as a share of the default's:
#: sixty points across one 3.5 inch column crowd at the default's sizes
PAPER_MARKER_SCALE = 0.5
#: hatching of a band -> its legend entry, which says what it means
HATCHES = {"///": "hatched ///: impactless", "...": "dotted ...: permanent contact"}


@_v.checks_flags
def plot_response(ds: xr.Dataset, ax: Axes | None = None,
                  path: str | os.PathLike[str] | None = None, bands: bool = True, *,
                  figsize: tuple[float, float] | None = None, dpi: float | None = None,
                  style: str | None = None) -> Figure:
    """Response amplitudes X_m and Y_m against the forcing frequency, chaotic points
    marked, labelled with the model's own names (:class:`vibimpact.models.PlotSpec`).

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset with the ``response`` analysis: ``X_m``, ``Y_m``, ``regime``.
    ax : pair of matplotlib.axes.Axes, optional
        Axes for X_m and Y_m; a new 8 x 6.5 inch figure otherwise (one column, 3.5 x 4
        inches, in the paper style).
    path : str or os.PathLike, optional
        Save the figure there.
    bands : bool
        Regime bands behind the curves (needs ``label``, ``period``,
        ``impacts_per_period``): the up sweep's in the upper half of each panel, the down
        sweep's in the lower half, coloured and hatched as in :func:`plot_intervals`.
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
        Naming ``ax``, ``figsize``, ``dpi`` or ``style``; for a dataset that names no
        model; or, in one line, for a sweep whose model records no response maxima (all
        ``X_m`` and ``Y_m`` missing: a model without a planar contact on two positions).

    Notes
    -----
    Up and down sweeps are drawn in two colours; chaotic points carry a black cross and
    quasi-periodic ones a plus.  Diverged points are left out.  A model with a circular
    obstacle (:attr:`~vibimpact.models.PlotSpec.circle`) has its radius drawn as a dashed
    line (e.g. the built-in rotor's retainer clearance).
    """
    check_sweep(ds, "X_m", "Y_m", "regime")
    lk = look(figsize, dpi, style, ax)
    with lk.context():
        if ax is None:
            fig, axes = new_figure(lk, 2, 6.5, 4.0)
        else:
            fig, axes = axes_of(ax, 2, "for X_m and for Y_m")
        _check_response(ds)  # after the options' checks, before anything is drawn
        if bands and all(v in ds for v in ("label", "period", "impacts_per_period")):
            _bands(ds, axes, lk, own=ax is None)
        _curves(ds, axes, lk)
        return lk.finish(fig, path)


def _check_response(ds):
    """ValueError, one line, for a sweep whose points hold no response maximum."""
    if not any(np.isfinite(np.asarray(ds[v].values, dtype=float)).any()
               for v in ("X_m", "Y_m")):
        model = ds.attrs.get("model")
        raise ValueError(f"the sweep of the {model} model records no response maxima "
                         "(X_m, Y_m all missing: they are those of a planar contact on "
                         "two positions, or the 'response' analysis was not run); plot "
                         "another kind")


def _response_labels(ds):
    """``(label of X_m, label of Y_m)``: the maxima of the model's two contact positions
    (their state names) in its length unit."""
    from .. import models

    sp = spec(ds)
    name = ds.attrs.get("model")
    model = models.get(name) if name in models.names() else None
    states = ("X", "Y")  # the variables' own letters, for a model this installation lacks
    if model is not None and model.contact is not None and \
            len(model.contact.positions) == 2:
        states = tuple(model.state_names[i] for i in model.contact.positions)
    unit = f" / {sp.length_unit}" if sp.length_unit else ""
    return tuple(f"{v}  (max |{s}|{unit})" for v, s in zip(("X_m", "Y_m"), states))


def _curves(ds, axes, lk):
    """The response maxima of every direction on ``axes`` (X_m, Y_m), their legend."""
    marked = set()
    scale = PAPER_MARKER_SCALE if lk.paper else 1.0  # a narrow column: the points crowd
    for d, sub in directions(ds):
        eta = sub["eta"].values
        reg = np.asarray(sub["regime"].values, dtype=int)
        color = DIRECTION_COLORS.get(d, "tab:green")
        for a, name in zip(axes, ("X_m", "Y_m")):
            v = np.asarray(sub[name].values, dtype=float).copy()
            v[reg == 4] = np.nan
            a.plot(eta, v, color=color, lw=width(0.6), marker=".", ms=3 * scale,
                   label=f"sweep {d}")
            for code, marker, ms in ((3, "x", 5 * scale), (2, "+", 6 * scale),
                                     (5, "1", 6 * scale)):
                sel = (reg == code) & np.isfinite(v)
                if sel.any():
                    lab = REGIME_NAMES[code] if (a, code) not in marked else None
                    marked.add((a, code))
                    a.plot(eta[sel], v[sel], ls="none", marker=marker, ms=ms,
                           mew=width(0.67), color="k", label=lab)
    sp = spec(ds)
    for a, label in zip(axes, _response_labels(ds)):
        if sp.circle is not None:
            a.axhline(sp.circle, color="0.4", lw=width(0.53), ls="--",
                      label=sp.circle_name if a is axes[0] else None)
        a.set_ylabel(label)
        a.grid(True, alpha=0.5)
    lk.legend(axes[0])
    axes[-1].set_xlabel(frequency_label(ds))
    lk.title(axes[0], title(ds))


def _band(iv, k, h):
    """Extent, colour, legend name and key, and hatch of interval ``k`` of ``iv``.

    Impactless intervals are hatched ``///``, permanent contact ``...``.
    """
    a = min(iv["start"].values[k], iv["end"].values[k]) - h / 2
    b = max(iv["start"].values[k], iv["end"].values[k]) + h / 2
    color, name, key = class_color(iv["regime"].values[k], iv["period"].values[k])
    hatch = None
    if float(iv["impacts"].values[k]) == 0.0:
        hatch = "..." if "permanent contact" in str(iv["label"].values[k]) else "///"
    return a, b, color, name, key, hatch


def _each_band(ds):
    """``(row, iv, k, band)`` for interval ``k`` of the intervals ``iv`` of every sweep
    direction (``row`` 0, 1 in the order of :func:`directions`), ``band`` from
    :func:`_band`."""
    from ..sweeps.dataset import intervals

    h = grid_step(ds["eta"].values)
    for row, (d, sub) in enumerate(directions(ds)):
        sub = sub.copy()
        sub.attrs["sweep_direction"] = d
        iv = intervals(sub)
        for k in range(iv.sizes["interval"]):
            yield row, iv, k, _band(iv, k, h)


def band_legend(ax, own, bands, lk, alpha=1.0, title=None):
    """A legend below the axes (:meth:`Look.legend_below`) of the bands drawn: one entry
    per colour present and one per hatching present, which says what the hatching
    means."""
    from matplotlib.patches import Patch

    used: dict[tuple[int, int], tuple[str, str]] = {}  # {key: (name, colour)}
    hatches = set()
    for _, _, color, name, key, hatch in bands:
        used.setdefault(key, (name, color))
        hatches.add(hatch)
    handles = [Patch(facecolor=c, alpha=alpha, label=n) for _, (n, c) in sorted(used.items())]
    handles += [Patch(facecolor="white", edgecolor="0.4", hatch=h, label=text)
                for h, text in HATCHES.items() if h in hatches]
    return lk.legend_below(ax, own, handles, title=title,
                           ncol=min(len(handles), 3 if lk.paper else 6))


def _bands(ds, axes, lk, own):
    """Regime bands behind response curves, the up sweep in the upper half of each axes,
    the down sweep in the lower half, and their legend below the axes (``own``: the
    figure is the plotting function's)."""
    two = "direction" in ds.dims and ds.sizes["direction"] > 1
    bands = []
    for row, _, _, band in _each_band(ds):
        a, b, color, _, _, hatch = band
        lo, hi = (0.0, 1.0) if not two else ((0.5, 1.0) if row == 0 else (0.0, 0.5))
        bands.append(band)
        for ax in axes:
            ax.axvspan(a, b, ymin=lo, ymax=hi, facecolor=color, alpha=BAND_ALPHA, lw=0,
                       hatch=hatch, edgecolor="0.6" if hatch else None, zorder=0)
    if bands:
        band_legend(axes[-1], own, bands, lk, alpha=BAND_ALPHA,
                    title="bands: up sweep (upper half), down sweep (lower half)"
                    if two else None)


def _short(label, regime, period):
    if regime == 1:
        return f"P{period}" if period else "P"
    return {2: "QP", 3: "C", 4: "D", 5: "U"}.get(regime, "")


def plot_intervals(ds: xr.Dataset, ax: Axes | None = None,
                   path: str | os.PathLike[str] | None = None, *,
                   figsize: tuple[float, float] | None = None, dpi: float | None = None,
                   style: str | None = None) -> Figure:
    """The regime map: coloured bands along eta, one row per sweep direction.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset (``label``, ``regime``, ``period``, ``impacts_per_period``).
    ax : matplotlib.axes.Axes, optional
        Draw into these axes; a new figure 9 inches wide otherwise (one column, 3.5
        inches, in the paper style).
    path : str or os.PathLike, optional
        Save the figure there.
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
    Each interval of :func:`vibimpact.intervals` (consecutive points with the same label)
    is a band from half a grid step before its first point to half a step after its last.
    Periodic bands are green (shades by period; yellow-green: periodic with a period too
    long to resolve), quasi-periodic orange, chaotic red,
    diverged black; impactless bands are hatched ``///``, permanent contact dotted; the
    legend lists the colours and hatchings present.  Wide bands carry a short label (P1,
    P2, QP, C, D).
    """
    check_sweep(ds, "label", "regime", "period", "impacts_per_period")
    lk = look(figsize, dpi, style, ax)
    require(ds, "intervals")  # after the options' checks
    n = len(directions(ds))
    with lk.context():
        own = ax is None
        if ax is None:
            ax = lk.figure((9, 1.6 + 0.7 * n), 1.4 + 0.35 * n).add_subplot()
        _interval_rows(ds, ax, lk, own)
        return lk.finish(ax.figure, path)


def _interval_rows(ds, ax, lk, own):
    """The bands of every direction as rows of ``ax``, their labels and legend."""
    eta = ds["eta"].values
    h = grid_step(eta)
    span = float(eta.max() - eta.min()) + h
    bands = []
    for row, iv, k, band in _each_band(ds):
        a, b, color, _, _, hatch = band
        bands.append(band)
        ax.broken_barh([(a, b - a)], (row - 0.4, 0.8), facecolors=color,
                       edgecolors="white", linewidth=width(0.2), hatch=hatch)
        if (b - a) > 0.035 * span:
            reg = int(iv["regime"].values[k])
            ax.text((a + b) / 2, row, _short(iv["label"].values[k], reg,
                                             int(iv["period"].values[k])),
                    ha="center", va="center", fontsize="small",
                    color=text_color(color))
    dirs = directions(ds)
    ax.set_yticks(range(len(dirs)), [f"sweep {d}" for d, _ in dirs])
    ax.set_ylim(len(dirs) - 0.5, -0.5)
    ax.set_xlim(float(eta.min()) - h / 2, float(eta.max()) + h / 2)
    ax.set_xlabel(frequency_label(ds))
    band_legend(ax, own, bands, lk)
    lk.title(ax, title(ds))
