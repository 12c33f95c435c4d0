"""What the shipped defaults produce: every verdict of the paper report holds.

``reports/paper.json`` (written by ``analyses/paper/paper.py``) lists the verdict of every
interval claim of the paper at the shipped defaults, and the sweep step it used.  These
tests sweep the presets again, as the report does, and judge every claim on the fresh
sweep by the report's own rule (:func:`vibimpact.paper.claims.judge`): a change of the
code or of the defaults that moves any verdict -- "agree", "partly" or "disagree", either
way -- fails here, not silently in the next report.  The sweeps take about a minute, so
that test is in the slow run (``.ci/run``); the checks of the report's own data are fast.
"""
import json
from pathlib import Path

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.paper import claims as C

ROOT = Path(__file__).resolve().parents[1]
PAPER = json.loads((ROOT / "reports" / "paper.json").read_text())
#: the report's sweeps: both directions, pure continuation, its analyses and eta step
ANALYSES = ("period", "impacts", "response", "poincare", "lyapunov")
STEP = PAPER["step"]
CLAIMS = sorted(PAPER["verdicts"])


@pytest.fixture(scope="module")
def sweeps():
    cache = {}

    def get(preset):
        if preset not in cache:
            eta = np.round(np.arange(0.9, 1.5 + 1e-9, STEP), 6)
            cache[preset] = vi.sweep(vi.presets.get(preset), eta, direction="both",
                                     analyses=ANALYSES,
                                     continuation=vi.Continuation(blocks=1))
        return cache[preset]
    return get


def test_the_report_was_made_at_the_shipped_defaults():
    """Hypothesis: the verdicts below are those of the shipped B and Ec."""
    from vibimpact.models.params import DEFAULT_B, DEFAULT_EC

    assert PAPER["B"] == pytest.approx(DEFAULT_B)
    assert PAPER["Ec"] == pytest.approx(DEFAULT_EC)


def test_the_report_judged_every_claim_of_the_paper():
    """Hypothesis: reports/paper.json has a verdict, one of the verdict rule's, for every
    claim of vibimpact.paper.claims and for no other (a claim added or renamed since the
    report was made fails)."""
    assert set(PAPER["verdicts"]) == {c.key for c in C.CLAIMS}
    assert set(PAPER["verdicts"].values()) <= set(C.VERDICTS)


@pytest.mark.slow  # four up-and-down sweeps of 121 points: about a minute on 2 cores
@pytest.mark.parametrize("key", CLAIMS)
def test_every_verdict_of_the_report_holds_in_a_fresh_sweep(key, sweeps):
    """Hypothesis: every interval claim gets, on a fresh sweep of its preset at the
    shipped defaults and the report's step, the verdict reports/paper.md gives it
    (agree, partly or disagree)."""
    claim = next(c for c in C.CLAIMS if c.key == key)
    verdict, det = C.judge(sweeps(claim.preset), claim)
    assert verdict == PAPER["verdicts"][key], (key, det)
