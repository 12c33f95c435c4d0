"""A continued branch of periodic orbits on a response curve: stable solid, unstable dashed.

:func:`plot_branch` draws a :class:`vibimpact.analysis.Branch` (from
:func:`vibimpact.analysis.continue_orbit`) on given axes, so that a response curve of a
sweep (:func:`vibimpact.plotting.plot_response`) can show the unstable parts of the
branches that a brute-force sweep, which only ever sees attractors, misses (Seydel 2010,
sec. 2.2: stable solid, unstable dashed, is the usual convention of bifurcation diagrams).
"""
from __future__ import annotations

import numpy as np

__all__ = ["plot_branch", "BIFURCATION_MARKERS"]

#: marker of each bifurcation kind found along a branch
BIFURCATION_MARKERS = {"period doubling": "o", "fold": "s", "fold (turning point)": "s",
                       "Neimark-Sacker": "D"}


def plot_branch(ax, branch, var="X_m", *, color="k", label=None, lw=1.2, markers=True):
    """Draw one response measure of a continued branch against its parameter.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    branch : vibimpact.analysis.Branch
        Computed with ``amplitude=True``.
    var : str
        A key of ``branch.amplitude`` (``"X_m"``, ``"Y_m"``, ``"R_m"`` for the rotor;
        ``"x_m"`` for the Duffing oscillator).
    color : colour
    label : str, optional
        Legend entry of the stable part (the unstable part gets "<label> (unstable)").
    lw : float
    markers : bool
        Mark the bifurcations of the branch (o period doubling, s fold, D Neimark--Sacker).

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
    amp = getattr(branch, "amplitude", None)
    if not isinstance(amp, dict) or not hasattr(branch, "values") or \
            not hasattr(branch, "stable"):
        raise ValueError("branch must be a vibimpact.analysis.Branch")
    if var not in amp:
        raise ValueError(f"var must be one of {', '.join(amp) or '(none: computed with '}"
                         f"{'' if amp else 'amplitude=False)'}, got {var!r}")
    x = np.asarray(branch.values, dtype=float)
    y = np.asarray(amp[var], dtype=float)
    st = np.asarray(branch.stable, dtype=bool)
    artists = []
    labelled = {True: False, False: False}
    i = 0
    while i < x.size:
        j = i
        while j + 1 < x.size and st[j + 1] == st[i]:
            j += 1
        # a run of equal stability, joined to the next point so the line is unbroken
        k = min(j + 1, x.size - 1)
        s = st[i]
        lab = None
        if label is not None and not labelled[bool(s)]:
            lab = label if s else f"{label} (unstable)"
            labelled[bool(s)] = True
        artists += ax.plot(x[i:k + 1], y[i:k + 1], color=color, lw=lw,
                           ls="-" if s else "--", label=lab)
        i = j + 1
    if markers:
        for idx, kind, _value in getattr(branch, "bifurcations", ()):
            m = BIFURCATION_MARKERS.get(kind)
            if m is None or not 0 <= idx < x.size:
                continue
            artists += ax.plot([x[idx]], [y[idx]], ls="none", marker=m, ms=5, mfc="white",
                               mec=color, mew=1.0)
    return artists
