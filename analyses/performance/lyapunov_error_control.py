"""Lyapunov exponents with the tangent vectors' error test loosened, against the full test.

Run as ``python analyses/performance/lyapunov_error_control.py``; replaces the section
"lyapunov-error-control" of ``reports/performance.md``.  Every number written is measured
here.

The variational equations ``v' = J(x) v`` ride on the state's integration.  The
tangent vectors' local errors are tested at ``tangent_tol`` times the tolerances: 1 (as
the state), 1e3 (the default of :func:`vibimpact.analysis.lyapunov_spectrum`) or inf
(not tested: the steps are the state's).  Three measurements, at the sweep's tolerances
(rtol 1e-8, atol 1e-11):

1. the one-period Jacobian of the stroboscopic map (4 tangent vectors) from 40 states on
   a chaotic attractor and on an impacting periodic orbit (both chosen at run time by the
   classifier from fixed candidate lists), against a
   reference at rtol 1e-12 (tangent_tol 1): relative error of the matrix, and run time;
2. the largest exponent of impacting periodic orbits against the exact value
   ``log |mu_max| / T`` from the Floquet multipliers of the shot orbit;
3. the largest exponent of chaotic motion (1 exponent, 20 periods of alignment, then
   600 periods), every setting from the same state: values, standard errors, run time.
"""
import datetime
import math
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # analyses/: _common
from _common import smoke  # noqa: E402
from _common.report import write_section  # noqa: E402

import vibimpact as vi
from vibimpact.analysis import Averaging, lyapunov_spectrum, monodromy, shoot_periodic_orbit

ROOT = Path(__file__).resolve().parents[2]
REPORT = ROOT / "reports" / "performance.md"
TOL = dict(rtol=1e-8, atol=1e-11)
REF = dict(rtol=1e-12, atol=1e-14)
#: tangent_tol settings compared
MODES = (1.0, 1e3, math.inf)
NAMES = {1.0: "1", 1e3: "1e3 (default)", math.inf: "inf"}
#: where the chaotic and the impacting periodic trajectories are looked for: the first
#: speed of each list that the preset's upward sweep (from eta = 0.9, step 0.01) labels
#: chaotic, respectively periodic with impacts, at the current defaults
CHAOTIC_CANDIDATES = {"fig8": np.round(np.arange(1.19, 1.30, 0.01), 6),
                      "fig10": np.round(np.arange(1.20, 1.31, 0.01), 6),
                      "fig11": np.round(np.arange(0.97, 1.06, 0.01), 6)}
PERIODIC_CANDIDATES = {"fig8": np.round(np.arange(1.10, 1.19, 0.01), 6),
                       "fig10": np.round(np.arange(1.05, 1.15, 0.01), 6)}
#: states per trajectory of the Jacobians' errors; periods of the periodic orbits'
#: exponents; at most this many periods of the chaotic exponents
JACOBIAN_STATES, PERIODIC_PERIODS, CHAOTIC_PERIODS = 40, 200, 600
_SWEEPS = {}


def _sweep(preset):
    """The preset's upward sweep from eta 0.9 (step 0.01) to 1.31: the attractors the
    presets' sweeps reach by continuation (from rest the motion may settle on another)."""
    if preset not in _SWEEPS:
        etas = np.round(np.arange(0.9, 1.31 + 1e-9, 0.01), 6)
        _SWEEPS[preset] = vi.sweep(vi.presets.get(preset), etas,
                                   analyses=("period", "impacts", "lyapunov"),
                                   continuation=vi.Continuation(blocks=1))
    return _SWEEPS[preset]


def _state(preset, eta):
    """Parameters and the sweep's final state at ``eta``."""
    ds = _sweep(preset).sel(eta=eta)
    return vi.presets.get(preset).replace(eta=float(eta)), ds["final_state"].values


def _first(preset, candidates, want):
    """The first candidate speed whose sweep point satisfies ``want(point)``, and the
    point's label; None when none does."""
    ds = _sweep(preset)
    for e in candidates:
        pt = ds.sel(eta=e)
        if want(pt):
            return float(e), str(pt["label"].values), int(pt["period"].values)
    return None


def chosen_points():
    """(preset, eta, label) of the chaotic, and (preset, eta, n, label) of the periodic
    trajectories, decided by the classifier at run time."""
    chaotic, periodic = [], []
    for preset, cands in CHAOTIC_CANDIDATES.items():
        got = _first(preset, cands, lambda pt: int(pt["regime"].values) == 3)
        if got:
            chaotic.append((preset, got[0], got[1]))
    for preset, cands in PERIODIC_CANDIDATES.items():
        got = _first(preset, cands, lambda pt: int(pt["regime"].values) == 1 and
                     int(pt["period"].values) >= 1 and
                     float(pt["impacts_per_period"].values) > 0)
        if got:
            periodic.append((preset, got[0], got[2], got[1]))
    return chaotic, periodic


def _timed(fn):
    t = time.perf_counter()
    out = fn()
    return time.perf_counter() - t, out


def jacobian_errors(preset, eta, n_states=40):
    """Relative errors and times of one-period Jacobians, both modes, vs the reference."""
    p, x0 = _state(preset, eta)
    run = vi.simulate(p, periods=n_states, state0=x0, transient=100,
                      solver=vi.SolverSettings(**TOL))
    rows = {mode: [] for mode in MODES}
    times = dict.fromkeys(MODES, 0.0)
    for x in run.strobe[1:]:
        ref = monodromy(vi.System(p, **REF), x, 1).matrix
        scale = np.linalg.norm(ref)
        for mode in rows:
            t, m = _timed(lambda x=x, mode=mode: monodromy(vi.System(p, **TOL), x, 1,
                                                           tangent_tol=mode).matrix)
            times[mode] += t
            rows[mode].append(np.linalg.norm(m - ref) / scale)
    return {k: np.array(v) for k, v in rows.items()}, times


def periodic_exponents(preset, eta, n):
    """Exact largest exponent of a shot orbit and both modes' estimates."""
    p, x = _state(preset, eta)
    orb = shoot_periodic_orbit(vi.System(p, rtol=1e-12, atol=1e-14), x, n)
    T = vi.System(p).period
    exact = float(np.log(orb.abs_max) / (n * T))
    out = {}
    s = vi.System(p, **TOL)
    avg = Averaging(transient=0, min_periods=PERIODIC_PERIODS, max_periods=PERIODIC_PERIODS,
                    align=20)
    for mode in MODES:
        t, ly = _timed(lambda mode=mode: lyapunov_spectrum(
            s, state0=orb.state, n_exponents=1, averaging=avg, tangent_tol=mode,
            floquet=False))
        out[mode] = (float(ly.exponents[0]), float(ly.stderr[0]), t)
    t, ly = _timed(lambda: lyapunov_spectrum(  # the default: the periodic-orbit watch
        s, state0=orb.state, n_exponents=1, averaging=avg))
    out["floquet"] = (float(ly.exponents[0]), float(ly.stderr[0]), t)
    return exact, bool(orb.converged), out


def chaotic_exponents(preset, eta):
    p, x = _state(preset, eta)
    out = {}
    avg = Averaging(transient=0, min_periods=min(100, CHAOTIC_PERIODS),
                    max_periods=CHAOTIC_PERIODS, target_stderr=1e-9, align=20)
    for mode in MODES:
        t, ly = _timed(lambda mode=mode: lyapunov_spectrum(
            vi.System(p, **TOL), state0=x, n_exponents=1, averaging=avg, tangent_tol=mode,
            floquet=False))
        out[mode] = (float(ly.exponents[0]), float(ly.stderr[0]), ly.periods, t)
    return out


def main(argv=None):
    global REPORT
    out = smoke.parser(__doc__).parse_args(argv).smoke
    REPORT = smoke.moved(REPORT, out)
    smoke.shrink(globals(), out, JACOBIAN_STATES=2, PERIODIC_PERIODS=30, CHAOTIC_PERIODS=30,
                 CHAOTIC_CANDIDATES={"fig8": CHAOTIC_CANDIDATES["fig8"]},
                 PERIODIC_CANDIDATES={"fig8": PERIODIC_CANDIDATES["fig8"]})
    p0 = vi.presets.get("fig8")
    for mode in MODES:  # compile first
        lyapunov_spectrum(vi.System(p0, **TOL), n_exponents=1, tangent_tol=mode,
                          averaging=Averaging(transient=0, min_periods=2, max_periods=2,
                                              block=2, align=0))
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    lines = ["# Lyapunov exponents: the tangent vectors' error test", "",
             "Written by `python analyses/performance/lyapunov_error_control.py`; every number is "
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
    chaotic, periodic = chosen_points()
    for preset, eta in [c[:2] for c in chaotic[:1]] + [q[:2] for q in periodic[:1]]:
        err, times = jacobian_errors(preset, eta, JACOBIAN_STATES)
        for mode in MODES:
            lines.append(f"| {preset} eta = {eta} | {NAMES[mode]} | "
                         f"{np.median(err[mode]):.1e} | {err[mode].max():.1e} | "
                         f"{1e3 * times[mode]:.0f} |")
    head = " | ".join(f"tangent_tol {NAMES[m]}" for m in MODES)
    lines += ["", "## Impacting periodic orbits: largest exponent against log|mu_max| / T", "",
              "The QR route (`floquet=False`): 200 periods after 20 of alignment, from the "
              "shot orbit (Newton at rtol 1e-12); value per unit tau (standard error), "
              "time.  The orbits are the first speeds of fixed candidate lists that the "
              "preset's upward sweep labels periodic with impacts at the current defaults.  "
              "The last column is `lyapunov_spectrum`'s default, which recognises the "
              "periodic orbit and returns its Floquet exponent (a QR average splits a "
              "complex pair of multipliers):",
              "", f"| orbit | sweep's label | exact | {head} | default (Floquet watch) |",
              "| --- | --- | ---: |" + " ---: |" * (len(MODES) + 1)]
    for preset, eta, n, label in periodic:
        exact, ok, out = periodic_exponents(preset, eta, n)
        cells = " | ".join(f"{out[m][0]:.5f} ({out[m][1]:.0e}), {1e3 * out[m][2]:.0f} ms"
                           for m in (*MODES, "floquet"))
        lines.append(f"| {preset} eta = {eta:g}{'' if ok else ' (shooting failed)'} | "
                     f"{label} | {exact:.5f} | {cells} |")
    lines += ["", "## Chaotic motion: largest exponent over 600 periods", "",
              "Every setting from the same state (the trajectories part after a few "
              "periods, so the estimates are independent samples of the same exponent); "
              "value (standard error), time.  The trajectories are the first speeds of "
              "fixed candidate lists that the preset's upward sweep labels chaotic at the "
              "current defaults:", "",
              f"| trajectory | sweep's label | {head} | largest difference / combined "
              "stderr |", "| --- | --- |" + " ---: |" * len(MODES) + " ---: |"]
    speed = []
    for preset, eta, label in chaotic:
        out = chaotic_exponents(preset, eta)
        lam = {m: out[m][0] for m in MODES}
        err = {m: out[m][1] for m in MODES}
        z = max(abs(lam[a] - lam[b]) / math.hypot(err[a], err[b])
                for a in MODES for b in MODES if a < b)
        speed.append(out[1.0][3] / out[1e3][3])
        cells = " | ".join(f"{lam[m]:.4f} ({err[m]:.0e}), {out[m][3]:.2f} s" for m in MODES)
        lines.append(f"| {preset} eta = {eta:g} | {label} | {cells} | {z:.1f} |")
    if speed:
        lines += ["", f"The default (tangent_tol 1e3) runs the chaotic exponents "
                  f"{min(speed):.1f}-{max(speed):.1f}x faster than tangent_tol 1."]
    write_section(REPORT, "lyapunov-error-control", "\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
