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

#: the script: argv = checkpoint, output, resume (0/1), and the signal it sends itself
#: once SIGNAL_AFTER points are saved (0: none) -- the moment is a count of saved points,
#: not a time
SIGNAL_AFTER = 3
SCRIPT = f'''
import os
import sys

import numpy as np

import vibimpact as vi

checkpoint, out, resume = sys.argv[1], sys.argv[2], sys.argv[3] == "1"
signum = int(sys.argv[4])
eta = np.round(np.arange(1.0, 1.5 + 1e-9, 0.0025), 12)
done = [0]


def progress(k):
    """Count saved points (the engine calls it after saving); write the worker
    processes' pids and signal once at the count."""
    done[0] += k
    if signum and done[0] >= {SIGNAL_AFTER} and done[0] - k < {SIGNAL_AFTER}:
        import multiprocessing
        with open(out + ".workers", "w") as f:
            f.write(" ".join(str(c.pid) for c in multiprocessing.active_children()))
        os.kill(os.getpid(), signum)


try:
    ds = vi.sweep(vi.presets.get("fig8"), eta, analyses={ANALYSES!r},
                  continuation=vi.Continuation(blocks={BLOCKS}),
                  execution=vi.Execution(workers=2, checkpoint=checkpoint,
                                         resume=resume, progress=progress))
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


def _alive(pids):
    """The processes of ``pids`` that still exist (signal 0 probes without sending)."""
    alive = []
    for pid in pids:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            continue
        except PermissionError:
            pass
        alive.append(pid)
    return alive


def _wait_gone(pids, seconds=20.0):
    """The processes of ``pids`` left after they had ``seconds`` to end (an exited
    parent's children are reaped by init, not at once)."""
    deadline = time.monotonic() + seconds
    while _alive(pids) and time.monotonic() < deadline:
        time.sleep(0.05)
    return _alive(pids)


@pytest.mark.slow
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
    # the script signals itself after its third saved point (a count, not a time);
    # the timeout only ends a hung run
    proc = subprocess.run([sys.executable, str(script), str(ckpt), str(out), "0",
                           str(int(signum))], capture_output=True, text=True, env=env,
                          cwd=tmp_path, timeout=900)
    stdout, stderr = proc.stdout, proc.stderr
    assert proc.returncode == 128 + signum, stderr
    assert f"interrupted by {int(signum)}" in stdout
    workers = [int(w) for w in Path(f"{out}.workers").read_text().split()]
    # the script's child processes when signalled (the two workers and their helpers)
    assert len(workers) >= 2
    assert _wait_gone(workers) == []  # all gone with the script
    saved = Checkpoint(ckpt).saved()[0]
    assert SIGNAL_AFTER <= saved < GRID.size
    assert not list(ckpt.glob(".tmp-*"))
    assert not out.exists()

    done = subprocess.run([sys.executable, str(script), str(ckpt), str(out), "1", "0"],
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
