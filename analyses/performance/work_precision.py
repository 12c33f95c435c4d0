"""Work-precision against SciPy, integrator overhead against the RHS floor, and start-up.

Run as ``python analyses/performance/work_precision.py``; writes the section ``work_precision`` of
``reports/performance.md`` and ``reports/work_precision.png`` (both replaced atomically).
Every number in the section is measured by this script in the same run (issue 6, parts
1, 2 and 5).

(1) Work-precision on four trajectories (a fig8 periodic and a fig8 chaotic one, fig10 and
    fig11 at eta = 1.02, all on the branch continued up from eta = 1.0 in steps of 0.02
    with 200 transient periods each, as ``tests/conftest.py::continued_state``).  Every
    trajectory's regime is decided in the run by the classifier
    (:func:`vibimpact.classify_params`, see ``benchmark_kernel.label_orbit``) and
    written into the report; the fig8 speeds are the first of ``CASES``' candidate lists
    that the classifier labels periodic with impacts, and chaotic, at the current B and Ec
    (which change with calibrations):
    max abs stroboscopic error against our dop853 at rtol = atol = 1e-13 (cross-checked
    with SciPy DOP853 at 1e-13) versus wall time, for our rk4 / dp5 / dop853 and for SciPy
    ``solve_ivp`` RK45 / DOP853 / LSODA restarted at every switch with the compiled
    right-hand side (:func:`vibimpact.testing.reference.solve_reference`), and numbalsoda LSODA
    called from numba when it is installed (given the switch times: ``_lsoda_baseline``).
    Ratio table: SciPy
    DOP853 time / our dop853 time at equal error (log time interpolated linearly in log
    error along each method's Pareto front).
(2) Overhead: wall time per RHS evaluation inside our integrators (``counters
    ['rhs_evals']``) against a bare compiled loop calling ``vibimpact._kernel.rotor.rhs``
    as many times on states sampled along the same trajectory (with their modes); and the
    RHS evaluations per forcing period each method needs at a fixed error.
The first (cold) run of the command line is measured by ``analyses/performance/first_run.py``.
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
from numba import njit

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import _lsoda_baseline as lsoda_baseline  # noqa: E402
import vibimpact as vi  # noqa: E402
from vibimpact._kernel import rotor  # noqa: E402
from vibimpact.testing.reference import solve_reference, strobe_times  # noqa: E402
from vibimpact.sweeps import continued_state as _continued  # noqa: E402
from benchmark_kernel import (LABEL_PERIODS, LABEL_TRANSIENT, describe,  # noqa: E402
                              is_impacting_chaotic, is_impacting_periodic, label_orbit,
                              pick_orbit)

ROOT = Path(__file__).resolve().parents[2]
REPORT = ROOT / "reports" / "performance.md"
FIGURE = ROOT / "reports" / "work_precision.png"
SECTION = "work_precision"

# (label, preset, candidate etas, wanted regime or None, periods): the first candidate
# whose regime the classifier finds wanted is used (None: the one eta, whatever it is);
# periods short enough that chaos does not swamp the error
CASES = [("fig8 periodic", "fig8", (1.185, 1.13, 1.15, 1.10, 1.16, 1.05),
          is_impacting_periodic, 20),
         ("fig8 chaotic", "fig8", (1.22, 1.19, 1.21, 1.24, 1.185, 1.18), is_impacting_chaotic,
          10),
         ("fig10", "fig10", (1.02,), None, 20),
         ("fig11", "fig11", (1.02,), None, 20)]
SAMPLE_PERIODS, SAMPLES_PER_PERIOD = 50, 64   # states of the bare-RHS floor (2)
REF_TOL = 1e-13
RK4_STEPS = [50, 100, 200, 400, 800, 1600, 3200]
OUR_TOLS = [10.0 ** -k for k in range(4, 13)]          # 1e-4 ... 1e-12
SCIPY_TOLS = {"RK45": [10.0 ** -k for k in range(5, 12)],     # 1e-5 ... 1e-11 (slow)
              "DOP853": [10.0 ** -k for k in range(5, 13)],   # 1e-5 ... 1e-12
              "LSODA": [10.0 ** -k for k in range(5, 13)]}
OUR_REPEATS, SCIPY_REPEATS = 5, 2
ERR_FIXED = 1e-8            # error level of the "RHS evaluations per period" table
OVERHEAD_PERIODS = 300
OVERHEAD_SETTINGS = {"rk4": dict(steps_per_period=400),
                     "dp5": dict(rtol=1e-9, atol=1e-9),
                     "dop853": dict(rtol=1e-9, atol=1e-9)}
LSODA_NB = "numbalsoda LSODA"
METHODS = ["ours rk4", "ours dp5", "ours dop853", "SciPy RK45", "SciPy DOP853",
           "SciPy LSODA", LSODA_NB]
LSODA_NB_TOLS = [10.0 ** -k for k in range(5, 13)]     # 1e-5 ... 1e-12
STYLE = {"ours rk4": ("o", "-", "C0"), "ours dp5": ("s", "-", "C1"),
         "ours dop853": ("D", "-", "C2"), "SciPy RK45": ("v", "--", "C3"),
         "SciPy DOP853": ("^", "--", "C4"), "SciPy LSODA": ("x", "--", "C5"),
         LSODA_NB: ("P", ":", "C6")}
TARGET_RATIO, TARGET_OVERHEAD = 300.0, 1.3
#: (trajectory, method, tol) of the baseline runs that failed (reported, not plotted)
FAILED = []


#: the defaults of the continuation that places the trajectories (eta_start, step, transient)
_CONT = _continued.__kwdefaults__


def _span(tols):
    """``1e-04 ... 1e-12`` of a list of tolerances."""
    return f"{max(tols):.0e} ... {min(tols):.0e}"


def results_b(results):
    """``B, Ec`` of the trajectories' presets, in words."""
    pairs = sorted({(r["B"], r["Ec"]) for r in results.values()})
    return "; ".join(f"{b:g}, Ec = {e:g}" for b, e in pairs)


def continued_state(preset, eta):
    """The impacting branch at ``eta`` (:func:`vibimpact.sweeps.continued_state`)."""
    return _continued(vi.presets.get(preset), eta)


# ---------------------------------------------------------------- (1) work-precision
def work_precision(p, s0, periods, case=""):
    """Reference, its SciPy cross-check, and per method a list (setting, err, time, nfev)."""
    tt = strobe_times(p.eta, periods)

    def ours(method, **kw):
        return lambda: vi.simulate(p, periods=periods, state0=s0,
                                   solver=vi.SolverSettings(method=method, **kw))

    ref = ours("dop853", rtol=REF_TOL, atol=REF_TOL)()
    assert ref.ok, ref.reason
    truth = ref.strobe
    sp = solve_reference(p, tt[-1], s0, rtol=REF_TOL, atol=REF_TOL, method="DOP853",
                         t_eval=tt)
    cross = float(np.max(np.abs(sp.y - truth)))
    series = {m: [] for m in METHODS}
    jobs = [("ours rk4", f"{n}/period", ours("rk4", steps_per_period=n)) for n in RK4_STEPS]
    for m in ("dp5", "dop853"):
        jobs += [(f"ours {m}", f"{tol:.0e}", ours(m, rtol=tol, atol=tol)) for tol in OUR_TOLS]
    for name, label, fn in jobs:
        fn()  # warm-up
        t, run = best_time(fn, OUR_REPEATS)
        assert run.ok, (name, label, run.reason)
        series[name].append((label, float(np.max(np.abs(run.strobe - truth))), t,
                             run.counters["rhs_evals"]))
    for m, tols in SCIPY_TOLS.items():
        for tol in tols:
            def fn(m=m, tol=tol):
                return solve_reference(p, tt[-1], s0, rtol=tol, atol=tol, method=m,
                                       t_eval=tt)
            try:
                t, sol = best_time(fn, SCIPY_REPEATS)
            except RuntimeError as exc:   # report, do not hide
                print(f"  SciPy {m} tol {tol:.0e} failed: {exc}")
                FAILED.append((case, f"SciPy {m}", tol))
                continue
            series[f"SciPy {m}"].append((f"{tol:.0e}", float(np.max(np.abs(sol.y - truth))),
                                         t, sol.nfev))
    if lsoda_baseline.available():
        for tol in LSODA_NB_TOLS:
            fn = lsoda_baseline.make_runner(p, s0, ref, tt, tol)
            try:
                fn()  # warm-up (compiles the callback and driver once)
                t, (states, nfev) = best_time(fn, OUR_REPEATS)
            except RuntimeError as exc:   # report, do not hide
                print(f"  {LSODA_NB} tol {tol:.0e} failed: {exc}")
                FAILED.append((case, LSODA_NB, tol))
                continue
            series[LSODA_NB].append((f"{tol:.0e}", float(np.max(np.abs(states - truth))), t,
                                     nfev))
    return cross, len(ref.impacts), series


def pareto(points, col=2):
    """(error, cost) of the runs no other run beats in both, by increasing error."""
    front = []
    for q in sorted(points, key=lambda q: (q[1], q[col])):
        if not front or q[col] < front[-1][1]:
            front.append((q[1], q[col]))
    return front


def cost_at_error(points, err, col=2):
    """Least cost (time, col 2, or RHS evaluations, col 3) reaching ``err``: log cost
    interpolated linearly in log error along the Pareto front; NaN outside its range."""
    front = pareto(points, col)
    if not front:
        return np.nan
    e = np.log10([max(q[0], 1e-300) for q in front])
    c = np.log10([q[1] for q in front])
    x = np.log10(err)
    if x < e[0] or x > e[-1]:
        return np.nan
    return 10.0 ** np.interp(x, e, c)


def ratios(series, a="ours dop853", b="SciPy DOP853"):
    """(error, time a, time b, b/a) at the decades of error both methods cover."""
    A, B = series[a], series[b]
    lo = max(min(q[1] for q in A), min(q[1] for q in B))
    hi = min(max(q[1] for q in A), max(q[1] for q in B))
    out = []
    for k in range(int(np.floor(np.log10(hi))), int(np.ceil(np.log10(lo))) - 1, -1):
        err = 10.0 ** k
        ta, tb = cost_at_error(A, err), cost_at_error(B, err)
        if np.isfinite(ta) and np.isfinite(tb):
            out.append((err, ta, tb, tb / ta))
    return out


# ---------------------------------------------------------------- (2) overhead
@njit(cache=False)
def _bare_rhs_loop(ts, ys, modes, p, n):
    """``n`` calls of the model RHS, cycling over sampled (t, state, mode)."""
    out = np.empty(4)
    acc = 0.0
    m = ts.size
    for i in range(n):
        j = i % m
        rotor.rhs(ts[j], ys[j], p, modes[j], out)
        acc += out[2] + out[3]
    return acc


def overhead(p, s0):
    """Rows (method, settings, rhs evals, time, ns/eval inside, ns/eval bare, ratio,
    accepted steps, rejected steps, located events incl. observer events)."""
    pa = np.ascontiguousarray(p.as_array())
    samp = vi.simulate(p, periods=SAMPLE_PERIODS, state0=s0, dense=SAMPLES_PER_PERIOD)
    ys = np.ascontiguousarray(samp.dense)
    ts = np.ascontiguousarray(samp.t_dense) - samp.t_dense[0]   # forcing phase from tau=0
    modes = np.zeros((ys.shape[0], rotor.N_MODE), dtype=np.int64)
    for j in range(ys.shape[0]):
        rotor.init_mode(ts[j], ys[j], pa, modes[j])
    contact_share = float(np.mean(modes[:, 0] == 1))
    inc = np.flatnonzero(modes[:, 0] == 1)     # contact samples only (the dearer RHS)
    if inc.size == 0:
        inc = np.arange(ts.size)
    _bare_rhs_loop(ts, ys, modes, pa, 10)   # compile
    rows = []
    for method, kw in OVERHEAD_SETTINGS.items():
        def fn(method=method, kw=kw):
            return vi.simulate(p, periods=OVERHEAD_PERIODS, state0=s0,
                               solver=vi.SolverSettings(method=method, **kw))
        fn()
        t, run = best_time(fn, 3)
        n = run.counters["rhs_evals"]
        tb, _ = best_time(lambda n=n: _bare_rhs_loop(ts, ys, modes, pa, n), 3)
        tc, _ = best_time(lambda n=n: _bare_rhs_loop(ts[inc], ys[inc], modes[inc], pa, n),
                          3)
        desc = ", ".join(f"{k}={v:g}" for k, v in kw.items())
        c = run.counters
        rows.append((method, desc, n, t, 1e9 * t / n, 1e9 * tb / n, t / tb, c["steps"],
                     c["rejected"], c["events"] + c["observed"], 1e9 * tc / n))
    return rows, contact_share


# ---------------------------------------------------------------- plot and report
def plot(results, path):
    fig, axes = plt.subplots(2, 2, figsize=(11, 8.5))
    for ax, (label, res) in zip(axes.flat, results.items()):
        for name in METHODS:
            pts = sorted(res["series"][name], key=lambda q: q[2])
            if not pts:
                continue
            mk, ls, c = STYLE[name]
            ax.loglog([max(q[1], 1e-17) for q in pts], [q[2] for q in pts], marker=mk,
                      ls=ls, color=c, ms=4, lw=1, label=name)
        ax.set_title(f"{label}: eta = {res['eta']} ({res['regime']}), {res['periods']} "
                     f"periods, {res['impacts']} impacts", fontsize=9)
        ax.set_xlabel("max abs strobe error vs dop853 at 1e-13")
        ax.set_ylabel("wall time [s]")
        ax.grid(True, which="both", alpha=0.3)
    axes.flat[0].legend(fontsize=7, loc="best")
    fig.suptitle("Work-precision: vibimpact kernel (solid) vs SciPy solve_ivp (dashed) and "
                 "numbalsoda LSODA (dotted), restarted at switches, compiled RHS",
                 fontsize=10)
    fig.tight_layout()
    tmp = path.with_name(path.stem + ".tmp.png")
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, path)


def numbalsoda_note():
    v = lsoda_baseline.available()
    if v is None:
        return ("not importable here, so not benchmarked (`pip install numbalsoda` builds "
                "C++ and Fortran sources and needs gfortran)")
    return (f"{v}: LSODA called from an `@njit` driver with a `@cfunc` right-hand side "
            "(`analyses/performance/_lsoda_baseline.py`); it has no event location, so it is given the "
            "reference's switch times and modes and restarted at each (its times include "
            "no event location, ours do)")


def report(results, ov, load, elapsed):
    now = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    L = ["# Work-precision and overhead (issue 6)", "",
         "Written by `python analyses/performance/work_precision.py`; every number below is measured by "
         "that script in one run (nothing typed in by hand).", "",
         f"- date: {now}; script wall time {elapsed:.0f} s",
         f"- machine: `{platform.platform()}`, `os.cpu_count()` = {os.cpu_count()}; "
         f"load average at start / end {load[0]:.2f} / {load[1]:.2f} (other work on the "
         "machine inflates all timings alike; all timings single-threaded)",
         f"- versions: Python {platform.python_version()}, numpy {np.__version__}, "
         f"scipy {scipy.__version__}, numba {numba.__version__}, vibimpact {vi.__version__}",
         f"- numbalsoda: {numbalsoda_note()}", "",
         "## (1) Work-precision", "",
         f"Trajectories: continued up from eta = {_CONT['eta_start']:g} (rest) in steps of "
         f"{_CONT['step']:g} with {_CONT['transient']} "
         "transient periods at each step (the impacting branch), then integrated for the "
         "periods stated. Error: max abs difference of the stroboscopic states from our "
         f"dop853 at rtol = atol = {REF_TOL:g}. Our methods: rk4 at {RK4_STEPS} steps per "
         f"period, dp5 and dop853 at rtol = atol = {_span(OUR_TOLS)} (best of "
         f"{OUR_REPEATS} after a warm-up). SciPy `solve_ivp` (scipy "
         f"{scipy.__version__}) RK45, DOP853, LSODA with the compiled model RHS, restarted "
         "at every switch and stopped at every strobe time (`vibimpact.testing.reference."
         "solve_reference`), rtol = atol = "
         + ", ".join(f"{m} {_span(t)}" for m, t in SCIPY_TOLS.items())
         + f", best of {SCIPY_REPEATS}.", "",
         f"Regime: decided in this run by `classify_params` on the trajectory's attractor "
         f"(at most {LABEL_TRANSIENT} transient periods from state0, {LABEL_PERIODS} "
         f"recorded); "
         f"parameters B = {results_b(results)}.  The fig8 rows use the first candidate "
         "speed with the regime their name asks for: "
         + "; ".join(f"{label}: " + ", ".join(f"{e:g} {describe(g)}" for e, g in r["tried"])
                     for label, r in results.items() if len(r["tried"]) > 1) + ".", "",
         "| trajectory | eta | regime (classifier) | periods | impacts | state0 | ref. "
         f"cross-check: SciPy DOP853 {REF_TOL:g} vs ours {REF_TOL:g} |",
         "| --- | ---: | --- | ---: | ---: | --- | ---: |"]
    for label, r in results.items():
        L.append(f"| {label} | {r['eta']} | {describe(r['regime'])} | {r['periods']} | "
                 f"{r['impacts']} | [{', '.join(f'{v:.6g}' for v in r['s0'])}] | "
                 f"{r['cross']:.2e} |")
    L += ["", f"![work-precision]({FIGURE.name})", "",
          "### Speed ratio at equal error: SciPy DOP853 time / our dop853 time", "",
          "Least time reaching each error, log time interpolated linearly in log error along "
          f"each method's Pareto front; target >= {TARGET_RATIO:.0f}x.", "",
          "| trajectory | error | ours dop853 [ms] | SciPy DOP853 [ms] | ratio |",
          "| --- | ---: | ---: | ---: | ---: |"]
    summary = []
    for label, r in results.items():
        for err, ta, tb, q in r["ratios"]:
            L.append(f"| {label} | {err:.0e} | {1e3 * ta:.2f} | {1e3 * tb:.1f} | {q:.0f} |")
        qs = [x[3] for x in r["ratios"]]
        if qs:
            gm = float(np.exp(np.mean(np.log(qs))))
            summary.append((label, min(qs), gm, max(qs)))
    L += ["", "| trajectory | min ratio | geometric mean | max ratio | target >= "
          f"{TARGET_RATIO:.0f}x met (at every error level) |",
          "| --- | ---: | ---: | ---: | :---: |"]
    for label, lo, gm, hi in summary:
        L.append(f"| {label} | {lo:.0f} | {gm:.0f} | {hi:.0f} | "
                 f"{'yes' if lo >= TARGET_RATIO else '**no**'} |")
    if FAILED:
        L += ["", "Baseline runs that failed (no result, left out of the plot and tables): "
              + "; ".join(f"{m} at rtol = atol = {tol:.0e} ({where})"
                          for where, m, tol in FAILED)
              + ".  numbalsoda's LSODA stops after 100,000 internal steps when its step "
              "size underflows (`t + h = t`)."]
    L += ["", f"The same against {LSODA_NB} ({LSODA_NB} time / our dop853 time at equal "
          "error; numbalsoda gets the switch times for free, see above):", "",
          "| trajectory | error levels | min ratio | geometric mean | max ratio |",
          "| --- | ---: | ---: | ---: | ---: |"]
    for label, r in results.items():
        qs = ([x[3] for x in ratios(r["series"], b=LSODA_NB)]
              if r["series"][LSODA_NB] else [])
        if qs:
            L.append(f"| {label} | {len(qs)} | {min(qs):.2f} | "
                     f"{float(np.exp(np.mean(np.log(qs)))):.2f} | {max(qs):.2f} |")
        else:
            L.append(f"| {label} | 0 | - | - | - |")
    # per-eval cost of SciPy, for context
    sp_ns = [1e9 * q[2] / q[3] for r in results.values() for q in r["series"]["SciPy DOP853"]]
    our_ns = [1e9 * q[2] / q[3] for r in results.values() for q in r["series"]["ours dop853"]]
    L += ["", f"Wall time per RHS evaluation over these runs (median): SciPy DOP853 "
          f"{np.median(sp_ns) / 1e3:.1f} us, ours dop853 {np.median(our_ns):.0f} ns "
          f"({np.median(sp_ns) / np.median(our_ns):.0f}x). The time ratio at equal error is "
          "this per-evaluation ratio times the ratio of evaluations each needs (table "
          "below).", "",
          f"### RHS evaluations per forcing period at error {ERR_FIXED:.0e}", "",
          "Interpolated as above (log evaluations against log error along the Pareto front); "
          "'-' where the method's runs do not bracket the error.", "",
          "| trajectory | " + " | ".join(METHODS) + " |",
          "| --- |" + " ---: |" * len(METHODS)]
    for label, r in results.items():
        cells = []
        for m in METHODS:
            n = cost_at_error(r["series"][m], ERR_FIXED, col=3)
            cells.append("-" if not np.isfinite(n) else f"{n / r['periods']:.0f}")
        L.append(f"| {label} | " + " | ".join(cells) + " |")
    L += ["", "### All runs", "", "<details><summary>setting, error, time, RHS evaluations "
          "per run</summary>", "",
          "| trajectory | method | setting | error | time [ms] | RHS evals |",
          "| --- | --- | --- | ---: | ---: | ---: |"]
    for label, r in results.items():
        for m in METHODS:
            for s, e, t, n in r["series"][m]:
                L.append(f"| {label} | {m} | {s} | {e:.2e} | {1e3 * t:.2f} | {n} |")
    L += ["", "</details>", "",
          "## (2) Integrator overhead against the RHS floor", "",
          f"Inside: wall time of `vi.simulate` over {OVERHEAD_PERIODS} periods (best of 3, "
          "warm) / `counters['rhs_evals']`; it includes everything the integrator does "
          "besides the RHS (stage combinations, error norm, step control, switching "
          "functions and event location, strobe and event logging, the Python wrapper). "
          "Floor: a bare `@njit` loop calling `vibimpact._kernel.rotor.rhs` the same number "
          f"of times, cycling over {SAMPLES_PER_PERIOD} states per period sampled along "
          f"{SAMPLE_PERIODS} periods of the same "
          "trajectory (with the mode each state is in), best of 3; the integrator spends "
          "more of its evaluations in contact than this time-uniform sample does, so the "
          "last two columns repeat the floor on the contact states only (the dearer RHS), "
          f"an upper bound of the floor. Target: ratio <= {TARGET_OVERHEAD}.", "",
          "| trajectory | contact share of samples | method | settings | accepted steps | "
          "rejected | located events | RHS evals | RHS evals / accepted step | time [s] | "
          "ns/eval inside | ns/eval bare | ratio | target met | ns/eval bare, contact states only "
          "| ratio to it |",
          "| --- | ---: | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | "
          "---: | :---: | ---: | ---: |"]
    for label, (rows, share) in ov.items():
        for m, desc, n, t, ns_in, ns_bare, q, acc, rej, nev, ns_c in rows:
            L.append(f"| {label} | {share:.2f} | {m} | {desc} | {acc} | {rej} "
                     f"({100 * rej / max(acc + rej, 1):.0f}%) | {nev} | {n} | {n / acc:.1f} | "
                     f"{t:.4f} | {ns_in:.0f} | {ns_bare:.0f} | {q:.2f} | "
                     f"{'yes' if q <= TARGET_OVERHEAD else '**no**'} | {ns_c:.0f} | "
                     f"{ns_in / ns_c:.2f} |")
    write_section(REPORT, SECTION, "\n".join(L))


def main(argv=None):
    global REPORT, FIGURE
    out = smoke.parser(__doc__).parse_args(argv).smoke
    REPORT, FIGURE = smoke.moved(REPORT, out), smoke.moved(FIGURE, out)
    low = [1e-5, 1e-6, 1e-7]
    smoke.shrink(globals(), out, CASES=[CASES[0][:4] + (2,), CASES[2][:4] + (2,)],
                 SAMPLE_PERIODS=2, RK4_STEPS=[50, 100, 200], OUR_TOLS=[1e-4, 1e-6, 1e-8],
                 SCIPY_TOLS=dict.fromkeys(SCIPY_TOLS, low), LSODA_NB_TOLS=low,
                 OUR_REPEATS=1, SCIPY_REPEATS=1, OVERHEAD_PERIODS=5, ERR_FIXED=1e-5)
    t_start = time.perf_counter()
    load0 = os.getloadavg()[0]
    REPORT.parent.mkdir(parents=True, exist_ok=True)
    results, ov = {}, {}
    for label, preset, etas, want, periods in CASES:
        t0 = time.perf_counter()
        if want is None:
            eta = etas[0]
            s0 = continued_state(preset, eta)
            regime = label_orbit(vi.presets.get(preset).replace(eta=eta), s0)
            tried = [(eta, regime)]
        else:
            eta, s0, regime, tried = pick_orbit(
                preset, etas, want, lambda q, preset=preset: continued_state(preset, q.eta))
        p = vi.presets.get(preset).replace(eta=eta)
        print(f"{label}: eta = {eta}: {describe(regime)}")
        cross, n_imp, series = work_precision(p, s0, periods, label)
        results[label] = dict(eta=eta, periods=periods, s0=s0, cross=cross, impacts=n_imp,
                              series=series, ratios=ratios(series), regime=regime,
                              tried=tried, B=p.B, Ec=p.Ec)
        ov[label] = overhead(p, s0)
        print(f"{label}: cross-check {cross:.2e}, {n_imp} impacts, "
              f"{time.perf_counter() - t0:.1f} s")
        for err, ta, tb, q in results[label]["ratios"]:
            print(f"   error {err:.0e}: ours {1e3 * ta:.2f} ms, SciPy {1e3 * tb:.1f} ms, "
                  f"ratio {q:.0f}")
        for m, desc, n, t, a, b, q, *_ in ov[label][0]:
            print(f"   overhead {m:7s} {a:.0f} ns/eval vs bare {b:.0f} ns/eval: {q:.2f}x")
    plot(results, FIGURE)
    load1 = os.getloadavg()[0]
    report(results, ov, (load0, load1), time.perf_counter() - t_start)
    print(f"wrote {REPORT} (section {SECTION}) and {FIGURE} in "
          f"{time.perf_counter() - t_start:.0f} s")


if __name__ == "__main__":
    main()
