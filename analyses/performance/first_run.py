"""Wall time of a first (cold) and a repeated (warm) run of the command line.

A *cold* run starts with an empty numba cache: ``NUMBA_CACHE_DIR`` points at a fresh
temporary directory, so every kernel function the command needs is compiled (the
package's own ``__pycache__`` is not used when ``NUMBA_CACHE_DIR`` is set, see
``vibimpact/_kernel/cache_guard.py``).  The *warm* run repeats the command with the cache
the cold run wrote: nothing is compiled.  Each run is a fresh ``python -m vibimpact``
subprocess, timed from its start to its exit (interpreter start-up and imports included).
Every pair runs twice: with the precompiled kernel the install built (the default,
``vibimpact._kernel.precompiled``) and JIT only (``VIBIMPACT_PRECOMPILED=0``, what an
install without a C compiler gets); the report also gives the install-time build's
duration and the numba cache files each cold run wrote (0: it compiled nothing).

Run as ``python analyses/performance/first_run.py [--repeat N] [--no-report]``: it prints the times
and replaces the section ``first_run`` of ``reports/performance.md`` (the target, 10 s for
the cold ``classify``, is judged there); :func:`measure` returns the times as a dict.
"""
from __future__ import annotations

import datetime
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # analyses/: _common
from _common import smoke  # noqa: E402
from _common.report import write_section  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
REPORT = ROOT / "reports" / "performance.md"
SECTION = "first_run"
#: the acceptance target of the cold first ``classify`` (seconds, this 2-core machine)
TARGET_COLD_S = 10.0

#: the commands timed: name -> arguments after ``vibimpact`` ({out}: a file in the
#: temporary directory)
COMMANDS = {
    "classify": ["classify", "--eta", "0.9:1.5:0.002", "-o", "{out}.nc", "--no-progress"],
    "simulate": ["simulate", "--preset", "fig8", "--eta", "1.2", "-o", "{out}.nc"],
}


#: a smoke run (``--smoke``): the "cold" runs keep the install's warm numba cache and
#: the install-time build is not timed, so that nothing is compiled
SMOKE = False

#: the environment variable that turns the precompiled kernel off (vibimpact._kernel.precompiled)
PRECOMPILED_ENV = "VIBIMPACT_PRECOMPILED"


def _cache_files(cache_dir):
    """numba cache files (``*.nbi``, ``*.nbc``) under ``cache_dir``: what was compiled."""
    return sum(f.endswith((".nbi", ".nbc")) for _, _, fs in os.walk(cache_dir) for f in fs)


def _run(args, cache_dir, out, precompiled=True):
    env = dict(os.environ) if SMOKE else dict(os.environ, NUMBA_CACHE_DIR=cache_dir)
    env.pop(PRECOMPILED_ENV, None)
    if not precompiled:
        env[PRECOMPILED_ENV] = "0"
    cmd = [sys.executable, "-m", "vibimpact"] + [a.format(out=out) for a in args]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                          text=True)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({proc.returncode}):\n{proc.stderr}")
    return wall


def measure(commands=None, repeat=1):
    """Cold and warm wall times (seconds) of each command.

    Parameters
    ----------
    commands : sequence of str, optional
        Names in :data:`COMMANDS` (all by default).
    repeat : int
        Cold/warm pairs per command, each with its own empty cache; the smallest time of
        each kind is reported (the machine's other load only ever adds).

    Returns
    -------
    dict
        ``{name: {"cold_s", "warm_s", "cold_files", "jit_cold_s", "jit_warm_s",
        "jit_cold_files", "command"}}``: times (s) and numba cache files written by the
        cold run, with the precompiled kernel (the default) and without it
        (``VIBIMPACT_PRECOMPILED=0``: what an install without a C compiler gets).
    """
    out = {}
    for name in commands or COMMANDS:
        args = COMMANDS[name]
        r = {"command": "vibimpact " + " ".join(a.replace("{out}", "OUT") for a in args)}
        for prefix, pre in (("", True), ("jit_", False)):
            cold, warm, files = [], [], []
            for _ in range(repeat):
                with tempfile.TemporaryDirectory(prefix="vibimpact-first-run-") as tmp:
                    cache = os.path.join(tmp, "numba-cache")
                    os.mkdir(cache)
                    cold.append(_run(args, cache, os.path.join(tmp, "cold"), pre))
                    files.append(_cache_files(cache))
                    warm.append(_run(args, cache, os.path.join(tmp, "warm"), pre))
            r.update({f"{prefix}cold_s": min(cold), f"{prefix}warm_s": min(warm),
                      f"{prefix}cold_files": max(files)})
        out[name] = r
    return out


def precompiled_status():
    """What the installed package says about its precompiled kernel (one line)."""
    code = "from vibimpact._kernel import precompiled; print(precompiled.status())"
    env = {k: v for k, v in os.environ.items() if k != PRECOMPILED_ENV}
    return subprocess.run([sys.executable, "-c", code], env=env, check=True,
                          capture_output=True, text=True).stdout.strip()


def build_seconds():
    """Seconds the install-time build of the precompiled kernel takes (built into a
    temporary directory with an empty numba cache, as ``pip install`` builds it)."""
    with tempfile.TemporaryDirectory(prefix="vibimpact-first-run-") as tmp:
        cache = os.path.join(tmp, "numba-cache")
        os.mkdir(cache)
        code = ("import sys; from vibimpact._kernel import aot_build; "
                "print(aot_build.build(sys.argv[1]))")
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", code, os.path.join(tmp, "_aot.so")],
                       env=env, check=True, capture_output=True)
        return time.perf_counter() - t0


def _help_compiles():
    """Files ``vibimpact --help`` writes into an empty numba cache (0: nothing compiled)."""
    with tempfile.TemporaryDirectory(prefix="vibimpact-first-run-") as tmp:
        cache = os.path.join(tmp, "numba-cache")
        os.mkdir(cache)
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "vibimpact", "--help"], env=env, check=True,
                       stdout=subprocess.DEVNULL)
        return time.perf_counter() - t0, sum(len(f) for _, _, f in os.walk(cache))


def _cpu():
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def report(res, help_s, help_files, repeat, status, build_s):
    """The section text for ``reports/performance.md``."""
    import numba

    now = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    cold = res["classify"]["cold_s"]
    jit_cold = res["classify"]["jit_cold_s"]
    L = ["## First run (cold numba cache)", "",
         f"Written by `python analyses/performance/first_run.py` on {now}; {os.cpu_count()} CPUs "
         f"({_cpu()}), Python {platform.python_version()}, numba {numba.__version__}, "
         f"load average {os.getloadavg()[0]:.2f} at the end.  Each command runs as a fresh "
         "`python -m vibimpact` process, timed from start to exit (interpreter start-up, "
         "imports and writing the file included).  *Cold*: `NUMBA_CACHE_DIR` is a new empty "
         "directory, so every kernel function the command uses and the install did not "
         "precompile is compiled; *warm*: the same command again with the cache the cold "
         f"run wrote.  Best of {repeat}.", "",
         "The install compiles the rotor's integration loop and the analyses' array "
         "routines ahead of time (`setup.py`, `vibimpact/_kernel/aot_build.py`); the "
         f"installed package says of it: *{status}*.  Building it took {build_s:.0f} s "
         "here (part of `pip install`).  The *JIT only* columns turn it off "
         f"(`{PRECOMPILED_ENV}=0`): what an install without a C compiler gets.", "",
         "| command | cold [s] | warm [s] | cache files written cold | JIT only: cold [s] "
         "| JIT only: warm [s] | JIT only: cache files written cold |",
         "| --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for r in res.values():
        L.append(f"| `{r['command']}` | {r['cold_s']:.1f} | {r['warm_s']:.1f} | "
                 f"{r['cold_files']} | {r['jit_cold_s']:.1f} | {r['jit_warm_s']:.1f} | "
                 f"{r['jit_cold_files']} |")
    L += ["",
          f"- cold `classify` on the default grid: {cold:.1f} s against the target of "
          f"{TARGET_COLD_S:.0f} s: " + ("met" if cold <= TARGET_COLD_S else "**not met**"),
          f"- the same, JIT only: {jit_cold:.1f} s: " + (
              "within the target too" if jit_cold <= TARGET_COLD_S
              else "**over the target** (the precompiled kernel is what meets it)"),
          f"- `vibimpact --help` with an empty cache: {help_s:.2f} s, {help_files} files "
          "written to the cache (" + ("nothing compiled" if help_files == 0
                                      else "**it compiles**") + ")"]
    return "\n".join(L)


def main(argv=None):
    global REPORT
    ap = smoke.parser(__doc__)
    ap.add_argument("--repeat", type=int, default=1,
                    help="cold/warm pairs per command (the smallest times are shown)")
    ap.add_argument("--no-report", action="store_true",
                    help="print the times only; leave reports/performance.md as it is")
    ap.add_argument("commands", nargs="*", metavar="COMMAND",
                    help=f"commands to time, of {', '.join(COMMANDS)} (default: all)")
    args = ap.parse_args(argv)
    REPORT = smoke.moved(REPORT, args.smoke)
    smoke.shrink(globals(), args.smoke, SMOKE=True, COMMANDS={
        "classify": ["classify", "--eta", "1.2:1.21:0.01", "-o", "{out}.nc", "--no-progress"],
        "simulate": COMMANDS["simulate"]})
    unknown = [c for c in args.commands if c not in COMMANDS]
    if unknown:
        ap.error(f"unknown command(s) {', '.join(unknown)}; known: {', '.join(COMMANDS)}")
    res = measure(args.commands or None, repeat=args.repeat)
    for name, r in res.items():
        print(f"{name:9s} cold {r['cold_s']:6.1f} s   warm {r['warm_s']:5.1f} s   "
              f"JIT only: cold {r['jit_cold_s']:6.1f} s   warm {r['jit_warm_s']:5.1f} s   "
              f"({r['command']})")
    if not args.no_report:
        if set(res) != set(COMMANDS):
            ap.error("the report needs every command; use --no-report with a subset")
        help_s, help_files = _help_compiles()
        text = report(res, help_s, help_files, args.repeat, precompiled_status(),
                      float("nan") if SMOKE else build_seconds())
        write_section(REPORT, SECTION, text)
        print(f"wrote section {SECTION} of {REPORT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
