"""The checkpoint of a sweep or a map: one directory, one file per saved entry.

Layout
------
``request.json``
    ``{"kind", "fingerprint", "request", "streams"}``: the kind ("sweep" or "map"), the
    fingerprint of everything the results depend on (a resume never mixes two requests),
    the request itself (readable; a map's partial view is rebuilt from it) and the shape
    of the streams (rows, directions, points per stream).
``<direction>_<row>_<start>-<stop>.npz``
    An *entry*: finished points ``start .. stop - 1`` (sweep order) of the stream
    ``(row, direction)``, each point the result dict of
    :func:`vibimpact.points.point.analyse_point` (stacked field by field), with the
    request's fingerprint and its own indices (row, direction, positions, grid indices).
    A sweep saves every point as its own entry the moment it is finished; a map saves one
    entry per row.
``last_resume.json``
    What the last resume loaded: points, complete streams, the entries set aside (with
    why: damaged, another request's, or misplaced) and the points and streams computed
    again because of them.

Every file is written to a temporary name, flushed and renamed, so an entry is either
completely on disk or absent: a run killed at any moment (Ctrl-C, SIGKILL, a lost
cluster) loses only the points in flight, and every point is a deterministic function of
the request, so a resumed run is identical to an uninterrupted one.

Damaged checkpoints
-------------------
* ``request.json`` unreadable, not JSON or not a checkpoint record, or a directory that
  is not a checkpoint: :meth:`Checkpoint.open` raises ``ValueError`` naming it; nothing
  is guessed.
* An entry that cannot be read back completely (truncated, garbage, a foreign ``.npz``:
  *damaged*), that carries another request's fingerprint (*foreign*: copied from another
  sweep or map), or whose own indices (row, direction, positions, grid indices) are not
  those of its name or lie outside the request (*misplaced*) can only come from a damaged
  disk or a hand edit: it is renamed ``<name>.corrupt`` (kept as evidence), its points
  count as not done and are computed again, and the last resume lists it with its reason
  and the number of points (streams) that were computed again because of it
  (:func:`set_aside_line` says it in one line).
"""
from __future__ import annotations

import hashlib
import io
import json
import logging
import os
import re
import shutil
import tempfile
from pathlib import Path

import numpy as np

from .._text import count

log = logging.getLogger(__name__)

REQUEST = "request.json"
LAST_RESUME = "last_resume.json"
_ENTRY = re.compile(r"^(up|down|states)_(\d{6})_(\d{6})-(\d{6})\.npz$")
_META = ("fingerprint", "row", "direction", "position", "eta_index")


class SetAside(ValueError):
    """An entry that is not loaded; ``reason`` is "damaged", "foreign" or "misplaced"."""

    def __init__(self, reason):
        super().__init__(reason)
        self.reason = reason


#: why an entry was set aside, in words
REASONS = {"damaged": "damaged", "foreign": "from another request",
           "misplaced": "indices not its own"}


def fingerprint(request):
    """A stable hash of a JSON-able request description."""
    text = json.dumps(request, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def entry_name(row, direction, start, stop):
    return f"{direction}_{row:06d}_{start:06d}-{stop:06d}.npz"


def _atomic_write(target, data):
    target = Path(target)
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


def pack(points):
    """``{field: array}`` of a list of result dicts: a field every point has with one shape
    is stacked (``f:NAME``), any other is kept per point (``p<k>:NAME``)."""
    arrays = {}
    keys = set().union(*(r.keys() for r in points))
    for key in sorted(keys):
        vals = [np.asarray(r[key]) if key in r else None for r in points]
        if all(v is not None for v in vals) and len({v.shape for v in vals}) == 1 and \
                len({v.dtype.kind for v in vals}) == 1:
            arrays[f"f:{key}"] = np.stack(vals)
        else:
            for k, v in enumerate(vals):
                if v is not None:
                    arrays[f"p{k}:{key}"] = v
    return arrays


def _value(v):
    """An array element back as it was saved: 0-d -> Python scalar or str."""
    if v.ndim == 0:
        return str(v) if v.dtype.kind == "U" else v.item()
    return v


def unpack(arrays, m):
    """The ``m`` result dicts of :func:`pack`'s arrays."""
    points = [{} for _ in range(m)]
    for name, arr in arrays.items():
        head, _, key = name.partition(":")
        if head == "f":
            if arr.shape[0] != m:
                raise ValueError(f"{key}: {count(arr.shape[0], 'point')}, expected {m}")
            for k in range(m):
                points[k][key] = _value(arr[k])
        elif head.startswith("p"):
            points[int(head[1:])][key] = _value(arr)
    return points


class Checkpoint:
    """The checkpoint directory ``path``: its lifecycle (open, resume, count, clean up).

    The path-level questions (:meth:`exists`, :meth:`saved`, :meth:`last_resume`,
    :meth:`remove`) need no request; :meth:`open` ties the handle to one request before
    entries are loaded (:meth:`load`) or saved (:meth:`save`).
    """

    def __init__(self, path, what="checkpoint"):
        self.path = Path(path)
        self.what = what  # "checkpoint" or "map checkpoint", in messages
        self.fp = None
        self.n = None
        self._record = None  # request.json's bytes, to restore a vanished checkpoint

    # --- path level -----------------------------------------------------------------
    def exists(self):
        return os.path.lexists(self.path)

    def check_reusable(self, resume):
        """ValueError unless a run may go ahead: ``path`` is absent, or (with ``resume``)
        a directory; without ``resume``, an existing checkpoint is a
        :class:`vibimpact.io.NeedsFlag` naming the flag ``resume``."""
        if self.exists() and not self.path.is_dir():
            raise ValueError(f"checkpoint {os.fspath(self.path)!r} exists and is not a "
                             "directory; remove it")
        if self.exists() and not resume:
            raise self._exists(f"checkpoint {os.fspath(self.path)!r} exists")

    def _exists(self, refused):
        """The refusal of an existing checkpoint without ``resume``."""
        from ..io import NeedsFlag

        return NeedsFlag(f"{refused} (an interrupted run)", "resume",
                         "to continue it, or remove it")

    def entries(self):
        """``[(name, row, direction, start, stop)]`` of the entry files now present."""
        try:
            names = sorted(os.listdir(self.path))
        except OSError:
            return []
        out = []
        for name in names:
            m = _ENTRY.match(name)
            if m:
                out.append((name, int(m[2]), m[1], int(m[3]), int(m[4])))
        return out

    def _streams_shape(self):
        try:
            return json.loads((self.path / REQUEST).read_text())["streams"]["points"]
        except Exception:
            return None

    def saved(self):
        """``(points, complete streams)`` in the entries now present (by their names):
        distinct grid points, so that overlapping entries or entries beyond the grid
        never count more points than the request has."""
        per = {}
        n = self._streams_shape()
        for _, row, d, a, b in self.entries():
            stop = b if n is None else min(b, int(n))
            per.setdefault((row, d), set()).update(range(a, stop))
        return (sum(len(v) for v in per.values()),
                sum(1 for v in per.values() if n is not None and len(v) == n))

    def last_resume(self):
        """``{"points", "streams", "damaged", "reasons", "recomputed_points",
        "recomputed_streams"}`` of the last resume (zeros if none)."""
        empty = {"points": 0, "streams": 0, "damaged": [], "reasons": {},
                 "recomputed_points": 0, "recomputed_streams": 0}
        try:
            rec = json.loads((self.path / LAST_RESUME).read_text())
            return {k: rec.get(k, v) if k not in ("points", "streams", "damaged") else rec[k]
                    for k, v in empty.items()}
        except Exception:
            return empty

    def remove(self):
        shutil.rmtree(self.path, ignore_errors=True)

    # --- one request ----------------------------------------------------------------
    def open(self, kind, request, streams, resume):
        """Create the checkpoint of ``request`` or, with ``resume``, reopen it.

        Parameters
        ----------
        kind : {"sweep", "map"}
        request : dict
            JSON-able: everything the results depend on.
        streams : dict
            ``{"rows", "directions", "points"}``.
        resume : bool

        Raises
        ------
        ValueError
            ``path`` exists without ``resume`` (a :class:`vibimpact.io.NeedsFlag` naming
            the flag ``resume``), is not a checkpoint, or belongs to a different
            request.
        """
        path, what = self.path, self.what
        self.fp = fingerprint(request)
        self.n = int(streams["points"])
        self.streams = streams
        if self.exists():
            if not resume:
                raise self._exists(f"{what} {path} already exists")
            self._check(kind)
            return self
        path.mkdir(parents=True)
        record = {"kind": kind, "fingerprint": self.fp, "request": request,
                  "streams": streams}
        _atomic_write(path / REQUEST, json.dumps(record, sort_keys=True, default=str,
                                                 indent=1).encode())
        return self

    def _check(self, kind):
        path, what = self.path, self.what
        meta = path / REQUEST
        if not path.is_dir() or not meta.is_file():
            raise ValueError(f"{what} {path} is not a vibimpact {kind} checkpoint (no "
                             f"readable {REQUEST}); remove it or choose another output")
        try:
            old = json.loads(meta.read_text())
        except (OSError, ValueError):
            raise ValueError(f"{what} {path} has no readable {REQUEST}") from None
        if not isinstance(old, dict) or "fingerprint" not in old:
            raise ValueError(f"{what} {path}: {REQUEST} is not a vibimpact checkpoint "
                             "record")
        if old.get("kind", kind) != kind or old["fingerprint"] != self.fp:
            raise ValueError(f"{what} {path} belongs to a different {kind} request")

    def save(self, row, direction, points):
        """Write one entry: ``points`` is ``[(position, result)]``, contiguous."""
        pos = np.array([i for i, _ in points], dtype=np.int64)
        arrays = pack([r for _, r in points])
        arrays.update(fingerprint=np.array(self.fp), row=np.array(row, dtype=np.int64),
                      direction=np.array(direction), position=pos,
                      eta_index=pos if direction == "up" else self.n - 1 - pos)
        buf = io.BytesIO()
        np.savez_compressed(buf, **arrays)
        name = entry_name(row, direction, int(pos[0]), int(pos[-1]) + 1)
        try:
            if self._record is None:
                self._record = (self.path / REQUEST).read_bytes()
            if not self.path.is_dir():  # moved or removed while the run goes on
                self.path.mkdir(parents=True)
                _atomic_write(self.path / REQUEST, self._record)
                log.warning("%s %s vanished during the run; recreated (the points saved "
                            "before are in the run's memory and its result)", self.what,
                            self.path)
            _atomic_write(self.path / name, buf.getvalue())
        except OSError as exc:  # a full disk, a read-only file system
            raise OSError(exc.errno, f"cannot save to {self.what} {os.fspath(self.path)!r}"
                          f": {exc.strerror or exc}") from None

    def _read(self, name, row, direction, start, stop):
        with np.load(self.path / name, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
        if any(k not in arrays for k in _META):
            raise SetAside("damaged")
        if str(arrays["fingerprint"]) != self.fp:
            raise SetAside("foreign")
        pos = np.arange(start, stop)
        grid = pos if direction == "up" else self.n - 1 - pos
        if int(arrays["row"]) != row or str(arrays["direction"]) != direction or \
                not np.array_equal(arrays["position"], pos) or \
                not np.array_equal(arrays["eta_index"], grid) or \
                not self._inside(row, direction, stop):
            raise SetAside("misplaced")
        try:
            points = unpack({k: v for k, v in arrays.items() if k not in _META}, pos.size)
        except (ValueError, IndexError):
            raise SetAside("damaged") from None
        for r in points:  # a census start's result (census.reach) has no final state
            if "decided_by" not in r and (np.ndim(r.get("final_state")) != 1 or
                                          "regime" not in r):
                raise SetAside("damaged")
        return dict(zip(pos.tolist(), points))

    def _inside(self, row, direction, stop):
        """Whether entry points ``.. stop - 1`` of stream ``(row, direction)`` lie in the
        request's streams."""
        streams = getattr(self, "streams", None) or {}
        rows = int(streams.get("rows", row + 1))
        dirs = streams.get("directions", [direction])
        return 0 < stop <= self.n and 0 <= row < rows and direction in dirs

    def attach(self):
        """Tie the handle to the request recorded in the checkpoint (to look at it)."""
        record = read_record(self.path)
        self.fp = record["fingerprint"]
        self.n = int(record["streams"]["points"])
        self.streams = record["streams"]
        return record

    def load(self, resume=True):
        """``{(row, direction): {position: result}}`` of every readable entry.

        With ``resume``, entries set aside (damaged, foreign or misplaced) are renamed
        ``<name>.corrupt`` and what was loaded and set aside is written to
        ``last_resume.json``; without, they are only skipped (a look at a running
        checkpoint changes nothing).
        """
        done, aside = {}, []
        for name, row, d, a, b in self.entries():
            try:
                points = self._read(name, row, d, a, b)
            except Exception as exc:  # BadZipFile, EOFError, OSError, KeyError, ...
                aside.append((name, getattr(exc, "reason", "damaged"), row, d, a, b))
                if resume:
                    try:
                        os.replace(self.path / name, self.path / (name + ".corrupt"))
                    except OSError:
                        pass
                continue
            done.setdefault((row, d), {}).update(points)
        if resume:
            self._record_resume(done, aside)
        return done

    def _record_resume(self, done, aside):
        """Write ``last_resume.json``: what :meth:`load` loaded and set aside, and how many
        points (streams) of the request are computed again because of the latter."""
        npts = sum(len(v) for v in done.values())
        full = sum(1 for v in done.values() if len(v) == self.n)
        again, streams = set(), set()
        for _, _, row, d, a, b in aside:
            if not self._inside(row, d, min(b, self.n)) or a >= min(b, self.n):
                continue  # outside the request: it stood for none of its points
            have = done.get((row, d), {})
            again.update((row, d, i) for i in range(a, min(b, self.n)) if i not in have)
            if len(have) < self.n:
                streams.add((row, d))
        rec = {"points": npts, "streams": full,
               "damaged": [name + ".corrupt" for name, *_ in aside],
               "reasons": {name + ".corrupt": why for name, why, *_ in aside},
               "recomputed_points": len(again), "recomputed_streams": len(streams)}
        _atomic_write(self.path / LAST_RESUME, json.dumps(rec).encode())
        log.info("checkpoint %s: %d points loaded, %d entries set aside", self.path, npts,
                 len(aside))


def set_aside_line(last, where, unit="points"):
    """The one warning line about the entries a resume set aside, or None if none was.

    Parameters
    ----------
    last : dict
        :meth:`Checkpoint.last_resume`.
    where : str
        The checkpoint, as the message names it.
    unit : {"points", "rows"}
        What the run counts: points of a sweep, rows of a map.

    Returns
    -------
    str or None
        E.g. ``"vibimpact: warning: 2 point files in c.nc.partial were set aside as
        *.corrupt (up_000000_000004-000005.npz: from another request; ...); their 1 point
        was computed again"``.
    """
    bad = last.get("damaged") or []
    if not bad:
        return None
    reasons = last.get("reasons") or {}
    shown = [f"{name[:-len('.corrupt')]}: {REASONS.get(reasons.get(name), 'damaged')}"
             for name in bad[:3]]
    more = ", ..." if len(bad) > 3 else ""
    key = "recomputed_points" if unit == "points" else "recomputed_streams"
    k = int(last.get(key, 0))
    again = f"their {count(k, unit[:-1])} {'was' if k == 1 else 'were'} computed again" \
        if k else f"none of their {unit} needed computing again"
    return (f"vibimpact: warning: {count(len(bad), unit[:-1] + ' file')} in {where} "
            f"{'was' if len(bad) == 1 else 'were'} set aside as *.corrupt "
            f"({'; '.join(shown)}{more}); {again}")


def read_record(path):
    """The ``request.json`` record of a checkpoint directory (ValueError if none)."""
    try:
        return json.loads((Path(path) / REQUEST).read_text())
    except (OSError, ValueError):
        raise ValueError(f"{os.fspath(path)!r} is not a vibimpact checkpoint") from None


def is_checkpoint(path):
    return (Path(path) / REQUEST).is_file()
