"""Output streams that cannot be written (issue 44, class 1): stdout or stderr full
(``/dev/full``: ENOSPC), closed (``>&-``) or a pipe whose reader has gone (EPIPE).

The work's files are kept, one line says so on stderr when it can be written, and the
exit status is 74 (the printed output was lost) or 141 (a closed pipe, silently); a
command's own non-zero status (2 for bad input) is kept; never a traceback, never 0.

The fast tests run :func:`vibimpact.cli.main` in this process with ``sys.stdout`` or
``sys.stderr`` replaced by a stream whose writes fail; the slow ones start the command
line with its real streams on ``/dev/full``, closed, or on a pipe with no reader.
"""
from __future__ import annotations

import errno
import io
import os
import subprocess
import sys

import pytest

from vibimpact.cli import main
from vibimpact.cli.common.streams import BROKEN_PIPE, Guarded, LOST_OUTPUT

SIM = ["simulate", "--preset", "fig8", "--eta", "1.0", "--periods", "2", "--transient", "2"]


class Failing(io.TextIOBase):
    """A text stream whose every write fails with ``errno`` (and its flush, once a
    write was tried: as a file's, with nothing buffered it writes nothing)."""

    def __init__(self, code):
        self.code = code
        self.attempts = 0

    def write(self, text):
        self.attempts += 1
        raise OSError(self.code, os.strerror(self.code))

    def flush(self):
        if self.attempts:
            raise OSError(self.code, os.strerror(self.code))


#: stands for a stream the process was started without (Python sets it to None)
CLOSED = "closed"


def call(argv, monkeypatch, stdout=None, stderr=None):
    """main(argv) with the given streams (a StringIO where None, None where CLOSED)
    -> (status, stdout, stderr); a SystemExit is a status."""
    out, err = (io.StringIO() if s is None else None if s is CLOSED else s
                for s in (stdout, stderr))
    monkeypatch.setattr(sys, "stdout", out)
    monkeypatch.setattr(sys, "stderr", err)
    try:
        rc = main([str(a) for a in argv])
    except SystemExit as exc:
        rc = exc.code
    text = lambda s: s.getvalue() if isinstance(s, io.StringIO) else ""  # noqa: E731
    return rc, text(out), text(err)


def assert_lost(rc, err, where="stdout"):
    """Status 74 and, when stderr works, the one line naming stdout."""
    assert rc == LOST_OUTPUT, (rc, err)
    assert "Traceback" not in err
    if where == "stdout":
        lines = err.strip().splitlines()
        assert lines[-1].startswith("vibimpact: error: cannot write to stdout ("), err
        assert "printed results are lost" in lines[-1]


@pytest.mark.parametrize("argv", [["presets"], ["presets", "--help"], ["--help"]],
                         ids=["presets", "presets-help", "help"])
def test_stdout_full_is_status_74_with_one_line(argv, monkeypatch):
    """Hypothesis: a command (or argparse's --help) whose stdout fails with ENOSPC
    ends with status 74 and one line on stderr, not a traceback (presets) or 0
    (--help: argparse swallows the error)."""
    rc, _, err = call(argv, monkeypatch, stdout=Failing(errno.ENOSPC))
    assert_lost(rc, err)
    assert len(err.strip().splitlines()) == 1


def test_version_to_a_full_stdout_is_status_74(monkeypatch):
    """Hypothesis: --version (printed inside argparse's action, then SystemExit(0))
    with stdout failing ends with SystemExit(74), not 0 or a traceback."""
    rc, _, err = call(["--version"], monkeypatch, stdout=Failing(errno.ENOSPC))
    assert_lost(rc, err)


def test_a_closed_pipe_is_status_141_without_a_line(monkeypatch):
    """Hypothesis: stdout on a pipe whose reader has gone (EPIPE, ``| head -1``) ends
    with 141 (128 + SIGPIPE, as the shell reports a program SIGPIPE ended) and says
    nothing: the reader stopped reading on purpose."""
    rc, _, err = call(["presets"], monkeypatch, stdout=Failing(errno.EPIPE))
    assert rc == BROKEN_PIPE and err == ""


def test_a_closed_stdout_is_status_74(monkeypatch):
    """Hypothesis: a process started with stdout closed (Python leaves sys.stdout None,
    and print() then writes nothing without a word) ends with 74, not 0."""
    rc, _, err = call(["presets"], monkeypatch, stdout=CLOSED)
    assert_lost(rc, err)
    assert "(closed)" in err


def test_a_failing_stream_is_written_once_and_the_command_goes_on(monkeypatch, tmp_path):
    """Hypothesis: after a failed write the stream is not written again, the command
    runs to its end and its file is kept (simulate writes run.nc, then its summary
    line fails: 74 with the file there, not a traceback after the file)."""
    monkeypatch.chdir(tmp_path)
    out = Failing(errno.ENOSPC)
    rc, _, err = call([*SIM, "-o", "run.nc"], monkeypatch, stdout=out)
    assert_lost(rc, err)
    assert (tmp_path / "run.nc").is_file()
    assert out.attempts == 1


def test_a_failing_stderr_makes_a_successful_command_74(monkeypatch, tmp_path):
    """Hypothesis: a command that succeeds but whose stderr lines (-v's log) could not
    be written ends with 74 (the lines are lost; nothing can say so), its file kept and
    its stdout written; a command that writes nothing to a failing stderr ends 0."""
    monkeypatch.chdir(tmp_path)
    rc, out, _ = call(["-v", *SIM, "-o", "run.nc"], monkeypatch,
                      stderr=Failing(errno.ENOSPC))
    assert rc == LOST_OUTPUT and out.startswith("wrote run.nc")
    assert (tmp_path / "run.nc").is_file()
    rc, out, _ = call(["presets"], monkeypatch, stderr=Failing(errno.ENOSPC))
    assert rc == 0 and "fig8" in out


@pytest.mark.parametrize("stream", ["stdout", "stderr", "both"])
def test_a_usage_error_keeps_status_2(stream, monkeypatch):
    """Hypothesis: bad input keeps its status 2 whichever stream fails (the status
    says more than "output lost"), without a traceback."""
    kw = {"stdout": Failing(errno.ENOSPC)} if stream != "stderr" else {}
    if stream != "stdout":
        kw["stderr"] = Failing(errno.ENOSPC)
    rc, _, err = call(["presets", "--no-such-option"], monkeypatch, **kw)
    assert rc == 2 and "Traceback" not in err
    rc, _, err = call([*SIM[:1], "--eta", "-1", "-o", "x.nc"], monkeypatch, **kw)
    assert rc == 2 and "Traceback" not in err


def test_the_streams_are_given_back(monkeypatch):
    """Hypothesis: after main() the caller's own sys.stdout and sys.stderr are in
    place again (the guards are the command's only)."""
    out, err = Failing(errno.ENOSPC), io.StringIO()
    call(["presets"], monkeypatch, stdout=out, stderr=err)
    assert sys.stdout is out and sys.stderr is err


def test_guarded_passes_a_working_stream_through():
    """Hypothesis: the guard changes nothing for a stream that works (text, flush,
    isatty, encoding)."""
    s = io.StringIO()
    g = Guarded(s, "stdout")
    g.write("a")
    g.writelines(["b", "c"])
    g.flush()
    assert s.getvalue() == "abc" and g.error is None and g.isatty() is False


# ------------------------------------------------------------- the real streams (slow)

ENV = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}  # as a user has it

COMMANDS = {
    "presets": ["presets"],
    "help": ["--help"],
    "version": ["--version"],
    "simulate": [*SIM, "-o", "run.nc"],
    "classify": ["classify", "--eta", "1.0:1.01:0.01", "--workers", "1", "--analyses",
                 "period", "--no-progress", "-o", "c.nc"],
    "attractors": ["attractors", "--preset", "fig11", "--eta", "1.06", "--starts", "3",
                   "--workers", "1", "--no-progress", "-o", "a.nc"],
    "basins": ["basins", "--preset", "fig11", "--eta", "1.06", "--grid", "10x10",
               "--workers", "1", "--no-progress", "-o", "b.nc"],
    "orbits": ["orbits", "--preset", "fig11", "--eta", "1.06", "--period", "1",
               "--random", "2", "--no-continue", "--workers", "1", "--no-progress",
               "-o", "o.nc"],
    "plot": ["plot", "src.nc", "-o", "src.png"],
}


def start(argv, fault, cwd):
    """Run ``vibimpact ARGV`` with ``fault`` on its streams -> (status, stderr)."""
    cmd = [sys.executable, "-m", "vibimpact", *argv]
    err = subprocess.PIPE
    if fault == "full":
        with open("/dev/full", "w") as full:
            r = subprocess.run(cmd, stdout=full, stderr=err, cwd=cwd, env=ENV,
                               text=True, timeout=120)
        return r.returncode, r.stderr
    if fault == "pipe":
        rd, wr = os.pipe()
        os.close(rd)  # no reader: every write is EPIPE
        try:
            r = subprocess.run(cmd, stdout=wr, stderr=err, cwd=cwd, env=ENV, text=True,
                               timeout=120)
        finally:
            os.close(wr)
        return r.returncode, r.stderr
    redirect = {"closed": ">&-", "stderr-full": "2>/dev/full",
                "stderr-closed": "2>&-"}[fault]
    r = subprocess.run(["bash", "-c", f'exec "$@" {redirect}', "sh", *cmd],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=cwd, env=ENV,
                       text=True, timeout=120)
    return r.returncode, r.stderr + r.stdout


@pytest.fixture(scope="module")
def simulated(tmp_path_factory):
    d = tmp_path_factory.mktemp("streams")
    subprocess.run([sys.executable, "-m", "vibimpact", *SIM, "-o", "run.nc"], cwd=d,
                   env=ENV, check=True, capture_output=True, timeout=120)
    return d


@pytest.mark.slow
@pytest.mark.parametrize("fault", ["full", "closed", "pipe"])
@pytest.mark.parametrize("name", list(COMMANDS))
def test_a_command_with_an_unusable_stdout(name, fault, simulated, tmp_path):
    """Hypothesis: every command with its stdout on /dev/full, closed, or on a pipe
    with no reader ends 74 with one line on stderr (141 and nothing for the pipe),
    never 0 and never a traceback or Python's "Exception ignored" at exit, and the
    file it was asked for is written."""
    import shutil

    shutil.copy(simulated / "run.nc", tmp_path / "src.nc")
    argv = COMMANDS[name]
    rc, err = start(argv, fault, tmp_path)
    assert "Traceback" not in err and "Exception ignored" not in err, err
    if fault == "pipe":
        assert (rc, err) == (BROKEN_PIPE, "")
    else:
        assert rc == LOST_OUTPUT, err
        assert err.count("\n") == 1 and "cannot write to stdout" in err, err
    if "-o" in argv:
        assert (tmp_path / argv[argv.index("-o") + 1]).exists()


@pytest.mark.slow
@pytest.mark.parametrize("fault", ["stderr-full", "stderr-closed"])
def test_an_unusable_stderr(fault, tmp_path):
    """Hypothesis: with stderr full or closed, bad input still ends 2 and writes
    nothing to stdout (a closed stderr made print(..., file=sys.stderr) print on
    stdout), a command whose stderr lines are lost ends 74, and one that writes nothing
    to stderr ends 0."""
    rc, out = start(["presets", "--no-such-option"], fault, tmp_path)
    assert (rc, out) == (2, "")
    rc, out = start(["simulate", "--eta", "-1", "-o", "x.nc"], fault, tmp_path)
    assert (rc, out) == (2, "")
    rc, out = start(["-v", *SIM, "-o", "run.nc"], fault, tmp_path)
    assert rc == LOST_OUTPUT and out.startswith("wrote run.nc"), out
    rc, out = start(["presets"], fault, tmp_path)
    assert rc == 0 and "fig8" in out


@pytest.mark.slow
def test_a_closed_stdout_gets_no_file_on_its_descriptor(tmp_path):
    """Hypothesis: started with stdout closed, the command's own files do not take
    descriptor 1 (the null device is put there first), so the file written is the
    command's data alone and the status is 74."""
    rc, err = start([*SIM, "-o", "run.nc"], "closed", tmp_path)
    assert rc == LOST_OUTPUT, err
    import xarray as xr

    with xr.open_dataset(tmp_path / "run.nc") as ds:
        assert ds.attrs["command"].startswith("vibimpact simulate")
