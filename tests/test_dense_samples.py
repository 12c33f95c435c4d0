"""Every dense sample is written, by every method, also where sample times fall on step
ends (fixed-step runs, whose steps divide the sampling interval)."""
import numpy as np
import pytest

import vibimpact as vi


@pytest.mark.parametrize("method", ["rk4", "dp5", "dop853"])
@pytest.mark.parametrize("steps_per_period", [400, 64])
def test_dense_samples_match_a_tight_reference_at_every_sample_time(method, steps_per_period):
    """Dense samples at ``tau = j T / m`` agree with a tight DOP853 run's samples to the
    run's accuracy (at its stroboscopic points) at every j, and those at ``j = 0 mod m`` equal the stroboscopic
    points.  With fixed steps of ``T / 400`` or ``T / 64`` the sample times coincide with
    step ends up to rounding; a sample skipped there would leave uninitialised memory
    (garbage or NaN) in the output."""
    p = vi.presets.get("fig11").replace(eta=1.06)
    m = 16
    kw = dict(periods=20, transient=30, dense=m)
    run = vi.simulate(p, **kw, solver=vi.SolverSettings(
        method=method, steps_per_period=steps_per_period,
        adaptive=method != "rk4" and steps_per_period == 400))
    ref = vi.simulate(p, **kw, solver=vi.SolverSettings(rtol=1e-12, atol=1e-14))
    assert run.ok and ref.ok
    assert run.dense.shape == ref.dense.shape == (20 * m + 1, 4)
    assert np.all(np.isfinite(run.dense))
    np.testing.assert_array_equal(run.dense[::m], run.strobe)
    # the run's own accuracy, measured at its stroboscopic points (RK4 with 64 fixed steps
    # a period is off by about 0.07 there, DOP853 with rtol 1e-6 by 5e-7): a sample taken
    # at a wrong time or not at all would be off by far more
    tol = 5.0 * np.abs(run.strobe - ref.strobe).max()
    assert np.abs(run.dense - ref.dense).max() < tol


def test_fixed_step_samples_on_step_ends_are_all_written():
    """The case that found the bug: RK4 with its default fixed step, 16 samples a period;
    80 of 641 rows were left unwritten."""
    p = vi.presets.get("fig11").replace(eta=1.06)
    run = vi.simulate(p, periods=40, transient=100, dense=16,
                      solver=vi.SolverSettings(method="rk4"))
    assert run.ok
    assert run.dense.shape == (641, 4)
    assert np.all(np.isfinite(run.dense))
    np.testing.assert_array_equal(run.dense[::16], run.strobe)
