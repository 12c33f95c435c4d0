"""A resume keeps every entry the interrupted run saved (issue 44, class 6).

``orbits`` resumed after SIGTERM, SIGKILL or a lost worker set aside every entry the
run had saved as ``*.corrupt`` and computed it again: the check of a loaded point
wanted a sweep's ``final_state``, which an orbit's extent does not have.  SIGINT while a
``basins`` or ``classify`` checkpoint was being made left a directory without its
``request.json`` that the next ``--resume`` refused.  Now the check is per kind and a
checkpoint is made whole (under a temporary name, with its request, then renamed).
"""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from vibimpact.engine import ckdir
from vibimpact.engine.store import FIELDS, Checkpoint
from test_bad_input import listing

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "analyses" / "reliability"))
from _cases_r4_checkpoints import AT_CREATION  # noqa: E402 -- the reliability run's fault

STREAMS = {"rows": 1, "directions": ["states"], "points": 2}

#: one point result of each checkpoint kind, as its runner saves it
RESULTS = {
    "orbits": dict(lo=1.05, hi=1.07, lo_reason="end of the window",
                   hi_reason="fold", stable=np.array([[1.05, 1.07]]),
                   values=np.linspace(1.05, 1.07, 5), stable_points=np.ones(5, bool),
                   impacts=np.zeros(5, np.int64), abs_max=np.ones(5),
                   same_impacts=np.array([1.05, 1.07])),
    "census": dict(decided_by=1, periods=3, final_state=np.zeros(4)),
    "sweep": dict(final_state=np.zeros(4), regime=1),
    "map": dict(final_state=np.zeros(4), regime=2, period=1),
}


@pytest.mark.parametrize("kind", list(RESULTS))
def test_every_entry_of_every_kind_loads_on_resume(kind, tmp_path):
    """Hypothesis: the entries a run of each checkpoint kind (orbits, census, sweep,
    map) saved all load on resume: none is set aside, the last resume counts them."""
    assert set(RESULTS) == set(FIELDS)
    ck = Checkpoint(tmp_path / "ck").open(kind, {"k": kind}, STREAMS, False)
    for j in range(2):
        ck.save(0, "states", [(j, RESULTS[kind])])
    done = Checkpoint(tmp_path / "ck").open(kind, {"k": kind}, STREAMS, True).load()
    assert sorted(done[(0, "states")]) == [0, 1]
    last = Checkpoint(tmp_path / "ck").last_resume()
    assert (last["points"], last["damaged"]) == (2, [])
    assert not list((tmp_path / "ck").glob("*.corrupt"))


@pytest.mark.parametrize("kind", ["orbits", "sweep"])
def test_a_result_without_its_kinds_fields_is_still_damaged(kind, tmp_path):
    """Hypothesis: an entry of the right request whose point lacks a field of its kind
    (an orbit without 'hi', a sweep point without 'regime') is set aside as damaged."""
    ck = Checkpoint(tmp_path / "ck").open(kind, {"k": kind}, STREAMS, False)
    missing = {k: v for k, v in RESULTS[kind].items() if k not in ("hi", "regime")}
    ck.save(0, "states", [(0, missing)])
    done = Checkpoint(tmp_path / "ck").open(kind, {"k": kind}, STREAMS, True).load()
    assert done == {}
    assert Checkpoint(tmp_path / "ck").last_resume()["reasons"] == {
        "states_000000_000000-000001.npz.corrupt": "damaged"}


def test_an_interrupt_while_the_checkpoint_is_made_leaves_none(tmp_path, monkeypatch):
    """Hypothesis: an interrupt while request.json is written into a new checkpoint
    leaves no checkpoint and no temporary directory, so the next run (resumed or not)
    starts afresh; the run after that makes it whole."""
    real = ckdir.write_atomic

    def interrupted(fd, name, data):
        if name == "request.json":
            raise KeyboardInterrupt
        return real(fd, name, data)

    monkeypatch.setattr(ckdir, "write_atomic", interrupted)
    with pytest.raises(KeyboardInterrupt):
        Checkpoint(tmp_path / "c.nc.partial").open("sweep", {"a": 1}, STREAMS, False)
    assert listing(tmp_path) == []
    monkeypatch.setattr(ckdir, "write_atomic", real)
    ck = Checkpoint(tmp_path / "c.nc.partial").open("sweep", {"a": 1}, STREAMS, True)
    assert listing(ck.path) == ["request.json"]


def test_a_killed_makers_temporary_checkpoint_is_removed(tmp_path):
    """Hypothesis: the temporary directory of a checkpoint whose maker was killed
    (SIGKILL, a dead process id in its name) is removed when the checkpoint is made;
    a live maker's is left alone."""
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True).stdout.strip()
    stale = tmp_path / f".c.nc.partial.{dead}-abcd1234.tmp"
    live = tmp_path / f".c.nc.partial.{os.getpid()}-abcd1234.tmp"
    for d in (stale, live):
        d.mkdir()
        (d / "request.json").write_text("{}")
    Checkpoint(tmp_path / "c.nc.partial").open("sweep", {"a": 1}, STREAMS, False)
    assert listing(tmp_path) == [live.name, "c.nc.partial"]


def _harness(tmp_path, code, argv):
    """``vibimpact argv`` in a Python process that runs ``code`` first (``code`` that
    does not end by running the command line gets that appended)."""
    if "main(sys.argv" not in code:
        code += "\nimport sys\nfrom vibimpact.cli import main\nsys.exit(main(sys.argv[1:]))"
    return subprocess.run([sys.executable, "-c", code, *argv], cwd=tmp_path,
                          capture_output=True, text=True, timeout=180)


#: the process signals itself after its second saved entry
AFTER_TWO = """
import os, signal
from vibimpact.engine.store import Checkpoint
real, saved = Checkpoint.save, []
def save(self, *a, **k):
    real(self, *a, **k)
    saved.append(1)
    if len(saved) == 2:
        os.kill(os.getpid(), signal.{sig})
Checkpoint.save = save
"""
COMMANDS = {
    "classify": ["classify", "--preset", "fig8", "--eta", "1.0:1.03:0.01", "--workers",
                 "1", "--analyses", "period", "--no-progress", "-o", "o.nc"],
    "basins": ["basins", "--preset", "fig11", "--eta", "1.06", "--grid", "10x10",
               "--workers", "1", "--no-progress", "-o", "o.nc"],
    "attractors": ["attractors", "--preset", "fig11", "--eta", "1.06,1.07", "--starts",
                   "4", "--workers", "1", "--no-progress", "-o", "o.nc"],
    "orbits": ["orbits", "--preset", "fig11", "--eta", "1.06", "--period", "1:3",
               "--random", "48", "--window", "0.01", "--workers", "1", "--no-progress",
               "-o", "o.nc"],
    "map": ["map", "--preset", "fig8", "--eta", "1.0:1.02:0.01", "--vary",
            "kh=100,110,120", "--workers", "1", "-o", "o.nc"],
}


def _same_as_uninterrupted(tmp_path, argv):
    from vibimpact.io import differences, read_netcdf

    ref = tmp_path / "ref"
    ref.mkdir()
    done = subprocess.run([sys.executable, "-m", "vibimpact", *argv], cwd=ref,
                          capture_output=True, text=True, timeout=180)
    assert done.returncode == 0, done.stderr
    # the data bit for bit (an orbit file's attributes hold its timings)
    assert differences(read_netcdf(ref / "o.nc"), read_netcdf(tmp_path / "o.nc"),
                       attributes=False)[0] == []


@pytest.mark.slow
@pytest.mark.parametrize("sig", ["SIGINT", "SIGKILL"])
@pytest.mark.parametrize("command", list(COMMANDS))
def test_a_signal_while_the_checkpoint_is_made_leaves_a_run_that_resumes(command, sig,
                                                                          tmp_path):
    """Hypothesis: SIGINT or SIGKILL while a checkpointed command writes its new
    checkpoint's request.json leaves no checkpoint without a request: --resume runs to
    the end (exit 0), removes what the killed run left, and writes the uninterrupted
    run's file bit for bit."""
    argv = COMMANDS[command]
    stopped = _harness(tmp_path, AT_CREATION.replace("{sig}", sig), argv)
    assert stopped.returncode == (130 if sig == "SIGINT" else -9), stopped.stderr
    assert not (tmp_path / "o.nc.partial").exists()
    resumed = subprocess.run([sys.executable, "-m", "vibimpact", *argv, "--resume"],
                             cwd=tmp_path, capture_output=True, text=True, timeout=180)
    assert resumed.returncode == 0, resumed.stderr
    assert "not a vibimpact" not in resumed.stderr
    assert listing(tmp_path) == ["o.nc"]
    _same_as_uninterrupted(tmp_path, argv)


@pytest.mark.slow
@pytest.mark.parametrize("sig", ["SIGTERM", "SIGKILL"])
@pytest.mark.parametrize("command", ["orbits", "classify", "attractors"])
def test_a_resume_after_a_signal_loads_every_saved_entry(command, sig, tmp_path):
    """Hypothesis: after SIGTERM or SIGKILL following two saved entries, --resume loads
    every entry the run saved (none set aside as *.corrupt), says so, and writes the
    uninterrupted run's file bit for bit."""
    argv = COMMANDS[command]
    stopped = _harness(tmp_path, AFTER_TWO.replace("{sig}", sig), argv)
    assert stopped.returncode == (143 if sig == "SIGTERM" else -9), stopped.stderr
    saved = Checkpoint(tmp_path / "o.nc.partial").saved()[0]
    assert saved >= 2
    resumed = subprocess.run([sys.executable, "-m", "vibimpact", *argv, "--resume"],
                             cwd=tmp_path, capture_output=True, text=True, timeout=180)
    assert resumed.returncode == 0, resumed.stderr
    assert "set aside" not in resumed.stderr
    assert f"resumed from o.nc.partial: {saved} points loaded" in resumed.stderr
    _same_as_uninterrupted(tmp_path, argv)
