"""Bifurcation diagram: the Poincaré (stroboscopic) points of a sweep against eta, of the
model's first two states or of any states the sweep stores (a ring's speed ``Vr``)."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..base import _validate as _v
from ._sweep import (DIRECTION_COLORS, axes_of, check_sweep, directions, frequency_label,
                     grid_step, new_figure, title)
from .poincare import poincare_variable, state_names
from .needs import require
from .style import look

if TYPE_CHECKING:  # names of the annotations only
    import os
    from collections.abc import Sequence

    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


def plot_bifurcation(ds: xr.Dataset, ax: Axes | None = None,
                     path: str | os.PathLike[str] | None = None, *,
                     states: str | Sequence[str] | None = None,
                     figsize: tuple[float, float] | None = None, dpi: float | None = None,
                     style: str | None = None) -> Figure:
    """Draw the Poincaré points of a sweep against eta: X and Y (two panels), or the
    states named.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset (:func:`vibimpact.sweep` with the ``poincare`` analysis, or a file
        of ``vibimpact classify`` / ``vibimpact bifurcation``), of any model; uses
        ``poincare_X``, ``poincare_Y`` (``eta``, ``sample`` [, ``direction``]) and the
        ``poincare_<state>`` samples of the other states named by ``states``.
    ax : matplotlib.axes.Axes or sequence of them, optional
        One Axes per state drawn (X and Y by default); a new figure otherwise, 8 inches
        wide and 2.75 high per panel plus 1 (one column, 3.5 wide and 1.6 per panel plus
        0.4, in the paper style).
    states : str or sequence of str, optional
        The states drawn, one panel each, by their names in the model (``"Vr"``,
        ``("X", "Vr")``; ``"X'"`` stands for ``"dX"``,
        :func:`vibimpact.plotting.poincare.poincare_variable`).  Default: the model's
        first two states (the built-in rotor's X and Y).
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
        Naming ``ax``, ``figsize``, ``dpi``, ``style`` or ``states`` (a name that is no
        state of the model, or one whose samples the dataset does not hold).

    Notes
    -----
    The up sweep is drawn as small filled dots and the down sweep as rings, in two
    colours (:data:`DIRECTION_MARKS`): where both sweeps find the same point the dot sits
    inside the ring, where they differ the motion depends on the history (hysteresis,
    coexisting attractors).  Behind the points, bands coloured by the regime of each eta
    in the dataset (``regime``, ``period``; the colours and legend of
    :func:`vibimpact.plotting.plot_response`'s bands, :func:`regime_bands`): the up
    sweep's in the upper half of each panel, the down sweep's in the lower half; drawn
    when the dataset holds the intervals' ``label``, ``impacts_per_period`` and ``arcs``
    too.  A periodic orbit of period n shows n dots above its eta, chaos a vertical
    smear.  Lengths are in clearances; +Y points down, along gravity.  Each panel's line
    of a direction holds exactly the finite samples of its variable (by eta, then by
    sample).

    Examples
    --------
    >>> from vibimpact.io import read_netcdf
    >>> from vibimpact.plotting import plot_bifurcation
    >>> fig = plot_bifurcation(read_netcdf("bif.nc"), path="bif.png")  # doctest: +SKIP
    >>> fig = plot_bifurcation(read_netcdf("ring.nc"), states="Vr")  # doctest: +SKIP
    """
    check_sweep(ds, "poincare_X", "poincare_Y")
    drawn = _drawn(ds, states)
    lk = look(figsize, dpi, style, ax)
    n = len(drawn)
    with lk.context():
        if ax is None:
            fig, axes = new_figure(lk, n, 1.0 + 2.75 * n, 0.4 + 1.6 * n)
        else:
            fig, axes = axes_of(ax, n, "one per state drawn: "
                                + ", ".join(name for _, name in drawn))
        require(ds, "bifurcation")  # after the options' checks, before any drawing
        _draw(ds, axes, lk, drawn, own=ax is None)
        return lk.finish(fig, path)


def _drawn(ds, states):
    """``[(variable, state name), ...]`` of the panels, from ``states``."""
    if states is None:
        names = state_names(ds)
        return [("poincare_X", names[0] if names else "X"),
                ("poincare_Y", names[1] if len(names) > 1 else "Y")]
    if isinstance(states, str):
        states = [states]
    try:
        states = list(states)
    except TypeError:
        raise _v.WrongType(f"states must be a state name or a sequence of them, got "
                           f"{type(states).__name__} {states!r}"[:200]) from None
    if not states:
        raise ValueError("states must name at least one state")
    drawn = [poincare_variable(ds, name) for name in states]
    if len({v for v, _ in drawn}) != len(drawn):
        raise ValueError(f"states names a state twice: {states!r}"[:200])
    return drawn


#: a panel's label by its state name (default: "NAME  (Poincaré)")
_LABELS = {"Y": "Y  (Poincaré, +Y down)"}


#: marks of each sweep direction: the up sweep's small filled dots sit inside the down
#: sweep's rings where the two coincide, so that both show (markersize in points, edge
#: width as a factor of the style's line width)
DIRECTION_MARKS: dict[str, dict[str, Any]] = {
    "up": dict(marker="o", ms=1.6, mew=0.0, alpha=0.8),
    "down": dict(marker="o", ms=3.6, mfc="none", mew=0.33, alpha=0.8)}
#: the markers' size in the paper style, as a share of the default's (a narrow column)
PAPER_MARK_SCALE = 0.7
#: the variables the regime bands need (:func:`vibimpact.sweeps.dataset.intervals`'s)
BAND_VARS = ("regime", "label", "period", "impacts_per_period", "arcs")


def direction_marks(d, paper=False):
    """The ``plot`` keywords of the marks of sweep direction ``d``
    (:data:`DIRECTION_MARKS`; another direction: the up sweep's), scaled for the
    style."""
    from .style import width

    marks = dict(DIRECTION_MARKS.get(d, DIRECTION_MARKS["up"]))
    if paper:
        marks["ms"] *= PAPER_MARK_SCALE
    marks["mew"] = width(marks["mew"])
    return marks


def regime_bands(ds, axes, lk, own):
    """Bands behind the points of ``axes``, one per interval of
    :func:`vibimpact.sweeps.dataset.intervals` (consecutive points of one label) from half
    a grid step before its first eta to half a step after its last, in the colour of its
    regime class (:func:`vibimpact.plotting.style.class_color`, the response and interval
    plots' colours): the up sweep's in the upper half of each panel, the down sweep's in
    the lower half; their legend below (:func:`vibimpact.plotting.response.band_legend`;
    ``own``: the figure is plot_bifurcation's).  Returns the bands' ``(start, end,
    colour, name, key, hatch)``."""
    from ..sweeps.dataset import intervals
    from .response import band_legend
    from .style import BAND_ALPHA, class_color

    h = grid_step(ds["eta"].values)
    dirs = directions(ds)
    bands = []
    for row, (d, sub) in enumerate(dirs):
        sub = sub.copy()
        sub.attrs["sweep_direction"] = d
        iv = intervals(sub)
        lo, hi = (0.0, 1.0) if len(dirs) < 2 else ((0.5, 1.0) if row == 0 else (0.0, 0.5))
        for k in range(iv.sizes["interval"]):
            s, e = sorted((float(iv["start"].values[k]), float(iv["end"].values[k])))
            color, name, key = class_color(iv["regime"].values[k], iv["period"].values[k])
            bands.append((s - h / 2, e + h / 2, color, name, key, None))
            for ax in axes:
                ax.axvspan(s - h / 2, e + h / 2, ymin=lo, ymax=hi, facecolor=color,
                           alpha=BAND_ALPHA, lw=0, zorder=0)
    if bands:
        band_legend(axes[-1], own, bands, lk, alpha=BAND_ALPHA,
                    title="bands: up sweep (upper half), down sweep (lower half)"
                    if len(dirs) > 1 else None)
    return bands


def _draw(ds, axes, lk, drawn, own):
    """The regime bands and the Poincaré points of every direction on ``axes``, one per
    ``(variable, name)`` of ``drawn`` (``own``: the figure is plot_bifurcation's)."""
    if all(v in ds for v in BAND_VARS):
        regime_bands(ds, axes, lk, own)
    for d, sub in directions(ds):
        eta = sub["eta"].values
        color = DIRECTION_COLORS.get(d, "tab:green")
        marks = direction_marks(d, lk.paper)
        what = "dots" if marks.get("mfc") != "none" else "rings"
        for a, (var, _) in zip(axes, drawn):
            v = np.asarray(sub[var].transpose("eta", ...).values, dtype=float)
            v = v.reshape(eta.size, -1)
            e = np.broadcast_to(eta[:, None], v.shape)
            ok = np.isfinite(v)
            a.plot(e[ok], v[ok], ls="none", color=color, rasterized=True, zorder=2,
                   label=f"sweep {d} ({what})", **marks)
    for a, (_, name) in zip(axes, drawn):
        a.set_ylabel(_LABELS.get(name, f"{name}  (Poincaré)"))
    axes[-1].set_xlabel(frequency_label(ds))
    for a in axes:
        a.grid(True, alpha=0.5)
    leg = lk.legend(axes[0])
    for h in leg.legend_handles:
        h.set_alpha(1.0)
        h.set_markersize(LEGEND_MARK_SIZE if h.get_markerfacecolor() != "none"
                         else 1.6 * LEGEND_MARK_SIZE)
    lk.title(axes[0], title(ds))


#: size (points) of the filled dot in the legend (a ring: 1.6 times it)
LEGEND_MARK_SIZE = 5.0
