"""The README's and the reports' figures are the data's: these tests fail when they drift.

Every number of the README's summary, of the calibration report and of the paper report is
written by a script from the files it measured (``reports/calibration.nc``,
``reports/paper.json``); the shipped defaults are the calibration's winner.
"""
import json
import re
import sys
from pathlib import Path

import pytest

import vibimpact as vi
from vibimpact.models import params

ROOT = Path(__file__).resolve().parents[1]
REPORTS = ROOT / "reports"
for _kind in ("paper", "performance", "reliability"):
    sys.path.insert(0, str(ROOT / "analyses" / _kind))


def _winner():
    import xarray as xr

    with xr.open_dataset(REPORTS / "calibration.nc") as cal:
        return json.loads(cal.attrs["winner"])


def _section(text, name):
    m = re.search(rf"<!-- section:{name} -->\n(.*?)\n<!-- /section:{name} -->", text, re.S)
    return None if m is None else m.group(1)


def test_readme_summary_is_what_the_report_files_say():
    """Hypothesis: the README's summary section is exactly what readme_summary renders from
    reports/calibration.nc, calibration.md and paper.json (no hand-typed figure)."""
    import readme_summary

    got = _section((ROOT / "README.md").read_text(), readme_summary.SECTION)
    assert got is not None, "README has no summary section"
    assert got.strip() == readme_summary.summary_text(ROOT).strip()


def test_shipped_defaults_are_the_converged_calibration_winner():
    """Hypothesis: DEFAULT_B, DEFAULT_EC and every fitted preset's B and contact dampings
    are the winning reading's of the calibration, whose optimum is interior and
    converged."""
    win = _winner()
    assert win["interior"] and win["converged"]
    assert params.DEFAULT_B == pytest.approx(win["B"], rel=1e-12, abs=1e-15)
    assert params.DEFAULT_EC == pytest.approx(win["Ec"], rel=1e-12)
    for fig, d in win["presets"].items():
        p = vi.presets.get(fig)
        for name in ("B", "Bh", "BT", "f"):
            assert getattr(p, name) == pytest.approx(d[name], abs=1e-15), (fig, name)
        assert p.Ec == pytest.approx(win["Ec"], rel=1e-12)


def test_calibration_report_states_the_datasets_winner():
    """Hypothesis: the winner's JSON block in calibration.md is the dataset's winner."""
    text = (REPORTS / "calibration.md").read_text()
    blocks = [json.loads(b) for b in re.findall(r"```json\n(.*?)\n```", text, re.S)]
    assert _winner() in blocks


def test_paper_report_counts_are_its_data_and_describe_the_shipped_defaults():
    """Hypothesis: the paper report's headline count of agreeing claims (shipped and
    previous defaults) is the one its JSON records, the JSON's verdicts add up to it, and
    it was made at the shipped B and Ec."""
    pap = json.loads((REPORTS / "paper.json").read_text())
    text = (REPORTS / "paper.md").read_text()
    assert f"**Interval claims: {pap['agree']} of {pap['claims']} agree" in text
    assert pap["claims_previous"] == pap["claims"]
    assert f"with the same detection: {pap['agree_previous']} of {pap['claims']}" in text
    assert sum(v == "agree" for v in pap["verdicts"].values()) == pap["agree"]
    assert sum(v == "agree" for v in pap["verdicts_previous"].values()) == \
        pap["agree_previous"]
    assert pap["B"] == pytest.approx(params.DEFAULT_B) and \
        pap["Ec"] == pytest.approx(params.DEFAULT_EC)


def test_performance_report_has_the_low_damping_timing():
    """Hypothesis: the performance report carries the measured low-damping ratio section,
    written by analyses/performance/benchmark_sweep.py, for the shipped defaults."""
    sec = _section((REPORTS / "performance.md").read_text(), "low-damping")
    assert sec is not None
    assert f"| shipped defaults | {params.DEFAULT_B:g} | {params.DEFAULT_EC:g} |" in sec


def test_performance_report_judges_the_first_run_by_its_own_numbers():
    """Hypothesis: the performance report carries the first-run section written by
    analyses/performance/first_run.py, timing each of its commands on an empty numba cache
    (first and warm run) and on a cache filled by the install's step (aot_build), whose
    time it gives with the package's word that the filled cache was in use; on the empty
    cache the first run compiles (cache files written), on the filled one it compiles
    nothing (none written); the empty cache's run prints the compile line (its time from
    the start, before the run ends), no warm or filled run does; and its verdicts on the
    targets are the ones its times imply."""
    import first_run

    sec = _section((REPORTS / "performance.md").read_text(), first_run.SECTION)
    assert sec is not None
    fill = re.search(r"^The fill \(the install step\) took ([\d.]+) s and wrote (\d+) cache "
                     r"files; the package then said of its kernel: \*(.*)\*\.$", sec, re.M)
    assert fill is not None
    assert float(fill.group(1)) > 0.0 and int(fill.group(2)) > 0
    assert fill.group(3).startswith("in use: numba's cache ")
    assert "python -m vibimpact._kernel.aot_build" in sec
    num = r" ([\d.]+) \|"
    rows = {m.group(1): (float(m.group(2)), *(float(g) for g in m.groups()[3:]))
            for m in re.finditer(r"^\| `(vibimpact [^`]+)` \|" + num + r" ([\d.]+|none) \|"
                                 + num * 4, sec, re.M)}
    lines = {m.group(1): m.group(3) for m in re.finditer(
        r"^\| `(vibimpact [^`]+)` \|" + num + r" ([\d.]+|none) \|", sec, re.M)}
    commands = {name: "vibimpact " + " ".join(a.replace("{out}", "OUT") for a in args)
                for name, args in first_run.COMMANDS.items()}
    assert set(rows) == set(commands.values())
    for empty, empty_files, warm, filled, filled_files in rows.values():
        assert empty >= warm > 0.0 and empty_files > 0
        assert filled > 0.0 and filled_files == 0
    for name, command in commands.items():
        empty, _, _, filled, _ = rows[command]
        verdict = re.search(rf"^- first `{name}` on the filled cache: ([\d.]+) s against the "
                            rf"target of (\d+) s: (.*); on an empty cache: ([\d.]+) s: (.*)$",
                            sec, re.M)
        assert verdict is not None, name
        assert float(verdict.group(2)) == first_run.TARGET_FIRST_S
        # the prose's figure and verdict against the same report's table (no clock here)
        for prose, tabled, said in ((verdict.group(1), filled, verdict.group(3)),
                                    (verdict.group(4), empty, verdict.group(5))):
            assert float(prose) == pytest.approx(tabled, abs=0.051)
            assert said == ("met" if tabled <= first_run.TARGET_FIRST_S else "**not met**")
        line = re.search(rf"^- `{name}`'s compile line on an empty cache \(seconds from the "
                         rf"process's start to the line on stderr\): ([\d.]+) s against the "
                         rf"target of (\d+) s: (met|\*\*not met\*\*); printed by a warm or "
                         rf"filled-cache run: no$", sec, re.M)
        assert line is not None, name
        assert float(line.group(1)) == pytest.approx(float(lines[command]), abs=0.0051)
        assert 0.0 < float(line.group(1)) < empty
        assert float(line.group(2)) == first_run.TARGET_LINE_S
        assert line.group(3) == ("met" if float(line.group(1)) <= first_run.TARGET_LINE_S
                                 else "**not met**")


def test_every_package_name_the_readme_cites_exists():
    """Hypothesis: each dotted name `vibimpact.x.y` in the README resolves to a module or
    an attribute of one (a module or name moved by a refactoring fails here)."""
    import importlib

    names = sorted(set(re.findall(r"`(vibimpact(?:\.[A-Za-z_]\w*)+)",
                                  (ROOT / "README.md").read_text())))
    assert names
    broken = []
    for name in names:
        parts = name.split(".")
        for i in range(len(parts), 0, -1):
            try:
                obj = importlib.import_module(".".join(parts[:i]))
            except ImportError:
                continue
            try:
                for attr in parts[i:]:
                    obj = getattr(obj, attr)
            except AttributeError:
                broken.append(name)
            break
        else:
            broken.append(name)
    assert broken == []


def test_reliability_report_counts_are_its_own_cases():
    """Hypothesis: reports/reliability.md is written by analyses/reliability/reliability.py and its
    summary is the count of its own case table: per fault class, the cases tried, clean,
    with a traceback, hung, with files left and with data lost are the rows of that class
    with that verdict, and the 'all' row is the sum over the classes."""
    import reliability

    sec = _section((REPORTS / "reliability.md").read_text(), reliability.SECTION)
    assert sec is not None
    summary, cases = sec.split("## Every case")
    rows = {m.group(1): [int(x) for x in m.group(2).split(" | ")]
            for m in re.finditer(r"^\| ([^|*]+?) \| ([\d |]+?) \|$", summary, re.M)}
    total = re.search(r"^\| \*\*all\*\* \| (.+) \|$", summary, re.M).group(1)
    total = [int(x.strip("* ")) for x in total.split(" | ")]
    assert rows and [sum(col) for col in zip(*rows.values())] == total
    table = [ln.split(" | ") for ln in cases.splitlines() if ln.startswith("| ")
             and not ln.startswith("| class") and not ln.startswith("| ---")]
    for klass, (tried, clean, tracebacks, hangs, left, lost, not_tried) in rows.items():
        mine = [r for r in table if r[0] == "| " + klass]
        verdicts = [r[4] for r in mine]
        assert len(mine) == tried + not_tried, klass
        assert verdicts.count("not tried") == not_tried
        assert verdicts.count("clean") == clean
        assert verdicts.count("**traceback**") == tracebacks
        assert verdicts.count("**hang**") == hangs
        assert sum(r[5] != "-" for r in mine) == left
        assert sum(r[6] == "**lost**" for r in mine) == lost


def test_performance_report_judges_the_ring_by_its_own_times():
    """Hypothesis: the performance report carries the section written by
    analyses/performance/ring_bench.py for its own request (grid, presets, repeats); each
    preset's best time is the least of its repeats, the ratio is the ring's best over
    eq. (5)'s, its verdict is the one the ratio implies against the script's target, and
    the same-motion ratios of (b) are those of their own times."""
    import ring_bench

    sec = _section((REPORTS / "performance.md").read_text(), ring_bench.SECTION)
    assert sec is not None
    assert f"`vibimpact classify --preset PRESET --eta {ring_bench.GRID}`" in sec
    assert f"best of {ring_bench.REPEATS}" in sec
    best = {}
    for name in ring_bench.PRESETS:
        row = re.search(rf"^\| {re.escape(name)} \| (\w+) \| ([\d., ]+) \| ([\d.]+) \|", sec,
                        re.M)
        assert row is not None, name
        times = [float(t) for t in row.group(2).split(", ")]
        assert len(times) == ring_bench.REPEATS and float(row.group(3)) == min(times)
        best[name] = float(row.group(3))
    ratio = re.search(r"^Ratio ring / eq\. \(5\): ([\d.]+) \(target <= ([\d.]+)\): "
                      r"\*\*(met|not met)\*\*\.$", sec, re.M)
    assert ratio is not None
    eq5, ring = (best[name] for name in ring_bench.PRESETS)
    assert float(ratio.group(1)) == pytest.approx(ring / eq5, abs=0.006)
    assert float(ratio.group(2)) == ring_bench.TARGET
    assert ratio.group(3) == ("met" if float(ratio.group(1)) <= ring_bench.TARGET
                              else "not met")
    same = re.findall(r"^\| [^|]+ \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \|$", sec, re.M)
    assert len(same) == 2
    for rotor, held, r in same:
        assert float(r) == pytest.approx(float(held) / float(rotor), rel=0.01, abs=0.006)
    parts = re.findall(r"^\| ([^|]+) \| ([\d.]+) \| [\d-]+ \| ([\d.]+) \| [\d-]+ \| "
                       r"([\d.]+|nan) \|$", sec, re.M)
    assert [p[0] for p in parts] == ["whole sweep"] + [p[0] for p in ring_bench.PARTS]
    for _, eq5_s, ring_s, r in parts:
        if float(eq5_s) >= 0.1:  # the ratio of the unrounded times; the rounding of 0.01
            assert float(r) == pytest.approx(float(ring_s) / float(eq5_s), rel=0.11)


def _section(text, name):
    return text.split(f"<!-- section:{name} -->")[1].split(f"<!-- /section:{name} -->")[0]


def test_every_verdict_on_fig8s_chaos_in_the_reports_is_the_claims_rule():
    """Hypothesis: wherever reports/performance.md judges fig8's chaos against the paper,
    it is by the paper report's rule: each row's verdict is claims.verdict of the
    detection the row states (interval, Jaccard, agree); the paper report's verdict it
    quotes is reports/paper.json's; and no section judges the chaos by another wording
    (the old 'within one sweep step' span test that said 'not within' where paper.md
    said 'partly')."""
    import math

    from vibimpact.paper import claims as C

    text = (REPORTS / "performance.md").read_text()
    sec = _section(text, "sweep-claims")
    rows = [r for r in sec.splitlines() if r.startswith("| ") and "**" in r]
    assert rows
    for r in rows:
        cells = [c.strip() for c in r.strip("|").split("|")]
        span, score, agree, verdict = cells[1], float(cells[2]), cells[3], cells[4]
        a, b = (float(x) for x in span.split(" to ")) if span != "none" else (math.nan,) * 2
        det = C.Detection("up", a, b, score, agree == "True", ())
        assert verdict == f"**{C.verdict(det)}**", r
    paper = json.loads((REPORTS / "paper.json").read_text())
    assert f"gives it **{paper['verdicts']['fig8-chaos']}**" in sec
    assert "one sweep step." not in text.replace(sec, "")
