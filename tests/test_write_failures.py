"""A full disk or a vanished directory at any moment of a write: one line, exit 2, nothing
lost.

A small file system needs root to mount, so the faults are injected in this process:
the low-level calls a write goes through (``os.fsync`` of a checkpoint entry,
``os.replace`` of an entry or an output, the NetCDF and Zarr writers, the figure's
``savefig``) raise ``OSError(ENOSPC)`` (NetCDF's own ``RuntimeError: NetCDF: HDF
error``) at a chosen call.  Every case checks: exit status 2, one stderr line
``vibimpact: error: ...`` naming the file, no temporary file left, the checkpoint kept,
and, once the fault is gone, that ``--resume`` gives a file bit-identical to an
uninterrupted run.
"""
import errno
import os
from pathlib import Path

import pytest

from vibimpact.io import differences, read_netcdf

from test_bad_input import assert_refused, run_cli
from test_bad_output import integrations  # noqa: F401 -- a fixture: integrations started

CLASSIFY = ["classify", "--eta", "1.0:1.04:0.01", "--no-progress", "--workers", "1"]
MAP = ["map", "--eta", "1.0,1.1", "--vary", "kh=10,20", "--no-progress", "--workers", "1"]
SIM = ["simulate", "--eta", "1.2", "--periods", "5", "--transient", "5"]


def _full(*args, **kwargs):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def fail_nth(func, match, at):
    """``func`` that raises ENOSPC at the ``at``-th call (1-based) whose arguments
    ``match(*args)`` accepts, and at every matching call after it."""
    calls = []

    def wrapped(*args, **kwargs):
        if match(*args):
            calls.append(args)
            if len(calls) >= at:
                _full()
        return func(*args, **kwargs)
    return wrapped


def _is_entry(name):
    """A checkpoint entry: by its path, or by its name in the checkpoint (written
    relative to the directory's descriptor)."""
    return (".partial" in str(name) or os.sep not in str(name)) and \
        str(name).endswith(".npz")


def _leftovers(d):
    """Temporary files anywhere under ``d`` (the writers' and the checkpoint's)."""
    return sorted(str(p.relative_to(d)) for p in Path(d).rglob("*")
                  if p.name.endswith((".tmp", ".old")) or p.name.startswith(".tmp-"))


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The files of uninterrupted runs: {"c.nc": classify, "m.nc": map}."""
    d = tmp_path_factory.mktemp("reference")
    old = os.getcwd()
    os.chdir(d)
    try:
        assert run_cli([*CLASSIFY, "-o", "c.nc"], _NoCapture())[0] == 0
        assert run_cli([*MAP, "-o", "m.nc"], _NoCapture())[0] == 0
    finally:
        os.chdir(old)
    return {"c.nc": read_netcdf(d / "c.nc"), "m.nc": read_netcdf(d / "m.nc")}


class _NoCapture:
    def readouterr(self):
        return "", ""


def _partial_hdf(tmp, *args, **kwargs):
    """What NetCDF does on a full disk: part of the file, then RuntimeError."""
    Path(tmp).write_bytes(b"\x89HDF\r\n\x1a\n" + b"\x00" * 100)
    raise RuntimeError("NetCDF: HDF error")


def _to_netcdf_fails(self, path, *args, **kwargs):
    return _partial_hdf(path)


def _fsync_fails(at):
    """The ``at``-th fsync (request.json is the first, then one per saved entry)."""
    return lambda mp, out: mp.setattr(os, "fsync", fail_nth(os.fsync, lambda fd: True,
                                                            at))


def _entry_rename_fails(at):
    return lambda mp, out: mp.setattr(os, "replace", fail_nth(
        os.replace, lambda src, dst, *a: _is_entry(dst), at))


def _output_rename_fails(mp, out):
    mp.setattr(os, "link", lambda *a, **k: _full())  # then os.replace is tried
    mp.setattr(os, "replace", fail_nth(
        os.replace, lambda src, dst, *a: os.path.basename(str(dst)) == out, 1))


def _netcdf_fails(mp, out):
    mp.setattr("xarray.Dataset.to_netcdf", _to_netcdf_fails)


#: case -> (argv, output, install(monkeypatch, output))
CHECKPOINTED = {
    "classify: checkpoint entry write (fsync) at point 3": (CLASSIFY, "c.nc",
                                                            _fsync_fails(4)),
    "classify --workers 2: checkpoint entry write (fsync) at point 3": (
        [*CLASSIFY[:-1], "2"], "c.nc", _fsync_fails(4)),
    "classify: checkpoint entry rename at point 2": (CLASSIFY, "c.nc",
                                                     _entry_rename_fails(2)),
    "classify: output write (NetCDF HDF error)": (CLASSIFY, "c.nc", _netcdf_fails),
    "classify: output rename": (CLASSIFY, "c.nc", _output_rename_fails),
    "map: row entry write (fsync)": (MAP, "m.nc", _fsync_fails(3)),
    "map: output write (NetCDF HDF error)": (MAP, "m.nc", _netcdf_fails),
    "map: Zarr output write": (MAP, "m.zarr", lambda mp, out: mp.setattr(
        "xarray.Dataset.to_zarr", lambda *a, **k: _full())),
}


@pytest.mark.parametrize("case", list(CHECKPOINTED))
def test_write_failure_keeps_the_checkpoint_and_resume_loses_nothing(
        case, reference, tmp_path, monkeypatch, capfd):
    """A full disk while a checkpoint entry or the output is written or renamed ends in
    one line and exit 2 with no temporary file left and the checkpoint kept; --resume
    after the fault is gone gives the uninterrupted run's file bit for bit."""
    argv, out, install = CHECKPOINTED[case]
    monkeypatch.chdir(tmp_path)
    with monkeypatch.context() as mp:
        install(mp, out)
        rc, stdout, err = run_cli([*argv, "-o", out], capfd)
    assert_refused(rc, "", err, "NetCDF: HDF error" if install is _netcdf_fails
                   else "No space left on device")
    assert "--resume" in err
    assert _leftovers(tmp_path) == []
    assert (tmp_path / (out + ".partial") / "request.json").is_file()
    assert not (tmp_path / out).exists()
    rc, stdout, err = run_cli([*argv, "-o", out, "--resume"], capfd)
    assert rc == 0, err
    assert "resumed from" in err
    assert not (tmp_path / (out + ".partial")).exists()
    assert _leftovers(tmp_path) == []
    if out.endswith(".nc"):
        diffs, _ = differences(reference[out], read_netcdf(tmp_path / out))
        assert diffs == []


def test_injected_faults_fire_where_they_should():
    """The table's faults hit what they name: entries only (not request.json or a
    temporary name), and from the chosen call on (a fault that never fired would let its
    case pass without testing anything)."""
    assert _is_entry("c.nc.partial/up_000000_000001-000002.npz")
    assert not _is_entry("c.nc.partial/request.json")
    assert not _is_entry(".c.nc.abc.tmp")
    f = fail_nth(lambda x: x, lambda x: x > 0, 2)
    assert f(0) == 0 and f(1) == 1 and f(0) == 0
    with pytest.raises(OSError, match="No space left"):
        f(5)


def _savefig_fails(mp, out):
    mp.setattr("matplotlib.figure.Figure.savefig", lambda *a, **k: _full())


def _recorded_sweep(d):
    """A classify file to rerun and to plot (three points, period and the chaos test
    its labels need)."""
    assert run_cli(["classify", "--eta", "1.0:1.02:0.01", "--no-progress", "--workers",
                    "1", "--analyses", "period,lyapunov", "-o", "c.nc"], _NoCapture())[0] == 0


#: case -> (argv, the files that must not exist afterwards, install, setup)
UNCHECKPOINTED = {
    "simulate: output write": ([*SIM, "-o", "r.nc"], ["r.nc"], _netcdf_fails, None),
    "simulate: output rename": ([*SIM, "-o", "r.nc"], ["r.nc"],
                                lambda mp, out: _output_rename_fails(mp, "r.nc"), None),
    "simulate --plot: image write removes the run's file": (
        [*SIM, "-o", "r.nc", "--plot", "xy.png"], ["r.nc", "xy.png"], _savefig_fails, None),
    "bifurcation: data write": (["bifurcation", "--eta", "1:1.01:0.01", "--no-progress",
                                 "-o", "b.png"], ["b.png", "b.nc"], _netcdf_fails, None),
    "bifurcation: image write removes the data file": (
        ["bifurcation", "--eta", "1:1.01:0.01", "--no-progress", "-o", "b.png"],
        ["b.png", "b.nc"], _savefig_fails, None),
    "continue: output write": (["continue", "--eta", "1.12", "--stop", "1.13", "-o",
                                "p1.nc"], ["p1.nc"], _netcdf_fails, None),
    "plot: image write": (["plot", "c.nc", "--kind", "intervals", "-o", "p.png"],
                          ["p.png"], _savefig_fails, _recorded_sweep),
    "rerun: output write": (["rerun", "c.nc", "-o", "new.nc"], ["new.nc", "new.nc.partial"],
                            _netcdf_fails, _recorded_sweep),
}


@pytest.mark.parametrize("case", list(UNCHECKPOINTED))
def test_write_failure_of_every_command_is_one_line(case, tmp_path, monkeypatch, capfd):
    """A full disk while any writing command writes (its file, its image, a rerun's
    file) ends in one line and exit 2, with no temporary file left and none of the
    command's outputs (they succeed or fail together: simulate --plot and bifurcation
    remove the file they wrote before the image failed)."""
    argv, absent, install, setup = UNCHECKPOINTED[case]
    monkeypatch.chdir(tmp_path)
    if setup is not None:
        setup(tmp_path)
    capfd.readouterr()
    with monkeypatch.context() as mp:
        install(mp, absent[0])
        rc, stdout, err = run_cli(argv, capfd)
    err = "".join(line for line in err.splitlines(True)  # rerun says what it runs first
                  if not line.startswith("vibimpact: rerunning "))
    assert_refused(rc, "", err, "NetCDF: HDF error" if install is _netcdf_fails
                   else "No space left on device")
    assert _leftovers(tmp_path) == []
    assert [name for name in absent if (tmp_path / name).exists()] == []


def test_checkpoint_moved_away_mid_run_loses_nothing(reference, tmp_path, monkeypatch,
                                                     capfd):
    """The checkpoint directory moved away after two points: the store recreates it and
    the run ends normally with the uninterrupted run's file bit for bit (before: a
    FileNotFoundError traceback and every computed point lost)."""
    from vibimpact.engine.store import Checkpoint

    monkeypatch.chdir(tmp_path)
    real = Checkpoint.save
    calls = []

    def save(self, *args, **kwargs):
        calls.append(args)
        if len(calls) == 3:
            os.rename(self.path, tmp_path / "moved")
        return real(self, *args, **kwargs)

    monkeypatch.setattr(Checkpoint, "save", save)
    rc, stdout, err = run_cli([*CLASSIFY, "-o", "c.nc"], capfd)
    assert rc == 0, err
    assert len(calls) == 5
    assert sorted(p.name for p in (tmp_path / "moved").iterdir()) == [
        "request.json", "up_000000_000000-000001.npz", "up_000000_000001-000002.npz"]
    assert not (tmp_path / "c.nc.partial").exists()
    diffs, _ = differences(reference["c.nc"], read_netcdf(tmp_path / "c.nc"))
    assert diffs == []


def test_unwritable_checkpoint_is_refused_before_computing(tmp_path, monkeypatch, capfd):
    """--resume into a checkpoint that cannot be written (read-only: injected, since
    root writes anywhere) is refused at once, exit 2, one line; the checkpoint stays."""
    import tempfile

    monkeypatch.chdir(tmp_path)
    (tmp_path / "c.nc.partial").mkdir()
    real = tempfile.mkstemp

    def mkstemp(*args, dir=None, **kwargs):
        if dir is not None and str(dir).endswith(".partial"):
            raise OSError(errno.EROFS, os.strerror(errno.EROFS))
        return real(*args, dir=dir, **kwargs)

    monkeypatch.setattr(tempfile, "mkstemp", mkstemp)
    rc, stdout, err = run_cli([*CLASSIFY, "-o", "c.nc", "--resume"], capfd)
    assert_refused(rc, stdout, err, "checkpoint 'c.nc.partial' is not writable "
                                    "(Read-only file system)")
    assert (tmp_path / "c.nc.partial").is_dir()


def test_full_file_system_is_refused_before_computing(tmp_path, monkeypatch, capfd):
    """A file system with no free space (statvfs says 0 bytes) is refused before the
    run, for a sweep and a simulation alike: exit 2, one line, no file."""
    class Full:
        f_bavail, f_frsize = 0, 4096

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(os, "statvfs", lambda path: Full())
    for argv in ([*CLASSIFY, "-o", "c.nc"], [*SIM, "-o", "r.nc"]):
        rc, stdout, err = run_cli(argv, capfd)
        assert_refused(rc, stdout, err, "only 0 bytes free on the file system")
    assert list(tmp_path.iterdir()) == []


def test_resume_replaces_only_the_file_written_from_its_checkpoint(tmp_path, monkeypatch,
                                                                   capfd):
    """--resume replaces an existing output without --overwrite only when it is the
    file written from that checkpoint (kept with --keep-checkpoint, or left by a run
    killed before removing it); once the file is another one, it is refused."""
    monkeypatch.chdir(tmp_path)
    argv = ["classify", "--eta", "1.0:1.01:0.01", "--no-progress", "--workers", "1",
            "--analyses", "period", "-o", "c.nc"]
    rc, stdout, err = run_cli([*argv, "--keep-checkpoint"], capfd)
    assert rc == 0, err
    first = read_netcdf(tmp_path / "c.nc")
    rc, stdout, err = run_cli([*argv, "--resume", "--keep-checkpoint"], capfd)
    assert rc == 0, err
    assert differences(first, read_netcdf(tmp_path / "c.nc"))[0] == []
    (tmp_path / "c.nc").write_bytes(b"someone else's file")
    rc, stdout, err = run_cli([*argv, "--resume"], capfd)
    assert_refused(rc, stdout, err, "output file 'c.nc' exists; pass --overwrite")
    assert (tmp_path / "c.nc").read_bytes() == b"someone else's file"


def test_map_plot_failure_removes_the_map_and_resume_loses_nothing(
        reference, tmp_path, monkeypatch, capfd):
    """map --plot onto a full disk: one line, exit 2, the map file removed again (both
    outputs or neither), the checkpoint kept; --resume then writes both, the map bit for
    bit the uninterrupted one."""
    monkeypatch.chdir(tmp_path)
    argv = [*MAP, "-o", "m.nc", "--plot", "m.png"]
    with monkeypatch.context() as mp:
        _savefig_fails(mp, "m.png")
        rc, stdout, err = run_cli(argv, capfd)
    assert_refused(rc, "", err, "cannot write 'm.png': No space left on device")
    assert "--resume" in err
    assert not (tmp_path / "m.nc").exists() and not (tmp_path / "m.png").exists()
    assert (tmp_path / "m.nc.partial" / "request.json").is_file()
    assert _leftovers(tmp_path) == []
    rc, stdout, err = run_cli([*argv, "--resume"], capfd)
    assert rc == 0, err
    assert (tmp_path / "m.png").is_file() and not (tmp_path / "m.nc.partial").exists()
    assert differences(reference["m.nc"], read_netcdf(tmp_path / "m.nc"))[0] == []


def test_output_larger_than_the_free_space_is_refused_before_computing(
        tmp_path, monkeypatch, capfd, integrations):  # noqa: F811 -- the fixture imported
    """Where the size of the file is known from the request (a run's dense samples, a
    sweep's or map's grid), a file system with less free space than that is refused
    before any work: exit 2, one line with both sizes, no integration started, no
    file."""

    class TwoMiB:
        f_bavail, f_frsize = 512, 4096

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(os, "statvfs", lambda path: TwoMiB())
    for argv in ([*SIM[:-4], "--periods", "200", "--dense", "2000", "-o", "r.nc"],
                 ["classify", "--eta", "0.9:1.5:0.0005", "-o", "c.nc"],
                 ["bifurcation", "--eta", "0.9:1.5:0.0005", "-o", "b.png"],
                 ["map", "--eta", "0.9:1.5:0.01", "--vary", "kh=10:200:5", "-o", "m.zarr"]):
        rc, stdout, err = run_cli(argv, capfd)
        assert_refused(rc, stdout, err, "only 2 MiB free on the file system")
        assert "MiB needed" in err
        assert not integrations
    assert list(tmp_path.iterdir()) == []
