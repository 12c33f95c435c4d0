"""Accuracy of the simulation kernel against known solutions and invariants."""
import numpy as np
import pytest

import vibimpact as vi
from vibimpact._kernel.rotor import energy


def test_linear_case_matches_closed_form_steady_state():
    """With k3 = 0 and no contact, eq. (5) is a damped forced linear oscillator; after the
    transient the strobe equals its closed-form steady state to 1e-9."""
    p = vi.Params(k3=0.0, Ec=0.1, eta=0.5, G=0.3, B=0.1)
    a = p.Ec * p.eta ** 2 / (1.0 - p.eta ** 2 + 1j * p.B * p.eta)
    steady = np.array([a.real, a.imag + p.G, (1j * p.eta * a).real, (1j * p.eta * a).imag])
    run = vi.simulate(p, periods=20, transient=100)
    assert run.ok and len(run.impacts) == 0
    assert np.abs(run.strobe - steady).max() < 1e-9


def test_energy_is_conserved_through_1000_contacts():
    """Without damping, forcing and weight the Hertz contact is conservative: the energy
    1/2|v|^2 + 1/2 R^2 + 1/4 k3 R^4 + 2/5 kh (R-1)^(5/2) H(R-1) drifts < 1e-9 relative
    over more than 1,000 contacts."""
    p = vi.Params(B=0.0, Bh=0.0, BT=0.0, f=0.0, Ec=0.0, G=0.0, kh=120.0, eta=1.0)
    run = vi.simulate(p, periods=340, state0=[0.0, 0.0, 1.3, 0.4],
                      dense=4, solver=vi.SolverSettings(rtol=1e-13, atol=1e-15))
    assert run.ok
    assert len(run.impacts) >= 1000
    pa = p.as_array()
    e = np.array([energy(s, pa) for s in run.dense])
    assert np.abs(e - e[0]).max() / e[0] < 1e-9


def test_every_contact_entry_lies_on_the_retainer_circle(contact_case):
    """Event location refines every contact entry and exit to |R - 1| < 1e-10."""
    p, s0, ref = contact_case
    for method in ("dop853", "dp5", "rk4"):
        run = vi.simulate(p, periods=4, state0=s0,
                          solver=vi.SolverSettings(method=method))
        sw = run.events["state"][run.events["which"] == 0]
        assert len(sw) >= 10
        assert np.abs(np.hypot(sw[:, 0], sw[:, 1]) - 1.0).max() < 1e-10


def test_impact_records_are_consistent(contact_case):
    """Impact records: entries move outwards (v_impact > 0), exits follow entries, the
    penetration is positive and the angle is the angle of the entry state."""
    p, s0, ref = contact_case
    imp = ref.impacts
    assert len(imp) == 7
    assert np.all(imp["v_impact"] > 0.0)
    assert np.all(imp["penetration"] > 0.0)
    done = ~np.isnan(imp["t_exit"])
    assert np.all(imp["duration"][done] > 0.0)
    ent = ref.events["state"][(ref.events["which"] == 0) & (ref.events["mode_before"][:, 0] == 0)]
    np.testing.assert_allclose(imp["theta"], np.degrees(np.arctan2(ent[:, 1], ent[:, 0])))


def _slope(x, y):
    return np.polyfit(np.log(x), np.log(y), 1)[0]


def test_rk4_converges_at_fourth_order_across_contacts(contact_case):
    """Fixed-step RK4 restarted at every switch, with steps graded next to the contact
    surface, converges at order >= 3.5 (nominal 4) on a contact trajectory with BT = 0.05;
    stepping blindly across the switch would give order 1."""
    p, s0, ref = contact_case
    ns = [400, 800, 1600, 3200]
    err = [np.abs(vi.simulate(p, periods=4, state0=s0, solver=vi.SolverSettings(
        method="rk4", steps_per_period=n)).strobe - ref.strobe).max() for n in ns]
    order = -_slope(ns, err)
    assert 3.5 <= order <= 4.5, order


def test_adaptive_methods_keep_their_order_across_contacts(contact_case):
    """Error against work (RHS evaluations) of the adaptive pairs on the same trajectory:
    DP5 at least order 4.5; DOP853 at least order 7.5.  (The slope may exceed the order:
    the steps at the contacts' ends, sized by the h^(5/2) law of the Hertz force, take a
    smaller share of the work at tighter tolerances.)"""
    p, s0, ref = contact_case
    tols = [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11]
    for method, lo, hi in (("dp5", 4.5, np.inf), ("dop853", 7.5, np.inf)):
        work, err = [], []
        for tol in tols:
            run = vi.simulate(p, periods=4, state0=s0,
                              solver=vi.SolverSettings(method=method, rtol=tol, atol=tol))
            work.append(run.counters["rhs_evals"])
            err.append(np.abs(run.strobe - ref.strobe).max())
        order = -_slope(work, err)
        assert lo <= order <= hi, (method, order)


@pytest.mark.parametrize("method, bound", [("dp5", 45.0), ("dop853", 15.0)])
def test_global_error_stays_proportional_to_tolerance_across_contacts(contact_case, method,
                                                                      bound):
    """Hypothesis: with the steps at the contacts' ends sized from the method's error
    constants there (the Hertz force's h^(5/2) law; the embedded estimate under-reports
    those steps' error, by up to 180x at an exit inside a step), the strobe error over 7
    contacts stays within a fixed multiple of the tolerance at every tolerance from 1e-6
    to 1e-11: 15 for DOP853, 45 for DP5 (more steps, more accumulated local error).  With
    the steps found by the error estimate alone the worst ratios were 51 and 87."""
    p, s0, ref = contact_case
    ratios = [np.abs(vi.simulate(p, periods=4, state0=s0, solver=vi.SolverSettings(
        method=method, rtol=tol, atol=tol)).strobe - ref.strobe).max() / tol
              for tol in (1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11)]
    assert max(ratios) < bound, (method, ratios)


def test_error_is_proportional_to_tolerance(contact_case):
    """Tolerance proportionality: lowering rtol by 1e4 lowers the DOP853 error by >= 1e3."""
    p, s0, ref = contact_case
    e = [np.abs(vi.simulate(p, periods=4, state0=s0,
                            solver=vi.SolverSettings(rtol=t, atol=t)).strobe
                - ref.strobe).max() for t in (1e-7, 1e-11)]
    assert e[1] < e[0] / 1e3


def test_duffing_linear_limit_matches_closed_form():
    """With beta = 0 the Duffing model is linear: strobe equals the closed-form steady
    state to 1e-9."""
    p = vi.DuffingParams(delta=0.2, alpha=1.0, beta=0.0, gamma=0.3, omega=1.4)
    a = p.gamma / (p.alpha - p.omega ** 2 + 1j * p.delta * p.omega)
    run = vi.simulate(p, periods=10, transient=80)
    np.testing.assert_allclose(run.strobe[:, 0], a.real, atol=1e-9)
    np.testing.assert_allclose(run.strobe[:, 1], (1j * p.omega * a).real, atol=1e-9)


def test_duffing_amplitude_matches_harmonic_balance():
    """Weakly nonlinear Duffing oscillator: the periodic amplitude satisfies the
    harmonic-balance frequency response [(alpha - w^2) a + 3/4 beta a^3]^2 + (delta w a)^2
    = gamma^2 (Nayfeh & Mook, Nonlinear Oscillations, 1979, sec. 4.1) to 0.5 %."""
    p = vi.DuffingParams(delta=0.1, alpha=1.0, beta=0.05, gamma=0.1, omega=0.8)
    run = vi.simulate(p, periods=5, transient=200)
    maxima = run.events["state"][run.events["which"] == 0, 0]
    amp = maxima.max()
    w = p.omega
    resid = ((p.alpha - w ** 2) * amp + 0.75 * p.beta * amp ** 3) ** 2 \
        + (p.delta * w * amp) ** 2 - p.gamma ** 2
    # relative error in amplitude: d(resid)/d(amp) * da = resid
    da = abs(resid) / abs(2 * ((p.alpha - w ** 2) * amp + 0.75 * p.beta * amp ** 3)
                         * ((p.alpha - w ** 2) + 2.25 * p.beta * amp ** 2)
                         + 2 * (p.delta * w) ** 2 * amp)
    assert da / amp < 5e-3
    assert 0.1 < amp < 1.0



def test_a_stable_impacting_orbit_is_found_periodic_within_the_transient():
    """On a stable impacting P1 orbit (fig8, eta = 1.13, |mu|max about 0.82) the sweep's
    10-period integrations repeat their step sequences, so the strobe points repeat to
    the period test's tolerance long before the 200-period cap.  A step-size rule that
    carried step sizes from contact event to contact event (tried, reverted) broke this:
    the point ran the whole transient and was labelled 'periodic (long period)'.  Pinned
    to B = 0.07, Ec = 0.11 (the defaults when written), where the orbit contracts that
    fast."""
    p = vi.presets.get("fig8").replace(B=0.07, Ec=0.11)
    ds = vi.sweep(p, [1.12, 1.125, 1.13], execution=vi.Execution(workers=1))
    assert ds.label.values[-1] == "P1, 2 impacts, 2 small arcs"
    assert int(ds.transient.values[-1]) <= 60


def test_stable_impacting_orbit_repeats_at_the_sweeps_tolerance():
    """Hypothesis: on a stable impacting period-1 orbit (fig8, eta = 1.085, |mu| = 0.82,
    two contacts per period) the stroboscopic points of a run at the sweep's tolerances
    (rtol 1e-8) repeat to 2e-7 of the orbit's size, well inside the period test's 1e-6:
    the step-size control across the contacts must not trade this accuracy for speed.
    (Two step-control shortcuts at the contact switches cut the RHS evaluations by 20 %
    but let these points scatter by 1.6e-6 and 9e-6 of the orbit's size, so the sweep
    stopped finding the period; they were reverted.)  Pinned to B = 0.07, Ec = 0.11, the
    defaults when written."""
    from vibimpact.analysis import shoot_periodic_orbit
    from vibimpact.sweeps import continued_state

    p = vi.presets.get("fig8").replace(eta=1.085, B=0.07, Ec=0.11)
    orb = shoot_periodic_orbit(vi.System(p), continued_state(p, 1.085), 1)
    assert orb.converged and orb.minimal_period == 1 and orb.abs_max < 0.9
    run = vi.simulate(p, periods=30, state0=orb.state,
                      solver=vi.SolverSettings(rtol=1e-8, atol=1e-11))
    assert run.ok and len(run.impacts) == 60
    scale = np.abs(run.strobe).max()
    assert np.ptp(run.strobe, axis=0).max() < 2e-7 * scale
