"""Loaded arcs of the retainer from the contact intervals (entry to exit, sliding included),
checked against the dense output: the angles the trajectory sweeps while it is in contact.

The reference of every check here is computed from dense samples alone (no event log): the
circle is cut into cells of REF_CELL degrees, and a cell is loaded when a run of consecutive
samples in contact (the model's penetration > 0) sweeps over it.  Its arcs are the runs of
loaded cells.  The arcs under test come from runs without dense output (the event log and
the stroboscopic samples): dense samples are taken from the step's continuous extension,
so they do not change the steps, and a run with and one without them are the same motion.
"""
import dataclasses

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.analysis import contact_arcs
from vibimpact.analysis.impacts import contact_spans_of
from vibimpact.models.contact import SPAN_DTYPE, contact_spans

#: cell of the dense-output reference, degrees
REF_CELL = 0.05
#: agreement asked of the arcs' ends with the dense output, degrees (issue 32)
TOLERANCE = 1.0
#: dense samples per forcing period of the reference
DENSE = 1500


def _vector(params):
    return params.as_array() if hasattr(params, "as_array") else np.asarray(params, float)


def dense_reference(run):
    """``(start, end)`` arrays (degrees, ends in (-180, 180], sorted by start) of the
    loaded arcs seen in ``run``'s dense samples, and the loaded cell mask."""
    c, p = run.contact, _vector(run.params)
    inside = c.penetration(run.dense, p) > 0.0
    ang = np.radians(c.angle(run.dense, p))
    n = int(round(360.0 / REF_CELL))
    cells = np.zeros(n, dtype=bool)
    edge = np.flatnonzero(np.diff(np.r_[0, inside.astype(int), 0]))
    for a, b in zip(edge[::2], edge[1::2]):            # samples a..b-1 are in contact
        u = np.degrees(np.unwrap(ang[a:b]))
        lo, hi = u.min(), u.max()
        if hi - lo >= 360.0:
            cells[:] = True
            continue
        k = np.arange(int(np.floor(lo / REF_CELL)), int(np.ceil(hi / REF_CELL)) + 1)
        cells[np.mod(k, n)] = True
    if cells.all():
        return np.array([180.0]), np.array([180.0]), cells
    # runs of loaded cells on the circle, starting the walk at an empty cell
    shift = int(np.flatnonzero(~cells)[0])
    ring = np.roll(cells, -shift)
    e = np.flatnonzero(np.diff(np.r_[0, ring.astype(int), 0]))
    start = (e[::2] + shift) * REF_CELL
    end = (e[1::2] - 1 + shift) * REF_CELL
    wrap = lambda x: 180.0 - np.mod(180.0 - x, 360.0)  # noqa: E731
    o = np.argsort(wrap(start))
    return wrap(start)[o], wrap(end)[o], cells


def circular(a, b):
    """|a - b| on the circle, degrees."""
    return np.abs(180.0 - np.mod(180.0 - (np.asarray(a) - np.asarray(b)), 360.0))


def without_dense(run):
    """The same run without its dense samples (events and stroboscopic samples only)."""
    return dataclasses.replace(run, dense=None, t_dense=None, dense_per_period=0)


def assert_arcs_match_dense(run):
    """The arcs of ``run`` without its dense samples have the dense reference's number
    and ends to within TOLERANCE degrees."""
    arcs = contact_arcs(without_dense(run))
    start, end, _ = dense_reference(run)
    assert arcs.n_arcs == start.size, (str(arcs), start, end)
    np.testing.assert_array_less(circular(arcs.start, start), TOLERANCE)
    np.testing.assert_array_less(circular(arcs.end, end), TOLERANCE)
    return arcs


@pytest.fixture(scope="module")
def fig8_ab():
    """fig8 at eta = 1.185 on the impacting branch (the paper's contacts A and B)."""
    p = vi.presets.get("fig8").replace(eta=1.185)
    return vi.simulate(p, periods=3, transient=300, state0=[1.0, 0.0, 0.0, 1.185],
                       dense=DENSE)


def test_fig8_two_contacts_load_two_arcs_as_wide_as_the_dense_output_shows(fig8_ab):
    """Hypothesis: at fig8, eta = 1.185, each of the two contacts per period slides over
    tens of degrees while it lasts; the arcs (from the event log, no dense samples) are
    those angular extents to within 1 degree of the dense output, both in the bottom
    half, and no longer points of zero width at the entry angles."""
    arcs = assert_arcs_match_dense(fig8_ab)
    assert arcs.n_arcs == 2 and arcs.summary == "2 small arcs"
    assert np.all(arcs.width > 10.0 * TOLERANCE)
    assert np.all((arcs.start > 0.0) & (arcs.end < 180.0))


def test_each_impact_record_holds_the_extent_of_its_contact(fig8_ab):
    """Hypothesis: every impact record's theta_min..theta_max is the extent of the angle
    the dense samples of that contact sweep (to within 1 degree), its entry angle and its
    exit angle lie inside it, and theta_exit - theta is the angle travelled."""
    run, c = fig8_ab, fig8_ab.contact
    p = _vector(run.params)
    imp = run.impacts[np.isfinite(run.impacts["t_exit"])]
    assert imp.size >= 4
    for rec in imp:
        sel = (run.t_dense > rec["t_entry"]) & (run.t_dense < rec["t_exit"])
        u = np.degrees(np.unwrap(np.radians(np.r_[rec["theta"],
                                                  c.angle(run.dense[sel], p)])))
        assert abs(u.min() - rec["theta_min"]) < TOLERANCE
        assert abs(u.max() - rec["theta_max"]) < TOLERANCE
        assert rec["theta_min"] <= rec["theta"] <= rec["theta_max"]
        assert rec["theta_min"] <= rec["theta_exit"] <= rec["theta_max"]
        assert abs(rec["theta_exit"] - u[-1]) < TOLERANCE


def test_loaded_share_is_the_fraction_of_recorded_time_in_contact_on_each_arc(fig8_ab):
    """Hypothesis: an arc's loaded share is the time in contact on it over the recorded
    time, which the dense samples measure as the fraction of samples in contact on it
    (to within a few samples); the shares of contact time sum to 1."""
    run = fig8_ab
    arcs = contact_arcs(without_dense(run))
    c, p = run.contact, _vector(run.params)
    inside = c.penetration(run.dense, p) > 0.0
    ang = c.angle(run.dense, p)
    for s, w, loaded in zip(arcs.start, arcs.width, arcs.loaded):
        on = inside & (np.mod(ang - s, 360.0) <= w)
        assert loaded == pytest.approx(on.mean(), abs=4.0 / DENSE)
    assert arcs.share.sum() == pytest.approx(1.0)
    assert arcs.loaded.sum() == pytest.approx(
        np.nansum(run.impacts["duration"]) / (run.t_strobe[-1] - run.t_strobe[0]), rel=1e-6)


def test_an_arc_across_180_degrees_is_one_arc_matching_the_dense_output():
    """Hypothesis: fig10 at eta = 1.3 loads five arcs, one of them across +-180 deg; that
    one is a single arc with start > end, and all five agree with the dense output."""
    p = vi.presets.get("fig10").replace(eta=1.3)
    run = vi.simulate(p, periods=2, transient=200, state0=[1.0, 0.0, 0.0, 1.3], dense=DENSE)
    arcs = assert_arcs_match_dense(run)
    across = arcs.start > arcs.end
    assert across.sum() == 1 and arcs.n_arcs >= 3
    w = arcs.width[across][0]
    assert w == pytest.approx(np.mod(arcs.end[across][0] - arcs.start[across][0], 360.0))


def test_an_impactless_run_loads_no_arc():
    """Hypothesis: a run that never reaches the retainer has no contact span and no arc."""
    run = vi.simulate(vi.presets.get("fig8").replace(eta=0.9), periods=3, transient=20)
    assert run.impacts.size == 0 and contact_spans_of(run).size == 0
    arcs = contact_arcs(run)
    assert arcs.n_arcs == 0 and arcs.summary == "none" and arcs.largest_gap == 360.0


def test_a_model_without_contact_loads_no_arc():
    """Hypothesis: a run of a model that declares no contact (Duffing) has no arcs."""
    run = vi.simulate(vi.DuffingParams(), periods=2, transient=0)
    assert contact_arcs(run).summary == "none"


def test_a_permanent_contact_at_rest_is_one_small_arc_matching_the_dense_output():
    """Hypothesis: a heavy rotor (G = 5) resting on the bottom of the retainer is in
    contact all the time without any impact; its arc is the small one the dense output
    shows around +90 deg, loaded all the time."""
    p = vi.presets.get("fig8").replace(eta=1.0, G=5.0)
    run = vi.simulate(p, periods=2, transient=50, state0=[0.0, 1.0, 0.0, 0.0], dense=DENSE)
    assert run.impacts.size == 0
    arcs = assert_arcs_match_dense(run)
    assert arcs.n_arcs == 1 and 0.0 < arcs.start[0] < 90.0 < arcs.end[0]
    assert arcs.loaded[0] == pytest.approx(1.0)


def test_a_rotor_rolling_round_the_retainer_in_permanent_contact_loads_the_whole_circle():
    """Hypothesis: with a large unbalance and no gravity the rotor rolls round the
    retainer without leaving it (no impact record at all); the contact covers the whole
    circle (one arc of 360 deg), as the dense output shows, with and without dense
    samples (the extrema of R inside the contact follow the angle round)."""
    p = vi.presets.get("fig8").replace(eta=1.0, G=0.0, Ec=2.0)
    run = vi.simulate(p, periods=2, transient=100, state0=[1.0, 0.0, 0.0, 1.0], dense=64)
    assert run.impacts.size == 0
    assert dense_reference(run)[2].all()
    for arcs in (contact_arcs(run), contact_arcs(without_dense(run))):
        assert arcs.n_arcs == 1 and arcs.width[0] == 360.0 and arcs.largest_gap == 0.0
        assert arcs.summary == "whole circle" and arcs.loaded[0] == pytest.approx(1.0)


def test_the_ring_models_arcs_match_its_dense_output():
    """Hypothesis: a model other than eq. (5) that declares the same contact (the turning
    retainer ring) gets its arcs from its own event log, equal to its dense output."""
    p = vi.presets.get("fig8-ring").replace(eta=1.185)
    run = vi.simulate(p, periods=2, transient=300, state0=[1.0, 0.0, 0.0, 1.185, 0.0],
                      dense=DENSE)
    arcs = assert_arcs_match_dense(run)
    assert arcs.n_arcs >= 2 and np.all(arcs.width > TOLERANCE)


def _log(angles_deg, kinds):
    """A synthetic event log of the rotor's contact on the unit circle: ``kinds`` 'in',
    'out' or 'x' (an extremum inside a contact) at times 1, 2, ..."""
    a = np.radians(np.asarray(angles_deg, float))
    state = np.column_stack([np.cos(a), np.sin(a), np.zeros(a.size), np.zeros(a.size)])
    which = np.array([2 if k == "x" else 0 for k in kinds])
    before = [[1 if k in ("out", "x") else 0, 0] for k in kinds]
    return np.arange(1.0, a.size + 1.0), which, np.array(before), state


def test_contact_intervals_merge_into_arcs_across_periods_with_the_gap_rule():
    """Hypothesis: the arcs are the union of the contacts' intervals on the circle; two
    contacts whose intervals overlap or leave a gap of at most ``gap`` degrees load one
    arc, a wider gap two, and each arc's share is its contacts' time over all contact
    time."""
    from vibimpact.models import ROTOR

    # contact 1: 10 -> 30 deg (1 time unit); contact 2: 25 -> 50 (1); contact 3: 58 -> 60
    t, which, before, state = _log([10, 30, 25, 50, 58, 60],
                                   ["in", "out", "in", "out", "in", "out"])
    spans = contact_spans(ROTOR.contact, None, t, which, before, state, (0.0, 10.0))
    assert spans.dtype == SPAN_DTYPE and spans.size == 3
    merged = contact_arcs(spans, gap=10.0)
    assert merged.n_arcs == 1 and merged.start[0] == pytest.approx(10.0)
    assert merged.end[0] == pytest.approx(60.0)
    split = contact_arcs(spans, gap=5.0)
    np.testing.assert_allclose(split.start, [10.0, 58.0])
    np.testing.assert_allclose(split.width, [40.0, 2.0])
    np.testing.assert_allclose(split.share, [2.0 / 3.0, 1.0 / 3.0])


def test_a_contact_sliding_across_180_degrees_is_followed_the_short_way_round():
    """Hypothesis: a contact entering at 170 deg, sliding through 178 deg and leaving at
    -172 deg covers 170..188 deg (not the 342 deg the other way round): one arc from 170
    to -172, 18 deg wide."""
    from vibimpact.models import ROTOR

    t, which, before, state = _log([170, 178, -172], ["in", "x", "out"])
    spans = contact_spans(ROTOR.contact, None, t, which, before, state, (0.0, 5.0))
    assert spans["theta_max"][0] - spans["theta_min"][0] == pytest.approx(18.0)
    arcs = contact_arcs(spans)
    assert arcs.n_arcs == 1 and arcs.start[0] == pytest.approx(170.0)
    assert arcs.end[0] == pytest.approx(-172.0) and arcs.width[0] == pytest.approx(18.0)


def test_contacts_open_at_the_window_ends_are_spans_to_the_window_ends():
    """Hypothesis: a contact already open when the window starts (its first contact
    event is an exit) is a span from the window's start, one still open at its end a
    span to the end; neither is lost, and only the second counts as entered."""
    from vibimpact.models import ROTOR

    t, which, before, state = _log([40, 100, 120], ["out", "in", "x"])
    s0 = np.array([[np.cos(np.radians(20.0)), np.sin(np.radians(20.0)), 0.0, 0.0]])
    spans = contact_spans(ROTOR.contact, None, t, which, before, state, (0.0, 5.0),
                          samples=(np.array([0.0]), s0))
    assert spans.size == 2
    assert spans["entered"].tolist() == [False, True]
    assert spans["exited"].tolist() == [True, False]
    np.testing.assert_allclose(spans["t_start"], [0.0, 2.0])
    np.testing.assert_allclose(spans["t_end"], [1.0, 5.0])
    np.testing.assert_allclose(spans["theta_min"], [20.0, 100.0])
    np.testing.assert_allclose(spans["theta_max"], [40.0, 120.0])


@pytest.mark.slow  # a user model compiles its whole kernel in every process
def test_a_user_model_declaring_the_rotors_contact_gets_arcs_matching_its_dense_output():
    """Hypothesis: a user model (Model.from_functions with the rotor's kernel functions
    and contact) gets its loaded arcs from its own contact declaration and event log:
    arcs of tens of degrees, the same as its dense output shows.  (Its integration
    lacks the built-in rotor's step control, so after the transient it need not be on
    the built-in run's orbit: it is compared with its own dense output only.)"""
    from vibimpact._kernel import rotor as K
    from vibimpact.models import ROTOR

    user = vi.Model.from_functions(
        "my_rotor", K.rhs, K.jac, K.switches, K.transition, K.init_mode, K.TERMINAL,
        ("X", "Y", "dX", "dY"), K.PARAM_NAMES, omega_index=9, n_mode=K.N_MODE,
        contact=ROTOR.contact)
    p = vi.presets.get("fig8").replace(eta=1.185)
    run = vi.simulate(p.as_array(), periods=2, transient=300, model=user,
                      state0=[1.0, 0.0, 0.0, 1.185], dense=DENSE)
    assert run.impacts.size > 0
    arcs = assert_arcs_match_dense(run)
    assert arcs.n_arcs >= 1 and np.all(arcs.width > 10.0 * TOLERANCE)
