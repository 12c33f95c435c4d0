"""``vibimpact -v`` says what a run does, ``-vv`` each point too, and without ``-v``
nothing of it is written (issue 32: ``-v`` logged almost nothing).

Each command runs in this process (:func:`vibimpact.cli.main`) on a tiny request, its
stderr captured; the log lines are the package's ``logging`` records (logger
``vibimpact``), which ``-v`` sends to stderr at INFO and ``-vv`` at DEBUG.
"""
import contextlib
import io as stdio

import pytest

from vibimpact.cli import main

N = ["--no-progress", "--workers", "1"]
#: command -> (arguments, what its -v log must say: one fragment per step)
COMMANDS = {
    "classify": (["classify", "--eta", "1.0:1.02:0.01", "--blocks", "2", *N, "-o", "c.nc"],
                 ["INFO: parameters: ", "kh = 120", "INFO: plan: 1 row(s) x eta 1..1.02 "
                  "(3 points) x up: 2 blocks, 3 points to compute", "on serial",
                  "INFO: block 1/2 done (row 0 up, eta 1..1.01): 2 points (2 computed): ",
                  "INFO: block 2/2 done", "transients ", "tasks done in ",
                  "INFO: file of vibimpact frequency sweep: rotor"]),
    "simulate": (["simulate", "--eta", "1.25", "--periods", "3", "--transient", "5",
                  "-o", "s.nc", "--plot", "s.png"],
                 ["INFO: file of vibimpact simulation", "eta = 1.25",
                  "INFO: figure written to s.png ("]),
    "attractors": (["attractors", "--eta", "1.06", "--starts", "4", *N, "-o", "a.nc"],
                   ["INFO: block 1/", "4 points (4 computed)",
                    "INFO: census at eta 1.06: ", "attractors from 4 starts",
                    "INFO: file of vibimpact census"]),
    "continue": (["continue", "--eta", "1.18", "--stop", "1.19", "--approach", "1.1",
                  "--transient", "50", "-o", "b.nc"],
                 ["INFO: branch of the P1 orbit in eta from 1.18 towards 1.19",
                  "periods of transient (eta stepped from 1.1)", "INFO: branch: ",
                  " orbits, eta from 1.18 to ", "ended: ", "INFO: file of vibimpact"]),
}


def run(tmp_path, monkeypatch, *args):
    """``vibimpact ARGS`` in ``tmp_path``: ``(status, stderr)``."""
    monkeypatch.chdir(tmp_path)
    out, err = stdio.StringIO(), stdio.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main([str(a) for a in args] + ["--overwrite"])
    return rc, err.getvalue()


@pytest.mark.parametrize("command", list(COMMANDS))
def test_v_logs_each_step_and_no_v_logs_nothing(command, tmp_path, monkeypatch):
    """Hypothesis: with -v the command's stderr holds a line for each step a user
    follows (parameters, the plan: grid, blocks and points, each block's summary with
    its regimes and transients, the timing, the file and figure written, a census's
    attractors, a branch's start and end), at INFO and no DEBUG line; the same command
    without -v writes none of them."""
    args, wanted = COMMANDS[command]
    rc, err = run(tmp_path, monkeypatch, "-v", *args)
    assert rc == 0, err
    missing = [w for w in wanted if w not in err]
    assert missing == [], err
    assert "DEBUG:" not in err
    rc, quiet = run(tmp_path, monkeypatch, *args)
    assert rc == 0, quiet
    assert "INFO:" not in quiet and "DEBUG:" not in quiet
    assert not [w for w in wanted if w.split(": ", 1)[-1] in quiet and "INFO" in w]


def test_vv_adds_each_points_decision(tmp_path, monkeypatch):
    """Hypothesis: -vv adds one DEBUG line per point computed, with its eta, its regime,
    its transient and why it was decided so; -v has none of them."""
    args = ["classify", "--eta", "1.0:1.02:0.01", *N, "-o", "c.nc"]
    rc, err = run(tmp_path, monkeypatch, "-vv", *args)
    assert rc == 0, err
    points = [line for line in err.splitlines() if line.startswith("vibimpact: DEBUG: "
                                                                   "point eta ")]
    assert [p.split()[4] for p in points] == ["1:", "1.01:", "1.02:"]
    assert all(" after a transient of " in p and " periods over all attempts, " in p
               for p in points)
    rc, err = run(tmp_path, monkeypatch, "-v", *args)
    assert "point eta" not in err


def test_the_plan_and_the_block_lines_count_transients_the_same_way():
    """Hypothesis: the plan line states ``transient_max`` as a budget per attempt and
    every block and point line counts a transient over all attempts, so a point whose
    transient (restarts included) exceeds the budget is not reported as breaking a
    limit: the plan does not say "at most", and the block line names the count's scope
    (issue 32: "transient at most 200 periods" beside "transients 328..328 periods")."""
    from types import SimpleNamespace

    from vibimpact.engine import logtext
    from vibimpact.points.logtext import point

    task = SimpleNamespace(row=0, direction="up", etas=[1.0], done=[], todo=1)
    settings = SimpleNamespace(analyses=("period",), transient_max=200)
    plan = logtext.request([0], [1.0], ["up"], [task], settings)
    res = {"regime": 1, "period": 1, "transient": 328, "recorded": 40}
    blk = logtext.block(task, [(0, res)], 1, 1, 0.5)
    one = point(1.0, res)
    assert "transient budget 200 periods per attempt" in plan and "at most" not in plan
    assert "transients 328..328 periods over all attempts" in blk
    assert "after a transient of 328 periods over all attempts" in one
