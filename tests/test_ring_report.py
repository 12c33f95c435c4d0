"""``reports/ring.md`` (issue 31, part 4: the turning retainer ring against the paper's
claims) is what its data ``reports/ring.json`` renders, and that data is consistent with
itself, with the presets it describes and with ``reports/paper.json`` it quotes.

Fast, except the smoke run of ``analyses/ring/ring_study.py`` (slow); the study itself is
``python analyses/ring/ring_study.py``.
"""
import hashlib
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

import vibimpact as vi
from vibimpact.paper import claims as C

ROOT = Path(__file__).resolve().parents[1]
REPORTS = ROOT / "reports"
sys.path.insert(0, str(ROOT / "analyses" / "ring"))
import ring_report as R  # noqa: E402

VERDICTS = ("agree", "partly", "disagree")
OUTCOMES = ("reached", "exists", "absent")


@pytest.fixture(scope="module")
def summary():
    return json.loads((REPORTS / "ring.json").read_text())


def test_report_is_rendered_from_the_json(summary):
    """Hypothesis: ring.md is exactly what ring.json renders, so every number in it (the
    intervals, verdicts, counts, fractions, multipliers, timings) equals the data."""
    assert R.render(summary) == (REPORTS / "ring.md").read_text()


def test_every_claim_once_with_consistent_counts(summary):
    """Hypothesis: the claims table has each of the paper's 12 interval claims once, in
    order, each column with a verdict of paper.py's three; the counts of the summary are
    the 'agree' verdicts of their column; eq. (5) and the ring preset carry a census
    outcome for every claim."""
    rows = summary["claims"]
    assert [r["key"] for r in rows] == [c.key for c in C.CLAIMS]
    for col in ("eq5", "ring", "light"):
        assert all(r[col]["verdict"] in VERDICTS for r in rows), col
        assert summary["counts"][col] == sum(r[col]["verdict"] == "agree" for r in rows)
    for col in ("eq5", "ring"):
        assert all(r[col]["outcome"] in OUTCOMES and r[col]["evidence"] for r in rows), col


def test_detections_are_runs_near_their_claims(summary):
    """Hypothesis: every detected interval (claims table, each variant, each map row)
    is an ordered run of grid points overlapping the claim widened by claims.WINDOW (or
    NEAR), and an 'agree' verdict has one; a claim with no detection is not 'agree'."""
    claims = {c.key: c for c in C.CLAIMS}
    dets = [(r["key"], r[col]) for r in summary["claims"] for col in ("eq5", "ring", "light")]
    dets += [(k, d) for v in summary["intervals"].values() for k, d in v.items()]
    dets += [(k, d) for m in summary["map"] for k, d in m["claims"].items()]
    for key, d in dets:
        c = claims[key]
        if d["start"] is None:
            assert d["end"] is None and not d["agree"], key
            continue
        assert d["start"] <= d["end"], key
        pad = max(C.WINDOW, C.NEAR) + 1e-9
        assert d["start"] <= c.hi + pad and d["end"] >= c.lo - pad, key
    for r in summary["claims"]:
        for col in ("eq5", "ring", "light"):
            assert (r[col]["verdict"] == "agree") == r[col]["agree"], (r["key"], col)


def test_windows_evidence_is_the_claimed_motion(summary):
    """Hypothesis: each of the P3, P6, P10 windows has one row per variant; a census
    attractor quoted as showing it has the claimed period (and impacts) in its name and
    a fraction in (0, 1]; a hunted orbit quoted has the claimed period, and a stable one
    has no multiplier outside the unit circle."""
    keys = [v["key"] for v in summary["variants"]]
    assert [w["key"] for w in summary["windows"]] == summary["settings"]["windows"]
    for w in summary["windows"]:
        assert [r["variant"] for r in w["rows"]] == keys
        for r in w["rows"]:
            for a in r["census"]:
                assert a["name"].startswith(f"P{w['period']},"), a
                if w["impacts"]:
                    assert f"{w['impacts']} impacts" in a["name"], a
                assert 0 < a["fraction"] <= 1 and a["se"] >= 0
            for o in r["hunt"] or []:
                assert o["label"].startswith(f"P{w['period']},"), o
                if o["stable"]:
                    assert o["abs_mu"] <= 1.0 + 1e-6, o
            assert (r["hunt"] is None) == (r["variant"] not in
                                           summary["settings"]["window_hunt"])


def test_settings_describe_the_shipped_presets(summary):
    """Hypothesis: the report describes the presets as shipped: B and Ec are fig11's,
    the preset ring (Jr, cr, Mr) is fig11-ring's and fig10-ring's, and the map's rows
    are the listed Jr values (a change of the presets makes the report stale)."""
    st = summary["settings"]
    eq5, ring = vi.presets.get("fig11"), vi.presets.get("fig11-ring")
    assert (st["B"], st["Ec"]) == (eq5.B, eq5.Ec) == (ring.B, ring.Ec)
    for name in ("fig10-ring", "fig11-ring"):
        p = vi.presets.get(name)
        assert st["preset_ring"] == dict(Jr=p.Jr, cr=p.cr, Mr=p.Mr), name
    assert [m["Jr"] for m in summary["map"]] == st["map"]["jr"]
    for fig in ("ring_map.png", "ring_motion.png"):
        assert (REPORTS / "figures" / fig).is_file(), fig
    held = next(v for v in summary["variants"] if v["key"] == "held")
    assert held["model"] == "eq5" and held["Jr"] is None


def test_tail_shares_are_a_partition_and_match_the_detection(summary):
    """Hypothesis: over the interval of fig11-impactless, the shares of the kinds of
    motion of every variant and every map row sum to 1, and a variant or row with
    impactless points there has a detected impactless interval (the same rule as
    claims.match_points), one without none inside the claim."""
    t = summary["tail"]
    assert t["claim"] == "fig11-impactless"
    rows = [(v, summary["intervals"][k][t["claim"]]) for k, v in t["variants"].items()]
    rows += [(m["tail"], m["claims"][t["claim"]]) for m in summary["map"]]
    for shares, det in rows:
        assert sorted(shares) == sorted(t["motions"])
        assert math.isclose(sum(shares.values()), 1.0, abs_tol=1e-9)
        if shares["impactless"] > 0:
            assert det["start"] is not None
        elif det["start"] is not None:
            assert det["end"] < t["lo"] or det["start"] > t["hi"]


def test_paper_md_column_is_paper_json(summary):
    """Hypothesis: the reference column quotes reports/paper.json as it is now (the
    verdicts and census outcomes of paper.md)."""
    pj = json.loads((REPORTS / "paper.json").read_text())
    assert summary["paper_md"]["verdicts"] == pj["verdicts"]
    assert summary["paper_md"]["outcomes"] == pj["census_outcomes"]


def _det(start, end, verdict="partly"):
    return dict(start=start, end=end, direction="up", verdict=verdict,
                agree=verdict == "agree")


def test_move_sentence_measures_the_largest_end_move():
    """Hypothesis: the templated sentence on a claim's interval reports the largest move
    of either end from eq. (5)'s over the Jr variants (here 0.006, Jr=0.01), the held and
    the lightest ring's intervals, and calls a
    move of at most one grid step 'within one grid step'; without eq. (5)'s interval it
    measures nothing."""
    s = dict(settings=dict(step=0.002), intervals={
        "held": {"k": _det(1.2, 1.3, "agree"), "n": _det(None, None, "disagree")},
        "Jr=1": {"k": _det(1.202, 1.3), "n": _det(1.4, 1.41)},
        "Jr=0.01": {"k": _det(1.2, 1.306), "n": _det(None, None, "disagree")},
        "Jr=1, Mr=0.1": {"k": _det(1.198, 1.3), "n": _det(None, None, "disagree")}})
    text = R._move_sentence(s, "k")
    assert "detected under 4 of 4 variants, agreeing under 1" in text
    assert "held 1.200–1.300 (up), lightest ring (Jr=0.01) 1.200–1.306 (up)" in text
    assert "Jr variants an end moves at most 0.006 (Jr=0.01), away from" in text
    assert "Mr variants an end moves at most 0.002 (Jr=1, Mr=0.1), within one grid step" \
        in text
    assert "eq. (5) detects nothing there" in R._move_sentence(s, "n")
    assert R._span(_det(None, None)) == "—" and R._span(_det(1.2, 1.2)) == "1.200 (up)"
    assert math.isclose(R._moves(s, "k", ["Jr=1", "Jr=0.01"])[0], 0.006)


def _fingerprint():
    files = sorted(p for p in REPORTS.rglob("*") if p.is_file())
    return {p: hashlib.sha256(p.read_bytes()).hexdigest() for p in files}


@pytest.mark.slow
def test_study_smoke_run_writes_a_consistent_report(tmp_path):
    """Hypothesis: ``ring_study.py --smoke DIR`` (a coarse grid, two ring variants, one
    window, 16 starts) exits 0, writes ring.md, ring.json and the map figure under DIR
    only, and its ring.md is what its ring.json renders."""
    before = _fingerprint()
    out = tmp_path / "smoke"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])]))
    proc = subprocess.run([sys.executable, "analyses/ring/ring_study.py", "--smoke",
                           str(out)], cwd=ROOT, env=env, capture_output=True, text=True,
                          timeout=900)
    assert proc.returncode == 0, proc.stderr[-4000:]
    for name in ("ring.md", "ring.json", "figures/ring_map.png", "figures/ring_motion.png"):
        assert (out / name).is_file() and (out / name).stat().st_size > 0, name
    data = json.loads((out / "ring.json").read_text())
    assert R.render(data) == (out / "ring.md").read_text()
    assert [r["key"] for r in data["claims"]] == [c.key for c in C.CLAIMS]
    assert _fingerprint() == before, "the smoke run wrote into reports/"
