"""Comparing two datasets bit for bit: their data, coordinates and attributes (what
``vibimpact rerun`` and the tests use to say two files are the same run).

Re-exported by :mod:`vibimpact.io`, where the readers and writers are.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..base import _validate as _v

if TYPE_CHECKING:  # names of the annotations only
    import xarray as xr

__all__ = ["attribute_differences", "differences"]


#: dtype kinds of text: objects (str), unicode, bytes, NumPy's StringDType (Zarr)
TEXT_KINDS = "OUST"


def _as_text(x):
    """An array of text as an array of ``str`` (StringDType through objects)."""
    return x.astype(object).astype(str) if x.dtype.kind == "T" else x.astype(str)


def _same_value(a, b):
    """Whether two attribute values are the same: text as text, numbers bit for bit
    (NaN equal to NaN) whatever their width (a file's int8 ``flag_values`` equal the
    int64 of a list), a one-element sequence equal to its element (NetCDF reads one
    back as the other)."""
    if isinstance(a, str) or isinstance(b, str):
        return isinstance(a, str) and isinstance(b, str) and a == b
    x, y = np.ravel(np.asarray(a)), np.ravel(np.asarray(b))
    if x.shape != y.shape or (x.dtype.kind in "biu") != (y.dtype.kind in "biu") or \
            x.dtype.kind in TEXT_KINDS or y.dtype.kind in TEXT_KINDS:
        return x.shape == y.shape and x.dtype.kind in TEXT_KINDS and \
            y.dtype.kind in TEXT_KINDS and bool(np.array_equal(_as_text(x), _as_text(y)))
    return bool(np.array_equal(x, y, equal_nan=x.dtype.kind in "fc"))


def _short(value):
    """``repr`` of an attribute value, at most 80 characters."""
    if isinstance(value, (np.ndarray, np.generic)):
        value = value.item() if value.size == 1 else value.tolist()
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


@_v.checks_flags
def attribute_differences(a: xr.Dataset, b: xr.Dataset, *,
                          files: bool = False) -> tuple[list[tuple[str, str]], int]:
    """Compare the attributes of two datasets: every global attribute but those of
    :data:`vibimpact.base.provenance.NOT_COMPARED` (time stamps, versions, platform, the
    command line), and every attribute of every variable and coordinate both have.

    Values are compared as text when either is text, numbers bit for bit (NaN equal to
    NaN) whatever their width (a file's int8 ``flag_values`` equal a list's int64), a
    one-element sequence equal to its element (NetCDF reads one back as the other).

    Parameters
    ----------
    a, b : xarray.Dataset
    files : bool
        Both were written by the same command (``vibimpact rerun``): an attribute on one
        side only is a difference too.  Otherwise only the attributes both have are
        compared (a dataset of the API lacks the attributes the command line and the
        writers add).

    Returns
    -------
    (list of (str, str), int)
        ``(name, why)`` for every attribute that differs, named ``attr`` (global) or
        ``variable:attr`` (as ``ncdump`` writes them), and how many were compared.
    """
    from ..base.provenance import NOT_COMPARED

    pairs = [("", a.attrs, b.attrs, NOT_COMPARED)]
    pairs += [(f"{n}:", a[n].attrs, b[n].attrs, ())
              for n in sorted((set(a.variables) & set(b.variables)), key=str)]
    out, checked = [], 0
    for prefix, x, y, skip in pairs:
        for key in sorted({k for k in (*x, *y) if k not in skip}, key=str):
            name = f"{prefix}{key}"
            if key in x and key in y:
                checked += 1
                if not _same_value(x[key], y[key]):
                    out.append((name, f"{_short(x[key])} vs {_short(y[key])}"))
            elif files:
                checked += 1
                side, value = ("original", x[key]) if key in x else ("rerun", y[key])
                out.append((name, f"only in the {side} ({_short(value)})"))
    return out, checked


@_v.checks_flags
def differences(a: xr.Dataset, b: xr.Dataset, *,
                attributes: bool = True) -> tuple[list[tuple[str, str]], int]:
    """Compare two datasets bit for bit (NaN equal to NaN): their data variables and
    coordinates and, with ``attributes``, the attributes both have
    (:func:`attribute_differences`: every global attribute but the time stamps, versions,
    platform and command line of :data:`vibimpact.base.provenance.NOT_COMPARED`, which differ
    between two runs of the same command, and every attribute of every variable), so
    that a file whose attributes contradict its data or its command (units, flag
    meanings, parameters changed after the run) is not the same.

    Parameters
    ----------
    a, b : xarray.Dataset
    attributes : bool
        Compare the attributes both datasets have too (named ``attribute NAME`` or
        ``attribute VARIABLE:NAME`` in the list).

    Returns
    -------
    (list of (str, str), int)
        ``(name, why)`` for every data variable or coordinate that differs (missing on
        one side, another shape or dtype, values that differ) and every attribute, and
        how many variable names were compared.
    """

    # the names as str (a NetCDF or Zarr name is one): sorted, and reported as text
    names_a = set(map(str, a.data_vars)) | set(map(str, a.coords))
    names_b = set(map(str, b.data_vars)) | set(map(str, b.coords))
    out = [(n, "only in the original") for n in sorted(names_a - names_b)]
    out += [(n, "only in the rerun") for n in sorted(names_b - names_a)]
    for name in sorted(names_a & names_b):
        da, db = a[name], b[name]
        if da.dims != db.dims or da.shape != db.shape:
            out.append((name, f"shape {dict(da.sizes)} vs {dict(db.sizes)}"))
            continue
        x, y = da.values, db.values
        if x.dtype.kind in TEXT_KINDS or y.dtype.kind in TEXT_KINDS:
            xs, ys = _as_text(x), _as_text(y)
            if x.dtype.kind not in TEXT_KINDS or y.dtype.kind not in TEXT_KINDS:
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
    if attributes:
        out += [(f"attribute {n}", why) for n, why in attribute_differences(a, b)[0]]
    return out, len(names_a | names_b)
