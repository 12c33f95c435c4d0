"""Fault injection against the command line: what a fault does to every command.

Run as ``python analyses/reliability/reliability.py [--quick] [--no-report]`` (the report's
header says how long the run took; ``--quick`` runs one moment per fault).  Every case runs ``python -m vibimpact``
in a fresh directory as a subprocess of its own session, injects one fault and judges
what it left:

* **killed worker** -- ``SIGKILL`` to a worker process of ``classify``/``bifurcation``
  (a local process pool) or ``map`` (a Dask worker) at several moments of the run;
* **SIGTERM / SIGINT** -- to the command itself at several moments (computing, writing),
  for every command that writes (``simulate``, ``classify``, ``bifurcation``, ``map``,
  ``continue``, ``rerun``);
* **disk full** -- the output (and checkpoint) on a 64 KiB ``tmpfs`` (needs root to mount
  it; the cases are reported as not tried otherwise) and the output ``/dev/full``;
* **vanished checkpoint** -- the checkpoint directory removed while the command runs;
* **foreign checkpoint entry** -- a point file of another preset's sweep copied into an
  interrupted checkpoint before ``--resume``;
* **limits and paths** -- requests and output names that cannot work (checked before any
  computing);
* **continuation at a bound** -- ``continue`` from a parameter that is 0 in the presets
  (BT, f, Bh, Rr) and down to B = 0: must run and write its branch;
* **command-line wording** -- refusals (an existing output, ``--resume`` with nothing to
  resume) must name the command line's options, never the API's keywords;
* **user model sizes** -- user models that declare fewer state entries, parameters or
  modes than their functions use, an ``omega_index`` outside the parameters, a plain
  Python function, a complex state (one Python process each, through ``simulate``,
  ``lyapunov_spectrum`` and ``sweep``): refused before the kernel runs them;
* the classes of the third adversarial round (stopped processes, signals during large
  writes, writes killed, the resource tracker killed, damaged map stores, raw parameter
  vectors, array coercion, numerical edges, tampered files, options refused up front,
  plots of bad files): see ``_cases_round3.py``;
* signals at start-up, signals lost where Python cannot raise them, and signals during
  the command line's import: see ``_cases_signals.py``;
* the classes of the fourth adversarial round: output streams that cannot be written and
  reruns of crafted files (``_cases_r4_streams.py``); FIFOs, deep JSON, symlinks and
  resumes in checkpoints (``_cases_r4_checkpoints.py``); checks before work, outputs
  named twice, refusals of ``continue2`` and ``plot`` (``_cases_r4_inputs.py``); crafted
  and oversized input files, ``map --overwrite`` (``_cases_r4_files.py``); failed
  integrations in censuses and API arguments (``_cases_r4_results.py``).

``--only CLASS`` (repeatable) runs the cases of those classes alone and prints their
table without writing the report.

Verdicts per case: *hang* (still running at its time limit: the process group is
killed), *traceback* (``Traceback`` or ``Exception ignored`` on stderr), *clean* (no
hang, no traceback, the expected exit status, at most one ``vibimpact: error:`` line and
no Python warning), *files left* (temporary or partial files beside the output, the
checkpoint directory excepted), *data lost* (after an interruption of a checkpointed
command -- ``classify``, ``map`` -- ``--resume`` does not give a file identical to the
uninterrupted one, or a run that survived its fault wrote a different file; the other
commands keep no checkpoint: they are judged on the rest).  Writes the section
``reliability`` of ``reports/reliability.md``.
"""
from __future__ import annotations

import datetime
import os
import platform
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import _cases_r4_checkpoints
import _cases_r4_files
import _cases_r4_inputs
import _cases_r4_results
import _cases_r4_streams
import _cases_round3
import _cases_signals
from _reliability_cases import (API_WORDS, BAD, BOUNDS, RUNS, USER_MODEL,
                               USER_MODEL_CASES, WORDING)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # analyses/: _common
from _common import smoke  # noqa: E402
from _common.report import write_section  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
REPORT = ROOT / "reports" / "reliability.md"
SECTION = "reliability"

#: the requests the faults are injected into (long enough to be interrupted; small
#: enough that a case takes seconds)
CLASSIFY = ["classify", "--eta", "0.9:1.5:0.001", "--direction", "both", "--workers", "2",
            "--no-progress", "-o", "c.nc"]
BIFURCATION = ["bifurcation", "--eta", "0.9:1.5:0.001", "--workers", "2", "--no-progress",
               "-o", "b.png"]
MAP = ["map", "--eta", "1.0:1.3:0.005", "--vary", "kh=50:80:10", "--workers", "2",
       "--no-progress", "-o", "m.zarr"]
SIMULATE = ["simulate", "--eta", "1.2", "--periods", "20000", "--transient", "100",
            "-o", "s.nc"]
CONTINUE = ["continue", "--eta", "1.12", "--stop", "1.3", "-o", "br.nc"]
RERUN = ["rerun", "c.nc"]

#: command name -> (arguments, output, has --resume: a checkpoint to resume from)
COMMANDS = {"classify": (CLASSIFY, "c.nc", True), "bifurcation": (BIFURCATION, "b.nc", False),
            "map": (MAP, "m.zarr", True), "simulate": (SIMULATE, "s.nc", False),
            "continue": (CONTINUE, "br.nc", False), "rerun": (RERUN, None, False)}


@dataclass
class Outcome:
    """What one case did."""

    klass: str
    case: str
    rc: int | None = None
    seconds: float = 0.0
    hang: bool = False
    traceback: bool = False
    clean: bool = False
    files_left: list = field(default_factory=list)
    data_lost: bool | None = None  # None: not applicable
    message: str = ""
    tried: bool = True


def _env():
    env = dict(os.environ)
    env.pop("VIBIMPACT_PRECOMPILED", None)
    return env


def _descendants(pid):
    """Process ids below ``pid`` (children first), from /proc."""
    out, todo = [], [pid]
    while todo:
        p = todo.pop(0)
        try:
            kids = []
            for task in os.listdir(f"/proc/{p}/task"):
                with open(f"/proc/{p}/task/{task}/children") as fh:
                    kids += [int(x) for x in fh.read().split()]
        except OSError:
            continue
        out += kids
        todo += kids
    return out


def _worker(pid):
    """A worker process of the run ``pid``: the newest leaf of its process tree."""
    leaves = [p for p in _descendants(pid) if not _descendants(p)]
    return max(leaves) if leaves else None


def run(argv, cwd, timeout, fault=None, delay=0.0, ignoring=()):
    """``python -m vibimpact argv`` in ``cwd``, started with the signals ``ignoring``
    ignored; ``fault(proc)`` called after ``delay`` s.
    Returns ``(rc or None on a hang, stdout, stderr, seconds)``."""
    def ignore():
        for sig in ignoring:
            signal.signal(sig, signal.SIG_IGN)

    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "vibimpact", *argv], cwd=cwd, env=_env(),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True, preexec_fn=ignore if ignoring else None)
    timer = None
    if fault is not None:
        timer = threading.Timer(delay, lambda: proc.poll() is None and fault(proc))
        timer.start()
    try:
        out, err = proc.communicate(timeout=timeout)
        rc = proc.returncode
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        rc = None
    finally:
        if timer is not None:
            timer.cancel()
    return rc, out, err, time.perf_counter() - t0


def _left(cwd, keep=()):
    """Temporary or partial files left in ``cwd`` (the checkpoint directory and the
    outputs in ``keep`` excepted)."""
    bad = []
    for name in os.listdir(cwd):
        if name in keep or name.endswith(".partial") and os.path.isdir(os.path.join(cwd, name)):
            continue
        if name.startswith(".") or name.endswith((".tmp", ".partial")) or "rerun-" in name:
            bad.append(name)
    return sorted(bad)


def _same(a, b):
    """Whether two outputs (NetCDF or Zarr) hold the same data variables bit for bit."""
    import numpy as np
    import xarray as xr

    def load(p):
        return xr.open_zarr(p) if str(p).endswith(".zarr") else xr.open_dataset(p)

    try:
        x, y = load(a), load(b)
    except (OSError, ValueError, KeyError):
        return False
    if set(x.data_vars) != set(y.data_vars):
        return False
    for v in x.data_vars:
        u, w = np.asarray(x[v].values), np.asarray(y[v].values)
        if u.shape != w.shape:
            return False
        eq = (np.array_equal(u, w, equal_nan=True) if u.dtype.kind in "fc"
              else np.array_equal(u, w))
        if not eq:
            return False
    return True


def judge(klass, case, rc, err, seconds, expect, cwd, keep=()):
    """The :class:`Outcome` of one finished (or hung) run."""
    lines = [ln for ln in err.splitlines() if ln.strip()]
    errors = [ln for ln in lines if ln.startswith("vibimpact: error:")]
    o = Outcome(klass, case, rc, seconds, hang=rc is None,
                traceback=any("Traceback" in ln or "Exception ignored" in ln for ln in lines),
                files_left=_left(cwd, keep))
    warnings = [ln for ln in lines if "Warning:" in ln]
    o.message = (errors[-1] if errors else (warnings or lines or [""])[-1])[:160]
    api = [ln for ln in errors if API_WORDS.search(ln)]
    if api:
        o.message = f"API wording: {api[0]}"[:160]
    o.clean = (not o.hang and not o.traceback and rc in expect and len(errors) <= 1
               and not warnings and not api)
    return o


def _resume_check(o, argv, out, cwd, reference, timeout):
    """After an interrupted checkpointed run: resume it and compare with the reference."""
    rc, _, err, _ = run([*argv, "--resume"], cwd, timeout)
    o.data_lost = rc != 0 or not _same(os.path.join(cwd, out), reference)
    if o.data_lost and rc != 0:
        o.message += f" | resume: exit {rc}: {err.strip().splitlines()[-1:]}"


def references(base, timeout):
    """Uninterrupted outputs of the checkpointed commands, and their wall times."""
    ref, wall = {}, {}
    for name in ("classify", "bifurcation", "map", "simulate", "continue"):
        argv, out, _ = COMMANDS[name]
        d = base / f"ref-{name}"
        d.mkdir()
        rc, _, err, sec = run(argv, d, timeout)
        if rc != 0:
            raise RuntimeError(f"reference {name} failed ({rc}): {err[-500:]}")
        ref[name], wall[name] = str(d / out), sec
    return ref, wall


def _fresh(base, tag):
    return Path(tempfile.mkdtemp(prefix=f"{tag}-", dir=base))


def killed_worker_cases(base, ref, wall, moments, timeout):
    out = []
    for name in ("classify", "bifurcation", "map"):
        argv, output, _ = COMMANDS[name]
        for frac in moments:
            d = _fresh(base, f"kill-{name}")

            def fault(proc):
                w = _worker(proc.pid)
                if w is not None:
                    os.kill(w, signal.SIGKILL)

            rc, _, err, sec = run(argv, d, timeout, fault, frac * wall[name])
            o = judge("killed worker", f"{name}, SIGKILL to a worker at {frac:.0%}", rc,
                      err, sec, {0, 2}, d, keep=(output, "b.png"))
            if not o.hang:
                if rc == 0:
                    o.data_lost = not _same(d / output, ref[name])
                elif COMMANDS[name][2]:
                    _resume_check(o, argv, output, d, ref[name], timeout)
            out.append(o)
    return out


def signal_cases(base, ref, wall, moments, timeout):
    out = []
    for name, (argv, output, resumable) in COMMANDS.items():
        for sig, code in ((signal.SIGTERM, 143), (signal.SIGINT, 130)):
            for frac in (moments if sig == signal.SIGTERM else moments[:1]):
                d = _fresh(base, f"sig-{name}")
                if name == "rerun":
                    shutil.copy(ref["classify"], d / "c.nc")
                    w = wall["classify"]
                else:
                    w = wall[name]
                rc, _, err, sec = run(argv, d, timeout, lambda p, s=sig: p.send_signal(s),
                                      frac * w)
                keep = ("c.nc",) if name == "rerun" else ()
                o = judge(f"{signal.Signals(sig).name}", f"{name} at {frac:.0%}", rc, err, sec,
                          {code, 0}, d, keep=keep + ((output,) if rc == 0 else ()))
                if resumable and not o.hang and rc == code:
                    _resume_check(o, argv, output, d, ref[name], timeout)
                out.append(o)
    return out


def _mount_small(path):
    path.mkdir()
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(path)],
                       capture_output=True)
    return r.returncode == 0


def disk_full_cases(base, ref, timeout):
    out = []
    small = base / "small"
    mounted = _mount_small(small)
    try:
        for name in ("simulate", "classify", "bifurcation", "map", "continue"):
            argv, output, resumable = COMMANDS[name]
            if not mounted:
                out.append(Outcome("disk full", f"{name} onto a 64 KiB file system",
                                   tried=False, message="needs root to mount a tmpfs"))
                continue
            for f in small.iterdir():
                shutil.rmtree(f) if f.is_dir() else f.unlink()
            rc, _, err, sec = run(argv, small, timeout)
            o = judge("disk full", f"{name} onto a 64 KiB file system", rc, err, sec, {2},
                      small)
            out.append(o)
    finally:
        if mounted:
            subprocess.run(["umount", str(small)], capture_output=True)
    d = _fresh(base, "devfull")
    rc, _, err, sec = run([*SIMULATE[:-1], "/dev/full", "--overwrite"], d, timeout)
    out.append(judge("disk full", "simulate -o /dev/full --overwrite", rc, err, sec, {2}, d))
    return out


def vanished_cases(base, ref, wall, timeout):
    out = []
    for name in ("classify", "map"):
        argv, output, _ = COMMANDS[name]
        d = _fresh(base, f"vanish-{name}")
        ckpt = d / f"{output}.partial"
        rc, _, err, sec = run(argv, d, timeout,
                              lambda p, c=ckpt: shutil.rmtree(c, ignore_errors=True),
                              0.5 * wall[name])
        o = judge("vanished checkpoint", f"{name}: OUT.partial removed at 50%", rc, err, sec,
                  {0, 2}, d, keep=(output,))
        if rc == 0:
            o.data_lost = not _same(d / output, ref[name])
        out.append(o)
    return out


def foreign_cases(base, ref, wall, timeout):
    """A fig10 point file copied into an interrupted fig8 checkpoint, then --resume."""
    d = _fresh(base, "foreign")
    other = [a if a != "c.nc" else "o.nc" for a in CLASSIFY[:-1]] + ["o.nc", "--preset",
                                                                      "fig10",
                                                                      "--keep-checkpoint"]
    run(other, d, timeout)
    rc, _, err, sec = run(CLASSIFY, d, timeout, lambda p: p.send_signal(signal.SIGINT),
                          0.5 * wall["classify"])
    src = sorted((d / "o.nc.partial").glob("*.npz"))
    dst = d / "c.nc.partial"
    copied = 0
    if src and dst.is_dir():
        for f in src[:3]:
            target = dst / f.name
            if not target.exists():
                shutil.copy(f, target)
                copied += 1
    o = judge("foreign checkpoint entry", f"{copied} fig10 point file(s) in a fig8 checkpoint",
              0, "", 0.0, {0}, d, keep=("o.nc", "c.nc"))
    rc, _, err, sec = run([*CLASSIFY, "--resume"], d, timeout)
    o.rc, o.seconds = rc, sec
    o.hang = rc is None
    o.traceback = "Traceback" in err
    o.data_lost = rc != 0 or not _same(d / "c.nc", ref["classify"])
    o.clean = rc == 0 and not o.traceback
    o.message = (err.strip().splitlines() or [""])[-1][:160]
    return [o]


def bad_input_cases(base, timeout):
    out = []
    for case, argv in BAD.items():
        d = _fresh(base, "bad")
        if "dangling.nc" in argv:
            os.symlink(d / "nowhere" / "x.nc", d / "dangling.nc")
        rc, _, err, sec = run(argv, d, timeout)
        runs = case in RUNS
        o = judge("limits and paths", case, rc, err, sec, {0, 2} if runs else {2}, d,
                  keep=("dangling.nc", "c.nc") if runs else ("dangling.nc",))
        o.clean = o.clean and sec < 20.0 and (runs or not any(
            (d / n).exists() for n in ("s.nc", "c.nc", "m.zarr")))
        out.append(o)
    return out


def bound_cases(base, timeout):
    """Continuations from (or down to) a parameter's bound: they run and write."""
    out = []
    for case, argv in BOUNDS.items():
        d = _fresh(base, "bound")
        rc, stdout, err, sec = run(argv, d, timeout)
        o = judge("continuation at a bound", case, rc, err, sec, {0}, d, keep=("br.nc",))
        o.clean = o.clean and (d / "br.nc").exists()
        o.message = o.message or (stdout.strip().splitlines() or [""])[0][:160]
        out.append(o)
    return out


def wording_cases(base, timeout):
    """Refusals that must name the command line's options (--overwrite, --resume)."""
    out = []
    for case, (argv, existing) in WORDING.items():
        d = _fresh(base, "words")
        name = existing.rstrip("/")
        if existing.endswith((".zarr", "/")):
            (d / name).mkdir()
        else:
            (d / name).write_bytes(b"old")
        rc, _, err, sec = run(argv, d, timeout)
        o = judge("command-line wording", case, rc, err, sec, {2}, d, keep=(name,))
        flag = "--resume" if name.endswith(".partial") else "--overwrite"
        o.clean = o.clean and flag in err
        out.append(o)
    return out


def python_case(base, tag, klass, case, code, timeout, said):
    """The :class:`Outcome` of ``code`` run by a Python process of its own in a fresh
    directory: clean when it exits 0, leaves nothing and its last printed line starts
    with one of ``said`` (a tuple)."""
    d = _fresh(base, tag)
    t0 = time.perf_counter()
    try:
        proc = subprocess.run([sys.executable, "-c", code], cwd=d, env=_env(),
                              capture_output=True, text=True, timeout=timeout)
        rc, stdout, err = proc.returncode, proc.stdout, proc.stderr
    except subprocess.TimeoutExpired:
        rc, stdout, err = None, "", ""
    o = judge(klass, case, rc, err, time.perf_counter() - t0, {0}, d)
    o.message = (stdout.strip().splitlines() or [""])[-1][:160]
    o.clean = o.clean and o.message.startswith(said)
    return o


def user_model_cases(base, timeout):
    """User models that lie about their sizes (API, one Python process each): refused
    before the kernel runs them."""
    return [python_case(base, "model", "user model sizes", case,
                        USER_MODEL.replace("CHANGES", changes).replace("ENTRY", entry),
                        timeout, ("refused:",))
            for case, (changes, entry) in USER_MODEL_CASES.items()]


#: class -> the function of this module that runs its cases (the reference runs first)
CLASS_CASES = {
    "killed worker": lambda b, r, w, m, t: killed_worker_cases(b, r, w, m, t),
    "SIGTERM": lambda b, r, w, m, t: signal_cases(b, r, w, m, t),
    "SIGINT": lambda b, r, w, m, t: signal_cases(b, r, w, m, t),
    "disk full": lambda b, r, w, m, t: disk_full_cases(b, r, t),
    "vanished checkpoint": lambda b, r, w, m, t: vanished_cases(b, r, w, t),
    "foreign checkpoint entry": lambda b, r, w, m, t: foreign_cases(b, r, w, t),
    "limits and paths": lambda b, r, w, m, t: bad_input_cases(b, t),
    "continuation at a bound": lambda b, r, w, m, t: bound_cases(b, t),
    "command-line wording": lambda b, r, w, m, t: wording_cases(b, t),
    "user model sizes": lambda b, r, w, m, t: user_model_cases(b, t),
}
#: the modules of further classes (each: ``CLASSES``, class -> ``func(kit, base,
#: timeout)``, and ``shrink()``), run after this module's own
EXTRA = (_cases_round3, _cases_signals, _cases_r4_streams, _cases_r4_checkpoints,
         _cases_r4_inputs, _cases_r4_files, _cases_r4_results)
#: the classes that need the reference runs
NEEDS_REFERENCES = {"killed worker", "SIGTERM", "SIGINT", "disk full",
                    "vanished checkpoint", "foreign checkpoint entry"}


def measure_extra(extra, base, timeout, only=None):
    """The :class:`Outcome` of every case of the classes of the module ``extra`` (of the
    classes ``only``); a function serving several classes runs once."""
    out, done = [], set()
    for klass, func in extra.CLASSES.items():
        if (only and klass not in only) or func in done:
            continue
        done.add(func)
        out += [o for o in func(sys.modules[__name__], base, timeout)
                if not only or o.klass in only]
    return out


def measure(quick=False, timeout=300, only=None):
    """Every case's :class:`Outcome` (of the classes ``only``, a set, if given), and
    the reference wall times."""
    moments = (0.5,) if quick else (0.1, 0.5, 0.95)
    base = Path(tempfile.mkdtemp(prefix="vibimpact-reliability-"))
    try:
        ref, wall = {}, {}
        if not only or only & NEEDS_REFERENCES:
            ref, wall = references(base, timeout)
        out, ran = [], set()
        for klass, func in CLASS_CASES.items():
            if (only and klass not in only) or func.__code__ in ran:
                continue
            if klass in ("SIGTERM", "SIGINT"):  # one function runs both
                ran.add(func.__code__)
            out += [o for o in func(base, ref, wall, moments, timeout)
                    if not only or o.klass in only]
        for extra in EXTRA:
            out += measure_extra(extra, base, timeout, only)
        return out, wall
    finally:
        subprocess.run(["umount", str(base / "small")], capture_output=True)
        shutil.rmtree(base, ignore_errors=True)


def report(outcomes, wall, quick, took=None):
    """The section text of ``reports/reliability.md`` (``took``: the run's wall time, s)."""
    now = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    ran = "" if took is None else f" in {took / 60:.1f} min"
    L = ["# Reliability under faults", "",
         f"Written by `python analyses/reliability/reliability.py{' --quick' if quick else ''}` on {now}"
         f"{ran} ({os.cpu_count()} CPUs, Python {platform.python_version()}); every number below "
         "is counted by it.  Reference runs (uninterrupted): " + ", ".join(
             f"{k} {v:.1f} s" for k, v in wall.items()) + ".  Moments are fractions of the "
         "reference's wall time.", "",
         "| class | cases tried | clean | tracebacks | hangs | files left | data lost | "
         "not tried |", "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    classes = list(dict.fromkeys(o.klass for o in outcomes))
    tot = [0] * 7
    for k in classes:
        os_ = [o for o in outcomes if o.klass == k]
        tried = [o for o in os_ if o.tried]
        row = [len(tried), sum(o.clean for o in tried), sum(o.traceback for o in tried),
               sum(o.hang for o in tried), sum(bool(o.files_left) for o in tried),
               sum(bool(o.data_lost) for o in tried), len(os_) - len(tried)]
        tot = [a + b for a, b in zip(tot, row)]
        L.append(f"| {k} | " + " | ".join(str(x) for x in row) + " |")
    L.append("| **all** | " + " | ".join(f"**{x}**" for x in tot) + " |")
    L += ["", "## Every case", "",
          "| class | case | exit | s | verdict | files left | data | last message |",
          "| --- | --- | ---: | ---: | --- | --- | --- | --- |"]
    for o in outcomes:
        if not o.tried:
            verdict = "not tried"
        elif o.hang:
            verdict = "**hang**"
        elif o.traceback:
            verdict = "**traceback**"
        else:
            verdict = "clean" if o.clean else "**unexpected exit**"
        data = "-" if o.data_lost is None else ("**lost**" if o.data_lost else "identical")
        msg = o.message.replace("|", "/").replace("`", "'")
        L.append(f"| {o.klass} | {o.case} | {o.rc if o.rc is not None else '-'} | "
                 f"{o.seconds:.1f} | {verdict} | {', '.join(o.files_left) or '-'} | {data} | "
                 f"{msg} |")
    return "\n".join(L)


def _smoke_cases():
    """The names :func:`smoke.shrink` sets in a smoke run: every command on a tiny
    request, and the first case of each table of requests."""
    tiny = {"classify": ["--eta", "1.0:1.1:0.02"], "bifurcation": ["--eta", "1.0:1.1:0.02"],
            "map": ["--eta", "1.0:1.1:0.05", "--vary", "kh=50,60"],
            "simulate": ["--periods", "200"], "continue": ["--stop", "1.13"]}
    commands = {}
    for name, (argv, output, resumable) in COMMANDS.items():
        argv = list(argv)
        for opt, value in zip(tiny.get(name, [])[::2], tiny.get(name, [])[1::2]):
            argv[argv.index(opt) + 1] = value
        commands[name] = (argv, output, resumable)
    first = {name: dict(list(table.items())[:1]) for name, table in
             (("BAD", BAD), ("BOUNDS", BOUNDS), ("WORDING", WORDING),
              ("USER_MODEL_CASES", USER_MODEL_CASES))}
    return dict(COMMANDS=commands, CLASSIFY=commands["classify"][0],
                SIMULATE=commands["simulate"][0], **first)


def main(argv=None):
    global REPORT
    ap = smoke.parser(__doc__)
    ap.add_argument("--quick", action="store_true", help="one moment per fault")
    ap.add_argument("--no-report", action="store_true", help="print only")
    ap.add_argument("--timeout", type=float, default=300.0,
                    help="seconds before a run counts as hung (default 300)")
    ap.add_argument("--only", action="append", metavar="CLASS",
                    help="run only the cases of this class (repeatable); the report is "
                         "then printed, not written")
    args = ap.parse_args(argv)
    REPORT = smoke.moved(REPORT, args.smoke)
    # the commands get SIGINT as from a terminal: a run started as a script's background
    # job ignores SIGINT, and its commands would inherit that (and rightly ignore it)
    signal.signal(signal.SIGINT, signal.default_int_handler)
    if args.smoke is not None:
        smoke.shrink(globals(), args.smoke, **_smoke_cases())
        for extra in EXTRA:
            extra.shrink()
        args.quick = True
    only = set(args.only or ())
    known = set(CLASS_CASES).union(*(extra.CLASSES for extra in EXTRA))
    unknown = only - known
    if unknown:
        ap.error(f"--only: unknown class {sorted(unknown)[0]!r} (one of "
                 f"{', '.join(sorted(known))})")
    t0 = time.perf_counter()
    outcomes, wall = measure(args.quick, args.timeout, only or None)
    text = report(outcomes, wall, args.quick, time.perf_counter() - t0)
    print(text)
    if not args.no_report and not only:
        write_section(REPORT, SECTION, text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
