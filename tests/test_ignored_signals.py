"""A signal the process was started ignoring stays ignored.

A shell script's background job (``vibimpact classify ... &``) starts with SIGINT
ignored, so that the Ctrl-C typed for the script does not reach it, and ``trap '' TERM``
or ``nohup``-like wrappers make a command ignore a signal on purpose.  Python keeps such a
signal ignored; the package's signal guard, its write block and the command line's entry
point must not turn it back on (they did: the guard installed its handler over
``SIG_IGN``, and a background ``classify`` died of the script's Ctrl-C).  A signal that
is not ignored is still handled as before.
"""
import os
import signal
import time

import numpy as np
import pytest
import xarray as xr

from test_faults_signals import (assert_one_interrupted_line, finish, messages,
                                 signal_and_finish, start)

SWEEP = ["classify", "--eta", "0.95:1.25:0.002", "--preset", "fig8", "--direction",
         "both", "--no-progress", "-o", "c.nc"]


@pytest.fixture
def sigint_ignored():
    """SIGINT ignored for the test, its handler put back after it."""
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    yield
    signal.signal(signal.SIGINT, old)


def test_the_guard_leaves_an_ignored_sigint_ignored_and_still_handles_sigterm(
        sigint_ignored):
    """Hypothesis: inside StopWorkersOnSignal, a SIGINT the process ignores does
    nothing (the block runs on) and stays ignored after the block, while SIGTERM is
    still the guard's: Interrupted(15)."""
    from vibimpact.engine.signals import Interrupted, StopWorkersOnSignal

    ran = []
    with StopWorkersOnSignal():
        assert signal.getsignal(signal.SIGINT) == signal.SIG_IGN
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(0.01)
        ran.append(1)
    assert ran == [1] and signal.getsignal(signal.SIGINT) == signal.SIG_IGN
    with pytest.raises(Interrupted) as info:
        with StopWorkersOnSignal():
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.01)
    assert info.value.signum == signal.SIGTERM
    assert signal.getsignal(signal.SIGINT) == signal.SIG_IGN


def test_an_api_write_under_an_ignored_sigint_completes(sigint_ignored, tmp_path,
                                                        monkeypatch):
    """Hypothesis: a SIGINT that the process ignores, arriving during write_netcdf,
    neither stops the write nor raises afterwards: the file is in place, whole."""
    from vibimpact.io import read_netcdf, write_netcdf

    original = xr.Dataset.to_netcdf

    def write(self, *args, **kwargs):
        os.kill(os.getpid(), signal.SIGINT)
        return original(self, *args, **kwargs)

    monkeypatch.setattr(xr.Dataset, "to_netcdf", write)
    ds = xr.Dataset({"x": (("i",), np.arange(5.0))})
    write_netcdf(ds, tmp_path / "r.nc")
    assert [p.name for p in tmp_path.iterdir()] == ["r.nc"]
    assert np.array_equal(read_netcdf(tmp_path / "r.nc")["x"].values, ds["x"].values)


def _start_ignoring(ignored, cwd):
    """``python -m vibimpact`` + SWEEP (through the script's entry point) in its own
    session, started with the signals ``ignored`` set to SIG_IGN (as a shell gives a
    background job SIGINT)."""
    return start(SWEEP, cwd, module="vibimpact", ignoring=ignored)


@pytest.mark.slow
@pytest.mark.parametrize("ignored, sent", [
    ((signal.SIGINT,), signal.SIGINT),
    ((signal.SIGTERM,), signal.SIGTERM),
    ((signal.SIGINT, signal.SIGTERM), signal.SIGTERM),
], ids=["SIGINT ignored, SIGINT sent", "SIGTERM ignored, SIGTERM sent",
        "both ignored, SIGTERM sent"])
def test_a_command_started_ignoring_a_signal_runs_through_it(ignored, sent, tmp_path):
    """Hypothesis: classify started with a signal ignored and sent that signal twice,
    during its start-up (the command line's import) and during its computation, runs
    to the end: exit 0, the file written, nothing on stderr."""
    proc = _start_ignoring(ignored, tmp_path)
    try:
        for moment in (0.2, 2.5):  # start-up, then the sweep (the run takes longer)
            time.sleep(moment)
            if proc.poll() is None:
                os.kill(proc.pid, sent)
        status = finish(proc, timeout=300)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert status == 0 and messages(tmp_path) == []
    assert (tmp_path / "c.nc").exists()


@pytest.mark.slow
def test_sigterm_still_ends_a_command_started_ignoring_sigint(tmp_path):
    """Hypothesis: with only SIGINT ignored, SIGTERM during the computation ends
    classify as ever: exit 143, one 'interrupted' line, no output file."""
    proc = _start_ignoring((signal.SIGINT,), tmp_path)
    time.sleep(2.5)
    assert_one_interrupted_line(tmp_path, signal_and_finish(proc, signal.SIGTERM, 300))
    assert not (tmp_path / "c.nc").exists()
