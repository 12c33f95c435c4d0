"""Every script of ``analyses/`` runs, in its tiny ``--smoke DIR`` mode, so that none rots
silently (issue 29, point 5).

A script is a ``.py`` file of an ``analyses/<kind>/`` folder with a ``__main__`` block; the
others are helpers that scripts import.  The smoke runs are slow studies (minutes on 2
cores: they start worker pools, command-line subprocesses and fault injections), so they
carry the ``slow`` mark; the checks that every script is covered and that the profile
fails on an entry that matches nothing are fast.
"""
import hashlib
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
ANALYSES = ROOT / "analyses"

#: script (relative to analyses/) -> the files its smoke run must write under its directory
SMOKE = {
    "paper/paper.py": ["paper.md", "paper.json", "figures/response_fig8.png",
                       "figures/xy_fig10.png", "README.md"],
    "paper/calibrate.py": ["calibration.md", "calibration.nc", "figures/calibration.png"],
    "paper/census_claims.py": ["census_claims.json"],
    "paper/transitions.py": ["transitions.md", "figures/branches_fig8.png"],
    "paper/readme_summary.py": ["README.md"],
    "performance/performance.py": ["performance.md", "work_precision_fig8.png",
                                   "work_precision.png"],
    # not run by performance.py: it compiles the kernel cold, installs into throwaway
    # environments and writes a report of its own
    "performance/kernel_install.py": ["kernel_install.md"],
    # not run by performance.py either: a study of its own (sweeps on every method)
    "performance/label_precision.py": ["performance.md", "label_precision.json",
                                       "label_precision.png"],
    "reliability/reliability.py": ["reliability.md"],
    "ring/ring_study.py": ["ring.md", "ring.json", "figures/ring_map.png",
                           "figures/ring_motion.png"],
    "tools/bit_identity.py": ["bit_identity.json"],
    "tools/eta_path.py": ["eta_path.txt"],
}
#: the sections of performance.md each performance script writes (run by performance.py)
PERFORMANCE_SECTIONS = {
    "benchmark_kernel.py": ["kernel"], "first_run.py": ["first_run"],
    "benchmark_sweep.py": ["sweep", "sweep-claims", "low-damping"], "profile_sweep.py": ["profile"],
    "work_precision.py": ["work_precision"], "stress.py": ["stress"],
    "benchmark_map.py": ["map"], "lyapunov_error_control.py": ["lyapunov-error-control"],
    "census_bench.py": ["census"], "ring_bench.py": ["ring"],
    "variational_bench.py": ["variational"], "call_overhead.py": ["call_overhead"],
}


def _py_files():
    return sorted(p for p in ANALYSES.glob("*/*.py") if p.parent.name != "_common")


def _is_script(path):
    return re.search(r'^if __name__ == "__main__":', path.read_text(), re.M) is not None


def _performance_scripts():
    sys.path.insert(0, str(ANALYSES / "performance"))
    try:
        import performance
    finally:
        sys.path.remove(str(ANALYSES / "performance"))
    return performance.SCRIPTS


def test_every_script_is_smoked_and_every_helper_imported():
    """Hypothesis: every script of the analyses folders is run by this test (directly, or
    by performance.py, whose scripts each have their sections checked here), and every
    helper module is imported by a script of its folder -- a new script cannot escape the
    smoke test."""
    scripts = {p.relative_to(ANALYSES).as_posix() for p in _py_files() if _is_script(p)}
    helpers = [p for p in _py_files() if not _is_script(p)]
    perf = {f"performance/{name}" for name in _performance_scripts()}
    assert set(PERFORMANCE_SECTIONS) == set(_performance_scripts())
    assert scripts == set(SMOKE) | perf, "scripts without a smoke run (or gone)"
    for h in helpers:
        users = [p for p in h.parent.glob("*.py") if p != h and _is_script(p) and re.search(
            rf"^\s*(from {h.stem} import|import {h.stem}\b)", p.read_text(), re.M)]
        assert users, f"{h.relative_to(ANALYSES)} is imported by no script of its folder"


def test_every_script_takes_the_smoke_option():
    """Hypothesis: each smoked script (and each one performance.py runs) declares
    ``--smoke`` (without it its smoke run would write into reports/)."""
    for rel in [*SMOKE, *(f"performance/{n}" for n in PERFORMANCE_SECTIONS)]:
        text = (ANALYSES / rel).read_text()
        assert "smoke.parser(" in text or '"--smoke"' in text, rel


def _fingerprint():
    """SHA-256 of everything a script could overwrite by mistake."""
    files = sorted(p for p in (ROOT / "reports").rglob("*") if p.is_file())
    files.append(ROOT / "README.md")
    return {p: hashlib.sha256(p.read_bytes()).hexdigest() for p in files}


@pytest.mark.slow
@pytest.mark.parametrize("script", sorted(SMOKE))
def test_script_runs_in_its_smoke_mode(script, tmp_path):
    """Hypothesis: ``python analyses/<script> --smoke DIR`` run from the repository root
    exits 0, writes its outputs (non-empty) under DIR and leaves reports/ and the README
    as they were."""
    before = _fingerprint()
    out = tmp_path / "smoke"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])]))
    proc = subprocess.run([sys.executable, f"analyses/{script}", "--smoke", str(out)],
                          cwd=ROOT, env=env, capture_output=True, text=True, timeout=1500)
    assert proc.returncode == 0, proc.stderr[-4000:]
    for name in SMOKE[script]:
        assert (out / name).is_file() and (out / name).stat().st_size > 0, name
    if script == "performance/performance.py":
        text = (out / "performance.md").read_text()
        for name, sections in PERFORMANCE_SECTIONS.items():
            for sec in sections:
                assert f"<!-- section:{sec} -->" in text, (name, sec)
    assert _fingerprint() == before, "a smoke run wrote into reports/ or the README"


def _profile_sweep():
    for kind in ("performance",):
        sys.path.insert(0, str(ANALYSES / kind))
    import profile_sweep

    return profile_sweep


def test_a_profile_entry_that_matches_nothing_fails_the_profile():
    """Hypothesis: profile_sweep.bucket_times raises UnmatchedProfileEntry naming every
    entry whose function the profile never saw (the rot that printed 0.00 s for the
    Lyapunov kernel and the Floquet step) -- also an entry of a part whose other entry
    matched, which would silently drop its share -- and returns each part's seconds
    (entries of one part summed, tottime or cumtime as asked) when every entry matched."""
    ps = _profile_sweep()
    # pstats layout: (file, line, function) -> (calls, primitive calls, tottime, cumtime,
    # callers)
    stats = {("/x/vibimpact/_kernel/driver.py", 1, "integrate"): (3, 3, 1.5, 2.0, {}),
             ("/x/vibimpact/_kernel/variational.py", 5, "integrate"): (1, 1, 0.5, 0.5, {}),
             ("/x/vibimpact/analysis/period.py", 9, "detect_period"): (2, 2, 0.25, 0.75, {})}
    buckets = (("kernel", "_kernel/driver.py", "integrate", "tottime"),
               ("kernel", "_kernel/variational.py", "integrate", "tottime"),
               ("periods", "analysis/period.py", "detect_period", "cumtime"))
    assert ps.bucket_times(stats, buckets) == {"kernel": 2.0, "periods": 0.75}
    for gone in (("Floquet step", "sweeps/point.py", "_floquet", "cumtime"),
                 ("kernel", "_kernel/gone.py", "integrate", "tottime")):
        with pytest.raises(ps.UnmatchedProfileEntry,
                           match=f"{gone[0]}.*{gone[1]}:{gone[2]}"):
            ps.bucket_times(stats, buckets + (gone,))


def test_a_kernel_entry_point_counts_as_its_python_function():
    """Hypothesis: the integration loop called through its compiled entry point, which
    cProfile records as a built-in ``<built-in method vibimpact._kernel.driver.integrate>``,
    counts as ``_kernel/driver.py:integrate`` (summed with calls through numba's
    dispatcher), and a built-in of another name matches nothing."""
    ps = _profile_sweep()
    stats = {("~", 0, "<built-in method vibimpact._kernel.driver.integrate>"):
             (9, 9, 3.0, 3.0, {}),
             ("/x/vibimpact/_kernel/driver.py", 1, "integrate"): (1, 1, 0.5, 0.5, {})}
    buckets = (("kernel", "_kernel/driver.py", "integrate", "tottime"),)
    assert ps.bucket_times(stats, buckets) == {"kernel": 3.5}
    other = {("~", 0, "<built-in method builtins.len>"): (1, 1, 1.0, 1.0, {})}
    with pytest.raises(ps.UnmatchedProfileEntry):
        ps.bucket_times(other, buckets)


def test_the_profile_section_shows_every_part_the_script_profiles():
    """Hypothesis: the profile section of reports/performance.md has one row per part of
    profile_sweep.BUCKETS (the parts the script profiles today, in its order) and no part
    it no longer profiles, each with a time above 0.00 s in both columns: a report
    written by an older script, with parts that matched nothing, fails."""
    ps = _profile_sweep()
    text = (ROOT / "reports" / "performance.md").read_text()
    sec = text.split("<!-- section:profile -->")[1].split("<!-- /section:profile -->")[0]
    rows = [r for r in sec.splitlines() if r.startswith("| ") and r.endswith("|")]
    table = rows[:rows.index(next(r for r in rows if r.startswith("| **total")))]
    parts = [r.split(" | ")[0][2:] for r in table[2:]]
    names = list(dict.fromkeys(b[0] for b in ps.BUCKETS))
    assert parts[:len(names)] == names
    assert parts[len(names):] == ["Python around the kernels (wall - kernels)"]
    for r in table[2:2 + len(names)]:
        times = [float(c) for c in r.strip("| ").split(" | ")[1:]]
        assert len(times) == 2 and min(times) > 0.0, r


def test_the_profile_names_functions_that_exist():
    """Hypothesis: every (file, function) of profile_sweep.BUCKETS names a function that is
    defined in that file of the package today (no entry names a module that cannot
    exist, such as the removed pycc module ``vibimpact._kernel._aot``)."""
    ps = _profile_sweep()
    for part, suffix, func, _ in ps.BUCKETS:
        src = (ROOT / "vibimpact" / suffix).read_text()
        assert re.search(rf"^def {re.escape(func)}\(", src, re.M), (part, suffix, func)
