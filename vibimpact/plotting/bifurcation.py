"""Bifurcation diagram: the Poincaré (stroboscopic) points of a sweep against eta, of the
model's first two states or of any states the sweep stores (a ring's speed ``Vr``)."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..base import _validate as _v
from ._sweep import (DIRECTION_COLORS, axes_of, check_sweep, directions, frequency_label,
                     new_figure, title)
from .poincare import poincare_variable, state_names
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
    The up and down sweeps are drawn as small dots in two colours: where they differ the
    motion depends on the history (hysteresis, coexisting attractors).  A periodic orbit
    of period n shows n dots above its eta, chaos a vertical smear.  Lengths are in
    clearances; +Y points down, along gravity.  Each panel's line of a direction holds
    exactly the finite samples of its variable (by eta, then by sample).

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
        _draw(ds, axes, lk, drawn)
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


def _draw(ds, axes, lk, drawn):
    """The Poincaré points of every direction on ``axes``, one per ``(variable, name)``
    of ``drawn``."""
    for d, sub in directions(ds):
        eta = sub["eta"].values
        color = DIRECTION_COLORS.get(d, "tab:green")
        for a, (var, _) in zip(axes, drawn):
            v = np.asarray(sub[var].transpose("eta", ...).values, dtype=float)
            v = v.reshape(eta.size, -1)
            e = np.broadcast_to(eta[:, None], v.shape)
            ok = np.isfinite(v)
            a.plot(e[ok], v[ok], ls="none", marker=".", ms=1.5, mew=0, color=color,
                   alpha=0.7, rasterized=True, label=f"sweep {d}")
    for a, (_, name) in zip(axes, drawn):
        a.set_ylabel(_LABELS.get(name, f"{name}  (Poincaré)"))
    axes[-1].set_xlabel(frequency_label(ds))
    for a in axes:
        a.grid(True, alpha=0.5)
    leg = lk.legend(axes[0], markerscale=6)
    for h in leg.legend_handles:
        h.set_alpha(1.0)
    lk.title(axes[0], title(ds))
