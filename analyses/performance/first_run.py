"""Wall time of the first run of the command line, on an empty and on a filled numba cache.

Every measurement gets a new, empty ``NUMBA_CACHE_DIR`` (the package's own
``__pycache__`` is not used when it is set, see ``vibimpact/_kernel/cache_guard.py``):

* *empty cache*: what an install that did not fill numba's cache gets (a regular wheel,
  an install into an empty environment, kernel sources edited or numba changed since the
  install): the first run compiles every kernel function the command uses and caches it;
  the *warm* run repeats the command on the cache that first run wrote;
* *filled cache*: ``python -m vibimpact._kernel.aot_build`` first fills the new directory
  as ``pip install -e .`` does (``setup.py`` runs that module); its time is the install
  step's.  The first run then loads the kernel from the cache.

Each run is a fresh ``python -m vibimpact`` subprocess, timed from its start to its exit
(interpreter start-up and imports included); the numba cache files a run wrote or
rewrote are counted (0: it compiled nothing).

Run as ``python analyses/performance/first_run.py [--repeat N] [--no-report]``: it prints the
times and replaces the section ``first_run`` of ``reports/performance.md`` (where a first
run on the filled cache is judged against its target: at most 10 s); :func:`measure`
returns the times as a dict.
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
#: the acceptance target of a first run (seconds, this 2-core machine; issue 29 point 6)
TARGET_FIRST_S = 10.0

#: the commands timed: name -> arguments after ``vibimpact`` ({out}: a file in the
#: temporary directory)
COMMANDS = {
    "classify": ["classify", "--eta", "0.9:1.5:0.002", "-o", "{out}.nc", "--no-progress"],
    "simulate": ["simulate", "--preset", "fig8", "--eta", "1.2", "-o", "{out}.nc"],
}

#: the fill of numba's cache that ``setup.py`` runs at install (``vibimpact/_kernel/aot_build.py``)
FILL = ["-m", "vibimpact._kernel.aot_build"]

#: a smoke run (``--smoke``): every run keeps the environment's own numba cache (filled
#: at install or warm), so that nothing is compiled; its numbers mean nothing
SMOKE = False


def _cache_files(cache_dir, since=None):
    """numba cache files (``*.nbi``, ``*.nbc``) under ``cache_dir`` (written or rewritten
    at or after ``since``, a ``time.time()``, when given): what was compiled."""
    return sum(f.endswith((".nbi", ".nbc")) and (
        since is None or os.path.getmtime(os.path.join(d, f)) >= since)
        for d, _, fs in os.walk(cache_dir) for f in fs)


def _env(cache_dir):
    """The environment of a run: ``NUMBA_CACHE_DIR=cache_dir`` (in a smoke run, the
    environment's own cache)."""
    return dict(os.environ) if SMOKE else dict(os.environ, NUMBA_CACHE_DIR=cache_dir)


def _python(args, cache_dir, said=None):
    """``(seconds, stdout)`` of ``python ARGS`` with the numba cache ``cache_dir``; with a
    list ``said``, the seconds from the start to each line on stderr are appended to it
    as ``(seconds, line)``."""
    import threading

    cmd = [sys.executable, *args]
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, env=_env(cache_dir), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    err = []

    def read_stderr():
        for line in proc.stderr:
            err.append((time.perf_counter() - t0, line))

    reader = threading.Thread(target=read_stderr)
    reader.start()
    stdout = proc.stdout.read()
    proc.wait()
    wall = time.perf_counter() - t0
    reader.join()
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({proc.returncode}):\n"
                           + "".join(line for _, line in err))
    if said is not None:
        said.extend(err)
    return wall, stdout


#: the start of the line a run prints before numba compiles the kernel
COMPILE_LINE = "vibimpact: compiling the kernel for first use"
#: the acceptance target of that line's time from the start (seconds; issue 43)
TARGET_LINE_S = 1.0


def _run(args, cache_dir, out):
    """``(seconds, cache files written, seconds to the compile line or None)`` of
    ``vibimpact ARGS`` with the numba cache ``cache_dir``."""
    start, said = time.time(), []
    wall, _ = _python(["-m", "vibimpact"] + [a.format(out=out) for a in args], cache_dir,
                      said)
    line = next((t for t, text in said if text.startswith(COMPILE_LINE)), None)
    return wall, _cache_files(cache_dir, since=start), line


def _fill(cache_dir):
    """``(seconds, cache files, status)``: the install's fill of ``cache_dir`` and what
    the package then says of its kernel (:func:`vibimpact._kernel.cache_stamp.status`)."""
    wall, _ = _python(FILL, cache_dir)
    code = "from vibimpact._kernel import cache_stamp; print(cache_stamp.status())"
    _, status = _python(["-c", code], cache_dir)
    status = status.strip()
    if not SMOKE and not status.startswith("in use"):
        raise RuntimeError(f"the filled cache {cache_dir} is not in use: {status}")
    return wall, _cache_files(cache_dir), status


def _fresh_cache(tmp):
    cache = os.path.join(tmp, "numba-cache")
    os.mkdir(cache)
    return cache


def measure(commands=None, repeat=1):
    """First-run wall times (seconds) of each command on an empty and on a filled cache.

    Parameters
    ----------
    commands : sequence of str, optional
        Names in :data:`COMMANDS` (all by default).
    repeat : int
        Measurements of each kind per command, each with its own new cache directory;
        the smallest time of each kind is reported (the machine's other load only ever
        adds).

    Returns
    -------
    dict
        ``{"commands": {name: {"command", "empty_s", "empty_files", "warm_s",
        "filled_s", "filled_files", "line_s", "line_elsewhere"}}, "fill_s",
        "fill_files", "status"}``: the first run on an empty cache, the cache files it
        wrote and the seconds from its start to its compile line (:data:`COMPILE_LINE`;
        None where one of its runs did not print it), the run after it (warm), the first
        run on a filled cache and the cache files it wrote, whether a warm or filled run
        printed the compile line; the fill's seconds
        (the smallest of its runs, one per filled measurement), the cache files it
        wrote and what the package said of the filled cache.
    """
    out, fills = {}, []
    fill_files, status = 0, ""
    for name in commands or COMMANDS:
        args = COMMANDS[name]
        empty, warm, empty_files, filled, filled_files = [], [], [], [], []
        line, warm_line, filled_line = [], [], []
        for _ in range(repeat):
            with tempfile.TemporaryDirectory(prefix="vibimpact-first-run-") as tmp:
                cache = _fresh_cache(tmp)
                seconds, files, said = _run(args, cache, os.path.join(tmp, "empty"))
                empty.append(seconds)
                empty_files.append(files)
                line.append(said)
                seconds, _, said = _run(args, cache, os.path.join(tmp, "warm"))
                warm.append(seconds)
                warm_line.append(said)
            with tempfile.TemporaryDirectory(prefix="vibimpact-first-run-") as tmp:
                cache = _fresh_cache(tmp)
                seconds, fill_files, status = _fill(cache)
                fills.append(seconds)
                seconds, files, said = _run(args, cache, os.path.join(tmp, "filled"))
                filled.append(seconds)
                filled_files.append(files)
                filled_line.append(said)
        out[name] = {"command": "vibimpact " + " ".join(a.replace("{out}", "OUT")
                                                        for a in args),
                     "empty_s": min(empty), "empty_files": max(empty_files),
                     "warm_s": min(warm), "filled_s": min(filled),
                     "filled_files": max(filled_files),
                     # the compile line: its time on the empty cache (None where a run
                     # did not print it), and whether a warm or filled run printed it
                     "line_s": None if None in line else min(line),
                     "line_elsewhere": any(t is not None for t in warm_line + filled_line)}
    return {"commands": out, "fill_s": min(fills), "fill_files": fill_files,
            "status": status}


def _help_compiles():
    """Seconds and files ``vibimpact --help`` writes into an empty numba cache (0:
    nothing compiled)."""
    with tempfile.TemporaryDirectory(prefix="vibimpact-first-run-") as tmp:
        cache = _fresh_cache(tmp)
        start = time.time()
        wall, _ = _python(["-m", "vibimpact", "--help"], cache)
        return wall, _cache_files(cache, since=start)


def _cpu():
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _verdict(seconds):
    return "met" if seconds <= TARGET_FIRST_S else "**not met**"


def report(res, help_s, help_files, repeat):
    """The section text for ``reports/performance.md``."""
    import numba

    now = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    rows = res["commands"]
    L = ["## First run (empty and filled numba cache)", "",
         f"Written by `python analyses/performance/first_run.py` on {now}; {os.cpu_count()} CPUs "
         f"({_cpu()}), Python {platform.python_version()}, numba {numba.__version__}, "
         f"load average {os.getloadavg()[0]:.2f} at the end.  Each command runs as a fresh "
         "`python -m vibimpact` process, timed from start to exit (interpreter start-up, "
         "imports and writing the file included), and every measurement has a new "
         "`NUMBA_CACHE_DIR` of its own.  *Empty cache*: what an install that did not fill "
         "numba's cache gets (a regular wheel, an install into an empty environment, "
         "kernel sources edited or numba changed since): the first run compiles every "
         "kernel function it uses; *warm*: the same command again on the cache that run "
         "wrote.  *Filled cache*: `python -m vibimpact._kernel.aot_build` first fills the "
         "new directory as `pip install -e .` does (`setup.py`), then the command runs.  "
         f"Best of {repeat}.", "",
         f"The fill (the install step) took {res['fill_s']:.1f} s and wrote "
         f"{res['fill_files']} cache files; the package then said of its kernel: "
         f"*{res['status']}*.", "",
         "| command | empty cache: first run [s] | empty cache: compile line after [s] "
         "| empty cache: cache files written "
         "| empty cache: warm [s] | filled cache: first run [s] "
         "| filled cache: cache files written |",
         "| --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for r in rows.values():
        said = "none" if r["line_s"] is None else f"{r['line_s']:.2f}"
        L.append(f"| `{r['command']}` | {r['empty_s']:.1f} | {said} | {r['empty_files']} | "
                 f"{r['warm_s']:.1f} | {r['filled_s']:.1f} | {r['filled_files']} |")
    L.append("")
    for name, r in rows.items():
        said = ("not printed" if r["line_s"] is None else f"{r['line_s']:.2f} s against "
                f"the target of {TARGET_LINE_S:.0f} s: "
                + ("met" if r["line_s"] <= TARGET_LINE_S else "**not met**"))
        L.append(f"- `{name}`'s compile line on an empty cache (seconds from the "
                 f"process's start to the line on stderr): {said}; printed by a warm or "
                 f"filled-cache run: {'**yes**' if r['line_elsewhere'] else 'no'}")
    for name, r in rows.items():
        L.append(f"- first `{name}` on the filled cache: {r['filled_s']:.1f} s against the "
                 f"target of {TARGET_FIRST_S:.0f} s: {_verdict(r['filled_s'])}; on an empty "
                 f"cache: {r['empty_s']:.1f} s: {_verdict(r['empty_s'])}")
    L.append(f"- `vibimpact --help` with an empty cache: {help_s:.2f} s, {help_files} files "
             "written to the cache (" + ("nothing compiled" if help_files == 0
                                         else "**it compiles**") + ")")
    return "\n".join(L)


def main(argv=None):
    global REPORT
    ap = smoke.parser(__doc__)
    ap.add_argument("--repeat", type=int, default=1,
                    help="measurements of each kind per command (the smallest times are "
                         "shown)")
    ap.add_argument("--no-report", action="store_true",
                    help="print the times only; leave reports/performance.md as it is")
    ap.add_argument("commands", nargs="*", metavar="COMMAND",
                    help=f"commands to time, of {', '.join(COMMANDS)} (default: all)")
    args = ap.parse_args(argv)
    if args.repeat < 1:
        ap.error(f"--repeat must be at least 1, got {args.repeat}")
    REPORT = smoke.moved(REPORT, args.smoke)
    smoke.shrink(globals(), args.smoke, SMOKE=True, COMMANDS={
        "classify": ["classify", "--eta", "1.2:1.21:0.01", "-o", "{out}.nc", "--no-progress"],
        "simulate": COMMANDS["simulate"]})
    unknown = [c for c in args.commands if c not in COMMANDS]
    if unknown:
        ap.error(f"unknown command(s) {', '.join(unknown)}; known: {', '.join(COMMANDS)}")
    res = measure(args.commands or None, repeat=args.repeat)
    print(f"fill (install step) {res['fill_s']:.1f} s: {res['status']}")
    for name, r in res["commands"].items():
        print(f"{name:9s} empty cache: first {r['empty_s']:6.1f} s ({r['empty_files']} files)"
              f"  warm {r['warm_s']:5.1f} s   filled cache: first {r['filled_s']:5.1f} s "
              f"({r['filled_files']} files)   ({r['command']})")
    if not args.no_report:
        if set(res["commands"]) != set(COMMANDS):
            ap.error("the report needs every command; use --no-report with a subset")
        help_s, help_files = _help_compiles()
        write_section(REPORT, SECTION, report(res, help_s, help_files, args.repeat))
        print(f"wrote section {SECTION} of {REPORT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
