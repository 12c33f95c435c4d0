"""A map's row checkpoint: a Zarr store that the finished rows are written into.

While a map is computed, its checkpoint (``OUT.partial`` for ``vibimpact map -o OUT``)
is a Zarr (format 3) store laid out like the final map: every variable of the map
dataset with its dimensions ``(direction, PARAM, eta, ...)`` (no ``direction`` for a
one-way map), every point "not computed" at first, plus

* ``row_done`` (int8, dims ``(direction, PARAM)``): 1 once a row is completely written;
* ``row_damaged`` (int8, same dims): 1 for the rows that the last resume found
  unreadable and computed again;
* the attribute ``vibimpact_map_checkpoint``: a JSON record of the request (but its
  grids, which are the coordinates) and the fingerprint of the whole request, so a
  resume never mixes two maps.

Every finished row is written at once, by the process that submitted the rows (the Dask
*client*, so the workers need no shared file system): its values into the row's own
chunks (one row per chunk, so writing a row touches no other row), then its
``row_done`` flag.  A run killed at any moment (Ctrl-C, SIGKILL, a lost cluster) loses
only the rows in flight: a row whose values were being written has no flag yet and is
recomputed by a resume.  The chunks carry a zstd checksum, so a chunk that was cut short
or altered (a damaged disk, a hand edit) fails to decode: the row is then computed again
and counted in ``row_damaged``.  Every row is a deterministic function of the request,
so a resumed map is identical to an uninterrupted one.

The checkpoint can be opened while the map runs, with ``xarray.open_zarr(path,
consolidated=False)`` or :func:`vibimpact.maps.open_map`, to look at the rows finished
so far (``row_done == 1``; the others hold the "not computed" values).
"""
from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np

from ..sweeps.checkpoint import fingerprint

#: attribute holding the request record
ATTR = "vibimpact_map_checkpoint"
#: flag variables of the rows
DONE, DAMAGED = "row_done", "row_damaged"


def _not_a_checkpoint(path, why):
    return ValueError(f"map checkpoint {os.fspath(path)} is not a vibimpact map checkpoint "
                      f"({why}); remove it or choose another output")


class RowStore:
    """The row checkpoint of one map request (see the module docstring).

    Use :meth:`open`; ``at`` below is a row's index in the leading dimensions,
    ``(direction_index, row)`` for a two-way map, ``(row,)`` otherwise.

    Attributes
    ----------
    path : pathlib.Path
    damaged : list of tuple
        The ``at`` of the rows that :meth:`load` found unreadable.
    """

    def __init__(self, path, group, names):
        self.path = Path(path)
        self._group = group
        self._arrays = {k: group[k] for k in names}
        self._done = group[DONE]
        self.damaged = []
        try:  # zarr's own bridge from its synchronous API to its event loop
            from zarr.core.sync import sync

            self._async = {k: a.async_array for k, a in self._arrays.items()}
            self._sync = sync
        except (ImportError, AttributeError):  # then one array after the other
            self._async = None

    @classmethod
    def open(cls, path, template, request, resume):
        """Create the checkpoint of ``template`` at ``path`` or, with ``resume``, reopen it.

        Parameters
        ----------
        path : str or os.PathLike
        template : xarray.Dataset
            The map with every point "not computed"; its first dimensions (``direction``
            if present, then the varied parameter) index the rows, ``eta`` follows.
        request : dict
            JSON-able description of everything the rows depend on.
        resume : bool

        Returns
        -------
        RowStore

        Raises
        ------
        ValueError
            ``path`` exists without ``resume``, is not a map checkpoint, or belongs to a
            different request.
        """
        import zarr

        path = Path(path)
        fp = fingerprint(request)
        names = list(template.data_vars)
        if os.path.lexists(path):
            if not resume:
                raise ValueError(f"map checkpoint {path} already exists: pass resume=True "
                                 "(--resume) to continue it, or remove it")
            if not (path / "zarr.json").is_file():
                raise _not_a_checkpoint(path, "no zarr.json")
            try:
                group = zarr.open_group(path, mode="r+", zarr_format=3)
                record = json.loads(group.attrs[ATTR])
                fp_old = record["fingerprint"]
                missing = [k for k in names + [DONE, DAMAGED] if k not in group]
            except Exception as exc:  # KeyError, ValueError, zarr's own errors
                raise _not_a_checkpoint(path, f"{type(exc).__name__}: {exc}") from None
            if missing:
                raise _not_a_checkpoint(path, f"no variable {missing[0]!r}")
            if fp_old != fp:
                raise ValueError(f"map checkpoint {path} belongs to a different map request")
            return cls(path, group, names)
        path.parent.mkdir(parents=True, exist_ok=True)
        # the grids are the store's coordinates: the record keeps the rest, readable
        brief = {k: v for k, v in request.items() if k not in ("eta", "values")}
        _create(path, template, {"kind": "map", "fingerprint": fp, "request": brief})
        return cls(path, zarr.open_group(path, mode="r+", zarr_format=3), names)

    def save(self, at, arrays):
        """Write one finished row (``{variable: values along eta}``), then its flag.

        The variables' chunks are written concurrently, in one call into zarr's event
        loop (0.6x the CPU time of one call per variable).
        """
        if self._async is None:
            for k, arr in self._arrays.items():
                arr[at] = arrays[k]
        else:
            self._sync(_gather([a.setitem(at, arrays[k]) for k, a in self._async.items()]))
        self._done[at] = 1

    def load(self, at, shapes):
        """A saved row's ``{variable: values}``, or None when it is not done.

        Parameters
        ----------
        at : tuple of int
        shapes : dict
            ``{variable: (shape, dtype)}`` of one row.

        A row flagged done whose values cannot be read back (or have another shape or
        type) is reported as not done and remembered in :attr:`damaged`.
        """
        try:
            if int(self._done[at]) != 1:
                return None
        except Exception:  # a damaged flag: the row is not known to be done
            return None
        try:
            out = {}
            for k, (shape, dtype) in shapes.items():
                v = np.asarray(self._arrays[k][at])
                if v.shape != shape:
                    raise ValueError(f"{k}: shape {v.shape}")
                if dtype == object:
                    if v.dtype.kind not in "UTO" and "String" not in type(v.dtype).__name__:
                        raise ValueError(f"{k}: dtype {v.dtype}")
                    v = np.array(v.tolist(), dtype=object)
                elif v.dtype != dtype:
                    raise ValueError(f"{k}: dtype {v.dtype}")
                out[k] = v
        except Exception:  # zarr/zstd decode errors, ValueError, ...
            self.damaged.append(tuple(at))
            return None
        return out

    def record_damaged(self):
        """Store :attr:`damaged` in ``row_damaged`` (one write, replacing the last one's)."""
        flags = np.zeros(self._group[DAMAGED].shape, dtype=np.int8)
        for at in self.damaged:
            flags[at] = 1
        self._group[DAMAGED][...] = flags


async def _gather(coroutines):
    import asyncio

    await asyncio.gather(*coroutines)


def _fill(values):
    """The value every element of ``values`` holds, or None when they differ."""
    first = values.flat[0]
    if values.dtype.kind == "f" and np.isnan(first):
        same = np.isnan(values).all()
    else:
        same = bool((values == first).all())
    return first if same else None


def _create(path, template, record):
    """Write the empty checkpoint into a temporary directory, then rename it to ``path``."""
    import warnings

    import xarray as xr
    from zarr.codecs import ZstdCodec

    lead = template["regime"].dims[:-1]  # (direction,) name
    shape = tuple(template.sizes[d] for d in lead)
    ds = template.copy()
    flag = dict(long_name="row completely written", flag_values="0 1")
    ds[DONE] = (lead, np.zeros(shape, dtype=np.int8), flag)
    ds[DAMAGED] = (lead, np.zeros(shape, dtype=np.int8),
                   dict(long_name="row found damaged by the last resume and recomputed"))
    ds.attrs = dict(template.attrs, **{ATTR: json.dumps(record, sort_keys=True,
                                                        default=str)})
    enc = {}
    for name in list(ds.variables):
        ds[name].encoding = {}
    fills = {name: _fill(var.values) for name, var in ds.data_vars.items()}
    for name, var in ds.data_vars.items():
        per_row = (1,) * len(lead) + var.shape[len(lead):]
        enc[name] = {"chunks": var.shape if name == DAMAGED else per_row,
                     "compressors": (ZstdCodec(level=1, checksum=True),)}
        if fills[name] is not None:
            enc[name]["fill_value"] = fills[name]
    # every variable holds one "not computed" value, its Zarr fill value: then only the
    # metadata need writing (chunks never written read as the fill value)
    lazy = all(f is not None for f in fills.values())
    directory = path.parent
    tmp = tempfile.mkdtemp(prefix="." + path.name + ".", suffix=".tmp", dir=directory)
    try:
        with warnings.catch_warnings():  # strings are inferred from the in-memory values
            warnings.simplefilter("ignore", xr.SerializationWarning)
            (ds.chunk() if lazy else ds).to_zarr(tmp, mode="w", consolidated=False,
                                                 zarr_format=3, encoding=enc,
                                                 compute=not lazy)
        os.rename(tmp, path)
    finally:
        if os.path.exists(tmp):
            shutil.rmtree(tmp, ignore_errors=True)


def _counts(path):
    """``(done, damaged)`` row flags of a checkpoint, or None when there is none."""
    try:
        import zarr

        group = zarr.open_group(path, mode="r", zarr_format=3)
        done = np.asarray(group[DONE][...])
    except Exception:
        return None
    try:
        damaged = np.asarray(group[DAMAGED][...])
    except Exception:
        damaged = np.zeros_like(done)
    return done, damaged


def saved_rows(path):
    """Number of rows saved in a checkpoint (0 when there is none)."""
    flags = _counts(path)
    return 0 if flags is None else int((flags[0] == 1).sum())


def damaged_rows(path):
    """Number of rows the last resume found damaged and computed again (0 if none)."""
    flags = _counts(path)
    return 0 if flags is None else int((flags[1] == 1).sum())
