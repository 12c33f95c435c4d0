"""Sweep datasets store each point's loaded arcs (start, end, width, loaded share) on an
``arc`` dimension, in degrees, with CF units."""
import numpy as np

import vibimpact as vi
from vibimpact.points.point import PointResult, SweepSettings
from vibimpact.sweeps.arc_vars import MAX_STORED_ARCS
from vibimpact.sweeps.dataset import to_dataset


def _result(table, n_state=4):
    r = PointResult.empty(n_state, SweepSettings().n_samples).as_dict()
    if table is None:           # a result without an arc table (an older checkpoint's)
        r.pop("arc_table", None)
    else:
        r["arc_table"] = np.asarray(table, float).reshape(-1, 4)
    return r


def _dataset(up, down):
    etas = np.array([1.0, 1.1])
    return to_dataset(vi.presets.get("fig8"), etas, ("up", "down"),
                      {"up": [_result(t) for t in up], "down": [_result(t) for t in down]},
                      SweepSettings(), direction="both", continuation=True, blocks=1,
                      command="")


def test_each_points_arcs_are_stored_on_the_arc_dimension_in_degrees():
    """Hypothesis: a point's arc table lands at its own eta (the down stream is stored in
    grid order too), one arc per slot with NaN after its last, start/end/width in
    degrees and the loaded share dimensionless."""
    two = [[27.0, 62.0, 35.0, 0.1], [117.0, 152.0, 35.0, 0.1]]
    across = [[170.0, -172.0, 18.0, 0.05]]
    ds = _dataset(up=[two, np.zeros((0, 4))], down=[across, two])
    assert ds.sizes["arc"] == MAX_STORED_ARCS
    for name, units in (("arc_start", "degree"), ("arc_end", "degree"),
                        ("arc_width", "degree"), ("arc_loaded", "1")):
        assert ds[name].dims == ("direction", "eta", "arc")
        assert ds[name].attrs["units"] == units and ds[name].attrs["long_name"]
    up = ds.sel(direction="up")
    np.testing.assert_array_equal(up["arc_start"].values[0, :2], [27.0, 117.0])
    assert np.isnan(up["arc_start"].values[0, 2:]).all()
    assert np.isnan(up["arc_start"].values[1]).all()        # no contact: no arc
    down = ds.sel(direction="down")
    # the down stream's first result is its first point in sweep order: the largest eta
    np.testing.assert_array_equal(down["arc_end"].values[1, :1], [-172.0])
    np.testing.assert_array_equal(down["arc_width"].values[0, :2], [35.0, 35.0])


def test_a_point_with_more_arcs_than_slots_keeps_the_most_loaded_in_order_of_start():
    """Hypothesis: with more arcs than MAX_STORED_ARCS a point keeps the most loaded
    ones, still sorted by start (n_arcs, not the slots, counts them all)."""
    k = MAX_STORED_ARCS + 3
    start = np.linspace(-170.0, 170.0, k)
    loaded = np.r_[np.full(3, 0.001), np.full(k - 3, 0.05)][::-1]
    table = np.column_stack([start, start + 5.0, np.full(k, 5.0), loaded])
    ds = _dataset(up=[table, None], down=[None, None])
    got = ds.sel(direction="up")["arc_start"].values[0]
    np.testing.assert_array_equal(got, start[loaded > 0.01])


def test_results_without_arc_tables_leave_every_arc_slot_not_computed():
    """Hypothesis: results that carry no arc table (points not computed, or a checkpoint
    written before arcs were stored) give the arc variables all NaN (not computed), so a
    map's empty template has the variables its filled rows have."""
    ds = _dataset(up=[None, None], down=[None, None])
    names = [name for name in ds.data_vars if name.startswith("arc_")]
    assert sorted(names) == ["arc_end", "arc_loaded", "arc_start", "arc_width"]
    assert all(np.isnan(ds[name].values).all() for name in names)


def test_a_model_without_contact_gets_no_arc_variables_even_with_empty_tables():
    """Hypothesis: a sweep of a model that declares no contact (Duffing) stores no arc
    variables, even when its points carry (empty) arc tables."""
    etas = np.array([1.0, 1.1])
    res = [_result(np.zeros((0, 4)), n_state=2), _result(np.zeros((0, 4)), n_state=2)]
    ds = to_dataset(vi.DuffingParams(), etas, ("up",), {"up": res}, SweepSettings(),
                    direction="up", continuation=True, blocks=1, command="")
    assert not any(name.startswith("arc_") for name in ds.data_vars)
