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
the request, so a resumed run is identical to an uninterrupted one.  A new checkpoint
is made whole, its ``request.json`` in it, under a temporary name and renamed into
place: an interrupt never leaves a checkpoint without its request.

Files are read and written through a descriptor of the checkpoint directory itself
(:mod:`vibimpact.engine.ckdir`): a checkpoint that is, or becomes during the run, a
symbolic link, a file or another directory is refused naming what was found, and
nothing is read or written where a link points.  Only regular files are read (a FIFO
named like an entry does not block: it is set aside), and JSON is bounded in size and
depth (:mod:`vibimpact.base._json`).

Damaged checkpoints
-------------------
* ``request.json`` unreadable, not a regular file, not JSON (or nested too deep) or not
  a checkpoint record, or a directory that is not a checkpoint: :meth:`Checkpoint.open`
  raises ``ValueError`` naming it; nothing is guessed.
* An entry that cannot be read back completely (truncated, garbage, a foreign ``.npz``,
  a point result without the fields of its kind: *damaged*; a FIFO, a directory or a
  link named like an entry: *not a file*), that carries another request's fingerprint (*foreign*:
  copied from another
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
from pathlib import Path
from typing import Any

import numpy as np

from ..base import _json
from ..base._regular import NotRegular, open_regular
from ..base._text import count
from . import ckdir

log = logging.getLogger(__name__)

REQUEST = "request.json"
LAST_RESUME = "last_resume.json"
_ENTRY = re.compile(r"^(up|down|states)_(\d{6})_(\d{6})-(\d{6})\.npz$")
_META = ("fingerprint", "row", "direction", "position", "eta_index")


class SetAside(ValueError):
    """An entry that is not loaded; ``reason`` is "damaged", "foreign", "misplaced" or
    "special"."""

    def __init__(self, reason):
        super().__init__(reason)
        self.reason = reason


#: why an entry was set aside, in words
REASONS = {"damaged": "damaged", "foreign": "from another request",
           "misplaced": "indices not its own", "special": "not a regular file"}

#: the fields every point result of a checkpoint kind has (one without is damaged)
FIELDS = {"sweep": ("final_state", "regime"), "map": ("final_state", "regime"),
          "census": ("decided_by",),
          "orbits": ("lo", "hi", "lo_reason", "hi_reason", "stable", "values",
                     "stable_points", "impacts", "abs_max", "same_impacts")}


def fingerprint(request):
    """A stable hash of a JSON-able request description."""
    text = json.dumps(request, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def entry_name(row, direction, start, stop):
    return f"{direction}_{row:06d}_{start:06d}-{stop:06d}.npz"


def pack(points):
    """``{field: array}`` of a list of result dicts: a field every point has with one shape
    is stacked (``f:NAME``), any other is kept per point (``p<k>:NAME``)."""
    arrays = {}
    keys = set().union(*(r.keys() for r in points))
    for key in sorted(keys):
        vals = [np.asarray(r[key]) if key in r else None for r in points]
        every = [v for v in vals if v is not None]
        if len(every) == len(vals) and len({v.shape for v in every}) == 1 and \
                len({v.dtype.kind for v in every}) == 1:
            arrays[f"f:{key}"] = np.stack(every)
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
    points: list[dict[str, Any]] = [{} for _ in range(m)]
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
        self.fp: str | None = None
        self.n: int | None = None  # points per stream, once tied to a request
        # "sweep", "map", "census", "orbits": what a point result holds
        self.kind: str | None = None
        self._record = None  # request.json's bytes, to restore a vanished checkpoint
        self._ident = None  # (st_dev, st_ino) of the directory this run writes into

    # --- path level -----------------------------------------------------------------
    def exists(self):
        return os.path.lexists(self.path)

    def _shown(self):
        return repr(os.fspath(self.path))

    def _not_a_directory(self, found, during=False):
        """The refusal of a checkpoint path that holds ``found`` (:func:`ckdir.found_at`)
        instead of a directory (``during``: found so in the middle of the run)."""
        link = "not following a link out of the checkpoint: " \
            if found.startswith("a symbolic link") else ""
        if during:
            return ValueError(f"{self.what} {self._shown()} was replaced by {found} "
                              f"during the run; {link}the run stops")
        return ValueError(f"{self.what} {self._shown()} is {found}, not a directory; "
                          f"{link}remove it or choose another output")

    def check_reusable(self, resume):
        """ValueError unless a run may go ahead: ``path`` is absent, or (with ``resume``)
        a directory (not a symbolic link to one); without ``resume``, an existing
        checkpoint is a :class:`vibimpact.io.NeedsFlag` naming the flag ``resume``."""
        found = ckdir.found_at(self.path)
        if found is not None and found != "a directory":
            if found.startswith("a symbolic link"):
                raise self._not_a_directory(found)
            raise ValueError(f"checkpoint {self._shown()} exists and is not a "
                             f"directory ({found}); remove it")
        if found is not None and not resume:
            raise self._exists(f"checkpoint {self._shown()} exists")

    def _exists(self, refused):
        """The refusal of an existing checkpoint without ``resume``."""
        from ..io import NeedsFlag

        return NeedsFlag(f"{refused} (an interrupted run)", "resume",
                         "to continue it, or remove it")

    @staticmethod
    def _entries(fd):
        out = []
        for name in sorted(os.listdir(fd)):
            m = _ENTRY.match(name)
            if m:
                out.append((name, int(m[2]), m[1], int(m[3]), int(m[4])))
        return out

    def entries(self):
        """``[(name, row, direction, start, stop)]`` of the entry files now present (none
        where the path is not a directory)."""
        try:
            with ckdir.opened(self.path) as fd:
                return self._entries(fd)
        except (OSError, ValueError):
            return []

    def read_json(self, name):
        """The JSON file ``name`` of the checkpoint (a regular file, bounded, not through
        a link); ValueError or OSError if it cannot be read (not a regular file, too
        large or deep, not JSON, missing)."""
        with ckdir.opened(self.path) as fd:
            return _json.load_file(name, name, dir_fd=fd, follow=False)

    def write_file(self, name, data):
        """Write the file ``name`` (bytes) into the checkpoint, atomically, never through
        a symbolic link; OSError or ValueError if it cannot be."""
        with ckdir.opened(self.path) as fd:
            ckdir.write_atomic(fd, name, data)

    def _streams_shape(self):
        try:
            return int(self.read_json(REQUEST)["streams"]["points"])
        except Exception:
            return None

    def saved(self):
        """``(points, complete streams)`` in the entries now present (by their names):
        distinct grid points, so that overlapping entries or entries beyond the grid
        never count more points than the request has."""
        per: dict[tuple[int, str], set[int]] = {}
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
            rec = self.read_json(LAST_RESUME)
            return {k: rec.get(k, v) if k not in ("points", "streams", "damaged") else rec[k]
                    for k, v in empty.items()}
        except Exception:
            return empty

    def remove(self):
        shutil.rmtree(self.path, ignore_errors=True)  # a symbolic link is left alone

    # --- one request ----------------------------------------------------------------
    def open(self, kind, request, streams, resume):
        """Create the checkpoint of ``request`` or, with ``resume``, reopen it.

        A new checkpoint is made whole with its ``request.json`` (built under a
        temporary name beside it and renamed into place, :func:`ckdir.create`).

        Parameters
        ----------
        kind : {"sweep", "map", "census", "orbits"}
        request : dict
            JSON-able: everything the results depend on.
        streams : dict
            ``{"rows", "directions", "points"}``.
        resume : bool

        Raises
        ------
        ValueError
            ``path`` exists without ``resume`` (a :class:`vibimpact.io.NeedsFlag` naming
            the flag ``resume``), is not a checkpoint (a symbolic link or a file
            included), or belongs to a different request.
        """
        from ..base._writing import remove_dead_temporaries

        path, what = self.path, self.what
        self.fp = fingerprint(request)
        self.n = int(streams["points"])
        self.streams = streams
        self.kind = kind
        record = {"kind": kind, "fingerprint": self.fp, "request": request,
                  "streams": streams}
        data = json.dumps(record, sort_keys=True, default=str, indent=1).encode()
        if self.exists():
            if not resume:
                raise self._exists(f"{what} {path} already exists")
            self._check(kind)
            return self
        remove_dead_temporaries(os.fspath(path))  # a creation killed before its rename
        self._record = data
        st = ckdir.create(path, {REQUEST: data})
        self._ident = (st.st_dev, st.st_ino)
        return self

    def _check(self, kind):
        """Reopen the existing checkpoint; ValueError unless it is a directory (not a
        link) whose request.json records this request."""
        path, what = self.path, self.what
        try:
            fd, st = ckdir.dir_fd(path)
        except ckdir.Found as exc:
            raise self._not_a_directory(exc.found) from None
        except OSError as exc:
            raise ValueError(f"{what} {self._shown()} cannot be opened "
                             f"({exc.strerror or exc})") from None
        try:
            raw, old = self._request(fd, kind)
        finally:
            os.close(fd)
        if not isinstance(old, dict) or "fingerprint" not in old:
            raise ValueError(f"{what} {path}: {REQUEST} is not a vibimpact checkpoint "
                             "record")
        if old.get("kind", kind) != kind or old["fingerprint"] != self.fp:
            raise ValueError(f"{what} {path} belongs to a different {kind} request")
        self._record, self._ident = raw, (st.st_dev, st.st_ino)

    def _request(self, fd, kind):
        """``(bytes, value)`` of the request.json of the checkpoint directory ``fd``;
        ValueError if there is none or it cannot be read."""
        path, what = self.path, self.what
        try:
            raw = read_regular_request(fd)
            return raw, _json.loads(raw, REQUEST)
        except FileNotFoundError:
            raise ValueError(f"{what} {path} is not a vibimpact {kind} checkpoint (no "
                             f"readable {REQUEST}); remove it or choose another "
                             "output") from None
        except (OSError, ValueError) as exc:
            raise ValueError(f"{what} {path} has no readable {REQUEST} "
                             f"({getattr(exc, 'strerror', None) or exc})") from None

    def _dir_to_save(self):
        """The descriptor of the checkpoint directory to save into: this run's (made
        again with its request if it vanished).  ValueError naming what was found when
        it was replaced by a symbolic link, a file or another directory."""
        try:
            fd, st = ckdir.dir_fd(self.path)
        except ckdir.Found as exc:
            raise self._not_a_directory(exc.found, during=True) from None
        except FileNotFoundError:  # moved or removed while the run goes on
            ckdir.create(self.path, {REQUEST: self._record})
            log.warning("%s %s vanished during the run; recreated (the points saved "
                        "before are in the run's memory and its result)", self.what,
                        self.path)
            fd, st = ckdir.dir_fd(self.path)
        if self._ident is not None and (st.st_dev, st.st_ino) != self._ident:
            try:
                same = read_regular_request(fd) == self._record
            except (OSError, ValueError):
                same = False
            if not same:
                os.close(fd)
                raise ValueError(f"{self.what} {self._shown()} was replaced by another "
                                 f"directory during the run (without this run's "
                                 f"{REQUEST}); the run stops")
        self._ident = (st.st_dev, st.st_ino)
        return fd

    def save(self, row, direction, points):
        """Write one entry: ``points`` is ``[(position, result)]``, contiguous."""
        assert self.n is not None  # tied to a request (open)
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
                with ckdir.opened(self.path) as fd:
                    self._record = read_regular_request(fd)
            fd = self._dir_to_save()
            try:
                ckdir.write_atomic(fd, name, buf.getvalue())
            finally:
                os.close(fd)
        except OSError as exc:  # a full disk, a read-only file system
            raise OSError(exc.errno, f"cannot save to {self.what} {self._shown()}"
                          f": {exc.strerror or exc}") from None

    def _read(self, fd, name, row, direction, start, stop):
        assert self.n is not None  # tied to a request (open, attach)
        try:
            efd = open_regular(name, name, dir_fd=fd, follow=False)
        except NotRegular:
            raise SetAside("special") from None
        with os.fdopen(efd, "rb") as fh, np.load(fh, allow_pickle=False) as z:
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
        if not all(self._whole(r) for r in points):
            raise SetAside("damaged")
        return dict(zip(pos.tolist(), points))

    def _whole(self, result):
        """Whether a loaded point result has the fields of its kind (:data:`FIELDS`); a
        sweep's or a map's final state is a vector."""
        need = FIELDS.get(self.kind, ()) if self.kind is not None else ()
        if any(k not in result for k in need):
            return False
        return "final_state" not in need or np.ndim(result["final_state"]) == 1

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
        self.kind = record.get("kind")
        return record

    def load(self, resume=True):
        """``{(row, direction): {position: result}}`` of every readable entry.

        With ``resume``, entries set aside (damaged, foreign, misplaced or not a regular
        file) are renamed ``<name>.corrupt`` and what was loaded and set aside is
        written to ``last_resume.json``; without, they are only skipped (a look at a
        running checkpoint changes nothing).
        """
        done: dict[tuple[int, str], dict[int, dict[str, Any]]] = {}
        aside = []
        try:
            fd, _ = ckdir.dir_fd(self.path)
        except ckdir.Found as exc:
            raise self._not_a_directory(exc.found) from None
        try:
            for name, row, d, a, b in self._entries(fd):
                try:
                    points = self._read(fd, name, row, d, a, b)
                except Exception as exc:  # BadZipFile, EOFError, OSError, KeyError, ...
                    aside.append((name, getattr(exc, "reason", "damaged"), row, d, a, b))
                    if resume:
                        try:
                            os.replace(name, name + ".corrupt", src_dir_fd=fd,
                                       dst_dir_fd=fd)
                        except OSError:
                            pass
                    continue
                done.setdefault((row, d), {}).update(points)
            if resume:
                self._record_resume(fd, done, aside)
        finally:
            os.close(fd)
        return done

    def _record_resume(self, fd, done, aside):
        """Write ``last_resume.json``: what :meth:`load` loaded and set aside, and how many
        points (streams) of the request are computed again because of the latter."""
        assert self.n is not None  # tied to a request (open, attach)
        npts = sum(len(v) for v in done.values())
        full = sum(1 for v in done.values() if len(v) == self.n)
        again: set[tuple[int, str, int]] = set()
        streams: set[tuple[int, str]] = set()
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
        ckdir.write_atomic(fd, LAST_RESUME, json.dumps(rec).encode())
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
    shown = [f"{name[:-len('.corrupt')]}: {REASONS.get(reasons.get(name, ''), 'damaged')}"
             for name in bad[:3]]
    more = ", ..." if len(bad) > 3 else ""
    key = "recomputed_points" if unit == "points" else "recomputed_streams"
    k = int(last.get(key, 0))
    again = f"their {count(k, unit[:-1])} {'was' if k == 1 else 'were'} computed again" \
        if k else f"none of their {unit} needed computing again"
    return (f"vibimpact: warning: {count(len(bad), unit[:-1] + ' file')} in {where} "
            f"{'was' if len(bad) == 1 else 'were'} set aside as *.corrupt "
            f"({'; '.join(shown)}{more}); {again}")


def read_regular_request(fd):
    """The bytes of ``request.json`` in the checkpoint directory ``fd`` (a regular file,
    bounded, not a link)."""
    from ..base._regular import read_regular

    return read_regular(REQUEST, REQUEST, _json.MAX_BYTES, dir_fd=fd, follow=False)


def read_record(path):
    """The ``request.json`` record of a checkpoint directory: a dict with a
    ``fingerprint`` and the ``streams`` (``points``); ValueError naming ``path`` and why
    not (not a directory, a symbolic link, no readable or too deep ``request.json``)."""
    shown = repr(os.fspath(path))
    try:
        with ckdir.opened(path) as fd:
            record = _json.load_file(REQUEST, f"its {REQUEST}", dir_fd=fd, follow=False)
    except FileNotFoundError:
        raise ValueError(f"{shown} is not a vibimpact checkpoint (no {REQUEST})") from None
    except ckdir.Found as exc:
        raise ValueError(f"{shown} is not a vibimpact checkpoint: it is {exc.found}") \
            from None
    except (OSError, ValueError) as exc:
        raise ValueError(f"{shown} is not a vibimpact checkpoint: "
                         f"{getattr(exc, 'strerror', None) or exc}") from None
    streams = record.get("streams") if isinstance(record, dict) else None
    points = streams.get("points") if isinstance(streams, dict) else None
    if not isinstance(record.get("fingerprint") if isinstance(record, dict) else None,
                      str) or not isinstance(points, int) or isinstance(points, bool) \
            or points < 1:
        raise ValueError(f"{shown} is not a vibimpact checkpoint: its {REQUEST} is not a "
                         "checkpoint record")
    return record


def is_checkpoint(path):
    """Whether ``path`` is a directory (not a link) holding a regular ``request.json``."""
    import stat

    try:
        with ckdir.opened(path) as fd:
            st = os.stat(REQUEST, dir_fd=fd, follow_symlinks=False)
    except (OSError, ValueError):
        return False
    return stat.S_ISREG(st.st_mode)
