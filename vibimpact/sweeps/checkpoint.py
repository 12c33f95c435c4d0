"""Checkpoints of a sweep: one small file per finished point, written atomically.

A checkpoint is a directory holding ``request.json`` (a fingerprint of the request, so a
resume never mixes two different sweeps) and ``<direction>_<index>.npz`` per finished
point.  Each file is written to a temporary name and renamed, so a point is either
completely on disk or absent: a sweep killed at any moment (Ctrl-C, SIGKILL) loses at
most the points in flight.
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


def load_point(path, direction, index):
    """A finished point's result dict, or None."""
    f = point_file(path, direction, index)
    if not f.exists():
        return None
    with np.load(f, allow_pickle=False) as z:
        out = {}
        for k in z.files:
            v = z[k]
            if k in SCALARS:
                out[k] = v.item()
            elif v.dtype.kind == "U":
                out[k] = str(v)
            else:
                out[k] = v
        return out
