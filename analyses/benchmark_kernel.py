"""First kernel benchmark: throughput of the RK methods and work-precision against SciPy.

Run as ``python analyses/benchmark_kernel.py``; writes ``reports/performance.md`` and
``reports/work_precision_fig8.png`` (both replaced atomically).  Every number in the report
is measured by this script on the machine it states; nothing is copied in by hand.

(a) Throughput: accepted RK steps and right-hand-side evaluations per second of wall time
    for ``rk4``, ``dp5`` and ``dop853`` on an impacting fig8 trajectory (warm-up call first,
    ``time.perf_counter``, best of 3).
(b) Work-precision on one impacting fig8 trajectory over 20 periods: max abs stroboscopic
    error against our dop853 at rtol = atol = 1e-13 (itself cross-checked against SciPy
    DOP853 at 1e-13), versus run time, for our dop853 and for SciPy DOP853 restarted at
    every switch (:mod:`vibimpact.reference`), both at rtol = atol = 1e-6 ... 1e-12; then
    the speed ratio at equal error (log time interpolated linearly in log error along the
    Pareto front of each method's runs).
"""
import datetime
import os
import platform
import sys
import time
from pathlib import Path

import matplotlib
from _report import best_time, write_section
import numba
import numpy as np
import scipy

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import vibimpact as vi  # noqa: E402
from vibimpact.reference import solve_reference, strobe_times  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
REPORT = ROOT / "reports" / "performance.md"
FIGURE = ROOT / "reports" / "work_precision_fig8.png"

PRESET, ETA = "fig8", 1.185          # two impacts per forcing period (paper's A and B)
START = (1.1, 0.0, 0.0, 1.3)         # reaches the impacting upper branch
THROUGHPUT_PERIODS = 1000
WP_PERIODS = 20
TOLS = [10.0 ** (-k / 2) for k in range(12, 25)]   # 1e-6 ... 1e-12, half decades
REPEATS = 3


def throughput(p, s0):
    """Rows (method, settings, steps, rejected, rhs, time, steps/s, rhs/s)."""
    rows = []
    settings = {"rk4": dict(steps_per_period=400), "dp5": dict(rtol=1e-9, atol=1e-12),
                "dop853": dict(rtol=1e-9, atol=1e-12)}
    for method, kw in settings.items():
        def call():
            return vi.simulate(p, periods=THROUGHPUT_PERIODS, state0=s0, method=method, **kw)
        call()  # warm-up (JIT load)
        t, run = best_time(call, REPEATS)
        assert run.ok and len(run.impacts) > 0, (method, run.reason)
        c = run.counters
        desc = ", ".join(f"{k}={v:g}" for k, v in kw.items())
        rows.append((method, desc, c["steps"], c["rejected"], c["rhs_evals"], t,
                     c["steps"] / t, c["rhs_evals"] / t))
    # the SciPy baseline on the same trajectory, for context (fewer periods: it is slow)
    n = 50
    tt = strobe_times(p.eta, n)
    solve_reference(p, tt[1], s0, rtol=1e-9, atol=1e-12, t_eval=tt[:2])  # warm-up
    t, ref = best_time(lambda: solve_reference(p, tt[-1], s0, rtol=1e-9, atol=1e-12,
                                               t_eval=tt))
    rows.append(("SciPy DOP853 (restarted)", f"rtol=1e-09, atol=1e-12, {n} periods",
                 ref.nsteps, -1, ref.nfev, t, ref.nsteps / t, ref.nfev / t))
    return rows


def work_precision(p, s0):
    """Reference strobe, its SciPy cross-check, and (tol, error, time, rhs) per method."""
    tt = strobe_times(p.eta, WP_PERIODS)

    def ours(tol, method="dop853"):
        return vi.simulate(p, periods=WP_PERIODS, state0=s0, method=method, rtol=tol,
                           atol=tol)

    ref_run = ours(1e-13)
    assert ref_run.ok and len(ref_run.impacts) > 0
    truth = ref_run.strobe
    sp13 = solve_reference(p, tt[-1], s0, rtol=1e-13, atol=1e-13, t_eval=tt)
    cross = float(np.max(np.abs(sp13.y - truth)))
    series = {"ours dop853": [], "ours dp5": [], "SciPy DOP853 (restarted)": []}
    for tol in TOLS:
        for name, fn in (("ours dop853", lambda: ours(tol)),
                         ("ours dp5", lambda: ours(tol, "dp5"))):
            fn()
            t, run = best_time(fn)
            assert run.ok, run.reason
            series[name].append((tol, float(np.max(np.abs(run.strobe - truth))), t,
                                 run.counters["rhs_evals"]))
        t, ref = best_time(lambda: solve_reference(p, tt[-1], s0, rtol=tol, atol=tol,
                                                   t_eval=tt))
        series["SciPy DOP853 (restarted)"].append(
            (tol, float(np.max(np.abs(ref.y - truth))), t, ref.nfev))
    return cross, series


def pareto(points):
    """(error, time) of the runs no other run beats in both, by increasing error."""
    front = []
    for _, e, t, _ in sorted(points, key=lambda q: (q[1], q[2])):
        if not front or t < front[-1][1]:
            front.append((e, t))
    return front


def time_at_error(points, err):
    """Least time to reach ``err``: log time interpolated linearly in log error along the
    Pareto front of the measured runs (error vs tolerance is not monotone near the
    ``(R - 1)^{3/2}`` contact law, see the report); NaN outside the measured range."""
    front = pareto(points)
    e = np.log10([q[0] for q in front])
    t = np.log10([q[1] for q in front])
    x = np.log10(err)
    if x < e[0] or x > e[-1]:
        return np.nan
    return 10.0 ** np.interp(x, e, t)


def ratios(series):
    """SciPy time / our dop853 time at equal error, at the error levels 10^(k/2)."""
    a, b = series["ours dop853"], series["SciPy DOP853 (restarted)"]
    lo = max(min(q[1] for q in a), min(q[1] for q in b))
    hi = min(max(q[1] for q in a), max(q[1] for q in b))
    out = []
    for k in range(int(np.floor(2 * np.log10(hi))), int(np.ceil(2 * np.log10(lo))) - 1, -1):
        err = 10.0 ** (k / 2)
        ta, tb = time_at_error(a, err), time_at_error(b, err)
        if np.isfinite(ta) and np.isfinite(tb):
            out.append((err, ta, tb, tb / ta))
    return out


def plot(series, path):
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    for (name, pts), marker in zip(series.items(), "os^"):
        ax.loglog([q[1] for q in pts], [q[2] for q in pts], marker=marker, label=name)
        for q in pts:
            ax.annotate(f"{q[0]:.0e}", (q[1], q[2]), fontsize=6, xytext=(3, 3),
                        textcoords="offset points")
    ax.set_xlabel("max abs strobe error over 20 periods")
    ax.set_ylabel("run time [s] (best of 3)")
    ax.set_title(f"Work-precision, {PRESET} eta = {ETA}, impacting (labels: rtol = atol)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    tmp = path.with_name(path.stem + ".tmp.png")
    fig.savefig(tmp, dpi=120)
    plt.close(fig)
    os.replace(tmp, path)


def report(s0, n_imp, rows, cross, series, rat):
    now = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    L = ["# Kernel performance", "",
         "Written by `python analyses/benchmark_kernel.py`; every number below is measured "
         "by that script (nothing typed in by hand).", "",
         f"- date: {now}",
         f"- machine: `{platform.platform()}`, processor `{platform.processor() or '?'}`, "
         f"`os.cpu_count()` = {os.cpu_count()} (all timings single-threaded)",
         f"- versions: Python {platform.python_version()}, numpy {np.__version__}, "
         f"scipy {scipy.__version__}, numba {numba.__version__}, vibimpact {vi.__version__}",
         f"- trajectory: preset `{PRESET}`, eta = {ETA}, state0 = "
         f"[{', '.join(f'{v:.12g}' for v in s0)}] (on the impacting attractor: reached from "
         f"{list(START)} after 200 periods); {n_imp} impacts in {WP_PERIODS} periods", "",
         "## (a) Throughput", "",
         f"{THROUGHPUT_PERIODS} forcing periods per run (SciPy: as stated), warm-up call "
         "first, best of 3 wall times (`time.perf_counter`). Steps are accepted steps.", "",
         "| method | settings | steps | rejected | RHS evals | time [s] | steps/s | RHS/s |",
         "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for m, desc, st, rej, nf, t, sps, fps in rows:
        L.append(f"| {m} | {desc} | {st} | {rej if rej >= 0 else 'n/a'} | {nf} | {t:.4f} | "
                 f"{sps:.3g} | {fps:.3g} |")
    L += ["", "## (b) Work-precision, 20 periods", "",
          "Error: max abs difference of the 21 stroboscopic states from the reference, our "
          "dop853 at rtol = atol = 1e-13. Cross-check of that reference: SciPy DOP853 at "
          f"rtol = atol = 1e-13 (restarted at switches) differs from it by **{cross:.2e}**.",
          "Both integrators at rtol = atol = tol; SciPy is restarted at every switch and "
          "stops at every strobe time (`vibimpact.reference.solve_reference`, compiled RHS). "
          "Time: best of 3.", "",
          "| tol | " + " | ".join(f"{n} error | {n} time [s] | {n} RHS" for n in series)
          + " | time ratio SciPy/dop853 at equal tol |",
          "| ---: |" + " ---: | ---: | ---: |" * len(series) + " ---: |"]
    for i, tol in enumerate(TOLS):
        cells = []
        for pts in series.values():
            _, e, t, nf = pts[i]
            cells += [f"{e:.2e}", f"{t:.4f}", f"{nf}"]
        ta = series["ours dop853"][i][2]
        tb = series["SciPy DOP853 (restarted)"][i][2]
        L.append(f"| {tol:.1e} | " + " | ".join(cells) + f" | {tb / ta:.0f} |")
    worst = {n: max(q[1] / q[0] for q in pts) for n, pts in series.items()}
    over = {n: sum(q[1] > 30 * q[0] for q in pts) for n, pts in series.items()}
    L += ["", "Error is not monotone in the tolerance for either integrator: largest "
          "error/tol ratio " + ", ".join(f"{n} {worst[n]:.0f}" for n in series)
          + "; runs with error > 30 tol: " + ", ".join(f"{n} {over[n]}/{len(TOLS)}"
                                                      for n in series) + ".",
          "", "Speed ratio at equal error (SciPy time / our dop853 time; for each method "
          "the least time reaching the error, log time interpolated linearly in log error "
          "along the Pareto front of its measured runs):", "",
          "| error | ours dop853 [s] | SciPy DOP853 [s] | ratio |",
          "| ---: | ---: | ---: | ---: |"]
    for err, ta, tb, r in rat:
        L.append(f"| {err:.1e} | {ta:.4f} | {tb:.4f} | {r:.0f} |")
    if rat:
        gm = float(np.exp(np.mean(np.log([r[3] for r in rat]))))
        L += ["", f"Geometric mean of the ratio over these error levels: **{gm:.0f}x**."]
    L += ["", f"![work-precision]({FIGURE.name})", ""]
    write_section(REPORT, "kernel", "\n".join(L))


def main():
    REPORT.parent.mkdir(parents=True, exist_ok=True)
    p = vi.presets.get(PRESET).replace(eta=ETA)
    s0 = vi.simulate(p, periods=1, transient=200, state0=list(START)).final_state
    n_imp = len(vi.simulate(p, periods=WP_PERIODS, state0=s0).impacts)
    if n_imp == 0:
        sys.exit("benchmark trajectory does not impact")
    rows = throughput(p, s0)
    cross, series = work_precision(p, s0)
    rat = ratios(series)
    plot(series, FIGURE)
    report(s0, n_imp, rows, cross, series, rat)
    for r in rows:
        print(f"{r[0]:>26s}: {r[6]:.3g} steps/s, {r[7]:.3g} RHS/s")
    print(f"reference cross-check (ours 1e-13 vs SciPy 1e-13): {cross:.2e}")
    for err, ta, tb, r in rat:
        print(f"error {err:.1e}: ours {ta:.4f} s, SciPy {tb:.4f} s, ratio {r:.0f}")
    print(f"wrote {REPORT.relative_to(ROOT)} and {FIGURE.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
