"""Size limits that refuse absurd requests before any work, with the estimated time.

The costs are rough averages measured on the fig8 sweep (``reports/performance.md``: 301
points in about 7 s on one core, i.e. ~0.025 s per point; one forcing period of
``simulate`` with DOP853 at the default tolerances takes ~0.2 ms).  They only make the
refusal message concrete ("about 11 months"); nothing else depends on them.
"""
import math

#: most grid points of a sweep (per direction)
MAX_POINTS = 100_000
#: rough cost of one sweep point (all analyses), seconds
SECONDS_PER_POINT = 0.03
#: most forcing periods (transient + recorded) of one ``simulate`` call
MAX_PERIODS = 10_000_000
#: rough cost of one forcing period of ``simulate``, seconds
SECONDS_PER_PERIOD = 2e-4


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
