"""``vibimpact rerun`` of a crafted file (issue 44, class 5): a file's recorded command
asked for a classify of 100,000 points in both directions, a 300 x 300 map, 10,000,000
forcing periods or a 100,000-point bifurcation, and rerun started it without a word.

Now rerun says on stderr what it runs and how big it is, and refuses a command over the
limits of :mod:`vibimpact.cli.common.rerun_size` (one line, exit 2, nothing computed, no file)
unless ``--yes`` is given.  The crafted files are a tiny sweep file with its ``command``
attribute replaced (rerun reads nothing else before the guard); the runs accepted with
``--yes`` reach the recorded command's own function, replaced here by a stub.
"""
from __future__ import annotations

import shlex
from pathlib import Path

import pytest

from test_bad_input import run_cli, tiny_sweep_file

import doc_blocks as db
from vibimpact.cli import bifurcation, classify, continue_, map as cli_map, simulate
from vibimpact.cli import build_parser
from vibimpact.cli.common.rerun_size import (RERUN_MAX_BRANCH_PERIODS, RERUN_MAX_PERIODS,
                                      RERUN_MAX_POINTS, RERUN_MAX_SAMPLES,
                                      RERUN_MAX_WORKERS, size_of)

#: crafted recorded command -> (module, name of the command's function, what is said)
CRAFTED = {
    "classify 100,000 points both ways": (
        "vibimpact classify --eta 0.50001:1.5:0.00001 --direction both -o c.nc",
        classify, "_cmd_classify", "200,000 sweep points (both directions)"),
    "bifurcation 100,000 points": (
        "vibimpact bifurcation --eta 0.50001:1.5:0.00001 --direction up -o b.png",
        bifurcation, "_cmd_bifurcation", "100,000 sweep points"),
    "map 300 x 300": (
        "vibimpact map --eta 1.001:1.3:0.001 --vary kh=1:300:1 -o m.zarr",
        cli_map, "_cmd_map", "90,000 map cells"),
    "map both directions": (
        "vibimpact map --eta 1.001:1.2:0.001 --vary kh=1:60:1 --direction both -o m.nc",
        cli_map, "_cmd_map", "24,000 map cells (both directions)"),
    "simulate 10,000,000 periods": (
        "vibimpact simulate --periods 9999500 -o s.nc",
        simulate, "_cmd_simulate", "10,000,000 forcing periods"),
    "simulate dense samples": (
        "vibimpact simulate --periods 200000 --dense 60 -o s.nc",
        simulate, "_cmd_simulate", "12,200,002 samples stored"),
    "simulate --plot's samples": (
        "vibimpact simulate --periods 200000 -o s.nc --plot s.png",
        simulate, "_cmd_simulate", "13,000,002 samples stored"),
    "continue 100,000 points": (
        "vibimpact continue --stop 1.2 --max-points 100000 -o p.nc",
        continue_, "_cmd_continue", "100,000 orbit periods along the branch"),
    "continue long period with --switch": (
        "vibimpact continue --stop 1.2 --period 20 --max-points 400 --switch -o p.nc",
        continue_, "_cmd_continue", "24,000 orbit periods along the branch and its"),
    "continue far --approach": (
        "vibimpact continue --eta 1.1 --approach 100 --transient 20000 --stop 1.2 -o p.nc",
        continue_, "_cmd_continue", "forcing periods to the start"),
    "classify 4096 workers": (
        "vibimpact classify --eta 1.0:1.01:0.01 --workers 4096 -o c.nc",
        classify, "_cmd_classify", "4,096 worker processes"),
}


def crafted(d, command):
    """A tiny sweep file ``c.nc`` in ``d`` recording ``command``."""
    tiny_sweep_file(Path(d) / "in.nc", command=command)
    return "in.nc"


@pytest.mark.parametrize("case", list(CRAFTED))
def test_a_crafted_large_command_is_refused_without_yes(case, tmp_path, monkeypatch, capfd):
    """Hypothesis: rerun of a file recording a command over a rerun's limits ends with
    one line naming the file, the command, its size and --yes, exit 2, before any
    work (the command's function is not called) and with no file left."""
    command, module, func, said = CRAFTED[case]
    called = []
    monkeypatch.setattr(module, func, lambda args: called.append(args) or 0)
    monkeypatch.chdir(tmp_path)
    name = crafted(tmp_path, command)
    rc, out, err = run_cli(["rerun", name], capfd)
    assert rc == 2 and out == "" and not called, (rc, err)
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("vibimpact: error: 'in.nc' records "), err
    assert said in lines[0] and "--yes" in lines[0] and "a rerun starts without asking" \
        in lines[0], lines[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.nc"]


@pytest.mark.parametrize("case", list(CRAFTED))
def test_yes_runs_the_crafted_command_announced(case, tmp_path, monkeypatch, capfd):
    """Hypothesis: with --yes the same file passes the guard: rerun says on stderr what
    it runs and how big, then calls the recorded command (a stub here, returning 2:
    the rerun's status is the command's)."""
    command, module, func, said = CRAFTED[case]
    called = []
    monkeypatch.setattr(module, func, lambda args: called.append(args) or 2)
    monkeypatch.chdir(tmp_path)
    name = crafted(tmp_path, command)
    rc, _, err = run_cli(["rerun", name, "--yes"], capfd)
    assert rc == 2 and len(called) == 1, err
    assert err.splitlines() == [f"vibimpact: rerunning {command!r}: "
                                f"{size_of(called[0]).text()}"]
    assert said in err


def test_a_small_rerun_is_announced_and_runs(tmp_path, monkeypatch, capfd):
    """Hypothesis: the rerun of a small real file needs no --yes: one line on stderr
    says the command and its size (2 sweep points, 1 worker process, a time), and it
    ends 'identical' with exit 0."""
    monkeypatch.chdir(tmp_path)
    rc, _, err = run_cli(["classify", "--eta", "1.0:1.01:0.01", "--analyses", "period",
                          "--workers", "1", "--no-progress", "-o", "c.nc"], capfd)
    assert rc == 0, err
    rc, out, err = run_cli(["rerun", "c.nc"], capfd)
    assert rc == 0 and out.startswith("identical"), (out, err)
    line, = err.splitlines()
    assert line.startswith("vibimpact: rerunning 'vibimpact classify --eta 1.0:1.01:0.01")
    assert "2 sweep points, 1 worker process, about " in line


def test_a_grid_the_command_refuses_is_one_line(tmp_path, capfd, monkeypatch):
    """Hypothesis: a recorded grid over the command's own limit (100,001 points) is
    refused in the command's words, in one line, not announced first."""
    monkeypatch.chdir(tmp_path)
    name = crafted(tmp_path, "vibimpact classify --eta 0.5:1.5:0.00001 -o c.nc")
    rc, _, err = run_cli(["rerun", name, "--yes"], capfd)
    assert rc == 2 and len(err.splitlines()) == 1, err
    assert "--eta: eta grid has 100001 points" in err


def _doc_commands():
    """Every rerunnable vibimpact command of README.md and the user guide."""
    from vibimpact.cli.rerun import RERUNNABLE

    out = []
    for page in db.pages():
        for block in db.runnable(page):
            if block.language == "python":
                continue
            for line in db.shell_lines(block):
                for seg in db.segments(db.command(line) or []):
                    if seg[:1] == ["vibimpact"] and len(seg) > 1 and seg[1] in RERUNNABLE \
                            and line.expect == 0:
                        out.append(seg)
    return out


def test_every_documented_command_reruns_without_asking():
    """Hypothesis: the file of every classify, bifurcation, map, simulate and continue
    command of the README and the user guide is under every rerun limit (the limits
    are sized for them), and the limits are below the commands' own."""
    from vibimpact.base import _limits

    commands = _doc_commands()
    assert len(commands) > 20
    for words in commands:
        args = build_parser().parse_args(words[1:])
        assert size_of(args).over == [], shlex.join(words)
    assert RERUN_MAX_POINTS < _limits.MAX_POINTS and RERUN_MAX_PERIODS < _limits.MAX_PERIODS
    assert min(RERUN_MAX_SAMPLES, RERUN_MAX_BRANCH_PERIODS, RERUN_MAX_WORKERS) > 0
