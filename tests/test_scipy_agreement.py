"""Acceptance check: the kernel agrees with SciPy ``solve_ivp`` restarted at every switch.

Acceptance criterion: "Agreement with SciPy solve_ivp (DOP853, rtol 1e-12, restarted at
every switch) over 20 periods to 1e-8 on fig8, fig10 and rr10 states with impacts; fig11
(stick phases) to 1e-6".  The reference (:func:`vibimpact.testing.reference.solve_reference`)
shares only the model functions with the kernel; steps, error control and event location
are SciPy's.  Initial states lie on impacting attractors of the upper branch (reached from
``(1.1, 0, 0, 1.3)`` after 200 periods), and every test asserts that impacts really occur.
Besides the stroboscopic states, the impacts themselves are compared (``_same_impacts``):
each contact entry's time, angle theta = atan2(Y, X) and impact speed, ours from
``run.impacts`` against the state SciPy reaches at its located entry (event at R = 1).
"""
import numpy as np
import pytest

import vibimpact as vi
from conftest import preset
from vibimpact.testing.reference import solve_reference, strobe_times

PERIODS = 20


def _on_attractor(p, start=(1.1, 0.0, 0.0, 1.3)):
    return vi.simulate(p, periods=1, transient=200, state0=list(start)).final_state


def _compare(p, s0):
    """Kernel run, SciPy reference and the max abs strobe difference over 20 periods."""
    run = vi.simulate(p, periods=PERIODS, transient=0, state0=s0,
                      solver=vi.SolverSettings(rtol=1e-12, atol=1e-14))
    assert run.ok, run.reason
    t = strobe_times(p.eta, PERIODS)
    ref = solve_reference(p, t[-1], s0, rtol=1e-12, atol=1e-12, method="DOP853", t_eval=t)
    err = float(np.max(np.abs(run.strobe - ref.y)))
    return run, ref, err


def _same_switches(run, ref):
    """Both integrators see the same sequence of mode changes at nearly the same times."""
    term = run.events["which"] != 2
    k_modes = run.events["mode_after"][term]
    r_modes = np.array([e[3] for e in ref.events]).reshape(-1, 2)
    assert k_modes.shape == r_modes.shape
    assert np.array_equal(k_modes, r_modes)
    assert np.array_equal(run.events["which"][term], ref.event_which)
    assert np.max(np.abs(run.events["t"][term] - ref.event_times)) < 1e-6


def _same_impacts(p, s0, run, ref, tol):
    """Every contact entry (impact) of the kernel matches SciPy's located entry at R = 1.

    SciPy's entry times are the reference's contact events from free flight; its states
    there come from a second reference run that also stops at those times (stopping at an
    output time is exact, and a stop a rounding error before or after the event changes the
    state by ~1e-12).  Tolerances, from the strobe tolerance ``tol`` that bounds the
    difference of the two solutions' states (the tests assert it at the strobe times; it
    holds between them, since both are accurate to far better than ``tol`` between
    switches): the contact point lies on R = 1, where a position error eps moves the angle
    by at most eps radians, so theta agrees to ``tol`` rad; the entry time agrees to
    ``tol / |v_r|`` (a radial position error eps shifts the crossing of R = 1 by
    eps / |v_r|); the impact speed v_r = R' agrees to ``tol`` plus the radial
    acceleration (|R''| < 10 here) times that time shift.  Measured margins are 100x or
    more (differences 1e-12 ... 1e-9 against tol = 1e-8)."""
    entry = np.array([e[0] for e in ref.events if e[1] == 0 and e[2][0] == 0])
    imp = run.impacts
    assert len(imp) == entry.size, (len(imp), entry.size)
    t = strobe_times(p.eta, PERIODS)
    ref2 = solve_reference(p, t[-1], s0, rtol=1e-12, atol=1e-12, method="DOP853",
                           t_eval=np.union1d(t, entry))
    y = ref2.y[np.searchsorted(ref2.t, entry)]
    R = np.hypot(y[:, 0], y[:, 1])
    assert np.abs(R - 1.0).max() < 1e-9          # SciPy's states really are entries
    vr = (y[:, 0] * y[:, 2] + y[:, 1] * y[:, 3]) / R
    dt_tol = tol / np.abs(vr)
    assert np.all(np.abs(imp["t_entry"] - entry) <= dt_tol)
    dtheta = (imp["theta"] - np.degrees(np.arctan2(y[:, 1], y[:, 0])) + 180.0) % 360.0 - 180.0
    assert np.abs(dtheta).max() <= np.degrees(tol)
    assert np.all(np.abs(imp["v_impact"] - vr) <= tol + 10.0 * dt_tol)


@pytest.mark.parametrize("name, eta, tol", [
    ("fig8", 1.185, 1e-8),   # impacting, upper branch (chaotic at the calibrated B, Ec)
    ("fig8", 1.2, 1e-8),     # impacting, upper branch, another speed
    ("fig10", 1.2, 1e-8),    # tangential viscous damping BT: discontinuous at R = 1
    ("rr10", 1.15, 1e-8),    # Coulomb friction, shaft radius 10 (v_t > 0 throughout)
    ("fig11", 1.15, 1e-6),   # Coulomb friction, mass point
])
def test_presets_agree_with_scipy(name, eta, tol):
    """Hypothesis: on an impacting trajectory of each preset, our DOP853 (rtol 1e-12,
    atol 1e-14) and SciPy's DOP853 (rtol = atol = 1e-12, restarted at every switch) give
    the same stroboscopic states over 20 forcing periods to ``tol`` (1e-8; 1e-6 for
    fig11), with the same sequence of contact and friction switches and the same impacts
    (entry time, angle, impact speed; see ``_same_impacts``)."""
    p = preset(name).replace(eta=eta)
    s0 = _on_attractor(p)
    run, ref, err = _compare(p, s0)
    assert len(run.impacts) >= PERIODS, "the trajectory must impact"
    _same_switches(run, ref)
    _same_impacts(p, s0, run, ref, tol)
    assert err < tol, f"{name} eta={eta}: max strobe difference {err:.3e} >= {tol:g}"


def test_stick_phases_agree_with_scipy():
    """Hypothesis: with strong friction (f = 0.3) on a mass point (Rr = 0), where v_t
    reaches 0 in contact and Filippov stick phases occur, kernel and SciPy reference agree
    over 20 periods to 1e-6 and go through the same slip/stick switches, with the same
    impacts (entry time, angle, impact speed) to the same 1e-6."""
    p = preset("fig11").replace(eta=1.1, f=0.3, Rr=0.0)
    s0 = [1.05, 0.0, 0.0, 0.5]
    run, ref, err = _compare(p, s0)
    assert len(run.impacts) > 0
    mode_after = run.events["mode_after"]
    stick = (run.events["which"] == 1) & (mode_after[:, 0] == 1) & (mode_after[:, 1] == 0)
    assert stick.sum() > 0, "the case must contain stick phases"
    _same_switches(run, ref)
    _same_impacts(p, s0, run, ref, 1e-6)
    assert err < 1e-6, f"stick case: max strobe difference {err:.3e}"


def test_short_slip_reversal_agrees_with_scipy():
    """Hypothesis: a slip reversal (-1 -> +1) followed 3.7e-3 time units later by v_t = 0
    again (then stick), as at tau = 85.398 here, is integrated through; the SciPy
    reference does so and the kernel should match it to 1e-6."""
    p = preset("fig11").replace(eta=1.2, f=0.3, Rr=0.0)
    run, ref, err = _compare(p, [1.05, 0.0, 0.0, 0.5])
    assert err < 1e-6


def test_paper_code_and_the_reference_live_outside_the_core():
    """Hypothesis: vibimpact.paper (the claims) and vibimpact.testing (the reference
    solver) import from the kernel only vibimpact._kernel.boundary, and no module of the
    package core imports either of them (issue 29: paper code and the reference solver
    leave the core)."""
    import ast
    from pathlib import Path

    pkg = Path(vi.__file__).resolve().parent
    outside = ("paper", "testing")
    bad = []
    for path in pkg.rglob("*.py"):
        rel = path.relative_to(pkg)
        base = ["vibimpact", *rel.parent.parts]
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                mod = ".".join(base[:len(base) - node.level + 1] + [node.module or ""]
                               ) if node.level else node.module
                names = [f"{mod}.{a.name}".replace("..", ".") for a in node.names]
            elif isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            else:
                continue
            for full in names:
                if rel.parts[0] in outside:
                    if "._kernel" in full and not full.startswith(
                            "vibimpact._kernel.boundary"):
                        bad.append(f"{rel}: {full}")
                elif any(full.startswith(f"vibimpact.{o}") for o in outside):
                    bad.append(f"{rel}: {full}")
    assert not bad, bad
