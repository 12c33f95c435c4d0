"""Counts in words agree with their number ("1 impact", "2 impacts") in labels, legends
and printed lines, and every command's progress bar carries the command's name and
prints its full line once (issue 24, part 4)."""
import re
import time

import numpy as np
import pytest

from vibimpact.base._text import count
from vibimpact.cli import main


def run_cli(argv, capfd):
    try:
        rc = main([str(a) for a in argv])
    except SystemExit as exc:
        rc = exc.code
    out, err = capfd.readouterr()
    return rc, out, err


@pytest.mark.parametrize("n, noun, plural, want", [
    (1, "impact", None, "1 impact"), (2, "impact", None, "2 impacts"),
    (0, "impact", None, "0 impacts"), (1.0, "impact", None, "1 impact"),
    (3.0, "small arc", None, "3 small arcs"), (np.int64(1), "point", None, "1 point"),
    (1, "boundary", "boundaries", "1 boundary"), (2, "boundary", "boundaries",
                                                  "2 boundaries")])
def test_count_makes_the_noun_agree(n, noun, plural, want):
    """Hypothesis: exactly one takes the singular, every other count (0 included) the
    plural; a whole float prints without decimals."""
    assert count(n, noun, plural) == want


def test_sweep_labels_say_1_impact_and_2_impacts():
    """Hypothesis: the interval label of a periodic point with one impact per period says
    "1 impact" (it said "1 impacts"), with two "2 impacts"; the Regime's text agrees."""
    from vibimpact.analysis.classify import Label, Regime
    from vibimpact.points.point import REGIME_CODES
    from vibimpact.sweeps.dataset import label_text

    code = REGIME_CODES[Label.PERIODIC]
    assert label_text(code, 1, 1.0, "1 small arc") == "P1, 1 impact, 1 small arc"
    assert label_text(code, 3, 2.0, "2 small arcs") == "P3, 2 impacts, 2 small arcs"
    one = Regime(Label.PERIODIC, n=1, impacting=True, impacts_per_period=1.0)
    assert str(one) == "P1, 1 impact"
    assert str(Regime(Label.PERIODIC, n=2, impacting=True,
                      impacts_per_period=2.0)) == "P2, 2 impacts"


def test_map_summary_counts_points_and_directions(capsys):
    """Hypothesis: the map's printed summary says "1 point" for a one-point map and
    "2 directions" for an up-and-down map (it said "1 points", "2 direction")."""
    import xarray as xr

    from vibimpact.cli.map import _summary

    one = xr.Dataset({"regime": (("kh", "eta"), np.array([[1]], dtype="i1"))},
                     coords={"kh": [40.0], "eta": [1.0]})
    _summary(one, 1.0, computed=1)
    assert "= 1 point:" in capsys.readouterr().out
    both = xr.Dataset({"regime": (("direction", "kh", "eta"), np.ones((2, 1, 2), "i1"))},
                      coords={"direction": ["up", "down"], "kh": [40.0],
                              "eta": [1.0, 1.1]})
    _summary(both, 1.0, computed=4)
    assert capsys.readouterr().out.startswith("map 2 directions x 1 kh x 2 eta = 4 points:")


def _bar_lines(err, name):
    """The bar's states in stderr: tqdm redraws with carriage returns."""
    return [s.strip() for s in re.split(r"[\r\n]", err) if s.strip().startswith(f"{name}:")]


def test_progress_bar_prints_its_full_line_once_when_closed_late(capfd):
    """Hypothesis: a bar whose work ends some time before its context closes (a map's
    Dask cluster shutting down) prints its 100 % line once, not a second time at close;
    a bar that stops short prints no 100 % line."""
    from vibimpact.engine.progress import bar

    with bar(True, 2, "map") as report:
        time.sleep(0.15)
        report(1)
        time.sleep(0.15)
        report(1)
        time.sleep(0.15)
    err = capfd.readouterr().err
    assert sum("100%" in s for s in _bar_lines(err, "map")) == 1
    with bar(True, 3, "map") as report:
        report(1)
    lines = _bar_lines(capfd.readouterr().err, "map")
    assert lines and not any("100%" in s for s in lines)


def test_progress_callback_names_the_bar_by_the_text_given(capfd):
    """Hypothesis: a str progress argument is a bar of that name; True is the front
    end's own name; a callable is called with the counts."""
    from vibimpact.engine.progress import callback

    with callback("bifurcation", 1, "sweep") as report:
        report(1)
    with callback(True, 1, "sweep") as report:
        report(1)
    err = capfd.readouterr().err
    assert _bar_lines(err, "bifurcation") and _bar_lines(err, "sweep")
    seen = []
    with callback(seen.append, 5, "sweep") as report:
        report(2)
        report(3)
    assert seen == [2, 3] and capfd.readouterr().err == ""


@pytest.mark.parametrize("argv, name", [
    (["classify", "--eta", "1.0,1.01", "--workers", "1", "-o", "c.nc"], "classify"),
    (["bifurcation", "--eta", "1.0,1.01", "--workers", "1", "-o", "b.png"], "bifurcation"),
    (["map", "--eta", "1.0,1.01", "--vary", "kh=40,80", "--workers", "1", "-o", "m.nc"],
     "map")])
def test_each_command_names_its_progress_bar_and_prints_it_once(argv, name, tmp_path,
                                                                 monkeypatch, capfd):
    """Hypothesis: classify, bifurcation and map each draw one progress bar named after
    the command (bifurcation said "classify:"), and its 100 % line appears once."""
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(argv, capfd)
    assert rc == 0, err
    lines = _bar_lines(err, name)
    assert lines, err
    others = {"classify", "bifurcation", "map", "sweep"} - {name}
    assert not any(_bar_lines(err, o) for o in others), err
    assert sum("100%" in s for s in lines) == 1, lines
