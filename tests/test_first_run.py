"""A first run says that it compiles the kernel before it does, and a run whose cache is
in use says nothing of it."""
import os
import subprocess
import sys

import pytest

from vibimpact.cli.common import first_run

CLASSIFY = ["classify", "--eta", "1.0", "--no-progress", "--overwrite"]


def _nbi(directory):
    return [f for _, _, files in os.walk(directory) for f in files if f.endswith(".nbi")]


@pytest.mark.parametrize("command", [CLASSIFY, ["simulate", "--eta", "1.0", "--periods",
                                                 "2", "--overwrite"]])
def test_a_cold_run_prints_the_compile_line_before_compiling(command, tmp_path):
    """Hypothesis: with an empty numba cache the first line on stderr of a computing
    command is the compile line, and it comes before numba
    has cached any kernel function (the directory holds no index yet when it is read);
    the process is then stopped, so the test does not wait for the compile."""
    cache = tmp_path / "cache"
    cache.mkdir()
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    proc = subprocess.Popen([sys.executable, "-m", "vibimpact", *command, "-o",
                             str(tmp_path / "out.nc")], cwd=tmp_path, env=env,
                            stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True)
    try:
        line = proc.stderr.readline()
        cached = _nbi(cache)
    finally:
        proc.kill()
        proc.wait()
        proc.stderr.close()
    assert line.startswith("vibimpact: compiling the kernel for first use"), line
    assert "later runs load it" in line
    assert cached == []


def test_a_warm_run_prints_no_compile_line(tmp_path):
    """Hypothesis: where the install's cache is in use (the test environment's), a
    classify run compiles nothing and its stderr holds no compile line."""
    from vibimpact._kernel.cache_stamp import cache_state

    if not cache_state()[0]:
        pytest.fail("the test environment's kernel cache is not in use: "
                    + cache_state()[1])
    r = subprocess.run([sys.executable, "-m", "vibimpact", *CLASSIFY, "-o",
                        str(tmp_path / "w.nc")], cwd=tmp_path, capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "compiling the kernel" not in r.stderr


def test_the_line_is_said_once_and_only_for_the_kernel(monkeypatch, capsys):
    """Hypothesis: the listener prints for a compile of a kernel function only (not for
    a user model's function, which numba compiles in every process), and once."""
    monkeypatch.setitem(first_run._STATE, "said", False)

    class Ev:
        def __init__(self, module):
            def f():
                pass
            f.__module__ = module
            self.data = {"dispatcher": type("D", (), {"py_func": staticmethod(f)})()}

    assert not first_run._of_kernel(Ev("my_model"))
    assert first_run._of_kernel(Ev("vibimpact._kernel.driver"))
    first_run._say()
    first_run._say()
    err = capsys.readouterr().err
    assert err.count("compiling the kernel") == 1


def test_a_compile_is_certain_only_where_the_cache_holds_no_integration_loop(tmp_path):
    """Hypothesis: the file-system test says a compile is certain for an empty
    ``NUMBA_CACHE_DIR`` and for a kernel whose ``__pycache__`` holds no index of the
    integration loop, and not where such an index lies anywhere below the cache
    directory or in ``__pycache__``; and the index it looks for is the one numba wrote
    for the test environment's filled cache (a renamed loop would fail here)."""
    from vibimpact._kernel.cache_stamp import cache_state

    empty = tmp_path / "empty"
    empty.mkdir()
    assert first_run.compile_is_certain({"NUMBA_CACHE_DIR": str(empty)})
    deep = tmp_path / "filled" / "work" / "_kernel_abc"
    deep.mkdir(parents=True)
    (deep / "driver.integrate-414.py311.nbi").write_bytes(b"")
    assert not first_run.compile_is_certain({"NUMBA_CACHE_DIR": str(tmp_path / "filled")})
    kernel = tmp_path / "kernel"
    (kernel / "__pycache__").mkdir(parents=True)
    assert first_run.compile_is_certain({}, kernel)
    (kernel / "__pycache__" / "driver.integrate-9.py311.nbi").write_bytes(b"")
    assert not first_run.compile_is_certain({}, kernel)
    if not cache_state()[0]:
        pytest.fail("the test environment's kernel cache is not in use: "
                    + cache_state()[1])
    env = {k: v for k, v in os.environ.items() if k == "NUMBA_CACHE_DIR"}
    assert not first_run.compile_is_certain(env)


def test_an_error_before_the_work_prints_no_compile_line_on_a_cold_cache(tmp_path):
    """Hypothesis: on an empty numba cache, a command refused before it computes (an
    output that exists without --overwrite; an option out of range) prints its one
    error line and no compile line: the line waits for numba's first call."""
    cache = tmp_path / "cache"
    cache.mkdir()
    (tmp_path / "o.nc").write_bytes(b"x")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    for argv in (["classify", "--eta", "1.0", "--no-progress", "-o", "o.nc"],
                 ["attractors", "--eta", "1.0", "--starts", "0", "-o", "a.nc"]):
        r = subprocess.run([sys.executable, "-m", "vibimpact", *argv], cwd=tmp_path,
                           env=env, capture_output=True, text=True, timeout=120)
        lines = r.stderr.splitlines()
        assert r.returncode == 2 and len(lines) == 1, (argv, r.stderr)
        assert lines[0].startswith("vibimpact: error:") or "error:" in lines[0], lines
