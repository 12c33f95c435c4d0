"""Checkpoints of a sweep: one small file per finished point, written atomically.

A checkpoint is a directory holding ``request.json`` (a fingerprint of the request, so a
resume never mixes two different sweeps) and ``<direction>_<index>.npz`` per finished
point.  Each file is written to a temporary name and renamed, so a point is either
completely on disk or absent: a sweep killed at any moment (Ctrl-C, SIGKILL) loses at
most the points in flight.

Damaged checkpoints
-------------------
* ``request.json`` unreadable, not JSON, or not a fingerprint record: :func:`open_checkpoint`
  raises ``ValueError`` naming the file (the CLI reports it as one line, exit status 2).
  Nothing is guessed: without the fingerprint a resume could mix two sweeps.
* A point file that cannot be read back completely (truncated, garbage, a foreign ``.npz``
  without the fields of a point, a directory in its place) can only come from a damaged
  disk or a hand edit, since points are written atomically.  It is treated as **not done**:
  :func:`load_point` renames it to ``<name>.corrupt`` (kept as evidence, no longer counted
  as a saved point) and returns None, so the point is recomputed and saved again.  Every
  point is a deterministic function of the request, so the resumed result is still
  identical to an uninterrupted run.  :func:`corrupt_files` lists the renamed files.
"""
from __future__ import annotations

import hashlib
import io
import json
import os
import tempfile
from pathlib import Path

import numpy as np

from .point import SCALARS


def fingerprint(request):
    """A stable hash of a JSON-able request description."""
    text = json.dumps(request, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def open_checkpoint(path, request, resume):
    """Create (or, with ``resume``, reopen) a checkpoint directory.

    Raises
    ------
    ValueError
        ``checkpoint`` exists without ``resume``, or belongs to a different request.
    """
    path = Path(path)
    meta = path / "request.json"
    fp = fingerprint(request)
    if path.exists():
        if not resume:
            raise ValueError(f"checkpoint {path} already exists: pass resume=True "
                             "(--resume) to continue it, or remove it")
        try:
            old = json.loads(meta.read_text())
        except (OSError, ValueError):
            raise ValueError(f"checkpoint {path} has no readable request.json") from None
        if not isinstance(old, dict) or "fingerprint" not in old:
            raise ValueError(f"checkpoint {path}: {meta.name} is not a vibimpact checkpoint "
                             "record") from None
        if old.get("fingerprint") != fp:
            raise ValueError(f"checkpoint {path} belongs to a different sweep request")
        return path
    path.mkdir(parents=True)
    _atomic_write_bytes(meta, json.dumps({"fingerprint": fp, "request": request},
                                         sort_keys=True, default=str, indent=1).encode())
    return path


def _atomic_write_bytes(target, data):
    fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=".tmp-", suffix=target.suffix)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, target)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def point_file(path, direction, index):
    return Path(path) / f"{direction}_{index:06d}.npz"


def save_point(path, direction, index, result):
    """Write one finished point atomically."""
    buf = io.BytesIO()
    np.savez(buf, **{k: np.asarray(v) for k, v in result.items()})
    _atomic_write_bytes(point_file(path, direction, index), buf.getvalue())


#: fields every saved point has besides :data:`SCALARS`
_REQUIRED = ("final_state", "orbit_point", "samples", "arcs", "reason")


def _read_point(f):
    with np.load(f, allow_pickle=False) as z:
        missing = [k for k in (*SCALARS, *_REQUIRED) if k not in z.files]
        if missing:
            raise ValueError(f"missing fields {missing}")
        out = {}
        for k in z.files:
            v = z[k]
            if k in SCALARS:
                out[k] = v.item()
            elif v.dtype.kind == "U":
                out[k] = str(v)
            else:
                out[k] = v
    if np.shape(out["final_state"]) != (4,) or np.ndim(out["samples"]) != 2:
        raise ValueError("bad shapes")
    return out


def load_point(path, direction, index):
    """A finished point's result dict, or None when it is not done.

    A damaged point file is renamed to ``<name>.corrupt`` and reported as not done (see
    the module docstring), so the point is recomputed.
    """
    f = point_file(path, direction, index)
    if not f.exists():
        return None
    try:
        return _read_point(f)
    except Exception:  # zipfile.BadZipFile, EOFError, OSError, ValueError, KeyError, ...
        set_aside(f)
        return None


def set_aside(f):
    """Rename a damaged checkpoint file ``f`` to ``f.corrupt`` (see :func:`corrupt_files`)."""
    try:
        os.replace(f, f.with_name(f.name + ".corrupt"))
    except OSError:
        pass


def corrupt_files(path):
    """Names of the damaged point (or map row) files set aside by :func:`set_aside`."""
    try:
        return sorted(n for n in os.listdir(path) if n.endswith(".npz.corrupt"))
    except OSError:
        return []
