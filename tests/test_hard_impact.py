"""The hard-impact oscillator (issue 42, item 3): ``x'' + 2 zeta x' + x = A cos(eta t)``,
a rigid stop at ``x = d``, ``x'+ = -r x'-`` (:mod:`vibimpact.builtin_models.hard_impact`).

Each check is against an independent reference: the closed form of the period-1
single-impact orbit and its multipliers (Shaw & Holmes 1983; derived in the model's
docstring), the square-root law of the impact map at grazing (Nordmark 1991), the
geometric series of a chattering sequence's accumulation time (Budd & Dux 1994); and
every command runs on the model's preset.
"""
import math

import numpy as np
import pytest

import vibimpact as vi
from vibimpact import analysis as an
from vibimpact.builtin_models.hard_impact import HardImpactParams
from vibimpact.cli import main

PNG = b"\x89PNG\r\n\x1a\n"


def _phi(tau, zeta):
    """The free oscillator's fundamental matrix over ``tau``."""
    w = math.sqrt(1.0 - zeta * zeta)
    c, s = math.cos(w * tau), math.sin(w * tau)
    return math.exp(-zeta * tau) * np.array([[c + zeta * s / w, s / w],
                                             [-s / w, c - zeta * s / w]])


def shaw_holmes(zeta, d, r, A, eta):
    """The period-1 single-impact orbits in closed form (the model's docstring): a list
    of ``(strobe state at t = 0 mod T, impact speed, multipliers)``, one per root with
    ``v > 0`` whose flight stays below the stop."""
    T = 2.0 * math.pi / eta
    P = A / math.hypot(1.0 - eta * eta, 2.0 * zeta * eta)
    phi = math.atan2(2.0 * zeta * eta, 1.0 - eta * eta)
    (a, b), (cp, e) = _phi(T, zeta)
    K = (1.0 - a) * (1.0 + e * r) + b * r * cp
    B = b * (1.0 + r) * eta
    arg = K * d / (P * math.hypot(K, B))
    if abs(arg) > 1.0:
        return []
    orbits = []
    for sign in (1.0, -1.0):
        theta = math.atan2(B, K) + sign * math.acos(arg)
        D, W = d - P * math.cos(theta), P * eta * math.sin(theta)
        v = (cp * D + (e - 1.0) * W) / (1.0 + e * r)
        t0 = ((theta + phi) / eta) % T
        h0 = np.array([D, W - r * v])
        assert np.allclose(_phi(T, zeta) @ h0, [D, W + v], atol=1e-12)  # the derivation
        taus = np.linspace(0.0, T, 2001)[1:-1]
        flight = P * np.cos(eta * (t0 + taus) - phi) + np.array(
            [(_phi(tau, zeta) @ h0)[0] for tau in taus])
        if v <= 0.0 or flight.max() >= d:
            continue
        S = np.array([[-r, 0.0], [(1.0 + r) * (A * math.cos(eta * t0) - d) / v, -r]])
        mu = np.linalg.eigvals(S @ _phi(T, zeta))
        tau = T - t0  # to the next strobe time
        strobe = np.array([P * math.cos(phi), P * eta * math.sin(phi)]) + _phi(tau, zeta) @ h0
        orbits.append((strobe, v, mu))
    return orbits


CASES = [(eta, r) for eta in (1.2, 1.3, 1.5, 1.8) for r in (0.5, 0.7, 0.9)]


@pytest.mark.parametrize("eta, r", CASES)
def test_the_period_one_orbit_and_its_multipliers_are_shaw_and_holmes(eta, r):
    """Hypothesis: for each closed-form period-1 single-impact orbit at ``zeta = 0.05``,
    ``d = 0.5``, ``A = 1`` (several eta and r; stable or not) the kernel's one-period map
    takes the closed form's stroboscopic state to itself within 1e-8 with exactly one
    impact, at the closed-form speed (1e-8); Newton shooting from a guess 2e-3 away
    converges to it within 1e-8; and the kernel's multipliers
    (variational equations, saltation at the impact) equal the roots of
    ``mu^2 - tr(S Phi(T)) mu + r^2 exp(-2 zeta T)`` within 1e-8."""
    p = HardImpactParams(zeta=0.05, d=0.5, r=r, A=1.0, eta=eta)
    orbits = shaw_holmes(0.05, 0.5, r, 1.0, eta)
    assert orbits, "the closed form has an orbit here"
    system = vi.System(p)
    tight = vi.SolverSettings(rtol=1e-12, atol=1e-13)
    for strobe, v, mu in orbits:
        run = vi.simulate(p, periods=1, state0=strobe, solver=tight)
        np.testing.assert_allclose(run.strobe[-1], strobe, atol=1e-8)  # a fixed point
        assert run.impacts.size == 1
        assert abs(run.impacts["v_impact"][0] - v) < 1e-8
        orbit = an.shoot_periodic_orbit(system, strobe + np.array([2e-3, -2e-3]))
        assert orbit.converged and orbit.iterations >= 1
        np.testing.assert_allclose(orbit.state, strobe, atol=1e-8)
        got = np.sort_complex(np.asarray(orbit.multipliers, complex))
        np.testing.assert_allclose(got, np.sort_complex(mu.astype(complex)), atol=1e-8)
        assert abs(np.prod(got) - r * r * math.exp(-0.05 * 4 * math.pi / eta)) < 1e-8


@pytest.mark.parametrize("eta, r", [(1.3, 0.7), (1.8, 0.9)])
def test_lyapunov_exponents_through_impacts_are_the_closed_form_floquet_exponents(eta, r):
    """Hypothesis: on the stable period-1 orbit the Lyapunov spectrum (variational
    equations with the impacts' saltation, averaged over periods) is ``log|mu| / T`` of
    the closed-form multipliers within 1e-8, and the Benettin QR exponents sum to the
    closed-form contraction ``(2 log r) / T - 2 zeta`` (``det M = r^2 exp(-2 zeta T)``
    every period) within 1e-8."""
    p = HardImpactParams(zeta=0.05, d=0.5, r=r, A=1.0, eta=eta)
    T = 2.0 * math.pi / eta
    stable = [mu for _, _, mu in shaw_holmes(0.05, 0.5, r, 1.0, eta)
              if np.abs(mu).max() < 1.0]
    assert len(stable) == 1
    res = an.lyapunov_spectrum(vi.System(p))
    np.testing.assert_allclose(np.sort(res.exponents),
                               np.sort(np.log(np.abs(stable[0])) / T), atol=1e-8)
    assert abs(res.qr_exponents.sum() - (2.0 * math.log(r) / T - 2.0 * 0.05)) < 1e-8


def test_the_impact_map_has_nordmarks_square_root_at_grazing():
    """Hypothesis: from the impact-free periodic orbit of amplitude ``P`` (``zeta = 0.05``,
    ``A = 1``, ``eta = 1.3``, ``r = 0.7``), a stop at ``d = P - delta`` changes the
    one-period map by ``|F(x0) - x0| ~ delta^(1/2)`` (Nordmark 1991: the impact speed is
    ``eta sqrt(2 P delta)``, and it enters the map through the jump ``(1 + r) u``): the
    log-log slope over delta in [1e-8, 1e-4] (four decades) is 1/2 within 0.05, and the
    prefactor is Nordmark's ``(1 + r) eta sqrt(2 P) |Phi(T - t_g) e_2|`` within 2 % at the
    smallest delta (``t_g``: the free orbit's time of maximum)."""
    zeta, A, eta, r = 0.05, 1.0, 1.3, 0.7
    P = A / math.hypot(1.0 - eta * eta, 2.0 * zeta * eta)
    phi = math.atan2(2.0 * zeta * eta, 1.0 - eta * eta)
    x0 = np.array([P * math.cos(phi), P * eta * math.sin(phi)])
    sol = vi.SolverSettings(rtol=1e-12, atol=1e-14)
    deltas = np.logspace(-8, -4, 9)
    change = []
    for delta in deltas:
        p = HardImpactParams(zeta=zeta, d=P - delta, r=r, A=A, eta=eta)
        run = vi.simulate(p, periods=1, state0=x0, solver=sol)
        assert run.impacts.size == 1
        change.append(np.linalg.norm(run.strobe[-1] - x0))
    slope = np.polyfit(np.log(deltas), np.log(change), 1)[0]
    assert abs(slope - 0.5) < 0.05
    T = 2.0 * math.pi / eta
    t_g = (phi / eta) % T
    nordmark = (1.0 + r) * eta * math.sqrt(2.0 * P) * np.linalg.norm(
        _phi(T - t_g, zeta)[:, 1])
    assert abs(change[0] / math.sqrt(deltas[0]) / nordmark - 1.0) < 0.02


@pytest.mark.parametrize("r", [0.5, 0.8])
def test_a_chattering_sequence_accumulates_at_the_geometric_series_and_sticks(r):
    """Hypothesis: with the stop above the rest position (``d = -0.5``: the spring presses
    the mass into it with ``a = 0.5``), no damping and weak forcing (``A = 1e-3``), a mass
    leaving the stop at ``u0 = 0.01`` chatters and sticks at the accumulation time of
    Budd & Dux's geometric series ``2 u0 / (a (1 - r))`` within 1 %, then rests on the
    stop (strobe ``(d, 0)``) while the force keeps pressing."""
    a, u0 = 0.5, 0.01
    p = HardImpactParams(zeta=0.0, d=-0.5, r=r, A=1e-3, eta=0.5)
    run = vi.simulate(p, periods=1, state0=np.array([-0.5, -u0]))
    ev = run.events
    stick = np.flatnonzero((ev["which"] == 2) & (ev["mode_after"][:, 1] == 0))
    assert stick.size == 1
    t_inf = 2.0 * u0 / (a * (1.0 - r))
    assert abs(ev["t"][stick[0]] - t_inf) < 0.01 * t_inf
    np.testing.assert_array_equal(run.strobe[-1], [-0.5, 0.0])
    assert run.impacts.size >= 3


def test_the_model_is_registered_with_its_presets():
    """Hypothesis: the registry finds the model (``vi.HARD_IMPACT``), ``vibimpact
    presets`` lists its presets, and a coefficient of restitution outside [0, 1] is
    refused with a ValueError naming r."""
    assert vi.HARD_IMPACT is vi.models.get("hard_impact")
    assert vi.presets.get("hard-impact") == HardImpactParams()
    for r in (1.5, -0.5):
        with pytest.raises(ValueError, match=r"^r must be >= 0 and <= 1"):
            HardImpactParams(r=r)


def _cli(argv):
    try:
        return main([str(a) for a in argv])
    except SystemExit as exc:
        return exc.code


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_every_command_runs_on_the_preset(tmp_path, capsys):
    """Hypothesis: simulate, classify, bifurcation, attractors, basins, orbits, continue
    and plot each run on ``--preset hard-impact`` with tiny problems (exit status 0), the
    files record the model and its states, and the images are PNGs; the census finds
    the period-1 orbit with one impact per period."""
    d = tmp_path
    commands = [
        ["presets"],
        ["simulate", "--preset", "hard-impact", "--periods", "3", "--transient", "30",
         "-o", d / "run.nc", "--plot", d / "xy.png"],
        ["classify", "--preset", "hard-impact", "--eta", "1.28,1.3", "--workers", "1",
         "--no-progress", "-o", d / "sweep.nc"],
        ["bifurcation", "--preset", "hard-impact", "--eta", "1.28,1.3", "--workers", "1",
         "--no-progress", "-o", d / "bif.png"],
        ["attractors", "--preset", "hard-impact", "--eta", "1.3", "--starts", "6",
         "--no-progress", "-o", d / "census.nc"],
        ["basins", "--preset", "hard-impact", "--eta", "1.3", "--grid", "5x5",
         "--no-progress", "-o", d / "basins.nc", "--plot", d / "basins.png"],
        ["orbits", "--preset", "hard-impact", "--eta", "1.3", "--period", "1:1",
         "--random", "4", "--no-continue", "--no-progress", "-o", d / "orbits.nc"],
        ["continue", "--preset", "hard-impact", "--eta", "1.3", "--stop", "1.31", "-o",
         d / "p1.nc"],
    ] + [["plot", d / f"{f}.nc", "-o", d / f"{f}.png"]
         for f in ("run", "sweep", "census", "p1")]
    for argv in commands:
        assert _cli(argv) == 0, argv
    assert "hard-impact" in capsys.readouterr().out
    for f in ("run", "sweep", "census", "basins", "orbits", "p1"):
        ds = vi.io.read_netcdf(d / f"{f}.nc")
        assert ds.attrs["model"] == "hard_impact", f
    for f in ("xy", "bif", "basins", "run", "sweep", "census", "p1"):
        assert (d / f"{f}.png").read_bytes()[:8] == PNG, f
    census = vi.io.read_netcdf(d / "census.nc")
    assert census["fraction"].sum() == pytest.approx(1.0)
