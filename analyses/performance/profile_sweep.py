"""Where the fig8 sweep spends its time, and what the transient extrapolation removed.

Run as ``python analyses/performance/profile_sweep.py``; replaces the "profile" section of
``reports/performance.md``.  The main job's sweep (``vibimpact classify --eta
0.9:1.5:0.002`` on fig8, all analyses) runs serially under cProfile twice: without and with
the extrapolation of transients (``SweepSettings(extrapolate=0)`` and the default), after
a warm-up.  Every number written is measured here or read from the settings it describes
(``SweepSettings``, the decision rule); the rejected steps per contact are counted on a
fig8 trajectory whose regime the classifier decides in the same run, and the fig11 label
changes by the same two sweeps on fig11 (without the profiler).
"""
import cProfile
import datetime
import platform
import pstats
import time
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # analyses/: _common
from _common import smoke  # noqa: E402
from _common.profiles import by_source  # noqa: E402
from _common.report import write_section  # noqa: E402

import vibimpact as vi
from vibimpact.analysis import Label
from vibimpact.sweeps import SweepSettings
from vibimpact.points.point import REGIME_CODES
from vibimpact.points.transient import CHUNK_AFTER_JUMP

from benchmark_kernel import (CANDIDATE_ETAS, describe, is_impacting_periodic,  # noqa: E402
                              pick_orbit)

ROOT = Path(__file__).resolve().parents[2]
REPORT = ROOT / "reports" / "performance.md"
ETA = np.round(np.arange(0.9, 1.5 + 1e-9, 0.002), 6)

#: (part, file suffix, function name, "tottime" or "cumtime"); the first part is the
#: compiled kernel's own time (every integration: plain, variational for the exponent and
#: the monodromy matrices), the rest Python parts measured cumulatively (they contain the
#: kernel time of their own integrations).  The integrator is numba's dispatcher, whether
#: its machine code came from numba's cache (filled at install) or was compiled on first
#: use: cProfile names it after its Python source.  Every part must match a function the
#: profiled sweep called (:func:`bucket_times` fails otherwise): a renamed or moved
#: function must be renamed here, not silently reported as 0 s.
BUCKETS = (
    ("integrator kernel (all integrations)", "_kernel/driver.py", "integrate", "tottime"),
    ("of the total: Lyapunov exponent (variational equations, non-periodic points, "
     "cumulative)", "analysis/lyapunov.py", "lyapunov_spectrum", "cumtime"),
    ("of the total: Floquet multipliers (Newton shooting, cumulative)",
     "analysis/shooting.py", "shoot_periodic_orbit", "cumtime"),
    ("of the total: period detection (cumulative)", "analysis/period.py", "detect_period",
     "cumtime"),
    ("of the total: impact records (cumulative)", "models/contact.py", "impacts_from_events",
     "cumtime"),
)
#: the parts whose times are the compiled kernels' own (the Python rest is wall - these)
KERNEL_PARTS = ("integrator kernel (all integrations)",)


class UnmatchedProfileEntry(LookupError):
    """A part of :data:`BUCKETS` matched no function of the profile."""


def bucket_times(stats, buckets=BUCKETS):
    """Seconds of each part of ``buckets`` in ``stats`` (:attr:`pstats.Stats.stats`).

    A part may have several entries (their times summed: a part spread over two
    functions); every entry must match a function the profile saw.

    A compiled kernel function called through its entry point (the package calls the
    integration loop's overload directly once numba has typed it) is profiled as a
    built-in, ``<built-in method vibimpact._kernel.driver.integrate>``: it counts as the
    function of that module (``_kernel/driver.py``, ``integrate``), as the same function
    called through numba's dispatcher does.

    Raises
    ------
    UnmatchedProfileEntry
        Naming every entry that matched no function: the function was renamed or moved,
        and the report would show 0 s for it (or silently leave its share out of a part).
    """
    out, missing = {}, []
    stats = by_source(stats)
    for name, suffix, func, col in buckets:
        t, hit = 0.0, False
        for (fname, _, fn), (_, _, tt, ct, _) in stats.items():
            if fname.endswith(suffix) and fn == func:
                t += tt if col == "tottime" else ct
                hit = True
        if not hit:
            missing.append(f"{name!r} ({suffix}:{func})")
        out[name] = out.get(name, 0.0) + t
    if missing:
        raise UnmatchedProfileEntry(
            "profile entries that match no function the sweep called (renamed or moved? "
            "fix BUCKETS in analyses/performance/profile_sweep.py): " + "; ".join(missing))
    return out


def _profile(settings):
    pr = cProfile.Profile()
    t0 = time.perf_counter()
    pr.enable()
    ds = vi.sweep(vi.presets.get("fig8"), ETA, settings=settings,
                  execution=vi.Execution(workers=1))
    pr.disable()
    wall = time.perf_counter() - t0
    out = bucket_times(pstats.Stats(pr).stats)
    kernels = sum(out[k] for k in KERNEL_PARTS)
    out["Python around the kernels (wall - kernels)"] = max(0.0, wall - kernels)
    return wall, out, ds


def _change(before, after):
    """``"fell by 26 %"`` / ``"rose by 3 %"`` / ``"did not change"``: the relative change
    of a measured quantity, in words, from the numbers themselves."""
    if before <= 0 or round(100 * (after - before) / before) == 0:
        return "did not change" if after == before or before <= 0 else \
            "changed by less than 1 %"
    pct = 100 * (after - before) / before
    return f"{'fell' if pct < 0 else 'rose'} by {abs(pct):.0f} %"


#: forcing periods of the step-count runs
COUNT_PERIODS = 300


def rejected_per_contact():
    """DOP853 at the sweep's tolerances on a fig8 trajectory the classifier labels periodic
    with impacts (the first of ``benchmark_kernel.CANDIDATE_ETAS``, from rest after a
    continuation-free 200-period transient): (eta, regime, accepted, rejected, contacts)."""
    st = SweepSettings()
    eta, s0, regime, _ = pick_orbit(
        "fig8", CANDIDATE_ETAS, is_impacting_periodic,
        lambda q: vi.simulate(q, periods=1, transient=200, state0=[1.1, 0.0, 0.0, 1.3])
        .final_state)
    p = vi.presets.get("fig8").replace(eta=eta)
    run = vi.simulate(p, periods=COUNT_PERIODS, state0=s0,
                      solver=vi.SolverSettings(method=st.method, rtol=st.rtol, atol=st.atol))
    c = run.counters
    return eta, regime, c["steps"], c["rejected"], len(run.impacts)


def fig11_label_changes():
    """Points of the fig11 sweep (same grid) whose label differs with and without the
    extrapolation of transients."""
    p = vi.presets.get("fig11")
    a = vi.sweep(p, ETA, settings=SweepSettings(extrapolate=0),
                 execution=vi.Execution(workers=1))
    b = vi.sweep(p, ETA, settings=SweepSettings(), execution=vi.Execution(workers=1))
    return int((a.label.values != b.label.values).sum()), ETA.size


def main(argv=None):
    global REPORT
    out = smoke.parser(__doc__).parse_args(argv).smoke
    REPORT = smoke.moved(REPORT, out)
    # periodic and chaotic speeds of fig8 (continued from 1.0): every profiled part runs
    smoke.shrink(globals(), out, ETA=np.round(np.arange(1.0, 1.26, 0.05), 6), COUNT_PERIODS=20)
    # warm-up (numba cache, imports)
    vi.sweep(vi.presets.get("fig8"), ETA[:6], execution=vi.Execution(workers=1))
    runs = {}
    for label, st in (("without extrapolation", SweepSettings(extrapolate=0)),
                      ("with extrapolation (default)", SweepSettings())):
        runs[label] = _profile(st)
    L = ["# Profile of the main job's sweep (issue 6, part 4)", "",
         "Written by `python analyses/performance/profile_sweep.py`; every number is measured by it.", "",
         f"- date: {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC",
         f"- machine: `{platform.platform()}`; serial (one process), warm numba cache",
         "- request: fig8, eta = 0.9:1.5:0.002 (301 points), direction up, all analyses, "
         "under cProfile (which adds Python-call overhead; the kernel times are not "
         "affected)", ""]
    names = list(next(iter(runs.values()))[1])
    L.append("| part | " + " | ".join(f"{k} [s]" for k in runs) + " |")
    L.append("| --- |" + " ---: |" * len(runs))
    for n in names:
        L.append(f"| {n} | " + " | ".join(f"{r[1][n]:.2f}" for r in runs.values()) + " |")
    L.append("| **total (wall)** | " + " | ".join(f"**{r[0]:.2f}**" for r in runs.values())
             + " |")
    (w0, _, a), (w1, _, b) = runs.values()
    same = a.label.values == b.label.values
    L += ["",
          f"Transient periods per point: mean {float(a.transient.mean()):.0f} -> "
          f"{float(b.transient.mean()):.0f}, median {float(np.median(a.transient)):.0f} -> "
          f"{float(np.median(b.transient)):.0f}.  Sweep wall time {w0:.2f} s -> {w1:.2f} s "
          f"({w0 / w1:.2f}x).  Labels equal at {int(same.sum())} of {same.size} points; "
          "where they differ:", ""]
    rows = [f"| {e:.3f} | {x} | {y} |" for e, x, y, s in
            zip(ETA, a.label.values, b.label.values, same) if not s]
    L += ["| eta | without | with |", "| ---: | --- | --- |"] + (rows or ["| - | - | - |"])
    (_, t0, _), (_, t1, _) = runs.values()
    py = "Python around the kernels (wall - kernels)"
    k0, k1 = (sum(t[k] for k in KERNEL_PARTS) for t in (t0, t1))
    py0, py1 = t0[py], t1[py]
    tr0, tr1 = float(a.transient.mean()), float(b.transient.mean())
    md0, md1 = float(np.median(a.transient)), float(np.median(b.transient))
    st = SweepSettings()
    tol = st.rule.period_tol
    mu = 0.9
    wait = np.log(tol) / np.log(mu)
    mu_cap = tol ** (1.0 / st.transient_max)
    rec = -(-st.record // st.chunk) * st.chunk
    nonper = int((b.regime.values != REGIME_CODES[Label.PERIODIC]).sum())
    eta_c, regime_c, acc, rej, contacts = rejected_per_contact()
    n11, m11 = fig11_label_changes()
    L += ["",
          "What dominated and what was done:",
          "",
          "- **Wasted transient periods**: a point on a stable orbit waits for its "
          f"slowest Floquet mode to decay to the period test's {tol:g}: {wait:.0f} periods "
          f"at |mu| = {mu:g}, and never within the {st.transient_max}-period cap at "
          f"|mu| > {mu_cap:.3f} (|mu|^n = {tol:g}).  The transient now jumps to the limit "
          "of its stroboscopic points by minimal polynomial "
          "extrapolation (Cabay & Jackson 1976; Skelboe 1980) when they close in "
          "geometrically on a cycle (`vibimpact.analysis.extrapolate_limit`, at most "
          f"{st.extrapolate} jumps, the next check {CHUNK_AFTER_JUMP} periods after a "
          "jump); the period is accepted only "
          "from integrated points that repeat, and after a jump only if the orbit's "
          "Floquet multipliers lie inside the unit circle (a jump can land on a saddle).  "
          f"Measured above: the transient periods per point {_change(tr0, tr1)} in the mean "
          f"and {_change(md0, md1)} in the median, the Python work around the kernels "
          f"{_change(py0, py1)}, the integrator kernel's time {_change(k0, k1)}; the "
          f"kernel time left sits in the {nonper} non-periodic points of this sweep (the "
          f"{st.transient_max}-period transient each, its last {rec} periods the record, "
          "with many more contacts per period) and in the recorded periods; this "
          f"profile does not split it further.  On fig11 (same grid) the labels differ at "
          f"{n11} of {m11} points without and with the extrapolation; shooting and long "
          "runs (tests/test_extrapolation.py) check that such new periodic labels are "
          "slowly converging stable orbits that the cap misread as quasi-periodic or "
          "chaotic.",
          "- **Rejected steps after contacts**: a DOP853 step "
          "that starts on the retainer sees the Hertz force's (R-1)^{3/2} onset and "
          "needs a step far shorter than the one before the event, which the error control "
          f"finds by rejecting steps.  Counted here: fig8 eta = {eta_c:g} "
          f"({describe(regime_c)}), {COUNT_PERIODS} periods at the sweep's tolerances "
          f"(rtol {st.rtol:g}, atol {st.atol:g}): {rej} rejected of {acc + rej} steps "
          f"({100 * rej / max(acc + rej, 1):.0f} %), {rej / max(contacts, 1):.1f} rejected "
          f"steps per contact ({contacts} contacts); section (2) of the work-precision "
          "section counts them at other tolerances.  A step-size memory carried from event "
          "to event cut the RHS evaluations but was reverted: the sweep integrates in "
          f"{st.chunk}-period calls, the memory made their step sequences differ, and the "
          "strobe points of stable orbits stopped repeating "
          "(tests/test_kernel_accuracy.py now checks this).  Kept from that work: the "
          "switching functions at a step's start are reused from the step before (one "
          "switching-function evaluation fewer per step, results bit-identical).",
          "- **Allocation in the hot loop**: the variational right-hand side (every stage "
          "of the Lyapunov and Floquet integrations) allocated a 4x4 Jacobian per call; "
          "it now takes the Jacobian's two non-trivial rows as scalars "
          "(`rotor.jac_rows`), with the same exponents to the last digit (the speed-up "
          "was timed when the change was made, not by this script).  The integrator "
          "allocates its work arrays once per call, never per step.",
          f"- **The Lyapunov kernel** on the {nonper} non-periodic points: the variational "
          f"equations over {st.lyap_min}-{st.lyap_max} periods to a {st.lyap_target:g} "
          "standard error; apart from the allocation above, unchanged (it is the "
          "measurement asked for).",
          "- **Trigonometry via a rotating phasor**: not done.  The forcing terms cost "
          "two `sin`/`cos` per RHS evaluation, inside the bare RHS floor of section (2) "
          "of the work-precision section (column 'ns/eval bare'); the integrator's "
          "overhead over that floor is per-step work (stage combinations, error norm, "
          "switching-function samples, event location), so a phasor would shrink the "
          "floor, not the overhead ratio.",
          ]
    write_section(REPORT, "profile", "\n".join(L))
    print("\n".join(L))


if __name__ == "__main__":
    main()
