"""What a checkpoint or an input file may be (issue 44, classes 2 and 4).

A FIFO named like a checkpoint entry hung ``--resume`` forever (``np.load`` opened it
and waited for a writer), so did a FIFO as ``output.json``; a FIFO, a device or a socket
given as an input file was "no such file"; a checkpoint directory swapped for a symbolic
link in the middle of a run was followed, or its failure worded as "No such file or
directory".  Now a checkpoint's files are opened only when regular, without blocking
and never through a link, and what was found is named.
"""
import os
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

from vibimpact.engine.leftovers import output_of, wrote_output
from vibimpact.engine.store import Checkpoint
from test_bad_input import assert_refused, listing, run_cli

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "analyses" / "reliability"))
from _cases_r4_checkpoints import INPUT_COMMANDS, make_socket  # noqa: E402 -- shared

REQUEST = {"a": 1}
STREAMS = {"rows": 1, "directions": ["up"], "points": 3}


def _result(k):
    return {"final_state": np.arange(4.0) + k, "regime": 1, "period": k}


def _saved(tmp_path, n=3):
    """A sweep checkpoint with points 0 .. n-1 saved, one entry each."""
    ck = Checkpoint(tmp_path / "c.nc.partial").open("sweep", REQUEST, STREAMS, False)
    for k in range(n):
        ck.save(0, "up", [(k, _result(k))])
    return ck


def _bounded(func, *args):
    """``func(*args)`` in a thread that must finish within its bound (a FIFO opened for
    reading would block it for good); its result or exception."""
    got = []

    def call():
        try:
            got.append(func(*args))
        except Exception as exc:  # noqa: BLE001 -- handed to the test
            got.append(exc)

    worker = threading.Thread(target=call, daemon=True)
    worker.start()
    worker.join(10)
    assert not worker.is_alive(), f"{func.__name__} blocked"
    return got[0]


def _resume(path):
    return Checkpoint(path).open("sweep", REQUEST, STREAMS, True)


@pytest.mark.parametrize("make", ["fifo", "directory", "symlink"])
def test_an_entry_that_is_no_regular_file_is_set_aside_without_blocking(make, tmp_path):
    """Hypothesis: a FIFO, a directory or a symbolic link named like an entry is set aside
    as *.corrupt with the reason 'special' (not a regular file) and its point is not
    loaded; the other entries load; nothing blocks."""
    ck = _saved(tmp_path)
    name = "up_000000_000001-000002.npz"
    entry = ck.path / name
    entry.unlink()
    if make == "fifo":
        os.mkfifo(entry)
    elif make == "directory":
        entry.mkdir()
    else:
        (tmp_path / "elsewhere.npz").write_bytes(b"")
        entry.symlink_to(tmp_path / "elsewhere.npz")
    done = _bounded(_resume(ck.path).load)
    assert sorted(done[(0, "up")]) == [0, 2]
    last = Checkpoint(ck.path).last_resume()
    assert last["reasons"] == {name + ".corrupt": "special"}
    assert os.path.lexists(ck.path / (name + ".corrupt"))


@pytest.mark.parametrize("name", ["request.json", "output.json", "last_resume.json"])
def test_a_fifo_for_a_checkpoint_record_never_blocks(name, tmp_path):
    """Hypothesis: a FIFO in place of request.json makes a resume refuse the checkpoint
    ('not a regular file'); in place of output.json or last_resume.json it reads as no
    stamp / no last resume, and writing them replaces the FIFO; nothing blocks."""
    ck = _saved(tmp_path)
    (ck.path / name).unlink(missing_ok=True)
    os.mkfifo(ck.path / name)
    out = tmp_path / "c.nc"
    out.write_text("x")
    if name == "request.json":
        got = _bounded(_resume, ck.path)
        assert isinstance(got, ValueError)
        assert "has no readable request.json (request.json is a FIFO, not a regular " \
               "file)" in str(got)
        return
    assert _bounded(output_of, ck, str(out)) is False
    assert _bounded(Checkpoint(ck.path).last_resume)["points"] == 0
    _bounded(wrote_output, ck, str(out))
    assert _bounded(output_of, ck, str(out)) is True


@pytest.mark.parametrize("found", ["symlink", "file", "directory"])
def test_a_checkpoint_replaced_during_the_run_is_named_and_never_followed(found,
                                                                         tmp_path):
    """Hypothesis: a checkpoint directory swapped for a symbolic link, a file or another
    directory between two saves stops the run with a ValueError naming what was found;
    nothing is written where the link points, and the moved directory is untouched."""
    ck = _saved(tmp_path, 1)
    os.rename(ck.path, tmp_path / "moved")
    target = tmp_path / "target"
    target.mkdir()
    if found == "symlink":
        ck.path.symlink_to(target)
        words = f"was replaced by a symbolic link (to {str(target)!r}) during the run; " \
                "not following a link out of the checkpoint: the run stops"
    elif found == "file":
        ck.path.write_text("")
        words = "was replaced by a regular file during the run; the run stops"
    else:
        ck.path.mkdir()
        words = "was replaced by another directory during the run"
    with pytest.raises(ValueError) as info:
        ck.save(0, "up", [(1, _result(1))])
    assert words in str(info.value)
    assert listing(target) == []
    assert listing(tmp_path / "moved") == ["request.json", "up_000000_000000-000001.npz"]


def test_a_checkpoint_that_vanished_is_made_again_whole(tmp_path):
    """Hypothesis: a checkpoint removed during the run is made again with its
    request.json (the run goes on), and the entry saved next is in it."""
    ck = _saved(tmp_path, 1)
    for p in ck.path.iterdir():
        p.unlink()
    ck.path.rmdir()
    ck.save(0, "up", [(1, _result(1))])
    assert listing(ck.path) == ["request.json", "up_000000_000001-000002.npz"]
    assert sorted(_resume(ck.path).load()[(0, "up")]) == [1]


def test_a_checkpoint_that_is_a_symbolic_link_is_refused_before_any_work(
        tmp_path, monkeypatch, capfd):
    """Hypothesis: classify --resume onto OUT.partial that is a symbolic link to a real
    checkpoint is refused in one line naming the link, exit 2, nothing written; the
    API's resume refuses it too."""
    monkeypatch.chdir(tmp_path)
    ck = _saved(tmp_path)
    os.rename(ck.path, tmp_path / "real")
    os.symlink("real", "c.nc.partial")
    with pytest.raises(ValueError, match="is a symbolic link .* not following a link"):
        _resume(tmp_path / "c.nc.partial")
    rc, out, err = run_cli(["classify", "--eta", "1.0", "--workers", "1", "--no-progress",
                            "-o", "c.nc", "--resume"], capfd)
    assert_refused(rc, out, err, "checkpoint 'c.nc.partial' is a symbolic link (to "
                                 "'real'), not a directory")
    assert listing(tmp_path) == ["c.nc.partial", "real"]


KINDS = {"fifo": (os.mkfifo, "a FIFO"), "socket": (make_socket, "a socket")}


@pytest.mark.parametrize("kind", list(KINDS))
@pytest.mark.parametrize("command", list(INPUT_COMMANDS))
def test_an_input_that_is_no_regular_file_is_named_so(command, kind, tmp_path,
                                                      monkeypatch, capfd):
    """Hypothesis: a FIFO or a socket given as a command's input file is refused in one
    line saying what it is ('is a FIFO, not a regular file'), not 'no such file', exit
    2, before any work and without blocking; nothing written."""
    monkeypatch.chdir(tmp_path)
    make, words = KINDS[kind]
    make(tmp_path / "in.nc")
    argv = [a if a != "IN" else "in.nc" for a in INPUT_COMMANDS[command]]
    rc, out, err = run_cli(argv, capfd)
    assert_refused(rc, out, err, f"'in.nc' is {words}, not a regular file")
    assert listing(tmp_path) == ["in.nc"]


def test_a_character_device_as_input_is_named_so(tmp_path, monkeypatch, capfd):
    """Hypothesis: /dev/zero given to plot is 'a character device, not a regular file'
    (it would never end if read)."""
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(["plot", "/dev/zero", "-o", "p.png"], capfd)
    assert_refused(rc, out, err, "'/dev/zero' is a character device, not a regular file")


def test_a_map_store_holding_a_fifo_is_damaged_not_waited_on(tmp_path):
    """Hypothesis: open_map of a store holding a FIFO (where a chunk would be) is a
    ValueError naming it, returned at once (Zarr would block reading it)."""
    from vibimpact.maps.store import open_map

    store = tmp_path / "m.zarr"
    (store / "regime" / "c").mkdir(parents=True)
    (store / "zarr.json").write_text("{}")
    os.mkfifo(store / "regime" / "c" / "0")
    got = _bounded(open_map, store)
    assert isinstance(got, ValueError)
    assert "'regime/c/0' is a FIFO, not a regular file" in str(got)


CLASSIFY = ["classify", "--preset", "fig8", "--eta", "1.0:1.05:0.01", "--workers", "1",
            "--analyses", "period,impacts", "--no-progress"]


@pytest.mark.slow
def test_the_issues_fifo_reproducer_resumes_bit_identical(tmp_path):
    """Hypothesis: the issue's reproducer -- a classify checkpoint kept, one entry
    replaced by a FIFO, --resume -- finishes within its time limit, says the entry was
    set aside (not a regular file), and writes the uninterrupted run's file."""
    from vibimpact.io import differences, read_netcdf

    def run(*extra):
        return subprocess.run([sys.executable, "-m", "vibimpact", *CLASSIFY, "-o", "x.nc",
                               *extra], cwd=tmp_path, capture_output=True, text=True,
                              timeout=120)

    assert run("--keep-checkpoint").returncode == 0
    os.rename(tmp_path / "x.nc", tmp_path / "ref.nc")
    entry = tmp_path / "x.nc.partial" / "up_000000_000000-000001.npz"
    entry.unlink()
    os.mkfifo(entry)
    done = run("--resume")
    assert done.returncode == 0, done.stderr
    assert "up_000000_000000-000001.npz: not a regular file" in done.stderr
    assert differences(read_netcdf(tmp_path / "ref.nc"),
                       read_netcdf(tmp_path / "x.nc"))[0] == []
