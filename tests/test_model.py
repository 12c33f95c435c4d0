"""The model of eq. (5): parameters, presets, Jacobian, friction and fault handling."""
import math

import numpy as np
import pytest

import vibimpact as vi
from vibimpact._kernel import duffing, rotor, tableaux

STICK = vi.Params(G=1.5, f=0.3, Ec=0.3, eta=0.8, kh=120.0, B=0.1)


def test_from_dimensional_reproduces_paper_geometry():
    """Eq. (6) on the paper's data: r_h = 0.5 mm, R1 = 14 mm gives Rr = 28; the other
    groups follow their formulas."""
    m, k, rh = 2.0, 2.0e4, 0.5e-3
    p = vi.Params.from_dimensional(m=m, k=k, k2=-8000.0, b=20.0, kh=1.0e8, bh=0.0, bt=2.0,
                                   f=0.05, R1=14e-3, e=0.05e-3, rh=rh, g=9.81, omega=100.0)
    assert p.Rr == pytest.approx(28.0)
    assert p.Ec == pytest.approx(0.1)
    assert p.B == pytest.approx(20.0 / math.sqrt(k * m))
    assert p.BT == pytest.approx(2.0 / math.sqrt(k * m))
    assert p.k3 == pytest.approx(rh ** 2 * -8000.0)
    assert p.kh == pytest.approx(math.sqrt(rh) * 1.0e8 / k)
    assert p.G == pytest.approx(m * 9.81 / (k * rh))
    assert p.eta == pytest.approx(100.0 * math.sqrt(m / k))


@pytest.mark.parametrize("name,value", [("kh", -1.0), ("B", -0.1), ("Bh", -1.0), ("BT", -1.0),
                                        ("f", -0.1), ("Ec", -0.1), ("eta", 0.0),
                                        ("eta", -1.0), ("Rr", -1.0), ("kh", float("nan")),
                                        ("G", float("inf")), ("k3", "a")])
def test_invalid_parameters_raise_value_error_naming_them(name, value):
    """Values outside the model's domain raise ValueError whose message names the
    parameter."""
    with pytest.raises(ValueError, match=name):
        vi.presets.get("fig8").replace(**{name: value})


def test_unknown_parameter_and_preset_are_named():
    """An unknown parameter or preset name is refused with its name in the message."""
    with pytest.raises(ValueError, match="kappa"):
        vi.presets.get("fig8").replace(kappa=1.0)
    with pytest.raises(ValueError, match="fig99"):
        vi.presets.get("fig99")


def test_presets_match_spec_table():
    """Every paper preset (one per figure of the paper) exists with its kh, G, Bh, BT, f,
    Rr and k3, and they come first among all presets (the other models' follow)."""
    expect = {"fig4": (10, 0, 0, 0, 0, 0), "fig5": (10, 0.3, 0, 0, 0, 0),
              "fig6": (40, 0.3, 0, 0, 0, 0), "fig7": (80, 0.3, 0, 0, 0, 0),
              "fig8": (120, 0.3, 0, 0, 0, 0), "fig9": (120, 0.3, 0.05, 0, 0, 0),
              "fig10": (120, 0.3, 0, 0.05, 0, 0), "fig11": (120, 0.3, 0, 0, 0.05, 0),
              "rr10": (120, 0.3, 0, 0, 0.05, 10)}
    from vibimpact.builtin_models import rotor as rotor_model

    assert rotor_model.paper_names() == list(expect)
    assert vi.presets.names()[:len(expect)] == list(expect)
    for name, row in expect.items():
        p = vi.presets.get(name)
        assert (p.kh, p.G, p.Bh, p.BT, p.f, p.Rr) == row
        assert p.k3 == -0.002


def test_params_are_frozen_and_vector_follows_field_order():
    """Params cannot be mutated; as_array follows the kernel's parameter layout."""
    p = vi.presets.get("fig10")
    with pytest.raises(Exception):
        p.kh = 3.0
    assert list(p.as_array()) == [getattr(p, n) for n in rotor.PARAM_NAMES]


@pytest.mark.parametrize("method", ["rk4", "dp5", "dop853"])
def test_tableaux_satisfy_basic_order_conditions(method):
    """Consistency and low-order conditions of each tableau: rows of A sum to c,
    sum b = 1, b.c = 1/2, b.c^2 = 1/3, b.c^3 = 1/4, b.A c = 1/6."""
    A, b, c = {"rk4": (tableaux.RK4_A, tableaux.RK4_B, tableaux.RK4_C),
               "dp5": (tableaux.DP5_A[:6, :6], tableaux.DP5_B[:6], tableaux.DP5_C[:6]),
               "dop853": (tableaux.DOP853_A[:12, :12], tableaux.DOP853_B,
                          tableaux.DOP853_C[:12])}[method]
    np.testing.assert_allclose(A.sum(axis=1), c, atol=1e-14)
    for q, rhs in ((0, 1.0), (1, 1 / 2), (2, 1 / 3), (3, 1 / 4)):
        assert b @ c ** q == pytest.approx(rhs, abs=1e-14)
    assert b @ A @ c == pytest.approx(1 / 6, abs=1e-14)


def _fd_jacobian(fun, s, y, p, mode, n):
    J = np.empty((n, n))
    f1, f2 = np.empty(n), np.empty(n)
    for j in range(n):
        d = 1e-6 * max(1.0, abs(y[j]))
        yp, ym = y.copy(), y.copy()
        yp[j] += d
        ym[j] -= d
        fun(s, yp, p, mode, f1)
        fun(s, ym, p, mode, f2)
        J[:, j] = (f1 - f2) / (2 * d)
    return J


@pytest.mark.parametrize("mode,pars", [
    ((0, 0), dict()),
    ((1, 0), dict(BT=0.05, Bh=0.05)),
    ((1, 1), dict(f=0.1, BT=0.05, Bh=0.05, Rr=10.0)),
    ((1, -1), dict(f=0.1, BT=0.05)),
    ((1, 0), dict(f=0.3, BT=0.05, Bh=0.05)),     # Filippov stick
    ((1, 0), dict(f=0.3, BT=0.05, eps=0.05)),    # regularised friction
])
def test_analytic_jacobian_matches_finite_differences(mode, pars):
    """The analytic Jacobian of eq. (5) equals central finite differences of the RHS in
    every mode (free, contact with radial/tangential damping, slip both ways, stick,
    regularised friction) to 1e-6 relative."""
    p = vi.presets.get("fig8").replace(eta=1.23, **pars).as_array()
    y = np.array([0.4, 0.95, 0.3, -0.7])
    md = np.array(mode, dtype=np.int64)
    J = np.empty((4, 4))
    rotor.jac(2.1, y, p, md, J)
    Jfd = _fd_jacobian(rotor.rhs, 2.1, y, p, md, 4)
    np.testing.assert_allclose(J, Jfd, rtol=1e-6, atol=1e-6 * np.abs(Jfd).max())


def test_duffing_jacobian_matches_finite_differences():
    """The Duffing model's Jacobian equals finite differences of its RHS."""
    p = vi.DuffingParams().as_array()
    y = np.array([0.7, -0.3])
    md = np.zeros(1, dtype=np.int64)
    J = np.empty((2, 2))
    duffing.jac(0.4, y, p, md, J)
    np.testing.assert_allclose(J, _fd_jacobian(duffing.rhs, 0.4, y, p, md, 2), rtol=1e-7)


def test_stick_phases_hold_zero_tangential_speed():
    """With f = 0.3 and Rr = 0 the rotor sticks on the retainer: stick phases occur
    (friction state 0) and during a stick phase v_t stays 0 (Filippov sliding), without
    chattering (fewer than 300 steps per period)."""
    run = vi.simulate(STICK, periods=10, transient=20, state0=[0, 1.01, 0, 0], dense=200)
    assert run.ok
    after = run.events["mode_after"]
    assert np.sum(after[:, 1] == 0) >= 5
    assert run.counters["steps"] / 30 < 300
    # the state at a stick->slip transition still has v_t = 0
    ev = run.events
    leave = (ev["which"] == 1) & (ev["mode_before"][:, 1] == 0)
    y = ev["state"][leave]
    vt = (y[:, 3] * y[:, 0] - y[:, 2] * y[:, 1]) / np.hypot(y[:, 0], y[:, 1])
    assert leave.sum() >= 3
    assert np.abs(vt).max() < 1e-8


def test_regularised_friction_converges_to_stick_slip_solution():
    """The tanh(v_t/eps) law converges to the Filippov solution as eps -> 0, at first
    order: each tenfold decrease of eps cuts the strobe difference by at least 5x."""
    ref = vi.simulate(STICK, periods=10, transient=20, state0=[0, 1.01, 0, 0])
    err = [np.abs(vi.simulate(STICK.replace(eps=eps), periods=10, transient=20,
                              state0=[0, 1.01, 0, 0]).strobe - ref.strobe).max()
           for eps in (1e-2, 1e-3, 1e-4)]
    assert err[0] / err[1] > 5 and err[1] / err[2] > 5
    assert err[2] < 1e-3


def test_blow_up_is_reported_as_diverged_not_as_data():
    """A run whose state runs away ends with status DIVERGED and a reason, and returns no
    NaN: a rotor without retainer (kh = 0) in a strongly softening support (k3 = -5), and a
    Duffing oscillator with a repelling cubic term (finite-time blow-up)."""
    p = vi.presets.get("fig8").replace(kh=0.0, k3=-5.0, eta=1.0, Ec=0.5)
    runs = [vi.simulate(p, periods=50, state0=[0.0, 0.0, 3.0, 0.0]),
            vi.simulate(vi.DuffingParams(alpha=1.0, beta=-1.0, gamma=0.1), periods=50,
                        state0=[2.0, 0.0])]
    for run in runs:
        assert run.status is vi.Status.DIVERGED
        assert "bound" in run.reason or "finite" in run.reason
        assert np.all(np.isfinite(run.strobe))
        assert len(run.strobe) < 51


def test_simulate_rejects_bad_arguments_by_name():
    """simulate (and the solver settings it takes) raise ValueError naming a bad
    argument."""
    p = vi.presets.get("fig8")
    for kw, name in ((dict(periods=0), "periods"), (dict(transient=-1), "transient"),
                     (dict(state0=[1, 2]), "state0"), (dict(periods=2.5), "periods")):
        with pytest.raises(ValueError, match=name):
            vi.simulate(p, **kw)
    for kw, name in ((dict(method="euler"), "method"), (dict(rtol=0.0), "rtol")):
        with pytest.raises(ValueError, match=name):
            vi.simulate(p, solver=vi.SolverSettings(**kw))
