"""Shooting, monodromy matrices, Floquet multipliers and continuation (issue 8).

Checked against independent routes: a period doubling of the Duffing oscillator located
from brute-force simulation only, Liouville's formula for the determinant of the
monodromy matrix, finite-difference Jacobians of the stroboscopic map, and the
variational Lyapunov exponents of the rotor.
"""
import math

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.analysis import (Averaging, Steps, continue_orbit, floquet_exponents,
                                floquet_multipliers, locate_bifurcation, lyapunov_spectrum,
                                monodromy, shoot_periodic_orbit, strobe_map_jacobian)
from vibimpact.analysis.continuation import orbit_signature
from conftest import continued_state, preset

#: double-well Duffing oscillator of the classic period-doubling route (Thompson & Stewart
#: 1986; Kovacic & Brennan 2011): delta 0.3, alpha -1, beta 1, omega 1.2, gamma varied
DUFFING = vi.DuffingParams(delta=0.3, alpha=-1.0, beta=1.0, gamma=0.25, omega=1.2)


def _pd_by_simulation():
    """Independent reference for the period doubling in gamma, from simulation only.

    Past a supercritical period doubling the period-2 splitting ``s = |x_1 - x_0|`` of
    the converged stroboscopic points obeys ``s^2 ~ c (gamma - gamma*)``; a quadratic
    through ``s^2`` at five values (long transients, no Newton, no variational
    equations) has its root at ``gamma*``."""
    x = vi.simulate(DUFFING.replace(gamma=0.26), periods=1, transient=300,
                    state0=[1.0, 0.0]).final_state
    gs = np.array([0.268, 0.270, 0.272, 0.274, 0.276])
    s2 = []
    for g in gs:
        r = vi.simulate(DUFFING.replace(gamma=float(g)), periods=4, transient=3000,
                        state0=x,
                        solver=vi.SolverSettings(rtol=1e-11, atol=1e-13))
        assert np.abs(r.strobe[2] - r.strobe[0]).max() < 1e-9  # converged period 2
        s2.append(np.sum((r.strobe[1] - r.strobe[0]) ** 2))
    roots = np.roots(np.polyfit(gs, s2, 2))
    roots = roots[np.isreal(roots)].real
    return float(roots[np.argmin(np.abs(roots - 0.27))])


def test_duffing_period_doubling_matches_brute_force_reference():
    """The period-1 orbit of the double-well Duffing oscillator loses stability through
    mu = -1 at the gamma where brute-force simulation sees the period-2 splitting vanish
    (acceptance: within 1e-3; measured about 1e-5)."""
    ref = _pd_by_simulation()
    bif = locate_bifurcation(vi.System(DUFFING), [1.0, 0.0], param="gamma", start=0.25,
                             stop=0.28, tol=1e-6)
    assert bif.kind == "period doubling"
    assert abs(bif.value - ref) < 1e-3
    assert abs(bif.value - ref) < 1e-4  # what it actually achieves
    mu = bif.orbit.multipliers[0]
    assert abs(mu.imag) < 1e-9 and abs(mu.real + 1.0) < 1e-3


def test_monodromy_determinant_obeys_liouville():
    """det M = exp(-delta n T) for the Duffing oscillator (the trace of its Jacobian is
    -delta), so the product of the multipliers is fixed independently of the orbit."""
    orb = shoot_periodic_orbit(vi.System(DUFFING.replace(gamma=0.28)), [1.0, 0.0], 2)
    assert orb.converged and orb.minimal_period == 2
    T = 2.0 * math.pi / 1.2
    assert np.prod(orb.multipliers).real == pytest.approx(math.exp(-0.3 * 2 * T),
                                                          rel=1e-8)


def test_newton_converges_quadratically_to_a_tight_residual():
    """From a point of the transient the Newton iteration reaches the tolerance in a few
    monodromy evaluations; the cycle repeats under simulation."""
    p = DUFFING.replace(gamma=0.2)
    orb = shoot_periodic_orbit(vi.System(p), [1.0, 0.0], 1, tol=1e-11)
    assert orb.converged and orb.iterations <= 8 and orb.residual < 1e-10
    run = vi.simulate(p, periods=5, state0=orb.state,
                      solver=vi.SolverSettings(rtol=1e-12, atol=1e-14))
    assert np.abs(run.strobe - orb.state).max() < 1e-9


@pytest.fixture(scope="module")
def fig8_orbits():
    """Impacting period-1 orbits of fig8 (B = Ec = 0.1) on the continued upper branch:
    eta = 1.185 (two bottom impacts A, B; all exponents equal) and 1.195 (third contact
    C; two pairs)."""
    out = {}
    for eta in (1.185, 1.195):
        p = preset("fig8").replace(eta=eta)
        orb = shoot_periodic_orbit(vi.System(p), continued_state("fig8", eta), 1)
        out[eta] = (p, orb)
    return out


def test_fig8_floquet_exponents_match_variational_lyapunov(fig8_orbits):
    """ln|mu| / T of the fig8 periodic points equal the largest Lyapunov exponent of the
    analysers (variational equations, QR) within its error bar (-0.0500 at 1.185)."""
    for eta, (p, orb) in fig8_orbits.items():
        assert orb.converged and orb.stable
        ly = lyapunov_spectrum(vi.System(p), state0=orb.state, averaging=Averaging(
            transient=0, min_periods=400, target_stderr=1e-3))
        lam = np.log(orb.abs_max) / orb.period
        assert abs(lam - ly.exponents[0]) < 4 * ly.stderr[0] + 5e-4, eta
        # the whole spectrum: four Floquet exponents against four Lyapunov exponents
        fe = orb.exponents
        assert np.all(np.abs(fe - ly.exponents) < 4 * ly.stderr + 5e-4), eta
    assert np.log(fig8_orbits[1.185][1].abs_max) / fig8_orbits[1.185][1].period == \
        pytest.approx(-0.0500, abs=5e-4)


def test_variational_monodromy_matches_finite_differences(fig8_orbits):
    """The monodromy matrix from the variational equations with saltation matrices
    equals the central-difference Jacobian of the stroboscopic map, on impacting orbits
    with a continuous (fig8) and a discontinuous (fig10, B_T) contact force."""
    for eta, (p, orb) in fig8_orbits.items():
        fd = strobe_map_jacobian(vi.System(p), orb.state)
        assert np.abs(orb.monodromy - fd).max() < 1e-5 * np.abs(fd).max(), eta
    p = preset("fig10").replace(eta=1.1)
    orb = shoot_periodic_orbit(vi.System(p), continued_state("fig10", 1.1), 1)
    assert orb.converged
    sig = orbit_signature(vi.System(p), orb.state, 1)
    assert sig[0][0] >= 2  # contact entries and exits: the saltation matrix is used
    fd = strobe_map_jacobian(vi.System(p), orb.state)
    assert np.abs(orb.monodromy - fd).max() < 1e-5 * np.abs(fd).max()


def test_continuation_goes_round_the_folds_of_a_hardening_duffing():
    """Pseudo-arclength continuation follows the forced response of a hardening Duffing
    oscillator round both folds: the middle branch is unstable (a real multiplier > 1),
    stability changes only at the turning points, and the upper fold agrees with
    locate_bifurcation followed along the upper branch."""
    p = vi.DuffingParams(delta=0.1, alpha=1.0, beta=0.05, gamma=0.5, omega=0.8)
    x = vi.simulate(p, periods=1, transient=400).final_state
    br = continue_orbit(vi.System(p), x, param="omega", stop=(0.8, 2.0),
                        steps=Steps(ds=0.02, ds_max=0.05))
    turns = [(i, v) for i, k, v in br.bifurcations if k == "fold (turning point)"]
    assert len(turns) == 2
    (i1, w1), (i2, w2) = turns
    assert 1.2 < w1 < 1.3 and 1.1 < w2 < 1.2 and w2 < w1
    assert br.stable[:i1 - 1].all() and not br.stable[i1 + 1:i2 - 1].any()
    assert br.stable[i2 + 1:].all()
    mid = br.multipliers[(i1 + i2) // 2]
    assert abs(mid[0].imag) < 1e-9 and mid[0].real > 1.0
    assert br.amplitude["x_m"][i1] > br.amplitude["x_m"][i2]
    bif = locate_bifurcation(vi.System(p.replace(omega=1.2)), br.states[np.argmin(
        np.abs(br.values[:i1] - 1.2))], param="omega", start=1.2, stop=1.3, tol=1e-5)
    assert bif.kind == "fold" and abs(bif.value - w1) < 2e-3


def test_multipliers_are_sorted_and_exponents_follow():
    """floquet_multipliers sorts by modulus (conjugate pairs kept together) and
    floquet_exponents is ln|mu| / period, descending."""
    M = np.array([[0.0, -0.5, 0.0], [0.5, 0.0, 0.0], [0.0, 0.0, -0.9]])
    mu = floquet_multipliers(M)
    assert mu[0] == pytest.approx(-0.9)
    assert mu[1] == pytest.approx(0.5j) and mu[2] == pytest.approx(-0.5j)
    lam = floquet_exponents(mu, 2.0)
    assert lam == pytest.approx(np.log([0.9, 0.5, 0.5]) / 2.0)


@pytest.mark.parametrize("call, name", [
    (lambda: shoot_periodic_orbit(vi.System(DUFFING), [1.0, 0.0], 0), "n"),
    (lambda: shoot_periodic_orbit(vi.System(DUFFING), [1.0], 1), "state0"),
    (lambda: shoot_periodic_orbit(vi.System(DUFFING), [1.0, 0.0], tol=-1.0), "tol"),
    (lambda: monodromy(vi.System(DUFFING, method="rk5"), [1.0, 0.0]), "method"),
    (lambda: monodromy(DUFFING, [1.0, 0.0]), "system"),
    (lambda: shoot_periodic_orbit(DUFFING, [1.0, 0.0]), "system"),
    (lambda: floquet_multipliers(np.ones((2, 3))), "M"),
    (lambda: locate_bifurcation(vi.System(DUFFING), [1.0, 0.0], param="nope", start=0.2,
                                stop=0.3), "param"),
    (lambda: locate_bifurcation(vi.System(DUFFING), [1.0, 0.0], param="gamma", start=0.2,
                                stop=0.2), "stop"),
    (lambda: continue_orbit(vi.System(DUFFING), [1.0, 0.0], param="gamma", stop=(0.2, 0.3),
                            direction=2), "direction"),
    (lambda: Steps(ds_min=-1.0), "ds_min"),
    (lambda: Steps(max_points=1), "max_points"),
    (lambda: continue_orbit(vi.System(DUFFING), [1.0, 0.0], param="gamma", stop=0.3,
                            steps=dict(ds=0.1)), "steps"),
])
def test_bad_input_names_the_argument(call, name):
    """Bad arguments raise ValueError naming the argument."""
    with pytest.raises(ValueError, match=name):
        call()


def test_locate_refuses_an_unstable_start():
    """A start without a stable orbit of the asked period is refused (state0 named)."""
    with pytest.raises(ValueError, match="state0"):
        locate_bifurcation(vi.System(DUFFING.replace(gamma=0.28)), [1.0, 0.0],
                           param="gamma", start=0.28, stop=0.3)


def test_plot_branch_draws_stable_solid_and_unstable_dashed():
    """plot_branch draws the stable parts solid and the unstable part dashed."""
    from matplotlib.figure import Figure

    from vibimpact.plotting.branch import plot_branch

    p = vi.DuffingParams(delta=0.1, alpha=1.0, beta=0.05, gamma=0.5, omega=1.1)
    x = vi.simulate(p, periods=1, transient=400).final_state
    br = continue_orbit(vi.System(p), x, param="omega", stop=(1.1, 1.4),
                        steps=Steps(ds=0.02, ds_max=0.05))
    ax = Figure().add_subplot()
    arts = plot_branch(ax, br, "x_m", label="P1")
    styles = {a.get_linestyle() for a in arts if len(a.get_xdata()) > 1}
    assert styles == {"-", "--"}
    with pytest.raises(ValueError, match="var"):
        plot_branch(ax, br, "X_m")
