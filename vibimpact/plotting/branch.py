"""Continued branches of periodic orbits: stable solid, unstable dashed, bifurcations
marked.

* :func:`plot_branch` draws one response measure of a branch (a
  :class:`vibimpact.analysis.Branch`, or the dataset of a ``vibimpact continue`` file) on
  given axes;
* :func:`plot_branch_figure` is ``vibimpact plot BRANCH.nc --kind branch``: the response
  amplitudes and the largest Floquet multiplier against the parameter;
* :func:`overlay_branches` draws branches over the response curves of a sweep
  (:func:`vibimpact.plotting.plot_response`), so that they show the unstable parts that a
  brute-force sweep, which only ever sees attractors, misses.

Stable solid and unstable dashed is the usual convention of bifurcation diagrams (Seydel
2010, sec. 2.2).  Every line style and marker drawn gets a legend entry: the stable and
unstable parts of each branch, and each kind of bifurcation found (open black markers,
:data:`BIFURCATION_MARKERS`, placed at the bifurcation's parameter value, with the kind's
:attr:`~vibimpact.base.bifurcation_kinds.BifurcationKind.words` in the legend).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..base import _validate as _v
from ..base.bifurcation_kinds import BifurcationKind

if TYPE_CHECKING:  # names of the annotations only
    import os
    from collections.abc import Sequence

    import xarray as xr
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analysis import Branch

__all__ = ["plot_branch", "plot_branch_figure", "overlay_branches", "BIFURCATION_MARKERS",
           "BRANCH_COLORS"]

#: marker of each bifurcation kind found along a branch (any other: UNKNOWN's)
BIFURCATION_MARKERS = {BifurcationKind.PERIOD_DOUBLING: "o", BifurcationKind.FOLD: "^",
                       BifurcationKind.TURNING_POINT: "s",
                       BifurcationKind.NEIMARK_SACKER: "D", BifurcationKind.GRAZING: "v",
                       BifurcationKind.UNKNOWN: "*"}
#: colours of successive branches on one figure
BRANCH_COLORS = ("k", "tab:purple", "tab:brown", "tab:olive", "tab:cyan")


def _as_branch(branch):
    """A Branch from a Branch or a ``vibimpact continue`` dataset; ValueError naming
    ``branch`` otherwise."""
    import xarray as xr

    if isinstance(branch, xr.Dataset):
        from ..continuation.branches import branch_from_dataset

        from ._sweep import check_contents

        try:
            out = branch_from_dataset(branch)
        except ValueError:
            raise ValueError("branch must be a vibimpact.analysis.Branch or the dataset "
                             "of a 'vibimpact continue' file") from None
        check_contents(branch, grids=(str(branch.attrs.get("continuation_param", "eta")),
                                      "bifurcation_value", "bifurcation_lower",
                                      "bifurcation_upper"), codes=(), increasing=())
        return out
    if not isinstance(getattr(branch, "amplitude", None), dict) or \
            not hasattr(branch, "values") or not hasattr(branch, "stable"):
        raise ValueError("branch must be a vibimpact.analysis.Branch")
    return branch


def _branch_kind(kind):
    """The :class:`BifurcationKind` of a branch's event (a kind or its short name) that
    has a marker; UNKNOWN for anything else."""
    try:
        # a lookup by value (EnumMeta.__call__), not a call of __new__
        kind = BifurcationKind(kind)  # type: ignore[call-arg]
    except ValueError:
        return BifurcationKind.UNKNOWN
    return kind if kind in BIFURCATION_MARKERS else BifurcationKind.UNKNOWN


def _labelled(ax):
    """The legend labels already on ``ax``."""
    return set(ax.get_legend_handles_labels()[1])


def _event_xy(x, y, idx, kind, value):
    """Where the marker of a bifurcation goes: at its value, on the segment before
    point ``idx`` (at the point itself for a turning point)."""
    if kind != BifurcationKind.TURNING_POINT and 0 < idx < x.size and x[idx] != x[idx - 1] \
            and np.isfinite(value):
        w = (value - x[idx - 1]) / (x[idx] - x[idx - 1])
        return value, y[idx - 1] + w * (y[idx] - y[idx - 1])
    return x[idx], y[idx]


@_v.checks_flags
def plot_branch(ax: Axes, branch: Branch | xr.Dataset, var: str = "X_m", *,
                color: str = "k", label: str | None = None, lw: float = 1.2,
                markers: bool = True) -> list:
    """Draw one response measure of a continued branch against its parameter.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    branch : vibimpact.analysis.Branch or xarray.Dataset
        Computed with ``amplitude=True``, or read from a ``vibimpact continue`` file.
    var : str
        A key of ``branch.amplitude`` (``"X_m"``, ``"Y_m"``, ``"R_m"`` for the built-in rotor;
        ``"x_m"`` for the Duffing oscillator), or ``"floquet_abs_max"`` for the largest
        modulus of the Floquet multipliers.
    color : colour
    label : str, optional
        Legend entry of the stable part (the unstable part gets "<label> (unstable)").
    lw : float
    markers : bool
        Mark the bifurcations of the branch (:data:`BIFURCATION_MARKERS`), grazings
        included, each kind with a legend entry (its
        :attr:`~vibimpact.base.bifurcation_kinds.BifurcationKind.words`) unless ``ax`` has one
        already.

    Returns
    -------
    list of matplotlib artists

    Raises
    ------
    ValueError
        Naming ``branch`` or ``var``.

    Examples
    --------
    >>> import numpy as np, vibimpact as vi
    >>> from vibimpact.analysis import continue_orbit
    >>> from vibimpact.plotting.branch import plot_branch
    >>> from matplotlib.figure import Figure
    >>> p = vi.DuffingParams(delta=0.1, alpha=1.0, beta=0.05, gamma=0.5, omega=0.9)
    >>> br = continue_orbit(vi.System(p), [0.0, 0.0], param="omega", stop=(0.9, 1.0))
    >>> ax = Figure().add_subplot()
    >>> len(plot_branch(ax, br, "x_m")) > 0
    True
    """
    branch = _as_branch(branch)
    amp = branch.amplitude
    if var == "floquet_abs_max":
        mu = np.asarray(branch.multipliers)
        y = np.abs(mu).max(axis=1) if mu.size else np.zeros(0)
    elif var in amp:
        y = np.asarray(amp[var], dtype=float)
    else:
        raise ValueError(f"var must be floquet_abs_max or one of "
                         f"{', '.join(amp) or '(none: computed with amplitude=False)'}, "
                         f"got {var!r}")
    x = np.asarray(branch.values, dtype=float)
    st = np.asarray(branch.stable, dtype=bool)
    from ..continuation.branches import stretches

    artists = []
    labelled = {True: False, False: False}
    for i, j, s in stretches(st):
        # a run of equal stability, joined to the next point so the line is unbroken
        k = min(j + 1, x.size - 1)
        lab = None
        if label is not None and not labelled[s]:
            lab = label if s else f"{label} (unstable)"
            labelled[s] = True
        artists += ax.plot(x[i:k + 1], y[i:k + 1], color=color, lw=lw,
                           ls="-" if s else "--", label=lab)
    if markers:
        for idx, kind, value in getattr(branch, "bifurcations", ()):
            kind = _branch_kind(kind)
            m = BIFURCATION_MARKERS[kind]
            if not 0 <= idx < x.size:
                continue
            text = kind.words
            bx, by = _event_xy(x, y, idx, kind, value)
            artists += ax.plot([bx], [by], ls="none", marker=m, ms=6, color="k",
                               mfc="white", mec="k", mew=1.0, zorder=5,
                               label=None if text in _labelled(ax) else text)
    return artists


def _branch_label(ds, name=None):
    """``P1 branch`` (``P1 branch (name)``) of a branch dataset."""
    n = int(ds.attrs.get("period", 1))
    return f"P{n} branch" + (f", {name}" if name else "")


def _legend(lk, axes):
    """One legend beside ``axes[0]`` (placed by the Look ``lk``) with every labelled
    artist of ``axes`` (first label wins), replacing the one it had."""
    seen: dict[str, Artist] = {}
    for a in axes:
        for h, lab in zip(*a.get_legend_handles_labels()):
            seen.setdefault(lab, h)
    if seen:
        lk.legend(axes[0], handles=list(seen.values()))


def _without_param(ds, name):
    """An object with the attributes of ``ds`` less those of parameter ``name`` (its
    ``param_NAME`` and its entry in the ``params`` JSON), for :func:`title`: the
    subtitle lists the parameters held fixed, never the one the branch varies (its
    value in the file is only where the continuation started)."""
    import json
    from types import SimpleNamespace

    from ..base._json import loads

    attrs = {k: v for k, v in ds.attrs.items() if k != f"param_{name}"}
    try:
        params = loads(attrs["params"], "the attribute 'params'")
    except (KeyError, TypeError, ValueError):
        params = None
    if isinstance(params, dict) and name in params:
        params.pop(name)
        attrs["params"] = json.dumps(params, sort_keys=True)
    return SimpleNamespace(attrs=attrs)


def plot_branch_figure(ds: xr.Dataset, path: str | os.PathLike[str] | None = None, *,
                       figsize: tuple[float, float] | None = None,
                       dpi: float | None = None, style: str | None = None) -> Figure:
    """The figure of ``vibimpact plot BRANCH.nc --kind branch``.

    One panel per response amplitude of the orbit (the first two, ``R_m`` left out:
    ``X_m`` and ``Y_m`` for the built-in rotor) and one with the largest modulus of the
    Floquet multipliers, ``|mu|max``, against the continuation parameter, with the
    stability boundary ``|mu| = 1`` drawn.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`vibimpact.continuation.branches.branch_to_dataset` (a ``vibimpact continue``
        file).
    path : str or os.PathLike, optional
        Save the figure there (atomically).
    figsize : (float, float), optional
        Width and height in inches (default 8 inches wide, 2.4 per panel; one column in
        the paper style).
    dpi : float, optional
        Resolution of the saved figure.
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
    from ..base._text import count
    from ._sweep import spec, title
    from .style import look, width

    branch = _as_branch(ds)
    unit = spec(ds).length_unit
    per = f" / {unit}" if unit else ""
    lk = look(figsize, dpi, style)
    names = [k for k in branch.amplitude if k != "R_m"][:2]
    with lk.context():
        fig = lk.figure((8, 2.4 * (len(names) + 1) + 0.6), 1.5 * (len(names) + 1) + 0.6)
        axes = list(fig.subplots(len(names) + 1, 1, sharex=True, squeeze=False)[:, 0])
        label = _branch_label(ds)
        for a, name in zip(axes, names + ["floquet_abs_max"]):
            plot_branch(a, branch, name, label=label, lw=width(0.8))
            a.set_ylabel(f"{name}  (max |{name[:-2]}|{per})" if name in names
                         else "|μ|max")
            a.grid(True, alpha=0.5)
        axes[-1].axhline(1.0, color="tab:red", lw=width(0.53), ls=":",
                         label="|μ| = 1 (stability boundary)")
        axes[-1].set_xlabel(spec(ds).symbol(str(branch.param)))
        _legend(lk, axes)
        x = np.asarray(branch.values, dtype=float)
        head = title(_without_param(ds, branch.param))
        lk.title(fig, f"{label} in {branch.param} from {x[0]:.6g} to {x[-1]:.6g}, "
                      f"{count(x.size, 'orbit')}" + (f"\n{head}" if head else ""))
        return lk.finish(fig, path)


def overlay_branches(axes: Sequence[Axes], branches: Sequence[xr.Dataset],
                     names: Sequence[str] | None = None, *,
                     style: str | None = None) -> list:
    """Draw branches over the two panels (``X_m``, ``Y_m``) of a response figure.

    The legend of ``axes[0]`` is redrawn with every labelled artist of both panels: the
    sweep's curves and markers, and each branch's stable and unstable parts and kinds of
    bifurcation.

    Parameters
    ----------
    axes : pair of matplotlib.axes.Axes
        From :func:`vibimpact.plotting.plot_response` (``fig.axes[:2]``).
    branches : sequence of xarray.Dataset
        ``vibimpact continue`` files continued in ``eta``, with the amplitudes.
    names : sequence of str, optional
        A name for each branch in the legend (the file names, say).
    style : {"default", "paper"}, optional
        The style the response figure was drawn in (line widths, legend placement).

    Returns
    -------
    list of matplotlib artists

    Raises
    ------
    ValueError
        Naming ``axes``, ``names``, ``branches`` or ``style``.
    """
    from .style import look, width

    lk = look(style=style)
    axes = list(axes)
    if len(axes) != 2:
        raise ValueError("axes must be the two Axes of a response figure (X_m, Y_m)")
    labels: list[str | None] = list(names) if names is not None else [None] * len(branches)
    if len(labels) != len(branches):
        raise ValueError("names must give one name per branch")
    artists = []
    for k, (ds, name) in enumerate(zip(branches, labels)):
        br = _as_branch(ds)
        if br.param != "eta" or not {"X_m", "Y_m"} <= set(br.amplitude):
            raise ValueError(f"branches[{k}] must be continued in eta with the "
                             f"amplitudes X_m, Y_m (it is in {br.param}, amplitudes "
                             f"{', '.join(br.amplitude) or 'none'})")
        color = BRANCH_COLORS[k % len(BRANCH_COLORS)]
        with lk.context():
            for a, var in zip(axes, ("X_m", "Y_m")):
                artists += plot_branch(a, br, var, color=color,
                                       label=_branch_label(ds, name), lw=width(0.9))
    with lk.context():
        _legend(lk, axes)
    return artists
