"""Checkpoint, resume and signals belong to the engine, so the API gets them (issue 29,
part 3): a script that calls ``vi.sweep`` with ``vi.Execution(checkpoint=...)``,
stopped by SIGINT or SIGTERM in the middle of the run, stops its worker processes and
keeps its checkpoint; run again with ``resume=True`` it completes the uninterrupted
result bit for bit, without recomputing the saved points.
"""
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.engine.store import Checkpoint

ROOT = Path(__file__).resolve().parents[1]
GRID = np.round(np.arange(1.0, 1.5 + 1e-9, 0.0025), 12)  # 201 points
ANALYSES = ("period", "impacts")
BLOCKS = 8

SCRIPT = f'''
import sys

import numpy as np

import vibimpact as vi

checkpoint, out, resume = sys.argv[1], sys.argv[2], sys.argv[3] == "1"
eta = np.round(np.arange(1.0, 1.5 + 1e-9, 0.0025), 12)
try:
    ds = vi.sweep(vi.presets.get("fig8"), eta, analyses={ANALYSES!r},
                  continuation=vi.Continuation(blocks={BLOCKS}),
                  execution=vi.Execution(workers=2, checkpoint=checkpoint,
                                         resume=resume))
except vi.Interrupted as exc:
    print("interrupted by", exc.signum, flush=True)
    sys.exit(128 + exc.signum)
np.savez(out, **{{k: ds[k].values for k in ds.data_vars if ds[k].dtype != object}})
'''


@pytest.fixture(scope="module")
def reference():
    """The uninterrupted sweep, computed in this process."""
    return vi.sweep(vi.presets.get("fig8"), GRID, analyses=ANALYSES,
                    continuation=vi.Continuation(blocks=BLOCKS))


def _running(marker):
    """Pids of the processes whose command line holds ``marker`` (the script's path:
    the script and its forked workers)."""
    pids = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/cmdline", "rb") as f:
                if marker.encode() in f.read():
                    pids.append(int(entry))
        except OSError:
            pass
    return pids


def _wait_gone(marker, seconds=20.0):
    deadline = time.monotonic() + seconds
    while _running(marker) and time.monotonic() < deadline:
        time.sleep(0.05)
    return _running(marker)


@pytest.mark.slow
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_api_sweep_survives_a_signal_and_resumes_bit_identical(tmp_path, reference,
                                                               signum):
    """Hypothesis: SIGINT or SIGTERM sent to a Python script in the middle of
    ``vi.sweep(..., execution=vi.Execution(workers=2, checkpoint=...))`` raises
    ``vi.Interrupted`` carrying the signal (exit status 128 + signum here), stops both
    worker processes, keeps the checkpoint with the points finished before and no
    temporary entry; the same script with ``resume=True`` loads those points and
    returns every variable of the uninterrupted sweep bit for bit."""
    script = tmp_path / f"api_sweep_{int(signum)}.py"
    script.write_text(SCRIPT)
    ckpt, out = tmp_path / "sweep.partial", tmp_path / "out.npz"
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get(
        "PYTHONPATH", ""))
    proc = subprocess.Popen([sys.executable, str(script), str(ckpt), str(out), "0"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=env, cwd=tmp_path)
    try:
        deadline = time.monotonic() + 300
        while Checkpoint(ckpt).saved()[0] < 3 and proc.poll() is None:
            assert time.monotonic() < deadline, "no point saved in 300 s"
            time.sleep(0.02)
        assert proc.poll() is None, proc.communicate()
        proc.send_signal(signum)
        stdout, stderr = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 128 + signum, stderr
    assert f"interrupted by {int(signum)}" in stdout
    assert _wait_gone(str(script)) == []  # the workers are gone too
    saved = Checkpoint(ckpt).saved()[0]
    assert 3 <= saved < GRID.size
    assert not list(ckpt.glob(".tmp-*"))
    assert not out.exists()

    done = subprocess.run([sys.executable, str(script), str(ckpt), str(out), "1"],
                          capture_output=True, text=True, env=env, cwd=tmp_path,
                          timeout=600)
    assert done.returncode == 0, done.stderr
    assert Checkpoint(ckpt).last_resume()["points"] == saved
    got = np.load(out)
    assert set(got.files) == {k for k in reference.data_vars
                              if reference[k].dtype != object}
    for k in got.files:
        assert np.array_equal(got[k], reference[k].values,
                              equal_nan=got[k].dtype.kind in "fc"), k


def test_a_signal_during_a_save_waits_for_the_save_to_finish():
    """Hypothesis: SIGTERM received inside a ``signals_deferred`` block (where the engine
    saves a checkpoint entry) does not cut the block; it raises ``Interrupted`` with
    its number right after, and the handlers found on entry are back."""
    from vibimpact.engine.signals import StopWorkersOnSignal, signals_deferred

    before = signal.getsignal(signal.SIGTERM)
    steps = []
    with pytest.raises(vi.Interrupted) as info:
        with StopWorkersOnSignal():
            with signals_deferred():
                os.kill(os.getpid(), signal.SIGTERM)
                time.sleep(0.05)  # the handler has run by now
                steps.append("saved")
            steps.append("after the block")
    assert steps == ["saved"]
    assert info.value.signum == signal.SIGTERM
    assert signal.getsignal(signal.SIGTERM) is before
    StopWorkersOnSignal.received = None
