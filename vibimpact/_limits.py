"""Size limits that refuse absurd requests before any work, with the estimated time.

The costs are rough single-core averages, used only to make the refusal message concrete
("about 11 months"); nothing else depends on them.  Where they come from:

* ``SECONDS_PER_POINT``: the main job's sweep (fig8, eta = 0.9:1.5:0.002, 301 points, all
  analyses, one worker), whose serial wall time ``python analyses/benchmark_sweep.py``
  measures (``reports/performance.md``, section "sweep", row "1 worker"): 1.58 s there,
  1.5 s in a re-timing on 2026-11-25 (same VM, warm cache), i.e. ~0.005 s per point.  A
  parameter-map point costs about the same (``analyses/benchmark_map.py``: 1452 points
  in 6.4 s serial, ~0.0044 s per point).
* ``SECONDS_PER_PERIOD``: ``simulate`` of fig8 at eta = 1.0 (two impacts per period),
  DOP853 at the default tolerances, 2000 periods in 0.094 s (re-timed 2026-11-25), i.e.
  ~5e-5 s per period; ``reports/performance.md`` section "kernel" (a) measures the
  throughput at tighter tolerances (1000 periods in 0.06 s).

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
