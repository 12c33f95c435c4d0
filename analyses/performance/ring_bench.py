"""Speed of the ring model (issue 31): its sweep against eq. (5)'s, and its cost per period.

Run as ``python analyses/performance/ring_bench.py``; replaces the section ``ring`` of
``reports/performance.md``.  Every number written is measured here, in one run:

(a) the target: ``vibimpact classify --preset fig11-ring --eta 0.9:1.5:0.002`` (direction
    up, every analysis, 16 blocks, 2 workers: the command line's defaults) against the
    same request on ``fig11`` (eq. (5)), each timed after a warm-up in this process, the
    two interleaved and repeated (best of 2) so that load from other processes hits both;
    target: the ring's time at most 1.5 times eq. (5)'s.  The two sweeps follow different
    motions (the turning ring changes the friction), so the regimes and the forcing
    periods each integrated are written next to the times;
(b) the same motion: the ring held by its inertia (``Jr = 1e14``, ``cr = Mr = 0``: the
    trajectory of eq. (5)) against eq. (5) at fig11, eta = 1.15, from the same state:
    plain integration of 2,000 forcing periods, and 100 one-period monodromy matrices
    (the variational equations, which use each model's Jacobian), best of 3: what one
    forcing period costs each model for the same work;
(c) where the time goes: both sweeps of (a) once more, serial, under cProfile: the
    integrator kernel's own time and, of the total, the Lyapunov exponents (variational
    equations) and the Floquet multipliers (Newton shooting), with the calls of each.

With ``--smoke DIR`` the problems are tiny and the report goes under DIR.
"""
from __future__ import annotations

import datetime
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # analyses/: _common
sys.path.insert(0, str(Path(__file__).resolve().parent))  # profile_sweep
from _common.cpu import machine_cpu as _machine_cpu  # noqa: E402
from _common.cpu import own_cpu as _own_cpu  # noqa: E402
from _common import smoke  # noqa: E402
from _common.report import write_section  # noqa: E402

import vibimpact as vi  # noqa: E402
from vibimpact.points.point import REGIME_CODES  # noqa: E402
from vibimpact.sweeps import parse_range  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
REPORT = ROOT / "reports" / "performance.md"
SECTION = "ring"
#: (eq. (5)'s preset, the ring's preset)
PRESETS = ("fig11", "fig11-ring")
GRID = "0.9:1.5:0.002"
WORKERS, BLOCKS, REPEATS = 2, 16, 2
TARGET = 1.5
#: (b): the held ring, the speed, the periods integrated, the monodromies, the repeats
HELD = dict(Jr=1e14, cr=0.0, Mr=0.0)
ETA_B, PERIODS_B, MONODROMIES_B, REPEATS_B = 1.15, 2000, 100, 3


def sweep(name, etas):
    """One sweep as ``vibimpact classify --preset name`` runs it: (wall seconds, dataset)."""
    t = time.perf_counter()
    ds = vi.sweep(vi.presets.get(name), etas, direction="up",
                  continuation=vi.Continuation(blocks=BLOCKS),
                  execution=vi.Execution(workers=WORKERS))
    return time.perf_counter() - t, ds


def run_a(etas):
    """The two sweeps, interleaved, ``REPEATS`` times each: ``{preset: (times, dataset)}``."""
    out = {name: ([], None) for name in PRESETS}
    for _ in range(REPEATS):
        for name in PRESETS:
            t, ds = sweep(name, etas)
            out[name] = (out[name][0] + [t], ds)
            print(f"(a) {name}: {t:.2f} s", flush=True)
    return out


def _best(fn, repeats):
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def run_b():
    """Per forcing period, on one motion: eq. (5) and the held ring from the same state."""
    rotor = vi.System(vi.presets.get(PRESETS[0]).replace(eta=ETA_B))
    held = vi.System(vi.presets.get(PRESETS[1]).replace(eta=ETA_B, **HELD))
    x4 = rotor.simulate(periods=1, transient=200).strobe[-1]
    x5 = np.append(x4, 0.0)
    out = {}
    for key, system, x in (("rotor", rotor, x4), ("held", held, x5)):
        system.strobe(5, x)  # warm
        vi.analysis.monodromy(system, x, 1)
        _, _, pts = system.strobe(PERIODS_B, x)
        t_plain = _best(lambda system=system, x=x: system.strobe(PERIODS_B, x), REPEATS_B)
        t_mono = _best(lambda system=system, x=x: [vi.analysis.monodromy(system, x, 1)
                                for _ in range(MONODROMIES_B)], REPEATS_B)
        out[key] = dict(plain=t_plain, mono=t_mono, strobe=np.asarray(pts)[:, :4])
        print(f"(b) {key}: {t_plain:.3f} s plain, {t_mono:.3f} s monodromies", flush=True)
    n = min(len(out["rotor"]["strobe"]), len(out["held"]["strobe"]))
    out["gap"] = float(np.max(np.abs(out["rotor"]["strobe"][:n] - out["held"]["strobe"][:n])))
    pts = out["rotor"]["strobe"]
    out["repeat"] = float(np.max(np.abs(pts[-1] - pts[-2])))
    return out


#: (c): (part, file suffix, function, column) as in profile_sweep.BUCKETS
PARTS = (("integrator kernel, own time", "_kernel/driver.py", "integrate", "tottime"),
         ("Lyapunov exponents (variational equations), cumulative",
          "analysis/lyapunov.py", "lyapunov_spectrum", "cumtime"),
         ("Floquet multipliers (Newton shooting), cumulative", "analysis/shooting.py",
          "shoot_periodic_orbit", "cumtime"))


def run_c(etas):
    """Each preset's sweep, serial, under cProfile: ``{preset: (wall, {part: (s, calls)})}``."""
    import cProfile
    import pstats

    from profile_sweep import bucket_times

    out, seen = {}, {}
    for name in PRESETS:
        prof = cProfile.Profile()
        t = time.perf_counter()
        prof.enable()
        try:
            vi.sweep(vi.presets.get(name), etas, direction="up",
                     continuation=vi.Continuation(blocks=BLOCKS),
                     execution=vi.Execution(workers=1, progress=False))
        finally:
            prof.disable()
        wall = time.perf_counter() - t
        stats = pstats.Stats(prof).stats
        seen.update(stats)
        col = {"tottime": 2, "cumtime": 3}
        out[name] = (wall, {part: (
            sum(v[col[c]] for (f, _, fn), v in stats.items()
                if f.endswith(suffix) and fn == func),
            sum(v[1] for (f, _, fn), v in stats.items() if f.endswith(suffix) and fn == func))
            for part, suffix, func, c in PARTS})
        print(f"(c) {name}: {wall:.2f} s serial under cProfile", flush=True)
    bucket_times(seen, PARTS)  # raises when a part matched no function of either sweep
    return out


def counts(ds):
    reg = ds["regime"].values
    return ", ".join(f"{lab.value} {int((reg == code).sum())}"
                     for lab, code in REGIME_CODES.items() if (reg == code).any())


def periods(ds):
    return int((ds["transient"].values + ds["recorded"].values).sum())


def met(ok):
    return "**met**" if ok else "**not met**"


def profile_lines(c):
    (w5, p5), (wr, pr) = (c[name] for name in PRESETS)
    lines = [f"(c) Where the time goes: the sweeps of (a) once more, serial (1 worker), "
             "under cProfile (its overhead included):", "",
             f"| part | {PRESETS[0]} [s] | calls | {PRESETS[1]} [s] | calls | ratio |",
             "| --- | ---: | ---: | ---: | ---: | ---: |",
             f"| whole sweep | {w5:.2f} | - | {wr:.2f} | - | {wr / w5:.2f} |"]
    for part, _, _, _ in PARTS:
        (s5, n5), (sr, nr) = p5[part], pr[part]
        lines.append(f"| {part} | {s5:.2f} | {n5} | {sr:.2f} | {nr} | "
                     f"{sr / s5 if s5 else float('nan'):.2f} |")
    return lines


def report(a, b, c, load, n_points):
    (t5, d5), (tr, dr) = (a[name] for name in PRESETS)
    best5, bestr = min(t5), min(tr)
    ratio = bestr / best5
    p5, pr = periods(d5), periods(dr)
    times = lambda ts: ", ".join(f"{t:.2f}" for t in ts)  # noqa: E731
    ro, he = b["rotor"], b["held"]
    lines = [
        "# The ring model's speed (issue 31)",
        "",
        "Written by `python analyses/performance/ring_bench.py`; every number is measured "
        "by it, in one run.",
        "",
        f"- date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC",
        f"- machine: `{platform.platform()}`, `os.cpu_count()` = {os.cpu_count()}; warm "
        "numba cache",
        f"- {load}",
        f"- request (a): `vibimpact classify --preset PRESET --eta {GRID}` ({n_points} "
        f"points, direction up, every analysis, {BLOCKS} blocks, {WORKERS} workers: the "
        f"command line's defaults), the two presets interleaved, best of {REPEATS}",
        "",
        "| preset | model | wall times [s] | best [s] | regimes | forcing periods "
        "integrated (transient + record) |",
        "| --- | --- | --- | ---: | --- | ---: |",
        f"| {PRESETS[0]} | {d5.attrs['model']} | {times(t5)} | {best5:.2f} | {counts(d5)} "
        f"| {p5:,} |",
        f"| {PRESETS[1]} | {dr.attrs['model']} | {times(tr)} | {bestr:.2f} | {counts(dr)} "
        f"| {pr:,} |",
        "",
        f"Ratio ring / eq. (5): {ratio:.2f} (target <= {TARGET:g}): {met(ratio <= TARGET)}.",
        "",
        "The two sweeps are different motions (the ring turns with the rotor's friction and "
        "changes it), so the ratio mixes the cost of the ring's equations with the cost of "
        "the motions it leads to; (b) separates the first.",
        "",
        f"(b) One motion: eq. (5) and the ring held by its inertia (Jr = {HELD['Jr']:g}, "
        f"cr = Mr = 0; the same trajectory: largest difference of X, Y, X', Y' over "
        f"{PERIODS_B:,} stroboscopic points {b['gap']:.1e}) at {PRESETS[0]}, eta = "
        f"{ETA_B:g} (its last two stroboscopic points differ by {b['repeat']:.0e}), from "
        f"the same state, best of {REPEATS_B}:",
        "",
        "| work | eq. (5) [ms] | held ring [ms] | ratio |",
        "| --- | ---: | ---: | ---: |",
        f"| {PERIODS_B:,} forcing periods, plain integration | {1e3 * ro['plain']:.1f} | "
        f"{1e3 * he['plain']:.1f} | {he['plain'] / ro['plain']:.2f} |",
        f"| {MONODROMIES_B} one-period monodromy matrices (variational equations) | "
        f"{1e3 * ro['mono']:.1f} | {1e3 * he['mono']:.1f} | {he['mono'] / ro['mono']:.2f} |",
        "",
    ] + profile_lines(c)
    return "\n".join(lines)


def main(argv=None):
    global REPORT
    args = smoke.parser(__doc__).parse_args(argv)
    REPORT = smoke.moved(REPORT, args.smoke)
    smoke.shrink(globals(), args.smoke, GRID="0.9:1.0:0.05", REPEATS=1, PERIODS_B=20,
                 MONODROMIES_B=2, REPEATS_B=1)
    etas = parse_range(GRID)
    for name in PRESETS:  # warm: imports, numba cache loaded in this process
        vi.sweep(vi.presets.get(name), etas[:2])
    load0, busy0, own0, t0 = os.getloadavg()[0], _machine_cpu(), _own_cpu(), \
        time.perf_counter()
    a = run_a(etas)
    b = run_b()
    c = run_c(etas)
    wall = time.perf_counter() - t0
    busy1 = _machine_cpu()
    if busy0 is None or busy1 is None:
        load = f"load average {load0:.2f} before the run (other processes' CPU not measurable)"
    else:
        other = max(0.0, (busy1 - busy0) - (_own_cpu() - own0)) / wall
        load = (f"other processes used on average {other:.2f} of {os.cpu_count()} cores "
                f"during the run ({wall:.0f} s; machine CPU time minus this benchmark's "
                f"own): " + ("**the machine was shared**, wall-clock figures are "
                             "conservative" if other >= 0.1 else
                             "the machine was not measurably shared"))
    write_section(REPORT, SECTION, report(a, b, c, load, etas.size))
    print(f"wrote section {SECTION} of {REPORT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
