"""Lyapunov exponents of periodic orbits whose leading Floquet multipliers are a complex pair.

The QR (Benettin) average splits such a pair over a finite run; on a periodic orbit
``lyapunov_spectrum`` returns the Floquet exponents ``ln|mu| / T`` instead (shot orbit,
monodromy eigenvalues), and ``floquet_lyapunov`` gives them for a point of an orbit.

Known values used below: with no contact damping (Bh = BT = f = 0, or no contact at all)
the only dissipation is the uniform viscous B, so the flow is conformally symplectic and
the monodromy matrix M satisfies ``M^T J M = exp(-B T) J``; its multipliers come in
quadruples ``mu, conj(mu), exp(-B T)/mu, exp(-B T)/conj(mu)``, and when all four are
complex and the two pairs differ in argument (the stable, underdamped case) they all have
``|mu| = exp(-B T / 2)`` (a quadruple with ``|mu|`` off that circle has two pairs of the
same argument), so every Floquet exponent is ``-B/2`` exactly (Dressler 1988, Phys. Rev.
A 38, 2103, for the pairing).  The numerical error of an exponent computed from a monodromy matrix
integrated at rtol 1e-10 is about ``1e-10 / T``, some 1e-11 per unit tau (the error
estimate the code reports is of that size); the tolerance 1e-8 leaves a margin of ~100
and is still 10^4 times below the QR splits these orbits show (1e-4 .. 1e-3).
"""
import math

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.analysis import (Averaging, floquet_lyapunov, lyapunov_spectrum,
                                shoot_periodic_orbit)

#: tolerance on a Floquet exponent per unit tau (module docstring)
TOL = 1e-8


def _pairs_differ_in_argument(mu):
    """Both multiplier pairs complex, with different arguments (module docstring)."""
    arg = np.sort(np.abs(np.angle(mu)))
    return bool(np.all(np.abs(np.imag(mu)) > 1e-3) and arg[2] - arg[0] > 1e-5)


def _impactless():
    """fig10 geometry at low damping and small unbalance: an impactless, nearly linear
    period-1 orbit (two underdamped modes: two complex pairs)."""
    return vi.presets.get("fig10").replace(B=0.01, Ec=0.05, eta=1.4)


@pytest.fixture(scope="module")
def impacting_fig10():
    """fig10 (BT = 0.05: dissipative contact, so the two pairs differ in modulus) at
    B = 0.01, Ec = 0.11, eta = 1.075: a period-1 orbit with 2 impacts per period, reached
    from (0.5, 0.5, 1, 0) after 600 periods (not yet converged to the repeat tolerance,
    so lyapunov_spectrum has to find the orbit itself)."""
    p = vi.presets.get("fig10").replace(B=0.01, Ec=0.11, eta=1.075)
    x = vi.simulate(p, periods=1, transient=600, state0=[0.5, 0.5, 1.0, 0.0]).final_state
    return p, x


def test_impactless_low_damping_orbit_has_floquet_exponents_minus_half_B():
    """No contact, uniform damping B: every Floquet exponent is -B/2 (module docstring);
    floquet_lyapunov from rest (Newton converges: the problem is nearly linear) returns
    four equal exponents -B/2 to TOL, with a numerical-error estimate below TOL."""
    p = _impactless()
    res = floquet_lyapunov(vi.System(p), [0.0, 0.0, 0.0, 0.0])
    assert res.status is vi.Status.OK and res.floquet_n == 1 and res.method == "floquet"
    orb = shoot_periodic_orbit(vi.System(p), [0.0] * 4)
    assert len(vi.simulate(p, periods=1, state0=orb.state).impacts) == 0
    assert _pairs_differ_in_argument(orb.multipliers)
    np.testing.assert_allclose(res.exponents, -p.B / 2, rtol=0, atol=TOL)
    assert np.all(res.stderr < TOL)


def test_spectrum_from_rest_converges_to_the_pair_not_a_split_of_it():
    """With default settings from rest, lyapunov_spectrum on the impactless orbit returns
    the Floquet exponents: lambda_1 = lambda_2 = -B/2 (the leading complex pair, not split
    into one above and one below) and the whole spectrum -B/2, each to TOL."""
    p = _impactless()
    res = lyapunov_spectrum(vi.System(p))
    assert res.status is vi.Status.OK and res.floquet_n == 1
    assert abs(res.exponents[0] + p.B / 2) <= TOL
    assert abs(res.exponents[1] + p.B / 2) <= TOL
    np.testing.assert_allclose(res.exponents, -p.B / 2, rtol=0, atol=TOL)
    assert res.converged and np.all(res.stderr < TOL)


def test_impacting_orbit_with_complex_pair_converges_to_shooting(impacting_fig10):
    """On an impacting period-1 orbit at B = 0.01 whose leading multipliers are a complex
    pair (and the second pair of a different modulus), lyapunov_spectrum from a state
    still in its transient returns the shooting's ln|mu|/T: both of the leading pair
    equal, and all four exponents, to TOL."""
    p, x = impacting_fig10
    orb = shoot_periodic_orbit(vi.System(p), x, 1)
    assert orb.converged and orb.stable and orb.critical == "complex"
    assert len(vi.simulate(p, periods=1, state0=orb.state).impacts) >= 1
    exact = orb.exponents
    assert abs(exact[0] - exact[1]) < TOL and exact[0] - exact[2] > 1e-3
    res = lyapunov_spectrum(vi.System(p), state0=x, averaging=Averaging(transient=0))
    assert res.status is vi.Status.OK and res.floquet_n == 1 and res.periods > 0
    np.testing.assert_allclose(res.exponents, exact, rtol=0, atol=TOL)
    assert np.all(np.isfinite(res.qr_exponents))


def test_conservative_contact_orbit_has_all_exponents_minus_half_B():
    """fig8 has Bh = BT = f = 0 (conservative Hertz contact): on its impacting period-1
    orbit at B = 0.01, eta = 1.4 (both multiplier pairs complex) every exponent is -B/2
    exactly (module docstring), and lyapunov_spectrum returns that to TOL; the QR average
    (floquet=False) still has its exact sum -2B (trace of the Jacobian: the volume growth
    is free of the pairs' rotation)."""
    p = vi.presets.get("fig8").replace(B=0.01, Ec=0.11, eta=1.4)
    x = vi.simulate(p, periods=1, transient=1500, state0=[0.0, 1.0, 0.0, 0.0]).final_state
    assert len(vi.simulate(p, periods=1, state0=x).impacts) >= 1
    assert _pairs_differ_in_argument(shoot_periodic_orbit(vi.System(p), x).multipliers)
    res = lyapunov_spectrum(vi.System(p), state0=x, averaging=Averaging(transient=0))
    assert res.floquet_n == 1
    np.testing.assert_allclose(res.exponents, -p.B / 2, rtol=0, atol=TOL)
    qr = lyapunov_spectrum(vi.System(p), state0=x, floquet=False, averaging=Averaging(
        transient=0, min_periods=200, max_periods=200))
    assert qr.floquet_n == 0 and abs(qr.exponents.sum() + 2 * p.B) < TOL


def test_chaotic_spectrum_is_bit_identical_with_and_without_the_watch():
    """On a chaotic trajectory (fig8, B = 0.01, eta = 1.2: positive largest exponent) the
    stroboscopic points never repeat, so the periodic-orbit watch never acts and the
    spectrum and its errors are bit for bit the QR average of floquet=False."""
    p = vi.presets.get("fig8").replace(B=0.01, Ec=0.11, eta=1.2)
    kw = dict(averaging=Averaging(transient=200, min_periods=300, max_periods=300))
    on = lyapunov_spectrum(vi.System(p), **kw)
    off = lyapunov_spectrum(vi.System(p), floquet=False, **kw)
    assert on.exponents[0] > 3 * on.stderr[0] > 0 and on.floquet_n == 0
    assert np.array_equal(on.exponents, off.exponents)
    assert np.array_equal(on.stderr, off.stderr) and on.periods == off.periods
    assert np.array_equal(on.qr_exponents, on.exponents)


def test_floquet_lyapunov_of_damped_linear_oscillator_is_analytic():
    """x'' + 3x' + x = 0 (unforced Duffing): the rest point's exponents are the
    eigenvalues (-3 +- sqrt 5)/2, the same with n = 2 (a multiple of the period), each
    within its reported numerical error (the leading one to TOL); n_exponents and
    include_phase select and append as in lyapunov_spectrum."""
    p = vi.DuffingParams(delta=3.0, alpha=1.0, beta=0.0, gamma=0.0, omega=1.0)
    exact = np.array([(-3 + math.sqrt(5)) / 2, (-3 - math.sqrt(5)) / 2])
    for n in (1, 2):
        res = floquet_lyapunov(vi.System(p), [0.1, 0.0], n)
        assert res.floquet_n == 1 and abs(res.exponents[0] - exact[0]) < TOL
        # |mu_2| = exp(-2.618 * 2 pi) = 7e-8 is only known to about atol / |mu_2|: the
        # reported numerical error must cover the actual one
        assert np.all(np.abs(res.exponents - exact) <= res.stderr)
    res = floquet_lyapunov(vi.System(p), [0.0, 0.0], n_exponents=1, include_phase=True)
    assert res.exponents.shape == (2,) and res.exponents[0] == 0.0
    assert abs(res.exponents[1] - exact[0]) < TOL


def test_floquet_lyapunov_reports_failure_not_numbers():
    """Where Newton does not find a period-1 orbit (Ueda's chaotic oscillator, two
    iterations from a point of the attractor) the result is status FAILED with NaN
    exponents and a reason, never numbers."""
    ueda = vi.DuffingParams(delta=0.05, alpha=0.0, beta=1.0, gamma=7.5, omega=1.0)
    res = floquet_lyapunov(vi.System(ueda), [2.5, 0.0], max_iter=2)
    assert res.status is vi.Status.FAILED and np.all(np.isnan(res.exponents))
    assert res.reason and not res.converged


@pytest.mark.parametrize("kwargs, name", [(dict(n=0), "^n must"),
                                          (dict(n_exponents=5), "^n_exponents must")])
def test_floquet_lyapunov_bad_arguments_raise_value_error(kwargs, name):
    """Invalid arguments raise ValueError naming the argument."""
    with pytest.raises(ValueError, match=name):
        floquet_lyapunov(vi.System(_impactless()), [0.0] * 4, **kwargs)


def test_spectrum_bad_floquet_tolerance_raises_value_error():
    """A non-positive floquet_tol is refused, naming it."""
    with pytest.raises(ValueError, match="floquet_tol"):
        lyapunov_spectrum(vi.System(_impactless()), floquet_tol=0.0)
