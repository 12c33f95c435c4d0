"""The kernel compiled at install time: numba's on-disk cache, filled by setup.py.

The fill (setup.py -> vibimpact._kernel.aot_build) must leave nothing for a first run to
compile, give the bits numba's JIT gives, compile nothing when its key is unchanged (an
extra installed later), and ``vibimpact --version`` must say whether it is in use and why
not.  None of it needs a C compiler: every test here runs without one.
"""
import importlib.util
import json
import os
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import vibimpact as vi
from vibimpact._kernel import aot_build
from vibimpact._kernel import boundary as kb
from vibimpact._kernel import cache_stamp

ROOT = Path(__file__).resolve().parents[1]

#: rotor runs with impacts (chaotic at 1.2, P1 at 1.13, permanent contact at 1.3), the
#: Lyapunov spectrum (the variational rotor's Benettin loop) and the array routines on
#: random inputs, pickled to sys.argv[1]; then the cache's hits and misses and the cache
#: files of the kernel's directory
_RUNS = """
import pickle, sys
import numpy as np
import vibimpact as vi
from vibimpact._kernel import aot_build, boundary as kb, driver
out = {}
p = vi.presets.get("fig8")
for eta, method in [(1.2, "dop853"), (1.13, "dp5"), (1.3, "rk4")]:
    r = vi.simulate(p.replace(eta=eta), periods=20, transient=10, dense=16,
                    state0=[1.1, 0.0, 0.0, 1.3], solver=vi.SolverSettings(method=method))
    out[eta] = (r.strobe, r.dense, r.final_state, r.impacts, dict(r.counters))
res = vi.analysis.lyapunov_spectrum(
    vi.System(p.replace(eta=1.2)), state0=[1.1, 0.0, 0.0, 1.3],
    averaging=vi.analysis.Averaging(transient=3, min_periods=8, max_periods=8, block=4,
                                    align=2), floquet=False)
out["lyapunov"] = (res.exponents, res.history)
rng = np.random.default_rng(3)
a, b, v, x = (rng.standard_normal((5, 5)), rng.standard_normal((5, 3)),
              rng.standard_normal(5), rng.standard_normal((12, 4)))
out["routines"] = (kb.dot(v, v), kb.matmul(a, b), kb.lstsq(a, b, 1e-12), kb.solve(a, v),
                   kb.eigvals(a))
res4 = (np.empty((12, 3)), np.empty((12, 4)), np.empty((12, 4)), np.empty(12))
kb.suffix_lag_residuals(x, 3, *res4)
out["recurrence"] = res4
stats = driver.integrate.stats
out["integrate_cache"] = (sum(stats.cache_hits.values()), sum(stats.cache_misses.values()))
with open(sys.argv[1], "wb") as fh:
    pickle.dump(out, fh)
"""


def _env(cache):
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["NUMBA_CACHE_DIR"] = str(cache)
    return env


def _cache_files(cache):
    return sorted(str(f.relative_to(cache)) for f in Path(cache).rglob("*.nb?"))


def _runs(cache, out):
    subprocess.run([sys.executable, "-c", _RUNS, str(out)], env=_env(cache), cwd=ROOT,
                   check=True, capture_output=True)
    with open(out, "rb") as fh:
        return pickle.load(fh)


def _setup_module():
    """setup.py as a module (its setup() call runs only as __main__)."""
    spec = importlib.util.spec_from_file_location("vibimpact_setup", ROOT / "setup.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def filled(tmp_path_factory):
    """An empty numba cache filled by setup.py's install step, then: the lines it said,
    the cache files it left, the lines a second install step said, and the runs of
    ``_RUNS`` in a process on that cache (``cached``) and in one with an empty cache
    (``jit``: numba compiles everything)."""
    work = tmp_path_factory.mktemp("kernel-cache")
    cache, empty = work / "filled", work / "empty"
    setup_py = _setup_module()
    saved = os.environ.get("NUMBA_CACHE_DIR")
    os.environ["NUMBA_CACHE_DIR"] = str(cache)
    try:
        said = setup_py.fill_kernel_cache(str(ROOT))
        files = _cache_files(cache)
        said_again = setup_py.fill_kernel_cache(str(ROOT))
    finally:
        if saved is None:
            os.environ.pop("NUMBA_CACHE_DIR")
        else:
            os.environ["NUMBA_CACHE_DIR"] = saved
    files_again = _cache_files(cache)
    cached = _runs(cache, work / "cached.pkl")
    return {"cache": cache, "said": said, "files": files, "said_again": said_again,
            "files_again": files_again, "files_after_runs": _cache_files(cache),
            "cached": cached, "jit": _runs(empty, work / "jit.pkl")}


def _equal(a, b):
    """Bit equality of two nested structures of arrays, numbers and dicts."""
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_equal(a[k], b[k]) for k in a)
    if isinstance(a, (tuple, list)):
        return len(a) == len(b) and all(_equal(x, y) for x, y in zip(a, b))
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype.names:  # structured (the impacts table): field by field
        return a.dtype == b.dtype and all(_equal(a[f], b[f]) for f in a.dtype.names)
    if a.dtype.kind not in "fc":
        return np.array_equal(a, b)
    return np.array_equal(a, b, equal_nan=True)


@pytest.mark.slow  # fills a fresh numba cache: a study of the install step
def test_the_install_step_fills_the_cache_and_says_so(filled):
    """Hypothesis: setup.py's install step compiles every export into an empty cache,
    says what it compiles, where and how long it took, and stamps the cache with the
    current key (sources, versions, processor)."""
    said = "\n".join(filled["said"])
    assert "compiling the numba kernel" in said and "integrate" in said
    assert "compiled the kernel" in said and " s" in said
    assert "kernel cache step done in" in said
    stamp = aot_build.read_stamp(next(filled["cache"].iterdir()))
    assert stamp["key"] == aot_build.cache_key()["key"]
    names = {f.split("/")[-1].split("-")[0] for f in filled["files"]}
    # numba's own index files, spelled as numba spells them (a factory-made function,
    # stop_model.<locals>.init_mode, is indexed as stop_model.locals.init_mode)
    missing = aot_build._exported_names() - names
    assert not missing, missing


@pytest.mark.slow  # fills a fresh numba cache: a study of the install step
def test_an_unchanged_key_compiles_nothing_again(filled):
    """Hypothesis: a second install step with the same key (installing an extra) says
    the kernel is already compiled, compiles nothing and leaves the cache files as they
    were."""
    said = "\n".join(filled["said_again"])
    assert "already compiled" in said and "compiling the numba kernel" not in said
    assert filled["files_again"] == filled["files"]


@pytest.mark.slow  # fills a fresh numba cache: a study of the install step
def test_a_first_run_on_the_filled_cache_compiles_nothing(filled):
    """Hypothesis: rotor runs of three methods, the Lyapunov spectrum and the array
    routines, in a fresh process on the filled cache, load the integration loop from it
    (hits, no miss) and write no cache file: the fill left nothing to compile."""
    hits, misses = filled["cached"]["integrate_cache"]
    assert hits > 0 and misses == 0
    assert filled["files_after_runs"] == filled["files"]


@pytest.mark.slow  # fills a fresh numba cache: a study of the install step
def test_the_cached_kernel_gives_the_bits_of_the_jit(filled):
    """Hypothesis: the runs give bit-identical samples, events, counters, exponents and
    routine results from the filled cache and from numba compiling everything afresh in
    an empty cache (which it did: misses, no hit)."""
    cached, jit = dict(filled["cached"]), dict(filled["jit"])
    assert jit.pop("integrate_cache")[0] == 0
    cached.pop("integrate_cache")
    assert _equal(cached, jit)
    assert cached[1.2][4]["events"] > 0


def _stamped(tmp_path, monkeypatch, **changes):
    """A cache directory with the exports' index files and a stamp of the current key
    with ``changes``; cache_stamp.cache_dir points at it."""
    key = aot_build.cache_key()
    names = sorted(aot_build._exported_names())
    stamp = dict(key, seconds=1.0, filled_at="2026-01-01T00:00:00+00:00", exported=names,
                 **changes)
    for name in names:
        (tmp_path / f"{name}-1.py311.nbi").write_bytes(b"")
    (tmp_path / aot_build.STAMP).write_text(json.dumps(stamp))
    monkeypatch.setattr(cache_stamp, "cache_dir", lambda: tmp_path)
    return key


def test_version_says_the_cache_is_in_use_when_its_key_matches(tmp_path, monkeypatch):
    """Hypothesis: a stamp of the current key with every export's index file is
    reported in use, with the fill's date and duration."""
    _stamped(tmp_path, monkeypatch)
    in_use, line = cache_stamp.cache_state()
    assert in_use and line.startswith("in use") and "2026-01-01" in line


@pytest.mark.parametrize("changes,words", [
    ({"key": "0" * 64, "sources": "0" * 64}, "other kernel sources"),
    ({"key": "0" * 64, "versions": {"numba": "0.1"}}, "numba"),
    ({"key": "0" * 64, "host": {"cpu": "z80", "features": ""}}, "another processor"),
])
def test_version_says_why_a_foreign_cache_is_not_used(tmp_path, monkeypatch, changes,
                                                      words):
    """Hypothesis: a cache filled from other sources, by other versions or for another
    processor is reported not in use, naming what differs, and how to fill it."""
    _stamped(tmp_path, monkeypatch, **changes)
    in_use, line = cache_stamp.cache_state()
    assert not in_use and words in line and "aot_build" in line


def test_version_says_when_nothing_was_filled_or_files_are_gone(tmp_path, monkeypatch):
    """Hypothesis: no stamp reads 'not filled at install'; a stamp whose cache files are
    gone (dropped by the cache guard, say) reads 'gone'; neither is in use."""
    _stamped(tmp_path, monkeypatch)
    for f in tmp_path.glob("*.nbi"):
        f.unlink()
    in_use, line = cache_stamp.cache_state()
    assert not in_use and "gone" in line
    (tmp_path / aot_build.STAMP).unlink()
    in_use, line = cache_stamp.cache_state()
    assert not in_use and line.startswith("not filled at install")


def test_version_option_prints_the_kernel_line(tmp_path):
    """Hypothesis: ``vibimpact --version`` prints the version, then the kernel's line
    (here: an empty cache directory, so not filled, naming the directory), on stdout,
    and exits 0."""
    done = subprocess.run([sys.executable, "-m", "vibimpact.cli", "--version"],
                          env=_env(tmp_path), cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0
    first, second = done.stdout.strip().splitlines()
    assert first == f"vibimpact {vi.__version__}"
    assert second.startswith("precompiled kernel: not filled at install")
    assert str(tmp_path) in second


def test_routine_pickles_to_the_same_routine():
    """A kernel routine travels to worker processes (pickled) and runs there the same."""
    r = pickle.loads(pickle.dumps(kb.dot))
    v = np.arange(3.0)
    assert r.name == "dot" and r(v, v) == kb.dot(v, v) == 5.0
    init = pickle.loads(pickle.dumps(vi.ROTOR.init_mode))
    assert init.name == "rotor_init_mode"


#: in a fresh interpreter (as a worker process that numba's memo of dispatchers does not
#: reach): unpickle the routines and models of stdin, call each family's initial mode and
#: the array routines, and print whether every dispatcher is its module's own and how
#: many functions numba compiled (rather than loaded from the cache)
_UNPICKLE = """
import pickle, sys
import numpy as np
from numba.core import event
compiled = []
class L(event.Listener):
    def on_start(self, ev):
        compiled.append(ev.data["dispatcher"].py_func.__qualname__)
    def on_end(self, ev):
        pass
event.register("numba:compile", L())
from vibimpact._kernel.precompiled import own_dispatcher
routines, models = pickle.load(sys.stdin.buffer)
own = all(own_dispatcher(r.name, r.jit) for r in routines)
for m in models:
    n = len(m.state_names)
    m.init_mode(0.0, np.full(n, 0.5), np.zeros(len(m.param_names)),
                np.zeros(m.n_mode, dtype=np.int64))
v = np.arange(3.0)
routines[0](v, v)
print(own, len(compiled), compiled)
"""


def test_a_routine_unpickled_in_a_fresh_process_loads_from_the_cache():
    """Hypothesis: a kernel routine or built-in model pickled to a process that never saw
    it (a worker) arrives as the dispatcher of its kernel module, with numba's disk cache,
    so that calling it there compiles nothing -- a factory-made ``init_mode`` (the rigid
    stop's) included, whose cache key holds the dispatchers it closes over; numba
    rebuilds a dispatcher it pickled by value without the cache, and every worker
    compiled its ``init_mode`` again."""
    from vibimpact._kernel.cache_stamp import cache_state

    if not cache_state()[0]:
        pytest.fail("the test environment's kernel cache is not in use: "
                    + cache_state()[1])
    models = [vi.models.get(n) for n in vi.models.names()]  # every built-in family
    routines = [kb.dot, kb.matmul, kb.solve, kb.eigvals, *(m.init_mode for m in models)]
    r = subprocess.run([sys.executable, "-c", _UNPICKLE], input=pickle.dumps(
        (routines, models)), capture_output=True, timeout=120, cwd=ROOT)
    assert r.returncode == 0, r.stderr.decode()
    own, count = r.stdout.decode().split()[:2]
    assert own == "True" and count == "0", r.stdout.decode()


@pytest.mark.parametrize("family", ["rotor", "duffing", "hard_impact"])
def test_an_init_mode_routine_made_anywhere_checks_its_arguments(family):
    """Hypothesis: a family's ``init_mode`` routine is checked however it was made -- by
    the boundary, or by name alone as when a worker process unpickles it -- so that a
    state vector of the wrong size is refused before the kernel reads past it."""
    from vibimpact._kernel.precompiled import routine
    from vibimpact._kernel.registry import family as kernel_family

    entry = kernel_family(family)
    n, n_p, n_m, _ = entry.sizes
    r = routine(f"{family}_init_mode", entry.init_mode)
    with pytest.raises(ValueError, match="must have"):
        r(0.0, np.zeros(n + 1), np.zeros(n_p), np.zeros(n_m, dtype=np.int64))


def test_the_filled_cache_holds_every_exported_function_by_numbas_own_names():
    """Hypothesis: after the kernel is built, every function the stamp checks has its
    cache index under the name numba gives it -- including functions a model's factory
    makes inside another (``stop_model.<locals>.rhs``, whose index numba writes without
    the angle brackets) -- so ``--version`` reports the filled cache as in use instead of
    'gone', and a second build compiles nothing."""
    from vibimpact._kernel import aot_build
    from vibimpact._kernel.cache_stamp import cache_state, cached_functions

    aot_build.build()
    names = aot_build._exported_names()
    assert any("locals" in n for n in names), "no factory-made function exported"
    assert names <= set(cached_functions()), sorted(names - set(cached_functions()))
    assert cache_state()[0], cache_state()[1]
    assert aot_build.build()["compiled"] is False
