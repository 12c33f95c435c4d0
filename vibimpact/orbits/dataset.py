"""A hunt's orbits as a self-describing ``xarray.Dataset`` and NetCDF file
(``vibimpact orbits``).

Dimensions: ``orbit`` (the orbits found, as :attr:`OrbitHunt.orbits` orders them),
``phase`` (the points of each cycle; the longest period, shorter cycles padded with
NaN), ``state``, ``multiplier``, ``interval`` (the stable sub-intervals of each orbit,
padded with NaN), ``branch_point`` (the points of each orbit's continued branch in
increasing forcing frequency, padded) and ``seed`` (every seed of the hunt).  Complex
Floquet multipliers are stored as ``floquet_real`` and ``floquet_imag`` (as
:mod:`vibimpact.continuation.branches` stores them).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import logging

import numpy as np

from ..models.words import file_words
from ..base import _validate as _v
from ..base._fill import complex_parts

_log = logging.getLogger(__name__)

if TYPE_CHECKING:  # names of the annotations only
    import os
    from collections.abc import Mapping
    from typing import Any

    import xarray as xr

    from ..core.system import System
    from .found import OrbitHunt

__all__ = ["hunt_to_dataset", "write_orbits", "read_orbits", "is_orbit_dataset",
           "TITLE"]

TITLE = "vibimpact orbit hunt: periodic orbits of the stroboscopic map"
_FLAG = dict(flag_values=np.array([0, 1], dtype="i1"), flag_meanings="unstable stable")


def _padded(rows, width, fill=np.nan, dtype=np.float64):
    """Rows of unequal length as one (len(rows), width) array padded with ``fill``."""
    out = np.full((len(rows), width), fill, dtype=dtype)
    for i, r in enumerate(rows):
        out[i, :len(r)] = r
    return out


def _orbit_vars(orbits, d, obstacle="obstacle"):
    """Variables on ``orbit`` (with ``phase``, ``state``, ``multiplier``); ``obstacle``:
    what the model's contact meets, in words."""
    k = len(orbits)
    width = max([o.period for o in orbits], default=1)
    pts = np.full((k, width, d), np.nan)
    for i, o in enumerate(orbits):
        pts[i, :o.period] = o.cycle
    mu = np.array([o.multipliers for o in orbits], dtype=complex).reshape(k, d)
    real, imag = complex_parts(mu)

    def ints(attr):
        return np.array([getattr(o, attr) for o in orbits], dtype="i4")

    one = dict(units="1")
    return {
        "period": ("orbit", ints("period"), dict(one, long_name="minimal period of the "
                                                  "orbit in forcing periods",
                                                  valid_min=np.int32(1))),
        "impacts_per_period": ("orbit", ints("impacts"), dict(one, long_name=(
            "impacts (contact entries) per period of the orbit (-1: not counted)"),
            valid_min=np.int32(0))),
        "n_arcs": ("orbit", ints("n_arcs"), dict(one, long_name="contact arcs the "
                                                  "impacts fall on")),
        "arcs": ("orbit", np.array([o.arcs for o in orbits], dtype=object),
                 dict(long_name="where the impacts fall, in words")),
        "stable": ("orbit", np.array([o.stable for o in orbits], dtype="i1"),
                   dict(long_name="orbit stable (every |mu| < 1)", **_FLAG)),
        "permanent_contact": ("orbit", np.array([o.permanent for o in orbits], dtype="i1"),
                              dict(long_name="no impact, in contact throughout (rolling "
                                             f"or whirling on the {obstacle})",
                                   flag_values=np.array([0, 1], dtype="i1"),
                                   flag_meanings="not_permanent permanent_contact")),
        "label": ("orbit", np.array([o.label for o in orbits], dtype=object),
                  dict(long_name="period, impacts per period and stability")),
        "orbit_point": (("orbit", "phase", "state"), pts, dict(one, long_name=(
            "stroboscopic points of the cycle from the canonical phase (largest first "
            "state variable); NaN past the period"))),
        "floquet_real": (("orbit", "multiplier"), real, dict(one, long_name=(
            "Floquet multipliers of P^period, real part, by decreasing modulus"))),
        "floquet_imag": (("orbit", "multiplier"), imag, dict(one, long_name=(
            "Floquet multipliers, imaginary part"))),
        "floquet_abs_max": ("orbit", np.abs(mu).max(axis=1) if k else np.zeros(0),
                            dict(one, long_name="largest modulus |mu|max")),
        "residual": ("orbit", np.array([o.residual for o in orbits], dtype=np.float64),
                     dict(one, long_name="Newton residual max |P^period(x) - x|")),
        "found_as": ("orbit", ints("found_as"), dict(one, long_name=(
            "period of the shooting that converged to the orbit"))),
        "seed_index": ("orbit", ints("seed"), dict(one, long_name=(
            "index (along seed) of the seed whose trajectory gave the start"))),
    }


def _extent_vars(orbits, param):
    """Variables of the existence and stability intervals (NaN: not continued)."""
    ext = [o.extent for o in orbits]
    nan = np.nan

    def col(f, fill=nan):
        return np.array([fill if e is None else f(e) for e in ext], dtype=np.float64)

    def text(f):
        return np.array(["" if e is None else f(e) for e in ext], dtype=object)

    n_int = max([len(e.stable) for e in ext if e is not None], default=0)
    n_pts = max([e.values.size for e in ext if e is not None], default=0)
    stab = [() if e is None else e.stable for e in ext]
    br = [np.zeros(0) if e is None else e for e in ext]
    one = dict(units="1")
    p = f"forcing frequency {param}"
    return {
        "exists_lo": ("orbit", col(lambda e: e.lo), dict(one, long_name=(
            f"lowest {p} to which the orbit was followed"))),
        "exists_hi": ("orbit", col(lambda e: e.hi), dict(one, long_name=(
            f"highest {p} to which the orbit was followed"))),
        "exists_lo_reason": ("orbit", text(lambda e: e.lo_reason),
                             dict(long_name="why the orbit ends at exists_lo")),
        "exists_hi_reason": ("orbit", text(lambda e: e.hi_reason),
                             dict(long_name="why the orbit ends at exists_hi")),
        "stable_lo": (("orbit", "interval"), _padded([[a for a, _ in s] for s in stab],
                                                      n_int), dict(one, long_name=(
            f"low end of each {p} interval in which the orbit is stable (NaN: none)"))),
        "stable_hi": (("orbit", "interval"), _padded([[b for _, b in s] for s in stab],
                                                      n_int), dict(one, long_name=(
            "high end of each stable interval"))),
        "same_impacts_lo": ("orbit", col(lambda e: e.same_impacts[0]), dict(
            one, long_name=f"low end of the {p} interval about the hunt's value with "
                           "the same impacts per period")),
        "same_impacts_hi": ("orbit", col(lambda e: e.same_impacts[1]), dict(
            one, long_name="high end of that interval")),
        f"branch_{param}": (("orbit", "branch_point"), _padded(
            [getattr(e, "values", ()) for e in br], n_pts), dict(one, long_name=(
                f"{p} of the orbit's continued branch, increasing (NaN: padding)"))),
        "branch_stable": (("orbit", "branch_point"), _padded(
            [getattr(e, "stable_points", ()) for e in br], n_pts, -1, "i1"), dict(
            long_name="orbit stable at the branch point (-1: padding)",
            flag_values=np.array([-1, 0, 1], dtype="i1"),
            flag_meanings="none unstable stable")),
        "branch_impacts": (("orbit", "branch_point"), _padded(
            [getattr(e, "impacts", ()) for e in br], n_pts, -1, "i4"), dict(
            one, long_name="impacts per period at the branch point (-1: not counted "
                           "or padding)", valid_min=np.int32(0))),
        "branch_abs_max": (("orbit", "branch_point"), _padded(
            [getattr(e, "abs_max", ()) for e in br], n_pts), dict(one, long_name=(
                "|mu|max at the branch point"))),
    }


def hunt_to_dataset(hunt: OrbitHunt, system: System, *, command: str | None = None,
                    attrs: Mapping[str, Any] | None = None) -> xr.Dataset:
    """An :class:`~vibimpact.orbits.OrbitHunt` as an ``xarray.Dataset``.

    Parameters
    ----------
    hunt : OrbitHunt
    system : System or parameter set
        The system hunted (its parameters and solver settings become attributes).
    command : str, optional
        The command line (attribute ``command``).
    attrs : dict, optional
        Further global attributes.

    Returns
    -------
    xarray.Dataset
        Per orbit: ``period``, ``impacts_per_period``, ``n_arcs``, ``arcs``, ``stable``
        (flag), ``permanent_contact`` (flag), ``label``, ``orbit_point`` (orbit, phase, state),
        ``floquet_real``,
        ``floquet_imag`` (orbit, multiplier), ``floquet_abs_max``, ``residual``,
        ``found_as``, ``seed_index``; the intervals ``exists_lo``, ``exists_hi``,
        ``exists_lo_reason``, ``exists_hi_reason``, ``stable_lo``, ``stable_hi``
        (orbit, interval), ``same_impacts_lo``, ``same_impacts_hi``; the branch
        ``branch_<param>``, ``branch_stable``, ``branch_impacts``, ``branch_abs_max``
        (orbit, branch_point); ``seed_state`` (seed, state).  Global attributes: the
        forcing frequency's name and value, the periods, the seeds' counts, the
        settings, counts and timings of the hunt (``count_failed_seeds``,
        ``count_failed_shots``: integrations that failed, with the solver's first
        reason in ``failure``), ``param_<name>``, ``solver_<key>``.

    Raises
    ------
    ValueError
        Naming ``hunt`` when it is not an OrbitHunt.
    """
    import xarray as xr

    from ..core.system import SOLVER_FIELDS, param_dict, to_system
    from .found import OrbitHunt

    if not isinstance(hunt, OrbitHunt):
        raise _v.WrongType(f"hunt must be a vibimpact.orbits.OrbitHunt, got "
                           f"{type(hunt).__name__}")
    system = to_system(system, "system")
    names = list(system.model.state_names)
    orbits = list(hunt.orbits)
    data = _orbit_vars(orbits, len(names), file_words(system.model)["obstacle"])
    data.update(_extent_vars(orbits, hunt.param))
    data["seed_state"] = (("seed", "state"), np.asarray(hunt.seeds, dtype=np.float64),
                          dict(units="1", long_name="seed states (the user's first, then "
                                                    "the random ones)"))
    coords = {"orbit": ("orbit", np.arange(len(orbits), dtype="i4"),
                        dict(long_name="orbit index")),
              "state": ("state", np.array(names, dtype=object),
                        dict(long_name="state variable"))}
    ds = xr.Dataset(data, coords=coords)
    st = hunt.settings
    glob = {"title": TITLE, "model": system.model.name, "forcing_param": hunt.param,
            "forcing_value": float(hunt.value), "periods": np.array(hunt.periods, "i4"),
            "n_seeds": int(hunt.seeds.shape[0]), "n_user_seeds": int(hunt.n_user),
            "random_seed": int(hunt.random_seed),
            "continued": int(any(o.extent is not None for o in orbits)),
            "command": command}
    glob.update({f"hunt_{k}": v for k, v in st.items()})
    glob.update({f"count_{k}": int(v) for k, v in hunt.counts.items()})
    glob["failure"] = str(hunt.failure)
    glob.update({k: round(float(v), 3) for k, v in hunt.timings.items()})
    glob.update({f"param_{k}": v for k, v in param_dict(system).items()})
    glob.update({f"solver_{k}": v for k, v in system.settings().as_dict(
        SOLVER_FIELDS).items()})
    glob.update(attrs or {})
    ds.attrs.update({k: "" if v is None else v for k, v in glob.items()})
    _log.info("orbit hunt at %s = %g from %d seeds: %d orbits (%s); counts %s; timings %s",
              hunt.param, float(hunt.value), int(hunt.seeds.shape[0]), len(orbits),
              "; ".join(str(o.label) for o in orbits) or "none", dict(hunt.counts),
              {k: round(float(v), 2) for k, v in hunt.timings.items()})
    return ds


def is_orbit_dataset(ds: xr.Dataset) -> bool:
    """Whether ``ds`` was made by :func:`hunt_to_dataset`."""
    return ds.attrs.get("title") == TITLE and "orbit" in ds.dims


@_v.checks_flags
def write_orbits(ds: xr.Dataset, path: str | os.PathLike[str],
                 overwrite: bool = False) -> None:
    """Write a hunt's dataset to NetCDF atomically (:func:`vibimpact.io.write_netcdf`).

    Raises
    ------
    ValueError
        Naming ``ds`` when it is not a hunt's dataset; as
        :func:`~vibimpact.io.write_netcdf` for the path.
    """
    from ..io import write_netcdf

    _v.dataset("ds", ds, "the xarray.Dataset of an orbit hunt (hunt_to_dataset)")
    if not is_orbit_dataset(ds):
        raise ValueError("ds is not an orbit hunt's dataset (hunt_to_dataset)")
    write_netcdf(ds, path, overwrite=overwrite)


def read_orbits(path: str | os.PathLike[str]) -> xr.Dataset:
    """Read a file of :func:`write_orbits` (fully loaded).

    Raises
    ------
    ValueError
        Naming ``path`` when the file is not an orbit hunt's.
    """
    from ..io import read_netcdf

    ds = read_netcdf(path)
    if not is_orbit_dataset(ds):
        raise ValueError(f"path {str(path)!r} is not an orbit hunt's file "
                         "('vibimpact orbits')")
    return ds
