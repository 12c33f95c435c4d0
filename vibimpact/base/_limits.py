"""Size limits that refuse absurd requests before any work, with the estimated time.

The costs are rough single-core averages, used only to make the refusal message concrete
("about 11 months"); nothing else depends on them.  Where they come from:

* ``SECONDS_PER_POINT``: the main job's sweep (fig8, eta = 0.9:1.5:0.002, 301 points, all
  analyses, one worker), whose serial wall time ``python analyses/performance/benchmark_sweep.py``
  measures (``reports/performance.md``, section "sweep", row "1 worker"), divided by its
  301 points and rounded.  A parameter-map point costs about the same
  (``analyses/performance/benchmark_map.py``, ``reports/performance.md`` section "map").
* ``SECONDS_PER_PERIOD``: ``simulate`` of fig8 at eta = 1.0 (two impacts per period),
  DOP853 at the default tolerances, per forcing period; ``reports/performance.md``
  section "kernel" (a) measures the throughput at tighter tolerances.

Re-time them when those reports change by much (these constants are typed here, so
they are not regenerated with the reports).
"""
import math

#: most grid points of a sweep (per direction)
MAX_POINTS = 100_000
#: rough cost of one sweep point (all analyses), seconds
SECONDS_PER_POINT = 0.005
#: most forcing periods (transient + recorded) of one ``simulate`` call
MAX_PERIODS = 10_000_000
#: the most worker processes of one run (``--workers``, ``vi.Execution(workers=)``)
MAX_WORKERS = 4096
#: the forcing frequencies a run may have (``eta`` of every grid, ``--eta``): the forcing
#: period ``2 pi / eta`` within six orders of magnitude of the models' time unit (the
#: built-in models are scaled so that their natural frequency is about 1).  Below, one
#: forcing period needs more steps than the solver's step limit per period; above, a step
#: of the model's own dynamics spans millions of forcing periods, and a run's period
#: limit is spent before the motion shows
ETA_RANGE = (1e-6, 1e6)
#: rough cost of one forcing period of ``simulate``, seconds
SECONDS_PER_PERIOD = 5e-5


def human_duration(seconds):
    """``12 s``, ``5 minutes``, ``3 hours``, ``4 days``, ``2 years`` (rounded)."""
    if not math.isfinite(seconds):
        return "forever"
    for unit, size in (("years", 365.25 * 86400), ("days", 86400), ("hours", 3600),
                       ("minutes", 60)):
        if seconds >= 2 * size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.2g} s"


def check_points(count, name="eta"):
    """ValueError naming ``name`` when a grid of ``count`` points is over the limit."""
    if not math.isfinite(count):
        raise ValueError(f"{name} grid has too many points to count (the step is too "
                         f"small); at most {MAX_POINTS}")
    if count > MAX_POINTS:
        cost = human_duration(count * SECONDS_PER_POINT)
        shown = f"{count:.3g}" if isinstance(count, float) else str(count)
        raise ValueError(f"{name} grid has {shown} points (about {cost} at "
                         f"~{SECONDS_PER_POINT:g} s per point); at most {MAX_POINTS}")


def check_periods(periods, transient):
    """ValueError naming ``periods`` when ``periods + transient`` is over the limit."""
    total = periods + transient
    if total > MAX_PERIODS:
        cost = human_duration(total * SECONDS_PER_PERIOD)
        raise ValueError(f"periods={periods} (+ transient={transient}) is {total} forcing "
                         f"periods (about {cost} at ~{SECONDS_PER_PERIOD * 1e3:g} ms per "
                         f"period); at most {MAX_PERIODS} in one run")


#: most memory (bytes) the arrays of one request may need: a simulate run's samples, a
#: sweep's or map's results; the one limit of every request, checked before any work
MAX_BYTES = 4 << 30
#: bytes of one point of a sweep or map besides its Poincaré samples (the scalar
#: results, final state, orbit point, multipliers and their text), a generous estimate
POINT_OVERHEAD_BYTES = 1024


def human_bytes(n):
    """``512 bytes``, ``3.2 MiB``, ``149 GiB``, ``4.4e+06 TiB`` (binary units)."""
    for unit, size in (("TiB", 1 << 40), ("GiB", 1 << 30), ("MiB", 1 << 20),
                       ("KiB", 1 << 10)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{int(n)} bytes"


def check_memory(nbytes, what):
    """ValueError when the arrays of a request need more than :data:`MAX_BYTES`.

    Parameters
    ----------
    nbytes : int
        The estimate: the arrays the request allocates in proportion to the numbers it
        was given (:func:`run_bytes`, :func:`points_bytes`).
    what : str
        The request's numbers, named as the caller's arguments, for the message.
    """
    if nbytes > MAX_BYTES:
        raise ValueError(f"{what} needs about {human_bytes(nbytes)} of memory for its "
                         f"arrays; at most {human_bytes(MAX_BYTES)} in one request")


def run_bytes(periods, dense, n_state):
    """Bytes of a run's arrays: ``periods + 1`` stroboscopic samples and
    ``periods * dense + 1`` dense samples, each a state and a time, held twice (the run
    and its dataset)."""
    rows = (periods + 1) + (periods * dense + 1 if dense else 0)
    return 2 * 8 * (n_state + 1) * rows


def check_run(periods, transient, dense, n_state):
    """ValueError when a run is over a limit: :func:`check_periods`, and its arrays
    (:func:`run_bytes`) over :data:`MAX_BYTES`; the one check of :func:`vibimpact.simulate`
    and of ``vibimpact simulate`` before it sizes its output."""
    check_periods(periods, transient)
    check_memory(run_bytes(periods, dense, n_state),
                 f"periods={periods} with dense={dense}")


#: most memory (bytes) the variables of one input file may declare: a command or
#: :func:`vibimpact.io.read_netcdf` reads a file's variables whole, and a file of a few
#: kilobytes can declare terabytes (a dimension of 2**40 without data, read as fill
#: values).  The same as :data:`MAX_BYTES`: no file the toolkit writes holds more, since
#: every request's arrays are held to it before any work
MAX_READ_BYTES = MAX_BYTES
#: bytes counted per element of a variable of variable-length strings (its pointer and
#: a short text; the texts themselves are not declared)
TEXT_ITEM_BYTES = 16


class DeclaredTooLarge(ValueError):
    """An input whose variables declare more than :data:`MAX_READ_BYTES`
    (:func:`check_declared`); its message names the file."""


def check_declared(variables, path, what="file"):
    """Refuse an input whose variables declare more than :data:`MAX_READ_BYTES`, before
    any of them is read.

    Parameters
    ----------
    variables : iterable of (str, tuple of int, int or None)
        ``(name, shape, itemsize)`` of each variable that will be loaded, from the
        file's metadata; an itemsize of None (variable-length strings) counts
        :data:`TEXT_ITEM_BYTES` per element.
    path : str
        The file, for the message.
    what : str
        What the file is ("file", "map").

    Raises
    ------
    DeclaredTooLarge
        A ValueError naming the file, the largest variable, its shape and the declared
        size.
    """
    total = 0
    largest: tuple[object, tuple[int, ...], int] | None = None
    for name, shape, itemsize in variables:
        n = math.prod(int(s) for s in shape) * int(itemsize or TEXT_ITEM_BYTES)
        total += n
        if largest is None or n > largest[2]:
            largest = (name, tuple(int(s) for s in shape), n)
    if total > MAX_READ_BYTES:
        assert largest is not None  # total > 0: some variable was counted
        name, shape, n = largest
        raise DeclaredTooLarge(f"{what} {path!r} declares {human_bytes(total)} of data "
                               f"(variable {str(name)[:60]!r} of shape {shape}: "
                               f"{human_bytes(n)}); at most {human_bytes(MAX_READ_BYTES)} "
                               "are read from one file")


def points_bytes(points, n_samples, n_state):
    """Bytes of the results of ``points`` sweep or map points with ``n_samples``
    Poincaré samples each."""
    return points * (8 * n_samples * n_state + POINT_OVERHEAD_BYTES)


#: most pixels of one drawn figure (width x height at its dpi): 2**28, about 1 GiB of
#: RGBA in the renderer; matplotlib's Agg fails with MemoryError well before its own
#: per-side limit of 2**23
MAX_PIXELS = 1 << 28
#: most pixels along one side of a drawn figure
MAX_SIDE_PIXELS = 1 << 16


def check_pixels(width, height, dpi, what="figure", smallest_pt=None):
    """Refuse a figure of ``width`` x ``height`` inches at ``dpi`` larger than
    :data:`MAX_PIXELS`, or :data:`MAX_SIDE_PIXELS` along a side (``--figsize 1e9x1e9``
    or ``--dpi 1000000`` ended in ``MemoryError`` from the renderer, after all the
    work), or one that cannot be drawn (:func:`check_drawable`).

    Raises
    ------
    ValueError
        Saying the size in pixels and the limit.
    """
    w, h = float(width) * float(dpi), float(height) * float(dpi)
    if not (math.isfinite(w * h) and w * h <= MAX_PIXELS and max(w, h) <= MAX_SIDE_PIXELS):
        raise ValueError(f"{what} of {width:g} x {height:g} inches at {dpi:g} dpi would be "
                         f"{w:.3g} x {h:.3g} pixels; at most {MAX_PIXELS:.3g} pixels and "
                         f"{MAX_SIDE_PIXELS} a side are drawn")
    check_drawable(width, height, dpi, what, smallest_pt)


def check_drawable(width, height, dpi, what="figure", smallest_pt=None):
    """Refuse a figure of ``width`` x ``height`` inches at ``dpi`` with a side under one
    pixel (an empty image cannot be written: ``--dpi 1e-300`` failed so after the
    work); and, given the size ``smallest_pt`` in points of the smallest text the figure
    draws, a ``dpi`` at which that text is under one pixel (``dpi * smallest_pt / 72 <
    1``: FreeType cannot raster a glyph under a pixel, ``--dpi 1`` ended in "invalid
    ppem").  The text is checked first (it does not depend on the size).

    Raises
    ------
    ValueError
        Saying the size in pixels and the limit.
    """
    if smallest_pt is not None and float(dpi) * smallest_pt / 72.0 < 1.0:
        raise ValueError(f"{what} at {dpi:g} dpi would draw its smallest text "
                         f"({smallest_pt:.3g} pt) {float(dpi) * smallest_pt / 72.0:.2g} "
                         f"pixels high; the renderer cannot draw a glyph under 1 pixel: "
                         f"give at least {72.0 / smallest_pt:.3g} dpi")
    w, h = float(width) * float(dpi), float(height) * float(dpi)
    if min(w, h) < 1.0:
        raise ValueError(f"{what} of {width:g} x {height:g} inches at {dpi:g} dpi would be "
                         f"{w:.3g} x {h:.3g} pixels; a side must be at least 1 pixel")
