"""Cases of :mod:`reliability` for signals that arrive where a command cannot act on them
at once (issue 32, part 1: SIGINT at 10 % of ``map`` printed a traceback and exited 0;
of ``rerun``, hung):

* **signal at start-up** -- SIGINT or SIGTERM at each of :data:`MOMENTS` after ``map``,
  ``rerun`` or ``classify`` starts (imports, numba's compiler, the Dask cluster or the
  process pool starting): exit 128 + signum, one line, nothing but the checkpoint left;
  an exit 0 means the signal was lost;
* **signal lost where Python cannot raise it** -- the command line run in-process with
  its preset lookup sending the signal from inside a ``ctypes`` callback (where numba's
  compiler lost it) or a library's bare ``except:``, for every checkpointed and
  plain command: exit 128 + signum, no "Exception ignored", no output;
* **signal during the command line's import** -- ``python -m vibimpact`` signalled while
  it imports its command line or builds its option parser: exit 128 + signum and the one
  line "vibimpact: interrupted";
* **signal the command was started ignoring** -- ``classify`` and ``map`` started with
  SIGINT or SIGTERM ignored (a shell script's background job ignores SIGINT), sent that
  signal at start-up and later: they run through it (exit 0, the output written,
  nothing said); with only SIGINT ignored, SIGTERM still ends them (exit 143).
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

SIGNALS = (signal.SIGINT, signal.SIGTERM)
#: seconds after the start
MOMENTS = (0.1, 0.25, 0.5, 1.0)
#: commands that run for seconds after these moments (see reliability.COMMANDS)
STARTED = ("map", "rerun", "classify")

#: in-process command lines (small requests) -> whether they keep a checkpoint
IN_PROCESS = {
    "simulate": (["simulate", "--eta", "1.2", "--periods", "20", "-o", "s.nc"], False),
    "classify": (["classify", "--eta", "1.0:1.03:0.01", "--no-progress", "-o", "c.nc"],
                 True),
    "bifurcation": (["bifurcation", "--eta", "1.0:1.03:0.01", "--no-progress", "-o",
                     "b.png"], False),
    "map": (["map", "--eta", "1.0:1.02:0.01", "--vary", "kh=50,60", "--no-progress", "-o",
             "m.zarr"], True),
    "continue": (["continue", "--eta", "1.12", "--stop", "1.13", "-o", "br.nc"], False),
    "rerun": (["rerun", "c.nc"], False),
}

#: the preset lookup loses the signal (WAY: "ctypes" or "except"); prints the status and
#: any file left beside the checkpoint and the rerun's input
LOST = '''
import ctypes, os, signal, sys, time
from vibimpact import presets
from vibimpact.cli import main
SIG, WAY, ARGV = signal.SIGNAME, "WAYNAME", ARGS


def wait():
    t = time.monotonic() + 5
    while time.monotonic() < t:
        pass


def lose():
    if WAY == "ctypes":
        def callback():
            os.kill(os.getpid(), SIG)
            wait()
        ctypes.CFUNCTYPE(None)(callback)()
    else:
        try:
            os.kill(os.getpid(), SIG)
            wait()
        except BaseException:
            pass


if ARGV[0] == "rerun":
    assert main(["classify", "--eta", "1.0:1.03:0.01", "--no-progress", "-o", "c.nc"]) == 0
before = set(os.listdir("."))
found = presets.get


def get(*a, **kw):
    lose()
    return found(*a, **kw)


presets.get = get
rc = main(ARGV)
left = sorted(n for n in set(os.listdir(".")) - before if not n.endswith(".partial"))
print(f"exit {rc}" + (f", wrote {left}" if left else ""))
'''

#: ``python -m vibimpact`` signalled while it imports its command line or builds its
#: parser (WHEN)
EARLY = '''
import builtins, os, runpy, signal, sys, time
SIG, WHEN = signal.SIGNAME, "WHENNAME"
sys.argv = ["vibimpact", "simulate", "--eta", "1.2", "--periods", "5", "-o", "s.nc"]


def wait():
    t = time.monotonic() + 5
    while time.monotonic() < t:
        pass


real = builtins.__import__


def imports(name, *a, **kw):
    if WHEN == "import" and name == "vibimpact.cli":
        os.kill(os.getpid(), SIG)
        wait()
    return real(name, *a, **kw)


builtins.__import__ = imports
if WHEN == "parse":
    import vibimpact.cli as cli
    built = cli.build_parser

    def build_parser():
        os.kill(os.getpid(), SIG)
        wait()
        return built()

    cli.build_parser = build_parser
runpy.run_module("vibimpact", run_name="__main__")
'''


def _python(kit, base, tag, code, timeout):
    """``(directory, rc or None, stdout, stderr, seconds)`` of ``code`` in a fresh
    directory."""
    d = kit._fresh(base, tag)
    t0 = time.perf_counter()
    try:
        proc = subprocess.run([sys.executable, "-c", code], cwd=d, env=kit._env(),
                              capture_output=True, text=True, timeout=timeout)
        rc, out, err = proc.returncode, proc.stdout, proc.stderr
    except subprocess.TimeoutExpired:
        rc, out, err = None, "", ""
    return d, rc, out, err, time.perf_counter() - t0


def startup_cases(kit, base, timeout):
    out, source = [], None
    for name in STARTED:
        argv, output, _ = kit.COMMANDS[name]
        for sig in SIGNALS:
            for at in MOMENTS:
                d = kit._fresh(base, f"early-{name}")
                keep = ()
                if name == "rerun":
                    if source is None:  # the file rerun reads: one classify, kept
                        source = kit._fresh(base, "early-source")
                        rc, _, err, _ = kit.run(kit.CLASSIFY, source, timeout)
                        if rc != 0:
                            raise RuntimeError(f"classify for rerun failed ({rc}): {err}")
                    subprocess.run(["cp", str(source / "c.nc"), str(d / "c.nc")],
                                   check=True)
                    keep = ("c.nc",)
                rc, _, err, sec = kit.run(argv, d, timeout,
                                          lambda p, s=sig: p.send_signal(s), at)
                name_sig = signal.Signals(sig).name
                o = kit.judge("signal at start-up", f"{name}, {name_sig} at {at:g} s", rc,
                              err, sec, {128 + sig}, d, keep=keep)
                if output is not None:
                    o.clean = o.clean and not (d / output).exists()
                out.append(o)
    return out


def lost_cases(kit, base, timeout):
    out = []
    ways = [(signal.SIGINT, "ctypes"), (signal.SIGINT, "except"),
            (signal.SIGTERM, "ctypes")]
    for name, (argv, _) in IN_PROCESS.items():
        for sig, way in ways:
            name_sig = signal.Signals(sig).name
            code = (LOST.replace("SIGNAME", name_sig).replace("WAYNAME", way)
                    .replace("ARGS", repr(argv)))
            d, rc, stdout, err, sec = _python(kit, base, "lost", code, timeout)
            where = "a ctypes callback" if way == "ctypes" else "a bare except"
            o = kit.judge("signal lost where Python cannot raise it",
                          f"{name}, {name_sig} in {where}", rc, err, sec, {0}, d,
                          keep=("c.nc",) if name == "rerun" else ())
            said = (stdout.strip().splitlines() or [""])[-1]
            o.clean = o.clean and said == f"exit {128 + sig}"
            o.message = f"{said}; {o.message}"[:160]
            out.append(o)
    return out


def import_cases(kit, base, timeout):
    out = []
    for sig in SIGNALS:
        for when in ("import", "parse"):
            name_sig = signal.Signals(sig).name
            code = EARLY.replace("SIGNAME", name_sig).replace("WHENNAME", when)
            d, rc, _, err, sec = _python(kit, base, "import", code, timeout)
            what = "imports its command line" if when == "import" else "builds its parser"
            o = kit.judge("signal during the command line's import",
                          f"{name_sig} while it {what}", rc, err, sec, {128 + sig}, d)
            o.clean = o.clean and err == "vibimpact: interrupted\n" and not os.listdir(d)
            out.append(o)
    return out


#: commands started with a signal ignored, and the moments (s) it is sent
IGNORING = ("classify", "map")
IGNORED_AT = (0.25, 1.0)


def ignored_cases(kit, base, timeout):
    out = []
    klass = "signal the command was started ignoring"
    for name in IGNORING:
        argv, output, _ = kit.COMMANDS[name]
        runs = [((sig,), sig, at) for sig in SIGNALS for at in IGNORED_AT]
        runs.append(((signal.SIGINT,), signal.SIGTERM, IGNORED_AT[-1]))
        for ignoring, sent, at in runs:
            d = kit._fresh(base, f"ignoring-{name}")
            rc, _, err, sec = kit.run(argv, d, timeout,
                                      lambda p, s=sent: p.send_signal(s), at,
                                      ignoring=ignoring)
            through = sent in ignoring
            said = "+".join(signal.Signals(s).name for s in ignoring)
            o = kit.judge(klass, f"{name}, {said} ignored, "
                          f"{signal.Signals(sent).name} at {at:g} s", rc, err, sec,
                          {0} if through else {128 + sent}, d)
            if through:
                o.clean = o.clean and not err.strip() and (d / output).exists()
            else:
                o.clean = o.clean and not (d / output).exists()
            out.append(o)
    return out


#: class -> the function that runs its cases
CLASSES = {"signal at start-up": startup_cases,
           "signal lost where Python cannot raise it": lost_cases,
           "signal during the command line's import": import_cases,
           "signal the command was started ignoring": ignored_cases}


def shrink():
    """A smoke run: one moment, one command and one way each."""
    global MOMENTS, STARTED, IGNORING, IGNORED_AT
    MOMENTS, STARTED = MOMENTS[2:3], STARTED[:1]
    IGNORING, IGNORED_AT = IGNORING[:1], IGNORED_AT[-1:]
    for key in list(IN_PROCESS)[1:]:
        del IN_PROCESS[key]
