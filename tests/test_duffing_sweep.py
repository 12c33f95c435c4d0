"""Models other than the rotor go through the same sweep engine and point pipeline."""
import numpy as np
import pytest

import vibimpact as vi


@pytest.fixture(scope="module")
def cascade():
    """A down sweep of the double-well Duffing oscillator (delta 0.3, alpha -1, beta 1,
    gamma 0.35) in omega, where it period-doubles on its way to chaos."""
    g = np.round(np.union1d(np.arange(1.29, 1.4001, 0.005), [1.3005, 1.301, 1.3015]), 6)
    system = vi.System(vi.DuffingParams(gamma=0.35))
    ds = vi.sweep(system, g, direction="down", analyses=("period", "lyapunov", "floquet"))
    return g, ds


def test_duffing_sweep_finds_the_period_doubling_cascade(cascade):
    """Hypothesis: swept down in omega, the forced Duffing oscillator's periodic points
    have periods 1, 2, 4 and then at least 8 in that order (each a power of two, never
    decreasing), and below the cascade the motion is chaotic with a significantly
    positive largest exponent -- the Feigenbaum route, found by the same engine and
    pipeline as the rotor's sweeps."""
    g, ds = cascade
    order = np.argsort(-g)
    periods = ds.period.values[order]
    regime = ds.regime.values[order]
    periodic = [int(n) for n, r in zip(periods, regime) if r == 1]
    assert all(n & (n - 1) == 0 for n in periodic), periodic
    assert periodic == sorted(periodic), periodic
    assert {1, 2, 4} <= set(periodic) and max(periodic) >= 8, periodic
    lowest = order[-2:]
    assert np.all(ds.regime.values[lowest] == 3)
    assert np.all(ds.lyapunov.values[lowest] > 3 * ds.lyapunov_err.values[lowest])


def test_duffing_sweep_dataset_names_the_models_state(cascade):
    """Hypothesis: a sweep of a two-variable model stores two-component states and
    multipliers named after the model's variables, and the period-1 orbit's Floquet
    multipliers lie inside the unit circle (it attracts)."""
    g, ds = cascade
    assert list(ds.state.values) == ["x", "dx"]
    assert ds.final_state.shape == (g.size, 2)
    p1 = np.where(ds.period.values == 1)[0]
    mu = ds.floquet_real.values[p1] + 1j * ds.floquet_imag.values[p1]
    assert np.all(np.abs(mu) < 1.0)


def test_duffing_map_and_classification_agree_with_the_sweep():
    """Hypothesis: a parameter map of the Duffing oscillator (omega against gamma) is made
    of the same rows a sweep gives (the row at gamma = 0.35 equals a one-block sweep), it
    shows the period doubling between gamma = 0.30 (P1) and 0.35 (P2) at omega = 1.33,
    and classify_params labels that point as the map does."""
    from vibimpact.points import classify_params

    system = vi.System(vi.DuffingParams())
    etas = np.array([1.32, 1.33, 1.34])
    m = vi.map2d(system, etas, {"gamma": [0.30, 0.35]})
    row = vi.sweep(system.with_params(gamma=0.35), etas,
                   continuation=vi.Continuation(blocks=1))
    np.testing.assert_array_equal(m.period.values[1], row.period.values)
    assert m.period.values[0, 1] == 1 and m.period.values[1, 1] == 2
    reg, res = classify_params(system.with_params(gamma=0.35, omega=1.33),
                               state0=row.final_state.values[0])
    assert str(reg) == "P2" and res.period == 2
