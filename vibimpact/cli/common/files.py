"""The files a command reads and writes: output paths checked before computing, input
files read with one line on failure, outputs written together or not at all."""
import os

from ...base._regular import why_not_a_file
from .errors import UsageError, error_text, reason


def check_output(path, overwrite, what, store=False, size=0):
    """Fail early (before computing) if ``path`` cannot be created: the one check of an
    output path (:func:`vibimpact.io.check_output_path`) as a :class:`UsageError`;
    ``size`` (bytes, an estimate of the file) must be free on its file system, and at
    least :data:`vibimpact.io.MIN_FREE`.

    Returns
    -------
    str
        The path (a store's trailing ``/`` removed).
    """
    from ...io import MIN_FREE, check_output_path

    try:
        return check_output_path(path, overwrite, what=what, store=store,
                                 free=max(MIN_FREE, size))
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None


def sweep_file_bytes(params, points, direction="up"):
    """An estimate of the file of a sweep or map of ``points`` grid points per
    direction (``"both"``: twice as many), for :func:`check_output`'s ``size``."""
    from ...base._limits import points_bytes
    from ...points.point import SweepSettings
    from ...core.system import to_system

    points *= 2 if direction == "both" else 1
    return points_bytes(points, SweepSettings().n_samples, to_system(params).n_state)


def is_store(path):
    """A Zarr store (a directory with its ``zarr.json``), as ``map`` writes."""
    return os.path.isdir(path) and os.path.isfile(os.path.join(path, "zarr.json"))


def read_input(path, what="", stores=False):
    """The dataset of an input file a command reads, or one line saying why not.

    Parameters
    ----------
    path : str
    what : str
        The option or role that names the file in the messages (``"--from"``).
    stores : bool
        Also read a Zarr store (a map).

    Raises
    ------
    UsageError
        A directory, a missing file or one that cannot be read.
    """
    from ... import io

    label = f"{what} {path!r}".strip()
    if stores and is_store(path):
        from ...maps.store import open_map

        reader, kind = open_map, "a Zarr store"
    elif os.path.isdir(path):
        raise UsageError(f"{label} is a directory, not a NetCDF file"
                         + (" or a Zarr store" if stores else ""))
    elif not os.path.isfile(path):
        raise UsageError(label + why_not_a_file(path))  # or a FIFO, a device, ...
    else:
        reader, kind = io.read_netcdf, "NetCDF"
    from ...base._limits import DeclaredTooLarge

    try:
        return reader(path)
    except DeclaredTooLarge as exc:  # the message names the file already
        raise UsageError(f"{what + ': ' if what else ''}{error_text(exc)}") from None
    except Exception as exc:  # netCDF4 raises OSError, xarray ValueError, ...
        raise UsageError(f"{what + ': ' if what else ''}cannot read {path!r} as {kind}: "
                         f"{reason(exc)}") from None


def write_outputs(*writes):
    """Write a command's outputs so that they succeed or fail together.

    Parameters
    ----------
    *writes : (str, callable)
        ``(path, write)`` in order; ``write()`` writes ``path``.  When one fails, or a
        signal (Ctrl-C, SIGTERM) stops the command before the last is written, the
        outputs written before it are removed again.

    Raises
    ------
    UsageError
        The failure in one line (ValueError, OSError, a NetCDF RuntimeError).
    """
    done: list[str] = []

    def undo():
        for path in done:
            try:
                os.unlink(path)
            except OSError:
                pass

    try:
        for path, write in writes:
            write()
            done.append(path)
    except (ValueError, OSError, RuntimeError) as exc:
        undo()
        written = f" ({', '.join(map(repr, done))} removed again)" if done else ""
        raise UsageError(f"{error_text(exc)}{written}") from None
    except BaseException:
        # Ctrl-C or SIGTERM between two outputs: none of them stays (the signal's own
        # line and exit status follow)
        undo()
        raise
