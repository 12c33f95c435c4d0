"""The classifier: each label from the case it is meant for, the rule's branches, and the
rotor inside and outside the paper's chaotic interval."""
import math

import numpy as np
import pytest

import vibimpact as vi
from conftest import preset
from vibimpact.analysis import Label, Regime, classify
from vibimpact.points import classify_params
from vibimpact.analysis.classify import decide


def _logistic(n=1000, r=4.0, x=0.3):
    out = np.empty(n)
    for _ in range(100):
        x = r * x * (1 - x)
    for k in range(n):
        x = r * x * (1 - x)
        out[k] = x
    return out


@pytest.mark.parametrize("n", [1, 2, 3, 7, 16])
def test_periodic_sequence_is_labelled_periodic_with_its_period(n):
    """A period-n orbit (4-D points, noise 1e-9) is PERIODIC with that n, confidence 1."""
    rng = np.random.default_rng(n)
    pts = np.tile(rng.normal(size=(n, 4)), (300 // n + 1, 1))[:300]
    pts = pts + 1e-9 * rng.normal(size=pts.shape)
    reg = classify(pts)
    assert reg.label is Regime.PERIODIC and reg.n == n and reg.confidence == 1.0


def test_golden_rotation_is_quasiperiodic():
    """A circle rotation by the golden ratio has no period and K ~ 0: QUASIPERIODIC."""
    k = np.arange(1000)
    ang = 2 * np.pi * k * (math.sqrt(5) - 1) / 2
    reg = classify(np.column_stack([np.cos(ang), np.sin(ang)]))
    assert reg.label is Regime.QUASIPERIODIC and reg.k01 < 0.1


def test_logistic_map_is_chaotic_by_k_alone_and_with_its_exponent():
    """The logistic map at r = 4 is CHAOTIC from the 0-1 test alone, and with its exponent
    ln 2 (and a small error) the label is confirmed with full confidence."""
    x = _logistic()
    assert classify(x).label is Regime.CHAOTIC
    reg = classify(x, lyapunov=math.log(2), lyapunov_err=0.01)
    assert reg.label is Regime.CHAOTIC and reg.confidence == 1.0


def test_henon_points_with_positive_exponent_are_chaotic():
    """The Hénon attractor (exponent 0.419) is CHAOTIC."""
    x, y = 0.1, 0.1
    pts = np.empty((1000, 2))
    for k in range(1100):
        x, y = 1 - 1.4 * x * x + y, 0.3 * x
        if k >= 100:
            pts[k - 100] = x, y
    reg = classify(pts, lyapunov=0.419, lyapunov_err=0.005)
    assert reg.label is Regime.CHAOTIC


@pytest.mark.parametrize("lam, err, k01, torus, label", [
    (-0.05, 0.001, math.nan, None, Label.UNSETTLED),      # attracting, no period found
    (0.0005, 0.001, 0.02, None, Label.QUASIPERIODIC),     # zero band, regular K
    (0.0005, 0.001, 0.02, True, Label.QUASIPERIODIC),     # ... on a torus
    (0.0005, 0.001, 0.02, False, Label.UNSETTLED),        # ... but the points contract
    (0.0005, 0.001, 0.95, None, Label.UNSETTLED),         # zero band, chaotic K
    (0.2, 0.01, 0.95, None, Label.CHAOTIC),               # clearly positive
    (0.2, 0.1, 0.02, None, Label.QUASIPERIODIC),          # positive but not significant
    (math.nan, math.nan, 0.9, None, Label.CHAOTIC),       # K only
    (math.nan, math.nan, 0.1, False, Label.UNSETTLED),    # K only, contracting points
    (math.nan, math.nan, math.nan, None, Label.UNSETTLED),  # no test at all
])
def test_decision_rule_branches(lam, err, k01, torus, label):
    """Without a detected period the rule decides from the exponent per period, its error,
    K and the torus evidence, as documented in DecisionRule: every label needs positive
    evidence, and what none decides is UNSETTLED, never a guess."""
    got, got_n, conf, _ = decide(0, lam, err, k01, torus=torus)
    assert got is label and got_n == 0 and 0.0 <= conf <= 1.0
    if label is Label.UNSETTLED:
        assert conf == 0.0


def test_period_beats_noisy_exponent_but_contradiction_lowers_confidence():
    """A detected period gives PERIODIC; a significantly positive exponent next to it
    halves the confidence instead of being ignored."""
    assert decide(2, -0.1, 0.001, math.nan)[2] == 1.0
    assert decide(2, 0.1, 0.001, math.nan)[2] == 0.5


def test_divergence_is_labelled_diverged():
    """Non-finite points or a diverged run are DIVERGED, never classified as motion."""
    assert classify(np.array([[0.0], [np.nan], [1.0]])).label is Regime.DIVERGED
    assert classify(np.zeros((10, 2)), diverged=True).label is Regime.DIVERGED
    p = vi.DuffingParams(delta=0.1, alpha=1.0, beta=-1.0, gamma=5.0, omega=1.0)
    reg, _ = classify_params(vi.System(p), transient_max=10, record=20)
    assert reg.label is Regime.DIVERGED


def test_ueda_oscillator_is_chaotic_and_damped_oscillator_periodic():
    """The Duffing model through classify_params: Ueda's chaotic regime is CHAOTIC with a
    positive exponent; a weakly forced linear oscillator is P1."""
    ueda = vi.DuffingParams(delta=0.05, alpha=0.0, beta=1.0, gamma=7.5, omega=1.0)
    reg, _ = classify_params(vi.System(ueda), state0=[2.5, 0.0], transient_max=100,
                             record=300)
    assert reg.label is Regime.CHAOTIC and reg.lyapunov > 0.05
    lin = vi.DuffingParams(delta=0.3, alpha=1.0, beta=0.0, gamma=0.2, omega=1.3)
    reg, _ = classify_params(vi.System(lin), transient_max=200, record=100)
    assert reg.label is Regime.PERIODIC and reg.n == 1


def test_pinned_fig8_chaotic_point_is_chaotic(fig8_chaotic):
    """At the tests' pinned configuration (conftest.MEASURED_AT, not the shipped defaults:
    what the shipped defaults give is tested against the paper's claims in
    test_shipped_defaults.py), fig8 at eta = 1.22 on the impacting branch is CHAOTIC,
    impacting, with a significantly positive exponent."""
    p, x = fig8_chaotic
    reg, run = classify_params(vi.System(p), state0=x, transient_max=100, record=300)
    assert reg.label is Regime.CHAOTIC and reg.impacting
    assert reg.lyapunov > 3 * reg.lyapunov_err


def test_pinned_fig8_impacting_orbit_is_p1_with_two_impacts():
    """At the pinned configuration (conftest.MEASURED_AT), fig8 at eta = 1.10 on the
    impacting branch (an orbit with two bottom impacts, like the paper's A and B): P1 with
    2 impacts per period, no exponent needed."""
    from conftest import continued_state, preset
    p = preset("fig8").replace(eta=1.10)
    reg, _ = classify_params(vi.System(p), state0=continued_state("fig8", 1.10),
                             transient_max=100, record=100)
    assert reg.label is Regime.PERIODIC and reg.n == 1
    assert reg.impacting and reg.impacts_per_period == 2.0
    assert math.isnan(reg.lyapunov)  # proven periodic: the exponent was skipped
    assert str(reg) == "P1, 2 impacts"


def test_bad_arguments_raise_value_error_naming_them():
    """Invalid input raises ValueError naming the argument."""
    with pytest.raises(ValueError, match="points"):
        classify(np.zeros((1, 2)))
    with pytest.raises(ValueError, match="period"):
        classify(np.zeros((10, 2)), period=-1.0)
    with pytest.raises(ValueError, match="lyapunov"):
        classify_params(vi.System(preset("fig8")), lyapunov="maybe")
    with pytest.raises(ValueError, match="system"):
        classify_params(preset("fig8"))
    with pytest.raises(ValueError, match="periods"):
        classify_params(vi.System(preset("fig8")), periods=10)
