"""``print(vi.intervals(ds))`` shows the table, labels included (issue 32: printing
``to_dataframe()`` hid the label column), and the result is still the Dataset it was."""
import numpy as np
import pytest
import xarray as xr

import vibimpact as vi
from vibimpact.sweeps import format_intervals

LABELS = ["P1 impactless", "P2, 4 impacts", "chaotic, impacting | odd", "quasi-periodic"]


def sweep(both=True):
    """A four-point sweep, one interval per point, one label holding a '|'."""
    eta = np.array([1.0, 1.1, 1.2, 1.3])
    data = {"regime": np.array([1, 1, 3, 2], "i1"), "period": np.array([1, 2, 0, 0], "i4"),
            "label": np.array(LABELS, dtype=object),
            "impacts_per_period": np.array([0.0, 4.0, 3.5, 2.0]),
            "arcs": np.array(["", "2 small arcs", "whole circle", "3 arcs"], dtype=object)}
    if both:
        return xr.Dataset({k: (("direction", "eta"), np.stack([v, v])) for k, v in
                           data.items()}, coords={"eta": eta, "direction": ["up", "down"]})
    return xr.Dataset({k: ("eta", v) for k, v in data.items()}, coords={"eta": eta},
                      attrs={"sweep_direction": "up"})


@pytest.mark.parametrize("both", [True, False])
def test_printing_the_intervals_shows_every_row_and_label(both):
    """Hypothesis: str() of intervals(ds) is format_intervals' table: a header and one
    line per interval that holds its direction, eta span, points and whole label (both
    directions of a two-way sweep)."""
    iv = vi.intervals(sweep(both))
    text = str(iv)
    assert text == format_intervals(iv)
    lines = text.splitlines()
    assert lines[0].split() == ["direction", "eta", "from", "eta", "to", "points", "label"]
    assert len(lines) == 1 + iv.sizes["interval"] == 1 + 4 * (2 if both else 1)
    for line, d, a, label in zip(lines[1:], iv["direction"].values, iv["start"].values,
                                 iv["label"].values):
        assert line.startswith(d) and f"{a:.4f}" in line and line.endswith(label)


def test_markdown_table_has_one_row_per_interval_with_escaped_bars():
    """Hypothesis: to_markdown() is a Markdown table: a header of five columns, the
    alignment row, and one row of five cells per interval, a '|' inside a label escaped
    so that it does not open a sixth cell."""
    import re

    iv = vi.intervals(sweep())
    rows = iv.to_markdown().splitlines()
    assert rows[0] == "| direction | η from | η to | points | label |"
    assert re.fullmatch(r"\|(:?-+:?\|){5}", rows[1])
    assert len(rows) == 2 + iv.sizes["interval"]
    for row, label in zip(rows[2:], iv["label"].values):
        cells = re.split(r"(?<!\\)\|", row)[1:-1]
        assert len(cells) == 5
        assert cells[4].strip().replace("\\|", "|") == label


def test_the_result_is_still_the_dataset_it_was(tmp_path):
    """Hypothesis: the result is an xarray.Dataset as before (indexing, sizes,
    to_dataframe with the label column, xarray.concat, write_netcdf); .dataset is the
    plain Dataset with the same data; a Dataset derived from it that is no table
    (a reduction) prints as a Dataset and refuses to_markdown naming what it lacks."""
    iv = vi.intervals(sweep())
    assert isinstance(iv, xr.Dataset) and iv.sizes["interval"] == 8
    assert list(iv.to_dataframe()["label"]) == LABELS + LABELS[::-1]
    both = xr.concat([iv, iv], dim="interval")
    assert both.sizes["interval"] == 16
    plain = iv.dataset
    assert type(plain) is xr.Dataset
    xr.testing.assert_identical(plain, xr.Dataset(dict(iv.data_vars), attrs=iv.attrs))
    vi.io.write_netcdf(iv, tmp_path / "iv.nc")
    assert list(vi.io.read_netcdf(tmp_path / "iv.nc")["label"].values) == list(
        iv["label"].values)
    reduced = iv[["start", "end"]].mean()
    assert str(reduced).startswith("<xarray.")
    with pytest.raises(ValueError, match="direction.*points.*label.*interval"):
        reduced.to_markdown()
