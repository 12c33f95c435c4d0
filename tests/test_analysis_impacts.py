"""Impact counts per period, contact arcs in the paper's words, impact statistics."""
import numpy as np
import pytest

from vibimpact.analysis import impacts as ia
from vibimpact.analysis.impacts import contact_arcs, impact_count, impact_statistics
from vibimpact.core.run import IMPACT_DTYPE


def test_period_three_orbit_with_eight_impacts_counts_eight_per_period():
    """A period-3 pattern with 3 + 2 + 3 impacts in its forcing periods, over 30 forcing
    periods, gives 8 impacts in every 3-period window (constant) and 8/3 per period."""
    pattern = [0, 0, 0, 1, 1, 2, 2, 2]
    idx = np.concatenate([np.array(pattern) + 3 * w for w in range(10)])
    c = impact_count(idx, n_periods=30, period=3)
    assert c.per_period == 8.0 and c.constant
    assert c.per_forcing_period == pytest.approx(8.0 / 3.0)
    np.testing.assert_array_equal(c.counts, np.full(10, 8))
    assert impact_count(idx, n_periods=30, period=1).constant is False


def test_incomplete_last_window_is_not_counted():
    """With 31 forcing periods and windows of 3, only 10 complete windows are counted and
    impacts in the 31st period are left out."""
    c = impact_count([0, 1, 30, 30], n_periods=31, period=3)
    assert c.counts.size == 10 and c.counts.sum() == 2


def test_no_impacts_count_zero_and_constant():
    """An impactless run has 0 impacts per period in every window."""
    c = impact_count(np.zeros(0, dtype=np.int64), n_periods=5)
    assert c.per_period == 0.0 and c.constant and c.counts.size == 5


@pytest.mark.parametrize("args,name", [
    (([-1, 0], 5), "impact_period"),
    (([0.5], 5), "impact_period"),
    ((np.zeros((2, 2), int), 5), "impact_period"),
    (([0], 0), "n_periods"),
    (([0], 2.0), "n_periods"),
    (([0], 5, 0), "period"),
    (([0], 2, 3), "n_periods"),
])
def test_bad_impact_count_input_raises_value_error_naming_argument(args, name):
    """Negative or fractional indices, bad n_periods or period raise ValueError naming it."""
    with pytest.raises(ValueError, match=name):
        impact_count(*args)


def test_cluster_across_plus_minus_180_is_one_arc():
    """Angles 175, 179, -178, -176 wrap round 180: one arc from 175 to -176, 9 deg wide."""
    arcs = contact_arcs([-178.0, 175.0, -176.0, 179.0])
    assert arcs.n_arcs == 1
    assert arcs.start[0] == 175.0 and arcs.end[0] == -176.0
    assert arcs.width[0] == pytest.approx(9.0)
    assert arcs.summary == "1 small arc"
    assert arcs.largest_gap == pytest.approx(351.0)


def test_two_separated_clusters_are_two_small_arcs():
    """Two clusters 84..97 and 120..131 deg are two small arcs with their shares."""
    angles = np.r_[np.linspace(84.0, 97.0, 9), np.linspace(120.0, 131.0, 3)]
    arcs = contact_arcs(angles)
    assert arcs.n_arcs == 2 and arcs.summary == "2 small arcs"
    np.testing.assert_allclose(arcs.start, [84.0, 120.0])
    np.testing.assert_allclose(arcs.end, [97.0, 131.0])
    np.testing.assert_allclose(arcs.share, [0.75, 0.25])
    assert str(arcs) == "2 small arcs (84..97\N{DEGREE SIGN}, 120..131\N{DEGREE SIGN})"
    assert arcs.to_text() == str(arcs)


def test_spread_over_bottom_half_is_bottom_half():
    """Impacts spread over 5..175 deg (bottom, +Y = gravity) are 'bottom half'."""
    arcs = contact_arcs(np.linspace(5.0, 175.0, 60))
    assert arcs.summary == "bottom half" and arcs.n_arcs == 1


def test_spread_over_top_half_is_top_half():
    """Impacts spread over -170..-10 deg are 'top half'."""
    assert contact_arcs(np.linspace(-170.0, -10.0, 40)).summary == "top half"


def test_spread_over_whole_circle_is_whole_circle():
    """Random angles all round the circle leave no 90-deg gap: 'whole circle'."""
    rng = np.random.default_rng(0)
    arcs = contact_arcs(rng.uniform(-180.0, 180.0, 300))
    assert arcs.summary == "whole circle" and arcs.largest_gap < 90.0
    assert arcs.share.sum() == pytest.approx(1.0)


def test_wide_arcs_straddling_both_halves_are_k_arcs():
    """Two wide arcs (-60..20 and 100..140 deg) with a 160-deg gap are '2 arcs'."""
    arcs = contact_arcs(np.r_[np.linspace(-60.0, 20.0, 30), np.linspace(100.0, 140.0, 20)])
    assert arcs.summary == "2 arcs" and arcs.n_arcs == 2


def test_no_angles_is_none_with_full_gap():
    """No contacts: 'none', no arcs, and the whole 360 deg empty."""
    arcs = contact_arcs([])
    assert arcs.summary == "none" and arcs.n_arcs == 0 and arcs.largest_gap == 360.0
    assert str(arcs) == "none"


def test_angles_are_wrapped_and_minus_180_is_180():
    """Angles outside (-180, 180] are wrapped; -180 is the same point as 180."""
    arcs = contact_arcs([-180.0, 180.0, 540.0])
    assert arcs.n_arcs == 1 and arcs.start[0] == 180.0 and arcs.width[0] == 0.0


def test_summary_thresholds_are_module_constants():
    """The words come from named module-level thresholds (45 deg, 4 arcs, 2 deg, 90 deg)."""
    assert (ia.SMALL_ARC_WIDTH, ia.MAX_SMALL_ARCS, ia.HALF_TOLERANCE,
            ia.WHOLE_CIRCLE_GAP) == (45.0, 4, 2.0, 90.0)
    five = np.r_[0.0, 40.0, 80.0, 120.0, 160.0]
    assert contact_arcs(five).summary == "bottom half"


@pytest.mark.parametrize("kwargs,name", [
    (dict(angles=[0.0, np.nan]), "angles"),
    (dict(angles=np.zeros((2, 2))), "angles"),
    (dict(angles=[0.0], gap=0.0), "gap"),
    (dict(angles=[0.0], gap=400.0), "gap"),
])
def test_bad_contact_arcs_input_raises_value_error_naming_argument(kwargs, name):
    """Non-finite or 2-D angles and a gap outside (0, 360) raise ValueError naming it."""
    with pytest.raises(ValueError, match=name):
        contact_arcs(**kwargs)


def test_impact_statistics_ignore_open_contacts():
    """Count, mean/max speed and max penetration over all contacts; the mean duration
    leaves out the contact still open (NaN)."""
    rec = np.zeros(3, dtype=IMPACT_DTYPE)
    rec["v_impact"] = [0.5, 0.3, 0.1]
    rec["penetration"] = [0.1, 0.2, 0.05]
    rec["duration"] = [0.4, 0.6, np.nan]
    s = impact_statistics(rec)
    assert s.count == 3
    assert s.mean_speed == pytest.approx(0.3) and s.max_speed == 0.5
    assert s.max_penetration == 0.2 and s.mean_duration == pytest.approx(0.5)
    assert s.as_dict()["count"] == 3


def test_impact_statistics_of_no_impacts_are_zero_count_and_nan():
    """No contacts: count 0 and NaN statistics, no warnings."""
    s = impact_statistics(np.zeros(0, dtype=IMPACT_DTYPE))
    assert s.count == 0
    assert all(np.isnan(v) for k, v in s.as_dict().items() if k != "count")


def test_impact_statistics_reject_unstructured_input():
    """A plain float array raises ValueError naming impacts."""
    with pytest.raises(ValueError, match="impacts"):
        impact_statistics(np.zeros(3))


def test_contact_still_open_at_the_end_of_the_window_keeps_its_peak_penetration():
    """A window with one contact entry, an extremum of R inside it and no exit (the contact
    is still open when the run ends) gives one impact with that extremum's penetration and
    an undefined duration; it used to index an empty array of exits."""
    from vibimpact.models.contact import impacts_from_events
    from vibimpact.models import ROTOR

    t = np.array([1.0, 1.2])
    which = np.array([0, 2])                      # contact entry, extremum of R
    mode_before = np.array([[0, 0], [1, 0]])      # free before the entry, in contact after
    state = np.array([[1.0, 0.0, 0.5, 0.0], [1.003, 0.0, 0.0, 0.1]])
    imp = impacts_from_events(ROTOR.contact, ROTOR.param_set().as_array(), t, which,
                              mode_before, state, t0=0.0, period=2.0)
    assert imp.size == 1
    assert imp["penetration"][0] == pytest.approx(0.003)
    assert np.isnan(imp["duration"][0])


def _records(lo, hi, duration):
    rec = np.zeros(len(lo), dtype=IMPACT_DTYPE)
    rec["theta"], rec["theta_min"], rec["theta_max"] = lo, lo, hi
    rec["theta_exit"], rec["duration"] = hi, duration
    return rec


def test_an_arc_with_both_ends_in_the_bottom_half_that_runs_over_the_top_is_not_bottom():
    """Hypothesis: the half a set of arcs lies in is decided by the arcs, not their ends:
    a contact sliding from 170 deg the long way round to 10 deg (200 deg over the top)
    has both ends in the bottom half, yet is '1 arc', while 10..170 deg is 'bottom half'."""
    over = contact_arcs(_records([170.0], [370.0], [1.0]))
    assert over.n_arcs == 1 and over.width[0] == pytest.approx(200.0)
    assert over.start[0] == 170.0 and over.end[0] == pytest.approx(10.0)
    assert over.summary == "1 arc"
    assert contact_arcs(_records([10.0], [170.0], [1.0])).summary == "bottom half"


def test_impact_records_give_arcs_from_their_extent_and_time_shares():
    """Hypothesis: impact records are arcs from theta_min to theta_max; an arc's share is
    its contacts' duration over all contact time (not their number), and without the
    recorded time its loaded fraction is unknown (NaN)."""
    arcs = contact_arcs(_records([20.0, 22.0, 120.0], [40.0, 41.0, 125.0], [1.0, 1.0, 2.0]))
    np.testing.assert_allclose(arcs.start, [20.0, 120.0])
    np.testing.assert_allclose(arcs.end, [41.0, 125.0])
    np.testing.assert_allclose(arcs.width, [21.0, 5.0])
    np.testing.assert_allclose(arcs.share, [0.5, 0.5])
    assert np.all(np.isnan(arcs.loaded))
    assert str(arcs) == "2 small arcs (20..41\N{DEGREE SIGN}, 120..125\N{DEGREE SIGN})"
