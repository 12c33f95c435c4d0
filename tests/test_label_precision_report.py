"""The label-level work-precision study (``analyses/performance/label_precision.py``): its
measures, and its report section, which must be what its data file says."""
import json
import re
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "analyses" / "performance"))
import label_precision as L  # noqa: E402


def _section(text, name):
    m = re.search(rf"<!-- section:{name} -->\n(.*?)\n<!-- /section:{name} -->", text, re.S)
    return None if m is None else m.group(1)


def test_the_section_is_what_the_studys_data_file_renders():
    """Hypothesis: the section label-precision of reports/performance.md is exactly
    render() of reports/label_precision.json: no number in it is typed by hand, and an
    edit of either alone fails here."""
    data = json.loads(L.DATA.read_text())
    got = _section(L.REPORT.read_text(), L.SECTION)
    assert got is not None, "performance.md has no label-precision section"
    assert got.strip() == L.render(data).strip()


def test_the_data_files_shares_and_counts_agree():
    """Hypothesis: in the data file each sweep's share of equal labels is 1 - (labels
    that differ) / points, those that differ where the reference is periodic are some of
    them, a sweep with all labels equal changes no claim's verdict and shifts no
    interval end, and every method's settings and the reference-quality sweeps are
    present for every preset."""
    data = json.loads(L.DATA.read_text())
    n = data["points"]
    for preset, p in data["precision"].items():
        assert {r["method"] for r in p["rows"]} == set(L.SETTINGS), preset
        assert len(p["floor"]) == len(L.FLOOR), preset
        for r in p["floor"] + p["rows"]:
            assert abs(r["agree"] - (1 - r["n_differ"] / n)) < 1e-12, (preset, r["text"])
            assert 0 <= r["n_differ_periodic"] <= r["n_differ"], (preset, r["text"])
            pw = r["pointwise"]
            assert 0 <= pw["n_differ_periodic"] <= pw["n_differ"] <= n, (preset, r["text"])
            if r["n_differ"] == 0:
                assert r["claims_changed"] == [] and r["shift"] == 0.0, (preset, r["text"])


def test_label_boundaries_lie_midway_where_the_label_changes():
    """Hypothesis: the boundaries of a labelled grid are the midpoints between
    neighbours with different labels, and none for one label."""
    eta = np.array([1.0, 1.1, 1.2, 1.3, 1.4])
    np.testing.assert_allclose(L.boundaries(eta, ["a", "a", "b", "b", "a"]), [1.15, 1.35])
    assert L.boundaries(eta, ["a"] * 5).size == 0


def test_the_end_shift_is_the_hausdorff_distance():
    """Hypothesis: the interval-end shift is the Hausdorff distance: symmetric, 0 for
    equal sets and for two empty ones, the largest nearest-neighbour distance otherwise
    (a boundary only one sweep has counts), infinite against an empty set."""
    assert L.hausdorff([1.0, 1.2], [1.0, 1.2]) == 0.0
    assert L.hausdorff([], []) == 0.0
    assert abs(L.hausdorff([1.0, 1.2], [1.01]) - 0.19) < 1e-12
    assert L.hausdorff([1.01], [1.0, 1.2]) == L.hausdorff([1.0, 1.2], [1.01])
    assert L.hausdorff([1.0], []) == float("inf")


def test_the_coarsest_agreeing_setting_needs_every_finer_one_to_agree():
    """Hypothesis: the coarsest setting reported is the first of a run of settings, up to
    the finest, whose labels all agree; a coarse setting that agrees by chance before a
    finer one that does not is not it, and none agreeing at the finest gives None."""
    rows = [{"method": "m", "n_differ": d, "text": t}
            for d, t in ((0, "a"), (3, "b"), (0, "c"), (0, "d"))]
    assert L.coarsest(rows, "m")["text"] == "c"
    rows[-1]["n_differ"] = 1
    assert L.coarsest(rows, "m") is None
