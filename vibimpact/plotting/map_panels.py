"""The panels of a parameter map (:func:`vibimpact.plotting.map2d.plot_map`) and their
colour scales.

Every quantity has one colour scale for the whole figure, built from the values of every
sweep direction drawn, so that a colour means the same in every panel of it:

* regime: a fixed colour per kind of motion; each panel's legend lists the kinds present
  in it;
* period and impacts per period (integers): a discrete scale, one colour per value
  present (:class:`Discrete`, drawn with a ``ListedColormap`` and a ``BoundaryNorm``);
* largest Lyapunov exponent: one diverging scale, symmetric about 0, over every panel,
  and a grey swatch under its bar naming what the grey cells are (not computed: the
  regimes of those points, periodic where the exponent is computed only without a
  period).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._sweep import REGIME_NAMES

__all__ = ["MAP_REGIME_COLORS", "MISSING", "Discrete", "exponent_norm", "exponent_panel",
           "impacts_scale", "missing_swatch", "not_computed_text", "period_scale",
           "regime_panel"]

#: regime code -> colour (0: not computed)
MAP_REGIME_COLORS = {0: "0.85", 1: "#31a354", 2: "tab:orange", 3: "tab:red", 4: "0.15",
                     5: "tab:purple"}
#: colour of points where a quantity was not computed or does not exist
MISSING = "0.9"
#: most categories a discrete scale shows one by one (the rest share the last)
MAX_CATEGORIES = 19

_NONE, _OTHER = -1, -2  # keys of "no period" and "the rest" in a period scale


@dataclass(frozen=True)
class Discrete:
    """A discrete colour scale: category ``k`` (code ``k`` of :meth:`codes`) has
    ``labels[k]`` and ``colors[k]``.

    Attributes
    ----------
    keys : tuple
        The value (or class of values) each category stands for.
    labels : tuple of str
    colors : tuple
    """

    keys: tuple
    labels: tuple
    colors: tuple

    def cmap(self):
        """One colour per category (``ListedColormap``)."""
        from matplotlib.colors import ListedColormap

        return ListedColormap(list(self.colors))

    def norm(self):
        """Integer codes to their colours (``BoundaryNorm`` with bins around 0, 1, ...)."""
        from matplotlib.colors import BoundaryNorm

        return BoundaryNorm(np.arange(-0.5, len(self.keys) + 0.5), len(self.keys))

    def draw(self, fig, ax, xe, ye, keys, label):
        """Draw the cells of ``keys`` (an array of :attr:`keys`) with a colour bar that
        names every category."""
        codes = np.full(np.shape(keys), 0, dtype=int)
        for k, key in enumerate(self.keys):
            codes[np.asarray(keys) == key] = k
        m = ax.pcolormesh(xe, ye, codes, cmap=self.cmap(), norm=self.norm())
        # the bar in an inset of the panel itself, right beside it: a bar given the
        # panel (ax=) floats in the column's margin when another panel of the column
        # needs a wider one (the regime legend)
        cb = fig.colorbar(m, cax=_bar_axes(ax), ticks=np.arange(len(self.keys)))
        cb.ax.set_yticklabels(list(self.labels))
        cb.ax.minorticks_off()
        if label:
            cb.set_label(label)
        return m


#: where a colour bar sits, in the panel's axes fraction (left, bottom, width, height):
#: the full height, or above the grey swatch (:data:`SWATCH`) of a panel that has one
BAR, SHORT_BAR = [1.03, 0.05, 0.04, 0.9], [1.03, 0.25, 0.04, 0.7]
#: the grey "not computed" swatch under a short bar
SWATCH = [1.03, 0.05, 0.04, 0.1]


def _bar_axes(ax, short=False):
    """The axes of a panel's colour bar: an inset of the panel, right beside it.  A bar
    given the panel (``fig.colorbar(ax=...)``) sits in the column's margin and floats
    away from its panel when another panel of the column needs a wider margin (the
    regime legend, a longer label), where its label reads as the next panel's.  A
    ``short`` bar leaves room for the grey swatch under it (:func:`missing_swatch`)."""
    return ax.inset_axes(SHORT_BAR if short else BAR)


def _tab20(k):
    from matplotlib import colormaps

    order = (0, 2, 4, 6, 8, 10, 12, 16, 18, 1, 3, 5, 7, 9, 11, 13, 17, 19, 15)
    return colormaps["tab20"](order[k % len(order)])


def period_keys(period, regime):
    """The period of every periodic point, :data:`_NONE` elsewhere."""
    return np.where(np.asarray(regime) == 1, np.asarray(period, dtype=int), _NONE)


def period_scale(keys):
    """The period scale over the period keys (:func:`period_keys`) of every panel:
    "no period" for points without one (or one too long), ``P<n>`` for each period present; beyond
    :data:`MAX_CATEGORIES` the most frequent periods and "other".

    Returns
    -------
    (Discrete, list of ndarray)
        The scale and the keys with the rare periods mapped to "other".
    """
    keys = [np.where(np.asarray(k) > 0, k, _NONE) for k in keys]  # 0: too long
    allk = np.concatenate([np.ravel(k) for k in keys])
    values = sorted(int(v) for v in np.unique(allk) if v > 0)
    if len(values) > MAX_CATEGORIES:
        counts = {v: int((allk == v).sum()) for v in values}
        keep = sorted(sorted(values, key=lambda v: -counts[v])[:MAX_CATEGORIES - 1])
        keys = [np.where(np.isin(k, keep) | (k == _NONE), k, _OTHER) for k in keys]
        values = keep + [_OTHER]
    has_none = bool(np.any(allk == _NONE))
    cats = ([(_NONE, "no period", MISSING)] if has_none else []) + [
        (v, f"P{v}" if v > 0 else "other", _tab20(i)) for i, v in enumerate(values)]
    return Discrete(*map(tuple, zip(*cats))), keys


def impacts_keys(ipp):
    """Impacts per period as scale keys: the integer count, ``"mean"`` for a mean count
    (not periodic) that is not a whole number, ``"none"`` where not computed."""
    v = np.asarray(ipp, dtype=float)
    out = np.full(v.shape, "none", dtype=object)
    fin = np.isfinite(v)
    whole = fin & (np.mod(v, 1.0) == 0.0)
    out[whole] = v[whole].astype(int)
    out[fin & ~whole] = "mean"
    return out


def impacts_scale(keys):
    """The impacts scale over the impacts keys (:func:`impacts_keys`) of every panel:
    one colour of a sequential map per whole count present (in order), beyond
    :data:`MAX_CATEGORIES` counts the largest share ``">= n"``; grey "not computed" and
    "non-integer mean" (a motion without a period) when present.

    Returns
    -------
    (Discrete, list of ndarray)
    """
    from matplotlib import colormaps

    flat = [x for k in keys for x in np.ravel(k)]
    counts = sorted({int(x) for x in flat if not isinstance(x, str)})
    labels = [str(c) for c in counts]
    if len(counts) > MAX_CATEGORIES:
        top = counts[MAX_CATEGORIES - 1]
        keys = [np.array([x if isinstance(x, str) or x < top else top
                          for x in np.ravel(k)], dtype=object).reshape(np.shape(k))
                for k in keys]
        counts = counts[:MAX_CATEGORIES]
        labels = [str(c) for c in counts[:-1]] + [f">= {top}"]
    seq = colormaps["viridis"](np.linspace(0.0, 0.9, max(len(counts), 1)))
    # (key: a count or "mean"/"none", label, colour: an RGBA row or a grey's name)
    cats: list[tuple[object, str, object]] = [
        (c, lab, seq[i]) for i, (c, lab) in enumerate(zip(counts, labels))]
    if "mean" in flat:
        cats.append(("mean", "non-integer mean", "0.55"))
    if "none" in flat:
        cats.insert(0, ("none", "not computed", MISSING))
    return Discrete(*map(tuple, zip(*cats))), keys


def regime_panel(ax, xe, ye, reg):
    """The regime cells on ``ax`` with a legend, beside the axes, of the kinds present."""
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    codes = len(MAP_REGIME_COLORS)
    cmap = ListedColormap([MAP_REGIME_COLORS[c] for c in range(codes)])
    ax.pcolormesh(xe, ye, reg, cmap=cmap,
                  norm=BoundaryNorm(np.arange(-0.5, codes + 0.5), codes))
    present = [c for c in range(codes) if np.any(reg == c)]
    ax.legend(handles=[Patch(facecolor=MAP_REGIME_COLORS[c], edgecolor="0.5",
                             label=REGIME_NAMES[c]) for c in present],
              loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
    ax.set_title("regime")


def exponent_norm(lams):
    """One symmetric scale (``Normalize(-top, top)``) for the exponents of every panel:
    ``top`` is the largest ``|lambda|`` of any (1 when none was computed)."""
    from matplotlib.colors import Normalize

    fin = np.concatenate([np.ravel(x)[np.isfinite(np.ravel(x))] for x in lams])
    top = float(np.abs(fin).max()) if fin.size else 0.0
    top = top or 1.0
    return Normalize(-top, top)


def exponent_panel(fig, ax, xe, ye, lam, norm, regime=None):
    """The largest Lyapunov exponent on ``ax``, on ``norm``, with a grey swatch under its
    colour bar that says what the grey cells are (:func:`not_computed_text`)."""
    from matplotlib import colormaps

    cm = colormaps["RdBu_r"].with_extremes(bad=MISSING)
    grey = ~np.isfinite(np.asarray(lam, dtype=float))
    m = ax.pcolormesh(xe, ye, np.ma.masked_invalid(lam), cmap=cm, norm=norm)
    cb = fig.colorbar(m, cax=_bar_axes(ax, short=bool(grey.any())))
    cb.set_label("λ₁ per unit τ")
    if grey.any():
        missing_swatch(ax, not_computed_text(grey, regime))
    none = not np.isfinite(lam).any()
    ax.set_title("largest Lyapunov exponent" + (" (none computed: all periodic)"
                                                if none else ""))
    return m


#: the tick label of the grey swatch of the exponent panel
NOT_COMPUTED = "not computed"


def not_computed_text(grey, regime=None):
    """What the grey cells of the exponent panel are: ``"not computed"`` and, on a second
    line, the regimes of those cells in the dataset (``"(periodic)"``: the exponent is
    computed only where no period is found)."""
    if regime is None:
        return NOT_COMPUTED
    codes = np.unique(np.asarray(regime)[np.asarray(grey)])
    names = [REGIME_NAMES.get(int(c), "?") for c in codes]
    return f"{NOT_COMPUTED}\n({', '.join(names)})" if names else NOT_COMPUTED


def missing_swatch(ax, text):
    """A grey swatch (:data:`MISSING`) under the colour bar of ``ax``, labelled ``text``:
    the key of the cells drawn grey."""
    from matplotlib.patches import Rectangle

    sw = ax.inset_axes(SWATCH)
    sw.add_patch(Rectangle((0.0, 0.0), 1.0, 1.0, facecolor=MISSING, edgecolor="0.5",
                           lw=0.5, transform=sw.transAxes, label=text))
    sw.set_xticks([])
    sw.set_yticks([0.5], [text])
    sw.yaxis.tick_right()
    sw.tick_params(axis="y", length=0)
    sw.set_xlim(0.0, 1.0)
    sw.set_ylim(0.0, 1.0)
    for spine in sw.spines.values():
        spine.set_visible(False)
    return sw
