"""Tests of the calibration's pure pieces (``analyses/paper/calibrate_search.py``) and one smoke
run of ``analyses/paper/calibrate.py --quick`` on a tiny eta grid."""
import itertools
import json
import math
import re
import sys
from pathlib import Path

import pytest

ANALYSES = Path(__file__).resolve().parents[1] / "analyses" / "paper"
sys.path.insert(0, str(ANALYSES))

import calibrate_search as S  # noqa: E402
from vibimpact.paper import claims as C  # noqa: E402

CLAIMS = tuple(c for c in C.CLAIMS if c.preset in S.FIT_PRESETS)


def grid_land(Bs, Es, f):
    """A landscape {(B, Ec): (f(B, Ec), 0)} over the full grid Bs x Es."""
    return {(B, E): (f(B, E), 0) for B in Bs for E in Es}


def test_supersets_are_exactly_the_sets_containing_the_named_damping():
    """Hypothesis: reading (c) enumerates every subset of {Bh, BT, f} that contains the
    named damping, each once, and no other set."""
    for named in (("BT",), ("f",)):
        got = S.supersets(named)
        want = {frozenset(s) for k in range(4) for s in itertools.combinations(S.DAMPINGS, k)
                if set(named) <= set(s)}
        assert len(got) == len(set(got)) == 4
        assert {frozenset(s) for s in got} == want
        assert got[0] == named  # the paper's own reading first


def test_readings_cover_a_b_c_d():
    """Hypothesis: (a) is one damping per figure, (b) differs from (a) only in fig11 at
    B = 0, (c) holds the 15 other superset pairs (4 x 4 less (a)) with fig8 undamped, and
    (d) has one non-adoptable reading per fitted figure."""
    rs = {r.key: r for r in S.readings()}
    a, b = rs["a"], rs["b"]
    assert [f.damp for f in a.figures] == [(), ("BT",), ("f",)]
    assert [f.b_zero for f in b.figures] == [False, False, True]
    assert [f.damp for f in b.figures] == [f.damp for f in a.figures]
    cs = [r for r in rs.values() if r.kind == "c"]
    assert len(cs) == 15
    for r in cs:
        f8, f10, f11 = r.figures
        assert f8.damp == () and "BT" in f10.damp and "f" in f11.damp
    assert len({(r.figures[1].damp, r.figures[2].damp) for r in cs}) == 15
    ds = [r for r in rs.values() if r.kind == "d"]
    assert sorted(r.figures[0].preset for r in ds) == sorted(S.FIT_PRESETS)
    assert not any(r.adoptable for r in ds)


def _rows(B, Ec, score, agree, variants=("none", "BT", "f")):
    res = S.ClaimResult(score, agree, 1.0, 1.1)
    return {(v, B, Ec): {c.key: res for c in CLAIMS} for v in variants}


def test_objective_is_weighted_mean_and_count_counts_agreeing_claims():
    """Hypothesis: with every claim at Jaccard s the objective is 1 - s whatever the
    weights, and the count is the number of fitted claims that agree; a missing row gives
    None; reading (b) takes fig11 from the B = 0 row."""
    a, b = S.readings()[:2]
    rows = _rows(0.01, 0.05, 0.25, True)
    obj, n = S.evaluate(a, 0.01, 0.05, rows, CLAIMS)
    assert obj == pytest.approx(0.75) and n == len(CLAIMS)
    assert S.evaluate(b, 0.01, 0.05, rows, CLAIMS) is None  # no fig11 row at B = 0
    rows.update(_rows(0.0, 0.05, 1.0, False, variants=("f",)))
    obj, n = S.evaluate(b, 0.01, 0.05, rows, CLAIMS)
    w11 = sum(c.weight for c in CLAIMS if c.preset == "fig11")
    w = sum(c.weight for c in CLAIMS)
    assert obj == pytest.approx(0.75 * (w - w11) / w)
    assert n == sum(c.preset != "fig11" for c in CLAIMS)


def test_edge_status_and_interior_with_b_zero():
    """Hypothesis: a best pair with evaluated neighbours on both sides is interior; on the
    smallest or largest positive B or the extreme Ec it is on that edge; at B = 0 the B
    direction is at its bound, which counts as interior."""
    Bs, Es = (0.0, 0.001, 0.01, 0.1), (0.02, 0.05, 0.08)
    centre = grid_land(Bs, Es, lambda B, E: abs(math.log10(B + 1e-9) + 2) + abs(E - 0.05))
    assert S.edge_status(centre) == {"B": "interior", "Ec": "interior"}
    assert S.is_interior(S.edge_status(centre))
    low = grid_land(Bs, Es, lambda B, E: (0.5 if B == 0 else B) + abs(E - 0.05))
    assert S.edge_status(low)["B"] == "low" and not S.is_interior(S.edge_status(low))
    high = grid_land(Bs, Es, lambda B, E: -B + E)
    assert S.edge_status(high) == {"B": "high", "Ec": "low"}
    zero = grid_land(Bs, Es, lambda B, E: B + abs(E - 0.05))
    assert S.edge_status(zero) == {"B": "zero", "Ec": "interior"}
    assert S.is_interior(S.edge_status(zero))


def test_propose_refines_around_an_interior_best():
    """Hypothesis: around an interior best the new pairs are the cross of {B, geometric
    midpoints} and {Ec, arithmetic midpoints}, less the best itself (8 pairs)."""
    Bs, Es = (0.0, 0.001, 0.01, 0.1), (0.02, 0.05, 0.08)
    land = grid_land(Bs, Es, lambda B, E: abs(math.log10(B + 1e-9) + 2) + abs(E - 0.05))
    new = S.propose(land, b_factor=10.0, ec_step=0.03)
    bs = sorted({b for b, _ in new})
    es = sorted({e for _, e in new})
    assert bs == pytest.approx([math.sqrt(1e-5), 0.01, math.sqrt(1e-3)], rel=1e-3)
    assert es == pytest.approx([0.035, 0.05, 0.065])
    assert len(new) == 8 and (0.01, 0.05) not in new


def test_propose_extends_outward_on_an_edge_and_not_below_b_zero():
    """Hypothesis: a best on the largest B gets B x factor; on the smallest Ec, Ec -
    step (or half of Ec when that would reach 0); a best at B = 0 gets no new B, only new
    Ec at B = 0."""
    Bs, Es = (0.0, 0.001, 0.01, 0.1), (0.02, 0.05, 0.08)
    high = grid_land(Bs, Es, lambda B, E: -B + E)
    new = S.propose(high, b_factor=10.0, ec_step=0.03)
    assert max(b for b, _ in new) == pytest.approx(1.0)
    assert min(e for _, e in new) == pytest.approx(0.01)  # 0.02 - 0.03 < 0: halfway
    zero = grid_land(Bs, Es, lambda B, E: B + abs(E - 0.05))
    new = S.propose(zero, b_factor=10.0, ec_step=0.03)
    assert {b for b, _ in new} == {0.0}
    assert sorted(e for _, e in new) == pytest.approx([0.035, 0.065])


def test_convergence_criterion():
    """Hypothesis: converged needs a refinement, a change below TOL and an interior best;
    missing any one of the three is not converged."""
    inner = {"B": "interior", "Ec": "interior"}
    assert S.converged([0.5, 0.495], inner)
    assert S.converged([0.5, 0.5], {"B": "zero", "Ec": "interior"})
    assert not S.converged([0.5], inner)
    assert not S.converged([0.5, 0.48], inner)
    assert not S.converged([0.5, 0.495], {"B": "low", "Ec": "interior"})
    assert not S.converged([0.5, 0.495], {"B": "interior", "Ec": "high"})


def test_rank_prefers_more_agreeing_claims_then_lower_objective():
    """Hypothesis: a reading with more agreeing claims ranks first even at a worse
    objective; equal counts are ordered by the objective."""
    assert S.rank_key(0.7, 3) < S.rank_key(0.5, 2)
    assert S.rank_key(0.5, 2) < S.rank_key(0.6, 2)


def test_coarse_grid_matches_the_issue():
    """Hypothesis: the coarse grid is B = 0 plus B log-spaced from 0.001 to 0.1, and Ec
    from 0.02 to 0.15, strictly increasing (map rows need that)."""
    assert S.COARSE_B[0] == 0.0 and S.COARSE_B[1] == 0.001 and S.COARSE_B[-1] == 0.1
    assert all(b < c for b, c in zip(S.COARSE_B, S.COARSE_B[1:]))
    assert S.COARSE_EC[0] == 0.02 and S.COARSE_EC[-1] == 0.15


@pytest.mark.slow
def test_quick_run_writes_report_json_dataset_and_figure(tmp_path):
    """Hypothesis: ``calibrate.py --quick`` on a 3-point eta grid writes the report, its
    winner JSON block (keys reading, B, Ec, objective, agree_count, presets with Bh/BT/f),
    the dataset and the figure into --out, and nothing into reports/."""
    import calibrate

    out = tmp_path / "out"
    calibrate.main(["--quick", "--workers", "1", "--step", "0.3", "--out", str(out),
                    "--cache", str(tmp_path / "cache")])
    md = (out / "calibration.md").read_text()
    assert (out / "calibration.nc").stat().st_size > 0
    assert (out / "figures" / "calibration.png").stat().st_size > 0
    block = re.search(r"```json\n(\{.*?\n\})\n```", md, re.S).group(1)
    win = json.loads(block)
    for k in ("reading", "B", "Ec", "objective", "agree_count", "presets", "converged",
              "interior"):
        assert k in win
    assert set(win["presets"]) == set(S.FIT_PRESETS)
    for d in win["presets"].values():
        assert set(d) >= {"Bh", "BT", "f"}
    import xarray as xr

    ds = xr.load_dataset(out / "calibration.nc")
    assert {"objective", "agree_count", "score", "B", "Ec"} <= set(ds.data_vars)
