"""Questions over a hunt's dataset, answered with the evidence either way:
:func:`find_orbit` ("is there a stable P6 with 8 impacts on the bottom half on
1.05-1.07?").
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from dataclasses import dataclass

import numpy as np

from ..base import _validate as _v
from .dataset import is_orbit_dataset
from .found import interval_text

if TYPE_CHECKING:  # names of the annotations only
    import xarray as xr

__all__ = ["OrbitAnswer", "find_orbit"]


@dataclass(frozen=True)
class OrbitAnswer:
    """The answer of :func:`find_orbit`.

    Attributes
    ----------
    found : bool
        Some orbit of the hunt matches.
    orbits : tuple of int
        The matching orbits (indices along ``orbit``).
    where : tuple of tuple of (float, float)
        For each matching orbit, the forcing-frequency intervals (between branch points)
        where it matches; the hunt's value alone for an orbit not continued.
    evidence : tuple of str
        Lines that say why: each match with where it holds, or, without one, the orbits
        of that period (or with those impacts) and what they are instead, and how wide
        the hunt was.
    """

    found: bool
    orbits: tuple
    where: tuple
    evidence: tuple

    def __str__(self):
        return "\n".join(self.evidence)


def _wanted(period, impacts, stable, arcs, within):
    """Checked criteria."""
    period = None if period is None else _v.count("period", period, 1)
    impacts = None if impacts is None else _v.count("impacts", impacts, 0)
    stable = None if stable is None else _v.flag("stable", stable)
    if arcs is not None and not isinstance(arcs, str):
        raise _v.WrongType(f"arcs must be a str (words of the arcs, e.g. 'bottom'), got "
                           f"{type(arcs).__name__} {arcs!r}")
    if within is not None:
        try:
            lo, hi = (_v.finite("within", w) for w in within)
        except TypeError:
            raise _v.WrongType(f"within must be (low, high), got {within!r}") from None
        if hi < lo:
            raise ValueError(f"within must be (low, high) with low <= high, got {within!r}")
        within = (lo, hi)
    return period, impacts, stable, arcs, within


def _runs(values, ok):
    """Intervals ``(first, last)`` of the runs of True in ``ok`` along ``values``."""
    out, start = [], None
    for i, flag in enumerate(ok):
        if flag and start is None:
            start = i
        if not flag and start is not None:
            out.append((float(values[start]), float(values[i - 1])))
            start = None
    if start is not None:
        out.append((float(values[start]), float(values[len(ok) - 1])))
    return tuple(out)


def _match(ds, i, impacts, stable, within):
    """Where orbit ``i`` has ``impacts`` and ``stable`` inside ``within``: its branch
    points (or the hunt's value when it was not continued); () where nowhere."""
    param, value = ds.attrs["forcing_param"], float(ds.attrs["forcing_value"])
    vals = ds[f"branch_{param}"].values[i] if f"branch_{param}" in ds else np.zeros(0)
    keep = np.isfinite(vals)
    if keep.any():
        vals = vals[keep]
        imp = ds["branch_impacts"].values[i][keep]
        st = ds["branch_stable"].values[i][keep] == 1
    else:
        vals = np.array([value])
        imp = np.array([int(ds["impacts_per_period"].values[i])])
        st = np.array([bool(ds["stable"].values[i])])
    ok = np.ones(vals.size, dtype=bool)
    if impacts is not None:
        ok &= imp == impacts
    if stable is not None:
        ok &= st == stable
    if within is not None:
        ok &= (vals >= within[0]) & (vals <= within[1])
    return _runs(vals, ok)


def _describe(ds, i):
    """One line on orbit ``i``: label, arcs, existence and stability intervals."""
    line = f"#{i} {ds['label'].values[i]} ({ds['arcs'].values[i] or 'no contact'})"
    lo = float(ds["exists_lo"].values[i]) if "exists_lo" in ds else np.nan
    if np.isfinite(lo):
        hi = float(ds["exists_hi"].values[i])
        stab = [(a, b) for a, b in zip(ds["stable_lo"].values[i], ds["stable_hi"].values[i])
                if np.isfinite(a)]
        line += (f": exists on {lo:.5g}-{hi:.5g} ({ds['exists_lo_reason'].values[i]} / "
                 f"{ds['exists_hi_reason'].values[i]}), stable on {interval_text(stab)}, "
                 f"same impacts on {float(ds['same_impacts_lo'].values[i]):.5g}-"
                 f"{float(ds['same_impacts_hi'].values[i]):.5g}")
    return line


def _ranges(values):
    """``[1, 2, 3, 6, 8, 9]`` -> ``"1-3, 6, 8-9"``."""
    vals = sorted(int(v) for v in values)
    out, i = [], 0
    while i < len(vals):
        j = i
        while j + 1 < len(vals) and vals[j + 1] == vals[j] + 1:
            j += 1
        out.append(str(vals[i]) if i == j else f"{vals[i]}-{vals[j]}")
        i = j + 1
    return ", ".join(out)


def _asked(period, impacts, stable, arcs, within, param):
    words = [("stable " if stable else "unstable ") if stable is not None else "",
             f"P{period}" if period else "orbit",
             f" with {impacts} impacts" if impacts is not None else "",
             f" on arcs '{arcs}'" if arcs else "",
             f" on {param} {within[0]:g}-{within[1]:g}" if within else ""]
    return "".join(words)


@_v.checks_flags
def find_orbit(ds: xr.Dataset, period: int | None = None, impacts: int | None = None, *,
               stable: bool | None = None, arcs: str | None = None,
               within: tuple[float, float] | None = None) -> OrbitAnswer:
    """Is there an orbit of this period, these impacts, this stability, on these arcs,
    in this interval of the forcing frequency, among a hunt's orbits?

    An orbit matches where, at a point of its continued branch inside ``within``, its
    impacts per period and stability are those asked (the branch points are a step
    apart: a match narrower than a step can be missed; without continuation only the
    hunt's value counts), and the words of its arcs at the hunt's value contain
    ``arcs``.  The answer is evidence either way: the matches with where they hold, or
    the orbits of that period (else those with those impacts) and what they are
    instead, and how wide the hunt was: an orbit no start converged to is not
    excluded by the hunt.

    Parameters
    ----------
    ds : xarray.Dataset
        A hunt's dataset (:func:`vibimpact.orbits.hunt_to_dataset`, or a file of
        ``vibimpact orbits``).
    period : int, optional
        Minimal period.
    impacts : int, optional
        Impacts per period.
    stable : bool, optional
    arcs : str, optional
        Words the arcs must contain (``"bottom"``: all impacts on the bottom half).
    within : (float, float), optional
        Forcing-frequency interval.

    Returns
    -------
    OrbitAnswer

    Raises
    ------
    ValueError
        Naming the argument.

    Examples
    --------
    >>> ans = find_orbit(ds, period=6, impacts=8, stable=True, arcs="bottom",
    ...                  within=(1.05, 1.07))                    # doctest: +SKIP
    >>> print(ans)                                               # doctest: +SKIP
    """
    _v.dataset("ds", ds, "the xarray.Dataset of an orbit hunt (hunt_to_dataset)")
    if not is_orbit_dataset(ds):
        raise ValueError("ds is not an orbit hunt's dataset (hunt_to_dataset)")
    period, impacts, stable, arcs, within = _wanted(period, impacts, stable, arcs, within)
    param = str(ds.attrs["forcing_param"])
    k = ds.sizes["orbit"]
    per = ds["period"].values
    words = ds["arcs"].values
    hits, where = [], []
    for i in range(k):
        if period is not None and per[i] != period:
            continue
        if arcs is not None and arcs not in str(words[i]):
            continue
        runs = _match(ds, i, impacts, stable, within)
        if runs:
            hits.append(i)
            where.append(runs)
    asked = _asked(period, impacts, stable, arcs, within, param)
    periods = np.atleast_1d(ds.attrs.get("periods", []))
    scope = (f"hunt at {param} = {float(ds.attrs['forcing_value']):g}: {k} orbits from "
             f"{int(ds.attrs.get('n_seeds', 0))} seeds, periods {_ranges(periods)}"
             + ("" if int(ds.attrs.get("continued", 0)) else "; not continued"))
    if hits:
        lines = [f"yes: {asked}: {len(hits)} found ({scope})"]
        lines += [f"  {_describe(ds, i)}; matches on {interval_text(w)}"
                  for i, w in zip(hits, where)]
    else:
        lines = [f"no {asked} ({scope}); an orbit no start converged to is not excluded"]
        near = [i for i in range(k) if period is not None and per[i] == period]
        what = f"P{period} orbits found, none matching" if near else (
            f"no P{period} orbit found" if period is not None else "")
        if not near and impacts is not None:
            near = [i for i in range(k)
                    if int(ds["impacts_per_period"].values[i]) == impacts]
            what = ", ".join(w for w in (what, f"orbits with {impacts} impacts" if near
                                         else f"no orbit with {impacts} impacts") if w)
        lines.append(f"  {what or 'no orbit found'}" + (":" if near else ""))
        lines += [f"    {_describe(ds, i)}" for i in near]
    return OrbitAnswer(bool(hits), tuple(hits), tuple(where), tuple(lines))
