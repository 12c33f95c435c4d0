"""Which files a rotor speed passes through on its way from the command line to the kernel.

Two counts: the files that *handle eta as a number* (parse, validate, set or read it: it
is a bare number, text or grid array among a function's arguments), and the files it
is merely *carried* through inside the objects that hold it (parameter sets, systems,
tasks, kernel problems), which is every layer between the command line and the kernel.

Runs ``vibimpact classify`` in this process (one worker, so every call is seen) with a
profiler hook.  At every call into the kernel's boundary (``_kernel/boundary.py``) it
walks the call stack back to the command line and keeps the files of the frames that
hold the requested ``eta`` in their arguments (a float, an array, a parameter set, a
system, a kernel problem, a task tuple, the command line's text).  Each kernel call gives
one path (the jitted loop the boundary calls is its last file); the report is the longest
path and the union of all.  ``python analyses/tools/eta_path.py`` prints them.
"""
from __future__ import annotations

import dataclasses
import os
import pathlib
import sys
import tempfile

import numpy as np

ETA_TEXT = "1.23456:1.23556:0.001"
ETAS = (1.23456, 1.23556)
PKG = pathlib.Path(__file__).resolve().parents[2] / "vibimpact"
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))  # analyses/: _common
from _common import smoke  # noqa: E402


def _bare(value):
    """``eta`` as a number, text, grid array, or the text of a command line."""
    if isinstance(value, (tuple, list)):
        return any(isinstance(v, (str, float)) and _has_eta(v) for v in value[:64])
    if isinstance(value, (bool, dict)) or dataclasses.is_dataclass(value):
        return False
    if isinstance(value, (float, np.floating, str, np.ndarray)):
        return _has_eta(value)
    return False


def _has_eta(value, depth=0):
    if depth > 3:
        return False
    if isinstance(value, bool):
        return False
    if isinstance(value, (float, np.floating)):
        return any(abs(float(value) - e) < 1e-12 for e in ETAS)
    if isinstance(value, str):
        return "1.23456" in value
    if isinstance(value, np.ndarray):
        if value.dtype.kind != "f" or value.size > 100_000:
            return False
        return bool(np.any(np.abs(value[..., None] - np.array(ETAS)) < 1e-12))
    if isinstance(value, (tuple, list)):
        return any(_has_eta(v, depth + 1) for v in value[:64])
    if isinstance(value, dict):
        return any(_has_eta(v, depth + 1) for v in list(value.values())[:64])
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return any(_has_eta(getattr(value, f.name, None), depth + 1)
                   for f in dataclasses.fields(value))
    if hasattr(value, "__dict__") and type(value).__module__.startswith(("argparse",)):
        return any(_has_eta(v, depth + 1) for v in vars(value).values())
    return False


def _frame_has_eta(frame, test=_has_eta):
    code = frame.f_code
    names = code.co_varnames[:code.co_argcount + code.co_kwonlyargcount]
    return any(test(frame.f_locals.get(n)) for n in names)


def _path(frame, test=_has_eta):
    """Files (relative to the package) of the frames holding ``eta`` from the command
    line down to ``frame``, in call order, each once."""
    files = []
    while frame is not None:
        fname = frame.f_code.co_filename
        if fname.startswith(str(PKG)) and _frame_has_eta(frame, test):
            rel = str(pathlib.Path(fname).relative_to(PKG))
            if rel not in files:
                files.append(rel)
        frame = frame.f_back
    return files[::-1] + ["_kernel/driver.py"]


def trace(argv=None, bare=False):
    """``(longest, union)``: the longest path of ``eta`` from the command line to a kernel
    call and the union of the files of all paths, in order of first appearance (file
    names relative to ``vibimpact/``); with ``bare``, only the files that handle it as a
    number (:func:`_bare`)."""
    from vibimpact.cli import main

    boundary = str(PKG / "_kernel" / "boundary.py")
    paths = []

    def hook(frame, event, arg):
        if event == "call" and frame.f_code.co_filename == boundary and \
                frame.f_code.co_name in ("integrate", "benettin", "two_trajectory"):
            p = _path(frame, _bare if bare else _has_eta)
            if p not in paths:
                paths.append(p)

    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "c.nc")
        args = argv or ["classify", "--eta", ETA_TEXT, "--workers", "1", "-o", out]
        saved = sys.argv
        sys.argv = ["vibimpact"] + args  # as the console script runs it: main() reads argv
        sys.setprofile(hook)
        try:
            rc = main()
        finally:
            sys.setprofile(None)
            sys.argv = saved
    if rc not in (0, None):
        raise RuntimeError(f"vibimpact classify failed with exit code {rc}")
    if not paths:
        raise RuntimeError("no kernel call seen")
    union = []
    for p in paths:
        union += [f for f in p if f not in union]
    return max(paths, key=len), union


def measure():
    """``{"handled": [...], "carried": [...]}``: the longest path (files) of each kind."""
    return {"handled": trace(bare=True)[0], "carried": trace()[0]}


def main(argv=None):
    out = smoke.parser(__doc__).parse_args(argv).smoke
    lines = []
    for kind, bare in (("handled as a number", True), ("carried", False)):
        longest, union = trace(bare=bare)
        lines.append(f"eta {kind}, the longest path from the command line to the kernel:")
        lines += [f"  {k}. vibimpact/{f}" for k, f in enumerate(longest, 1)]
        lines.append(f"  {len(longest)} files on this path; on all paths: {', '.join(union)}")
    print("\n".join(lines))
    if out is not None:  # the trace is already tiny: a smoke run also writes it to a file
        smoke.moved(pathlib.Path("eta_path.txt"), out).write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
