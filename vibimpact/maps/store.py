"""A map file: :func:`write_map` and :func:`open_map`.

:func:`write_map` writes the assembled ``xarray.Dataset`` as a Zarr store (a directory,
``*.zarr``) or a NetCDF-4 file (``*.nc``), atomically in both cases: into a temporary
name in the target directory, then renamed.  :func:`open_map` reads either back, fully
loaded, with strings as Python ``str`` objects (as :func:`vibimpact.map2d` returns them);
it also opens a map's checkpoint (:func:`vibimpact.maps.map2d.partial_map`) while the map
runs.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import os
import shutil
import tempfile
import warnings

import numpy as np

from ..base import _validate as _v

if TYPE_CHECKING:  # names of the annotations only
    import xarray as xr

#: output formats by file extension
FORMATS = {".zarr": "zarr", ".nc": "netcdf"}


def output_format(path):
    """``"zarr"`` or ``"netcdf"`` from the extension of ``path``; ValueError otherwise."""
    ext = os.path.splitext(os.fspath(path).rstrip("/" + os.sep))[1].lower()
    if ext not in FORMATS:
        raise ValueError(f"map output {os.fspath(path)!r}: unknown extension; use .zarr "
                         "(a Zarr store) or .nc (NetCDF)")
    return FORMATS[ext]


def _chunks(ds):
    """Zarr chunks: whole rows, about a million values per chunk."""
    enc = {}
    for name, var in ds.data_vars.items():
        if var.ndim < 2:
            continue
        inner = int(np.prod(var.shape[2:] if "direction" in var.dims else var.shape[1:]))
        lead: tuple[int, ...]
        if "direction" in var.dims:
            lead = (1,)
            rows_dim = 1
        else:
            lead = ()
            rows_dim = 0
        per = max(1, min(var.shape[rows_dim], 1_000_000 // max(1, inner)))
        enc[name] = {"chunks": lead + (per,) + tuple(var.shape[rows_dim + 1:])}
    return enc


@_v.checks_flags
def write_map(ds: xr.Dataset, path: str | os.PathLike[str],
              overwrite: bool = False) -> None:
    """Write a map dataset atomically as Zarr (``*.zarr``) or NetCDF (``*.nc``).

    Both carry the CF global attributes and the provenance of
    :func:`vibimpact.io.for_file` (``ds`` itself is not changed) and no ``_FillValue`` on
    the coordinates.  A Zarr store is written whole, from the finished map, with
    consolidated metadata, so that ``xarray.open_zarr(path)`` opens it without a warning.

    Raises
    ------
    ValueError
        For an unknown extension, an existing ``path`` without ``overwrite``, an existing
        path that is not a Zarr store this toolkit wrote, or holds anything else
        (:func:`check_replaceable`), or a missing directory.
    OSError
        When writing fails (nothing is left behind).
    """
    from .. import io as vio

    fmt = output_format(path)
    if fmt == "netcdf":  # a NetCDF path ending in '/' is refused there
        vio.write_netcdf(ds, path, overwrite=overwrite)
        return
    path = vio.check_output_path(path, overwrite, store=True, free=0)
    directory = os.path.dirname(os.path.abspath(path))
    if os.path.lexists(path):
        check_replaceable(path)
    import zarr  # noqa: F401 -- imported before the provenance records its version

    out, encoding = vio.for_file(ds, "vibimpact.maps.write_map", netcdf=False)  # a copy
    for name in list(out.variables):  # xarray writes str objects as variable-length
        out[name].encoding = {}
    for name, chunks in _chunks(out).items():
        encoding.setdefault(name, {}).update(chunks)
    from ..base._writing import held_signals, temp_prefix

    # SIGINT / SIGTERM wait until zarr returns, then end the write: the temporary store
    # is removed and nothing put in place (see vibimpact.base._writing)
    with held_signals() as held:
        tmp = tempfile.mkdtemp(prefix=temp_prefix(path), suffix=".tmp", dir=directory)
        held.temporaries.append(tmp)
        old = None
        try:
            with warnings.catch_warnings():  # consolidated metadata is a zarr-python
                # extension of format 3, and what lets xarray.open_zarr(path) open it
                warnings.filterwarnings("ignore",
                                        message="Consolidated metadata is currently")
                try:
                    # every chunk written, the ones that hold only the fill value
                    # too: a chunk missing from the store is then damage (open_map)
                    out.to_zarr(tmp, mode="w", consolidated=True, zarr_format=3,
                                encoding=encoding, write_empty_chunks=True)
                except (OSError, RuntimeError) as exc:  # a full disk
                    raise vio.write_failed(path, exc) from None
            if held.signum is not None:  # stopped meanwhile: nothing is put in place
                return
            if os.path.lexists(path):
                check_replaceable(path)  # again: nothing added to it meanwhile
                old = tempfile.mkdtemp(prefix=temp_prefix(path), suffix=".old",
                                       dir=directory)
                os.rmdir(old)
                os.rename(path, old)
            try:
                os.rename(tmp, path)
            except OSError as exc:
                raise vio.write_failed(path, exc) from None
        finally:
            if os.path.exists(tmp):
                shutil.rmtree(tmp, ignore_errors=True)
            if old is not None:
                shutil.rmtree(old, ignore_errors=True)


#: the largest ``zarr.json`` of a store that ``overwrite`` looks into (a map's is a few
#: hundred kilobytes)
MAX_ZARR_JSON = 64 << 20


def check_replaceable(path: str, what: str = "output") -> None:
    """Refuse to replace ``path`` unless it is a Zarr store this toolkit wrote and
    nothing else: ``overwrite`` replaces what :func:`write_map` made, never a user's
    directory that happens to hold a ``zarr.json``.

    Replaceable: a directory (not a symbolic link) whose ``zarr.json`` carries the
    toolkit's provenance (``source`` "vibimpact ..." and ``vibimpact_version``,
    :func:`vibimpact.io.for_file`) and that holds only the entries of a Zarr store: its
    ``zarr.json`` and the arrays its metadata lists, each a directory of a ``zarr.json``
    and chunks (``c/`` and numbered entries below it), no symbolic link anywhere.

    Raises
    ------
    ValueError
        Naming ``path`` and what was found (a file, a symbolic link, no ``zarr.json``, a
        store without the toolkit's provenance, another entry).
    """
    def refuse(found):
        raise ValueError(f"{what} {path!r} {found}; overwriting replaces only a Zarr "
                         "store vibimpact wrote, so not replacing it (remove it yourself "
                         "or choose another name)")

    if os.path.islink(path):
        refuse(f"is a symbolic link (to {os.readlink(path)!r})")
    if not os.path.isdir(path):
        refuse("is a file, not a Zarr store")
    meta = os.path.join(path, "zarr.json")
    if os.path.islink(meta) or not os.path.isfile(meta):
        refuse("is a directory without a zarr.json (not a Zarr store)")
    if os.path.getsize(meta) > MAX_ZARR_JSON:
        refuse(f"has a zarr.json of {os.path.getsize(meta)} bytes")
    special = _special_entry(path)
    if special is not None:  # Zarr would block on a FIFO reading the metadata
        refuse(f"holds {special[0]!r}, {special[1]}")
    import zarr

    try:
        group = zarr.open_group(path, mode="r")
        attrs, arrays = dict(group.attrs), set(group.array_keys())
    except Exception as exc:  # noqa: BLE001 -- any failure to read it: not ours
        refuse(f"is a Zarr store whose metadata cannot be read ({type(exc).__name__})")
    if not (str(attrs.get("source", "")).startswith("vibimpact ")
            and "vibimpact_version" in attrs):
        refuse("is a Zarr store without vibimpact's provenance (written by someone "
               "else)")
    other = _foreign_entry(path, arrays)
    if other is not None:
        refuse(f"holds {other!r}, which is not part of the Zarr store vibimpact wrote")


def _foreign_entry(path, arrays):
    """The first entry under the store ``path`` that is not its ``zarr.json``, an
    array of ``arrays`` (its ``zarr.json`` and numbered chunks under ``c/``), or that is
    a symbolic link; None when there is none."""
    for top, dirs, files in os.walk(path):
        rel = os.path.relpath(top, path)
        parts = [] if rel == "." else rel.split(os.sep)
        for name in sorted(dirs + files):
            full = os.path.join(top, name)
            shown = os.path.join(*parts, name) if parts else name
            if os.path.islink(full):
                return shown
            if not parts:  # the store's own level: zarr.json and its arrays
                ok = name == "zarr.json" if name in files else name in arrays
            elif len(parts) == 1:  # an array's level: its zarr.json and chunks
                ok = name == ("zarr.json" if name in files else "c")
            else:  # chunks: numbered files and directories under c/
                ok = parts[1] == "c" and name.isdigit()
            if not ok:
                return shown
    return None


def _as_objects(ds):
    """Strings of any NumPy string dtype as object arrays of ``str``."""
    for name in list(ds.variables):
        v = ds[name].variable
        if v.dtype.kind in "UT" or (v.dtype.kind not in "biufcmMO" and
                                     "String" in type(v.dtype).__name__):
            new = v.copy(data=np.asarray(v.values).astype(object))
            if name in ds.coords:
                ds = ds.assign_coords({name: new})
            else:
                ds[name] = new
    return ds


def _listed(path):
    """The variables the consolidated metadata of the Zarr store ``path`` lists
    (``{name: metadata}``); ValueError naming ``path`` when its ``zarr.json`` cannot be
    read or holds no consolidated metadata: :func:`write_map` always writes them, so a
    store without is damaged (or not one of a map), and Zarr would open what the
    directory happens to hold.  It is read only as a regular file, bounded in size and
    nesting (:func:`vibimpact.base._json.load_file`)."""
    from ..base._json import load_file

    where = os.path.join(path, "zarr.json")
    try:
        meta = load_file(where, "it", follow=False, max_bytes=MAX_ZARR_JSON)
    except (OSError, ValueError) as exc:
        raise ValueError(f"map {path!r} is damaged: {where!r} cannot be read "
                         f"({getattr(exc, 'strerror', None) or exc})") from None
    listed = (meta.get("consolidated_metadata") or {}).get("metadata") \
        if isinstance(meta, dict) and isinstance(meta.get("consolidated_metadata"),
                                                  dict) else None
    if not listed or not isinstance(listed, dict):
        raise ValueError(f"map {path!r} is damaged: {where!r} has no consolidated "
                         "metadata (the list of its variables, which write_map always "
                         "writes)")
    return listed


def check_store(path: str) -> None:
    """ValueError naming ``path`` (and the variable) when the Zarr store ``path`` has no
    consolidated metadata (:func:`_listed`), or lacks a variable its metadata lists (its
    directory or ``zarr.json``) or a chunk of one.

    :func:`write_map` writes every chunk (``write_empty_chunks``), so a missing one is
    damage: Zarr would read it as the fill value (0, "not computed", for ``regime``) and
    a plot would show a blank map.
    """
    import zarr

    special = _special_entry(path)
    if special is not None:
        raise ValueError(f"map {path!r} is damaged: {special[0]!r} is {special[1]}, not a "
                         "regular file (a Zarr store holds files and directories only)")
    listed = _listed(path)
    for name, info in sorted(listed.items()):
        if isinstance(info, dict) and info.get("node_type") == "array" and \
                not os.path.isfile(os.path.join(path, name, "zarr.json")):
            raise ValueError(f"map {path!r} is damaged: variable {name!r} is missing "
                             f"({os.path.join(path, name)!r} has no zarr.json)")
    from ..base._limits import check_declared

    arrays, declared = [], []
    for name in sorted(os.listdir(path)):  # one array at a time: a group's arrays()
        if not os.path.isfile(os.path.join(path, name, "zarr.json")):  # leaves the
            continue  # other tasks running (tracebacks at exit) when one fails
        try:
            arr = zarr.open_array(os.path.join(path, name), mode="r")
            shape, itemsize = arr.shape, getattr(arr.dtype, "itemsize", None)
        except Exception as exc:  # an array's zarr.json Zarr cannot make sense of
            raise _unreadable(path, name, exc) from exc
        declared.append((name, shape, itemsize))
        check_declared(declared, path, "map")  # before a chunk is listed or read
        try:
            arrays.append((name, arr.nchunks_initialized, arr.nchunks))
        except Exception as exc:
            raise _unreadable(path, name, exc) from exc
    for name, have, want in arrays:
        if have < want:
            raise ValueError(f"map {path!r} is damaged: {want - have} of {want} chunks "
                             f"of variable {name!r} are missing (they would read as "
                             "the fill value)")


def _special_entry(path):
    """``(entry, what it is)`` of the first entry under the store ``path`` that is
    neither a regular file nor a directory (a FIFO, a device, a socket, a symbolic
    link): Zarr would block on a FIFO or follow a link; None when there is none."""
    import stat

    from ..base._regular import kind

    for top, dirs, files in os.walk(path):
        for name in sorted(dirs + files):
            full = os.path.join(top, name)
            mode = os.lstat(full).st_mode
            if not (stat.S_ISREG(mode) or stat.S_ISDIR(mode)):
                return os.path.relpath(full, path), kind(mode)
    return None


def _unreadable(path, name, exc):
    return ValueError(f"map {path!r} is damaged: the metadata of variable {name!r} "
                      f"cannot be read ({type(exc).__name__}: {exc})"[:400])


def open_map(path: str | os.PathLike[str]) -> xr.Dataset:
    """Read a map written by :func:`write_map` (fully loaded, file closed).

    Parameters
    ----------
    path : str or os.PathLike
        A ``*.zarr`` directory, a NetCDF file, or the checkpoint directory of a running
        or interrupted map (the map so far, with ``row_done``).

    Returns
    -------
    xarray.Dataset

    Raises
    ------
    ValueError
        Naming ``path``, for a damaged Zarr store: no consolidated metadata, a variable
        or a chunk missing, which Zarr would read as the fill value (a blank map)
        (:func:`check_store`), or data that cannot be read, such as a chunk truncated or
        overwritten (naming the variable too, :func:`vibimpact.io.load_variables`); and
        for a NetCDF map whose data cannot be read.
    """
    import xarray as xr

    from .. import io as vio

    from ..engine.store import is_checkpoint

    path = _v.path("path", path)
    if os.path.isdir(path) and is_checkpoint(path):
        from .map2d import partial_map

        return partial_map(path)
    if os.path.isdir(path):
        check_store(path)
        try:
            opened = xr.open_zarr(path, consolidated=True, chunks=None)
        except Exception as exc:  # metadata Zarr or xarray cannot make sense of
            raise ValueError(f"map {path!r} is damaged: it cannot be opened as a Zarr "
                             f"store ({type(exc).__name__}: {exc})"[:400]) from exc
        with opened as ds:
            ds = vio.load_variables(ds, path, "map")
    else:
        ds = vio.read_netcdf(path)
    return _as_objects(ds)
