"""Lyapunov exponents with the tangent vectors' error test loosened, against the full test.

Run as ``python analyses/lyapunov_error_control.py``; replaces the section
"lyapunov-error-control" of ``reports/performance.md``.  Every number written is measured
here.

The variational equations ``v' = J(x) v`` ride on the state's integration.  The
tangent vectors' local errors are tested at ``tangent_tol`` times the tolerances: 1 (as
the state), 1e3 (the default of :func:`vibimpact.analysis.lyapunov_spectrum`) or inf
(not tested: the steps are the state's).  Three measurements, at the sweep's tolerances
(rtol 1e-8, atol 1e-11):

1. the one-period Jacobian of the stroboscopic map (4 tangent vectors) from 40 states on
   a chaotic attractor (fig8, eta = 1.19) and on an impacting periodic orbit, against a
   reference at rtol 1e-12 (tangent_tol 1): relative error of the matrix, and run time;
2. the largest exponent of impacting periodic orbits against the exact value
   ``log |mu_max| / T`` from the Floquet multipliers of the shot orbit;
3. the largest exponent of chaotic motion (1 exponent, 20 periods of alignment, then
   600 periods), every setting from the same state: values, standard errors, run time.
"""
import datetime
import math
import platform
import time
from pathlib import Path

import numpy as np

from _report import write_section

import vibimpact as vi
from vibimpact.analysis import lyapunov_spectrum, monodromy, shoot_periodic_orbit

ROOT = Path(__file__).resolve().parents[1]
REPORT = ROOT / "reports" / "performance.md"
TOL = dict(rtol=1e-8, atol=1e-11)
REF = dict(rtol=1e-12, atol=1e-14)
#: tangent_tol settings compared
MODES = (1.0, 1e3, math.inf)
NAMES = {1.0: "1", 1e3: "1e3 (default)", math.inf: "inf"}
#: chaotic points of the presets' upward sweeps (exponent > 0.04 per unit tau there)
CHAOTIC = [("fig8", 1.19), ("fig10", 1.21), ("fig11", 1.25)]
#: impacting periodic orbits (one with a multiplier near the unit circle)
PERIODIC = [("fig8", 1.13, 1), ("fig8", 1.0, 1), ("fig10", 1.1, 1)]


def _state(preset, eta):
    """Final state of an upward sweep from eta 0.9 (step 0.01) to ``eta``: the attractor
    the presets' sweeps reach by continuation (from rest the motion may settle on another
    one)."""
    p = vi.presets.get(preset)
    etas = np.round(np.arange(0.9, eta + 1e-9, 0.01), 6)
    ds = vi.sweep(p, etas, analyses=("period",))
    return p.replace(eta=eta), ds["final_state"].values.reshape(-1, 4)[-1]


def _timed(fn):
    t = time.perf_counter()
    out = fn()
    return time.perf_counter() - t, out


def jacobian_errors(preset, eta, n_states=40):
    """Relative errors and times of one-period Jacobians, both modes, vs the reference."""
    p, x0 = _state(preset, eta)
    run = vi.simulate(p, periods=n_states, state0=x0, transient=100, **TOL)
    rows = {mode: [] for mode in MODES}
    times = dict.fromkeys(MODES, 0.0)
    for x in run.strobe[1:]:
        ref = monodromy(p, x, 1, **REF).matrix
        scale = np.linalg.norm(ref)
        for mode in rows:
            t, m = _timed(lambda: monodromy(p, x, 1, tangent_tol=mode, **TOL).matrix)
            times[mode] += t
            rows[mode].append(np.linalg.norm(m - ref) / scale)
    return {k: np.array(v) for k, v in rows.items()}, times


def periodic_exponents(preset, eta, n):
    """Exact largest exponent of a shot orbit and both modes' estimates."""
    p, x = _state(preset, eta)
    orb = shoot_periodic_orbit(p, x, n, rtol=1e-12, atol=1e-14)
    T = 2.0 * np.pi / eta
    exact = float(np.log(orb.abs_max) / (n * T))
    out = {}
    for mode in MODES:
        t, ly = _timed(lambda: lyapunov_spectrum(
            p, state0=orb.state, n_exponents=1, transient=0, min_periods=200,
            max_periods=200, align=20, tangent_tol=mode, **TOL))
        out[mode] = (float(ly.exponents[0]), float(ly.stderr[0]), t)
    return exact, bool(orb.converged), out


def chaotic_exponents(preset, eta):
    p, x = _state(preset, eta)
    out = {}
    for mode in MODES:
        t, ly = _timed(lambda: lyapunov_spectrum(
            p, state0=x, n_exponents=1, transient=0, min_periods=100, max_periods=600,
            target_stderr=1e-9, align=20, tangent_tol=mode, **TOL))
        out[mode] = (float(ly.exponents[0]), float(ly.stderr[0]), ly.periods, t)
    return out


def main():
    p0 = vi.presets.get("fig8")
    for mode in MODES:  # compile first
        lyapunov_spectrum(p0, n_exponents=1, transient=0, min_periods=2, max_periods=2,
                          block=2, align=0, tangent_tol=mode, **TOL)
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    lines = ["# Lyapunov exponents: the tangent vectors' error test", "",
             "Written by `python analyses/lyapunov_error_control.py`; every number is "
             "measured by it.  `tangent_tol`: the tangent vectors' local errors are tested "
             "at that many times the tolerances (1: as the state; inf: not at all).", "",
             f"- date: {now}; machine: `{platform.platform()}`",
             "- tolerances: rtol 1e-8, atol 1e-11 (the sweep's); reference rtol 1e-12, "
             "atol 1e-14, tangent_tol 1", "",
             "## One-period Jacobians of the stroboscopic map", "",
             "Relative error `|M - M_ref| / |M_ref|` (Frobenius) over 40 states of each "
             "trajectory, and the time of the 40 matrices:", "",
             "| trajectory | tangent_tol | median error | max error | time [ms] |",
             "| --- | --- | ---: | ---: | ---: |"]
    for preset, eta in [CHAOTIC[0], PERIODIC[0][:2]]:
        err, times = jacobian_errors(preset, eta)
        for mode in MODES:
            lines.append(f"| {preset} eta = {eta} | {NAMES[mode]} | "
                         f"{np.median(err[mode]):.1e} | {err[mode].max():.1e} | "
                         f"{1e3 * times[mode]:.0f} |")
    head = " | ".join(f"tangent_tol {NAMES[m]}" for m in MODES)
    lines += ["", "## Impacting periodic orbits: largest exponent against log|mu_max| / T", "",
              "200 periods after 20 of alignment, from the shot orbit (Newton at rtol "
              "1e-12); value per unit tau (standard error), time:", "",
              f"| orbit | exact | {head} |", "| --- | ---: |" + " ---: |" * len(MODES)]
    for preset, eta, n in PERIODIC:
        exact, ok, out = periodic_exponents(preset, eta, n)
        cells = " | ".join(f"{out[m][0]:.5f} ({out[m][1]:.0e}), {1e3 * out[m][2]:.0f} ms"
                           for m in MODES)
        lines.append(f"| {preset} eta = {eta} P{n}{'' if ok else ' (shooting failed)'} | "
                     f"{exact:.5f} | {cells} |")
    lines += ["", "## Chaotic motion: largest exponent over 600 periods", "",
              "Every setting from the same state (the trajectories part after a few "
              "periods, so the estimates are independent samples of the same exponent); "
              "value (standard error), time:", "",
              f"| trajectory | {head} | largest difference / combined stderr |",
              "| --- |" + " ---: |" * len(MODES) + " ---: |"]
    speed = []
    for preset, eta in CHAOTIC:
        out = chaotic_exponents(preset, eta)
        lam = {m: out[m][0] for m in MODES}
        err = {m: out[m][1] for m in MODES}
        z = max(abs(lam[a] - lam[b]) / math.hypot(err[a], err[b])
                for a in MODES for b in MODES if a < b)
        speed.append(out[1.0][3] / out[1e3][3])
        cells = " | ".join(f"{lam[m]:.4f} ({err[m]:.0e}), {out[m][3]:.2f} s" for m in MODES)
        lines.append(f"| {preset} eta = {eta} | {cells} | {z:.1f} |")
    lines += ["", f"The default (tangent_tol 1e3) runs the chaotic exponents "
              f"{min(speed):.1f}-{max(speed):.1f}x faster than tangent_tol 1."]
    write_section(REPORT, "lyapunov-error-control", "\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
