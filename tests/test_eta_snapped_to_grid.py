"""Issue 32, part 3: :func:`vibimpact.sweep` and :func:`vibimpact.map2d` take an eta
array built by hand (``np.arange``) as the command line's grid (:func:`vibimpact.grid`)
where it differs from it only by the arithmetic's error, and keep other values; the
map's varied parameter is snapped alike, to the command line's ``--vary`` values."""
import numpy as np
import pytest

import vibimpact as vi
from vibimpact.sweeps.sweep import SNAP_ULPS, check_grid, snap_grid

_QUICK = vi.SweepSettings(transient_max=8, chunk=4, record=16, record_periodic=4)


@pytest.mark.parametrize("text, built", [
    ("0.9:1.5:0.002", lambda: np.arange(0.9, 1.5 + 1e-12, 0.002)),
    ("0.1:0.7:0.1", lambda: np.arange(0.1, 0.7 + 1e-12, 0.1)),
    ("0.001:2:0.001", lambda: np.arange(0.001, 2 + 1e-12, 0.001)),
    ("0.9:1.5:0.002", lambda: np.linspace(0.9, 1.5, 301)),
    ("0.9:1.5:0.002", lambda: 0.9 + 0.002 * np.arange(301)),
])
def test_a_grid_built_by_hand_is_taken_as_the_command_lines(text, built):
    """arange, linspace and start + step * k give exactly vi.grid's values once checked,
    however many of their values differ from it before."""
    assert np.array_equal(check_grid(built()), vi.grid(text))


@pytest.mark.parametrize("values", [
    [1.0000000000001, 1.1],          # 13 decimals: further than the arithmetic's error
    [0.9 + 1e-13, 1.0],
    [1.0, 1.0 + 2 * SNAP_ULPS * np.spacing(1.0)],  # beyond SNAP_ULPS ulps of 1.0
    [1e4 + 1e-9, 2e4],                # from ROUND_BELOW on, nothing is rounded
    [1e-13, 1e-12],                   # rounds to 0: kept (eta > 0)
])
def test_values_meant_beyond_twelve_decimals_are_kept(values):
    """A value further than SNAP_ULPS ulps from its 12-decimal rounding, at or above
    ROUND_BELOW, or rounding to 0, is not changed."""
    arr = np.array(values)
    assert np.array_equal(snap_grid(arr), arr)


def test_snapping_that_would_repeat_a_value_changes_nothing():
    """Two values a few ulps apart that round to the same number are kept as given
    (the snapped grid would not be strictly increasing)."""
    arr = np.array([1.0, 1.0 + np.spacing(1.0)])
    assert np.array_equal(snap_grid(arr), arr)


def test_sweep_stores_the_grids_values_for_an_arange():
    """vi.sweep over np.arange(0.9, 1.5 + 1e-12, 0.002)[:3] stores exactly vi.grid's
    values (and so prints the same labels)."""
    ds = vi.sweep(vi.presets.get("fig8"), np.arange(0.9, 1.5 + 1e-12, 0.002)[:3],
                  analyses=(), settings=_QUICK)
    want = vi.grid("0.9:1.5:0.002")[:3]
    assert np.array_equal(ds["eta"].values, want)
    assert [repr(float(e)) for e in ds["eta"].values] == ["0.9", "0.902", "0.904"]


def test_map2d_stores_the_grids_values_for_an_arange():
    """vi.map2d stores the snapped eta of an arange as vi.sweep does."""
    ds = vi.map2d(vi.presets.get("fig8"), np.arange(0.1, 0.3 + 1e-12, 0.1),
                  {"B": [0.01]}, analyses=(), settings=_QUICK)
    assert np.array_equal(ds["eta"].values, vi.grid("0.1:0.3:0.1"))


@pytest.mark.parametrize("name, text, built", [
    ("f", "0.02:0.1:0.01", lambda: np.arange(0.02, 0.1 + 1e-12, 0.01)),
    ("B", "0.001:0.03:0.001", lambda: np.arange(0.001, 0.03 + 1e-12, 0.001)),
    ("kh", "10.1:12.1:0.1", lambda: np.arange(10.1, 12.1 + 1e-9, 0.1)),
    ("eps", "0.1:0.7:0.1", lambda: 0.1 + 0.1 * np.arange(7)),
])
def test_map_rows_built_by_hand_are_the_command_lines_vary(name, text, built):
    """The map's other axis is snapped as eta is: an arange (or start + step * k) of
    the varied parameter gives exactly the values of the command line's --vary range,
    though several of its values differ from them before."""
    from vibimpact.cli.map import parse_vary
    from vibimpact.maps.map2d import check_vary

    fig8 = vi.presets.get("fig8")
    _, cli_values = parse_vary(f"{name}={text}", fig8)
    _, api_values = check_vary(fig8, {name: built()})
    assert not np.array_equal(built(), cli_values)  # the case is not trivial
    assert np.array_equal(api_values, cli_values)


def test_map2d_stores_the_command_lines_rows_for_an_arange():
    """vi.map2d stores the snapped values of its varied parameter (its row coordinate)
    for an arange whose raw values differ from the range's."""
    raw = np.arange(0.1, 0.4 + 1e-12, 0.1)
    assert not np.array_equal(raw, vi.grid("0.1:0.4:0.1"))  # the case is not trivial
    ds = vi.map2d(vi.presets.get("fig8"), [1.0], {"eps": raw}, analyses=(),
                  settings=_QUICK)
    assert np.array_equal(ds["eps"].values, vi.grid("0.1:0.4:0.1"))
