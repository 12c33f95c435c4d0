"""Lyapunov exponents: analytic spectra, published values, and cross-checks between the
variational (saltation), two-trajectory, monodromy and time-series routes."""
import math

import numpy as np
import pytest

import vibimpact as vi
from vibimpact import System
from vibimpact.analysis import (Averaging, largest_lyapunov, lyapunov_from_jacobians,
                                lyapunov_from_series, lyapunov_spectrum,
                                strobe_map_jacobian)
from conftest import continued_state, preset


def test_damped_linear_oscillator_spectrum_is_analytic():
    """x'' + 3x' + x = 0 has exponents (-3 +- sqrt(5))/2: the variational route returns them
    (distinct real eigenvalues, so the QR estimate converges fast); with the tangent
    vectors' errors tested at the tolerances they sum to the trace to 1e-5."""
    p = vi.DuffingParams(delta=3.0, alpha=1.0, beta=0.0, gamma=0.0, omega=1.0)
    res = lyapunov_spectrum(System(p), state0=[1.0, 0.0], tangent_tol=1.0,
                            averaging=Averaging(transient=0, min_periods=100,
                                                max_periods=200))
    exact = np.array([(-3 + math.sqrt(5)) / 2, (-3 - math.sqrt(5)) / 2])
    np.testing.assert_allclose(res.exponents, exact, atol=2e-3)
    # trace of the Jacobian; the second tangent vector shrinks by e^-16 per period, to
    # within a few thousand of the absolute tolerance, hence 1e-5 and not 1e-8
    assert abs(res.exponents.sum() + 3.0) < 1e-5


def test_rotor_without_contact_has_all_exponents_minus_half_damping():
    """Far from the retainer (eta = 0.5, no contact) with k3 = 0 the rotor is two damped
    linear oscillators: four exponents -B/2 (underdamped), sum exactly -2B."""
    p = preset("fig8").replace(eta=0.5, k3=0.0)
    res = lyapunov_spectrum(System(p), averaging=Averaging(transient=20, min_periods=200,
                                                           max_periods=400))
    np.testing.assert_allclose(res.exponents, -0.05, atol=1e-3)
    assert abs(res.exponents.sum() + 0.2) < 1e-8


def test_henon_largest_exponent_through_the_map_route():
    """The Hénon map (a = 1.4, b = 0.3) has largest exponent 0.419 per iteration
    (Sprott 2003, *Chaos and Time-Series Analysis*, App. A: 0.41922); the exponents sum
    to ln b because det J = -b."""
    a, b = 1.4, 0.3
    x, y = 0.1, 0.1
    for _ in range(1000):
        x, y = 1 - a * x * x + y, b * x
    n = 100_000
    xs = np.empty(n)
    for k in range(n):
        xs[k] = x
        x, y = 1 - a * x * x + y, b * x
    J = np.zeros((n, 2, 2))
    J[:, 0, 0] = -2 * a * xs
    J[:, 0, 1] = 1.0
    J[:, 1, 0] = b
    res = lyapunov_from_jacobians(J)
    assert abs(res.exponents[0] - 0.419) < 0.01
    assert abs(res.exponents.sum() - math.log(b)) < 1e-9


UEDA = vi.DuffingParams(delta=0.05, alpha=0.0, beta=1.0, gamma=7.5, omega=1.0)


@pytest.fixture(scope="module")
def ueda():
    """Variational and two-trajectory estimates on Ueda's chaotic oscillator."""
    avg = Averaging(transient=100, min_periods=600, max_periods=3000, target_stderr=4e-3)
    return (lyapunov_spectrum(System(UEDA), [2.5, 0.0], averaging=avg),
            largest_lyapunov(System(UEDA), [2.5, 0.0], averaging=avg))


def test_ueda_oscillator_matches_published_exponent(ueda):
    """Ueda's oscillator x'' + 0.05 x' + x^3 = 7.5 cos t is chaotic (Ueda 1979, J. Stat.
    Phys. 20, 181) with largest exponent 0.10 per unit time (Sprott 2003, App. A, two
    significant digits); the spectrum sums to -0.05 (the Jacobian's trace)."""
    var, _ = ueda
    assert var.converged and var.stderr[0] <= 4e-3
    assert abs(var.exponents[0] - 0.10) < 0.01
    assert abs(var.exponents.sum() + 0.05) < 1e-8


def test_two_trajectory_agrees_with_variational_on_ueda(ueda):
    """Two independent routes (no Jacobian in the second) agree within their errors."""
    var, two = ueda
    assert abs(var.exponents[0] - two.exponents[0]) < 3 * math.hypot(var.stderr[0],
                                                                     two.stderr[0])


@pytest.mark.parametrize("name, eta", [("fig8", 1.185), ("fig10", 1.02), ("fig11", 1.22)])
def test_variational_exponent_equals_floquet_exponent_of_impacting_orbit(name, eta):
    """On a periodic impacting orbit the largest exponent from the variational equations
    (with saltation matrices where the field jumps: BT at contact entry/exit in fig10,
    friction in fig11) equals ln|mu_max|/T from the monodromy matrix by finite differences
    of the Poincaré map, within 2 %: the QR average (floquet=False; with the default the
    orbit's Floquet exponents are returned instead, see tests/test_lyapunov_floquet.py)."""
    p = preset(name).replace(eta=eta)
    x = continued_state(name, eta, transient=300)
    run = vi.simulate(p, periods=3, state0=x)
    assert len(run.impacts) >= 2 and np.ptp(run.strobe, axis=0).max() < 1e-6
    res = lyapunov_spectrum(System(p), state0=x, floquet=False, averaging=Averaging(
        transient=0, min_periods=300, max_periods=1500, target_stderr=5e-4))
    assert res.floquet_n == 0
    mu = np.linalg.eigvals(strobe_map_jacobian(System(p), x))
    floquet = np.log(np.abs(mu)).max() / res.period
    assert abs(res.exponents[0] - floquet) <= 0.02 * abs(floquet)


def test_looser_tangent_tolerance_gives_the_same_exponent_as_the_full_test():
    """With the tangent vectors' local errors tested at 1e3 times the tolerances (the
    default) or not at all, the largest exponent of an impacting periodic orbit with a
    multiplier close to the unit circle (fig8, eta = 1.13) equals the one with every entry
    tested at the tolerances to 1e-4 per unit tau, from the same state and periods (QR
    averages: floquet=False, else the shooting's tolerances decide)."""
    p = preset("fig8").replace(eta=1.13)
    x = continued_state("fig8", 1.13, transient=300)
    assert len(vi.simulate(p, periods=2, state0=x).impacts) >= 1
    kw = dict(state0=x, n_exponents=1, floquet=False, averaging=Averaging(
        transient=0, min_periods=150, max_periods=150, align=20))
    s = System(p, rtol=1e-8, atol=1e-11)
    lam_all = lyapunov_spectrum(s, tangent_tol=1.0, **kw).exponents[0]
    for tol in (1e3, math.inf):
        lam = lyapunov_spectrum(s, tangent_tol=tol, **kw).exponents[0]
        assert lam < 0.0 and abs(lam - lam_all) < 1e-4


def test_a_state_at_rest_still_controls_its_tangent_vectors():
    """x'' + 3x' + x = 0 from (1, 0): the state decays to rest, where its own error test
    allows quarter-period steps; the second tangent vector (exponent -2.618) is only
    right because its local errors are still tested (default tangent_tol), and is wrong
    by more than 5 % when they are not (tangent_tol = inf).  QR averages (floquet=False):
    the rest point is a periodic orbit whose Floquet exponents would be returned exactly."""
    p = System(vi.DuffingParams(delta=3.0, alpha=1.0, beta=0.0, gamma=0.0, omega=1.0))
    kw = dict(state0=[1.0, 0.0], floquet=False,
              averaging=Averaging(transient=0, min_periods=100, max_periods=200))
    exact = (-3 - math.sqrt(5)) / 2
    assert abs(lyapunov_spectrum(p, **kw).exponents[1] - exact) < 1e-3
    assert abs(lyapunov_spectrum(p, tangent_tol=math.inf, **kw).exponents[1] - exact) > \
        0.05 * abs(exact)


@pytest.fixture(scope="module")
def fig8_exponents(fig8_chaotic):
    p, x = fig8_chaotic
    avg = Averaging(transient=100, min_periods=4000, max_periods=4000)
    return (p, x, lyapunov_spectrum(System(p), x, averaging=avg),
            largest_lyapunov(System(p), x, averaging=avg.replace(align=20)))


def test_fig8_chaotic_point_variational_and_two_trajectory_agree(fig8_exponents):
    """Inside the paper's chaotic interval (fig8, eta = 1.22) the largest exponent is
    positive, and the variational and two-trajectory estimates agree within 10 %."""
    _, _, var, two = fig8_exponents
    assert var.exponents[0] > 3 * var.stderr[0] > 0
    assert abs(var.exponents[0] - two.exponents[0]) <= 0.1 * var.exponents[0]


def test_fig8_spectrum_pairs_to_minus_damping(fig8_exponents):
    """With Bh = BT = f = 0 the contact force is conservative and the damping uniform, so
    the flow is conformally symplectic: exponents pair as l1 + l4 = l2 + l3 = -B
    (Dressler 1988, Phys. Rev. A 38, 2103)."""
    p, _, var, _ = fig8_exponents
    lam = var.exponents
    assert abs(lam[0] + lam[3] + p.B) < 1e-6
    assert abs(lam[1] + lam[2] + p.B) < 1e-6


def test_nolds_time_series_estimate_confirms_the_sign(fig8_exponents):
    """Cross-check only: Rosenstein's estimate from the Poincaré X series is positive at the
    chaotic point and within a factor 2 of the variational value (nolds comes with the
    'test' extra the README's test command installs: its absence fails here)."""
    p, x, var, _ = fig8_exponents
    run = vi.simulate(p, periods=1500, state0=x)
    est = lyapunov_from_series(run.strobe[:, 0], period=var.period)
    assert var.exponents[0] / 2 < est < 2 * var.exponents[0]


def test_map_exponents_are_flow_exponents_times_period():
    """The stroboscopic map's exponents are the flow's times T; include_phase appends the
    forcing phase's exact zero."""
    p = vi.DuffingParams(delta=3.0, alpha=1.0, beta=0.0, gamma=0.0, omega=2.0)
    res = lyapunov_spectrum(System(p), state0=[1.0, 0.0], include_phase=True,
                            averaging=Averaging(transient=0, min_periods=100,
                                                max_periods=100))
    assert res.exponents.shape == (3,) and res.exponents[0] == 0.0
    np.testing.assert_allclose(res.map_exponents, res.exponents * math.pi)


def test_tighter_target_integrates_longer_and_meets_it():
    """Convergence control: the run goes on until the largest exponent's standard error
    reaches the target, so a tighter target needs more periods and is met."""
    avg = Averaging(transient=50, min_periods=200, max_periods=20000, align=20)
    loose = largest_lyapunov(System(UEDA), [2.5, 0.0],
                             averaging=avg.replace(target_stderr=1e-2))
    tight = largest_lyapunov(System(UEDA), [2.5, 0.0],
                             averaging=avg.replace(target_stderr=3e-3))
    assert loose.stderr[0] <= 1e-2 and tight.stderr[0] <= 3e-3
    assert tight.periods > loose.periods


def test_blow_up_is_labelled_not_returned_as_exponents():
    """A trajectory that escapes (softening Duffing, strong forcing) gives status DIVERGED
    and NaN exponents, never numbers."""
    p = vi.DuffingParams(delta=0.1, alpha=1.0, beta=-1.0, gamma=5.0, omega=1.0)
    res = lyapunov_spectrum(System(p), averaging=Averaging(transient=0, min_periods=50,
                                                           max_periods=100))
    assert res.status is vi.Status.DIVERGED and np.all(np.isnan(res.exponents))


@pytest.mark.parametrize("call, name", [
    (lambda s: lyapunov_spectrum(s, n_exponents=5), "n_exponents"),
    (lambda s: Averaging(min_periods=10, max_periods=5), "max_periods"),
    (lambda s: lyapunov_spectrum(s.with_solver(method="rk5")), "method"),
    (lambda s: Averaging(target_stderr=-1.0), "target_stderr"),
    (lambda s: Averaging(block=1), "block"),
    (lambda s: lyapunov_spectrum(s, averaging=dict(transient=0)), "averaging"),
    (lambda s: lyapunov_spectrum(s, state0=[1.0, 2.0]), "state0"),
    (lambda s: lyapunov_spectrum(s, tangent_tol=0.5), "tangent_tol"),
    (lambda s: lyapunov_spectrum(preset("fig8")), "system"),
    (lambda s: largest_lyapunov(s, d0=0.0), "d0"),
    (lambda s: strobe_map_jacobian(s, [0.0] * 4, eps=-1.0), "eps")])
def test_bad_arguments_raise_value_error_naming_them(call, name):
    """Invalid arguments raise ValueError naming the argument (a System is required)."""
    with pytest.raises(ValueError, match=name):
        call(System(preset("fig8")))


def test_a_direction_annihilated_by_a_stick_phase_has_exponent_minus_infinity():
    """A tangent direction that a Filippov stick phase projects to zero (the ring model's
    speed while its bearing holds the ring: the saltation matrix of the sliding surface
    removes it) has log |R_cc| = -inf every period: its exponent is -inf with error 0, the
    other exponents are finite, and no invalid-value warning is raised on the way."""
    import warnings

    s = System(vi.presets.get("fig8-ring").replace(eta=1.2))
    # fig8 has no friction and no tangential damping: nothing drives the ring, whose
    # bearing (Mr > 0) holds it; its speed's tangent direction is projected out
    av = Averaging(transient=20, min_periods=100, max_periods=100, block=20, align=20)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = vi.analysis.lyapunov_spectrum(s, state0=[0.9, 0.3, 0.0, 0.0, 0.0], averaging=av)
    lam = np.asarray(res.exponents)
    assert np.isneginf(lam).sum() == 1 and np.isneginf(lam[-1])
    assert np.all(np.isfinite(lam[:-1]))
    assert np.asarray(res.stderr)[-1] == 0.0
