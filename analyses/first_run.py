"""Wall time of a first (cold) and a repeated (warm) run of the command line.

A *cold* run starts with an empty numba cache: ``NUMBA_CACHE_DIR`` points at a fresh
temporary directory, so every kernel function the command needs is compiled (the
package's own ``__pycache__`` is not used when ``NUMBA_CACHE_DIR`` is set, see
``vibimpact/_kernel/cache_guard.py``).  The *warm* run repeats the command with the cache
the cold run wrote: nothing is compiled.  Each run is a fresh ``python -m vibimpact``
subprocess, timed from its start to its exit (interpreter start-up and imports included).

Run as ``python analyses/first_run.py [--repeat N]``; :func:`measure` returns the times
as a dict for reports.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

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


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=1,
                    help="cold/warm pairs per command (the smallest times are shown)")
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
    return 0


if __name__ == "__main__":
    sys.exit(main())
