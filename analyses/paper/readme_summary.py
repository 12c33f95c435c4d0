"""The README's summary of the calibration and of the agreement with the paper.

Every number in it is read from the files the reports' scripts wrote:
``reports/calibration.nc`` and ``.md`` (``analyses/paper/calibrate.py``: the winning reading and
pair, its objective and count, whether the optimum is interior and converged, the run's
time) and
``reports/paper.json`` (``analyses/paper/paper.py``: the claims that agree at the shipped and at
the previous defaults).  ``python analyses/paper/readme_summary.py`` rewrites the README's
``summary`` section; ``analyses/paper/paper.py`` calls it after the report, and
``tests/test_report_sources.py`` fails when the README no longer matches the files.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SECTION = "summary"


def calibration(root=ROOT):
    """The winner (``reports/calibration.nc``) and the run record (the last JSON block of
    ``reports/calibration.md``), as dicts."""
    import re

    import xarray as xr

    with xr.open_dataset(root / "reports" / "calibration.nc") as cal:
        win = json.loads(cal.attrs["winner"])
    blocks = re.findall(r"```json\n(.*?)\n```", (root / "reports" / "calibration.md")
                        .read_text(), re.S)
    run = json.loads(blocks[-1]) if blocks else {}
    return win, run


def paper(root=ROOT):
    """The claim verdicts of ``reports/paper.json``."""
    return json.loads((root / "reports" / "paper.json").read_text())


def _keys(verdicts, what):
    return ", ".join(sorted(k for k, v in verdicts.items() if v == what)) or "none"


def summary_text(root=ROOT):
    """The Markdown of the README's summary section."""
    win, run = calibration(root)
    pap = paper(root)
    conv = "interior and converged" if win["interior"] and win["converged"] else (
        "**not** converged" if win["interior"] else "**on the edge of the grid**")
    minutes = f", {run['seconds'] / 60:.1f} min on this machine" if "seconds" in run else ""
    damp = "; ".join(
        f"{fig}: " + (", ".join(f"{k} = {v:g}" for k, v in d.items() if k != "B" and v)
                      or "none") + (f", B = {d['B']:g}" if d.get("B") != win["B"] else "")
        for fig, d in sorted(win["presets"].items()))
    v = pap["verdicts"]
    lines = [
        f"* **Calibrated defaults: B = {win['B']:g}, Ec = {win['Ec']:g}**, not values "
        f"from the paper: the best pair of the reading that reproduces most of the paper's "
        f"interval claims, reading ({win['reading']}), {win['text']} (contact dampings "
        f"{damp}); objective {win['objective']:.3f}, {win['agree_count']} of "
        f"{win['claims']} fitted claims agree; optimum {conv} after "
        f"{win['refinements']} refinements (`python analyses/paper/calibrate.py`{minutes}; "
        "[reports/calibration.md](reports/calibration.md)).",
        f"* **Agreement with the paper** ([reports/paper.md](reports/paper.md)): "
        f"{pap['agree']} of {pap['claims']} interval claims agree within one sweep step at "
        f"these defaults, {pap['agree_previous']} of {pap['claims_previous']} at the previous "
        f"defaults (B = {pap['previous']['fig8']['B']:g}, Ec = "
        f"{pap['previous']['fig8']['Ec']:g}) in the same run.  Agree: {_keys(v, 'agree')}; "
        f"partly: {_keys(v, 'partly')}; disagree: {_keys(v, 'disagree')}.",
    ]
    return "\n".join(lines)


def main(argv=None):
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # analyses/: _common
    from _common import smoke
    from _common.report import write_section

    out = smoke.parser(__doc__).parse_args(argv).smoke
    text = summary_text()
    write_section(smoke.moved(ROOT / "README.md", out), SECTION, text)
    print(text)


if __name__ == "__main__":
    main()
