"""Starts whose integration fails are reported as failed, not counted as an attractor.

A census, a basin image and an orbit hunt at parameters the solver cannot integrate
(a ring of almost no inertia, a soft wall of stiffness 1e300, a start at X = 1e300)
used to list a "diverged" attractor with a basin fraction and say nothing.  Now a start
whose integration failed (``Status.FAILED``: step-size underflow, step limit, Zeno) is on
no attractor (label -1), counted apart (``failed``, ``failed_fraction``, ``failure``)
and said on stderr by the command line (one warning line, exit status 0); a motion that
genuinely diverges (the state leaves the solver's bound) stays the pseudo-attractor
"diverged".
"""
import numpy as np
import pytest

import vibimpact as vi
from vibimpact.census.reach import DIVERGED, FAILED

from test_bad_input import run_cli


def warnings_of(err):
    return [ln for ln in err.splitlines() if ln.startswith("vibimpact: warning:")]


@pytest.fixture(scope="module")
def soft_census():
    """A census of the soft-impact oscillator with k = 1e300: at eta 1.2 every start
    fails (step-size underflow), at eta 1.3 some do and the others reach an orbit."""
    system = vi.System(vi.presets.get("soft-impact")).with_params(k=1e300)
    return vi.attractors(system, [1.2, 1.3], starts=4)


def test_failed_starts_are_on_no_attractor(soft_census):
    """Hypothesis: a start whose integration failed gets label -1 and decided_by
    'integration_failed', and no attractor (no 'diverged' one) stands for it."""
    ds = soft_census
    assert np.all(ds.label.values[0] == -1)
    assert np.all(ds.decided_by.values[0] == FAILED)
    assert "diverged" not in ds.name.values.tolist()[0]
    assert int(ds.failed.values[0]) == 4
    assert "step size underflow" in str(ds.failure.values[0])


def test_attractor_fractions_and_failed_fraction_sum_to_one(soft_census):
    """Hypothesis: at a point where some starts fail and others reach an attractor, the
    attractors' fractions and the failed fraction add up to 1, each attractor's fraction
    counting only the starts on it."""
    ds = soft_census
    failed = int(ds.failed.values[1])
    assert 0 < failed < 4
    fr = np.nansum(ds.fraction.values[1])
    assert fr == pytest.approx(1.0 - failed / 4)
    assert fr + float(ds.failed_fraction.values[1]) == pytest.approx(1.0)
    on = ds.label.values[1] >= 0
    assert on.sum() == 4 - failed


def test_failed_flags_are_cf_described(soft_census):
    """Hypothesis: decided_by's CF flags name the failure, and the new count variables
    have a long_name and units."""
    ds = soft_census
    assert "integration_failed" in ds.decided_by.attrs["flag_meanings"].split()
    assert FAILED in ds.decided_by.attrs["flag_values"].tolist()
    for name in ("failed", "failed_fraction"):
        assert ds[name].attrs["units"] == "1" and ds[name].attrs["long_name"]


@pytest.mark.parametrize("change", [dict(Jr=1e-300), dict(cr=1e300), dict(Mr=1e12)])
def test_ring_extremes_fail_apart(change):
    """Hypothesis: the turning ring at an extreme inertia, damping or mass fails to
    integrate; its starts are reported failed, not as a 'diverged' attractor."""
    system = vi.System(vi.presets.get("fig8-ring")).with_params(**change)
    ds = vi.attractors(system, 1.2, starts=2)
    assert int(ds.failed.values[0]) + int((ds.label.values[0] >= 0).sum()) == 2
    assert int(ds.failed.values[0]) > 0
    assert "diverged" not in ds.name.values.tolist()[0]


def test_genuine_divergence_stays_the_diverged_pseudo_attractor():
    """Hypothesis: a motion that escapes (a softening Duffing oscillator driven hard: the
    state leaves the solver's bound) is still the pseudo-attractor 'diverged' with its
    fraction, and nothing is counted failed."""
    system = vi.System(vi.DuffingParams(delta=0.1, alpha=1.0, beta=-1.0, gamma=5.0,
                                        omega=1.0))
    ds = vi.attractors(system, None, starts=2)
    assert np.all(ds.decided_by.values == DIVERGED)
    assert ds.name.values.tolist()[0] == ["diverged"]
    assert float(ds.fraction.values[0, 0]) == 1.0
    assert int(ds.failed.values[0]) == 0


def test_basins_cells_beyond_the_solver_fail_apart():
    """Hypothesis: a basin image that starts every cell (``everywhere``, as the cells at
    X = 1e300 lie far outside the retainer) marks the cells there -1 (failed), counts
    them apart, and its fractions add up to 1 with the failed fraction; by default those
    cells are not started (-2) and none fails."""
    ds = vi.basins(vi.System(vi.presets.get("fig8")), 1.2, grid=(2, 2), eps=1,
                   ranges=((-0.5, 1e300), (-0.5, 0.5)), everywhere=True)
    assert np.all(ds.basin.values[:, 1] == -1)
    assert int(ds.failed) == 2
    assert np.nansum(ds.fraction.values) + float(ds.failed_fraction) == pytest.approx(1.0)
    assert "step size underflow" in str(ds.failure.values)
    inside = vi.basins(vi.System(vi.presets.get("fig8")), 1.2, grid=(2, 2), eps=1,
                       ranges=((-0.5, 1e300), (-0.5, 0.5)))
    assert np.all(inside.basin.values[:, 1] == -2) and int(inside.not_started) == 2
    assert int(inside.failed) == 0


def test_orbit_hunt_counts_failed_seeds():
    """Hypothesis: a hunt whose seeds fail to integrate counts them as failed_seeds (not
    diverged_seeds), keeps the solver's reason and says so in its note."""
    system = vi.System(vi.presets.get("fig8-ring")).with_params(Jr=1e-300)
    hunt = vi.hunt_orbits(system.with_params(eta=1.2), periods=[1], random=2,
                          continuation=False)
    assert hunt.orbits == ()
    assert hunt.counts["failed_seeds"] == 2 and hunt.counts["diverged_seeds"] == 0
    assert "step size underflow" in hunt.failure
    assert "2 of 2 seeds failed" in hunt.failed_note()


def test_cli_attractors_warns_once_and_exits_0(tmp_path, capfd):
    """Hypothesis: 'attractors' with failing starts writes its file, lists the failed
    share in its table and says one warning line with the count and the reason on
    stderr; exit status 0."""
    out = tmp_path / "a.nc"
    rc, so, err = run_cli(["attractors", "--preset", "soft-impact", "--set", "k=1e300",
                           "--eta", "1.2,1.3", "--starts", "4", "--no-progress", "-o",
                           out], capfd)
    assert rc == 0, err
    lines = warnings_of(err)
    assert len(lines) == 1 and "failed to integrate" in lines[0]
    assert "step size underflow" in lines[0]
    assert "integration failed" in so and "diverged" not in so
    assert out.exists()


@pytest.mark.slow
def test_cli_basins_and_orbits_warn_once(tmp_path, capfd):
    """Hypothesis: 'basins --everywhere' reaching X = 1e300 (cells far outside the
    retainer, which only --everywhere starts) and 'orbits' of a ring that cannot be
    integrated each write their file and say one warning line; exit status 0."""
    rc, so, err = run_cli(["basins", "--preset", "fig8", "--eta", "1.2", "--grid", "2x2",
                           "--eps", "1", "--range=-0.5:1e300,-0.5:0.5", "--everywhere",
                           "--no-progress", "-o", tmp_path / "b.nc"], capfd)
    assert rc == 0, err
    assert len(warnings_of(err)) == 1 and "2 of 4 starts" in err
    assert "integration failed" in so
    rc, so, err = run_cli(["orbits", "--preset", "fig8-ring", "--set", "Jr=1e-300",
                           "--eta", "1.2", "--period", "1", "--random", "2",
                           "--no-continue", "--no-progress", "-o", tmp_path / "o.nc"],
                          capfd)
    assert rc == 0, err
    assert len(warnings_of(err)) == 1 and "seeds failed to integrate" in err
    assert (tmp_path / "o.nc").exists()
