"""What the shipped defaults produce: the paper's claims the report says agree do agree.

``reports/paper.json`` (written by ``analyses/paper/paper.py``) lists the verdict of every
interval claim of the paper at the shipped defaults.  These tests sweep the presets again,
as the report does, and check each claim it calls "agree" on the fresh sweep: a change of
the code or of the defaults that breaks an agreement fails here, not silently in the next
report.
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
STEP = 0.005
AGREE = sorted(k for k, v in PAPER["verdicts"].items() if v == "agree")


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
    assert PAPER["B"] == pytest.approx(vi.params.DEFAULT_B)
    assert PAPER["Ec"] == pytest.approx(vi.params.DEFAULT_EC)


@pytest.mark.parametrize("key", AGREE or ["(none)"])
def test_claims_the_report_says_agree_agree_in_a_fresh_sweep(key, sweeps):
    """Hypothesis: every interval claim that reports/paper.md calls 'agree' at the
    shipped defaults is detected within one sweep step by a fresh sweep of its preset."""
    if key == "(none)":
        assert PAPER["agree"] == 0
        return
    claim = next(c for c in C.CLAIMS if c.key == key)
    det = C.detect(sweeps(claim.preset), claim)[0]
    assert det.agree, (key, det)
