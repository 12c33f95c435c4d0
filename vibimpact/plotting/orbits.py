"""The orbits of an orbit hunt against the forcing frequency: one horizontal bar per
orbit over the interval where it exists, solid where it is stable and dashed where it is
not (the convention of bifurcation diagrams, Seydel 2010 sec. 2.2), each labelled with
its period, impacts per period and stability at the hunt's value.

:func:`plot_orbits` reads only the dataset of :func:`vibimpact.orbits.hunt_to_dataset`
(a ``vibimpact orbits`` file).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # names of the annotations only
    import os

    import xarray as xr
    from matplotlib.figure import Figure

__all__ = ["plot_orbits", "PERIOD_COLORS"]

#: colour of an orbit's bar by its period (cycled)
PERIOD_COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple",
                 "tab:brown", "tab:pink", "tab:olive", "tab:cyan", "k")


def _stretches(vals, stable):
    """``(lo, hi, stable)`` runs along a branch's points (between neighbours of
    different stability, the change drawn halfway)."""
    out, i = [], 0
    while i < vals.size:
        j = i
        while j + 1 < vals.size and stable[j + 1] == stable[i]:
            j += 1
        lo = vals[i] if i == 0 else 0.5 * (vals[i - 1] + vals[i])
        hi = vals[j] if j == vals.size - 1 else 0.5 * (vals[j] + vals[j + 1])
        out.append((float(lo), float(hi), bool(stable[i])))
        i = j + 1
    return out


def _bars(ds, i, param):
    """The stretches of orbit ``i``: along its continued branch, or the hunt's value
    alone."""
    name = f"branch_{param}"
    vals = ds[name].values[i] if name in ds else np.zeros(0)
    keep = np.isfinite(vals)
    if keep.any():
        return _stretches(vals[keep], ds["branch_stable"].values[i][keep] == 1)
    v = float(ds.attrs["forcing_value"])
    return [(v, v, bool(ds["stable"].values[i]))]


def plot_orbits(ds: xr.Dataset, path: str | os.PathLike[str] | None = None, *,
                figsize: tuple[float, float] | None = None, dpi: float | None = None,
                style: str | None = None) -> Figure:
    """Each orbit's existence and stability intervals as horizontal bars.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`vibimpact.orbits.hunt_to_dataset` (a ``vibimpact orbits`` file).
    path : str or os.PathLike, optional
        Save the figure there (atomically).
    figsize : (float, float), optional
        Width and height in inches (default 8 wide, 0.35 per orbit).
    dpi : float, optional
    style : {"default", "paper"}, optional
        :mod:`vibimpact.plotting.style`.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        Naming ``ds``, ``figsize``, ``dpi`` or ``style``.
    """
    from matplotlib.lines import Line2D

    from ..base import _validate as _v
    from ..base._text import count
    from ..orbits.dataset import is_orbit_dataset
    from .style import attractor_colour, look, width

    _v.dataset("ds", ds, "the xarray.Dataset of an orbit hunt (hunt_to_dataset)")
    if not is_orbit_dataset(ds):
        raise ValueError("ds is not an orbit hunt's dataset (hunt_to_dataset)")
    from ._sweep import check_contents, spec

    check_contents(ds, grids=(), codes=(), increasing=())
    lk = look(figsize, dpi, style)
    param = str(ds.attrs["forcing_param"])
    value = float(ds.attrs["forcing_value"])
    k = ds.sizes["orbit"]
    with lk.context():
        fig = lk.figure((8, 1.4 + 0.35 * max(k, 1)), 1.0 + 0.22 * max(k, 1))
        ax = fig.subplots()
        gid = ds["global_id"].values if "global_id" in ds else np.full(k, -1)
        for i in range(k):
            # a stable orbit named after a census: its attractor's colour there
            color = attractor_colour(int(gid[i])) if int(gid[i]) >= 0 else \
                PERIOD_COLORS[(int(ds["period"].values[i]) - 1) % len(PERIOD_COLORS)]
            for lo, hi, stable in _bars(ds, i, param):
                if hi > lo:
                    ax.plot([lo, hi], [i, i], color=color, lw=width(2.0 if stable else 1.2),
                            ls="-" if stable else "--")
                else:
                    ax.plot([lo], [i], color=color, marker="o" if stable else "x",
                            ms=5)
        ax.axvline(value, color="0.4", lw=width(0.6), ls=":")
        ax.set_yticks(np.arange(k))
        ax.set_yticklabels([(f"A{int(g)}: " if int(g) >= 0 else "")
                            + (f"{lab} ({arcs})" if arcs else str(lab))
                            for lab, arcs, g in zip(ds["label"].values, ds["arcs"].values,
                                                    gid)])
        ax.set_ylim(max(k, 1) - 0.5, -0.5)  # no orbit found: an empty row
        ax.set_xlabel(spec(ds).symbol(str(param)))
        ax.grid(True, axis="x", alpha=0.5)
        handles = [Line2D([], [], color="k", lw=width(2.0), label="stable"),
                   Line2D([], [], color="k", lw=width(1.2), ls="--", label="unstable"),
                   Line2D([], [], color="0.4", lw=width(0.6), ls=":",
                          label=f"hunt at {param} = {value:g}")]
        lk.legend(ax, handles=handles)
        lk.title(ax, f"periodic orbits found at {param} = {value:g} and where each "
                     f"exists ({count(k, 'orbit')})")
        return lk.finish(fig, path)
