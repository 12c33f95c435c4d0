"""The warm-up helper compiles the points' array routines in another process."""
import os
import subprocess
import sys

import pytest

_SCRIPT = """
import multiprocessing as mp, os, sys
from vibimpact.engine import warmup
from vibimpact._kernel import boundary as kb
warmup.start()
helpers = [p for p in mp.active_children() if p.name == "vibimpact-warm-up"]
for p in helpers:
    p.join(300)
warmup.start()  # once per process: no second helper
again = [p for p in mp.active_children() if p.name == "vibimpact-warm-up"]
print(len(helpers), helpers[0].exitcode if helpers else None, len(again),
      kb.array_routines_compiled())
"""


def _cache_files(cache):
    return sorted((f, os.path.getmtime(os.path.join(d, f))) for d, _, files in os.walk(cache)
                  for f in files if f.endswith((".nbi", ".nbc")))


@pytest.mark.slow
def test_the_helper_fills_an_empty_cache_with_the_array_routines(tmp_path):
    """Hypothesis: in a fresh process with an empty numba cache, warmup.start() runs one
    helper process that exits cleanly after writing the six array routines (dot, matmul,
    lstsq, solve, eigvals, suffix_lag_residuals) to the cache, without compiling them in
    the calling process; a second start() starts nothing.  Where there is no fork (not
    Linux) start() starts nothing and writes nothing.  Then, in another fresh process on
    that cache (what the install's filled cache gives a first run), the helper only loads
    them: it exits cleanly and writes no cache file."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    out = subprocess.run([sys.executable, "-c", _SCRIPT], env=env, capture_output=True,
                         text=True, check=True).stdout.split()
    names = {f.split("-")[0] for _, _, files in os.walk(tmp_path) for f in files
             if f.endswith(".nbi")}
    if not sys.platform.startswith("linux"):
        assert out == ["0", "None", "0", "False"]
        assert not names
        return
    assert out == ["1", "0", "0", "False"]
    for routine in ("dot", "matmul", "lstsq", "solve", "eigvals", "suffix_lag_residuals"):
        assert any(n.endswith("." + routine) for n in names), (routine, sorted(names))
    before = _cache_files(tmp_path)
    again = subprocess.run([sys.executable, "-c", _SCRIPT], env=env, capture_output=True,
                           text=True, check=True).stdout.split()
    assert again == ["1", "0", "0", "False"]
    assert _cache_files(tmp_path) == before
