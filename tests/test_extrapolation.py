"""Minimal polynomial extrapolation of converging map iterations, and its use to end a
sweep point's transient on a slowly converging periodic orbit."""
import numpy as np
import pytest

import vibimpact as vi
from vibimpact.analysis import detect_period, extrapolate_limit, shoot_periodic_orbit
from vibimpact.sweeps import SweepSettings


def _iterate(f, x, m):
    xs = [np.asarray(x, dtype=float)]
    for _ in range(m - 1):
        xs.append(f(xs[-1]))
    return np.array(xs)


def test_limit_of_a_linear_iteration_is_exact_from_d_plus_2_iterates():
    """Hypothesis: for x -> A x + b in d = 4 dimensions (complex and real multipliers),
    d + 2 iterates determine the fixed point (I - A)^-1 b to rounding (Cabay & Jackson
    1976), although the iterates themselves are still far from it."""
    rng = np.random.default_rng(1)
    Q = rng.normal(size=(4, 4))
    J = np.array([[0.9 * np.cos(1.0), -0.9 * np.sin(1.0), 0, 0],
                  [0.9 * np.sin(1.0), 0.9 * np.cos(1.0), 0, 0],
                  [0, 0, -0.7, 0], [0, 0, 0, 0.95]])
    A = Q @ J @ np.linalg.inv(Q)
    b = rng.normal(size=4)
    xs = _iterate(lambda x: A @ x + b, np.zeros(4), 6)
    exact = np.linalg.solve(np.eye(4) - A, b)
    assert np.abs(xs[-1] - exact).max() > 0.1
    assert np.abs(extrapolate_limit(xs) - exact).max() < 1e-9 * np.abs(exact).max()


def test_restarted_extrapolation_converges_quadratically_on_a_nonlinear_map():
    """Hypothesis: on a smooth non-linear contraction (the Henon-like map below, fixed
    point with multipliers inside the unit circle), the error after extrapolating from
    iterates at error e is O(e^2): restarting twice takes 1e-2 to below 1e-8."""
    def f(x):
        return np.array([0.3 + 0.5 * x[1] - 0.2 * x[0] ** 2, 0.8 * x[0] + 0.1 * x[1] ** 2])

    ref = _iterate(f, np.zeros(2), 2000)[-1]
    x = ref + np.array([1e-2, -1e-2])
    errs = []
    for _ in range(3):
        x = extrapolate_limit(_iterate(f, x, 4))
        errs.append(np.abs(x - ref).max())
    assert errs[0] < 1e-3
    assert errs[1] < 10.0 * errs[0] ** 2 + 1e-14
    assert errs[2] < 1e-8


@pytest.mark.parametrize("bad", [np.zeros(4), [[0.0, np.nan]] * 4, "x"])
def test_bad_sequences_are_refused_naming_seq(bad):
    """Hypothesis: a 1-D, non-finite or non-numeric sequence is a ValueError naming seq."""
    with pytest.raises(ValueError, match="seq"):
        extrapolate_limit(bad)


def test_slowly_converging_orbit_is_found_periodic_with_extrapolation_only():
    """Hypothesis: fig11 at eta = 1.03 lies on a stable period-1 orbit whose slowest
    multiplier is close to 1 (|mu| about 0.985, checked by shooting), so its strobe points
    do not repeat to 1e-6 within the 200-period transient and the sweep without
    extrapolation (and without its shooting, which would also find it) does not call it
    P1; with extrapolation it does, and the recorded state lies on the shot orbit."""
    p = vi.presets.get("fig11").replace(B=0.07, Ec=0.11)  # pinned: the defaults when written
    eta = np.round(np.arange(0.99, 1.03 + 1e-9, 0.01), 6)
    a = vi.sweep(p, eta, settings=SweepSettings(extrapolate=0, shoot=0), analyses=("period",))
    b = vi.sweep(p, eta, settings=SweepSettings(), analyses=("period",))
    x = b.final_state.values[-1]
    orb = shoot_periodic_orbit(vi.System(p.replace(eta=1.03)), x, 1)
    assert orb.converged and 0.95 < orb.abs_max < 1.0
    assert int(b.period.values[-1]) == 1 and int(a.period.values[-1]) != 1
    assert np.abs(orb.state - x).max() < 1e-5
    # and a long plain run from the old end state confirms period 1
    run = vi.simulate(p.replace(eta=1.03), periods=1500, state0=a.final_state.values[-1])
    assert detect_period(run.strobe[-100:], tol=1e-6) == 1


@pytest.fixture(scope="module")
def saddle_case():
    """fig8 with kh = 10 at eta = 1.085, reached by an upward sweep from 0.9: its period-1
    orbit is a saddle (a multiplier 1.04) and its period-2 orbit attracts."""
    p = vi.presets.get("fig8").replace(kh=10.0, B=0.07, Ec=0.11)  # pinned: the defaults when written
    eta = np.round(np.arange(0.9, 1.085 + 1e-9, 0.005), 6)
    ds = vi.sweep(p, eta, analyses=("period",))
    return p.replace(eta=1.085), ds


def test_a_jump_onto_a_saddle_is_not_accepted_as_periodic(saddle_case):
    """Hypothesis: extrapolation finds a saddle as readily as an attractor, and the points
    after a jump onto a weakly unstable period-1 orbit repeat to 1e-6 long before they
    leave it; the sweep checks the multipliers of an orbit found after a jump and reports
    the attracting period-2 orbit, not the saddle."""
    p, ds = saddle_case
    x = ds.final_state.values[-1]
    p1 = shoot_periodic_orbit(vi.System(p), x, 1)
    p2 = shoot_periodic_orbit(vi.System(p), x, 2)
    assert p1.converged and p1.abs_max > 1.02
    assert p2.converged and p2.minimal_period == 2 and p2.abs_max < 1.0
    assert int(ds.period.values[-1]) == 2
    assert np.abs(p2.state - x).max() < 1e-5 or \
        np.abs(vi.simulate(p, periods=1, state0=p2.state).final_state - x).max() < 1e-5


def test_stability_check_tells_the_saddle_from_the_attractor(saddle_case):
    """Hypothesis: the sweep's stability check (monodromy matrix with the Lyapunov runs'
    tangent tolerance) calls the period-1 saddle not attracting and the period-2 orbit
    attracting, as the shooting's own multipliers do."""
    from vibimpact.points.point import point_system
    from vibimpact.points.transient import attracting

    p, ds = saddle_case
    x = ds.final_state.values[-1]
    system = point_system(p, SweepSettings())
    assert not attracting(system, shoot_periodic_orbit(vi.System(p), x, 1).state, 1)
    assert attracting(system, shoot_periodic_orbit(vi.System(p), x, 2).state, 2)
