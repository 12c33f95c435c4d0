"""Which files a rotor speed passes through on its way from the command line to the kernel.

Runs ``vibimpact classify`` in this process (one worker, so every call is seen) with a
profiler hook.  At every call into the kernel's boundary (``_kernel/boundary.py``) it
walks the call stack back to the command line and keeps the files of the frames that
hold the requested ``eta`` in their arguments (a float, an array, a parameter set, a
system, a kernel problem, a task tuple, the command line's text).  Each kernel call gives
one path (the jitted loop the boundary calls is its last file); the report is the longest
path and the union of all.  ``python analyses/eta_path.py`` prints them.
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
PKG = pathlib.Path(__file__).resolve().parents[1] / "vibimpact"


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


def _frame_has_eta(frame):
    code = frame.f_code
    names = code.co_varnames[:code.co_argcount + code.co_kwonlyargcount]
    return any(_has_eta(frame.f_locals.get(n)) for n in names)


def _path(frame):
    """Files (relative to the package) of the frames holding ``eta`` from the command
    line down to ``frame``, in call order, each once."""
    files = []
    while frame is not None:
        fname = frame.f_code.co_filename
        if fname.startswith(str(PKG)) and _frame_has_eta(frame):
            rel = str(pathlib.Path(fname).relative_to(PKG))
            if rel not in files:
                files.append(rel)
        frame = frame.f_back
    return files[::-1] + ["_kernel/driver.py"]


def trace(argv=None):
    """``(longest, union)``: the longest path of ``eta`` from the command line to a kernel
    call and the union of the files of all paths, in order of first appearance (file
    names relative to ``vibimpact/``)."""
    from vibimpact.cli import main

    boundary = str(PKG / "_kernel" / "boundary.py")
    paths = []

    def hook(frame, event, arg):
        if event == "call" and frame.f_code.co_filename == boundary and \
                frame.f_code.co_name in ("integrate", "benettin", "two_trajectory"):
            p = _path(frame)
            if p not in paths:
                paths.append(p)

    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "c.nc")
        args = argv or ["classify", "--eta", ETA_TEXT, "--workers", "1", "-o", out]
        sys.setprofile(hook)
        try:
            rc = main(args)
        finally:
            sys.setprofile(None)
    if rc not in (0, None):
        raise RuntimeError(f"vibimpact classify failed with exit code {rc}")
    if not paths:
        raise RuntimeError("no kernel call seen")
    union = []
    for p in paths:
        union += [f for f in p if f not in union]
    return max(paths, key=len), union


def main():
    longest, union = trace()
    print("longest path of eta from the command line to the kernel:")
    for k, f in enumerate(longest, 1):
        print(f"  {k}. vibimpact/{f}")
    print(f"eta passes through at most {len(longest)} files on its way to the kernel; "
          f"{len(union)} files on all its ways: {', '.join(union)}")


if __name__ == "__main__":
    main()
