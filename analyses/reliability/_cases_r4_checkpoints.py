"""Cases of :mod:`reliability` from the fourth adversarial round (issue 44, classes 2,
3, 4 and 6): FIFOs, deeply nested JSON and symbolic links in checkpoints and input
files, and resumes after an interrupt.

* **FIFO in a checkpoint or as an input** -- a kept checkpoint of ``classify``,
  ``attractors``, ``basins``, ``orbits`` and ``map`` whose first entry is replaced by a
  FIFO, then ``--resume`` (clean: exit 0 within the time limit, the entry set aside as
  "not a regular file", the file bit-identical to the uninterrupted one); a FIFO as
  ``request.json`` (exit 2, one line), as ``output.json`` or named like an entry beyond
  the grid (exit 0, identical); the checkpoint itself a FIFO (exit 2); a FIFO, a socket,
  ``/dev/zero`` or a directory given as the input of ``plot``, ``rerun``, ``simulate
  --from``, ``attractors --sweep`` or ``orbits --seeds`` (exit 2, one line naming what
  it is).
* **deeply nested JSON** -- ``request.json`` nested 200,000 levels (lists or objects) in
  the checkpoint of every checkpointed command (exit 2, one line naming the depth);
  ``output.json`` or ``last_resume.json`` so nested (exit 0, identical); a sweep's
  ``params`` or ``settings`` attribute so nested, given to ``plot``, ``simulate
  --from``, ``attractors --sweep`` and ``rerun``; a branch file's ``params`` to ``plot``;
  a map store's ``zarr.json``; a Dask scheduler file (no traceback, exit 0 or 2 -- 2
  when the value is needed, naming the attribute).
* **checkpoint replaced by a symlink** -- ``OUT.partial`` renamed and replaced by a
  symbolic link to an empty directory as soon as the run saved its first entry
  (``classify``, ``attractors``, ``basins``, ``orbits``, ``map``), or by a file (clean:
  exit 2, one line saying what replaced it, nothing written through the link); a
  checkpoint that is a link before ``--resume`` (exit 2).
* **resume after an interrupted write** -- SIGINT or SIGKILL while a new checkpoint's
  ``request.json`` is written (``classify``, ``basins``, ``attractors``, ``orbits``,
  ``map``), SIGTERM or SIGKILL once two entries are saved (``orbits``, ``classify``), a
  worker of ``orbits --workers 2`` killed: ``--resume`` exits 0, sets nothing aside,
  leaves no temporary and writes the uninterrupted run's file bit for bit.
"""
from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import sys
import time

#: command -> argv without the output (``-o o.nc`` is added)
COMMANDS = {
    "classify": ["classify", "--preset", "fig8", "--eta", "1.0:1.04:0.01", "--workers",
                 "1", "--analyses", "period,impacts", "--no-progress"],
    "attractors": ["attractors", "--preset", "fig11", "--eta", "1.06,1.07", "--starts",
                   "4", "--workers", "1", "--no-progress"],
    "basins": ["basins", "--preset", "fig11", "--eta", "1.06", "--grid", "10x10",
               "--workers", "1", "--no-progress"],
    "orbits": ["orbits", "--preset", "fig11", "--eta", "1.06", "--period", "1:3",
               "--random", "48", "--window", "0.01", "--workers", "1", "--no-progress"],
    "map": ["map", "--preset", "fig8", "--eta", "1.0:1.02:0.01", "--vary",
            "kh=100,110,120", "--workers", "1"],
}
#: longer runs, for a checkpoint swapped while they go on (many entries after the first)
LONG = {
    "classify": ["classify", "--preset", "fig8", "--eta", "1.0:1.3:0.005", "--workers",
                 "1", "--analyses", "period", "--no-progress"],
    "attractors": ["attractors", "--preset", "fig11", "--eta", "1.05:1.07:0.005",
                   "--starts", "6", "--workers", "1", "--no-progress"],
    "basins": ["basins", "--preset", "fig11", "--eta", "1.06", "--grid", "24x24",
               "--workers", "1", "--no-progress"],
    "orbits": ["orbits", "--preset", "fig11", "--eta", "1.06", "--period", "1:6",
               "--random", "48", "--workers", "1", "--no-progress"],
    "map": ["map", "--preset", "fig8", "--eta", "1.0:1.1:0.01", "--vary",
            "kh=100:190:10", "--workers", "1"],
}
OUT = "o.nc"
DEEP = ("[" * 200_000 + "]" * 200_000, '{"a":' * 200_000 + "1" + "}" * 200_000)

_KEPT = {}  # command -> directory holding ref.nc and its kept checkpoint ref.partial


def _outcome(kit, klass, case, rc, err, sec, expect, cwd, keep=(), needle=None):
    """kit.judge, and clean only when the one line says ``needle``."""
    o = kit.judge(klass, case, rc, err, sec, expect, cwd, keep=keep)
    if needle is not None and needle not in err:
        o.clean = False
        o.message = f"expected {needle!r}: {o.message}"[:160]
    return o


def _kept(kit, base, timeout, name):
    """A directory with the uninterrupted output ``ref.nc`` of command ``name`` and its
    kept checkpoint ``ref.partial`` (made once)."""
    if name not in _KEPT:
        d = kit._fresh(base, f"kept-{name}")
        rc, _, err, _ = kit.run([*COMMANDS[name], "-o", OUT, "--keep-checkpoint"], d,
                                timeout)
        if rc != 0:
            raise RuntimeError(f"reference {name} failed ({rc}): {err[-400:]}")
        os.rename(d / OUT, d / "ref.nc")
        os.rename(d / f"{OUT}.partial", d / "ref.partial")
        _KEPT[name] = d
    return _KEPT[name]


def _with_checkpoint(kit, base, timeout, name, tag):
    """A fresh directory holding a copy of ``name``'s kept checkpoint as OUT.partial."""
    src = _kept(kit, base, timeout, name)
    d = kit._fresh(base, tag)
    shutil.copytree(src / "ref.partial", d / f"{OUT}.partial", symlinks=True)
    return d, src / "ref.nc"


def _entries(ckpt):
    """The saved entries of the checkpoint ``ckpt`` (not the temporaries)."""
    return sorted(p for p in ckpt.glob("*.npz") if not p.name.startswith("."))


def _resume(kit, klass, case, d, ref, name, timeout, expect=(0,), needle=None,
            keep=(OUT,), forbid=None):
    """--resume in ``d``; with exit 0 expected, the output must be ``ref``'s data; not
    clean when stderr says ``forbid``."""
    rc, _, err, sec = kit.run([*COMMANDS[name], "-o", OUT, "--resume"], d, timeout)
    o = _outcome(kit, klass, case, rc, err, sec, set(expect), d, keep=keep,
                 needle=needle)
    if forbid is not None and forbid in err:
        o.clean, o.message = False, f"said {forbid!r}: {o.message}"[:160]
    if 0 in expect:
        o.data_lost = rc != 0 or not kit._same(d / OUT, ref)
        o.clean = o.clean and not o.data_lost
    return o


# --- FIFO in a checkpoint or as an input ----------------------------------------------
def fifo_cases(kit, base, timeout):
    klass = "FIFO in a checkpoint or as an input"
    out = []
    for name in COMMANDS:
        d, ref = _with_checkpoint(kit, base, timeout, name, f"fifo-{name}")
        entry = _entries(d / f"{OUT}.partial")[0]
        entry.unlink()
        os.mkfifo(entry)
        out.append(_resume(kit, klass, f"{name}: an entry replaced by a FIFO", d, ref,
                           name, timeout, needle="not a regular file"))
    for name, what, expect, needle in (
            ("classify", "request.json", (2,), "request.json is a FIFO, not a regular"),
            ("orbits", "output.json", (0,), None),
            ("map", "up_000009_000000-000003.npz", (0,), "not a regular file"),
            ("basins", "last_resume.json", (0,), None)):
        if name not in COMMANDS:
            continue
        d, ref = _with_checkpoint(kit, base, timeout, name, f"fifo-{name}-record")
        path = d / f"{OUT}.partial" / what
        if path.exists():
            path.unlink()
        os.mkfifo(path)
        out.append(_resume(kit, klass, f"{name}: {what} a FIFO", d, ref, name, timeout,
                           expect, needle))
    d = kit._fresh(base, "fifo-itself")  # refused before the command runs anything
    os.mkfifo(d / f"{OUT}.partial")
    out.append(_resume(kit, klass, "basins: OUT.partial itself a FIFO", d, None, "basins",
                       timeout, (2,), "exists and is not a directory (a FIFO)",
                       keep=(f"{OUT}.partial",)))
    return out + _input_cases(kit, base, timeout, klass)


def make_socket(path):
    """A Unix socket at ``path`` (nobody listening)."""
    s = socket.socket(socket.AF_UNIX)
    s.bind(str(path))
    s.close()


#: input kind -> make(path)
INPUT_KINDS = {"a FIFO": os.mkfifo, "a socket": make_socket,
               "a directory": os.mkdir}
#: command -> argv reading the input IN
INPUT_COMMANDS = {
    "plot": ["plot", "IN", "-o", "p.png"],
    "rerun": ["rerun", "IN"],
    "simulate --from": ["simulate", "--from", "IN", "-o", "s.nc"],
    "attractors --sweep": ["attractors", "--sweep", "IN", "-o", "a.nc"],
    "orbits --seeds": ["orbits", "--seeds", "IN", "-o", "b.nc"],
}


def _input_cases(kit, base, timeout, klass):
    out = []
    cases = [(c, "a FIFO") for c in INPUT_COMMANDS] + \
        [("plot", k) for k in INPUT_KINDS if k != "a FIFO"] + [("plot", "/dev/zero")]
    for command, kind in cases:
        d = kit._fresh(base, "input")
        if kind == "/dev/zero":
            path, words = "/dev/zero", "is a character device, not a regular file"
        else:
            path = "in.nc"
            INPUT_KINDS[kind](str(d / path))
            words = "is a directory" if kind == "a directory" else \
                f"is {kind}, not a regular file"
        argv = [a if a != "IN" else path for a in INPUT_COMMANDS[command]]
        rc, _, err, sec = kit.run(argv, d, timeout)
        out.append(_outcome(kit, klass, f"{command} of {kind}", rc, err, sec, {2}, d,
                            keep=("in.nc",), needle=words))
    return out


# --- deeply nested JSON ----------------------------------------------------------------
def deep_cases(kit, base, timeout):
    klass = "deeply nested JSON"
    out = []
    for k, name in enumerate(COMMANDS):
        d, ref = _with_checkpoint(kit, base, timeout, name, f"deep-{name}")
        (d / f"{OUT}.partial" / "request.json").write_text(DEEP[k % 2])
        out.append(_resume(kit, klass, f"{name}: request.json nested 200,000 "
                           f"{('lists', 'objects')[k % 2]}", d, ref, name, timeout, (2,),
                           "request.json is JSON nested more than 100 levels"))
    for name, what in (("classify", "output.json"), ("orbits", "last_resume.json")):
        if name not in COMMANDS:
            continue
        d, ref = _with_checkpoint(kit, base, timeout, name, f"deep-{name}-record")
        (d / f"{OUT}.partial" / what).write_text(DEEP[1])
        out.append(_resume(kit, klass, f"{name}: {what} nested 200,000 levels", d, ref,
                           name, timeout))
    return out + _deep_file_cases(kit, base, timeout, klass)


def _set_attr(path, attr, value):
    import netCDF4

    with netCDF4.Dataset(path, "a") as ds:
        ds.setncattr(attr, value)


def _deep_file_cases(kit, base, timeout, klass):
    out = []
    src = _kept(kit, base, timeout, "classify") / "ref.nc"
    files = kit._fresh(base, "deep-files")
    rc, _, err, _ = kit.run(["continue", "--preset", "fig8", "--eta", "1.0", "--stop",
                             "1.01", "-o", "br.nc"], files, timeout)
    if rc != 0:
        raise RuntimeError(f"continue failed ({rc}): {err[-400:]}")
    plans = [(attr, argv, expect) for attr in ("params", "settings") for argv, expect in (
        (["plot", "s.nc", "--kind", "intervals", "-o", "p.png"], {0, 2}),
        (["simulate", "--from", "s.nc", "--eta", "1.0", "-o", "y.nc"], {0, 2}),
        (["attractors", "--sweep", "s.nc", "--preset", "fig8", "--eta", "1.0",
          "--starts", "2", "-o", "a.nc"], {0, 2}),
        (["rerun", "s.nc"], {0, 1, 2}))]
    for attr, argv, expect in plans:
        d = kit._fresh(base, "deep-attr")
        shutil.copy(src, d / "s.nc")
        _set_attr(d / "s.nc", attr, DEEP[0])
        rc, _, err, sec = kit.run(argv, d, timeout)
        o = _outcome(kit, klass, f"{' '.join(argv[:2])}: sweep {attr} nested 200,000",
                     rc, err, sec, expect, d, keep=tuple(os.listdir(d)))
        if attr == "params" and rc == 2 and "nested more than 100" not in err:
            o.clean, o.message = False, f"not about the depth: {o.message}"[:160]
        out.append(o)
    d = kit._fresh(base, "deep-branch")
    shutil.copy(files / "br.nc", d / "br.nc")
    _set_attr(d / "br.nc", "params", DEEP[1])
    rc, _, err, sec = kit.run(["plot", "br.nc", "-o", "p.png"], d, timeout)
    out.append(_outcome(kit, klass, "plot: branch params nested 200,000", rc, err, sec,
                        {2}, d, keep=("br.nc",), needle="nested more than 100"))
    d = kit._fresh(base, "deep-zarr")
    (d / "m.zarr").mkdir()
    (d / "m.zarr" / "zarr.json").write_text(DEEP[1])
    rc, _, err, sec = kit.run(["plot", "m.zarr", "-o", "p.png"], d, timeout)
    out.append(_outcome(kit, klass, "plot: a map store's zarr.json nested 200,000", rc,
                        err, sec, {2}, d, keep=("m.zarr",), needle="nested more than 100"))
    if "map" not in COMMANDS:
        return out
    d = kit._fresh(base, "deep-scheduler")
    (d / "sched.json").write_text('{"address": ' + DEEP[0] + "}")
    argv = COMMANDS["map"][:COMMANDS["map"].index("--workers")]
    rc, _, err, sec = kit.run([*argv, "--scheduler", "sched.json", "-o", "m.nc"], d,
                              timeout)
    out.append(_outcome(kit, klass, "map --scheduler: a scheduler file nested 200,000",
                        rc, err, sec, {2}, d, keep=("sched.json",)))
    return out


# --- checkpoint replaced by a symlink --------------------------------------------------
def _when_saved(d, entries, action, limit=60.0):
    """A fault for kit.run: once OUT.partial in ``d`` holds ``entries`` entries,
    ``action(proc)`` (nothing if the run ends first)."""
    def fault(proc):
        ckpt = d / f"{OUT}.partial"
        t0 = time.monotonic()
        while time.monotonic() - t0 < limit and proc.poll() is None:
            try:
                if len(_entries(ckpt)) >= entries:
                    action(proc)
                    return
            except OSError:
                pass
            time.sleep(0.005)
    return fault


def _swap(d, make):
    """Rename OUT.partial and put ``make`` (``"link"`` to an empty directory, or
    ``"file"``) in its place."""
    def action(proc):
        ckpt = d / f"{OUT}.partial"
        os.rename(ckpt, d / "moved")
        if make == "link":
            (d / "elsewhere").mkdir()
            os.symlink("elsewhere", ckpt)
        else:
            ckpt.write_text("")
    return action


def symlink_cases(kit, base, timeout):
    klass = "checkpoint replaced by a symlink"
    out = []
    plans = [(name, "link") for name in LONG] + [("classify", "file")]
    for name, make in plans:
        d = kit._fresh(base, f"swap-{name}")
        rc, _, err, sec = kit.run([*LONG[name], "-o", OUT], d, timeout,
                                  _when_saved(d, 1, _swap(d, make)), 0.0)
        words = "a symbolic link (to 'elsewhere')" if make == "link" else \
            "a regular file"
        o = _outcome(kit, klass, f"{name}: OUT.partial replaced by {words.split(' (')[0]} "
                     "after its first entry", rc, err, sec, {2}, d,
                     keep=("moved", "elsewhere", f"{OUT}.partial"),
                     needle=f"was replaced by {words} during the run")
        if (d / "elsewhere").is_dir() and os.listdir(d / "elsewhere"):
            o.clean = False
            o.message = f"written through the link: {os.listdir(d / 'elsewhere')}"
        out.append(o)
    name = "attractors" if "attractors" in COMMANDS else "classify"
    d, ref = _with_checkpoint(kit, base, timeout, name, "link-before")
    os.rename(d / f"{OUT}.partial", d / "real")
    os.symlink("real", d / f"{OUT}.partial")
    out.append(_resume(kit, klass, f"{name}: --resume onto a link to a checkpoint", d,
                       ref, name, timeout, (2,),
                       "is a symbolic link (to 'real'), not a directory"))
    return out


# --- resume after an interrupted write -------------------------------------------------
#: the process signals itself while it writes a new checkpoint's request.json
AT_CREATION = """
import os, signal
from vibimpact.engine import ckdir
real = ckdir.write_atomic
def write_atomic(fd, name, data):
    if name == "request.json":
        os.kill(os.getpid(), signal.{sig})
    return real(fd, name, data)
ckdir.write_atomic = write_atomic
import sys
from vibimpact.cli import main
sys.exit(main(sys.argv[1:]))
"""


def _run_code(code, argv, cwd, timeout):
    """``python -c code argv`` in ``cwd`` (its own session); ``(rc or None, err)``."""
    proc = subprocess.Popen([sys.executable, "-c", code, *argv], cwd=cwd,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    try:
        _, err = proc.communicate(timeout=timeout)
        return proc.returncode, err
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        return None, proc.communicate()[1]


def _after_resume(kit, klass, case, d, ref, name, timeout):
    """--resume after an interrupt: clean when nothing is set aside, every entry left
    in the checkpoint is loaded (it says how many) and the file is ``ref``'s."""
    saved = len(_entries(d / f"{OUT}.partial"))
    needle = f"resumed from {OUT}.partial: {saved} point" if saved else None
    return _resume(kit, klass, case, d, ref, name, timeout, needle=needle,
                   forbid="set aside")


def resume_cases(kit, base, timeout):
    klass = "resume after an interrupted write"
    out = []
    for name in COMMANDS:
        for sig in ("SIGINT", "SIGKILL"):
            ref = _kept(kit, base, timeout, name) / "ref.nc"
            d = kit._fresh(base, f"create-{name}")
            rc, err = _run_code(AT_CREATION.replace("{sig}", sig),
                                [*COMMANDS[name], "-o", OUT], d, timeout)
            if rc not in (130, -9) or (d / f"{OUT}.partial").exists():
                o = kit.judge(klass, f"{name}: {sig} while its checkpoint is made", rc,
                              err, 0.0, {130, -9}, d)
                o.clean, o.message = False, f"left {os.listdir(d)}: {o.message}"[:160]
                out.append(o)
                continue
            out.append(_after_resume(kit, klass, f"{name}: {sig} while its checkpoint "
                                     "is made, then --resume", d, ref, name, timeout))
    plans = [("orbits", signal.SIGTERM, False), ("orbits", signal.SIGKILL, False),
             ("classify", signal.SIGKILL, False), ("orbits", signal.SIGKILL, True)]
    for name, sig, worker in plans:
        if name not in COMMANDS:
            continue
        argv = [*COMMANDS[name], "-o", OUT]
        if worker:
            argv[argv.index("--workers") + 1] = "2"
        ref = _kept(kit, base, timeout, name) / "ref.nc"
        d = kit._fresh(base, f"stop-{name}")
        def action(proc, sig=sig, worker=worker):
            pid = kit._worker(proc.pid) if worker else proc.pid
            if pid:
                os.kill(pid, sig)

        rc, _, err, sec = kit.run(argv, d, timeout, _when_saved(d, 2, action), 0.0)
        what = f"{'a worker of ' if worker else ''}{name}{' --workers 2' if worker else ''}"
        out.append(_after_resume(kit, klass, f"{what}: {sig.name} after two saved entries, "
                                 "then --resume", d, ref, name, timeout))
    return out


#: class -> the function that runs its cases: ``func(kit, base, timeout)`` -> Outcomes
CLASSES = {
    "FIFO in a checkpoint or as an input": fifo_cases,
    "deeply nested JSON": deep_cases,
    "checkpoint replaced by a symlink": symlink_cases,
    "resume after an interrupted write": resume_cases,
}


def shrink():
    """A smoke run: the checkpointed commands the cases name (classify, orbits, basins,
    map), one input command."""
    for table in (COMMANDS, LONG):
        for key in [k for k in table if k not in ("classify", "orbits", "basins", "map")]:
            del table[key]
    for key in list(INPUT_COMMANDS)[1:]:
        del INPUT_COMMANDS[key]
