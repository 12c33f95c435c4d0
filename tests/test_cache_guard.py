"""The kernel's numba cache is dropped when any kernel source changes."""
from vibimpact._kernel import cache_guard as cg


def _tree(tmp_path):
    src = tmp_path / "_kernel"
    src.mkdir()
    (src / "driver.py").write_text("x = 1\n")
    (src / "lyapunov.py").write_text("y = 2\n")
    cache = src / "__pycache__"
    cache.mkdir()
    return src, cache


def _fill(cache):
    for name in ("lyapunov.benettin-20.py311.nbi", "lyapunov.benettin-20.py311.1.nbc"):
        (cache / name).write_text("compiled")
    (cache / "driver.cpython-311.pyc").write_text("bytecode")


def test_cache_built_from_other_sources_is_dropped_and_unchanged_one_kept(tmp_path):
    """Hypothesis: numba's cache files in a directory without the sources' digest (built
    before the guard, or from other sources) are deleted, the bytecode is kept and the
    digest stamped; with unchanged sources the next import keeps the new cache; an edit
    of *another* file than the cached function's (driver.py, called by lyapunov's
    cached benettin) drops it again."""
    src, cache = _tree(tmp_path)
    _fill(cache)
    assert cg.drop_stale_cache(src, [cache]) == 2
    assert sorted(f.name for f in cache.iterdir()) == ["driver.cpython-311.pyc", cg.STAMP]
    _fill(cache)
    assert cg.drop_stale_cache(src, [cache]) == 0
    assert len(list(cache.glob("*.nb?"))) == 2
    (src / "driver.py").write_text("x = 3\n")
    assert cg.drop_stale_cache(src, [cache]) == 2
    assert not list(cache.glob("*.nb?"))


def test_numba_cache_dir_is_located_like_numba_does(tmp_path):
    """Hypothesis: with NUMBA_CACHE_DIR set, the guard also checks numba's directory for
    the package there, ``<dir>/<package name>_<sha1 of the package's path>``."""
    import hashlib

    src, _ = _tree(tmp_path)
    dirs = cg.cache_dirs(src, {"NUMBA_CACHE_DIR": str(tmp_path / "nc")})
    tag = hashlib.sha1(str(src).encode()).hexdigest()
    assert dirs == [src / "__pycache__", tmp_path / "nc" / f"_kernel_{tag}"]
    assert cg.cache_dirs(src, {}) == [src / "__pycache__"]


def test_unwritable_cache_directory_is_left_alone(tmp_path):
    """Hypothesis: a cache directory that cannot be created (its parent is a file) is
    skipped without an error, and the others are still checked."""
    src, cache = _tree(tmp_path)
    _fill(cache)
    blocker = tmp_path / "not_a_dir"
    blocker.write_text("")
    assert cg.drop_stale_cache(src, [blocker / "cache", cache]) == 2
