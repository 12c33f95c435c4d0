"""NetCDF input/output: a :class:`~vibimpact.Run` as a self-describing ``xarray.Dataset``.

The dataset holds every number needed to redo the run (all parameters, the solver settings
and the command line as global attributes) next to the data, with CF-style ``units`` and
``long_name`` attributes.  All lengths and times are the model's dimensionless ones (for
the built-in rotor, lengths in units of the radial clearance and times in ``tau``); their
units are therefore ``"1"``.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import logging
import os
import tempfile

import numpy as np

from ..base import _validate as _v

_log = logging.getLogger(__name__)

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Hashable
    from typing import Any

    import xarray as xr

    from ..core.run import Run

# a Run's dataset is made beside Run itself (Run.to_dataset); re-exported here, where the
# writers are
from ..core.run import run_to_dataset  # noqa: E402,F401

def as_run_dataset(value: xr.Dataset | Run, name: str = "ds") -> xr.Dataset:
    """The dataset of a run: a Dataset as it is, a :class:`~vibimpact.Run` through
    :meth:`~vibimpact.Run.to_dataset`.

    Every function that expects the dataset of a run (:func:`write_netcdf`,
    :func:`vibimpact.plotting.plot_xy`) takes a Run through this function.

    Parameters
    ----------
    value : xarray.Dataset or Run
    name : str
        The argument's name, for the error.

    Returns
    -------
    xarray.Dataset

    Raises
    ------
    TypeError
        When ``value`` is neither.
    """
    import xarray as xr

    if isinstance(value, xr.Dataset):
        return value
    # a Run converts itself (Run.to_dataset calls run_to_dataset above); recognised by
    # what it has, so that this module, below Run's, does not import it back
    if callable(getattr(value, "to_dataset", None)) and hasattr(value, "strobe"):
        return value.to_dataset()
    if not isinstance(value, xr.Dataset):
        raise TypeError(f"{name} must be an xarray.Dataset or a vibimpact.Run, got "
                        f"{type(value).__name__}")
    return value


#: the integer types CF-1.8 allows (its section 2.2: byte, short, int); CF-1.9 added the
#: unsigned and 64-bit ones, which readers of CF-1.8 need not know
CF_INTEGERS = ("int8", "int16", "int32")
#: attributes whose type must be the variable's (NUG, CF 2.5.1 and 3.5)
_TYPED_ATTRS = ("flag_values", "valid_min", "valid_max", "valid_range", "_FillValue",
                "missing_value")


#: the largest integer magnitude float64 holds exactly (and every integer below it)
EXACT_FLOAT_INTEGER = 2**53


def _cf_integer(values, name):
    """The CF-1.8 type for the integer ``values`` of variable ``name`` of another type
    (int64, unsigned): int32 when every value fits it, float64 when every value has a
    magnitude of at most 2**53 (float64 holds each exactly); ValueError naming ``name``
    otherwise (float64 would change the values)."""
    info = np.iinfo(np.int32)
    if values.size == 0:
        return np.dtype(np.int32)
    low, high = int(values.min()), int(values.max())
    if low >= info.min and high <= info.max:
        return np.dtype(np.int32)
    if max(-low, high) <= EXACT_FLOAT_INTEGER:
        return np.dtype(np.float64)
    raise ValueError(f"variable {name!r} holds the integer {high if high > -low else low}, "
                     f"which no CF-1.8 type holds exactly (int32 reaches {info.max}, "
                     f"float64 every integer up to 2**53 = {EXACT_FLOAT_INTEGER}); "
                     "not writing it")


def _typed(attrs, dtype):
    """``attrs`` with those of :data:`_TYPED_ATTRS` of another numeric type as ``dtype``
    where their values survive the conversion (JSON, Zarr's attributes, has no types)."""
    out = dict(attrs)
    for key in _TYPED_ATTRS:
        if key not in out:
            continue
        value = np.asarray(out[key])
        if value.dtype.kind not in "biuf" or value.dtype == dtype:
            continue
        new = value.astype(dtype)
        if np.array_equal(new, value):
            out[key] = new
    return out


def _foreign(dtype):
    """Whether ``dtype`` is an integer type CF-1.8 does not have (int64, unsigned)."""
    dtype = np.dtype(dtype)
    return dtype.kind in "iu" and dtype.name not in CF_INTEGERS


def _cf_encoding(var, values, name):
    """``var``'s encoding with a stored type CF-1.8 does not have (a dataset read from
    an older file keeps int64 there, whatever its values are now) as int32, or float64
    when ``values`` or the fill value do not fit int32; None when nothing changes."""
    enc = var.encoding
    if "dtype" not in enc or not _foreign(enc["dtype"]):
        return None
    enc = dict(enc)
    vals = np.asarray(values, dtype=np.float64)
    fill = enc.get("_FillValue", enc.get("missing_value"))
    probe = np.append(vals[np.isfinite(vals)], [] if fill is None else np.ravel(fill))
    enc["dtype"] = _cf_integer(probe.astype(np.int64) if probe.size and
                               np.all(np.abs(probe) < 2.0**62) else probe.astype(np.float64),
                               name)
    for key in ("_FillValue", "missing_value"):
        if enc.get(key) is not None:
            enc[key] = np.asarray(enc[key]).astype(enc["dtype"])[()]
    return enc


def _model_references(attrs):
    """The literature the built-in model a dataset records (its ``model`` attribute)
    declares (:attr:`vibimpact.models.Model.references`); None for a user's model, an
    unknown name or a dataset of no model."""
    from .. import models

    name = attrs.get("model")
    if not isinstance(name, str) or name not in models.names():
        return None
    return models.get(name).references or None


def _cf_types(out):
    """``out`` with every integer variable of a type CF-1.8 does not know (int64, the
    unsigned types) as int32 (or float64 when its values do not fit), in memory and in
    its encoding (the type a file it was read from stored), and the attributes that must
    have the variable's type (:data:`_TYPED_ATTRS`: ``flag_values``, the valid range)
    of every numeric variable in its type."""
    for name in list(out.variables):
        var = out.variables[name]
        if var.dtype.kind not in "biuf":
            continue
        values = None
        if _foreign(var.dtype):
            values = np.asarray(var.values)
            new = var.copy(data=values.astype(_cf_integer(values, name)))
        elif any(key in var.attrs for key in _TYPED_ATTRS) or _foreign(
                var.encoding.get("dtype", "f8")):
            new = var.copy(deep=False)
        else:
            continue
        encoding = _cf_encoding(new, new.values, name)
        if encoding is not None:
            new.encoding = encoding
        elif values is not None:  # converted here: the old stored type goes too
            new.encoding = {k: v for k, v in var.encoding.items() if k != "dtype"}
        new.attrs = _typed(var.attrs, np.dtype(new.encoding.get("dtype", new.dtype)))
        if name in out.coords:  # an index coordinate stays one
            out = out.assign_coords({name: new})
        else:
            out[name] = new
    return out


def _described(attrs):
    """The model and parameters a file records, for the log (e.g. ``rotor, kh = 120,
    ...`` for the built-in rotor)."""
    params = {k[6:]: v for k, v in attrs.items() if k.startswith("param_")}
    words = [str(attrs["model"])] if attrs.get("model") else []
    words += [f"{k} = {v:g}" if isinstance(v, (int, float)) else f"{k} = {v}"
              for k, v in params.items()]
    return ", ".join(words) or "no parameters recorded"


@_v.checks_flags
def for_file(ds: xr.Dataset, call: str, *,
             netcdf: bool | None = None) -> tuple[xr.Dataset, dict[Hashable, Any]]:
    """``(dataset, encoding)`` to write ``ds`` as a file that follows CF-1.8: a shallow
    copy (the data are shared, ``ds`` is not changed) whose global attributes carry the CF
    and provenance attributes of :func:`vibimpact.base.provenance.file_attrs`, and the encoding
    that writes no ``_FillValue`` on any coordinate (CF: coordinates have no missing
    values).

    The copy also gets what CF-1.8 asks of the data themselves, whatever built ``ds``:

    * an integer variable of a type CF-1.8 does not have (int64, unsigned: its section 2.2
      allows byte, short and int) is written as int32 when its values fit, else as
      float64 when float64 holds each exactly (magnitudes up to 2**53), its
      ``flag_values`` and valid range alike; one beyond 2**53 is refused (ValueError
      naming the variable), not rounded;
    * a dimension coordinate of text (``state``: X, Y, ...; ``direction``: up, down) is
      written as characters (``state(state, string2)``): a coordinate variable must be
      numeric and monotonic (CF 1.3), a character array labels its dimension instead
      (CF 6.1) and reads back as the same index of text (NetCDF only: Zarr has no
      character type of its own, and CF's rule is NetCDF's).

    Every writer of the package (:func:`write_netcdf`, :func:`vibimpact.maps.write_map`)
    goes through this function.

    Parameters
    ----------
    ds : xarray.Dataset
    call : str
        The writing function, named in ``history`` when ``ds`` records no ``command``.
    netcdf : bool, optional
        The file is NetCDF (text coordinates as characters); by default every call but
        :func:`vibimpact.maps.write_map`'s (a Zarr store).

    Returns
    -------
    (xarray.Dataset, dict)

    Raises
    ------
    ValueError
        Naming the variable, for integers of a magnitude beyond 2**53 that CF-1.8 has no
        exact type for.
    """
    from ..base.provenance import file_attrs

    if netcdf is None:
        netcdf = call != "vibimpact.maps.write_map"

    out = _cf_types(ds.copy(deep=False))
    out.attrs = file_attrs(ds.attrs, call, _model_references(ds.attrs))
    _log.info("file of %s: %s; %d variables, sizes %s", out.attrs.get("title", "?"),
              _described(out.attrs), len(out.variables), dict(out.sizes))
    encoding: dict[Hashable, dict[str, Any]] = {name: {"_FillValue": None}
                                                for name in out.coords}
    for name in out.indexes if netcdf else ():
        if name in out.dims and out[name].dtype.kind in TEXT_KINDS:
            encoding[name]["dtype"] = "S1"
    return out, encoding


#: free space (bytes) an output's file system must have before a command computes
MIN_FREE = 1 << 20


class NeedsFlag(ValueError):
    """A refusal that a flag of the call lifts: an existing output without
    ``overwrite``, an existing checkpoint without ``resume``.

    It carries what was refused and the flag's name as data, so that each interface
    names the flag in its own words: ``str(exc)`` is the API's (``...; pass
    overwrite=True to replace it``), :meth:`say` another's (the command line's
    ``exc.say("--overwrite")``).

    Parameters
    ----------
    refused : str
        What was refused ("output file 'r.nc' exists").
    flag : str
        The keyword argument that lifts it ("overwrite", "resume").
    purpose : str
        What the flag does ("to replace it").
    message : str, optional
        ``str(exc)``, when not the API's own words.
    """

    def __init__(self, refused: str, flag: str, purpose: str,
                 message: str | None = None) -> None:
        self.refused, self.flag, self.purpose = refused, flag, purpose
        super().__init__(message or self.say(f"{flag}=True"))

    def say(self, flag: str) -> str:
        """The refusal with the flag spelled ``flag`` (``"--overwrite"``)."""
        return f"{self.refused}; pass {flag} {self.purpose}"

    def __reduce__(self):  # pickled whole (a worker's error), not as str(exc) alone
        return (NeedsFlag, (self.refused, self.flag, self.purpose, str(self)))


class OutputExists(NeedsFlag):
    """An existing output path, refused without ``overwrite``: a :class:`NeedsFlag`
    whose ``path`` and ``what`` (the role of the path, "output file") are attributes."""

    def __init__(self, what: str, path: str) -> None:
        self.what, self.path = what, path
        super().__init__(f"{what} {path!r} exists", "overwrite", "to replace it")

    def __reduce__(self):
        return (OutputExists, (self.what, self.path))


@_v.checks_flags
def check_output_path(path: str | os.PathLike[str], overwrite: bool = False, *,
                      what: str = "output",
                      store: bool = False, free: int = MIN_FREE) -> str:
    """Vet an output path before anything is computed; every writer and every command
    that writes (its outputs and its checkpoint ``OUT.partial``) goes through it.

    Refused: an empty name, a name that is not valid UTF-8, a name ending with ``/``
    (a file's), a directory (unless ``store``: a Zarr directory), a dangling symbolic
    link, anything that is not a regular file (a device such as ``/dev/full``, a pipe,
    a socket) even with ``overwrite``, an existing path without ``overwrite``, a missing
    or unwritable directory, a name too long for the file system (the writer's own
    temporary name ``.NAME.PID-XXXXXXXX.tmp`` is created and removed, which also tests a
    read-only mount), and a file system with less than ``free`` bytes free.  The
    temporaries of ``path`` that writers killed with SIGKILL left beside it (their
    process gone) are removed first.

    Parameters
    ----------
    path : str or os.PathLike
    overwrite : bool
        An existing regular file (or Zarr directory, with ``store``) may be replaced.
    what : str
        Names the path in the messages ("output file", "plot file", "checkpoint").
    store : bool
        ``path`` is a directory store (Zarr): a trailing ``/`` is allowed, an existing
        directory is not refused here.
    free : int
        Bytes that must be free on the file system of ``path``.

    Returns
    -------
    str
        The path, with a store's trailing ``/`` removed.

    Raises
    ------
    OutputExists
        For an existing path without ``overwrite`` (a ``ValueError``).
    ValueError
        Naming ``what``, the path and the reason.
    """
    path = _v.path("path", path, allow_empty=True)
    if not path.strip():
        raise ValueError(f"{what} {path!r}: the name is empty")
    try:
        path.encode("utf-8")
    except UnicodeEncodeError:
        raise ValueError(f"{what} {path!r}: the name is not valid UTF-8 (NetCDF, Zarr "
                         "and the checkpoint need UTF-8 file names)") from None
    if store:
        path = path.rstrip("/" + os.sep) or path
    elif path.endswith(("/", os.sep)) or os.path.basename(path) in (".", ".."):
        raise ValueError(f"{what} {path!r} names a directory (ends with '/'); give a "
                         "file name")
    if os.path.islink(path) and not os.path.exists(path):
        raise ValueError(f"{what} {path!r} is a dangling symbolic link (to "
                         f"{os.readlink(path)!r}); remove it or choose another name")
    if os.path.isdir(path) and not store:
        raise ValueError(f"{what} {path!r} is a directory")
    if os.path.exists(path) and not os.path.isdir(path) and not os.path.isfile(path):
        raise ValueError(f"{what} {path!r} is not a regular file (a device, pipe or "
                         "socket); not replacing it")
    if os.path.lexists(path) and not overwrite:
        raise OutputExists(what, path)
    directory = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(directory):
        raise ValueError(f"cannot write {what} {path!r}: directory {directory!r} does "
                         "not exist")
    from ..base._writing import held_signals, remove_dead_temporaries, temp_prefix

    # what writers of this output killed with SIGKILL left (their pid is in the name)
    remove_dead_temporaries(path)
    with held_signals() as held:  # a signal between creating and removing the probe
        try:  # os.access says yes to root and knows nothing of read-only mounts: try it
            fd, probe = tempfile.mkstemp(prefix=temp_prefix(path), suffix=".tmp",
                                         dir=directory)
        except OSError as exc:
            import errno

            if exc.errno == errno.ENAMETOOLONG:
                raise ValueError(f"{what} {path!r}: the name is too long for the file "
                                 "system") from None
            raise ValueError(f"cannot write {what} {path!r}: directory {directory!r} is "
                             f"not writable ({exc.strerror or exc})") from None
        held.temporaries.append(probe)
        os.close(fd)
        os.unlink(probe)
    try:
        st = os.statvfs(directory)
        left = st.f_bavail * st.f_frsize
    except (OSError, AttributeError):
        left = None
    if left is not None and left < free:
        from ..base._limits import human_bytes

        raise ValueError(f"cannot write {what} {path!r}: only {human_bytes(left)} free on "
                         f"the file system of {directory!r}, {human_bytes(free)} needed")
    return path


def write_failed(path: str, exc: BaseException) -> OSError:
    """The ``OSError`` a writer raises when writing ``path`` failed with ``exc``.

    NetCDF reports a full disk as ``RuntimeError: NetCDF: HDF error``; the message says
    what the file system says (its free space) instead.

    Parameters
    ----------
    path : str
    exc : BaseException
        The error of the write.

    Returns
    -------
    OSError
    """
    import errno

    reason = getattr(exc, "strerror", None) or str(exc) or type(exc).__name__
    code = getattr(exc, "errno", None)
    try:
        st = os.statvfs(os.path.dirname(os.path.abspath(path)) or ".")
        if st.f_bavail * st.f_frsize < MIN_FREE:
            reason, code = os.strerror(errno.ENOSPC), errno.ENOSPC
    except (OSError, AttributeError):
        pass
    return OSError(code or errno.EIO, f"cannot write {path!r}: {reason}")


def _umask():
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


@_v.checks_flags
def write_netcdf(ds: xr.Dataset | Run, path: str | os.PathLike[str],
                 overwrite: bool = False) -> None:
    """Write a dataset to NetCDF-4 atomically.

    The file is written to a temporary file in the target directory and renamed into
    place, so a reader never sees a partial file and a failed write leaves nothing behind.
    SIGINT and SIGTERM received while the file is written end the write once netCDF4
    returns (the temporary removed, nothing put in place) and are then delivered; a
    second one ends the process at once.  The temporary's name carries this process's
    id, so that a later write of ``path`` removes what a killed one left
    (:mod:`vibimpact.base._writing`).
    It carries the CF global attributes (``Conventions``, ``history``, ``date_created``)
    and the provenance of :mod:`vibimpact.base.provenance`, and no ``_FillValue`` on its
    coordinates (:func:`for_file`); ``ds`` itself is not changed.

    Parameters
    ----------
    ds : xarray.Dataset or Run
        A Run is written as its dataset (:meth:`vibimpact.Run.to_dataset`).
    path : str or os.PathLike
    overwrite : bool
        Replace an existing file.

    Raises
    ------
    TypeError
        When ``ds`` is neither a Dataset nor a Run.
    OutputExists
        When ``path`` exists and not ``overwrite`` (also when it appeared while ``ds``
        was written); a ``ValueError``.
    ValueError
        For another path :func:`check_output_path` refuses (its directory does not
        exist or is not writable, a device, a dangling link, a name that is empty, too
        long or not UTF-8, ...), or an integer variable beyond 2**53 (:func:`for_file`;
        nothing is written).
    OSError
        When the file cannot be written: a full disk, which NetCDF reports as
        ``RuntimeError: NetCDF: HDF error``, included (:func:`write_failed`; the
        temporary file is removed).
    """
    ds = as_run_dataset(ds)
    path = check_output_path(path, overwrite, free=0)
    directory = os.path.dirname(os.path.abspath(path))
    import netCDF4  # noqa: F401 -- imported before the provenance records its version

    out, encoding = for_file(ds, "vibimpact.io.write_netcdf")
    from ..base._writing import held_signals, temp_prefix

    # SIGINT / SIGTERM wait until netCDF4 returns (it holds locks while it writes; a
    # signal raised inside one deadlocked the clean-up), then end the write: the
    # temporary is removed and the file not put in place
    with held_signals() as held:
        fd, tmp = tempfile.mkstemp(prefix=temp_prefix(path), suffix=".tmp",
                                   dir=directory)
        held.temporaries.append(tmp)
        os.close(fd)
        try:
            try:
                out.to_netcdf(tmp, mode="w", format="NETCDF4", engine="netcdf4",
                              encoding=encoding)
                os.chmod(tmp, 0o666 & ~_umask())
            except (OSError, RuntimeError) as exc:  # a full disk: "NetCDF: HDF error"
                raise write_failed(path, exc) from None
            if held.signum is not None:  # stopped meanwhile: nothing is put in place
                return
            if overwrite:
                _rename(tmp, path)
            else:
                try:
                    os.link(tmp, path)  # fails if path appeared meanwhile: never clobber
                except FileExistsError:  # made while ds was written: refused alike
                    raise OutputExists("output file", path) from None
                except OSError:  # no hard links on this file system
                    _rename(tmp, path)
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)


def _rename(tmp, path):
    try:
        os.replace(tmp, path)
    except OSError as exc:
        raise write_failed(path, exc) from None


def read_netcdf(path: str | os.PathLike[str]) -> xr.Dataset:
    """Open a file written by :func:`write_netcdf` (fully loaded, file closed).

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    xarray.Dataset

    Raises
    ------
    ValueError
        When the data of a variable cannot be read (:func:`load_variables`), or the
        variables declare more than :data:`vibimpact.base._limits.MAX_READ_BYTES` (checked
        from the metadata before anything is read: :func:`check_declared_netcdf`).
    """
    import xarray as xr

    path = _v.path("path", path)
    check_declared_netcdf(path)
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return load_variables(ds, path)


def check_declared_netcdf(path: str, what: str = "file") -> None:
    """Refuse a NetCDF file whose variables declare more than
    :data:`vibimpact.base._limits.MAX_READ_BYTES`, from its metadata alone (xarray reads the
    coordinates as it opens a file); ValueError naming the file and the variable."""
    import netCDF4

    from ..base._limits import check_declared

    with netCDF4.Dataset(path, "r") as nc:
        nc.set_auto_mask(False)
        items = [(name, var.shape, getattr(var.dtype, "itemsize", None))
                 for name, var in nc.variables.items()]
    check_declared(items, path, what)


def load_variables(ds: xr.Dataset, path: str, what: str = "file") -> xr.Dataset:
    """``ds`` (opened lazily from ``path``) with every variable loaded into memory; a
    variable whose data cannot be read (a chunk truncated or overwritten: a
    decompression or HDF error) is a ValueError naming ``path`` and the variable.

    Parameters
    ----------
    ds : xarray.Dataset
    path : str
        Where ``ds`` was opened from, for the message.
    what : str
        What ``path`` is ("file", "map").

    Returns
    -------
    xarray.Dataset
        ``ds``, loaded.

    Raises
    ------
    ValueError
        ``{what} PATH is damaged: variable NAME cannot be read (...)``.
    """
    for name, var in ds.variables.items():
        try:
            var.load()
        except Exception as exc:  # zstd's RuntimeError, netCDF4's HDF error, ...
            why = " ".join(str(exc).split()) or type(exc).__name__
            raise ValueError(f"{what} {path!r} is damaged: variable {name!r} cannot be "
                             f"read ({type(exc).__name__}: {why})"[:400]) from exc
    return ds


# the comparison of two datasets lives in io_compare; re-exported here beside the readers
from .compare import TEXT_KINDS, attribute_differences, differences  # noqa: E402,F401
