"""The figure options of the commands that draw: ``--figsize``, ``--dpi``, ``--style``,
and the image extension (matplotlib imported only when used)."""
import argparse
import os

from ...base._text import parse_real
from .errors import UsageError


def _figsize(text):
    from ...plotting.style import check_figsize

    w, sep, h = str(text).lower().partition("x")
    try:
        if sep:
            return check_figsize((parse_real(w), parse_real(h)))
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"must be WIDTHxHEIGHT in inches, two numbers > 0 "
                                     f"(e.g. 3.5x2.8), got {text!r}")


def _dpi(text):
    from ...plotting.style import check_dpi

    try:
        return check_dpi(parse_real(text))
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"must be a number > 0 (dots per inch), got {text!r}")


def _style(text):
    from ...plotting.style import STYLES, check_style

    try:
        return check_style(text)
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"must be one of {', '.join(map(repr, STYLES))}, "
                                     f"got {text!r}")


def add_figure_options(parser, what="the figure"):
    """``--figsize``, ``--dpi`` and ``--style`` of a command that draws ``what``; checked
    by :mod:`vibimpact.plotting.style`, as the plotting functions check their arguments."""
    parser.add_argument("--figsize", type=_figsize, default=None, metavar="WxH",
                        help=f"size of {what} in inches, e.g. 3.5x2.8 (default: the "
                             "kind's own; one journal column, 3.5 wide, with --style "
                             "paper)")
    parser.add_argument("--dpi", type=_dpi, default=None, metavar="N",
                        help=f"resolution of {what} in dots per inch (default: 150; 300 "
                             "with --style paper)")
    parser.add_argument("--style", type=_style, default=None, metavar="{default,paper}",
                        help="paper: a journal's look (serif fonts sized for one column, "
                             "thin lines, no title)")


#: the largest figure a command draws by default, in inches (a map of both sweep
#: directions): what --dpi is checked with when --figsize is not given
LARGEST_DEFAULT = (12.0, 16.0)
#: the resolution of a figure when --dpi is not given (the paper style's)
LARGEST_DPI = 300.0


def check_figure_size(args):
    """Refuse, before any work, a ``--figsize`` and ``--dpi`` whose image would exceed
    :data:`vibimpact.base._limits.MAX_PIXELS` (checked with :data:`LARGEST_DEFAULT` and
    :data:`LARGEST_DPI` for the option not given) or could not be drawn (a side under a
    pixel at the smallest resolution of a style, text under a pixel at ``--dpi``:
    :func:`vibimpact.base._limits.check_drawable`); the one check of every command that
    draws.  UsageError naming the options."""
    from ...base import _limits

    figsize: tuple[float, float] | None = getattr(args, "figsize", None)
    dpi: float | None = getattr(args, "dpi", None)
    if figsize is None and dpi is None:
        return
    from ...plotting.style import DPI, smallest_text_pt

    given = " ".join(([f"--figsize {figsize[0]:g}x{figsize[1]:g}"] if figsize is not None
                      else []) + ([f"--dpi {dpi:g}"] if dpi is not None else []))
    # at least a pixel a side at the smallest resolution, text of a pixel at --dpi (every
    # default figure is over an inch a side: the text rule keeps it over one pixel)
    try:
        _limits.check_drawable(*(figsize or (1.0, 1.0)),
                             dpi if dpi is not None else min(DPI.values()), what="the image",
                             smallest_pt=smallest_text_pt() if dpi is not None else None)
    except ValueError as exc:
        raise UsageError(f"{given}: {exc}; give a larger --figsize or --dpi") from None
    width, height = figsize if figsize is not None else LARGEST_DEFAULT
    try:
        _limits.check_pixels(width, height, dpi if dpi is not None else LARGEST_DPI,
                             what="the image")
    except ValueError as exc:
        raise UsageError(f"{given}: {exc}; give a smaller --figsize or --dpi") from None


def figure_options(args, drawing=True):
    """``{"figsize", "dpi", "style"}`` of the parsed arguments, for the plotting function;
    UsageError when one is given and ``drawing`` is false (no --plot to apply it to)."""
    opts = {k: getattr(args, k, None) for k in ("figsize", "dpi", "style")}
    if not drawing:
        given = [f"--{k}" for k, v in opts.items() if v is not None]
        if given:
            raise UsageError(f"{', '.join(given)}: for the image of --plot; give --plot "
                             "too")
    return opts


def image_ext_ok(path, what):
    from matplotlib.backend_bases import FigureCanvasBase

    ext = os.path.splitext(path)[1].lstrip(".").lower()
    if ext == "nc" or ext not in FigureCanvasBase.get_supported_filetypes():
        raise UsageError(f"{what} {path!r}: unknown image extension (use .png, .pdf or "
                          ".svg)")
