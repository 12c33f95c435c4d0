"""Wall time of a first (cold) and a repeated (warm) run of the command line.

A *cold* run starts with an empty numba cache: ``NUMBA_CACHE_DIR`` points at a fresh
temporary directory, so every kernel function the command needs is compiled (the
package's own ``__pycache__`` is not used when ``NUMBA_CACHE_DIR`` is set, see
``vibimpact/_kernel/cache_guard.py``).  The *warm* run repeats the command with the cache
the cold run wrote: nothing is compiled.  Each run is a fresh ``python -m vibimpact``
subprocess, timed from its start to its exit (interpreter start-up and imports included).

Run as ``python analyses/first_run.py [--repeat N] [--no-report]``: it prints the times
and replaces the section ``first_run`` of ``reports/performance.md`` (the target, 10 s for
the cold ``classify``, is judged there); :func:`measure` returns the times as a dict.
"""
from __future__ import annotations

import argparse
import datetime
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _report import write_section

ROOT = Path(__file__).resolve().parents[1]
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


def _run(args, cache_dir, out):
    env = dict(os.environ, NUMBA_CACHE_DIR=cache_dir)
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
        ``{name: {"cold_s": float, "warm_s": float, "command": str}}``.
    """
    out = {}
    for name in commands or COMMANDS:
        args = COMMANDS[name]
        cold, warm = [], []
        for _ in range(repeat):
            with tempfile.TemporaryDirectory(prefix="vibimpact-first-run-") as tmp:
                cache = os.path.join(tmp, "numba-cache")
                os.mkdir(cache)
                cold.append(_run(args, cache, os.path.join(tmp, "cold")))
                warm.append(_run(args, cache, os.path.join(tmp, "warm")))
        out[name] = {"cold_s": min(cold), "warm_s": min(warm),
                     "command": "vibimpact " + " ".join(a.replace("{out}", "OUT")
                                                        for a in args)}
    return out


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


def report(res, help_s, help_files, repeat):
    """The section text for ``reports/performance.md``."""
    import numba

    now = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    cold = res["classify"]["cold_s"]
    L = ["## First run (cold numba cache)", "",
         f"Written by `python analyses/first_run.py` on {now}; {os.cpu_count()} CPUs "
         f"({_cpu()}), Python {platform.python_version()}, numba {numba.__version__}, "
         f"load average {os.getloadavg()[0]:.2f} at the end.  Each command runs as a fresh "
         "`python -m vibimpact` process, timed from start to exit (interpreter start-up, "
         "imports and writing the file included).  *Cold*: `NUMBA_CACHE_DIR` is a new empty "
         "directory, so every kernel function the command uses is compiled; *warm*: the "
         f"same command again with the cache the cold run wrote.  Best of {repeat}.", "",
         "| command | cold [s] | warm [s] | compilation (cold - warm) [s] |",
         "| --- | ---: | ---: | ---: |"]
    for r in res.values():
        L.append(f"| `{r['command']}` | {r['cold_s']:.1f} | {r['warm_s']:.1f} | "
                 f"{r['cold_s'] - r['warm_s']:.1f} |")
    L += ["",
          f"- cold `classify` on the default grid: {cold:.1f} s against the target of "
          f"{TARGET_COLD_S:.0f} s: " + ("met" if cold <= TARGET_COLD_S else "**not met**"),
          f"- `vibimpact --help` with an empty cache: {help_s:.2f} s, {help_files} files "
          "written to the cache (" + ("nothing compiled" if help_files == 0
                                      else "**it compiles**") + ")"]
    return "\n".join(L)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=1,
                    help="cold/warm pairs per command (the smallest times are shown)")
    ap.add_argument("--no-report", action="store_true",
                    help="print the times only; leave reports/performance.md as it is")
    ap.add_argument("commands", nargs="*", metavar="COMMAND",
                    help=f"commands to time, of {', '.join(COMMANDS)} (default: all)")
    args = ap.parse_args(argv)
    unknown = [c for c in args.commands if c not in COMMANDS]
    if unknown:
        ap.error(f"unknown command(s) {', '.join(unknown)}; known: {', '.join(COMMANDS)}")
    res = measure(args.commands or None, repeat=args.repeat)
    for name, r in res.items():
        print(f"{name:9s} cold {r['cold_s']:6.1f} s   warm {r['warm_s']:5.1f} s   "
              f"({r['command']})")
    if not args.no_report:
        if set(res) != set(COMMANDS):
            ap.error("the report needs every command; use --no-report with a subset")
        help_s, help_files = _help_compiles()
        write_section(REPORT, SECTION, report(res, help_s, help_files, args.repeat))
        print(f"wrote section {SECTION} of {REPORT.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
