"""Orbit of a run in the plane its model declares (:class:`vibimpact.models.PlotSpec`): with
the circular obstacle and the impacts where the model has one, else a phase portrait."""
from __future__ import annotations

from typing import TYPE_CHECKING

import os

import numpy as np

if TYPE_CHECKING:  # names of the annotations only
    import xarray as xr
    from matplotlib.axes import Axes

    from ..core.run import Run


def _title(ds):
    """``preset, <forcing frequency> = .., <the parameters the model's title shows>``."""
    from .. import models
    from ..io.recorded import check_recorded

    a = ds.attrs
    check_recorded(a)  # what the title shows is what --set would accept
    parts = []
    if a.get("preset"):
        parts.append(str(a["preset"]))
    model = models.get(a["model"]) if a["model"] in models.names() else None
    spec = (model.plot if model is not None else None) or models.PlotSpec(xy=())
    names = [model.param_names[model.omega_index]] if model is not None else []
    for name in names + list(spec.title + spec.title_nonzero):
        key = f"param_{name}"
        if key in a and (name not in spec.title_nonzero or float(a[key]) != 0.0):
            parts.append(f"{spec.symbol(name)} = {float(a[key]):g}")
    status = a.get("status", "ok")
    if status != "ok":
        parts.append(str(status).upper())
    return ", ".join(parts)


def plot_xy(ds: xr.Dataset | Run, path: str | os.PathLike[str] | None = None,
            ax: Axes | None = None, *, figsize: tuple[float, float] | None = None,
            dpi: float | None = None, style: str | None = None) -> Axes:
    """Draw the orbit in the plane of the model's XY states with its obstacle and impacts.

    Parameters
    ----------
    ds : xarray.Dataset or Run
        The dataset of a run, as :meth:`vibimpact.Run.to_dataset` makes it
        and ``vibimpact simulate`` writes it, or the Run itself: uses ``trajectory`` if
        present, else ``strobe``, and the impact records (``impact_theta``,
        ``impact_theta_min``, ``impact_theta_max``).
    path : str or os.PathLike, optional
        Save the figure there (atomically, format from the extension).
    ax : matplotlib.axes.Axes, optional
        Draw into these axes; a new 6 x 6.6 inch figure otherwise (one column, 3.5 x 4.2
        inches, in the paper style).
    figsize : (float, float), optional
        Width and height of the new figure in inches (not with ``ax``).
    dpi : float, optional
        Resolution of the saved figure (default 150; 300 in the paper style).
    style : {"default", "paper"}, optional
        ``"paper"``: :data:`vibimpact.plotting.style.PAPER_STYLE`, a journal's look.

    Returns
    -------
    matplotlib.axes.Axes

    Raises
    ------
    ValueError
        Naming ``ax``, ``figsize``, ``dpi`` or ``style``, a dataset that names no model,
        or one without the states its model's plot draws.

    Notes
    -----
    What is drawn is what the dataset's model declares (:class:`~vibimpact.models.PlotSpec`;
    a model that is not built in: its first two states, no obstacle).  A model with a
    circular obstacle (``circle``: its radius, centred at the origin) gets that circle, the
    orbit in the plane of its ``xy`` states, the impacts and the loaded arcs, the second
    axis inverted where ``y_down``; any other model, the orbit and its stroboscopic points
    in the plane of its ``xy`` states.  Impact markers sit at the contact entry point
    ``circle * (cos theta, sin theta)``; the loaded arcs of
    :func:`vibimpact.analysis.contact_arcs` (each contact from entry to exit, sliding
    included) are drawn as thick bands on the unit circle from their start to their end.
    For the built-in rotor: the plane is (X, Y), lengths are in clearances and the
    retainer is the circle ``R = 1`` of the centre; gravity acts along +Y, so the Y axis
    is inverted: the bottom of the retainer (``theta = +90`` degrees) is drawn at the
    bottom (the paper's figs 8a, 10a-c and 11b-d mark the same arcs).

    Of a run longer than :data:`vibimpact.plotting.xy_dense.LAST_PERIODS` forcing periods
    the last that many periods of the trajectory are drawn in colour and the earlier ones
    thin and faint grey beneath them (a few hundred periods of a chaotic motion on top of
    each other bury the attractor), the stroboscopic points on top of everything; the
    legend says which periods each line holds.  A loaded-arc legend says "whole circle"
    only of arcs that cover the whole circle (:func:`arcs_label`).

    The trajectory is drawn as straight segments between samples, none longer than
    :data:`vibimpact.plotting.xy_dense.MAX_SEGMENT_PX` pixels of the figure: where the
    run's own dense samples are coarser (a chaotic impact motion would show as a
    polygon), the run is integrated again from its recorded start with enough samples
    per forcing period for the figure's size and resolution (the same motion: dense
    samples do not change the integrator's steps, and the stroboscopic samples are
    checked to be the recorded ones).

    Examples
    --------
    >>> from vibimpact.io import read_netcdf
    >>> from vibimpact.plotting import plot_xy
    >>> ax = plot_xy(read_netcdf("run.nc"), "xy.png")  # doctest: +SKIP
    >>> ax = plot_xy(run)  # a vibimpact.Run  # doctest: +SKIP
    """
    from ..io import as_run_dataset
    from .style import look

    value, ds = ds, as_run_dataset(ds)
    lk = look(figsize, dpi, style, ax)
    states = [str(s) for s in ds["state"].values]
    spec = _plot_spec(ds, states)
    if not set(spec.xy) <= set(states):
        raise ValueError(f"plot_xy needs the states {', '.join(spec.xy)} of the "
                         f"{ds.attrs.get('model', 'model')}; the dataset has {states}")
    with lk.context():
        own = ax is None
        if ax is None:
            ax = lk.figure((6, 6.6), 4.2).add_subplot()
        if spec.circle is not None:
            _orbit(value, ds, ax, lk, own, spec, [states.index(s) for s in spec.xy])
        else:
            _phase(value, ds, ax, lk, own, [states.index(s) for s in spec.xy], spec.xy)
        lk.finish(ax.figure, path)
    return ax


def _plot_spec(ds, states):
    """What the dataset's model declares its XY plots draw (a dataset that names no model
    is refused: ValueError; a model that is not built in: its first two states, no
    obstacle)."""
    from .. import models
    from ..io.recorded import model_name

    name = model_name(ds.attrs, "ds")
    if isinstance(name, str) and name in models.names() and \
            models.get(name).plot is not None:
        return models.get(name).plot
    return models.PlotSpec(xy=tuple(states[:2]))


def _phase(value, ds, ax, lk, own, cols, names):
    """The orbit and its stroboscopic points in the plane of the states ``names`` (a
    model whose contact is no circle around the origin)."""
    from .xy_dense import trajectory_for

    if "trajectory" in ds:
        raw = ds["trajectory"].values[:, cols]
        span = float(np.nanmax(np.ptp(raw, axis=0))) * 1.1 if raw.size else 1.0
        traj = trajectory_for(value, ds, ax, cols, span if span > 0 else 1.0, lk.dpi)
        draw_trajectory(ax, traj, cols, len(ds["strobe"]) - 1)
    _draw_strobe(ax, ds, cols, lk.paper)
    ax.set_xlabel(names[0])
    ax.set_ylabel(names[1])
    lk.title(ax, _title(ds))
    lk.legend_below(ax, own, ax.get_legend_handles_labels()[0], ncol=2)
    ax.grid(True, alpha=0.5)


def _orbit(value, ds, ax, lk, own, spec, cols):
    """The model's circular obstacle (``spec``: its :class:`~vibimpact.models.PlotSpec`),
    the orbit in the plane of the states ``cols``, its stroboscopic points, impacts and
    loaded arcs on ``ax``, with the legend below the axes (``own``: the figure is
    plot_xy's)."""
    from .style import width
    from .xy_dense import trajectory_for

    i, j = cols
    r = spec.circle
    phi = np.linspace(0.0, 2.0 * np.pi, 721)
    ax.plot(r * np.cos(phi), r * np.sin(phi), color="0.3", lw=width(1.0),
            label=spec.circle_label)
    if "trajectory" in ds:
        traj = trajectory_for(value, ds, ax, [i, j], 2.4 * r, lk.dpi)
        draw_trajectory(ax, traj, cols, len(ds["strobe"]) - 1)
    _draw_strobe(ax, ds, cols, lk.paper)
    arcs = loaded_arcs(value, ds)
    if arcs is not None and arcs.n_arcs:
        draw_arcs(ax, arcs, width(3.3), r)
    if "impact_theta" in ds and ds.sizes.get("impact", 0):
        deg = ds["impact_theta"].values
        th = np.radians(deg)
        ax.plot(r * np.cos(th), r * np.sin(th), ls="none", marker="x",
                ms=7 * (PAPER_MARK_SCALE if lk.paper else 1.0), mew=width(1.0),
                color="C3", zorder=3, label=f"impacts ({th.size})")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(spec.xy[0])
    ax.set_ylabel(f"{spec.xy[1]}  ({spec.y_note})" if spec.y_note else spec.xy[1])
    if spec.y_down and not ax.yaxis_inverted():
        ax.invert_yaxis()
    lk.title(ax, _title(ds))
    lk.legend_below(ax, own, ax.get_legend_handles_labels()[0], ncol=2)
    ax.grid(True, alpha=0.5)


#: colour and opacity of the faint earlier periods of a trajectory (:func:`draw_trajectory`)
EARLIER_COLOR, EARLIER_ALPHA = "0.7", 0.5
#: the markers' size in the paper style (one 3.5 inch column), as a share of the default's
PAPER_MARK_SCALE = 0.5
#: drawing order: faint earlier periods, the recent ones, impacts, stroboscopic points
Z_EARLIER, Z_RECENT, Z_STROBE = 1.5, 2.5, 4.0


def draw_trajectory(ax, traj, cols, n_periods):
    """The trajectory's samples ``traj`` (``n_periods`` forcing periods) in the plane of
    the states ``cols``: the last :data:`~vibimpact.plotting.xy_dense.LAST_PERIODS`
    periods in colour, the earlier ones thin and faint grey beneath them, each labelled
    with the periods it holds.  Returns the line of the recent periods."""
    from ..base._text import count
    from .style import width
    from .xy_dense import LAST_PERIODS, split_recent

    i, j = cols
    earlier, recent = split_recent(traj, n_periods)
    if earlier is None:
        label = f"trajectory, all {count(n_periods, 'period')}"
    else:
        label = f"trajectory, last {LAST_PERIODS} of {n_periods} periods"
        ax.plot(earlier[:, i], earlier[:, j], color=EARLIER_COLOR, lw=width(0.3),
                alpha=EARLIER_ALPHA, zorder=Z_EARLIER,
                label=f"earlier {count(n_periods - LAST_PERIODS, 'period')} (faint)")
    (line,) = ax.plot(recent[:, i], recent[:, j], color="C0", lw=width(0.47), alpha=0.9,
                      zorder=Z_RECENT, label=label)
    return line


def _draw_strobe(ax, ds, cols, paper=False):
    """The stroboscopic points on top of everything else (hollow over a trajectory;
    smaller in the paper style's narrow column)."""
    strobe = ds["strobe"].values
    ax.plot(strobe[:, cols[0]], strobe[:, cols[1]], ls="none", marker="o",
            ms=3.5 * (PAPER_MARK_SCALE if paper else 1.0),
            color="C1", mfc="none" if "trajectory" in ds else "C1", zorder=Z_STROBE,
            label=f"stroboscopic points ({len(strobe)})")


#: an arc narrower than this (degrees) is drawn this wide, centred on it, to be seen
MIN_DRAWN_ARC = 2.0


def loaded_arcs(value, ds):
    """The loaded arcs of a run (:func:`vibimpact.analysis.contact_arcs`): from the Run
    itself when given one (every contact interval, a permanent contact included), else
    from the dataset's impact records; None for a model without a contact."""
    from ..analysis.impacts import contact_arcs

    if hasattr(value, "events") and hasattr(value, "strobe"):
        return contact_arcs(value) if getattr(value, "contact", None) is not None else None
    if "impact_theta" not in ds:
        return None
    return contact_arcs(ds)


def arc_points(start, width, radius=1.0):
    """``(x, y)`` of an arc of the circle of ``radius`` from ``start`` (degrees) over
    ``width`` degrees in the direction of increasing theta (one point a quarter degree;
    an arc narrower than :data:`MIN_DRAWN_ARC` is drawn that wide about its middle)."""
    if width < MIN_DRAWN_ARC:
        start, width = start + 0.5 * width - 0.5 * MIN_DRAWN_ARC, MIN_DRAWN_ARC
    phi = np.radians(start + np.linspace(0.0, width, max(8, int(np.ceil(width * 4.0)) + 1)))
    return radius * np.cos(phi), radius * np.sin(phi)


def draw_arcs(ax, arcs, lw, radius=1.0):
    """The loaded arcs as thick bands on the circle of ``radius`` (the model's circular
    obstacle, :attr:`vibimpact.models.PlotSpec.circle`; the built-in rotor's retainer: 1)
    from start to end, labelled with their words and their extent in degrees."""
    text = arcs_label(arcs)
    for k, (s, w) in enumerate(zip(arcs.start, arcs.width)):
        x, y = arc_points(float(s), float(w), radius)
        ax.plot(x, y, color="C3", lw=lw, alpha=0.45, solid_capstyle="butt",
                label=text if k == 0 else None)


def arcs_label(arcs):
    """The legend text of the loaded arcs (:class:`vibimpact.analysis.ContactArcs`): their
    words and extents (:meth:`~vibimpact.analysis.ContactArcs.to_text`; the words alone
    beyond 4 arcs), except that "whole circle" is said only of arcs that cover it: arcs
    that leave gaps (each narrower than
    :data:`vibimpact.analysis.impacts.WHOLE_CIRCLE_GAP`, which the analysis calls the
    whole circle) are counted, listed and their largest gap given instead."""
    from ..base._text import count

    if arcs.n_arcs == 1 and float(arcs.width[0]) >= 360.0:
        return "loaded arcs: whole circle"
    if arcs.summary != "whole circle":
        return f"loaded arcs: {arcs if arcs.n_arcs <= 4 else arcs.summary}"
    extents = str(arcs).removeprefix(arcs.summary).strip()
    head = count(arcs.n_arcs, "arc") + (f" {extents}" if arcs.n_arcs <= 4 else "")
    return f"loaded arcs: {head}, largest gap {arcs.largest_gap:.0f}°"
