"""NetCDF input/output: a :class:`~vibimpact.Run` as a self-describing ``xarray.Dataset``.

The dataset holds every number needed to redo the run (all parameters, the solver settings
and the command line as global attributes) next to the data, with CF-style ``units`` and
``long_name`` attributes.  All lengths are in units of the radial clearance and all times in
the dimensionless time ``tau``; their units are therefore ``"1"``.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numbers
import os
import tempfile

import numpy as np

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Mapping
    from typing import Any

    import xarray as xr
    from numpy.typing import ArrayLike

    from .run import Run

#: model name -> state variable names (a user model gets x0, x1, ...)
_STATE_NAMES = {"rotor": ("X", "Y", "dX", "dY"), "duffing": ("x", "dx")}

_STATE_LONG = {"X": "horizontal displacement / clearance",
               "Y": "vertical displacement / clearance (+Y down, along gravity)",
               "dX": "horizontal velocity dX/dtau", "dY": "vertical velocity dY/dtau"}

#: impact record field -> (units, long_name)
_IMPACT_ATTRS = {
    "t_entry": ("1", "dimensionless time tau of contact entry (R = 1)"),
    "theta": ("degree", "contact angle atan2(Y, X) at entry; +90 = bottom of the retainer"),
    "v_impact": ("1", "normal impact speed dR/dtau at entry"),
    "penetration": ("1", "maximum penetration R - 1 during the contact / clearance"),
    "duration": ("1", "contact duration in tau (NaN: still in contact at the end)"),
    "t_exit": ("1", "dimensionless time tau of contact exit (NaN: still in contact)"),
    "period": ("1", "forcing period of the entry, counted from the end of the transient"),
}

_TAU = "dimensionless time tau = omega_0 t"


def _attr_value(value):
    """A value NetCDF can store as an attribute: str, int or float."""
    if value is None:
        return ""
    if isinstance(value, (bool, np.bool_)):
        return int(value)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if isinstance(value, str):
        return value
    if hasattr(value, "value") and isinstance(value.value, str):  # an Enum such as Status
        return value.value
    return str(value)


def _params_dict(params):
    if hasattr(params, "as_dict"):
        return params.as_dict()
    vec = np.atleast_1d(np.asarray(params, dtype=np.float64))
    return {f"p{i}": float(v) for i, v in enumerate(vec)}


def run_to_dataset(run: Run, command: str | None = None, *, state0: ArrayLike | None = None,
                   attrs: Mapping[str, Any] | None = None) -> xr.Dataset:
    """A :class:`~vibimpact.Run` as an ``xarray.Dataset``.

    Parameters
    ----------
    run : Run
        The result of :func:`vibimpact.simulate`.
    command : str, optional
        The command line (or call) that made the run, stored as the ``command`` attribute.
    state0 : array_like, optional
        The initial state at ``tau = 0``, stored as the variable ``state0``; the one the
        run records (:attr:`Run.state0 <vibimpact.Run.state0>`) by default.
    attrs : dict, optional
        Further global attributes (values converted to str, int or float).

    Returns
    -------
    xarray.Dataset
        Variables ``strobe`` (``sample``, ``state``) with coordinate ``t_strobe``;
        ``impact_<field>`` on dimension ``impact`` for each field of
        :data:`vibimpact.run.IMPACT_DTYPE`; ``trajectory`` (``time``, ``state``) when the
        run kept dense output; ``state0`` when the initial state is known.  Global
        attributes: ``model``, ``status``, ``reason``, ``param_<name>``,
        ``solver_<key>``, ``counter_<name>``, ``periods``, ``transient``, ``dense``,
        ``vibimpact_version``, ``command``.  :meth:`vibimpact.Run.to_dataset` and
        ``vibimpact simulate -o`` both make it here.

    Examples
    --------
    >>> import vibimpact as vi
    >>> from vibimpact.io import run_to_dataset
    >>> run = vi.simulate(vi.presets.get("fig8").replace(eta=1.25), periods=5, transient=5)
    >>> run_to_dataset(run).strobe.shape
    (6, 4)
    """
    import xarray as xr

    from . import __version__

    strobe = np.asarray(run.strobe, dtype=np.float64)
    n = strobe.shape[1]
    names = _STATE_NAMES.get(run.model, tuple(f"x{i}" for i in range(n)))
    if len(names) != n:
        names = tuple(f"x{i}" for i in range(n))
    state_coord = ("state", list(names), {"long_name": "state variable"})
    data_vars = {
        "strobe": (("sample", "state"), strobe,
                   {"units": "1", "long_name": "stroboscopic (Poincare) samples at "
                    "tau_k = 2 pi k / eta, after the transient"}),
    }
    coords = {
        "state": state_coord,
        "t_strobe": ("sample", np.asarray(run.t_strobe, dtype=np.float64),
                     {"units": "1", "long_name": _TAU + " of the stroboscopic samples"}),
    }
    for field in run.impacts.dtype.names:
        units, long_name = _IMPACT_ATTRS.get(field, ("1", field))
        data_vars[f"impact_{field}"] = ("impact", np.asarray(run.impacts[field]),
                                        {"units": units, "long_name": long_name})
    if run.dense is not None:
        data_vars["trajectory"] = (("time", "state"), np.asarray(run.dense, np.float64),
                                   {"units": "1", "long_name": "evenly sampled trajectory"})
        coords["time"] = ("time", np.asarray(run.t_dense, dtype=np.float64),
                          {"units": "1", "long_name": _TAU})
    state0 = run.state0 if state0 is None else state0
    if state0 is not None:
        data_vars["state0"] = ("state", np.asarray(state0, dtype=np.float64).reshape(n),
                               {"units": "1", "long_name": "initial state at tau = 0"})
    ds = xr.Dataset(data_vars, coords=coords)
    for name in names:
        if name in _STATE_LONG:
            ds.attrs[f"state_{name}"] = _STATE_LONG[name]

    glob = {"title": f"vibimpact simulation ({run.model} model)", "model": run.model,
            "status": run.status, "reason": run.reason,
            "vibimpact_version": __version__, "command": command}
    glob.update({f"param_{k}": v for k, v in _params_dict(run.params).items()})
    glob.update({f"solver_{k}": v for k, v in (run.solver or {}).items()})
    glob.update({f"counter_{k}": v for k, v in (run.counters or {}).items()})
    if run.periods is not None:
        glob.update(periods=run.periods, transient=run.transient,
                    dense=run.dense_per_period)
    glob.update(attrs or {})
    ds.attrs.update({k: _attr_value(v) for k, v in glob.items()})
    return ds


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

    from .run import Run

    if isinstance(value, Run):
        return value.to_dataset()
    if not isinstance(value, xr.Dataset):
        raise TypeError(f"{name} must be an xarray.Dataset or a vibimpact.Run, got "
                        f"{type(value).__name__}")
    return value


def for_file(ds: xr.Dataset, call: str | None) -> tuple[xr.Dataset, dict[str, Any]]:
    """``(dataset, encoding)`` to write ``ds`` as a file: a shallow copy (the data are
    shared, ``ds`` is not changed) whose global attributes carry the CF and provenance
    attributes of :func:`vibimpact.provenance.file_attrs`, and the encoding that writes no
    ``_FillValue`` on any coordinate (CF: coordinates have no missing values).

    Every writer of the package (:func:`write_netcdf`, :func:`vibimpact.maps.write_map`)
    goes through this function.

    Parameters
    ----------
    ds : xarray.Dataset
    call : str
        The writing function, named in ``history`` when ``ds`` records no ``command``.

    Returns
    -------
    (xarray.Dataset, dict)
    """
    from .provenance import file_attrs

    out = ds.copy(deep=False)
    out.attrs = file_attrs(ds.attrs, call)
    encoding = {name: {"_FillValue": None} for name in out.coords}
    return out, encoding


def _umask():
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_netcdf(ds: xr.Dataset | Run, path: str | os.PathLike[str],
                 overwrite: bool = False) -> None:
    """Write a dataset to NetCDF-4 atomically.

    The file is written to a temporary file in the target directory and renamed into
    place, so a reader never sees a partial file and a failed write leaves nothing behind.
    It carries the CF global attributes (``Conventions``, ``history``, ``date_created``)
    and the provenance of :mod:`vibimpact.provenance`, and no ``_FillValue`` on its
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
    ValueError
        When ``path`` exists and not ``overwrite``, or its directory does not exist.
    OSError
        When the file cannot be written (the temporary file is removed).
    """
    ds = as_run_dataset(ds)
    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    if os.path.isdir(path):
        raise ValueError(f"output {path!r} is a directory")
    if os.path.exists(path) and not overwrite:
        raise ValueError(f"output file {path!r} exists (pass overwrite=True to replace it)")
    if not os.path.isdir(directory):
        raise ValueError(f"cannot write {path!r}: directory {directory!r} does not exist")
    import netCDF4  # noqa: F401 -- imported before the provenance records its version

    out, encoding = for_file(ds, "vibimpact.io.write_netcdf")
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", suffix=".tmp",
                               dir=directory)
    os.close(fd)
    try:
        out.to_netcdf(tmp, mode="w", format="NETCDF4", engine="netcdf4", encoding=encoding)
        os.chmod(tmp, 0o666 & ~_umask())
        if overwrite:
            os.replace(tmp, path)
        else:
            try:
                os.link(tmp, path)  # fails if path appeared meanwhile: never clobber
            except FileExistsError:
                raise ValueError(f"output file {path!r} exists "
                                 "(pass overwrite=True to replace it)") from None
            except OSError:  # no hard links on this file system
                os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def read_netcdf(path: str | os.PathLike[str]) -> xr.Dataset:
    """Open a file written by :func:`write_netcdf` (fully loaded, file closed).

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    xarray.Dataset
    """
    import xarray as xr

    with xr.open_dataset(path, engine="netcdf4") as ds:
        return ds.load()


#: dtype kinds of text: objects (str), unicode, bytes, NumPy's StringDType (Zarr)
_TEXT = "OUST"


def _as_text(x):
    """An array of text as an array of ``str`` (StringDType through objects)."""
    return x.astype(object).astype(str) if x.dtype.kind == "T" else x.astype(str)


def differences(a: xr.Dataset, b: xr.Dataset) -> tuple[list[tuple[str, str]], int]:
    """Compare two datasets bit for bit (NaN equal to NaN).

    Only data variables and coordinates are compared, never attributes: those of a file
    include the time stamps ``date_created`` and ``history`` and the wall time
    (:data:`vibimpact.provenance.VOLATILE`), which differ between two runs of the same
    command.

    Returns
    -------
    (list of (str, str), int)
        ``(name, why)`` for every data variable or coordinate that differs (missing on
        one side, another shape or dtype, values that differ), and how many names were
        compared.
    """

    names_a = set(a.data_vars) | set(a.coords)
    names_b = set(b.data_vars) | set(b.coords)
    out = [(n, "only in the original") for n in sorted(names_a - names_b)]
    out += [(n, "only in the rerun") for n in sorted(names_b - names_a)]
    for name in sorted(names_a & names_b):
        x, y = a[name], b[name]
        if x.dims != y.dims or x.shape != y.shape:
            out.append((name, f"shape {dict(x.sizes)} vs {dict(y.sizes)}"))
            continue
        x, y = x.values, y.values
        if x.dtype.kind in _TEXT or y.dtype.kind in _TEXT:
            xs, ys = _as_text(x), _as_text(y)
            if x.dtype.kind not in _TEXT or y.dtype.kind not in _TEXT:
                out.append((name, f"dtype {x.dtype} vs {y.dtype}"))
            elif not np.array_equal(xs, ys):
                out.append((name, f"{int(np.sum(xs != ys))} of {xs.size} values differ"))
            continue
        if x.dtype != y.dtype:
            out.append((name, f"dtype {x.dtype} vs {y.dtype}"))
            continue
        if x.dtype.kind in "fc":
            nx, ny = np.isnan(x), np.isnan(y)
            same = (nx & ny) | ((~nx & ~ny) & (
                x.view(f"u{x.dtype.itemsize}") == y.view(f"u{y.dtype.itemsize}")
                if x.dtype.kind == "f" else x == y))
        else:
            same = x == y
        same = np.asarray(same)
        if not same.all():
            out.append((name, f"{int(same.size - same.sum())} of {same.size} values differ"))
    return out, len(names_a | names_b)
