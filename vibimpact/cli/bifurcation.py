"""``vibimpact bifurcation``: sweep eta up and down and draw the bifurcation diagram, its
data written next to the image.

Only the standard library and the command line's shared parts are imported at module
level; numpy, numba, xarray and matplotlib inside the command.
"""
from __future__ import annotations

import os
from typing import TYPE_CHECKING

from .common.checkpoints import run_checkpointed
from .common.figures import add_figure_options, figure_options, image_ext_ok
from .common.files import check_output, sweep_file_bytes, write_outputs
from .common.inputs import check_distinct
from .common.sweeps import add_sweep_options, command_line, sweep_inputs

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Callable

#: what a point of the diagram computes: its Poincare points and what its label needs
#: (the chaos tests run only where no period is found)
LABEL_ANALYSES = ("period", "impacts", "poincare", "lyapunov", "test01")

_BIFURCATION_EPILOG = """\
example:
  vibimpact bifurcation --eta 0.9:1.5:0.002 --preset fig8 -o bif.png

Sweeps eta up and down (--direction both by default) computing only the period, the
impacts, the Poincare (stroboscopic) points and, where no period is found, the chaos
tests (largest Lyapunov exponent, 0-1 test) that the labels need, so that its labels
and --kind intervals are those of 'vibimpact classify'; draws X and Y of the Poincare
points against eta (up and down sweeps told apart, on bands of their regimes) and
writes the data next to the image (bif.png -> bif.nc);
'vibimpact plot bif.nc --kind bifurcation' redraws it.

exit status: 0 written, 2 bad input (nothing computed) or a worker process died
(nothing written), 130 interrupted (Ctrl-C), 143 terminated (SIGTERM).
"""


def _cmd_bifurcation(args):
    # ``vibimpact rerun`` sets ``data_only`` to the .nc path: no image is drawn then
    data_only = getattr(args, "data_only", None)
    image = os.fspath(args.output)
    if data_only is None:
        image_ext_ok(image, "-o")
        data = os.path.splitext(image)[0] + ".nc"
    else:
        data = os.fspath(data_only)
    etas, params = sweep_inputs(args)
    if data_only is None:
        check_output(image, args.overwrite, "image file")
    check_output(data, args.overwrite, "data file",
                 size=sweep_file_bytes(params, etas.size, args.direction))
    check_distinct(("-o", None if data_only is not None else image), ("its data file", data))

    import vibimpact as vi
    from .. import io
    from ..plotting import plot_bifurcation

    run = vi.Execution(workers=args.workers,
                       progress=not args.no_progress and "bifurcation")
    ds, status = run_checkpointed(None, "points", lambda: vi.sweep(
        params, etas, direction=args.direction, analyses=LABEL_ANALYSES,
        continuation=vi.Continuation(blocks=args.blocks), execution=run))
    if ds is None:
        return status
    ds.attrs.update(command=command_line(args), preset=args.preset, eta_range=args.eta)
    writes: list[tuple[str, Callable[[], object]]] = [
        (data, lambda: io.write_netcdf(ds, data, overwrite=args.overwrite))]
    if data_only is None:
        writes.append((image, lambda: plot_bifurcation(ds, path=image,
                                                       **figure_options(args))))
    write_outputs(*writes)  # both or neither
    if data_only is not None:
        print(f"wrote {data}")
        return 0
    print(f"wrote {image} and {data}")
    return 0


def add_parser(sub, fmt):
    """Add ``bifurcation`` to the subparsers ``sub``."""
    b = sub.add_parser("bifurcation", help="sweep eta and draw the bifurcation diagram",
                       formatter_class=fmt, epilog=_BIFURCATION_EPILOG,
                       description="Sweep eta up and down and draw the Poincare points "
                                   "against eta; the data is written\nnext to the image "
                                   "as NetCDF.")
    add_sweep_options(b, "both")
    b.add_argument("-o", "--output", default="bifurcation.png", metavar="FILE.png",
                   help="image to write (default: bifurcation.png); the data goes to "
                        "FILE.nc")
    add_figure_options(b, "the image")
    b.set_defaults(func=_cmd_bifurcation)
