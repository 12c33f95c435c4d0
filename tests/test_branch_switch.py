"""Branch switching at a period doubling (vibimpact.analysis.switch_branch).

The double-well Duffing oscillator x'' + 0.3 x' - x + x^3 = gamma cos(1.2 t) (Guckenheimer
& Holmes 1983, sec. 2.2) has a period-doubling cascade in gamma: its period-1 orbit in
one well doubles near gamma = 0.2656, the period-2 orbit again near 0.2867.  The doubled
branch is followed from the first period doubling and checked against SciPy's
integration of the same equation and against the theory of the flip bifurcation (the
period-2 orbit's points split as the square root of the distance from the bifurcation;
its multiplier there is (-1)^2 = +1).
"""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import vibimpact as vi
from vibimpact.analysis import (continue_orbit, period_doubling_point,
                                shoot_periodic_orbit, switch_branch)

DELTA, ALPHA, BETA, OMEGA = 0.3, -1.0, 1.0, 1.2
STOP = 0.28


@pytest.fixture(scope="module")
def branches():
    """(system, period-1 branch over gamma 0.25..0.28, switched period-2 branch)."""
    s = vi.System(vi.DuffingParams(delta=DELTA, alpha=ALPHA, beta=BETA, gamma=0.25,
                                   omega=OMEGA))
    x = s.simulate(periods=1, transient=300, state0=[1.0, 0.0]).final_state
    p1 = continue_orbit(s, x, param="gamma", stop=STOP, refine=1e-8, amplitude=False)
    p2 = switch_branch(s, p1, stop=STOP, refine=1e-8, amplitude=False)
    return s, p1, p2


def _scipy_map(gamma, x, periods):
    """The Duffing flow over ``periods`` forcing periods from ``x`` by SciPy (DOP853)."""
    def f(t, y):
        return [y[1], -DELTA * y[1] - ALPHA * y[0] - BETA * y[0] ** 3
                + gamma * np.cos(OMEGA * t)]
    T = 2.0 * np.pi / OMEGA
    sol = solve_ivp(f, (0.0, periods * T), x, method="DOP853", rtol=1e-11, atol=1e-12)
    return sol.y[:, -1]


def test_the_switched_branch_starts_at_the_period_doubling_with_twice_the_period(branches):
    """Hypothesis: the doubled branch has n = 2 and starts at the parent's period-doubling
    value, where the parent's multiplier is -1."""
    s, p1, p2 = branches
    assert p1.n == 1 and p2.n == 2
    pd = [b for b in p1.bifurcations if b[1] == "period doubling"]
    assert len(pd) == 1
    lam, x, v = period_doubling_point(s, p1)
    assert abs(lam - pd[0][2]) < 1e-7
    assert p2.values[0] == lam
    parent = shoot_periodic_orbit(s.with_param("gamma", lam), x, 1)
    assert abs(parent.multipliers[0] + 1.0) < 1e-5  # the real multiplier -1
    assert np.all(p2.values[1:] > lam)  # supercritical here: on the unstable P1 side


def test_its_orbits_have_minimal_period_two_by_scipy(branches):
    """Hypothesis: every continued orbit is a period-2 orbit of the flow (SciPy returns to
    the point after two forcing periods to 1e-7) and not a period-1 orbit (it does not
    after one)."""
    _, _, p2 = branches
    for gamma, x in zip(p2.values[1::3], p2.states[1::3]):
        two = _scipy_map(gamma, x, 2)
        one = _scipy_map(gamma, x, 1)
        assert np.abs(two - x).max() < 1e-7
        assert np.abs(one - x).max() > 1e-3


def test_its_cycle_points_meet_at_the_period_doubling_as_a_square_root(branches):
    """Hypothesis: the two points of the period-2 cycle, x and P(x), converge to the
    period-1 orbit's point as gamma -> gamma*: their distance is 0 (to 1e-6) at the
    first point and grows as sqrt(gamma - gamma*) (the ratio constant to 10 % over the
    points within 2e-3 of gamma*)."""
    s, _, p2 = branches
    lam = p2.values[0]
    split = np.array([np.abs(_scipy_map(g, x, 1) - x).max()
                      for g, x in zip(p2.values, p2.states)])
    assert split[0] < 1e-6
    near = (p2.values > lam) & (p2.values - lam < 2e-3)
    assert near.sum() >= 3
    ratio = split[near] / np.sqrt(p2.values[near] - lam)
    assert ratio.max() / ratio.min() < 1.1


def test_its_multiplier_at_the_period_doubling_is_plus_one(branches):
    """Hypothesis: the doubled orbit's largest multiplier is +1 at the period doubling
    (first point, to 1e-5) and tends there along the branch: extrapolated linearly from
    the two nearest continued orbits, to 1e-3."""
    _, _, p2 = branches
    mu = p2.multipliers[:, 0]
    assert abs(mu[0] - 1.0) < 1e-5
    g, m = p2.values[1:3], mu[1:3].real
    assert np.all(np.abs(mu[1:3].imag) < 1e-9)
    extrapolated = m[0] + (m[1] - m[0]) * (p2.values[0] - g[0]) / (g[1] - g[0])
    assert abs(extrapolated - 1.0) < 1e-3


def test_the_doubled_branch_doubles_again(branches):
    """Hypothesis: the cascade goes on: the period-2 branch, continued past 0.28, has its
    own period doubling, at a larger gamma than the first (Feigenbaum cascade)."""
    s, p1, p2 = branches
    longer = switch_branch(s, p1, stop=0.29, amplitude=False)
    pd = [b for b in longer.bifurcations if b[1] == "period doubling"]
    assert len(pd) == 1 and p2.values[0] < pd[0][2] < 0.29
    p4 = switch_branch(s, longer, stop=0.29, amplitude=False,
                       steps=vi.analysis.Steps(max_points=3))
    assert p4.n == 4
    orb = shoot_periodic_orbit(s.with_param("gamma", p4.values[-1]), p4.states[-1], 4)
    assert orb.converged and orb.minimal_period == 4


def test_a_branch_without_period_doubling_is_refused(branches):
    """Hypothesis: switching needs a period doubling: a branch without one is refused
    naming branch, an index of no period doubling naming index."""
    s, p1, _ = branches
    short = continue_orbit(s, p1.states[0], param="gamma", stop=0.26, amplitude=False)
    with pytest.raises(ValueError, match="^branch"):
        switch_branch(s, short)
    with pytest.raises(ValueError, match="^index"):
        switch_branch(s, p1, index=3)
