"""The basins of attraction of a plane of states (:func:`vibimpact.basins`) as an image:
one colour per attractor, a legend naming each with its basin fraction, and the
boundary measures (Daza et al., Sci. Rep. 6, 31416 (2016)) in the title."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .style import attractor_colour, look

if TYPE_CHECKING:  # names of the annotations only
    import os

    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["plot_basins", "legend_labels"]

#: a diverged basin is drawn black (the attractors: style.attractor_colour of their id)
_GREY_DIVERGED = "0.1"
#: cells whose integration failed (basin -1: on no attractor) are drawn white
_FAILED = "white"
#: cells not started (basin -2: the start in penetration of the contact, the rotor's
#: corners outside the retainer) are drawn light grey
_NOT_STARTED = "0.9"


def _ids(ds):
    """The attractors' ids (``global_id``: the census' when named after one), else
    their indices."""
    if "global_id" in ds and ds["global_id"].dims == ("attractor",):
        return [int(g) for g in ds["global_id"].values]
    return list(range(int(ds.sizes["attractor"])))


def _short(v):
    """``v`` to 3 significant digits, 0 below 5e-4 (a state at rest prints 0)."""
    return "0" if abs(v) < 5e-4 else f"{v:.3g}"


def check_basins(ds) -> tuple[str, str]:
    """The plane's two state names of a basins dataset; ValueError when ``ds`` is not
    one (no ``basin (row, column)`` or no plane attributes)."""
    if "basin" not in getattr(ds, "data_vars", {}) or ds["basin"].dims != ("row", "column"):
        raise ValueError("the dataset holds no basin image (basin (row, column)); make one "
                         "with vibimpact.basins or 'vibimpact basins'")
    xname, yname = ds.attrs.get("plane_x"), ds.attrs.get("plane_y")
    if xname not in ds.coords or yname not in ds.coords:
        raise ValueError("the basins dataset has no plane coordinates (attributes plane_x, "
                         "plane_y)")
    from ._sweep import check_contents

    check_contents(ds, grids=(xname, yname), codes=(), increasing=(xname, yname))
    return str(xname), str(yname)


def legend_labels(ds: xr.Dataset) -> list[str]:
    """One legend text per attractor of a basins dataset: its name, where it lies (its
    representative state in the plane's variables, so that two orbits of one name are
    told apart) and its basin fraction with the standard error."""
    xname, yname = check_basins(ds)
    states = [str(s) for s in ds["state"].values] if "state" in ds.coords else []
    out = []
    for a in range(ds.sizes["attractor"]):
        name = str(ds["name"].values[a])
        f = float(ds["fraction"].values[a])
        se = float(ds["fraction_se"].values[a])
        where = ""
        if "representative" in ds and xname in states and yname in states:
            rep = np.asarray(ds["representative"].values[a], dtype=float)
            i, j = states.index(xname), states.index(yname)
            if np.isfinite(rep[i]) and np.isfinite(rep[j]):
                where = f" at {xname} {_short(rep[i])}, {yname} {_short(rep[j])}"
        frac = f": {100 * f:.1f} ± {100 * se:.1f} %" if math.isfinite(f) else ""
        out.append(f"A{_ids(ds)[a]}: {name}{where}{frac}")
    return out


def _obstacle(ds, ax, xname, yname, extent):
    """The model's circular obstacle (the rotor's retainer clearance) on a plane of its
    two contact positions, drawn as in the XY figures (equal axes; the vertical axis
    down where the model's XY figure has it down); the legend handles it adds."""
    from ._sweep import spec

    try:
        sp = spec(ds)
    except ValueError:  # a dataset that names no model: no obstacle known
        return []
    if sp.circle is None or tuple(sp.xy) != (xname, yname):
        return []
    r = float(sp.circle)
    phi = np.linspace(0.0, 2.0 * np.pi, 721)
    (line,) = ax.plot(r * np.cos(phi), r * np.sin(phi), color="black", lw=1.2, ls="--",
                      label=sp.circle_label)
    ax.set_aspect("equal")
    lo, hi = min(extent[0], extent[2], -r), max(extent[1], extent[3], r)
    pad = 0.02 * (hi - lo)
    ax.set_xlim(lo - pad, hi + pad)
    ax.set_ylim(lo - pad, hi + pad)
    if sp.y_down and not ax.yaxis_inverted():
        ax.invert_yaxis()
    if sp.y_note:
        ax.set_ylabel(f"{yname}  ({sp.y_note})")
    return [line]


def plot_basins(ds: xr.Dataset, ax: Axes | None = None,
                path: str | os.PathLike[str] | None = None, *,
                figsize: tuple[float, float] | None = None, dpi: float | None = None,
                style: str | None = None) -> Figure:
    """Draw a basin image: one colour per attractor, a legend naming each.

    Parameters
    ----------
    ds : xarray.Dataset
        A basins dataset (:func:`vibimpact.basins`, a file of ``vibimpact basins``):
        ``basin (row, column)``, the plane coordinates, ``name``, ``fraction``,
        ``fraction_se`` (``attractor``) and the boundary measures.
    ax : matplotlib.axes.Axes, optional
        Draw into these axes; a new figure otherwise (6.5 x 6.5 inches, the legend
        below; one column in the paper style).
    path : str or os.PathLike, optional
        Save the figure there (atomically, format from the extension).
    figsize : (float, float), optional
    dpi : float, optional
    style : {"default", "paper"}, optional

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        Naming ``ax``, ``figsize``, ``dpi`` or ``style``, or a dataset without a basin
        image.

    Notes
    -----
    Cells whose integration failed (``basin`` -1) are white, with a legend entry of
    their share of the started cells; cells not started (``basin`` -2, their start in
    penetration of the contact: the rotor's corners outside the retainer) light grey.
    Cell ``(r, c)`` is drawn centred on the plane's values of its start; the horizontal
    axis is the plane's first variable, the vertical its second.  The title gives the
    boundary fraction, the basin entropy ``Sb`` and the boundary basin entropy ``Sbb``
    with the log 2 criterion (Daza et al. 2016).

    Examples
    --------
    >>> import vibimpact as vi
    >>> from vibimpact.plotting.basins import plot_basins
    >>> ds = vi.io.read_netcdf("basins.nc")  # doctest: +SKIP
    >>> fig = plot_basins(ds, path="basins.png")  # doctest: +SKIP
    """
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    xname, yname = check_basins(ds)
    lk = look(figsize, dpi, style, ax)
    img = np.asarray(ds["basin"].values)
    n = int(ds.sizes["attractor"])
    colours = [attractor_colour(g) for g in _ids(ds)]
    names = [str(v) for v in ds["name"].values]
    colours = [_GREY_DIVERGED if nm == "diverged" else c for nm, c in zip(names, colours)]
    cmap = ListedColormap(colours).with_extremes(under=_FAILED, bad=_NOT_STARTED)
    norm = BoundaryNorm(np.arange(-0.5, n + 0.5), n)
    xs = np.asarray(ds[xname].values, dtype=float)
    ys = np.asarray(ds[yname].values, dtype=float)
    hx = (xs[-1] - xs[0]) / max(xs.size - 1, 1)
    hy = (ys[-1] - ys[0]) / max(ys.size - 1, 1)
    extent = (xs[0] - hx / 2, xs[-1] + hx / 2, ys[0] - hy / 2, ys[-1] + hy / 2)
    with lk.context():
        own = ax is None
        if ax is None:
            fig = lk.figure((6.5, 6.5), 4.2)
            ax = fig.add_subplot()
        else:
            fig = ax.figure
        # -1 (failed) below the colours; -2 (not started) masked
        ax.imshow(np.ma.masked_equal(img, -2), origin="lower", extent=extent, cmap=cmap,
                  norm=norm,
                  interpolation="nearest", aspect="auto", rasterized=True)
        ax.set_xlabel(xname)
        ax.set_ylabel(yname)
        handles = [Patch(facecolor=c, edgecolor="none", label=t)
                   for c, t in zip(colours, legend_labels(ds))]
        handles += _obstacle(ds, ax, xname, yname, extent)
        started = img != -2
        if np.any(img == -1):
            share = float(np.mean(img[started] == -1))
            handles.append(Patch(facecolor=_FAILED, edgecolor="0.5",
                                 label=f"integration failed: {100 * share:.1f} %"))
        if not started.all():
            handles.append(Patch(facecolor=_NOT_STARTED, edgecolor="none",
                                 label=f"not started ({int((~started).sum())} cells): "
                                       "in penetration of the contact"))
        lk.legend_below(ax, own, handles, fontsize="small")
        sbb = float(ds["boundary_basin_entropy"]) if "boundary_basin_entropy" in ds \
            else math.nan
        parts = []
        if "boundary_fraction" in ds:
            of = "of cells" if started.all() else "of the started cells"
            parts.append(f"boundary {100 * float(ds['boundary_fraction']):.1f} % {of}")
        if "basin_entropy" in ds:
            parts.append(f"Sb {float(ds['basin_entropy']):.3f}")
        if math.isfinite(sbb):
            verdict = "fractal (Sbb > log 2)" if sbb > math.log(2.0) else \
                "<= log 2: not decided"
            parts.append(f"Sbb {sbb:.3f}, {verdict}")
        freq = str(ds.attrs.get("frequency_name", "eta")).replace("eta", "η")
        eta = f"{freq} = {float(ds['eta']):g}\n" if "eta" in ds.coords else ""
        lk.title(ax, eta + "; ".join(parts[:2]) + ("\n" + parts[2] if parts[2:] else ""))
        return lk.finish(fig, path)
