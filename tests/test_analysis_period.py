"""detect_period on synthetic Poincare sequences with known answers, the two sections of a
run, and the fig8 rotor at eta = 1.185 (paper: two bottom impacts A, B per period)."""
import numpy as np
import pytest

import vibimpact as vi
from conftest import preset
from vibimpact.analysis.impacts import contact_arcs, impact_count
from vibimpact.analysis.period import detect_period, impact_map, poincare_section

GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0


def periodic_orbit(n, repeats=4, d=4, noise=1e-9, seed=0):
    """A period-n sequence of random points in [-1, 1]^d (successive points distinct),
    repeated, plus Gaussian noise."""
    rng = np.random.default_rng(seed + n)
    orbit = rng.uniform(-1.0, 1.0, size=(n, d))
    x = np.tile(orbit, (repeats, 1))
    x = np.vstack([x, orbit[:1]])                      # repeats * n + 1 points
    return x + noise * rng.standard_normal(x.shape)


def logistic(m, x0=0.3, r=4.0, transient=1000):
    x = x0
    for _ in range(transient):
        x = r * x * (1.0 - x)
    out = np.empty(m)
    for k in range(m):
        x = r * x * (1.0 - x)
        out[k] = x
    return out


@pytest.mark.parametrize("n", range(1, 65))
def test_noisy_periodic_sequences_of_period_1_to_64_are_found_exactly(n):
    """A period-n orbit of random points in R^4 with 1e-9 noise, 4 repetitions, has period
    exactly n (not a multiple, not 0) for every n = 1..64."""
    assert detect_period(periodic_orbit(n), tol=1e-6, max_period=64) == n


def test_period_needs_min_repeats_full_repetitions():
    """A period is only accepted when the window holds min_repeats * n + 1 points."""
    x = periodic_orbit(5, repeats=3)                  # 16 points = 3 * 5 + 1
    assert detect_period(x) == 5
    assert detect_period(x[:-1]) == 0
    assert detect_period(x[:-1], min_repeats=2) == 5


def test_period_above_max_period_gives_zero():
    """A period-10 orbit is not found when max_period is 9."""
    assert detect_period(periodic_orbit(10), max_period=9) == 0


def test_exact_fixed_point_and_one_dimensional_input_give_period_one():
    """A constant sequence (size 0, even at the origin) is period 1; (m,) arrays are d = 1."""
    assert detect_period(np.zeros((10, 4))) == 1
    assert detect_period(np.full(10, 3.5)) == 1
    assert detect_period(np.tile([0.1, 0.7], 8)) == 2


def test_fixed_point_with_integration_noise_is_period_one():
    """Noise of relative size 1e-9 around a fixed point far from 0 is below tol: period 1."""
    rng = np.random.default_rng(3)
    x = np.array([0.3, -0.8, 0.1, 0.5]) + 1e-9 * rng.standard_normal((61, 4))
    assert detect_period(x, tol=1e-6) == 1


def test_geometric_transient_toward_fixed_point_is_not_periodic():
    """x_k = 0.9^k a converges to a fixed point, but its first steps exceed tol: 0."""
    a = np.array([1.0, -0.5, 0.3, 0.2])
    x = 0.9 ** np.arange(200)[:, None] * a
    assert detect_period(x, tol=1e-6) == 0


def test_golden_ratio_circle_rotation_is_not_periodic():
    """A quasi-periodic rotation by the golden ratio never returns within tol: 0."""
    phase = 2.0 * np.pi * GOLDEN * np.arange(1000)
    assert detect_period(np.column_stack([np.cos(phase), np.sin(phase)])) == 0


def test_logistic_map_at_r4_is_not_periodic():
    """The chaotic logistic map at r = 4 has no period <= 64: 0."""
    assert detect_period(logistic(1000)) == 0


@pytest.mark.parametrize("kwargs,name", [
    (dict(points=[[0.0, np.nan]] * 10), "points"),
    (dict(points=[1.0, np.inf, 2.0]), "points"),
    (dict(points=np.zeros((3, 2, 2))), "points"),
    (dict(points=np.zeros(10), tol=0.0), "tol"),
    (dict(points=np.zeros(10), tol=-1e-6), "tol"),
    (dict(points=np.zeros(10), max_period=0), "max_period"),
    (dict(points=np.zeros(10), max_period=2.5), "max_period"),
    (dict(points=np.zeros(10), min_repeats=0), "min_repeats"),
    (dict(points=np.zeros(10), scale=-1.0), "scale"),
])
def test_bad_detect_period_input_raises_value_error_naming_argument(kwargs, name):
    """Invalid points, tol, max_period, min_repeats or scale raise ValueError naming it."""
    with pytest.raises(ValueError, match=name):
        detect_period(**kwargs)


class _FakeRun:
    """Only the attributes the sections read."""

    def __init__(self, strobe, events):
        self.strobe = strobe
        self.events = events


def test_impact_map_keeps_only_contact_entries():
    """Only events with which == 0 going from free flight (mode 0) into contact (mode 1)
    are impacts; exits and other switches are dropped; a section is a copy."""
    state = np.arange(20.0).reshape(5, 4)
    events = dict(t=np.arange(5.0), which=np.array([0, 0, 2, 0, 1]),
                  mode_before=np.array([[0, 0], [1, 0], [1, 0], [0, 0], [1, 0]]),
                  mode_after=np.array([[1, 0], [0, 0], [1, 0], [1, 0], [1, 1]]), state=state)
    run = _FakeRun(np.ones((3, 4)), events)
    np.testing.assert_array_equal(impact_map(run), state[[0, 3]])
    section = poincare_section(run)
    section[0, 0] = 5.0
    assert run.strobe[0, 0] == 1.0


def test_sections_without_impacts_have_shape_0_by_4():
    """No events (or an empty log) gives an empty (0, 4) impact map."""
    empty = dict(t=np.zeros(0), which=np.zeros(0, int), mode_before=np.zeros((0, 2), int),
                 mode_after=np.zeros((0, 2), int), state=np.zeros((0, 4)))
    assert impact_map(_FakeRun(np.ones((3, 4)), empty)).shape == (0, 4)
    assert impact_map(_FakeRun(np.ones((3, 4)), {})).shape == (0, 4)
    assert poincare_section(_FakeRun(np.zeros((0, 4)), {})).shape == (0, 4)


@pytest.fixture(scope="module")
def fig8_1185():
    """fig8 at eta = 1.185 from rest, and from a state on the impacting branch."""
    p = preset("fig8").replace(eta=1.185)
    rest = vi.simulate(p, periods=60, transient=400)
    upper = vi.simulate(p, periods=60, transient=400, state0=[1.0, 0.0, 0.0, 1.185])
    return rest, upper


def test_fig8_at_1185_from_rest_is_impactless_period_one(fig8_1185):
    """At the pinned configuration (conftest.MEASURED_AT), fig8 at eta = 1.185 started
    from rest settles on the lower, impactless branch: a period-1 orbit (the rotor never
    reaches the retainer)."""
    rest, _ = fig8_1185
    assert rest.ok
    assert detect_period(poincare_section(rest), tol=1e-6) == 1
    assert rest.impacts.size == 0 and impact_map(rest).shape == (0, 4)


def test_fig8_at_1185_upper_branch_is_period_one_with_two_bottom_impacts(fig8_1185):
    """At the pinned configuration (conftest.MEASURED_AT), fig8 at eta = 1.185 on the
    impacting branch is period 1 with two impacts per period at two fixed points of the
    bottom half (the paper's A and B; whether the shipped defaults reproduce them is
    tested in test_shipped_defaults.py)."""
    _, run = fig8_1185
    assert run.ok
    n = detect_period(poincare_section(run), tol=1e-6)
    assert n == 1
    count = impact_count(run.impacts["period"], len(run.strobe) - 1, period=n)
    assert count.constant and count.per_period == 2
    states = impact_map(run)
    theta = np.degrees(np.arctan2(states[:, 1], states[:, 0]))
    np.testing.assert_allclose(theta, run.impacts["theta"], atol=1e-9)
    assert np.all((theta > 0.0) & (theta < 180.0))
    arcs = contact_arcs(theta)
    assert arcs.summary == "2 small arcs"
    assert np.all(arcs.width < 1e-3)


def test_spiral_transient_turning_a_third_per_sample_is_not_period_3():
    """A transient spiralling into a fixed point while turning by ~1/3 turn per sample
    returns within the tolerance every 3 samples before it has converged; it must give 0
    (not converged), and the converged fixed point then gives 1 (found in fig10 with
    B = 0.05 at eta = 1.47, where the free rotation per forcing period is ~240 degrees)."""
    k = np.arange(40)
    q = 0.9 * np.exp(1j * (2 * np.pi / 3 + 0.01))
    z = 1.0 + 3e-6 * q ** k
    pts = np.c_[z.real, z.imag]
    assert np.max(np.abs(pts[3:] - pts[:-3])) <= 1e-6          # period 3 "fits" ...
    assert detect_period(pts, tol=1e-6) == 0                    # ... but is refused
    z = 1.0 + 3e-12 * q ** k
    assert detect_period(np.c_[z.real, z.imag], tol=1e-6) == 1


def _windows_by_calls(x, windows, tol, max_period):
    for w in windows:
        if w > len(x):
            break
        n = detect_period(x[-w:], tol=tol, max_period=min(max_period, (w - 1) // 3))
        if n:
            return n
    return 0


def test_period_of_trailing_windows_in_one_pass_equals_one_call_per_window():
    """Hypothesis: detect_period_windows takes the same decision as detect_period called
    on each trailing window in turn -- on periodic tails behind transients, spirals into
    a fixed point (refused by the divisor rule), noise-level fixed points, chaotic data,
    tails that converge only in the shortest window, and sequences shorter than the
    windows."""
    from vibimpact.analysis.period import detect_period_windows

    windows = (7, 13, 25, 49, 97, 193)
    rng = np.random.default_rng(3)
    cases = []
    for n in (1, 2, 3, 5, 8, 16, 31, 64):
        orbit = periodic_orbit(n, repeats=max(4, 200 // n), noise=1e-9)
        for lead in (0, 5, 60):  # a transient in front of the periodic tail
            cases.append(np.vstack([rng.uniform(-1, 1, (lead, 4)), orbit]))
    k = np.arange(200)[:, None]
    cases.append(0.3 + 2e-3 * 0.9 ** k * np.cos(2.1 * k + np.arange(4)))  # spiral in
    cases.append(0.3 + 2e-3 * (-0.999) ** k * np.ones((1, 4)))  # slow flip: period-2-like
    cases.append(1.0 + 1e-9 * rng.standard_normal((150, 4)))
    cases.append(np.vstack([logistic(180)[:, None] * np.ones((1, 4)),
                            np.full((7, 4), 0.4)]))  # converged only in the last 7
    cases.append(logistic(193)[:, None] * np.ones((1, 4)))
    cases.append(rng.uniform(-1, 1, (5, 4)))
    found = 0
    for x in cases:
        for tol, mp in ((1e-6, 64), (1e-3, 16), (1e-6, 2)):
            a = detect_period_windows(x, windows, tol=tol, max_period=mp)
            assert a == _windows_by_calls(x, windows, tol, mp)
            found += a > 0
    assert found >= 20


def test_impact_map_reads_the_models_own_contact_switch_and_mode():
    """Hypothesis: the impact map keeps the entries of the contact the model declares
    (its switch and mode entry), not of switch 0 and mode entry 0: a contact on switch 1
    and mode entry 1 gets exactly the entries into mode 1 on switch 1; a registered
    model without a contact (Duffing) gets no rows."""
    import dataclasses

    import vibimpact as vi

    state = np.arange(24.0).reshape(6, 4)
    events = dict(t=np.arange(6.0), which=np.array([0, 1, 1, 0, 1, 1]),
                  mode_before=np.array([[0, 0], [0, 0], [0, 1], [0, 0], [1, 0], [0, 0]]),
                  mode_after=np.array([[1, 0], [0, 1], [0, 0], [1, 0], [1, 1], [1, 0]]),
                  state=state)
    run = _FakeRun(np.ones((3, 4)), events)
    rotor = vi.models.get("rotor").contact
    np.testing.assert_array_equal(impact_map(run, rotor), state[[0, 3]])
    other = dataclasses.replace(rotor, switch=1, mode=1)
    np.testing.assert_array_equal(impact_map(run, other), state[[1, 4]])
    run.model = "duffing"
    assert impact_map(run).shape == (0, 4)
    run.model = "rotor"
    np.testing.assert_array_equal(impact_map(run), state[[0, 3]])
