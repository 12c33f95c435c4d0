"""Poincaré section of a sweep: the stroboscopic samples of every point in one plane,
coloured by eta.

A sweep stores, per point, ``n_samples`` stroboscopic (Poincaré) samples ``x(tau_k)``,
``tau_k = 2 pi k / eta`` (Guckenheimer & Holmes 1983, sec. 1.5), of its first two states
(``poincare_X``, ``poincare_Y``) and of every further state ``s`` as ``poincare_s``
(files written before that hold the first two only; :func:`poincare_variable` finds a
state's samples by its name).  :func:`plot_poincare` draws the first state against its
velocity when the file stores that velocity (the built-in rotor: ``X`` against ``dX``; the
Duffing and soft-impact models: ``x`` against ``dx``), else against the second stored
state (for the built-in rotor: ``X`` against ``Y``, the section's projection on its
clearance plane).  A periodic orbit of period n shows n dots, quasi-periodic motion a
closed curve, chaos a fractal cloud (Moon 1987, ch. 2).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._sweep import axes_of, check_sweep, directions, frequency_label, title
from .needs import require
from .style import look

if TYPE_CHECKING:  # names of the annotations only
    import os

    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["plot_poincare", "poincare_variable", "section_states", "section_samples",
           "state_names"]

#: regime code of a diverged point (its samples, where any, are left out)
_DIVERGED = 4


def state_names(ds: xr.Dataset) -> tuple[str, ...]:
    """The names of the states of the model a sweep dataset records: its ``state``
    coordinate, else the built-in model its ``model`` attribute names (a dataset that
    names none is refused: ValueError), else the names of the stored samples
    ``poincare_X``, ``poincare_Y``."""
    from .. import models
    from ..io.recorded import model_name

    if "state" in ds.coords:
        return tuple(str(s) for s in ds["state"].values)
    name = model_name(ds.attrs, "ds")
    if isinstance(name, str) and name in models.names():
        return tuple(models.get(name).state_names)
    return ("X", "Y")


def _stored(ds, names):
    """``{state index: variable name}`` of the Poincaré samples the dataset holds."""
    out = {}
    for j, name in enumerate(names):
        var = {0: "poincare_X", 1: "poincare_Y"}.get(j, f"poincare_{name}")
        if var in ds:
            out[j] = var
    return out


def poincare_variable(ds: xr.Dataset, name: str) -> tuple[str, str]:
    """The variable of a sweep dataset that holds the Poincaré samples of state ``name``.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset (:func:`state_names` says which states its model has).
    name : str
        A state name of the model (``"X"``, ``"dY"``, ``"Vr"``, ``"x"``), matched exactly,
        else ignoring case where that is unique; ``"X'"`` (a prime) stands for ``"dX"``.

    Returns
    -------
    (str, str)
        ``(variable, state name)``: ``("poincare_Vr", "Vr")``.

    Raises
    ------
    TypeError
        When ``name`` is not a str.
    ValueError
        Naming ``name``: not a state of the model, or a state whose samples the dataset
        does not hold; the message lists those it holds.
    """
    if not isinstance(name, str):
        raise TypeError(f"state must be a state name (str), got {type(name).__name__} "
                        f"{name!r}"[:200])
    names = state_names(ds)
    stored = _stored(ds, names)
    held = ", ".join(names[j] for j in sorted(stored)) or "none"
    key = name.strip()
    key = "d" + key[:-1] if key.endswith("'") else key
    if key not in names:
        folded = [n for n in names if n.lower() == key.lower()]
        if len(folded) != 1:
            raise ValueError(f"state {name!r} is no state of the model ({', '.join(names)}; "
                             "X' stands for dX)")
        key = folded[0]
    j = names.index(key)
    if j not in stored:
        raise ValueError(f"the sweep dataset holds no Poincaré samples of {key}; it holds "
                         f"those of {held}")
    return stored[j], key


def section_states(ds: xr.Dataset) -> tuple[tuple[str, str], tuple[str, str]]:
    """Which stored samples :func:`plot_poincare` draws, and the states they are.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset with ``poincare_X`` and ``poincare_Y``.

    Returns
    -------
    ((str, str), (str, str))
        ``((horizontal variable, its state name), (vertical variable, its state name))``:
        the first state, and its velocity ``d<first>`` when stored, else the second state.

    Raises
    ------
    ValueError
        When the dataset holds no Poincaré samples of its first two states.
    """
    names = state_names(ds)
    stored = _stored(ds, names)
    if 0 not in stored or 1 not in stored:
        raise ValueError("the sweep dataset has no poincare_X, poincare_Y (the Poincaré "
                         "samples of its first two states)")
    v = names.index("d" + names[0]) if "d" + names[0] in names else 1
    v = v if v in stored else 1
    return (stored[0], names[0]), (stored[v], names[v] if v < len(names) else "Y")


def section_samples(ds: xr.Dataset) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The finite Poincaré samples of one sweep direction, as :func:`plot_poincare`
    draws them.

    Parameters
    ----------
    ds : xarray.Dataset
        One direction of a sweep (no ``direction`` dim), with ``poincare_X``,
        ``poincare_Y`` (``eta``, ``sample``).

    Returns
    -------
    (h, v, eta) : ndarray, shape (m,) each
        Horizontal and vertical coordinates (:func:`section_states`) of every sample
        finite in both, eta of its point; points whose ``regime`` is diverged are left
        out.  Sample order: by eta, then by sample.
    """
    (hx, _), (vx, _) = section_states(ds)
    eta = np.asarray(ds["eta"].values, dtype=float)
    h = np.asarray(ds[hx].transpose("eta", ...).values, dtype=float).reshape(eta.size, -1)
    v = np.asarray(ds[vx].transpose("eta", ...).values, dtype=float).reshape(eta.size, -1)
    ok = np.isfinite(h) & np.isfinite(v)
    if "regime" in ds:
        ok &= (np.asarray(ds["regime"].values) != _DIVERGED)[:, None]
    e = np.broadcast_to(eta[:, None], h.shape)
    return h[ok], v[ok], e[ok]


def plot_poincare(ds: xr.Dataset, ax: Axes | None = None,
                  path: str | os.PathLike[str] | None = None, *,
                  figsize: tuple[float, float] | None = None, dpi: float | None = None,
                  style: str | None = None) -> Figure:
    """Draw the Poincaré section of a sweep: the samples of every point, coloured by eta.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset with the ``poincare`` analysis (:func:`vibimpact.sweep`, a file of
        ``vibimpact classify`` or ``vibimpact bifurcation``), of any model: uses
        ``poincare_X``, ``poincare_Y`` (``eta``, ``sample`` [, ``direction``]), the
        ``state`` coordinate (or the ``model`` attribute) for the axis names and
        ``regime`` where present.
    ax : matplotlib.axes.Axes or sequence of them, optional
        One Axes per sweep direction (up, then down); a new figure otherwise, the panels
        side by side (11 x 5 inches for two, 6.5 x 5.5 for one; one column, 3.5 wide, in
        the paper style).
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
        Naming ``ax``, ``figsize``, ``dpi`` or ``style``, or a dataset without Poincaré
        samples.

    Notes
    -----
    Each panel holds one scatter of :func:`section_samples` (every finite sample of
    every point not diverged, a periodic orbit's cycle repeated as the file stores it),
    coloured by eta on one scale for all panels, with its colour bar.  The horizontal
    axis is the model's first state, the vertical axis its velocity where the file
    stores it, else its second state (:func:`section_states`).

    Examples
    --------
    >>> from vibimpact.io import read_netcdf
    >>> from vibimpact.plotting.poincare import plot_poincare
    >>> fig = plot_poincare(read_netcdf("fig8.nc"), path="poincare.png")  # doctest: +SKIP
    """
    from matplotlib.colors import Normalize

    check_sweep(ds, "poincare_X", "poincare_Y")
    (_, hname), (_, vname) = section_states(ds)
    lk = look(figsize, dpi, style, ax)
    require(ds, "poincare")  # after the options' checks
    dirs = directions(ds)
    eta = np.asarray(ds["eta"].values, dtype=float)
    norm = Normalize(float(eta.min()), float(eta.max())) if eta.size else Normalize()
    with lk.context():
        own = ax is None
        if own:
            n = len(dirs)
            fig = lk.figure((5.2 * n + 0.8, 5.0 if n > 1 else 5.5), 2.1 if n > 1 else 3.0)
            axes = list(fig.subplots(1, n, sharex=True, sharey=True, squeeze=False)[0])
        else:
            fig, axes = axes_of(ax, len(dirs), "one per sweep direction")
        sc = None
        for a, (d, sub) in zip(axes, dirs):
            h, v, e = section_samples(sub)
            sc = a.scatter(h, v, c=e, cmap="viridis", norm=norm, s=2.0 if lk.paper else 5.0,
                           linewidths=0, rasterized=True, label=f"sweep {d}")
            a.set_xlabel(f"{hname}  (Poincaré)")
            a.grid(True, alpha=0.5)
            if len(dirs) > 1:
                a.set_title(f"sweep {d}", loc="left", fontsize="small")
        axes[0].set_ylabel(f"{vname}  (Poincaré)")
        fig.colorbar(sc, ax=axes, label=frequency_label(ds), shrink=0.9)
        if own:
            lk.title(fig, title(ds))
        return lk.finish(fig, path)
