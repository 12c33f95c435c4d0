"""The continuation's predictor: polynomial extrapolation along a period-1 branch, and
the sweep point that is first tried from the predicted state."""
import numpy as np
import pytest

import vibimpact as vi
from vibimpact.analysis import shoot_periodic_orbit
from vibimpact.sweeps import SweepSettings, analyse_point
from vibimpact.points.predict import extrapolate_branch

FIG8 = vi.presets.get("fig8")


def test_extrapolation_is_exact_for_a_polynomial_of_its_degree():
    """Hypothesis: the Lagrange predictor through m points reproduces any polynomial of
    degree m - 1 exactly (at unequal spacing too), and its error on a smooth function
    falls like h^m as the step h shrinks (order 4 for the cubic)."""
    e = np.array([0.3, 0.5, 0.55, 0.9])
    f = lambda t: np.stack([1 - 2 * t + 3 * t ** 3, t ** 2], axis=-1)  # noqa: E731
    assert np.allclose(extrapolate_branch(e, f(e), 1.2), f(1.2), rtol=0, atol=1e-12)
    errs = []
    for h in (0.02, 0.01, 0.005):
        t = 1.0 + h * np.arange(4)
        errs.append(abs(extrapolate_branch(t, np.sin(t)[:, None], 1.0 + 4 * h)[0]
                        - np.sin(1.0 + 4 * h)))
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(np.abs(orders - 4.0) < 0.15), orders


@pytest.mark.parametrize("params, states", [([1.0, 1.0], [[0.0], [1.0]]),
                                            ([1.0, np.nan], [[0.0], [1.0]])])
def test_bad_branches_are_refused_naming_params(params, states):
    """Hypothesis: repeated or non-finite parameter values cannot define a polynomial;
    the error names ``params``."""
    with pytest.raises(ValueError, match="params"):
        extrapolate_branch(params, states, 2.0)


@pytest.fixture(scope="module")
def branch_sweeps():
    """A period-1 impacting stretch of fig8 (kh = 54, eta 1.3-1.456), swept with and
    without the predictor."""
    p = FIG8.replace(kh=54.0)
    eta = np.round(1.3 + 0.004 * np.arange(40), 6)
    an = ("period", "impacts", "lyapunov")
    on = vi.sweep(p, eta, analyses=an, continuation=vi.Continuation(blocks=1))
    off = vi.sweep(p, eta, analyses=an, settings=SweepSettings(analyses=an, predict=0),
                   continuation=vi.Continuation(blocks=1))
    return on, off


def test_predictor_gives_the_same_orbits_with_shorter_transients(branch_sweeps):
    """Hypothesis: starting from the predicted point changes how long a point integrates,
    not what it finds: labels, periods and impacts per period equal those of plain
    continuation, final states agree to the period test's tolerance, and the transient
    (periods integrated before the record) is shorter in total, with points that need
    none (their first record is already periodic)."""
    on, off = branch_sweeps
    assert np.array_equal(on.regime.values, off.regime.values)
    assert np.array_equal(on.period.values, off.period.values)
    assert np.allclose(on.impacts_per_period.values, off.impacts_per_period.values,
                       equal_nan=True)
    scale = np.abs(off.final_state.values).max(axis=1, keepdims=True)
    assert np.all(np.abs(on.final_state.values - off.final_state.values) <= 1e-5 * scale)
    assert (on.transient.values == 0).sum() >= 10
    assert on.transient.values.sum() < 0.6 * off.transient.values.sum()


def test_a_guess_on_a_saddle_is_not_accepted():
    """Hypothesis: a prediction lands as readily on a saddle as on an attractor, and from
    the saddle's own point the record repeats to 1e-6; the point checks the multipliers
    and, the period-1 orbit being a saddle (|mu| = 1.04 at fig8, kh = 10, eta = 1.085),
    reports the attracting period-2 orbit instead."""
    p = FIG8.replace(kh=10.0, B=0.07, Ec=0.11)
    eta = np.round(np.arange(0.9, 1.085 + 1e-9, 0.005), 6)
    ds = vi.sweep(p, eta, analyses=("period",), settings=SweepSettings(
        analyses=("period",), predict=0))
    q = p.replace(eta=1.085)
    x = ds.final_state.values[-2]  # the previous point's state: plain continuation
    saddle = shoot_periodic_orbit(vi.System(q), x, 1)
    assert saddle.converged and saddle.abs_max > 1.02
    st = SweepSettings(analyses=("period",))
    res = analyse_point(q, x, st, guess=saddle.state)
    assert res.period == 2
    assert res.transient > 0
