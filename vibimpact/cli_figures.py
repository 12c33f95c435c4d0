"""The figure options of the commands that draw: ``--figsize``, ``--dpi``, ``--style``,
and the image extension (matplotlib imported only when used)."""
import argparse
import os

from .cli_errors import UsageError


def _figsize(text):
    from .plotting.style import check_figsize

    w, sep, h = str(text).lower().partition("x")
    try:
        if sep:
            return check_figsize((float(w), float(h)))
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"must be WIDTHxHEIGHT in inches, two numbers > 0 "
                                     f"(e.g. 3.5x2.8), got {text!r}")


def _dpi(text):
    from .plotting.style import check_dpi

    try:
        return check_dpi(float(text))
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"must be a number > 0 (dots per inch), got {text!r}")


def _style(text):
    from .plotting.style import STYLES, check_style

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
