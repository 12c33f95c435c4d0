"""The census section of ``reports/paper.md`` (issue 30, part 7): every interval claim of
the paper has exactly one of the three outcomes, and the report's section is the one its
data in ``reports/paper.json`` renders (the report cannot drift from the data).

Fast: reads the committed report and JSON; the computation is
``analyses/paper/census_claims.py`` (run by ``analyses/paper/paper.py``).
"""
import json
import re
import sys
from pathlib import Path

import pytest

from vibimpact.paper import claims as C

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "analyses" / "paper"))
import census_claims as K  # noqa: E402
import census_claims_report as R  # noqa: E402


@pytest.fixture(scope="module")
def summary():
    return json.loads((ROOT / "reports" / "paper.json").read_text())


@pytest.fixture(scope="module")
def section():
    text = (ROOT / "reports" / "paper.md").read_text()
    m = re.search(re.escape(R.BEGIN) + r".*?" + re.escape(R.END), text, re.S)
    assert m, "reports/paper.md has no census section"
    return m.group(0)


def test_every_claim_has_exactly_one_outcome(summary):
    """Hypothesis: each of the paper's interval claims appears once in the census
    summary, with one of the three outcomes (reached / exists / absent), and the outcome
    table of paper.json says the same."""
    rows = summary["census_claims"]["claims"]
    assert [r["key"] for r in rows] == [c.key for c in C.CLAIMS]
    for r in rows:
        assert r["outcome"] in R.OUTCOMES, r["key"]
        assert r["evidence"], r["key"]
    assert summary["census_outcomes"] == {r["key"]: r["outcome"] for r in rows}


def test_report_section_is_rendered_from_the_json(summary, section):
    """Hypothesis: the section in paper.md is exactly what its JSON renders, so every
    number in it (fractions, standard errors, multipliers, timings) equals the data."""
    assert R.render(summary["census_claims"]) == section


def test_outcomes_agree_with_the_stored_census(summary, section):
    """Hypothesis: an "absent" claim has no matching attractor in any stored census of
    the defaults nor from rest, and an "exists" claim by an attractor quotes a fraction
    in (0, 1] that is one of its stored attractors' (under the claim's matching rule);
    each claim's outcome is named in the section's table."""
    claims = {c.key: c for c in C.CLAIMS}
    for r in summary["census_claims"]["claims"]:
        c = claims[r["key"]]
        assert f"| {r['key']} |" in section and R.OUTCOME_TEXT[r["outcome"]] in section
        rows = [a for v in r["defaults"].values() for a in v]
        if r["outcome"] == "absent":
            assert not K.matches(rows, c).any(), r["key"]
            assert r["readings_with"] == 0, r["key"]
        if r["outcome"] == "exists" and r.get("fraction") is not None:
            assert 0 < r["fraction"] <= 1 and r["se"] >= 0
            assert f"{r['fraction']:.3f} ± {r['se']:.3f}" in r["evidence"]
            assert r["readings_with"] >= 1
