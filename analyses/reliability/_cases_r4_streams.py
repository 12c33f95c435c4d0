"""Cases of :mod:`reliability` from the fourth adversarial round (issue 44): output
streams that cannot be written (class 1) and reruns of crafted files (class 5).

* **unusable output stream** -- a command whose stdout is ``/dev/full`` (ENOSPC),
  closed (``>&-``) or a pipe whose reader has gone (EPIPE), or whose stderr is full or
  closed.  Clean: no traceback (nor Python's "Exception ignored" at exit), the status
  the user guide's errors page states (74 when printed output was lost, with one line
  when stderr works; 141 for the closed pipe, silently; 2 for bad input whichever
  stream fails; 0 when the failing stream was never written), and the command's file
  written.  :func:`reliability.run` gives its command pipes, so these cases start theirs
  with :func:`_run_with`.
* **rerun of a crafted file** -- ``vibimpact rerun`` of a small real sweep file whose
  ``command`` attribute was replaced by a large job (100,000 points both ways, a
  300 x 300 map, 10,000,000 forcing periods, a 100,000-point bifurcation, a 100,000-point
  branch, 4096 workers).  Clean: one line, exit 2, within seconds (nothing computed) and
  no file left; with ``--yes`` the guard lets it start (then sent SIGTERM a few seconds in: 143).
"""
from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time

#: command -> argv (run in a directory holding ``run.nc``, a small simulate file)
STREAM_COMMANDS = {
    "presets": ["presets"],
    "--help": ["--help"],
    "--version": ["--version"],
    "simulate": ["simulate", "--eta", "1.0", "--periods", "3", "--transient", "3",
                 "-o", "out.nc"],
    "classify": ["classify", "--eta", "1.0:1.01:0.01", "--workers", "1", "--analyses",
                 "period", "-o", "out.nc"],
    "attractors": ["attractors", "--preset", "fig11", "--eta", "1.06", "--starts", "3",
                   "--workers", "1", "-o", "out.nc"],
    "basins": ["basins", "--preset", "fig11", "--eta", "1.06", "--grid", "10x10",
               "--workers", "1", "-o", "out.nc"],
    "orbits": ["orbits", "--preset", "fig11", "--eta", "1.06", "--period", "1",
               "--random", "2", "--no-continue", "--workers", "1", "-o", "out.nc"],
    "plot": ["plot", "run.nc", "-o", "out.png"],
    "rerun": ["rerun", "run.nc"],
    "usage error": ["simulate", "--eta", "-1", "-o", "out.nc"],
}
#: fault -> (shell redirection or "pipe", stream written)
FAULTS = {
    "stdout on /dev/full": (">/dev/full", "stdout"),
    "stdout closed": (">&-", "stdout"),
    "stdout a pipe without reader": ("pipe", "stdout"),
    "stderr on /dev/full": ("2>/dev/full", "stderr"),
    "stderr closed": ("2>&-", "stderr"),
}
#: the faults every other command meets
LIGHT_FAULTS = tuple(FAULTS)
#: commands that write to stderr without -v (progress bars; rerun's announcement)
WRITES_STDERR = ("classify", "attractors", "basins", "rerun")
#: the longer commands meet these faults only (the class stays within two minutes)
HEAVY = {"classify": ("stdout on /dev/full", "stdout a pipe without reader",
                     "stderr on /dev/full"),
         "attractors": ("stdout on /dev/full", "stderr on /dev/full"),
         "basins": ("stdout closed", "stdout a pipe without reader"),
         "orbits": ("stdout on /dev/full", "stdout a pipe without reader")}

#: crafted recorded command -> its name
CRAFTED = {
    "classify 100,000 points both directions":
        "vibimpact classify --eta 0.50001:1.5:0.00001 --direction both -o c.nc",
    "map 300 x 300": "vibimpact map --eta 1.001:1.3:0.001 --vary kh=1:300:1 -o m.zarr",
    "simulate 10,000,000 periods": "vibimpact simulate --periods 9999500 -o s.nc",
    "bifurcation 100,000 points":
        "vibimpact bifurcation --eta 0.50001:1.5:0.00001 --direction up -o b.png",
    "continue 100,000 branch points": "vibimpact continue --stop 1.2 --max-points 100000 "
                                      "-o p.nc",
    "simulate 13,000,000 dense samples": "vibimpact simulate --periods 200000 -o s.nc "
                                         "--plot s.png",
    "classify 4096 workers": "vibimpact classify --eta 1.0:1.01:0.01 --workers 4096 "
                             "-o c.nc",
}
#: the crafted kinds also run with --yes (started, then SIGTERM)
WITH_YES = ("classify 100,000 points both directions", "simulate 10,000,000 periods")


def _run_with(kit, argv, cwd, timeout, redirect):
    """``python -m vibimpact argv`` in ``cwd`` with ``redirect`` (a shell redirection,
    or "pipe": stdout a pipe whose read end is closed) -> (rc or None, stdout, stderr,
    seconds); what is not redirected is captured."""
    cmd = [sys.executable, "-m", "vibimpact", *argv]
    t0 = time.perf_counter()
    rd = wr = None
    if redirect == "pipe":
        rd, wr = os.pipe()
        os.close(rd)
        stdout = wr
    else:
        cmd = ["bash", "-c", f'exec "$@" {redirect}', "sh", *cmd]
        stdout = subprocess.PIPE
    try:
        proc = subprocess.run(cmd, cwd=cwd, env=kit._env(), stdout=stdout,
                              stderr=subprocess.PIPE, text=True, timeout=timeout)
        rc, out, err = proc.returncode, proc.stdout or "", proc.stderr
    except subprocess.TimeoutExpired:
        rc, out, err = None, "", ""
    finally:
        if wr is not None:
            os.close(wr)
    return rc, out, err, time.perf_counter() - t0


def _source(kit, base, timeout):
    """A directory with ``run.nc`` (a small simulate file) and ``c.nc`` (a small
    classify file) to copy from."""
    d = kit._fresh(base, "streams-source")
    for argv in (["simulate", "--eta", "1.0", "--periods", "3", "--transient", "3", "-o",
                  "run.nc"],
                 ["classify", "--eta", "1.0:1.01:0.01", "--workers", "1", "--analyses",
                  "period", "--no-progress", "-o", "c.nc"]):
        rc, _, err, _ = kit.run(argv, d, timeout)
        if rc != 0:
            raise RuntimeError(f"{argv[0]} for the stream cases failed ({rc}): {err}")
    return d


def _expected(name, fault):
    """The exit status the errors page states for ``name`` under ``fault``."""
    redirect, stream = FAULTS[fault]
    if name == "usage error":
        return 2
    if stream == "stderr" and name not in WRITES_STDERR:
        return 0
    return 141 if redirect == "pipe" else 74


def stream_cases(kit, base, timeout):
    out, source = [], _source(kit, base, timeout)
    for name, argv in STREAM_COMMANDS.items():
        for fault in HEAVY.get(name, LIGHT_FAULTS):
            redirect, stream = FAULTS[fault]
            d = kit._fresh(base, "stream")
            shutil.copy(source / "run.nc", d / "run.nc")
            rc, stdout, err, sec = _run_with(kit, argv, d, timeout, redirect)
            expect = _expected(name, fault)
            o = kit.judge("unusable output stream", f"{name}, {fault}", rc, err, sec,
                          {expect}, d, keep=("run.nc", "out.nc", "out.png"))
            errors = [ln for ln in err.splitlines() if ln.startswith("vibimpact: error:")]
            if expect == 74 and stream == "stdout":  # the one line (beside progress bars)
                o.clean = (o.clean and len(errors) == 1
                           and "cannot write to stdout" in errors[0])
            if expect == 141:  # nothing said about the pipe
                o.clean = o.clean and not errors
            if expect == 2:  # a closed stderr must not send the error line to stdout
                o.clean = o.clean and stdout == ""
            wants = "out.png" if name == "plot" else "out.nc" if "-o" in argv else None
            if wants and expect != 2:
                o.clean = o.clean and (d / wants).exists()
                if not (d / wants).exists():
                    o.message = f"{wants} not written; {o.message}"[:160]
            out.append(o)
    return out


def _crafted_file(source, d, command):
    """``d/in.nc``: the small classify file with ``command`` as its recorded command."""
    import netCDF4

    shutil.copy(source / "c.nc", d / "in.nc")
    with netCDF4.Dataset(d / "in.nc", "a") as ds:
        ds.setncattr("command", command)


def crafted_cases(kit, base, timeout):
    out, source = [], _source(kit, base, timeout)
    klass = "rerun of a crafted file"
    for kind, command in CRAFTED.items():
        d = kit._fresh(base, "crafted")
        _crafted_file(source, d, command)
        rc, _, err, sec = kit.run(["rerun", "in.nc"], d, min(timeout, 60))
        o = kit.judge(klass, f"{kind}, without --yes", rc, err, sec, {2}, d,
                      keep=("in.nc",))
        lines = err.strip().splitlines()
        o.clean = (o.clean and len(lines) == 1 and "--yes" in lines[0]
                   and sorted(os.listdir(d)) == ["in.nc"] and sec < 30)
        out.append(o)
    for kind in WITH_YES:
        d = kit._fresh(base, "crafted-yes")
        _crafted_file(source, d, CRAFTED[kind])
        rc, _, err, sec = kit.run(["rerun", "in.nc", "--yes"], d, timeout,
                                  lambda p: p.send_signal(signal.SIGTERM), 3.0)
        o = kit.judge(klass, f"{kind}, --yes, SIGTERM after 3 s", rc, err, sec, {143}, d,
                      keep=("in.nc",))
        o.clean = o.clean and err.startswith("vibimpact: rerunning ")
        out.append(o)
    return out


#: class -> the function that runs its cases: ``func(kit, base, timeout)`` -> Outcomes
CLASSES = {"unusable output stream": stream_cases, "rerun of a crafted file": crafted_cases}


def shrink():
    """A smoke run: two commands, two faults, two crafted kinds, no --yes run."""
    global LIGHT_FAULTS, WITH_YES
    for table, keep in ((STREAM_COMMANDS, 2), (CRAFTED, 2)):
        for key in list(table)[keep:]:
            del table[key]
    LIGHT_FAULTS, WITH_YES = LIGHT_FAULTS[:2], ()
