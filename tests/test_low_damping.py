"""Known truths of the low-damping regime (passive magnetic bearings, B -> 0).

At low damping an impactless motion is a weakly nonlinear, harmonically forced oscillator:
its attractor is the forced period-1 orbit, and the free oscillation of the transient
decays like ``exp(-B tau / 2)`` -- hundreds to thousands of forcing periods, far past the
sweep's 200-period transient.  At ``B = 0`` exactly it never decays: the motion is
quasi-periodic.  The labels must be right on both sides without a blanket longer
transient.
"""
import math

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.analysis import shoot_periodic_orbit
from vibimpact.analysis.settling import contraction_rate
from vibimpact.points.point import REGIME_CODES, SweepSettings
from vibimpact.analysis.classify import Label

ETA = np.round(np.arange(1.30, 1.50 + 1e-9, 0.01), 6)  # 21 speeds above resonance
#: kh = 10 without gravity, and kh = 120 with gravity along +Y
PRESETS = ("fig4", "fig10")
P1, QP, UNSETTLED = (REGIME_CODES[k] for k in (Label.PERIODIC, Label.QUASIPERIODIC,
                                               Label.UNSETTLED))


@pytest.mark.parametrize("preset", PRESETS)
def test_undamped_impactless_motion_is_quasi_periodic_at_every_eta(preset):
    """Hypothesis: at B = 0 with no impacts the free oscillation never decays, so at every
    one of 21 speeds the motion is quasi-periodic (exponent zero, 0-1 test regular,
    Poincaré points that neither contract nor stop recurring), never periodic or
    unsettled."""
    p = vi.presets.get(preset).replace(B=0.0, Ec=0.05)
    ds = vi.sweep(p, ETA, analyses=("period", "impacts", "lyapunov", "test01"))
    assert np.all(ds.impacts_per_period.values == 0.0)
    assert np.all(ds.regime.values == QP), list(ds.label.values)
    assert np.all(np.abs(ds.lyapunov.values) < 1e-3)


@pytest.mark.parametrize("B", [0.001, 0.002, 0.005])
@pytest.mark.parametrize("preset", PRESETS)
def test_weakly_damped_impactless_motion_is_period_one_at_every_eta(preset, B):
    """Hypothesis: at B = 0.001, 0.002, 0.005 with no impacts the attractor is the forced
    period-1 orbit at every one of 21 speeds; its Floquet exponent is -B/2 to 1e-6 (the
    support's uniform damping B I is the only dissipation of the impactless motion, so
    every exponent of the otherwise conservative system is exactly -B/2: Dressler's
    pairing rule), and the label is bought by evidence within the
    transient budget, not by a longer transient: the free oscillation would need more
    periods than the budget to decay below the period test's tolerance, and shooting (or
    an extrapolation jump or the continuation's predictor, both checked by the orbit's
    multipliers) decided it within the budget."""
    p = vi.presets.get(preset).replace(B=B, Ec=0.05)
    st = SweepSettings()
    ds = vi.sweep(p, ETA, analyses=("period", "impacts", "floquet"))
    assert np.all(ds.impacts_per_period.values == 0.0)
    assert np.all(ds.regime.values == P1) and np.all(ds.period.values == 1), \
        list(ds.label.values)
    np.testing.assert_allclose(ds.floquet_exponent.values, -B / 2, rtol=1e-6)
    assert np.all(ds.transient.values <= st.transient_max + st.record)
    slow = np.log(st.rule.period_tol) / (-B / 2 * 2 * np.pi / ETA) > st.transient_max
    assert np.all(slow) and np.any(np.isfinite(ds.shoot_residual.values))
    shot = np.isfinite(ds.shoot_residual.values)
    assert np.all(ds.orbit_distance.values[shot] < 1.0)


def test_the_reported_low_damping_example_is_period_one_everywhere():
    """Hypothesis: the reported case (fig10, B = 0.002, Ec = 0.05, eta from 1.5 down to 1.3,
    step 0.01), once labelled 'quasi-periodic impactless' at all 21 points, is P1
    impactless at every point, as the CLI prints it."""
    p = vi.presets.get("fig10").replace(B=0.002, Ec=0.05)
    ds = vi.sweep(p, ETA, direction="down")
    assert set(ds.label.values.ravel()) == {"P1 impactless"}


def test_a_contracting_motion_without_shooting_is_unsettled_with_its_rate():
    """Hypothesis: with shooting turned off, a slowly contracting impactless transient at
    B = 0.002 is not labelled by default but UNSETTLED, with the measured contraction rate
    (the free oscillation's -B T / 2 per forcing period, within 5 %) and the periods it
    would still need (more than its budget)."""
    B, eta = 0.002, 1.4
    p = vi.presets.get("fig10").replace(B=B, Ec=0.05)
    st = SweepSettings(shoot=0, extrapolate=0)
    ds = vi.sweep(p, [eta], analyses=("period", "impacts"), settings=st)
    assert int(ds.regime.values[0]) == UNSETTLED
    rate = -B / 2 * 2 * np.pi / eta
    assert abs(float(ds.contraction.values[0]) / rate - 1.0) < 0.15
    assert float(ds.settle_periods.values[0]) > st.transient_max
    assert "would need" in str(ds.reason.values[0])


CASES = {  # preset, B, Ec: an impacting period-1 branch reached by continuation
    "fig8": (0.005, 0.05),
    "fig10": (0.01, 0.05),
}


@pytest.fixture(scope="module", params=sorted(CASES))
def impacting_branch(request):
    preset = request.param
    B, Ec = CASES[preset]
    p = vi.presets.get(preset).replace(B=B, Ec=Ec)
    eta = np.round(np.arange(1.0, 1.19 + 1e-9, 0.005), 6)
    ds = vi.sweep(p, eta, analyses=("period", "impacts", "floquet"),
                  continuation=vi.Continuation(blocks=1))
    return p, ds.sel(eta=slice(1.06, None))


def test_impacting_periodic_orbits_at_low_damping_are_labelled_with_their_period(
        impacting_branch):
    """Hypothesis: on the impacting period-1 branch (two impacts per period) at B <= 0.01,
    reached by continuation, every one of >= 20 speeds is labelled P1, and the orbit is an
    attractor by an independent computation: Newton shooting from the sweep's final state
    converges to a period-1 orbit with every |mu| < 1, whose |mu|max the sweep stored."""
    p, ds = impacting_branch
    assert ds.eta.size >= 20
    assert np.all(ds.period.values == 1) and np.all(ds.regime.values == P1), \
        list(zip(ds.eta.values, ds.label.values))
    assert np.all(ds.impacts_per_period.values == 2.0)
    for e, x, amax in zip(ds.eta.values, ds.final_state.values, ds.floquet_abs_max.values):
        orb = shoot_periodic_orbit(vi.System(p.replace(eta=float(e)), rtol=1e-10), x, 1,
                                   tol=1e-10)
        assert orb.converged and orb.minimal_period == 1 and orb.abs_max < 1.0
        assert abs(orb.abs_max - amax) < 1e-4
        assert np.abs(orb.state - x).max() < 1e-4


def test_impacting_orbits_multipliers_match_a_long_run(impacting_branch):
    """Hypothesis: the shooting's leading multiplier is what a long run sees: from the
    orbit's point pushed off by 1e-4, 600 periods of plain integration return to the orbit
    at the rate ln|mu|max per period (within 5 %, measured on the run's stroboscopic
    steps), and ends closer to the orbit than |mu|max^300 times the offset, at three speeds
    of the branch."""
    p, ds = impacting_branch
    for k in (0, ds.eta.size // 2, ds.eta.size - 1):
        pe = p.replace(eta=float(ds.eta.values[k]))
        orb = shoot_periodic_orbit(vi.System(pe, rtol=1e-11, atol=1e-13),
                                   ds.final_state.values[k], 1, tol=1e-11)
        run = vi.simulate(pe, periods=600, state0=orb.state + 1e-4,
                          solver=vi.SolverSettings(rtol=1e-11, atol=1e-13))
        c = contraction_rate(run.strobe[:400], 1)
        assert c is not None and c.contracting
        assert abs(c.rate / math.log(orb.abs_max) - 1.0) < 0.05
        assert np.abs(run.strobe[-1] - orb.state).max() < 1e-4 * orb.abs_max ** 300


def test_every_label_carries_its_evidence_at_low_damping():
    """Hypothesis: no label is a default.  On a low-damping fig8 sweep (B = 0.005, the
    shipped Ec, 61 speeds, all analysers) every periodic point has its period (no
    'periodic (long period)' without a recurrence found), every chaotic point a positive
    exponent beyond its error and the zero band, every quasi-periodic point an exponent in
    the zero band and Poincaré points that do not contract, and every unsettled point a
    reason."""
    from vibimpact.analysis.settling import FLOOR

    p = vi.presets.get("fig8").replace(B=0.005)
    st = SweepSettings()
    rule = st.rule
    eta = np.round(np.arange(0.9, 1.5 + 1e-9, 0.01), 6)
    ds = vi.sweep(p, eta)
    reg, per = ds.regime.values, ds.period.values
    T = 2 * np.pi / eta
    lam, err = ds.lyapunov.values * T, ds.lyapunov_err.values * T
    assert np.all(per[reg == P1] > 0)
    ch = reg == REGIME_CODES[Label.CHAOTIC]
    assert np.all(lam[ch] - rule.z * err[ch] > rule.zero)
    qp = reg == QP
    assert np.all(np.abs(lam[qp]) - rule.z * err[qp] <= rule.zero)
    assert np.all(~(ds.contraction.values[qp] < -FLOOR))
    assert all(str(r) for r in ds.reason.values[reg == UNSETTLED])
    assert set(np.unique(reg)) <= {P1, QP, UNSETTLED, REGIME_CODES[Label.CHAOTIC]}


def test_points_that_repeat_only_because_they_move_slowly_have_not_settled():
    """Hypothesis: the 'has it settled?' test scales with the contraction.  Points
    approaching their limit geometrically with steps below the period test's tolerance
    (1e-6 of their scale) repeat to it, yet at |mu| = 0.999 the geometric tail of those
    steps, step mu / (1 - mu), is 1000 times longer: not settled.  At |mu| = 0.5 the same
    steps leave a tail within the tolerance: settled."""
    from vibimpact.points.settle import unsettled_repeat

    k = np.arange(150)[:, None]
    limit = np.array([[0.8, -0.1, 0.3, 0.9]])
    direction = np.array([[1.0, 0.5, -0.3, 0.2]])
    for mu, settled in ((0.999, False), (0.5, True)):
        step = 5e-8 / (1.0 - mu)            # first step: 5e-8 of the unit scale
        z = limit + step * mu ** k * direction
        assert np.abs(np.diff(z, axis=0)).max() < 1e-6  # repeats to the tolerance
        con = unsettled_repeat(z, 1, 1e-6)
        assert (con is None) is settled
        if con is not None:
            assert abs(con.multiplier - mu) < 1e-6
            assert con.distance > 1e-6 * con.scale
