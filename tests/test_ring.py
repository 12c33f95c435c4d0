"""The rotor with a turning retainer ring (model ``ring``, :mod:`vibimpact._kernel.ring`).

Known values the model must reproduce: eq. (5) when the ring is held (huge ``Jr``, or a
bearing that never lets it turn), with a deviation of order ``1/Jr`` for a heavy ring;
rolling without slip, at zero friction power, for a free ring driven by a rotor in
permanent contact; the energy balance (the change of the energy equals the work of the
unbalance and of the shaft's drive less every dissipation, integrated along the run by a
user model wrapping the ring's kernel); Floquet multipliers that the Lyapunov spectrum
reproduces, with a multiplier 0 (exponent -inf) for a stuck ring; and the Filippov
invariants of the stick/slip and stuck/turning modes along runs.
"""
import math

import numpy as np
import pytest
from numba import njit

import vibimpact as vi
from vibimpact._kernel import ring as K
from vibimpact._kernel.rotor import PARAM_NAMES as ROTOR_NAMES
from vibimpact.analysis import (Averaging, lyapunov_spectrum, shoot_periodic_orbit,
                                strobe_map_jacobian)
from vibimpact.builtin_models.ring import RingParams

TIGHT = vi.SolverSettings(rtol=1e-12, atol=1e-14)
#: an impacting start (the rotor of eq. (5)); the ring at rest is appended
X0 = [0.5, 0.9, 0.5, 0.0]


def ring(fig, **kw):
    return vi.presets.get(f"{fig}-ring").replace(**kw)


def slip(states, p):
    """Slip velocity ``v_s = (X dY - Y dX)/R + Rr eta - Vr`` of states ``(m, >= 5)``."""
    X, Y, U, V, W = (states[:, j] for j in range(5))
    return (X * V - Y * U) / np.hypot(X, Y) + p.Rr * p.eta - W


def terminal_events(run):
    """Times and modes after of the run's mode changes (observer events left out)."""
    ev = run.events
    k = np.flatnonzero(ev["which"] != K.SW_EXTREMUM)
    return ev["t"][k], ev["mode_after"][k], ev["state"][k]


# -- 1. the held ring is eq. (5) ----------------------------------------------------------

@pytest.mark.parametrize("fig, eta", [("fig8", 1.06), ("fig8", 1.1), ("fig10", 1.06),
                                      ("fig11", 1.0)])
def test_held_or_stuck_ring_reproduces_eq5(fig, eta):
    """Hypothesis: a ring of inertia Jr = 1e14 (its acceleration T/Jr ~ 1e-14) and a ring
    whose bearing holds it (Mr = 1e6, Jr = 1: stuck, Vr = 0) give eq. (5)'s motion: from
    the same impacting state, ring at rest, the (X, Y, dX, dY) strobe over 20 periods
    equals eq. (5)'s (same preset and eta, rtol 1e-12) to 1e-10 (non-chaotic eta; the
    integration paths differ by rounding only), and the stuck ring's Vr is exactly 0 at
    every strobe and every event."""
    eq5 = vi.simulate(vi.presets.get(fig).replace(eta=eta), periods=20, state0=X0,
                      solver=TIGHT)
    assert eq5.ok and len(eq5.impacts) >= 10
    for kw in (dict(Jr=1e14), dict(Jr=1.0, Mr=1e6)):
        run = vi.simulate(ring(fig, eta=eta, **kw), periods=20, state0=X0 + [0.0],
                          solver=TIGHT)
        assert run.ok, (kw, run.reason)
        assert np.abs(run.strobe[:, :4] - eq5.strobe).max() < 1e-10, kw
    stuck = run  # the last one
    assert np.all(stuck.strobe[:, 4] == 0.0) and np.all(stuck.events["state"][:, 4] == 0.0)


@pytest.mark.parametrize("fig", ["fig10", "fig11"])
def test_heavy_ring_deviates_from_eq5_like_one_over_Jr(fig):
    """Hypothesis: a heavy free ring (Mr = 0) picks up a speed Vr ~ t T / Jr, so the
    rotor's deviation from eq. (5) over 20 periods (eta = 1.06, periodic: no chaotic
    amplification) is proportional to 1/Jr: the log-log slope over Jr = 1e3, 1e5, 1e7 is
    -1 within 0.02, with the deviation at 1e7 over 100 times the held ring's (the
    integration error)."""
    eta = 1.06
    eq5 = vi.simulate(vi.presets.get(fig).replace(eta=eta), periods=20, state0=X0,
                      solver=TIGHT).strobe
    Jrs = np.array([1e3, 1e5, 1e7, 1e14])
    dev = np.array([np.abs(vi.simulate(ring(fig, eta=eta, Jr=Jr, Mr=0.0), periods=20,
                                       state0=X0 + [0.0], solver=TIGHT).strobe[:, :4]
                           - eq5).max() for Jr in Jrs])
    slope = np.polyfit(np.log(Jrs[:3]), np.log(dev[:3]), 1)[0]
    assert abs(slope + 1.0) < 0.02, (slope, dev)
    assert dev[2] > 100 * dev[3], dev


# -- 2. a free ring rolls ------------------------------------------------------------------

#: rotor in permanent contact (no weight, unbalance driving a synchronous whirl past the
#: clearance) on a free ring with a frictionless bearing, shaft radius 10
ROLL = dict(G=0.0, Ec=2.0, eta=1.5, Rr=10.0, BT=0.0, f=0.05, cr=0.0, Mr=0.0)
ROLL_X0 = [1.0, 0.0, 0.0, 1.5, 0.0]
ROLL_PERIODS, ROLL_LATE = 40, 10


def test_free_ring_spins_up_to_rolling_without_slip():
    """Hypothesis: with cr = Mr = 0 nothing holds the ring back, so the contact's
    friction spins it up from rest until the slip v_s = L/R + Rr eta - Vr vanishes: the
    motion ends sticking (mode [1, 0, 1]: contact, rolling, turning) with no mode change
    over the last 10 of 40 periods (permanent contact), |v_s| < 1e-8 at their strobes,
    and the ring's speed is the shaft surface's, about (1 + Rr) eta."""
    p = ring("fig11", **ROLL)
    run = vi.simulate(p, periods=ROLL_PERIODS, state0=ROLL_X0, solver=TIGHT)
    assert run.ok
    t, modes, _ = terminal_events(run)
    late = run.t_strobe[-ROLL_LATE - 1]
    assert modes[-1].tolist() == [1, 0, 1] and t[-1] < late
    assert np.abs(slip(run.strobe[-ROLL_LATE - 1:], p)).max() < 1e-8
    assert abs(run.strobe[-1, 4] / ((1 + p.Rr) * p.eta) - 1) < 0.05


# -- 3. the energy balance, through a user model wrapping the ring's kernel --------------

#: accumulated works: unbalance, shaft drive; dissipations: support, Hertz damping,
#: contact (friction and tangential damping), ring's bearing
ACC = ("W_unbalance", "W_drive", "D_support", "D_hertz", "D_contact", "D_ring")
I_UNB, I_DRV, I_SUP, I_HZ, I_CON, I_RNG = range(5, 5 + len(ACC))


@njit
def _e_rhs(s, y, p, mode, out):
    K.rhs(s, y[:5], p, mode, out[:5])
    T, Wd, Fr, vs, lam = K._forces(s, y, p, mode[0], mode[1], mode[2])
    X, Y, U, V, W = y[0], y[1], y[2], y[3], y[4]
    eta = p[9]
    out[5] = p[7] * eta * eta * (math.cos(eta * s) * U + math.sin(eta * s) * V)
    out[7] = p[0] * (U * U + V * V)
    out[6] = out[8] = out[9] = 0.0
    R = math.sqrt(X * X + Y * Y)
    if mode[0] == 1:
        out[6] = -T * p[6] * eta
        out[9] = -T * vs
        if R > 1.0:
            Rd = (X * U + Y * V) / R
            out[8] = p[2] * (R - 1.0) ** 1.5 * p[3] * Rd * Rd
    out[10] = 0.0
    if not (p[13] > 0.0 and mode[2] == 0):  # a stuck ring does no work (Vr = 0)
        out[10] = p[12] * W * W + p[13] * mode[2] * W


@njit
def _e_jac(s, y, p, mode, J):
    J[:, :] = 0.0
    K.jac(s, y[:5], p, mode, J[:5, :5])


@njit
def _e_switches(s, y, p, mode, g):
    K.switches(s, y[:5], p, mode, g)


@njit
def _e_transition(s, y, p, mode, which):
    K.transition(s, y[:5], p, mode, which)  # a view: Vr set to 0 reaches the state


@njit
def _e_init_mode(s, y, p, mode):
    K.init_mode(s, y[:5], p, mode)


@pytest.fixture(scope="module")
def energy_model():
    return vi.Model.from_functions(
        "ring energy", _e_rhs, _e_jac, _e_switches, _e_transition, _e_init_mode,
        terminal=K.TERMINAL, state_names=("X", "Y", "dX", "dY", "Vr") + ACC,
        param_names=K.PARAM_NAMES, omega_index=9, n_mode=K.N_MODE, bound=1e9)


def energy(y, p):
    """E = |v|^2/2 + R^2/2 + k3 R^4/4 + 2/5 kh (R-1)^{5/2} H(R-1) - G Y + Jr Vr^2/2."""
    X, Y, U, V, W = y[:5]
    R = math.hypot(X, Y)
    return (0.5 * (U * U + V * V) + 0.5 * R * R + 0.25 * p.k3 * R ** 4
            + 0.4 * p.kh * max(R - 1.0, 0.0) ** 2.5 - p.G * Y + 0.5 * p.Jr * W * W)


def balance(model, p, periods, x0):
    """Run with the accumulators; returns (run, E(end) - E(0), inputs, dissipations)."""
    run = vi.simulate(p.as_array(), periods=periods, state0=list(x0) + [0.0] * len(ACC),
                      model=model, solver=TIGHT)
    y = run.final_state
    return (run, energy(y, p) - energy(np.asarray(x0, float), p), y[I_UNB] + y[I_DRV],
            y[[I_SUP, I_HZ, I_CON, I_RNG]].sum())


ALL_ON = dict(Bh=0.2, BT=0.05, f=0.1, Rr=5.0, cr=0.01, Mr=0.01, Jr=0.5)


@pytest.mark.slow  # a user model's kernel is compiled in the process (reports/performance.md, section first_run)
@pytest.mark.parametrize("fig, kw", [("fig8", {}), ("fig10", {}), ("fig11", {}),
                                     ("fig11", ALL_ON)])
def test_energy_balance_of_impacting_runs(energy_model, fig, kw):
    """Hypothesis: along any run, E(end) - E(0) equals the unbalance's work plus the
    drive's (-T Rr eta through the shaft's spin) less the support damping (B|v|^2), the
    Hertz damping (kh (R-1)^{3/2} Bh R'^2), the contact's friction and tangential damping
    (-T v_s) and the ring bearing's drag (cr Vr^2 + Mr|Vr|): to 1e-8, absolute and
    relative to the input, over 20 impacting periods at rtol 1e-12 (eta = 1.06), for the
    three presets and for one with Bh, BT, f, Rr, cr, Mr all non-zero (stick, slip, a
    stuck and a turning ring).  Without the drive's term that last run misses by more than
    1 (the drive is most of its input)."""
    p = ring(fig, eta=1.06, **kw)
    run, dE, inp, diss = balance(energy_model, p, 20, X0 + [0.0])
    assert run.ok and int(np.sum(run.events["which"] == K.SW_CONTACT)) >= 20
    assert abs(dE - (inp - diss)) < 1e-8 and abs(dE - (inp - diss)) < 1e-8 * inp
    if kw:
        _, modes, _ = terminal_events(run)
        assert {0, 1} <= set(modes[:, 1]) and {0, 1} <= set(modes[:, 2])
        assert abs(dE - (inp - run.final_state[I_DRV] - diss)) > 1.0


@pytest.mark.slow  # a user model's kernel is compiled in the process (reports/performance.md, section first_run)
def test_rolling_ring_dissipates_nothing(energy_model):
    """Hypothesis: once the free ring rolls without slip (test above), the contact's
    friction does no work (v_s = 0): its integrated power over the last 10 of 40 periods
    is below 1e-10, while the spin-up dissipated a finite amount (> 0.1); the balance
    of the whole run holds to 1e-8."""
    p = ring("fig11", **ROLL)
    run, dE, inp, diss = balance(energy_model, p, ROLL_PERIODS, ROLL_X0)
    assert run.ok
    d = run.strobe[:, I_CON]
    assert abs(d[-1] - d[-ROLL_LATE - 1]) < 1e-10 and d[-1] > 0.1
    assert abs(dE - (inp - diss)) < 1e-8 * max(1.0, inp)


# -- 4. Floquet multipliers and Lyapunov exponents -----------------------------------------

def _orbit(p):
    x = vi.simulate(p, periods=1, transient=300, state0=X0 + [0.0]).final_state
    orb = shoot_periodic_orbit(vi.System(p), x)
    assert orb.converged and orb.stable and orb.minimal_period == 1
    return orb


def test_lyapunov_exponent_of_turning_ring_orbit_is_floquet_exponent():
    """Hypothesis: on the stable period-1 orbit of fig10-ring at eta = 1.06 (2 impacts
    per period, BT > 0 and f = 0: the ring turns all along, Vr ~ 0.73, never stuck) the
    shooting's multipliers (variational monodromy, saltation at every switch) equal the
    finite-difference Jacobian's of the strobe map to 1e-6 in modulus, none is 0, and the
    QR average of the largest Lyapunov exponent (floquet=False) equals ln|mu_max| / T
    within 2 % (the tolerance of eq. (5)'s test in test_analysis_lyapunov.py)."""
    p = ring("fig10", eta=1.06)
    orb = _orbit(p)
    run = vi.simulate(p, periods=2, state0=orb.state)
    _, modes, _ = terminal_events(run)
    assert len(run.impacts) >= 4 and np.all(modes[:, 2] == 1)
    assert run.strobe[:, 4].min() > 0.5
    sys_ = vi.System(p)
    mu = np.sort(np.abs(orb.multipliers))
    fd = np.sort(np.abs(np.linalg.eigvals(strobe_map_jacobian(sys_, orb.state))))
    np.testing.assert_allclose(mu, fd, rtol=0, atol=1e-6)
    assert mu[0] > 0.1
    res = lyapunov_spectrum(sys_, state0=orb.state, floquet=False, averaging=Averaging(
        transient=0, min_periods=300, max_periods=1500, target_stderr=5e-4))
    floquet = math.log(mu[-1]) / sys_.period
    assert res.floquet_n == 0 and abs(res.exponents[0] - floquet) <= 0.02 * abs(floquet)


def test_stuck_ring_orbit_has_multiplier_zero():
    """Hypothesis: in fig8-ring (f = BT = 0: no tangential force, Mr > 0) the ring stays
    stuck, and a stuck bearing attracts a nudged ring back to Vr = 0 in finite time, so
    the monodromy of the period-1 orbit at eta = 1.06 has the multiplier 0 for the ring
    (not 1, and not a small number) besides eq. (5)'s four (to 1e-8), and the Lyapunov
    spectrum's last exponent is -inf, both as Floquet exponents (default) and as QR
    averages, with an error of 0 and no invalid-value warning on the way."""
    import warnings

    p = ring("fig8", eta=1.06)
    orb = _orbit(p)
    mu = np.sort(np.abs(orb.multipliers))
    assert mu[0] == 0.0
    eq5 = shoot_periodic_orbit(vi.System(vi.presets.get("fig8").replace(eta=1.06)),
                               orb.state[:4])
    np.testing.assert_allclose(mu[1:], np.sort(np.abs(eq5.multipliers)), rtol=0, atol=1e-8)
    np.testing.assert_allclose(orb.state[:4], eq5.state, rtol=0, atol=1e-8)
    for floquet in (True, False):
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)
            res = lyapunov_spectrum(vi.System(p), state0=orb.state, floquet=floquet,
                                    averaging=Averaging(transient=0, min_periods=300,
                                                        max_periods=300))
        assert res.exponents[-1] == -np.inf and np.all(np.isfinite(res.exponents[:4]))
        assert res.stderr[-1] == 0.0


# -- 5. Filippov sanity --------------------------------------------------------------------

@njit
def _tangential_force(s, y, p, contact, sc, sr):
    return K._forces(s, y, p, contact, sc, sr)[0]


@pytest.mark.parametrize("eta", [1.02, 1.06, 1.2])
def test_stick_and_stuck_phases_are_filippov_consistent(eta):
    """Hypothesis: along a run of fig11-ring with a bearing that stops the ring between
    impacts (Mr = 0.02), on dense samples between mode changes: a stuck ring has Vr
    exactly 0 (also over free flights longer than a forcing period); a turning ring's
    Vr and a slipping contact's v_s keep their mode's sign (never reverse within a phase);
    a sticking contact keeps |v_s| < 1e-8; and a stuck ring is released only where the
    tangential force exceeds its bearing's hold, |T| > Mr."""
    p = ring("fig11", eta=eta, Mr=0.02)
    run = vi.simulate(p, periods=30, dense=200, state0=X0 + [0.0])
    assert run.ok
    t, modes, states = terminal_events(run)
    td = run.t_dense
    k = np.searchsorted(t, td, side="right") - 1
    keep = (k >= 0) & (np.abs(td[:, None] - t[None, :]).min(axis=1) > 1e-9)
    m, y = modes[k[keep]], run.dense[keep]
    vs, W = slip(y, p), y[:, 4]
    stuck, c = m[:, 2] == 0, m[:, 0] == 1
    assert np.all(W[stuck] == 0.0) and np.sum(stuck & ~c) > 1000
    gaps = np.diff(t)[(modes[:-1, 2] == 0) & (modes[:-1, 0] == 0)]
    assert gaps.max() > 2 * math.pi / eta
    assert np.all(m[~stuck, 2] * W[~stuck] > 0.0)
    sl, st = c & (m[:, 1] != 0), c & (m[:, 1] == 0)
    assert sl.sum() > 100 and np.all(m[sl, 1] * vs[sl] > 0.0)
    assert st.sum() > 50 and np.abs(vs[st]).max() < 1e-8
    ev = run.events
    pv = p.as_array()
    for i in np.flatnonzero((ev["mode_before"][:, 2] == 0) & (ev["mode_after"][:, 2] != 0)):
        mb = ev["mode_before"][i]
        T = _tangential_force(ev["t"][i], ev["state"][i], pv, mb[0], ev["mode_after"][i][1],
                              0)
        assert abs(T) >= p.Mr * (1 - 1e-9), (ev["t"][i], T)


GRID_SETTINGS = [dict(Jr=1.0, Mr=1e6), dict(Mr=0.0), dict(Jr=1e4), dict(Jr=0.005),
                 dict(Rr=10.0), dict(Jr=1.0, Mr=0.1), dict(Jr=1e14)]


@pytest.mark.parametrize("fig", ["fig10", "fig11"])
def test_robustness_grid_runs_end_ok(fig):
    """Hypothesis: at the eta where earlier kernel versions failed (1.06, 1.18, 1.27,
    1.31: step size underflow of a held ring, a stuck ring released, Zeno loops at a
    slip's own zero crossing), for a stuck, a drag-free, a heavy, a very light, a wide
    and a held ring and one with a strong bearing, at the default and at tight
    tolerances, every 30-period run from an impacting state ends Status.OK."""
    bad = []
    for eta in (1.06, 1.18, 1.27, 1.31):
        for kw in GRID_SETTINGS:
            for solver in (None, TIGHT):
                run = vi.simulate(ring(fig, eta=eta, **kw), periods=30,
                                  state0=X0 + [0.0], solver=solver)
                if run.status is not vi.Status.OK:
                    bad.append((eta, kw, solver is TIGHT, run.reason))
    assert not bad


# -- 6. the registry ----------------------------------------------------------------------

def test_registry_names_order_and_presets():
    """Hypothesis: the model 'ring' has state (X, Y, dX, dY, Vr), three mode entries,
    the parameters of eq. (5) in its order then Jr, cr, Mr (the kernel's order); its
    presets fig8-ring, fig10-ring, fig11-ring carry the paper presets' values for every
    name of eq. (5) (eta included) and the ring's own positive Jr."""
    m = vi.models.get("ring")
    assert m.state_names == ("X", "Y", "dX", "dY", "Vr") and m.n_mode == 3
    assert tuple(m.param_names) == ROTOR_NAMES + ("Jr", "cr", "Mr") == K.PARAM_NAMES
    assert m.param_names[m.omega_index] == "eta"
    assert sorted(m.presets) == ["fig10-ring", "fig11-ring", "fig8-ring"]
    for fig in ("fig8", "fig10", "fig11"):
        paper, ours = vi.presets.get(fig), vi.presets.get(f"{fig}-ring")
        assert isinstance(ours, RingParams)
        for name in ROTOR_NAMES:
            assert getattr(ours, name) == getattr(paper, name), (fig, name)
        assert ours.Jr > 0 and ours.cr >= 0 and ours.Mr >= 0


@pytest.mark.parametrize("name, value", [("Jr", 0.0), ("Jr", -1.0), ("cr", -1e-3),
                                         ("Mr", -1e-3)])
def test_out_of_range_ring_parameters_raise_naming_them(name, value):
    """Hypothesis: Jr <= 0, cr < 0, Mr < 0 are ValueErrors naming the parameter, both
    when a parameter set is built and when a preset is changed."""
    with pytest.raises(ValueError, match=rf"^{name} must be"):
        RingParams(**{name: value})
    with pytest.raises(ValueError, match=rf"^{name} must be"):
        vi.presets.get("fig11-ring").replace(**{name: value})


def test_rolling_contact_orbit_has_exponent_minus_infinity_by_both_routes():
    """Hypothesis: at fig11-ring, eta = 1.1, the period-1 orbit's contact rolls without
    slip for part of each period (a sliding mode entered in finite time), so one Floquet
    multiplier is zero to rounding (about 1e-16): the Floquet route reports its exponent
    as -inf with error 0, as the QR route does, instead of ln(1e-16)/T, a number set by
    rounding; the other four exponents are finite, and the routes agree on the largest
    and on the sum of the four (the log of the volume contraction, which the QR average
    of 300 periods resolves better than the pairs' split)."""
    p = ring("fig11", eta=1.1)
    x = vi.simulate(p, periods=1, transient=300, state0=X0 + [0.0]).final_state
    orb = shoot_periodic_orbit(vi.System(p), x)
    assert orb.converged and np.sort(np.abs(orb.multipliers))[0] < 1e-13
    fl = lyapunov_spectrum(vi.System(p), state0=orb.state)
    qr = lyapunov_spectrum(vi.System(p), state0=orb.state, floquet=False,
                           averaging=Averaging(transient=0, min_periods=300, max_periods=300))
    assert fl.exponents[-1] == -np.inf and fl.stderr[-1] == 0.0
    assert qr.exponents[-1] == -np.inf
    assert np.all(np.isfinite(fl.exponents[:4]))
    assert abs(fl.exponents[0] - qr.exponents[0]) < 5e-4
    assert abs(fl.exponents[:4].sum() - qr.exponents[:4].sum()) < 1e-4


def test_analytic_jacobian_matches_central_differences_in_every_mode():
    """Hypothesis: the ring kernel's analytic Jacobian (rotor rows on the slip velocity,
    the ring's row, the stick forces with the ring turning or stuck, tanh-regularised
    friction) equals central differences of its right-hand side within the mode, to the
    differences' own accuracy (1e-8 of the largest entry), at 1,500 random states in
    and out of contact, in every contact-friction and ring mode."""
    from vibimpact._kernel import ring as K

    rng = np.random.default_rng(1)
    base = vi.presets.get("fig11-ring").replace(Rr=3.0, BT=0.05, Bh=0.1)
    worst = 0.0
    seen = set()
    for trial in range(1500):
        p = base.replace(eta=rng.uniform(0.9, 1.5), eps=0.01 if trial % 5 == 0 else 0.0,
                         Mr=0.0 if trial % 7 == 0 else 0.01, cr=rng.uniform(0, 0.01),
                         Jr=10 ** rng.uniform(-2, 2)).as_array()
        ang = rng.uniform(0, 2 * np.pi)
        R = rng.uniform(0.5, 0.99) if trial % 2 else rng.uniform(1.01, 1.05)
        y = np.array([R * np.cos(ang), R * np.sin(ang), rng.normal(), rng.normal(),
                      0.5 * rng.normal()])
        mode = np.array([int(R > 1), rng.choice([-1, 0, 1]), rng.choice([-1, 0, 1])],
                        dtype=np.int64)
        mode[1] = mode[1] if mode[0] else 0
        mode[2] = mode[2] if p[13] > 0 else 1
        seen.add(tuple(mode))
        s = rng.uniform(0, 10)
        J = np.zeros((5, 5))
        K.jac(s, y, p, mode, J)
        fd = np.zeros((5, 5))
        fp, fm = np.zeros(5), np.zeros(5)
        for j in range(5):
            d = 1e-6 * max(1.0, abs(y[j]))
            yp, ym = y.copy(), y.copy()
            yp[j] += d
            ym[j] -= d
            K.rhs(s, yp, p, mode, fp)
            K.rhs(s, ym, p, mode, fm)
            fd[:, j] = (fp - fm) / (2 * d)
        worst = max(worst, np.abs(J - fd).max() / max(1.0, np.abs(fd).max()))
    assert len(seen) == 3 + 9  # free flight x 3 ring modes, contact x 3 x 3
    assert worst < 1e-8
