"""Where a map's results live: the row checkpoint while it runs, the map file at the end.

Row checkpoint
--------------
While a map is computed, every finished row is saved at once, by the process that
submitted the rows (the Dask *client*, so the workers need no shared file system), in a
directory holding

* ``request.json``: a fingerprint of the request, so a resume never mixes two maps;
* ``row_<direction>_<index>.npz``: one file per finished row (all the variables of that
  row's sweep), written to a temporary name and renamed.

A row is therefore either completely on disk or absent: a map killed at any moment
(Ctrl-C, SIGKILL, a lost cluster) loses only the rows in flight, and a resume loads the
saved rows instead of recomputing them.  A row file that cannot be read back completely
(a damaged disk, a hand edit) is renamed ``<name>.corrupt`` and its row recomputed; every
row is a deterministic function of the request, so the resumed map is still identical to
an uninterrupted one.

Map file
--------
:func:`write_map` writes the assembled ``xarray.Dataset`` as a Zarr store (a directory,
``*.zarr``) or a NetCDF-4 file (``*.nc``), atomically in both cases: into a temporary
name in the target directory, then renamed.  :func:`open_map` reads either back, fully
loaded, with strings as Python ``str`` objects (as :func:`vibimpact.map2d` returns them).
"""
from __future__ import annotations

import io
import json
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np

from ..sweeps.checkpoint import _atomic_write_bytes, fingerprint, set_aside

#: output formats by file extension
FORMATS = {".zarr": "zarr", ".nc": "netcdf"}


def output_format(path):
    """``"zarr"`` or ``"netcdf"`` from the extension of ``path``; ValueError otherwise."""
    ext = os.path.splitext(os.fspath(path).rstrip("/" + os.sep))[1].lower()
    if ext not in FORMATS:
        raise ValueError(f"map output {os.fspath(path)!r}: unknown extension; use .zarr "
                         "(a Zarr store) or .nc (NetCDF)")
    return FORMATS[ext]


# --- row checkpoint ------------------------------------------------------------------

def open_rows(path, request, resume):
    """Create (or, with ``resume``, reopen) a row checkpoint directory.

    Parameters
    ----------
    path : str or os.PathLike
    request : dict
        JSON-able description of everything the rows depend on.
    resume : bool

    Returns
    -------
    pathlib.Path

    Raises
    ------
    ValueError
        ``path`` exists without ``resume``, is not a map checkpoint, or belongs to a
        different request.
    """
    path = Path(path)
    meta = path / "request.json"
    fp = fingerprint(request)
    if path.exists():
        if not resume:
            raise ValueError(f"map checkpoint {path} already exists: pass resume=True "
                             "(--resume) to continue it, or remove it")
        if not path.is_dir():
            raise ValueError(f"map checkpoint {path} is not a directory")
        try:
            old = json.loads(meta.read_text())
        except (OSError, ValueError):
            raise ValueError(f"map checkpoint {path} has no readable request.json") \
                from None
        if not (isinstance(old, dict) and old.get("kind") == "map"
                and "fingerprint" in old):
            raise ValueError(f"map checkpoint {path}: {meta.name} is not a vibimpact map "
                             "checkpoint record")
        if old["fingerprint"] != fp:
            raise ValueError(f"map checkpoint {path} belongs to a different map request")
        return path
    path.mkdir(parents=True)
    _atomic_write_bytes(meta, json.dumps({"kind": "map", "fingerprint": fp,
                                          "request": request}, sort_keys=True,
                                         default=str, indent=1).encode())
    return path


def row_file(path, direction, index):
    """The file of row ``index`` swept ``direction``."""
    return Path(path) / f"row_{direction}_{index:06d}.npz"


def save_row(path, direction, index, value, arrays):
    """Write one finished row atomically.

    ``arrays`` maps variable names to the row's values along eta; ``value`` (the varied
    parameter's value) is stored with them and checked on loading.
    """
    buf = io.BytesIO()
    payload = {k: np.asarray(v).astype(str) if np.asarray(v).dtype == object else
               np.asarray(v) for k, v in arrays.items()}
    np.savez(buf, _value=np.float64(value), _direction=np.str_(direction), **payload)
    _atomic_write_bytes(row_file(path, direction, index), buf.getvalue())


def load_row(path, direction, index, value, template):
    """A saved row's ``{variable: values}``, or None when it is not done.

    Parameters
    ----------
    template : dict
        ``{variable: (shape, dtype)}`` every row must match.

    A row file that cannot be read back completely, or that does not match ``template``
    or ``value``, is renamed to ``<name>.corrupt`` and reported as not done.
    """
    f = row_file(path, direction, index)
    if not f.exists():
        return None
    try:
        with np.load(f, allow_pickle=False) as z:
            if float(z["_value"]) != float(value) or str(z["_direction"]) != direction:
                raise ValueError("another row")
            out = {}
            for name, (shape, dtype) in template.items():
                v = z[name]
                if v.shape != shape:
                    raise ValueError(f"{name}: shape {v.shape}")
                if dtype == object:
                    if v.dtype.kind != "U":
                        raise ValueError(f"{name}: dtype {v.dtype}")
                    v = v.astype(object)
                elif v.dtype != dtype:
                    raise ValueError(f"{name}: dtype {v.dtype}")
                out[name] = v
        return out
    except Exception:  # BadZipFile, EOFError, OSError, KeyError, ValueError, ...
        set_aside(f)
        return None


def saved_rows(path):
    """Number of row files in a checkpoint directory (0 when there is none)."""
    try:
        return sum(1 for n in os.listdir(path)
                   if n.startswith("row_") and n.endswith(".npz"))
    except OSError:
        return 0


# --- map file --------------------------------------------------------------------------

def _chunks(ds):
    """Zarr chunks: whole rows, about a million values per chunk."""
    enc = {}
    for name, var in ds.data_vars.items():
        if var.ndim < 2:
            continue
        inner = int(np.prod(var.shape[2:] if "direction" in var.dims else var.shape[1:]))
        if "direction" in var.dims:
            lead = (1,)
            rows_dim = 1
        else:
            lead = ()
            rows_dim = 0
        per = max(1, min(var.shape[rows_dim], 1_000_000 // max(1, inner)))
        enc[name] = {"chunks": lead + (per,) + tuple(var.shape[rows_dim + 1:])}
    return enc


def write_map(ds, path, overwrite=False):
    """Write a map dataset atomically as Zarr (``*.zarr``) or NetCDF (``*.nc``).

    Raises
    ------
    ValueError
        For an unknown extension, an existing ``path`` without ``overwrite``, an existing
        directory that is not a Zarr store, or a missing directory.
    OSError
        When writing fails (nothing is left behind).
    """
    from .. import io as vio

    fmt = output_format(path)
    path = os.fspath(path).rstrip("/" + os.sep)
    if fmt == "netcdf":
        vio.write_netcdf(ds, path, overwrite=overwrite)
        return
    directory = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(directory):
        raise ValueError(f"cannot write {path!r}: directory {directory!r} does not exist")
    if os.path.lexists(path):
        if not overwrite:
            raise ValueError(f"output {path!r} exists (pass overwrite=True to replace it)")
        if not (os.path.isdir(path) and os.path.isfile(os.path.join(path, "zarr.json"))):
            raise ValueError(f"output {path!r} exists and is not a Zarr store; not "
                             "replacing it")
    tmp = tempfile.mkdtemp(prefix="." + os.path.basename(path) + ".", suffix=".tmp",
                           dir=directory)
    old = None
    try:
        out = ds.copy()
        for name in list(out.variables):  # xarray writes str objects as variable-length
            out[name].encoding = {}
        out.to_zarr(tmp, mode="w", consolidated=False, zarr_format=3,
                    encoding=_chunks(out))
        if os.path.lexists(path):
            old = tempfile.mkdtemp(prefix="." + os.path.basename(path) + ".", suffix=".old",
                                   dir=directory)
            os.rmdir(old)
            os.rename(path, old)
        os.rename(tmp, path)
    finally:
        if os.path.exists(tmp):
            shutil.rmtree(tmp, ignore_errors=True)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)


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


def open_map(path):
    """Read a map written by :func:`write_map` (fully loaded, file closed).

    Parameters
    ----------
    path : str or os.PathLike
        A ``*.zarr`` directory or a NetCDF file.

    Returns
    -------
    xarray.Dataset
    """
    import xarray as xr

    from .. import io as vio

    path = os.fspath(path)
    if os.path.isdir(path):
        with xr.open_zarr(path, consolidated=False, chunks=None) as ds:
            ds = ds.load()
    else:
        ds = vio.read_netcdf(path)
    return _as_objects(ds)
