"""Speed of the attractor census and of basin images (issue 30): the three targets.

Run as ``python analyses/performance/census_bench.py``; replaces the section ``census``
of ``reports/performance.md``.  Every number written is measured here, in one run:

(a) a census of 1,000 random starts (seed 0, the default box) at fig11, eta = 1.06,
    serial (target: at most 20 s); the attractors found, with their basin fractions;
(b) a 200 x 200 basin image at fig11, eta = 1.06, plane X, Y at rest, on 2 local
    workers (target: at most 120 s); its boundary measures; where its time goes, from a
    profiled serial census of a 20 x 20 grid (the share inside the integrator kernel,
    in numba's dispatch of the kernel calls, and in the rest);
(c) early stopping against fixed-length integration of the same starts: the 1,000
    starts of (a) census'd on their own (the census' time), then each integrated for a
    fixed number of forcing periods -- the most the census spent on any of them -- and
    labelled by the known attractor nearest to its last stroboscopic point (target: the
    census at least 5 times faster, with the same labels).

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
from _common.cpu import machine_cpu as _machine_cpu  # noqa: E402
from _common.cpu import own_cpu as _own_cpu  # noqa: E402
from _common import smoke  # noqa: E402
from _common.profiles import by_source  # noqa: E402
from _common.report import write_section  # noqa: E402

import vibimpact as vi  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
REPORT = ROOT / "reports" / "performance.md"
SECTION = "census"
PRESET, ETA = "fig11", 1.06
STARTS, TARGET_A = 1000, 20.0
GRID, WORKERS, TARGET_B = (200, 200), 2, 120.0
PROFILE_GRID = (20, 20)
FIXED_STARTS, TARGET_C = STARTS, 5.0


def _system():
    return vi.System(vi.presets.get(PRESET).replace(eta=ETA))


def table(ds):
    """``name fraction +- se`` of every attractor of a census (one eta) or basins set."""
    sub = ds.isel(eta=0) if "eta" in ds.dims else ds
    rows = sorted(range(sub.sizes["attractor"]), key=lambda a: -float(sub.fraction[a]))
    return "; ".join(f"{sub.name.values[a]} {float(sub.fraction[a]):.3f} +- "
                     f"{float(sub.fraction_se[a]):.3f}" for a in rows
                     if np.isfinite(float(sub.fraction[a])))


def run_a(system):
    t = time.perf_counter()
    ds = vi.attractors(system, ETA, starts=STARTS, seed=0)
    return time.perf_counter() - t, ds


def run_b(system):
    t = time.perf_counter()
    ds = vi.basins(system, ETA, grid=GRID, plane=("X", "Y"),
                   execution=vi.Execution(workers=WORKERS))
    return time.perf_counter() - t, ds


def profile_b(system):
    """Shares of a serial census' time over a small X, Y grid: the integrator kernel,
    numba's dispatch of the kernel calls (typing the arguments), the rest (Python)."""
    import cProfile
    import pstats

    prof = cProfile.Profile()
    t = time.perf_counter()
    prof.enable()
    try:
        vi.basins(system, ETA, grid=PROFILE_GRID, plane=("X", "Y"))
    finally:
        prof.disable()
    wall = time.perf_counter() - t
    stats = by_source(pstats.Stats(prof).stats)  # the loop's entry point as its source
    total = sum(v[2] for v in stats.values())
    kernel = sum(v[2] for (f, _, fn), v in stats.items()
                 if f.endswith("_kernel/driver.py") and fn == "integrate")
    calls = sum(v[0] for (f, _, fn), v in stats.items()
                if f.endswith("_kernel/driver.py") and fn == "integrate")
    # the way into the compiled code: a routine's call, checked or keyed
    dispatch = sum(v[3] for (f, _, fn), v in stats.items()
                   if f.endswith("_kernel/precompiled.py") and fn in ("__call__", "call_keyed")
                   ) - kernel
    return dict(wall=wall, kernel=kernel / total, dispatch=max(dispatch, 0.0) / total,
                calls=calls, cells=PROFILE_GRID[0] * PROFILE_GRID[1])


def fixed_labels(system, states, census, periods):
    """Each start integrated ``periods`` forcing periods and labelled by the census
    attractor whose cloud is nearest its last stroboscopic point; and that distance."""
    from vibimpact.points.point import point_system
    from vibimpact.census.library import nearest_distances
    from vibimpact.census.reach import CensusSettings
    from vibimpact.core.solver import Solver

    sys_ = point_system(system, CensusSettings().point)
    sub = census.isel(eta=0)
    clouds = [np.asarray(sub.samples.values[a]) for a in range(sub.sizes["attractor"])]
    labels, dists = [], []
    for x0 in states:
        seg = Solver(sys_, x0, check=False).advance(int(periods), events=False)
        last = np.asarray(seg.strobe[-1:])
        d = [float(nearest_distances(last, c[np.all(np.isfinite(c), axis=1)]).min())
             if np.isfinite(c).any() else np.inf for c in clouds]
        labels.append(int(np.argmin(d)))
        dists.append(float(min(d)))
    return np.array(labels), np.array(dists)


def run_c(system, states):
    t = time.perf_counter()
    census = vi.attractors(system, ETA, starts=states)
    t_census = time.perf_counter() - t
    periods = census.periods.values[0]
    longest = int(periods.max())
    t = time.perf_counter()
    labels, dists = fixed_labels(system, states, census, longest)
    t_fixed = time.perf_counter() - t
    agree = float(np.mean(labels == census.label.values[0]))
    return dict(t_census=t_census, t_fixed=t_fixed, longest=longest,
                median=float(np.median(periods)), mean=float(periods.mean()),
                agree=agree, n=len(states), max_dist=float(dists.max()),
                table=table(census))


def met(ok):
    return "**met**" if ok else "**not met**"


def report(a, b, prof, c, load):
    ta, da = a
    tb, db = b
    cells = GRID[0] * GRID[1]
    # the cells integrated: the disk inside the retainer (the corners are not started)
    on = db.started.values if "started" in db else np.ones(db.basin.shape, bool)
    started = int(on.sum())
    names = [str(v) for v in da.name.values[0]]
    p8 = any(n.startswith("P8, 11 impacts") for n in names)
    p14 = any(n.startswith("P14, 21 impacts") for n in names)
    ratio = c["t_fixed"] / c["t_census"]
    sbb = float(db.boundary_basin_entropy)
    lines = [
        "# Attractor census and basin images (issue 30)",
        "",
        "Written by `python analyses/performance/census_bench.py`; every number is measured "
        "by it, in one run.",
        "",
        f"- date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC",
        f"- machine: `{platform.platform()}`, `os.cpu_count()` = {os.cpu_count()}; warm "
        "numba cache",
        f"- {load}",
        f"- problem: {PRESET} (B = {vi.presets.get(PRESET).B:g}, Ec = "
        f"{vi.presets.get(PRESET).Ec:g} as shipped), eta = {ETA:g}, default "
        "`CensusSettings`",
        "",
        "| measurement | target | measured | verdict |",
        "| --- | ---: | ---: | --- |",
        f"| (a) census of {STARTS:,} random starts, serial | <= {TARGET_A:g} s | "
        f"{ta:.1f} s | {met(ta <= TARGET_A)} |",
        f"| (b) {GRID[0]} x {GRID[1]} basin image, plane X, Y at rest, {WORKERS} local "
        f"workers | <= {TARGET_B:g} s | {tb:.1f} s | {met(tb <= TARGET_B)} |",
        f"| (c) early stopping: fixed-length time / census time, {c['n']} starts | >= "
        f"{TARGET_C:g}x | {ratio:.1f}x | {met(ratio >= TARGET_C)} |",
        f"| (c) the same labels | all | {100 * c['agree']:.1f} % | "
        f"{met(c['agree'] == 1.0)} |",
        "",
        f"(a) attractors found: {table(da)}; P8 with 11 impacts "
        f"{'found' if p8 else 'NOT found'}, P14 with 21 impacts "
        f"{'found' if p14 else 'NOT found'}.  Forcing periods integrated per start: median "
        f"{np.median(da.periods.values):.0f}, mean {da.periods.values.mean():.0f}; "
        f"{ta / STARTS * 1e3:.1f} ms per start.",
        "",
        f"(b) {cells:,} cells, {started:,} of them started (inside the retainer), in "
        f"{tb:.1f} s ({tb / started * 1e3:.2f} ms per started cell on "
        f"{WORKERS} workers); attractors: {table(db)}; boundary cells "
        f"{float(db.boundary_fraction):.3f}, basin entropy Sb "
        f"{float(db.basin_entropy):.3f}, boundary basin entropy Sbb {sbb:.3f} (boxes of "
        f"{int(db.attrs['entropy_eps'])} x {int(db.attrs['entropy_eps'])} cells): "
        + ("Sbb > log 2, the boundary is fractal by the log 2 criterion." if
           bool(db.fractal_by_log2) else "Sbb <= log 2, the log 2 criterion does not "
           "decide.") + f"  Periods per started cell: median "
        f"{np.median(db.periods.values[on]):.0f}, mean {db.periods.values[on].mean():.0f}.",
        "",
        f"Where a cell's time goes (a serial {PROFILE_GRID[0]} x {PROFILE_GRID[1]} image "
        f"under cProfile, {prof['wall']:.1f} s): integrator kernel "
        f"{100 * prof['kernel']:.0f} %, numba's dispatch of the {prof['calls']} kernel "
        f"calls (typing their arguments) {100 * prof['dispatch']:.0f} %, the rest "
        f"(the census' Python: the entry test against the known attractors, the "
        f"settling analysis of the first round, the engine) "
        f"{100 * (1 - prof['kernel'] - prof['dispatch']):.0f} %.",
        "",
        f"(c) {c['n']} starts (the first of (a)): census {c['t_census']:.2f} s (periods "
        f"per start: median {c['median']:.0f}, mean {c['mean']:.0f}, at most "
        f"{c['longest']}); fixed length {c['longest']} periods for every start "
        f"{c['t_fixed']:.2f} s, each labelled by the census attractor nearest its last "
        f"stroboscopic point (largest such distance {c['max_dist']:.2g}); labels "
        f"agree on {100 * c['agree']:.1f} % of the starts.  Census: {c['table']}.",
    ]
    return "\n".join(lines)


def main(argv=None):
    global REPORT
    ap = smoke.parser(__doc__)
    args = ap.parse_args(argv)
    REPORT = smoke.moved(REPORT, args.smoke)
    smoke.shrink(globals(), args.smoke, STARTS=24, GRID=(10, 10), PROFILE_GRID=(5, 5),
                 FIXED_STARTS=12)
    system = _system()
    vi.attractors(system, ETA, starts=4)  # warm: imports, numba cache loaded
    load0, busy0, own0, t0 = os.getloadavg()[0], _machine_cpu(), _own_cpu(), \
        time.perf_counter()
    a = run_a(system)
    print(f"(a) {a[0]:.1f} s: {table(a[1])}", flush=True)
    b = run_b(system)
    print(f"(b) {b[0]:.1f} s: {table(b[1])}", flush=True)
    prof = profile_b(system)
    c = run_c(system, a[1].start_state.values[:FIXED_STARTS])
    print(f"(c) census {c['t_census']:.2f} s, fixed {c['t_fixed']:.2f} s, agree "
          f"{c['agree']:.3f}", flush=True)
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
    write_section(REPORT, SECTION, report(a, b, prof, c, load))
    print(f"wrote section {SECTION} of {REPORT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
