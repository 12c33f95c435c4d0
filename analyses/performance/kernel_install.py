"""How the kernel is compiled ahead of the first run: the candidates of issue 29, measured.

Candidates (issue 29, point 6):

* (a) numba's own on-disk cache, filled at install (``python -m vibimpact._kernel.aot_build``
  in the tree measured; public numba API only);
* (b) numba's ahead-of-time compiler, ``numba.pycc``, as the package used it up to
  ``--pycc-commit`` (the module built with the private flag patches), and the same
  build with the patches left out (public ``numba.pycc.CC`` only);
* the reference: no compilation ahead of time, a cold JIT (empty numba cache).

For each: seconds of the install-time step, seconds of a first run of two commands in a
fresh process (``simulate`` and a short ``classify``), and the numba cache files that
first run wrote (0: it compiled nothing).  Then what happens across numba versions: (a)
filled by another numba (``--other-numba``, installed into a throwaway venv) and read by
this one; (b) built by ``pip install``'s isolated build environment, whose numba is the
newest the index offers, not necessarily the runtime's.  Last, the real install path of
(a): ``pip install -v --no-deps -e TREE`` then ``-e "TREE[test]"`` in a throwaway venv
with no C compiler reachable (``CC=/bin/false``), and ``vibimpact --version`` there.

Every run is a fresh subprocess timed from start to exit; the machine has 2 cores shared
with other work, so the load average is printed beside the figures.  Run as
``python analyses/performance/kernel_install.py [--tree DIR] [--pycc-commit REV]
[--other-numba VERSION] [--smoke DIR]``; it writes ``reports/kernel_install.md``
(``--smoke DIR``: (a) alone, its report written under DIR, ``tests/test_analyses_smoke.py``).
"""
from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # analyses/: _common
from _common import smoke  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
REPORT = ROOT / "reports" / "kernel_install.md"

#: the first-run commands: name -> arguments after ``python -m vibimpact.cli``
COMMANDS = {
    "simulate": ["simulate", "--preset", "fig8", "--eta", "1.25", "-o", "{out}.nc"],
    "classify": ["classify", "--eta", "1.1:1.2:0.01", "-o", "{out}.nc", "--no-progress"],
}
#: the old build with its private patches turned off: public numba.pycc.CC only
PYCC_PUBLIC = ("import contextlib, sys; from vibimpact._kernel import aot_build as a; "
               "a._dispatcher_flags = lambda options: contextlib.nullcontext(); "
               "print(a.build(sys.argv[1]))")
PYCC_PATCHED = ("import sys; from vibimpact._kernel import aot_build as a; "
                "print(a.build(sys.argv[1]))")


def _env(cache=None, **extra):
    env = {k: v for k, v in os.environ.items()
           if k not in ("NUMBA_CACHE_DIR", "VIBIMPACT_PRECOMPILED", "PYTHONPATH")}
    if cache is not None:
        env["NUMBA_CACHE_DIR"] = str(cache)
    env.update(extra)
    return env


def timed(cmd, cwd, env):
    """``(seconds, completed process)`` of ``cmd`` run to its end."""
    t0 = time.perf_counter()
    done = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)
    seconds = time.perf_counter() - t0
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(map(str, cmd))} failed:\n{done.stderr[-2000:]}")
    return seconds, done


def cache_files(cache, since=None):
    """numba cache files under ``cache`` (written at or after the time ``since``, a
    ``time.time()``, when given: a numba of another version rewrites files in place)."""
    return sum(f.endswith((".nbi", ".nbc")) and (
        since is None or os.path.getmtime(os.path.join(d, f)) >= since)
        for d, _, fs in os.walk(cache) for f in fs)


def first_runs(tree, cache, python=sys.executable, counted=None):
    """``{command: (seconds, cache files it wrote or rewrote)}`` of a fresh process each, with
    ``NUMBA_CACHE_DIR=cache`` (None: numba's default, counted in ``counted``)."""
    out = {}
    counted = counted or cache
    with tempfile.TemporaryDirectory(prefix="kernel-install-out-") as tmp:
        for name, args in COMMANDS.items():
            start = time.time()
            cmd = [python, "-m", "vibimpact.cli"] + [a.format(out=f"{tmp}/{name}")
                                                     for a in args]
            seconds, _ = timed(cmd, tree, _env(cache))
            out[name] = (seconds, cache_files(counted, since=start))
    return out


def status(tree, cache, python=sys.executable):
    """What ``vibimpact --version`` says (its second line)."""
    _, done = timed([python, "-m", "vibimpact.cli", "--version"], tree, _env(cache))
    return done.stdout.strip().splitlines()[-1]


def measure_reference(tree, work):
    """The cold JIT: no cache at all."""
    return first_runs(tree, work / "cache-jit")


def measure_cache(tree, work):
    """(a): fill, fill again (up to date), then the first runs."""
    cache = work / "cache-a"
    fill, done = timed([sys.executable, "-m", "vibimpact._kernel.aot_build"], tree,
                       _env(cache))
    again, done2 = timed([sys.executable, "-m", "vibimpact._kernel.aot_build"], tree,
                         _env(cache))
    return {"fill_s": fill, "fill_out": done.stdout.strip().splitlines()[-1],
            "again_s": again, "again_out": done2.stdout.strip().splitlines()[-1],
            "files": cache_files(cache), "status": status(tree, cache),
            "first": first_runs(tree, cache)}


def old_tree(commit, work):
    """The tree of ``commit`` (the pycc build) extracted under ``work``."""
    dest = work / "pycc-tree"
    dest.mkdir()
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", commit],
                             capture_output=True, check=True).stdout
    subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    return dest


def measure_pycc(tree, work, code, label):
    """(b): build the module into the tree (in this environment), first runs with it."""
    ext = subprocess.run([sys.executable, "-c", "import sysconfig; print(sysconfig."
                          "get_config_var('EXT_SUFFIX'))"], capture_output=True,
                         text=True, check=True).stdout.strip()
    module = tree / "vibimpact" / "_kernel" / f"_aot{ext}"
    build, _ = timed([sys.executable, "-c", code, str(module)], tree,
                     _env(work / f"cache-build-{label}"))
    cache = work / f"cache-{label}"
    _, done = timed([sys.executable, "-c", "from vibimpact._kernel import cache_stamp; "
                     "print(cache_stamp.status())"], tree, _env(cache))
    result = {"build_s": build, "status": done.stdout.strip(),
              "first": first_runs(tree, cache)}
    # the tree's own checks that the precompiled functions give the JIT's bits
    bits = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                           "tests/test_precompiled.py", "-k", "bits"], cwd=tree,
                          env=_env(work / f"cache-bits-{label}"), capture_output=True,
                          text=True)
    result["bits"] = (bits.stdout.strip().splitlines() or ["no output"])[-1]
    for f in (module, Path(str(module) + ".json")):
        f.unlink(missing_ok=True)
    return result


def venv(path, python=sys.executable):
    """A throwaway venv that sees this environment's packages; its python."""
    subprocess.run([python, "-m", "venv", "--system-site-packages", str(path)], check=True)
    return path / "bin" / "python"


def measure_other_numba(tree, work, version):
    """(a) filled by numba ``version`` (a venv), read by this environment's numba."""
    py = venv(work / "venv-numba")
    timed([py, "-m", "pip", "install", "-q", f"numba=={version}"], tree, _env())
    cache = work / "cache-other"
    fill, _ = timed([py, "-m", "vibimpact._kernel.aot_build"], tree, _env(cache))
    _, done = timed([py, "-c", "import numba; print(numba.__version__)"], tree, _env())
    return {"version": done.stdout.strip(), "fill_s": fill, "status": status(tree, cache),
            "first": first_runs(tree, cache)}


def measure_install(tree, work, label, old=False):
    """``pip install -v --no-deps -e TREE`` then ``-e TREE[test]`` in a throwaway venv:
    seconds, the install's own lines, what the runtime says.  (a) with no C compiler
    reachable (``CC=/bin/false``); the pycc build (``old``) with one (it needs it)."""
    copy = work / f"install-tree-{label}"
    shutil.copytree(tree, copy, ignore=shutil.ignore_patterns("__pycache__", "*.so",
                                                              "*.so.json", "*.egg-info"))
    py = venv(work / f"venv-{label}")
    env = _env() if old else _env(CC="/bin/false", CXX="/bin/false", LDSHARED="/bin/false")
    out = {}
    for step, target in (("install", str(copy)), ("extra", f"{copy}[test]")):
        seconds, done = timed([py, "-m", "pip", "install", "-v", "--no-deps", "-e", target],
                              work, env)
        text = done.stdout + done.stderr
        said = [line.strip() for line in text.splitlines()
                if "vibimpact install:" in line or "precompiled kernel" in line]
        out[step] = (seconds, said)
        # the numba pip put into the isolated build environment, if any
        found = re.search(r"Successfully installed .*?numba-(\S+)", text)
        out[f"{step}_build_numba"] = found.group(1) if found else None
    if old:
        code = "from vibimpact._kernel import cache_stamp; print(cache_stamp.status())"
        _, done = timed([py, "-c", code], work, env)
        out["status"] = done.stdout.strip()
    else:
        _, done = timed([py, "-m", "vibimpact.cli", "--version"], work, env)
        out["status"] = done.stdout.strip().splitlines()[-1]
        out["first"] = first_runs(work, None, python=py,
                                  counted=copy / "vibimpact" / "_kernel")["simulate"]
    return out


def versions():
    import llvmlite
    import numba
    import numpy

    return (f"Python {platform.python_version()}, numba {numba.__version__}, llvmlite "
            f"{llvmlite.__version__}, NumPy {numpy.__version__}")


def _runs(first):
    return ", ".join(f"`{name}` {s:.1f} s ({files} cache files written or rewritten)"
                     for name, (s, files) in first.items())


def report(res, args):
    """The Markdown report of the measurements ``res``."""
    lines = ["# The kernel at install time: candidates measured", "",
             f"Written by `analyses/performance/kernel_install.py` on "
             f"{res['date']}; {res['versions']}; {os.cpu_count()} cores, load average "
             f"{res['load'][0]:.1f} before and {res['load'][1]:.1f} after (other work "
             f"shares the cores: compare figures of one run only); C compiler on PATH: "
             f"{res['cc']}.  Each figure is one fresh process, start to exit; first-run "
             f"commands: " + "; ".join(f"`vibimpact {' '.join(a)}`"
                                       for a in COMMANDS.values()) + ".", "",
             "## First run and install step", ""]
    if "jit" in res:
        lines.append(f"- no compilation ahead of time (cold JIT): {_runs(res['jit'])}")
    if "a" in res:
        a = res["a"]
        lines.append(
            f"- (a) numba's cache filled at install: fill {a['fill_s']:.1f} s "
            f"({a['files']} cache files), again with the key unchanged {a['again_s']:.1f} s "
            f"(\"{a['again_out']}\"); first run: {_runs(a['first'])}; `--version`: "
            f"\"{a['status']}\"")
    for label, name in (("b_patched", "(b) pycc as built up to " + args.pycc_commit[:10]
                         + ", private patches in"),
                        ("b_public", "(b) pycc with the public `numba.pycc.CC` only")):
        if label in res:
            b = res[label]
            lines.append(f"- {name}: build {b['build_s']:.1f} s; status \"{b['status']}\"; "
                         f"first run: {_runs(b['first'])}; its bit-identity tests "
                         f"(`pytest tests/test_precompiled.py -k bits` of that tree): "
                         f"{b.get('bits')}")
    lines += ["", "## Across numba versions", ""]
    if "other" in res:
        o = res["other"]
        lines.append(f"- (a) filled by numba {o['version']} ({o['fill_s']:.1f} s), read by "
                     f"this numba: `--version` says \"{o['status']}\"; first run: "
                     f"{_runs(o['first'])} (numba finds no entry of its own version and "
                     f"compiles: slower, never wrong)")
    if "install_b" in res:
        i = res["install_b"]
        lines.append(f"- (b) `pip install -e` of {args.pycc_commit[:10]} (isolated build "
                     f"environment, which got numba {i.get('install_build_numba')}; this "
                     f"environment has {res['versions'].split('numba ')[1].split(',')[0]}):"
                     f" {i['install'][0]:.1f} s, the extra again {i['extra'][0]:.1f} s "
                     f"(\"{'; '.join(i['extra'][1])}\"); the runtime then says "
                     f"\"{i['status']}\".  Where the two numbas differ, the module is built "
                     f"and then refused at run time by its versions check (issue 29), and every run "
                     f"compiles on first use.")
    if "install_a" in res:
        i = res["install_a"]
        lines += ["", "## The install of (a), no C compiler (`CC=/bin/false`)", "",
                  f"- `pip install -v --no-deps -e TREE`: {i['install'][0]:.1f} s; it says:"]
        lines += [f"  - `{s}`" for s in i["install"][1]]
        lines.append(f"- `pip install -v --no-deps -e \"TREE[test]\"`: {i['extra'][0]:.1f} s;"
                     f" it says:")
        lines += [f"  - `{s}`" for s in i["extra"][1]]
        lines.append(f"- `vibimpact --version` there: \"{i['status']}\"; first `simulate`: "
                     f"{i['first'][0]:.1f} s ({i['first'][1]} cache files written)")
    lines += ["", "## Choice", ""] + choice(res)
    return "\n".join(lines) + "\n"


#: the first run's target (issue 29, point 6), seconds on this machine
TARGET_FIRST_RUN_S = 10.0


def choice(res):
    """The paragraph that compares the candidates, from the figures of ``res``."""
    if "a" not in res:
        return ["(not all candidates measured)"]
    a = res["a"]
    worst = max(s for s, _ in a["first"].values())
    compiled = sum(n for _, n in a["first"].values())
    out = [f"(a), numba's own cache filled at install, is the one the package uses: its "
           f"first runs took at most {worst:.1f} s (target {TARGET_FIRST_RUN_S:.0f} s: "
           f"{'met' if worst <= TARGET_FIRST_RUN_S else 'NOT met'}) and compiled "
           f"{'nothing' if compiled == 0 else f'{compiled} cache files'}"]
    if "jit" in res:
        out[-1] += (f", against {max(s for s, _ in res['jit'].values()):.1f} s for the "
                    f"slowest cold JIT run")
    out[-1] += (f"; its install step took {a['fill_s']:.1f} s and {a['again_s']:.1f} s "
                f"with the key unchanged")
    if "b_patched" in res:
        b = res["b_patched"]
        b_worst = max(s for s, _ in b["first"].values())
        out[-1] += (f", where the pycc build took {b['build_s']:.1f} s for first runs of "
                    f"at most {b_worst:.1f} s.  On time the two differ by "
                    f"{abs(worst - b_worst):.1f} s in the first run and "
                    f"{abs(a['fill_s'] - b['build_s']):.1f} s in the install step, on a "
                    f"machine whose load changed from {res['load'][0]:.1f} to "
                    f"{res['load'][1]:.1f} during the measurement")
    if "install_a" in res and "install_b" in res:
        out[-1] += (f"; installing an extra after the package took "
                    f"{res['install_a']['extra'][0]:.1f} s with (a), which compiled "
                    f"nothing, and {res['install_b']['extra'][0]:.1f} s with (b), which "
                    f"built its module again")
    out[-1] += (".  (a) also uses numba's public API only (dispatchers with `cache=True`, "
                "called with the package's argument types; their `stats` for the cache "
                "directory), needs no C compiler, and is the JIT's own code, so the "
                "numbers are the JIT's bits (`tests/test_precompiled.py`).  Across numba "
                "versions it degrades to a compilation on first use: numba keys its cache "
                "on its own version, and `vibimpact --version` says why the cache is not "
                "in use.")
    out.append("")
    public = res.get("b_public", {}).get("bits")
    out.append("(b) was set aside: `numba.pycc` is pending deprecation and needs a C "
               "compiler; without the private patches its exports are compiled with "
               "pycc's own flags (the Python error model, the runtime on, a generic "
               "feature list for the processor), not the dispatchers', so identical bits "
               "are an observation, not a guarantee"
               + (f" (the tree's bit-identity tests of that build: {public})" if public
                  else "")
               + "; pip builds it again for every extra; and pip's isolated build compiles "
               "it with the build environment's numba, which the runtime has to refuse "
               "when it differs (see \"Across numba versions\").")
    return out


def main(argv=None):
    parser = smoke.parser(__doc__)
    parser.add_argument("--tree", type=Path, default=ROOT,
                        help="the source tree of (a) (default: this checkout)")
    parser.add_argument("--pycc-commit", default="db6352a",
                        help="a commit whose setup.py builds the pycc module (b)")
    parser.add_argument("--other-numba", default="0.68.0",
                        help="the numba version (a)'s cache is filled with across versions")
    parser.add_argument("--from-json", type=Path, default=None, metavar="FILE",
                        help="measure nothing: write the report of the figures FILE "
                             "(the .json a run writes beside its report) holds")
    args = parser.parse_args(argv)
    report_path = smoke.moved(REPORT, args.smoke)
    if args.from_json is not None:
        res = json.loads(args.from_json.read_text())
        _write(report_path, res, report(res, args))
        return 0
    res = {"date": datetime.date.today().isoformat(), "versions": versions(),
           "cc": shutil.which("cc") or "none", "load": [os.getloadavg()[0]]}
    with tempfile.TemporaryDirectory(prefix="kernel-install-") as tmp:
        work = Path(tmp)
        steps = [("a", lambda: measure_cache(args.tree, work))]
        if args.smoke is None:
            steps += [
                ("jit", lambda: measure_reference(args.tree, work)),
                ("install_a", lambda: measure_install(args.tree, work, "a")),
                ("other", lambda: measure_other_numba(args.tree, work, args.other_numba)),
                ("b_patched", lambda: measure_pycc(old_tree(args.pycc_commit, work), work,
                                                   PYCC_PATCHED, "patched")),
                ("b_public", lambda: measure_pycc(work / "pycc-tree", work, PYCC_PUBLIC,
                                                  "public")),
                ("install_b", lambda: measure_install(work / "pycc-tree", work, "b",
                                                      old=True))]
        for name, step in steps:
            print(f"measuring {name} ...", flush=True)
            try:
                res[name] = step()
            except Exception as exc:  # a candidate that fails is reported, not fatal
                print(f"  {name} failed: {exc}", flush=True)
                res.setdefault("failed", []).append(f"{name}: {str(exc)[-300:]}")
            print(f"  {res.get(name)}", flush=True)
    res["load"].append(os.getloadavg()[0])
    _write(report_path, res, report(res, args))
    return 1 if res.get("failed") else 0


def _write(report_path, res, text):
    """Print ``text`` and write it to ``report_path``, the figures ``res`` beside it as
    JSON (each file atomically)."""
    if res.get("failed"):
        text += "\n## Failed steps\n\n" + "\n".join(f"- {f}" for f in res["failed"]) + "\n"
    print(text)
    report_path.parent.mkdir(parents=True, exist_ok=True)
    for path, content in ((report_path.with_suffix(".json"), json.dumps(res, indent=1)),
                          (report_path, text)):
        tmp = path.with_name(path.name + ".tmp")
        tmp.write_text(content)
        os.replace(tmp, path)


if __name__ == "__main__":
    sys.exit(main())
