"""A user model built from numba functions runs through the same kernel."""
import math

import numpy as np
import pytest
from numba import njit

import vibimpact as vi


@njit
def _rhs(s, y, p, mode, out):
    out[0] = y[1]
    out[1] = p[2] * math.cos(p[3] * s) - p[0] * y[1] - p[1] * y[0]


@njit
def _jac(s, y, p, mode, J):
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0] = -p[1]
    J[1, 1] = -p[0]


@njit
def _switches(s, y, p, mode, g):
    g[0] = y[1]


@njit
def _transition(s, y, p, mode, which):
    return


@njit
def _init_mode(s, y, p, mode):
    mode[0] = 0


@pytest.mark.slow  # compiles a user model's kernel
def test_user_model_reproduces_linear_oscillator_steady_state():
    """A damped forced linear oscillator given as numba functions (Model.from_functions)
    is integrated by the generic kernel: its strobe equals the closed-form steady state to
    1e-9 and its velocity observer logs one maximum of x per period."""
    model = vi.Model.from_functions("linear", _rhs, _jac, _switches, _transition, _init_mode,
                                    terminal=[0], state_names=("x", "v"),
                                    param_names=("c", "k", "F", "w"), omega_index=3)
    c, k, F, w = 0.3, 1.0, 0.5, 1.7
    run = vi.simulate(np.array([c, k, F, w]), periods=10, transient=60, model=model)
    a = F / (k - w ** 2 + 1j * c * w)
    assert run.ok
    np.testing.assert_allclose(run.strobe[:, 0], a.real, atol=1e-9)
    np.testing.assert_allclose(run.strobe[:, 1], (1j * w * a).real, atol=1e-9)
    maxima = run.events["state"][run.events["which"] == 0, 0]
    assert len(maxima) == 10
    np.testing.assert_allclose(maxima, abs(a), atol=1e-9)


@njit
def _rhs_scratch(s, y, p, mode, out):
    # the same field through an allocated work array: user functions may allocate even
    # though the kernel calling them is compiled without numba's runtime
    a = np.empty(2)
    a[0] = y[1]
    a[1] = p[2] * math.cos(p[3] * s) - p[0] * y[1] - p[1] * y[0]
    out[0] = a[0]
    out[1] = a[1]


def _linear(rhs):
    return vi.Model.from_functions("linear", rhs, _jac, _switches, _transition, _init_mode,
                                   terminal=[0], state_names=("x", "v"),
                                   param_names=("c", "k", "F", "w"), omega_index=3)


@pytest.mark.slow  # a user model compiles its whole kernel in every process
def test_user_model_functions_may_allocate():
    """A user right-hand side that allocates a work array compiles under the kernel's
    runtime-free stage loop (it is called through a trampoline with the runtime on) and
    gives the same numbers, bit for bit, as the one that does not allocate."""
    p = np.array([0.3, 1.0, 0.5, 1.7])
    a = vi.simulate(p, periods=20, model=_linear(_rhs))
    b = vi.simulate(p, periods=20, model=_linear(_rhs_scratch))
    assert a.ok and b.ok
    np.testing.assert_array_equal(a.strobe, b.strobe)


@pytest.mark.slow  # a user model compiles its whole kernel in every process
def test_user_model_lyapunov_spectrum_equals_damping_rate():
    """The variational equations of a user model (its Jacobian allocated per evaluation,
    its saltation map per event) give the linear oscillator's exponents: both equal to
    the real part -c/2 of its eigenvalues (underdamped, c^2 < 4k)."""
    from vibimpact.analysis import Averaging, lyapunov_spectrum

    c = 0.3
    res = lyapunov_spectrum(vi.System(np.array([c, 1.0, 0.5, 1.7]), model=_linear(_rhs)),
                            averaging=Averaging(transient=10, min_periods=100,
                                                max_periods=100))
    assert res.status is vi.Status.OK
    np.testing.assert_allclose(res.exponents, [-c / 2, -c / 2], atol=2e-3)


#: the damped forced linear oscillator x'' + c x' + k x = F cos(w t), as a user model
#: and as the built-in Duffing oscillator (beta = 0), and the rotor far from its retainer
#: without cubic stiffness (two damped linear oscillators)
C, K, F, W = 0.3, 1.0, 0.5, 1.7
SYSTEMS = {
    "user model": lambda: (vi.System(np.array([C, K, F, W]), model=_linear(_rhs)), "w"),
    "duffing": lambda: (vi.System(vi.DuffingParams(delta=C, alpha=K, beta=0.0, gamma=F,
                                                   omega=W)), "omega"),
    "rotor": lambda: (vi.System(vi.presets.get("fig8").replace(eta=0.5, k3=0.0)), "eta"),
}


@pytest.mark.parametrize("name", [
    pytest.param(n, marks=pytest.mark.slow) if n == "user model" else n  # compiles its kernel
    for n in SYSTEMS])
def test_every_model_goes_through_the_analysers_as_a_system(name):
    """A user model, the built-in Duffing oscillator and the rotor go through shooting,
    the Lyapunov spectrum and continuation the same way, as a System: the shot orbit is
    the closed-form steady state (linear oscillators), its multipliers have modulus
    exp(-c T / 2), the exponents are -c/2 (the orbit's Floquet exponents, found by the
    spectrum's periodic-orbit watch), and every continued orbit is the steady state at
    its frequency."""
    from vibimpact.analysis import (Averaging, Steps, continue_orbit, lyapunov_spectrum,
                                    shoot_periodic_orbit)

    system, param = SYSTEMS[name]()
    x0 = system.simulate(periods=1, transient=100).final_state
    orb = shoot_periodic_orbit(system, x0)
    assert orb.converged and orb.stable and orb.minimal_period == 1
    rate = system.param("B") / 2 if name == "rotor" else C / 2
    np.testing.assert_allclose(np.abs(orb.multipliers), math.exp(-rate * system.period),
                               rtol=1e-8)
    res = lyapunov_spectrum(system, averaging=Averaging(transient=50, max_periods=2000))
    assert res.status is vi.Status.OK and res.floquet_n == 1
    np.testing.assert_allclose(res.exponents, -rate, atol=1e-8)
    br = continue_orbit(system, orb.state, param=param, stop=system.omega + 0.05,
                        steps=Steps(ds=0.01, max_points=4))
    assert br.param == param and br.values.size == 4 and br.stable.all()
    assert np.all(np.diff(br.values) > 0)
    if name == "rotor":
        return
    for w, x in zip(br.values, br.states):
        a = F / (K - w ** 2 + 1j * C * w)
        np.testing.assert_allclose(x, [a.real, (1j * w * a).real], atol=1e-8)
    a = np.abs(F / (K - br.values ** 2 + 1j * C * br.values))
    np.testing.assert_allclose(br.amplitude["x_m"], a, rtol=1e-3)
