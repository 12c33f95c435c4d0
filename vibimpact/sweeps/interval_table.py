"""The result of :func:`vibimpact.intervals`: a Dataset that prints as a table.

``print(vi.intervals(ds))`` shows every interval with its label (``to_dataframe()``
printed by pandas hides the middle columns, the label among them, in a narrow terminal);
:meth:`Intervals.to_markdown` gives the same table in Markdown.  An :class:`Intervals`
is an ``xarray.Dataset`` (a subclass, so every use of the Dataset ``intervals`` returned
before works: indexing, ``sizes``, ``to_dataframe()``, ``xarray.concat``, writing);
:attr:`Intervals.dataset` is the plain Dataset.

xarray is imported when the first table is made, not with this module.
"""
from __future__ import annotations

import functools

#: the variables a table needs (a Dataset derived from an Intervals that lacks one
#: prints as a Dataset)
COLUMNS = ("direction", "start", "end", "points", "label")


def _eta(value):
    """A grid value in the table's 8 columns: 4 decimals, or 4 significant digits from
    10^4 on (1e300 printed 300 digits)."""
    return f"{value:8.4f}" if abs(value) < 1e4 else f"{value:8.4g}"


def rows(iv):
    """``(direction, eta from, eta to, points, label)`` of every interval, as text."""
    return [(str(iv["direction"].values[k]), _eta(iv["start"].values[k]).strip(),
             _eta(iv["end"].values[k]).strip(), str(int(iv["points"].values[k])),
             str(iv["label"].values[k])) for k in range(iv.sizes["interval"])]


def _frequency(iv, symbol):
    """The name (``symbol``: the symbol) of the forcing frequency of the model the
    intervals are of (their ``model`` attribute); ``eta``, the sweeps' coordinate, for a
    model this installation does not know."""
    from .. import models

    name = iv.attrs.get("model")
    if not (isinstance(name, str) and name in models.names()):
        return "η" if symbol else "eta"
    model = models.get(name)
    freq = model.param_names[model.omega_index]
    return model.plot.symbol(freq) if symbol and model.plot is not None else freq


def table(iv):
    """The interval map as an aligned text table (:func:`vibimpact.format_intervals`)."""
    f = _frequency(iv, symbol=False)
    lines = [f"{'direction':<9} {f + ' from':>8} {f + ' to':>8} {'points':>6}  label"]
    for d, a, b, n, label in rows(iv):
        lines.append(f"{d:<9} {a:>8} {b:>8} {n:>6}  {label}")
    return "\n".join(lines)


def markdown(iv):
    """The interval map as a Markdown table (``|`` in a label escaped)."""
    f = _frequency(iv, symbol=True)
    lines = [f"| direction | {f} from | {f} to | points | label |",
             "|:--|--:|--:|--:|:--|"]
    for d, a, b, n, label in rows(iv):
        lines.append(f"| {d} | {a} | {b} | {n} | {label.replace('|', chr(92) + '|')} |")
    return "\n".join(lines)


def _is_table(ds):
    return "interval" in ds.dims and all(name in ds.variables for name in COLUMNS)


@functools.cache
def intervals_class():
    """The :class:`Intervals` class (made on first use, when xarray is imported)."""
    import xarray as xr

    class Intervals(xr.Dataset):
        """The labelled frequency-interval map of a sweep (:func:`vibimpact.intervals`).

        An ``xarray.Dataset`` on dimension ``interval`` (``start``, ``end``, ``label``,
        ``regime``, ``period``, ``impacts``, ``arcs``, ``points``, ``direction``) whose
        ``str()`` is the table of :func:`vibimpact.format_intervals`:
        ``print(vi.intervals(ds))`` shows every label.
        """

        __slots__ = ()

        def __str__(self):
            return table(self) if _is_table(self) else xr.Dataset.__repr__(self)

        def to_markdown(self) -> str:
            """The table as Markdown: direction, eta from, eta to, points, label.

            Returns
            -------
            str

            Raises
            ------
            ValueError
                When this Dataset (derived from the intervals) lacks a column.
            """
            if not _is_table(self):
                missing = [c for c in COLUMNS if c not in self.variables]
                if "interval" not in self.dims:
                    missing.append("interval dimension")
                raise ValueError(f"not an interval table (no {', '.join(missing)})")
            return markdown(self)

        @property
        def dataset(self) -> xr.Dataset:
            """The intervals as a plain ``xarray.Dataset`` (the data shared)."""
            return xr.Dataset(dict(self.data_vars), coords=self.coords, attrs=self.attrs)

    Intervals.__module__ = __name__
    Intervals.__qualname__ = "Intervals"
    return Intervals


def as_intervals(ds):
    """``ds`` (the Dataset of an interval map) as an :class:`Intervals`, sharing data."""
    cls = intervals_class()
    return cls(dict(ds.data_vars), coords=ds.coords, attrs=ds.attrs)


def __getattr__(name):  # Intervals itself, made on first use
    if name == "Intervals":
        return intervals_class()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
