"""What a call into the compiled kernel costs beyond the kernel's own work, and what the
main job's sweep spends outside the kernel.

Run as ``python analyses/performance/call_overhead.py``; replaces the "call_overhead"
section of ``reports/performance.md``.  Measured in one run, after a warm-up:

* the cost of a call that does no work (the integration loop entered with its clock
  already at the end; the linear solve of a 4 x 4 system), through the package's way in
  (:mod:`vibimpact._kernel.boundary`, a :class:`~vibimpact._kernel.precompiled.Routine`),
  through numba's dispatcher (which types every argument of every call), and through the
  compiled entry point itself; best of several batches, microseconds per call;
* the main job's sweep in the process (fig8, ``0.9:1.5:0.002`` up, every analysis, one
  worker): its wall time and the time spent inside the compiled integration loop (each
  call timed), their ratio, and the calls.
"""
import datetime
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # analyses/: _common
from _common import smoke  # noqa: E402
from _common.report import write_section  # noqa: E402

import vibimpact as vi  # noqa: E402
from vibimpact._kernel import boundary  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
REPORT = ROOT / "reports" / "performance.md"
ETA = "0.9:1.5:0.002"
#: calls per batch and batches of the no-op call timings
CALLS, BATCHES = 20000, 5
#: repeats of the sweep (best of)
REPEATS = 3


def _per_call(fn, args):
    """Best over :data:`BATCHES` of the mean microseconds of :data:`CALLS` calls."""
    best = float("inf")
    for _ in range(BATCHES):
        t0 = time.perf_counter()
        for _ in range(CALLS):
            fn(*args)
        best = min(best, (time.perf_counter() - t0) / CALLS)
    return best * 1e6


def no_op_calls():
    """``{way: microseconds}`` of an integration call that does no work and of a 4 x 4
    solve, by each way in."""
    system = vi.System(vi.presets.get("fig8").replace(eta=1.0))
    x = system.simulate(periods=1, transient=5).final_state
    held = {}
    way_in = boundary.integrate

    def grab(*a, **k):
        held["call"] = (a, k)
        return way_in(*a, **k)

    boundary.integrate = grab
    try:
        system.strobe(1, x)
    finally:
        boundary.integrate = way_in
    a, k = held["call"]
    loop = boundary._integrate
    inner = {}

    def grab_inner(key, *args):
        inner["args"] = args
        return loop.call_keyed(key, *args)

    boundary._integrate = type("Grab", (), {"call_keyed": staticmethod(grab_inner)})()
    try:
        way_in(*a, **k)
    finally:
        boundary._integrate = loop
    args = inner["args"]  # the clock is at the end: the loop returns at once
    entry = loop.jit.overloads[tuple(loop.jit.typeof_pyval(v) for v in args)].entry_point
    out = {"integration: boundary.integrate": _per_call(lambda: way_in(*a, **k), ()),
           "integration: numba dispatcher": _per_call(loop.jit, args),
           "integration: entry point": _per_call(entry, args)}
    solve = next(r for r, _ in boundary.array_routine_calls() if r.name == "solve")
    m, b = np.eye(4) * 2.0 + 0.1, np.ones(4)
    solve(m, b)
    entry = solve.jit.overloads[(solve.jit.typeof_pyval(m),
                                 solve.jit.typeof_pyval(b))].entry_point
    out.update({"4 x 4 solve: Routine": _per_call(solve, (m, b)),
                "4 x 4 solve: numba dispatcher": _per_call(solve.jit, (m, b)),
                "4 x 4 solve: entry point": _per_call(entry, (m, b))})
    return out


def sweep_time(eta):
    """``(wall, kernel, calls)`` of the in-process sweep over ``eta`` (best wall of
    :data:`REPEATS`; the kernel's time and calls of that repeat)."""
    from vibimpact.sweeps import parse_range

    etas = parse_range(eta)
    p = vi.presets.get("fig8")
    ex = vi.Execution(workers=1, progress=False)
    loop = boundary._integrate
    spent = [0.0, 0]

    class Timed:
        """The loop's Routine, each call timed."""

        @staticmethod
        def call_keyed(key, *args):
            t0 = time.perf_counter()
            out = loop.call_keyed(key, *args)
            spent[0] += time.perf_counter() - t0
            spent[1] += 1
            return out

    vi.sweep(p, etas[:3], execution=ex)  # warm-up
    best = None
    boundary._integrate = Timed()
    try:
        for _ in range(REPEATS):
            spent[:] = [0.0, 0]
            t0 = time.perf_counter()
            vi.sweep(p, etas, execution=ex)
            wall = time.perf_counter() - t0
            if best is None or wall < best[0]:
                best = (wall, spent[0], spent[1])
    finally:
        boundary._integrate = loop
    return best


def report(calls, sweep, seconds):
    wall, kernel, n = sweep
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    lines = ["## What a kernel call costs", "",
             f"Written by `python analyses/performance/call_overhead.py` on {stamp} in "
             f"{seconds:.0f} s ({platform.python_version()}, {platform.machine()}); every "
             "number below is measured by it.", "",
             "A call that does no work, best of "
             f"{BATCHES} batches of {CALLS} calls, microseconds per call:", "",
             "| call | µs |", "| --- | ---: |"]
    lines += [f"| {name} | {us:.2f} |" for name, us in calls.items()]
    lines += ["", f"The main job's sweep in the process (fig8, eta {ETA} up, every "
              f"analysis, one worker), best of {REPEATS}: {wall:.2f} s wall, "
              f"{kernel:.2f} s inside the compiled integration loop ({n} calls), "
              f"**{wall / kernel:.2f}×** the kernel's own time."]
    return "\n".join(lines)


def main(argv=None):
    global REPORT, ETA, CALLS, BATCHES, REPEATS
    args = smoke.parser(__doc__).parse_args(argv)
    REPORT = smoke.moved(REPORT, args.smoke)
    smoke.shrink(globals(), args.smoke, ETA="1.0:1.01:0.01", CALLS=20, BATCHES=1,
                 REPEATS=1)
    t0 = time.perf_counter()
    calls = no_op_calls()
    sweep = sweep_time(ETA)
    text = report(calls, sweep, time.perf_counter() - t0)
    print(text)
    write_section(REPORT, "call_overhead", text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
