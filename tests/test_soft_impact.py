"""The soft-impact oscillator, a built-in model declared as data (its kernel module, its
module in vibimpact.builtin_models, these tests), checked against published results: the
analytic linear response below grazing and the order-3/2 correction past grazing of a
piecewise-smooth continuous flow (di Bernardo, Budd & Champneys 2001, Physica D 160,
222-254); and a user model declaring the same contact gets the same impacts and arcs in
a sweep."""
import math

import numpy as np
import pytest
from numba import njit

import vibimpact as vi
from vibimpact import models
from vibimpact.analysis import shoot_periodic_orbit
from vibimpact.models.contact import Contact, ContactLaw

MODEL = models.get("soft_impact")
P = MODEL.param_set


def _linear(p):
    """Amplitude and stroboscopic point (t = 0 mod T) of the linear steady state."""
    w = p.eta
    den = (1.0 - w * w) ** 2 + (2.0 * p.zeta * w) ** 2
    x0 = p.A * (1.0 - w * w) / den
    v0 = p.A * 2.0 * p.zeta * w * w / den
    return p.A / math.sqrt(den), np.array([x0, v0])


def _grazing_eta(p):
    """The forcing frequency below resonance where the linear amplitude equals d."""
    lo, hi = 0.3, 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if _linear(p.replace(eta=mid))[0] < p.d:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def test_registry_finds_the_soft_impact_oscillator_and_its_presets():
    """A built-in model added as data is in the registry, its presets in presets.names(),
    its parameter set validates against its domains and pickles (for worker
    processes)."""
    import pickle

    assert "soft_impact" in models.names()
    assert {"soft-impact", "soft-impact-grazing"} <= set(vi.presets.names())
    p = vi.presets.get("soft-impact")
    assert isinstance(p, P) and models.of_params(p) is MODEL
    assert pickle.loads(pickle.dumps(p)) == p
    with pytest.raises(ValueError, match="zeta"):
        P(zeta=-0.1)
    with pytest.raises(ValueError, match="eta"):
        P(eta=0.0)


def test_below_grazing_the_orbit_is_the_analytic_linear_response():
    """Below grazing (linear amplitude < d) the stop is never touched: the stroboscopic
    fixed point equals the linear oscillator's analytic steady state to 1e-9 and no
    impact is recorded."""
    p = vi.presets.get("soft-impact")
    amp, x_lin = _linear(p)
    assert amp < p.d
    run = vi.simulate(p, periods=5, transient=400)
    assert run.impacts.size == 0
    np.testing.assert_allclose(run.strobe[-1], x_lin, atol=1e-9)


def test_grazing_splits_impactless_and_one_impact_orbits_at_the_analytic_frequency():
    """With a soft stop (k = 5, where the impacting period-1 orbit is stable past grazing;
    at the presets' k = 29 it gives way to longer periods at once) the sweep labels the
    period-1 orbit impactless just below the analytic grazing frequency (linear amplitude
    = d) and with one impact per period, on one arc, just above it."""
    p = vi.presets.get("soft-impact").replace(k=5.0)
    eg = _grazing_eta(p)
    ds = vi.sweep(vi.System(p), eta=[eg - 0.004, eg + 0.004])
    assert ds["period"].values.ravel().tolist() == [1, 1]
    assert ds["impacts_per_period"].values.ravel().tolist() == [0.0, 1.0]
    assert ds["n_arcs"].values.ravel().tolist() == [0, 1]


def test_past_grazing_the_orbit_moves_by_the_three_halves_power_of_the_penetration():
    """Past grazing an undamped spring stop (a continuous vector field with a
    discontinuous Jacobian) changes the period-1 orbit by a term of order 3/2 in the
    distance delta past grazing (di Bernardo, Budd & Champneys 2001): the local log-log
    slope of the orbit's shift from the linear one against delta tends to 3/2 as delta
    goes to 0 -- its error shrinks decade by decade (the next order is delta^(1/2) smaller)
    and is below 0.03 on the smallest decade."""
    base = vi.presets.get("soft-impact")
    amp, x_lin = _linear(base)
    deltas = np.array([1e-7, 1e-6, 1e-5, 1e-4])
    shifts = []
    for delta in deltas:
        p = base.replace(d=amp - delta)
        orb = shoot_periodic_orbit(vi.System(p), x_lin, 1, tol=1e-14)
        assert orb.converged
        shifts.append(float(np.linalg.norm(orb.state - x_lin)))
    slopes = np.diff(np.log(shifts)) / np.diff(np.log(deltas))
    errors = np.abs(slopes - 1.5)
    assert np.all(np.diff(errors) > 0), slopes
    assert errors[0] < 0.03, slopes


@njit
def _rhs(s, y, p, mode, out):
    a = p[4] * math.cos(p[5] * s) - 2.0 * p[0] * y[1] - y[0]
    if mode[0] == 1:
        a -= p[1] * (y[0] - p[3]) * (1.0 + p[2] * y[1])
    out[0] = y[1]
    out[1] = a


@njit
def _jac(s, y, p, mode, J):
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0] = -1.0 - (p[1] * (1.0 + p[2] * y[1]) if mode[0] == 1 else 0.0)
    J[1, 1] = -2.0 * p[0] - (p[1] * (y[0] - p[3]) * p[2] if mode[0] == 1 else 0.0)


@njit
def _switches(s, y, p, mode, g):
    g[0] = y[0] - p[3] if mode[0] == 1 else p[3] - y[0]
    g[1] = y[1]


@njit
def _transition(s, y, p, mode, which):
    if which == 0:
        mode[0] = 1 - mode[0]


@njit
def _init_mode(s, y, p, mode):
    mode[0] = 1 if y[0] > p[3] else 0


@pytest.mark.slow  # a user model compiles its whole kernel in every process
def test_a_user_model_that_declares_its_contact_gets_impacts_and_arcs_in_a_sweep():
    """A user model (Model.from_functions) with the soft-impact oscillator's functions and
    a declared Contact gets impact records from simulate, and impacts per period and
    contact arcs in a sweep, equal to the built-in model's."""
    user = vi.Model.from_functions(
        "my_stop", _rhs, _jac, _switches, _transition, _init_mode, [1, 0],
        ("x", "dx"), MODEL.param_names, omega_index=5,
        contact=Contact(switch=0, mode=0, penetration=lambda q, p: q[:, 0] - p[3],
                        normal_speed=lambda q, p: q[:, 1].copy(),
                        angle=lambda q, p: np.zeros(q.shape[0]), extremum=1,
                        positions=(0,), law=ContactLaw(stiffness="k", exponent=1.0)))
    p = vi.presets.get("soft-impact-grazing").replace(k=5.0)
    vec = p.as_array()
    run = vi.simulate(vec, periods=10, transient=300, model=user)
    ref = vi.simulate(p, periods=10, transient=300)
    assert run.impacts.size == ref.impacts.size > 0
    np.testing.assert_allclose(run.impacts["penetration"], ref.impacts["penetration"],
                               rtol=1e-6)
    eg = _grazing_eta(p)
    ds = vi.sweep(vi.System(vec, model=user), eta=[eg - 0.004, eg + 0.004])
    assert ds["impacts_per_period"].values.ravel().tolist() == [0.0, 1.0]
    assert ds["n_arcs"].values.ravel().tolist() == [0, 1]


def test_a_contact_that_does_not_fit_its_model_is_refused():
    """A contact declaration naming a switch, mode entry or law parameter the model does
    not have is a ValueError naming the contact."""
    law = ContactLaw(stiffness="k", exponent=1.0)
    kw = dict(penetration=lambda q, p: q[:, 0], normal_speed=lambda q, p: q[:, 1],
              angle=lambda q, p: q[:, 0] * 0.0, positions=(0,))
    for bad in (Contact(switch=5, mode=0, law=law, **kw),
                Contact(switch=0, mode=3, law=law, **kw),
                Contact(switch=0, mode=0, law=ContactLaw(stiffness="kh"), **kw)):
        with pytest.raises(ValueError, match="contact"):
            vi.Model.from_functions("bad", _rhs, _jac, _switches, _transition, _init_mode,
                                    [1, 0], ("x", "dx"), MODEL.param_names, omega_index=5,
                                    contact=bad)
