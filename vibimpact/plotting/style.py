"""The look of every figure: its size, its resolution and its style, defined once.

Two styles, each a dict of matplotlib ``rcParams`` applied while a figure is drawn (and
saved), never to the global state:

* ``"default"`` (:data:`DEFAULT_STYLE`): sans-serif at matplotlib's sizes, figures sized
  for a screen, a title naming the preset and the parameters;
* ``"paper"`` (:data:`PAPER_STYLE`): a journal look, serif fonts sized for a
  single-column figure (8 pt text, 7 pt ticks and legends), thin lines and ticks,
  TrueType fonts embedded in PDF, 300 dpi, and no title over the axes (a caption says
  it); figures are one column, :data:`COLUMN_WIDTH` inches, wide (the four-panel map two
  columns).

Every plotting function takes ``figsize``, ``dpi`` and ``style`` and checks them with
:func:`look`; the command line's ``--figsize``, ``--dpi`` and ``--style`` are the same
checks.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, cast

import logging
import math
import numbers
import os
import tempfile
from dataclasses import dataclass

from ..base import _validate as _v

if TYPE_CHECKING:  # names of the annotations only
    from matplotlib.figure import Figure
    from matplotlib.typing import RcKeyType

__all__ = ["BAND_ALPHA", "COLUMN_WIDTH", "DEFAULT_STYLE", "LONG_PERIOD_COLOR",
           "PAPER_STYLE", "PERIOD_COLORS", "REGIME_COLORS", "STYLES", "Look", "class_color",
           "look", "save_figure", "width"]

# --- the colours of the regime classes ---------------------------------------------------
# One colour per class a sweep's figures tell apart (the regime bands of plot_response and
# plot_intervals, the points of the Lyapunov plot): every pair differs by CIEDE2000
# Delta E >= 12 as drawn (opaque, and at BAND_ALPHA over white), well above the ~2.3 of a
# just-noticeable difference (Sharma 2003) and the ~10 at which two colours read as
# different categories rather than shades (Szafir 2017, small marks); the set started from
# the anchors chaotic red, quasi-periodic orange, unsettled purple, diverged black, not
# computed grey and was filled from ColorBrewer, Tableau and Paul Tol colours by largest
# smallest difference.  The old shades of green for P1..P6 differed by 2.7 (P2/P6) and 7.7
# (P1/P3): near-identical.  tests/test_figures_palette.py measures it.

#: regime code -> colour (periodic: by period, :data:`PERIOD_COLORS`)
REGIME_COLORS = {0: "#d9d9d9", 2: "#ff8c00", 3: "#e8001c", 4: "#262626", 5: "#9b30d9"}
#: colour of P1, P2, ... P8
PERIOD_COLORS = ("#2ca02c", "#386cb0", "#ffff33", "#17becf", "#fb9a99", "#a65628",
                 "#882255", "#999933")
#: colour of a periodic motion whose period is longer than len(PERIOD_COLORS) or not
#: resolved
LONG_PERIOD_COLOR = "#bc80bd"
#: opacity of the regime bands behind the response curves
BAND_ALPHA = 0.5
_REGIME_NAMES = {0: "not computed", 2: "quasi-periodic", 3: "chaotic", 4: "diverged",
                 5: "unsettled"}


def class_color(regime: int, period: int) -> tuple[str, str, tuple[int, int]]:
    """Colour, legend name and legend order of a regime class.

    Parameters
    ----------
    regime : int
        The regime code (CF flag of the ``regime`` variable; 1 periodic).
    period : int
        The period n of a periodic motion (0: not resolved).

    Returns
    -------
    (str, str, (int, int))
        P1 ... P8 each their own colour; a longer or unresolved period one colour
        ("periodic, long period"); the other regimes theirs.
    """
    regime, period = int(regime), int(period)
    if regime == 1 and 0 < period <= len(PERIOD_COLORS):
        return PERIOD_COLORS[period - 1], f"P{period}", (1, period)
    if regime == 1:
        return (LONG_PERIOD_COLOR, f"periodic, period > {len(PERIOD_COLORS)} or long",
                (1, 10**6))
    return (REGIME_COLORS.get(regime, REGIME_COLORS[0]), _REGIME_NAMES.get(regime, "?"),
            (regime if regime else 9, 0))


def text_color(color: str) -> str:
    """Black or white, whichever reads better on ``color`` (its relative luminance, WCAG
    2: white below 0.179, where both contrasts are equal)."""
    from matplotlib.colors import to_rgb

    lin = [c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4
           for c in to_rgb(color)]
    lum = 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2]
    return "white" if lum < 0.179 else "black"

#: rcParams of the ``"default"`` style (matplotlib's, with smaller legends)
DEFAULT_STYLE: dict[RcKeyType, Any] = {"legend.fontsize": "small", "legend.title_fontsize": "small",
                 "axes.titlesize": "medium", "figure.titlesize": "medium",
                 "grid.linewidth": 0.4}

#: rcParams of the ``"paper"`` style: a journal's single-column figure
PAPER_STYLE: dict[RcKeyType, Any] = {
    # a Times-like serif; DejaVu Serif for the glyphs STIX lacks (subscripts)
    "font.family": ["STIXGeneral", "DejaVu Serif"],
    "mathtext.fontset": "stix",
    "font.size": 8.0,
    "axes.labelsize": 8.0,
    "axes.titlesize": 8.0,
    "figure.titlesize": 8.0,
    "xtick.labelsize": 7.0,
    "ytick.labelsize": 7.0,
    "legend.fontsize": 7.0,
    "legend.title_fontsize": 7.0,
    "legend.frameon": False,
    "lines.linewidth": 0.8,
    "lines.markersize": 3.0,
    "axes.linewidth": 0.5,
    "patch.linewidth": 0.5,
    "hatch.linewidth": 0.4,
    "grid.linewidth": 0.3,
    "xtick.major.width": 0.5,
    "ytick.major.width": 0.5,
    "xtick.minor.width": 0.4,
    "ytick.minor.width": 0.4,
    "xtick.major.size": 2.5,
    "ytick.major.size": 2.5,
    "xtick.direction": "in",
    "ytick.direction": "in",
    "pdf.fonttype": 42,
    "ps.fonttype": 42,
}

#: style name -> rcParams
STYLES: dict[str, dict[RcKeyType, Any]] = {"default": DEFAULT_STYLE, "paper": PAPER_STYLE}

#: resolution (dots per inch) of a saved figure, per style
DPI = {"default": 150.0, "paper": 300.0}

#: width of a journal column in inches (the ``"paper"`` figures')
COLUMN_WIDTH = 3.5

#: the relative sizes the figures give text beyond their style's (``fontsize="small"``
#: of the sweep panels' titles and the basins' legend)
TEXT_SCALINGS = ("small",)


def smallest_text_pt():
    """The size in points of the smallest text any figure draws in any style: the
    smallest font size of :data:`STYLES` (their ``*size`` entries, matplotlib's default
    for those they leave, and :data:`TEXT_SCALINGS` of their ``font.size``), times the
    size of mathtext's sub- and superscripts (``$X_m$``; matplotlib's
    ``SHRINK_FACTOR``).

    :func:`vibimpact.base._limits.check_pixels` refuses a resolution at which it is under
    one pixel (FreeType cannot raster such a glyph)."""
    from matplotlib import rcParamsDefault
    from matplotlib._mathtext import SHRINK_FACTOR
    from matplotlib.font_manager import font_scalings

    sizes = []
    for style in STYLES.values():
        params: dict[RcKeyType, Any] = {**rcParamsDefault, **style}
        base = float(params["font.size"])
        keys = [k for k in params if k.endswith(("fontsize", "labelsize", "titlesize"))
                or k == "font.size"]
        for value in [params[k] for k in keys] + list(TEXT_SCALINGS):
            if isinstance(value, str):
                value = base * font_scalings.get(value, 1.0)  # "medium", "small", ...
            sizes.append(float(value))
    return min(sizes) * SHRINK_FACTOR


def check_figsize(figsize) -> tuple[float, float] | None:
    """``figsize`` as a ``(width, height)`` tuple of finite floats > 0 (inches), or None.

    Raises
    ------
    ValueError
        Naming ``figsize``.
    """
    if figsize is None:
        return None
    text = (f"figsize must be (width, height) in inches, two finite numbers > 0, got "
            f"{figsize!r}")
    if isinstance(figsize, (str, bytes)):
        raise _v.WrongType(text)
    try:
        pair = tuple(figsize)
    except TypeError:
        raise _v.WrongType(text) from None
    if not all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in pair):
        raise _v.WrongType(text)
    if len(pair) != 2 or not all(math.isfinite(v) and v > 0 for v in pair):
        raise ValueError(text)
    return float(pair[0]), float(pair[1])


def check_dpi(dpi):
    """``dpi`` as a finite float > 0, or None.

    Raises
    ------
    ValueError
        Naming ``dpi``.
    """
    if dpi is None:
        return None
    text = f"dpi must be a finite number > 0 (dots per inch), got {dpi!r}"
    if isinstance(dpi, bool) or not isinstance(dpi, numbers.Real):
        raise _v.WrongType(text)
    if not math.isfinite(dpi) or dpi <= 0:
        raise ValueError(text)
    return float(dpi)


def check_style(style):
    """``style`` as one of :data:`STYLES` (None: ``"default"``).

    Raises
    ------
    ValueError
        Naming ``style``.
    """
    if style is None:
        return "default"
    if not isinstance(style, str):
        raise _v.WrongType(f"style must be a str, one of {', '.join(map(repr, STYLES))}, "
                           f"got {type(style).__name__} {style!r}")
    if style not in STYLES:
        raise ValueError(f"style must be one of {', '.join(map(repr, STYLES))}, "
                         f"got {style!r}")
    return style


def width(factor):
    """A line width ``factor`` times the style's ``lines.linewidth`` (1.5 in the default
    style, 0.8 in the paper style), so that every line of a figure thins together."""
    from matplotlib import rcParams

    return factor * float(rcParams["lines.linewidth"])


@dataclass(frozen=True)
class Look:
    """The checked ``figsize``, ``dpi`` and ``style`` of one figure (made by :func:`look`).

    Attributes
    ----------
    style : str
    figsize : tuple of float or None
        None: the plot kind's own size for the style.
    dpi : float or None
        None: :data:`DPI` of the style for a new figure; the figure's own when saving
        into given axes.
    """

    style: str = "default"
    figsize: tuple[float, float] | None = None
    dpi: float | None = None

    @property
    def paper(self):
        """True for the ``"paper"`` style."""
        return self.style == "paper"

    def context(self):
        """The style's rcParams, applied while the figure is drawn and saved."""
        import matplotlib

        return matplotlib.rc_context(STYLES[self.style])

    def size(self, default, paper_height, columns=1) -> tuple[float, float]:
        """The figure size: ``figsize``, else ``default`` (width, height) in the default
        style and ``columns`` journal columns by ``paper_height`` inches in the paper
        style."""
        if self.figsize is not None:
            return self.figsize
        if self.paper:
            return COLUMN_WIDTH * columns, float(paper_height)
        return cast("tuple[float, float]", tuple(default))  # (width, height)

    def figure(self, default, paper_height, columns=1):
        """A new constrained-layout Figure of :meth:`size` at the look's resolution."""
        from matplotlib.figure import Figure

        from ..base._limits import check_pixels

        size, dpi = self.size(default, paper_height, columns), self.dpi or DPI[self.style]
        try:
            check_pixels(*size, dpi, smallest_pt=smallest_text_pt())
        except ValueError as exc:
            raise ValueError(f"figsize, dpi: {exc}") from None
        return Figure(figsize=size, dpi=dpi, layout="constrained")

    def title(self, target, text):
        """Set the title of axes ``target`` (or the suptitle of a Figure), except in the
        paper style, where the caption says it."""
        if self.paper or not text:
            return
        if hasattr(target, "suptitle"):
            target.suptitle(text)
        else:
            target.set_title(text)

    def legend(self, ax, handles=None, ncol=1, **kwargs):
        """A legend beside ``ax``, outside the data: on the right in the default style,
        above the axes in the paper style (where the figure is one column narrow)."""
        if self.paper:
            place = dict(loc="lower left", bbox_to_anchor=(0.0, 1.01, 1.0, 0.1),
                         mode="expand", ncol=max(ncol, 2), borderaxespad=0.0)
        else:
            place = dict(loc="upper left", bbox_to_anchor=(1.01, 1.0), ncol=ncol,
                         borderaxespad=0.0)
        place.update(kwargs)
        return ax.legend(handles=handles, **place) if handles is not None else \
            ax.legend(**place)

    def legend_below(self, ax, own, handles, **kwargs):
        """A legend of ``handles`` under the figure's axes when the figure is the
        plotting function's ``own`` (constrained layout makes room for it), else under
        ``ax``, the caller's axes, whose figure may hold other plots."""
        kwargs.setdefault("frameon", False)
        if own:
            return ax.figure.legend(handles=handles, loc="outside lower center", **kwargs)
        return ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.15),
                         **kwargs)

    def finish(self, fig, path=None):
        """Lay the figure out while the style is applied (the ticks and texts that
        matplotlib makes at drawing time get its fonts and widths too) and save it to
        ``path`` when given, at the look's dpi.  Returns ``fig``."""
        fig.draw_without_rendering()
        if path is not None:
            save_figure(fig, path, dpi=self.dpi or fig.dpi)
        return fig


def save_figure(fig: Figure, path: str | os.PathLike[str], dpi: float | None = None) -> None:
    """Save a figure atomically (temporary file in the same directory, then rename).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    path : str or os.PathLike
        The format follows the extension (``.png``, ``.pdf``, ``.svg``, ...).
    dpi : float, optional
        Resolution in dots per inch; the figure's own (``fig.dpi``) by default, which
        the plotting functions set from their ``dpi`` (150 unless told; 300 in the paper
        style).

    Raises
    ------
    ValueError
        For a path :func:`vibimpact.io.check_output_path` refuses (a missing directory,
        a device, ...) or an unsupported extension.
    OSError
        When the file cannot be written (no temporary file is left behind).
    """
    from ..io import check_output_path, write_failed

    path = check_output_path(path, overwrite=True, what="figure", free=0)
    directory = os.path.dirname(os.path.abspath(path))
    ext = os.path.splitext(path)[1].lstrip(".").lower()
    supported = fig.canvas.get_supported_filetypes()
    if ext not in supported:
        raise ValueError(f"cannot save a figure as {path!r}: unknown extension; use one of "
                         f"{', '.join('.' + e for e in sorted(supported))}")
    from ..base._limits import check_drawable, check_pixels
    from ..base._writing import before_write, temp_prefix

    out_dpi = fig.dpi if dpi is None else check_dpi(dpi)
    try:
        w_in, h_in = fig.get_size_inches()
        check_pixels(w_in, h_in, out_dpi)
        check_drawable(w_in, h_in, out_dpi, smallest_pt=smallest_text_pt())
    except ValueError as exc:
        raise ValueError(f"dpi: {exc}") from None
    before_write()
    # .NAME.PID-*.tmp: the next write of ``path`` removes it if this process dies here
    fd, tmp = tempfile.mkstemp(prefix=temp_prefix(path), suffix=".tmp", dir=directory)
    os.close(fd)
    try:
        try:
            fig.savefig(tmp, format=ext, dpi=out_dpi)
            mask = os.umask(0o022)
            os.umask(mask)
            os.chmod(tmp, 0o666 & ~mask)
            os.replace(tmp, path)
        except OSError as exc:  # a full disk
            raise write_failed(path, exc) from None
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    w, h = fig.get_size_inches()
    logging.getLogger(__name__).info("figure written to %s (%.3g x %.3g in, %g dpi)", path,
                                     w, h, fig.dpi if dpi is None else dpi)


def look(figsize=None, dpi=None, style=None, ax=None):
    """Check the figure options of a plotting function.

    Parameters
    ----------
    figsize : (float, float), optional
        Width and height in inches, > 0.
    dpi : float, optional
        Resolution of a saved figure, > 0.
    style : {"default", "paper"}, optional
    ax : optional
        The axes the caller was given: a ``figsize`` is refused with them (their figure
        has its size already).

    Returns
    -------
    Look

    Raises
    ------
    ValueError
        Naming the argument.
    """
    size = check_figsize(figsize)
    if size is not None and ax is not None:
        raise ValueError("figsize sizes a new figure; leave it out when passing ax "
                         "(size ax's figure instead)")
    dpi = check_dpi(dpi)
    if size is not None or dpi is not None:
        from ..base._limits import check_drawable, check_pixels

        # a pixel a side at the style's smallest resolution, text of a pixel at dpi (every
        # default figure is over an inch a side: the text rule keeps it over one pixel)
        try:
            check_drawable(*(size or (1.0, 1.0)), dpi or min(DPI.values()),
                           smallest_pt=smallest_text_pt() if dpi is not None else None)
            if size is not None and dpi is not None:
                check_pixels(*size, dpi)
        except ValueError as exc:
            raise ValueError(f"figsize, dpi: {exc}") from None
    return Look(style=check_style(style), figsize=size, dpi=dpi)


def attractor_colour(gid: int):
    """The colour of attractor ``A<gid>`` in every census, basins and orbit figure:
    tab10, then tab20's light shades, by its global id (one attractor, one colour)."""
    from matplotlib import colormaps

    # the stubs type a registered map as a Colormap, without .colors (ListedColormaps)
    tab10, tab20 = [colormaps[m].colors for m in ("tab10", "tab20")]  # type: ignore[attr-defined]
    base = list(tab10) + list(tab20[1::2])
    return base[int(gid) % len(base)]
