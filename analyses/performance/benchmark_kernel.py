"""First kernel benchmark: throughput of the RK methods and work-precision against SciPy.

Run as ``python analyses/performance/benchmark_kernel.py``; writes ``reports/performance.md`` and
``reports/work_precision_fig8.png`` (both replaced atomically).  Every number in the report
is measured by this script on the machine it states; nothing is copied in by hand.

The trajectory: the first fig8 speed of ``CANDIDATE_ETAS`` whose attractor, reached from
``START``, the classifier (:func:`vibimpact.classify_params`) labels periodic with
impacts at the current parameters (B and Ec change with calibrations, and with them which
speeds are periodic); the label, period, impacts and exponent found are written into the
report.

(a) Throughput: accepted RK steps and right-hand-side evaluations per second of wall time
    for ``rk4``, ``dp5`` and ``dop853`` on that trajectory (warm-up call first,
    ``time.perf_counter``, best of 3).
(b) Work-precision on it over 20 periods: max abs stroboscopic
    error against our dop853 at rtol = atol = 1e-13 (itself cross-checked against SciPy
    DOP853 at 1e-13), versus run time, for our dop853 and for SciPy DOP853 restarted at
    every switch (:mod:`vibimpact.testing.reference`), both at rtol = atol = 1e-6 ... 1e-12; then
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
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # analyses/: _common
from _common import smoke  # noqa: E402
from _common.report import best_time, write_section  # noqa: E402
import numba
import numpy as np
import scipy

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import vibimpact as vi  # noqa: E402
from vibimpact.analysis import Label  # noqa: E402
from vibimpact.points import classify_params  # noqa: E402
from vibimpact.testing.reference import solve_reference, strobe_times  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
REPORT = ROOT / "reports" / "performance.md"
FIGURE = ROOT / "reports" / "work_precision_fig8.png"

PRESET = "fig8"
#: speeds tried in this order; the first whose attractor is periodic with impacts is used
CANDIDATE_ETAS = (1.185, 1.13, 1.15, 1.10, 1.16, 1.05, 1.20, 1.25)
START = (1.1, 0.0, 0.0, 1.3)         # reaches the impacting upper branch
START_TRANSIENT = 200
#: the classifier's run on a candidate: transient, then recorded forcing periods
LABEL_TRANSIENT, LABEL_PERIODS = 300, 200
REF_TOL = 1e-13
THROUGHPUT_PERIODS = 1000
WP_PERIODS = 20
TOLS = [10.0 ** (-k / 2) for k in range(12, 25)]   # 1e-6 ... 1e-12, half decades
REPEATS = 3
#: set by main(): the chosen speed, its regime in words, the candidates tried, the params
ETA, REGIME_TEXT, TRIED, P0 = None, "", (), None


def label_orbit(p, s0):
    """The classifier's regime of the attractor reached from ``s0`` (the sweeps' point
    pipeline: a transient of at most ``LABEL_TRANSIENT`` periods, ended early on a
    converged orbit, then ``LABEL_PERIODS`` recorded; the exponent only without a
    period)."""
    regime, _ = classify_params(vi.System(p), state0=s0, transient_max=LABEL_TRANSIENT,
                                record=LABEL_PERIODS)
    return regime


def is_impacting_periodic(regime):
    return (regime.label is Label.PERIODIC and regime.n > 0 and bool(regime.impacting)
            and regime.impacts_per_period >= 1)


def is_impacting_chaotic(regime):
    return regime.label is Label.CHAOTIC and bool(regime.impacting)


def describe(regime):
    """The regime in words, with the evidence (period, or exponent and its error)."""
    text = str(regime)
    if np.isfinite(regime.lyapunov):
        text += (f" (largest exponent {regime.lyapunov:+.3f} +- {regime.lyapunov_err:.3f} "
                 "per unit tau)")
    return text


def pick_orbit(preset, etas, want, state_at):
    """First ``eta`` of ``etas`` (in order) whose regime from ``state_at(p)`` satisfies
    ``want``: ``(eta, state0, regime, tried)`` with ``tried`` the (eta, regime) of the
    candidates looked at; exits naming every candidate's label when none qualifies."""
    tried = []
    for eta in etas:
        p = vi.presets.get(preset).replace(eta=eta)
        s0 = np.asarray(state_at(p))
        regime = label_orbit(p, s0)
        tried.append((eta, regime))
        if want(regime):
            return eta, s0, regime, tried
    sys.exit(f"{preset}: no candidate eta has the wanted regime at the current parameters: "
             + "; ".join(f"{e}: {describe(r)}" for e, r in tried))


def throughput(p, s0):
    """Rows (method, settings, steps, rejected, rhs, time, steps/s, rhs/s)."""
    rows = []
    settings = {"rk4": dict(steps_per_period=400), "dp5": dict(rtol=1e-9, atol=1e-12),
                "dop853": dict(rtol=1e-9, atol=1e-12)}
    for method, kw in settings.items():
        def call(method=method, kw=kw):
            return vi.simulate(p, periods=THROUGHPUT_PERIODS, state0=s0,
                               solver=vi.SolverSettings(method=method, **kw))
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
        return vi.simulate(p, periods=WP_PERIODS, state0=s0,
                           solver=vi.SolverSettings(method=method, rtol=tol, atol=tol))

    ref_run = ours(REF_TOL)
    assert ref_run.ok and len(ref_run.impacts) > 0
    truth = ref_run.strobe
    sp13 = solve_reference(p, tt[-1], s0, rtol=REF_TOL, atol=REF_TOL, t_eval=tt)
    cross = float(np.max(np.abs(sp13.y - truth)))
    series = {"ours dop853": [], "ours dp5": [], "SciPy DOP853 (restarted)": []}
    for tol in TOLS:
        for name, fn in (("ours dop853", lambda tol=tol: ours(tol)),
                         ("ours dp5", lambda tol=tol: ours(tol, "dp5"))):
            fn()
            t, run = best_time(fn)
            assert run.ok, run.reason
            series[name].append((tol, float(np.max(np.abs(run.strobe - truth))), t,
                                 run.counters["rhs_evals"]))
        t, ref = best_time(lambda tol=tol: solve_reference(p, tt[-1], s0, rtol=tol,
                                                           atol=tol, t_eval=tt))
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
    ax.set_xlabel(f"max abs strobe error over {WP_PERIODS} periods")
    ax.set_ylabel(f"run time [s] (best of {REPEATS})")
    ax.set_title(f"Work-precision, {PRESET} eta = {ETA}, {REGIME_TEXT} (labels: rtol = atol)",
                 fontsize=9)
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
         "Written by `python analyses/performance/benchmark_kernel.py`; every number below is measured "
         "by that script (nothing typed in by hand).", "",
         f"- date: {now}",
         f"- machine: `{platform.platform()}`, processor `{platform.processor() or '?'}`, "
         f"`os.cpu_count()` = {os.cpu_count()} (all timings single-threaded)",
         f"- versions: Python {platform.python_version()}, numpy {np.__version__}, "
         f"scipy {scipy.__version__}, numba {numba.__version__}, vibimpact {vi.__version__}",
         f"- trajectory: preset `{PRESET}` (B = {P0.B:g}, Ec = {P0.Ec:g}), eta = {ETA}, "
         f"state0 = [{', '.join(f'{v:.12g}' for v in s0)}] (reached from {list(START)} after "
         f"{START_TRANSIENT} periods); {n_imp} impacts in {WP_PERIODS} periods",
         f"- regime, decided in this run by `classify_params` (at most {LABEL_TRANSIENT} "
         f"transient periods from state0, {LABEL_PERIODS} recorded): **{REGIME_TEXT}**; "
         "eta was the "
         "first of the candidates " + ", ".join(f"{e:g}" for e in CANDIDATE_ETAS)
         + " labelled periodic with impacts (" + "; ".join(
             f"{e:g}: {describe(r)}" for e, r in TRIED) + ")", "",
         "## (a) Throughput", "",
         f"{THROUGHPUT_PERIODS} forcing periods per run (SciPy: as stated), warm-up call "
         f"first, best of {REPEATS} wall times (`time.perf_counter`). Steps are accepted steps.", "",
         "| method | settings | steps | rejected | RHS evals | time [s] | steps/s | RHS/s |",
         "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for m, desc, st, rej, nf, t, sps, fps in rows:
        L.append(f"| {m} | {desc} | {st} | {rej if rej >= 0 else 'n/a'} | {nf} | {t:.4f} | "
                 f"{sps:.3g} | {fps:.3g} |")
    L += ["", f"## (b) Work-precision, {WP_PERIODS} periods", "",
          f"Error: max abs difference of the {WP_PERIODS + 1} stroboscopic states from the "
          f"reference, our dop853 at rtol = atol = {REF_TOL:g}. Cross-check of that "
          f"reference: SciPy DOP853 at rtol = atol = {REF_TOL:g} (restarted at switches) "
          f"differs from it by **{cross:.2e}**.",
          "Both integrators at rtol = atol = tol; SciPy is restarted at every switch and "
          "stops at every strobe time (`vibimpact.testing.reference.solve_reference`, compiled RHS). "
          f"Time: best of {REPEATS}.", "",
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


def _from_start(p):
    return vi.simulate(p, periods=1, transient=START_TRANSIENT, state0=list(START)).final_state


def main(argv=None):
    global ETA, REGIME_TEXT, TRIED, P0, REPORT, FIGURE
    out = smoke.parser(__doc__).parse_args(argv).smoke
    REPORT, FIGURE = smoke.moved(REPORT, out), smoke.moved(FIGURE, out)
    smoke.shrink(globals(), out, THROUGHPUT_PERIODS=20, WP_PERIODS=3, REPEATS=1,
                 TOLS=[1e-6, 1e-7, 1e-8])
    REPORT.parent.mkdir(parents=True, exist_ok=True)
    ETA, s0, regime, TRIED = pick_orbit(PRESET, CANDIDATE_ETAS, is_impacting_periodic,
                                        _from_start)
    REGIME_TEXT = describe(regime)
    p = P0 = vi.presets.get(PRESET).replace(eta=ETA)
    print(f"trajectory: {PRESET} eta = {ETA}: {REGIME_TEXT}")
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
    print(f"wrote {REPORT} and {FIGURE}")


if __name__ == "__main__":
    main()
