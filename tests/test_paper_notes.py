"""The hand-written reading of reports/paper.md cannot drift from the report's data.

``analyses/paper/paper_notes.md`` is rendered into ``reports/paper.md`` by
``analyses/paper/paper_notes.py``: verdicts and numbers are filled in from the data that
``paper.py`` stores in ``reports/paper.json``, every other statement carries a check on it.
"""
import copy
import json
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "analyses" / "paper"))
import paper_notes  # noqa: E402

PAPER = json.loads((ROOT / "reports" / "paper.json").read_text())
REPORT = (ROOT / "reports" / "paper.md").read_text()


def test_the_notes_in_the_report_are_the_notes_rendered_from_the_reports_data():
    """Hypothesis: the notes' section of reports/paper.md is exactly what
    paper_notes.render makes of analyses/paper/paper_notes.md and reports/paper.json
    today (every check passes; an edited note or changed data without a re-render
    fails)."""
    assert paper_notes.section_of(REPORT) == paper_notes.render(PAPER)


def test_a_note_that_contradicts_a_verdict_of_the_table_fails():
    """Hypothesis: when the data's verdict on fig9 (or on rr10, or on fig8's chaos)
    changes while the notes still state the old one, rendering raises NotesDrift naming
    the failed check -- the drift that let 'changes fig8 little' stand beside 'partly'."""
    for key, new in (("fig9:", "agree"), ("rr10:", "agree")):
        data = copy.deepcopy(PAPER)
        row = next(k for k in data["comparative"] if k.startswith(key))
        data["comparative"][row] = new
        with pytest.raises(paper_notes.NotesDrift, match="check fails"):
            paper_notes.render(data)
    data = copy.deepcopy(PAPER)
    data["verdicts"]["fig8-chaos"] = "agree"
    with pytest.raises(paper_notes.NotesDrift, match="check fails"):
        paper_notes.render(data)


def test_a_number_the_notes_interpret_is_checked_against_the_table():
    """Hypothesis: a measured number whose interpretation no longer holds (fig9's largest
    response difference below the criterion, while the notes say 'more than') fails the
    render."""
    data = copy.deepcopy(PAPER)
    row = next(k for k in data["comparative_values"] if k.startswith("fig9:"))
    data["comparative_values"][row]["max_response_diff"] = 0.01
    with pytest.raises(paper_notes.NotesDrift, match="check fails"):
        paper_notes.render(data)


def test_a_statement_that_nothing_checks_is_refused():
    """Hypothesis: a paragraph or a bullet with neither a filled-in value nor a check
    fails the render (prose cannot state a result that no test ties to the data), while a
    heading needs none."""
    text = "## Heading\n\nBacked: {{ V['fig8-AB'] }}.\n\n* an unchecked bullet\n"
    with pytest.raises(paper_notes.NotesDrift, match="no value or check backs"):
        paper_notes.render(PAPER, text)
    out = paper_notes.render(PAPER, "## Heading\n\nBacked: {{ V['fig8-AB'] }}.\n")
    assert f"Backed: {PAPER['verdicts']['fig8-AB']}." in out


def test_values_are_filled_from_the_data_with_their_format():
    """Hypothesis: ``{{ EXPR | FORMAT }}`` is replaced by the formatted value of EXPR on
    the data, and an expression naming data that is not there fails the render."""
    out = paper_notes.render(PAPER, "x {{ P['step'] | g }} y {{ cmp('fig9:')['same_label'] | .0% }}")
    fig9 = next(v for k, v in PAPER["comparative_values"].items() if k.startswith("fig9:"))
    assert f"x {PAPER['step']:g} y {fig9['same_label']:.0%}" in out
    with pytest.raises(paper_notes.NotesDrift, match="cannot be evaluated"):
        paper_notes.render(PAPER, "x <!-- check: V['no-such-claim'] == 'agree' -->")


def test_the_report_stores_its_sweep_step_and_grid():
    """Hypothesis: reports/paper.json stores the step and grid of the sweeps it was made
    from, and they are the ones its report states (paper.md's first paragraph)."""
    assert PAPER["step"] > 0 and PAPER["grid"] == f"0.9:1.5:{PAPER['step']:g}"
    assert f"η = {PAPER['grid']} with pure continuation" in REPORT.split("\n\n")[1]


def test_a_render_only_run_computes_no_sweep(tmp_path, monkeypatch):
    """Hypothesis: with paper_sweeps.CACHE_ONLY (paper.py --render-only) a sweep that the
    cache does not hold raises NotCached naming its file, instead of being computed, and
    writes nothing into the cache."""
    import paper_sweeps

    monkeypatch.setattr(paper_sweeps, "CACHE_ONLY", True)
    with pytest.raises(paper_sweeps.NotCached, match="fig8_.*nc"):
        paper_sweeps.sweep_one(("fig8", 0.005, str(tmp_path), False, {}))
    assert list(tmp_path.iterdir()) == []
