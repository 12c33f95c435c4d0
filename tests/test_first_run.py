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
