"""Continued branches of periodic orbits as self-describing datasets (``vibimpact
continue``).

:func:`follow_branch` is what the command runs: it reaches the starting orbit (integrating
from rest or a given state, optionally stepping the forcing frequency towards the start
as a sweep does, so that the orbit is the one a sweep follows) and continues it with
:func:`vibimpact.analysis.continue_orbit`.  :func:`branch_to_dataset` turns the
:class:`~vibimpact.analysis.Branch` into an ``xarray.Dataset`` with CF attributes (units,
declared flags) and every number needed to redo it; :func:`branch_from_dataset` gives the
Branch back.

Dimensions: ``point`` (the orbits, in continuation order: the parameter is not monotonic
past a fold), ``state``, ``multiplier`` and ``bifurcation`` (the events found along the
branch, possibly none).  The kind of each event is stored as the ``code`` of its
:class:`~vibimpact.base.bifurcation_kinds.BifurcationKind` (the codes of files written before
grazing joined are unchanged).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import logging

import numpy as np

from ..models.words import file_words
from ..base import _validate as _v
from ..base._fill import complex_parts
from ..base.bifurcation_kinds import BRANCH_KINDS, BifurcationKind, branch_flags

_log = logging.getLogger(__name__)
#: the attributes of a count whose -1 means "not counted": valid from 0, so that -1 is
#: outside the valid range, missing to a CF reader (CF 2.5.1), not a count
_COUNTED = dict(valid_min=np.int32(0))

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Mapping
    from typing import Any

    import xarray as xr
    from numpy.typing import ArrayLike

    from ..analysis import Branch, Steps
    from ..models.params import DuffingParams, Params
    from ..core.system import System

__all__ = ["STABLE_FLAGS", "branch_from_dataset", "branch_to_dataset", "follow_branch",
           "is_branch_dataset", "stretches"]

#: (flag_values, flag_meanings) of ``stable``
STABLE_FLAGS = ((0, 1), "unstable stable")

_TITLE = "vibimpact continuation of a periodic orbit"


def stretches(stable: ArrayLike) -> list[tuple[int, int, bool]]:
    """The runs of equal stability along a branch.

    Parameters
    ----------
    stable : array_like of bool, shape (k,)

    Returns
    -------
    list of (int, int, bool)
        ``(first, last, stable)`` index ranges (inclusive), in order.

    Examples
    --------
    >>> stretches([True, True, False, True])
    [(0, 1, True), (2, 2, False), (3, 3, True)]
    """
    st = np.asarray(stable, dtype=bool).reshape(-1)
    out, i = [], 0
    while i < st.size:
        j = i
        while j + 1 < st.size and st[j + 1] == st[i]:
            j += 1
        out.append((i, j, bool(st[i])))
        i = j + 1
    return out


def _flags(values, meanings, dtype):
    return dict(flag_values=np.array(values, dtype=dtype), flag_meanings=meanings)


def _kind_code(kind):
    """The stored code of a branch's bifurcation kind (a BifurcationKind or its short
    name); 0 (unknown) for one a branch file cannot hold."""
    try:
        # a lookup by value (EnumMeta.__call__), not a call of __new__
        kind = BifurcationKind(kind)  # type: ignore[call-arg]
    except ValueError:
        return BifurcationKind.UNKNOWN.code
    return kind.code if kind in BRANCH_KINDS else BifurcationKind.UNKNOWN.code


def follow_branch(system: System | Params | DuffingParams, *, stop: float,
                  param: str | None = None, n: int = 1,
                  state0: ArrayLike | None = None,
                  transient: int = 500, approach: float | None = None,
                  steps: Steps | None = None,
                  refine: float | None = 1e-6) -> tuple[Branch, np.ndarray]:
    """Reach a periodic orbit and continue it in one parameter.

    Parameters
    ----------
    system : System or parameter set
        The start: its value of ``param`` is where the branch begins.
    stop : float
        The other end of the parameter window.  Past a bound of the parameter's domain
        (:meth:`vibimpact.System.param_domain`, e.g. ``stop=-0.01`` for ``B >= 0``) the
        window is cut there: the branch ends on the bound, and its ``status`` says so.
    param : str, optional
        The parameter continued, by name (default: the model's forcing frequency,
        :attr:`vibimpact.models.Model.frequency_name`).  Its start value may lie on a bound of its
        domain (e.g. the built-in rotor's ``BT = 0``, as in its presets): the branch then
        steps into the domain (towards ``stop``).
    n : int
        Period of the orbit in forcing periods.
    state0 : array_like, optional
        Where the integration towards the orbit begins (rest by default).
    transient : int
        Forcing periods integrated before shooting (at every step of ``approach``).
    approach : float, optional
        Step the forcing frequency from this value to the system's in steps of 0.02,
        ``transient`` periods each, every step from the previous one's final state
        (:func:`vibimpact.sweeps.continued_state`): the orbit a sweep from there follows.
        Every step lies between two positive values, inside the forcing frequency's
        domain.
    steps : Steps, optional
        Step controls of :func:`~vibimpact.analysis.continue_orbit`.
    refine : float or None
        Width to which every stability change is narrowed (None: interpolated only).

    Returns
    -------
    (Branch, ndarray)
        The branch and the state its shooting started from.

    Raises
    ------
    ValueError
        Naming the argument (``state0`` when no period-``n`` orbit is found there).
    """
    from ..analysis import Steps, continue_orbit
    from ..core.system import to_system

    system = to_system(system, "system")
    stop = _v.finite("stop", stop)
    transient = _v.count("transient", transient, 0)
    mdl = system.model
    omega_name = mdl.frequency_name
    if param is None:
        param = omega_name
    if param == omega_name:  # a forcing frequency the solver can resolve, at both ends
        from ..sweeps.sweep import check_frequency

        check_frequency(system.omega, f"system's forcing frequency {omega_name}")
        check_frequency(stop, "stop")
    x = None if state0 is None else _v.state("state0", state0, system.n_state)
    if approach is not None:
        from ..sweeps import continued_state

        approach = _v.positive("approach", approach)
        x = continued_state(system.params, system.omega, eta_start=approach,
                            transient=transient, state0=x)
    else:
        x = system.simulate(periods=1, transient=transient, state0=x).final_state
    _log.info("branch of the P%d orbit in %s from %g towards %g; start state %s after %d "
              "periods of transient%s", n, param, system.param(param), stop,
              np.array2string(np.asarray(x), precision=4), transient,
              f" (eta stepped from {approach:g})" if approach is not None else "")
    branch = continue_orbit(system, x, n, param=param, stop=stop,
                            steps=Steps() if steps is None else steps,
                            direction=1 if stop >= system.param(param) else -1,
                            refine=refine)
    vals = np.asarray(branch.values, dtype=float)
    _log.info("branch: %d orbits, %s from %g to %g, %d stable; %d stability changes (%s); "
              "ended: %s", vals.size, param, vals[0] if vals.size else np.nan,
              vals[-1] if vals.size else np.nan, int(np.sum(branch.stable)),
              len(branch.bifurcations), ", ".join(f"{k} at {v:g}" for _, k, v in
                                                   branch.bifurcations) or "none",
              branch.status)
    return branch, np.asarray(x, dtype=np.float64)


def _point_vars(branch, names, unit=""):
    """The data variables on ``point`` (and ``state``, ``multiplier``); ``unit``: the
    model's length unit as a suffix (``" / clearance"``), or ``""``."""
    mu = np.asarray(branch.multipliers, dtype=complex)
    real, imag = complex_parts(mu)
    out = {
        "orbit_state": (("point", "state"), np.asarray(branch.states, dtype=np.float64),
                        dict(units="1", long_name="stroboscopic point of the orbit at the "
                                                  "start of a forcing period")),
        "floquet_real": (("point", "multiplier"), real,
                         dict(units="1", long_name="Floquet multipliers, real part, by "
                                                   "decreasing modulus")),
        "floquet_imag": (("point", "multiplier"), imag,
                         dict(units="1", long_name="Floquet multipliers, imaginary part")),
        "floquet_abs_max": ("point", np.abs(mu).max(axis=1) if mu.size else
                            np.zeros(0), dict(units="1", long_name="largest modulus "
                                              "|mu|max of the Floquet multipliers")),
        "stable": ("point", np.asarray(branch.stable, dtype="i1"),
                   dict(long_name="orbit stable (every |mu| < 1)",
                        **_flags(*STABLE_FLAGS, "i1"))),
    }
    impacts = getattr(branch, "impacts_per_period", None)
    if impacts is not None:
        out["impacts_per_period"] = (
            "point", np.asarray(impacts, dtype="i4"),
            dict(units="1", long_name="impacts (contact entries) per period of the orbit "
                                      "(-1: not counted)", **_COUNTED))
    for key, values in branch.amplitude.items():
        long_name = (f"response amplitude max |{key[:-2]}| of the orbit{unit}"
                     if key != "R_m" else
                     f"largest radial displacement max R of the orbit{unit}")
        out[key] = ("point", np.asarray(values, dtype=np.float64),
                    dict(units="1", long_name=long_name))
    return out


def _event_vars(branch):
    """The data variables on ``bifurcation``."""
    events = tuple(branch.bifurcations)
    brackets = tuple(branch.brackets) or tuple((v, v) for _, _, v in events)
    lo = [min(b) for b in brackets]
    hi = [max(b) for b in brackets]
    lower = dict(units="1", long_name="lower end of the parameter interval holding the "
                                      "bifurcation")
    value = dict(units="1", long_name="parameter value of the bifurcation (|mu|max - 1 "
                                      "interpolated in its interval; a grazing: the "
                                      "interval's midpoint)")
    impacts = tuple(getattr(branch, "event_impacts", ()) or ())
    if len(impacts) != len(events):
        impacts = ((-1, -1),) * len(events)
    return {
        "bifurcation_kind": ("bifurcation", np.array(
            [_kind_code(k) for _, k, _ in events], dtype="i1"),
            dict(long_name="kind of bifurcation: the multiplier leaving the unit circle "
                           "(-1 period doubling, +1 fold, complex pair Neimark-Sacker), "
                           "the parameter turning, or the impacts per period changing "
                           "(grazing)", **_flags(*branch_flags(), "i1"))),
        "bifurcation_impacts_before": (
            "bifurcation", np.array([a for a, _ in impacts], dtype="i4"),
            dict(units="1", long_name="impacts per period of the orbit before the "
                                      "bifurcation (-1: not counted)", **_COUNTED)),
        "bifurcation_impacts_after": (
            "bifurcation", np.array([b for _, b in impacts], dtype="i4"),
            dict(units="1", long_name="impacts per period of the orbit after the "
                                      "bifurcation (-1: not counted)", **_COUNTED)),
        "bifurcation_value": ("bifurcation", np.array([v for _, _, v in events], float),
                              value),
        "bifurcation_lower": ("bifurcation", np.array(lo, dtype=np.float64), lower),
        "bifurcation_upper": ("bifurcation", np.array(hi, dtype=np.float64),
                              dict(units="1", long_name="upper end of that interval")),
        "bifurcation_point": ("bifurcation", np.array([i for i, _, _ in events], "i4"),
                              dict(units="1", long_name="index (along point) of the first "
                                   "orbit past the bifurcation, or of the turning point")),
    }


def branch_to_dataset(branch: Branch, system: System | Params | DuffingParams, *,
                      start_state: ArrayLike | None = None, command: str | None = None,
                      attrs: Mapping[str, Any] | None = None) -> xr.Dataset:
    """A :class:`~vibimpact.analysis.Branch` as an ``xarray.Dataset``.

    Parameters
    ----------
    branch : Branch
        From :func:`vibimpact.analysis.continue_orbit` (or :func:`follow_branch`).
    system : System or parameter set
        The system it was continued in (parameters at the start, model, solver).
    start_state : array_like, optional
        The state the continuation's shooting started from (variable ``start_state``).
    command : str, optional
        The command line, attribute ``command``.
    attrs : dict, optional
        Further global attributes.

    Returns
    -------
    xarray.Dataset
        Coordinates: the parameter (named after it) and ``state``; variables
        ``orbit_state``, ``floquet_real``, ``floquet_imag``, ``floquet_abs_max``,
        ``stable`` (flag), ``impacts_per_period``, the amplitudes
        (:attr:`~vibimpact.analysis.Branch.amplitude`: ``X_m``, ``Y_m``, ``R_m`` for the
        built-in rotor) on ``point``; ``bifurcation_kind`` (flag: the
        :attr:`~vibimpact.base.bifurcation_kinds.BifurcationKind.code`),
        ``bifurcation_value``, ``bifurcation_lower``, ``bifurcation_upper``,
        ``bifurcation_point``, ``bifurcation_impacts_before``,
        ``bifurcation_impacts_after`` on ``bifurcation``.  Global attributes:
        ``continuation_param``, ``period``,
        ``status``, ``param_<name>``, ``solver_<key>``, ``command``.

    Raises
    ------
    ValueError
        Naming ``branch`` when it is not a Branch.
    """
    import xarray as xr

    from ..analysis import Branch
    from ..analysis.bifurcation import CONTINUATION_SOLVER
    from ..core.system import SOLVER_FIELDS, param_dict, to_system

    if not isinstance(branch, Branch):
        raise _v.WrongType(f"branch must be a vibimpact.analysis.Branch, got "
                         f"{type(branch).__name__}")
    system = to_system(system, "system")
    names = list(system.model.state_names)
    param = branch.param if isinstance(branch.param, str) else f"p{int(branch.param)}"
    data = _point_vars(branch, names, file_words(system.model)["unit"])
    data.update(_event_vars(branch))
    if start_state is not None:
        data["start_state"] = ("state", np.asarray(start_state, np.float64).reshape(-1),
                               dict(units="1", long_name="state the start orbit was shot "
                                                         "from"))
    coords = {param: ("point", np.asarray(branch.values, dtype=np.float64),
                      dict(units="1", long_name=f"continuation parameter {param}")),
              "state": ("state", np.array(names, dtype=object),
                        dict(long_name="state variable"))}
    ds = xr.Dataset(data, coords=coords)
    glob = {"title": _TITLE, "model": system.model.name, "continuation_param": param,
            "period": int(branch.n), "status": branch.status, "command": command}
    glob.update({f"param_{k}": v for k, v in param_dict(system).items()})
    glob.update({f"solver_{k}": v for k, v in system.settings(
        **CONTINUATION_SOLVER).as_dict(SOLVER_FIELDS).items()})
    glob.update(attrs or {})
    # NetCDF attributes: no None (a solver setting left to the integrator, no command)
    ds.attrs.update({k: "" if v is None else v for k, v in glob.items()})
    return ds


def is_branch_dataset(ds: xr.Dataset) -> bool:
    """Whether ``ds`` was made by :func:`branch_to_dataset` (a ``vibimpact continue``
    file)."""
    return (ds.attrs.get("title") == _TITLE and "point" in ds.dims
            and str(ds.attrs.get("continuation_param", "")) in ds.coords)


def branch_from_dataset(ds: xr.Dataset) -> Branch:
    """The :class:`~vibimpact.analysis.Branch` a dataset of :func:`branch_to_dataset`
    holds.

    Raises
    ------
    ValueError
        Naming ``ds`` when it is not such a dataset.
    """
    from ..analysis import Branch

    _v.dataset("ds", ds, "the xarray.Dataset of a continued branch (branch_to_dataset)")
    if not is_branch_dataset(ds):
        raise ValueError("ds is not a continued branch (a 'vibimpact continue' file)")
    param = str(ds.attrs["continuation_param"])
    amp = {str(k): ds[k].values.copy() for k in ds.data_vars
           if str(k).endswith("_m") and ds[k].dims == ("point",)}
    events = tuple((int(i), BifurcationKind.from_code(k), float(v)) for i, k, v in zip(
        ds["bifurcation_point"].values, ds["bifurcation_kind"].values,
        ds["bifurcation_value"].values))
    brackets = tuple((float(a), float(b)) for a, b in zip(
        ds["bifurcation_lower"].values, ds["bifurcation_upper"].values))
    mu = ds["floquet_real"].values + 1j * ds["floquet_imag"].values
    # files written before the impacts per period were counted: -1 (not counted)
    impacts = (ds["impacts_per_period"].values.astype(np.int64)
               if "impacts_per_period" in ds else np.full(ds.sizes["point"], -1, np.int64))
    around = (tuple((int(a), int(b)) for a, b in zip(
        ds["bifurcation_impacts_before"].values, ds["bifurcation_impacts_after"].values))
        if "bifurcation_impacts_before" in ds else ((-1, -1),) * len(events))
    return Branch(param, ds[param].values.copy(), ds["orbit_state"].values.copy(), mu,
                  ds["stable"].values.astype(bool), amp, int(ds.attrs["period"]), events,
                  str(ds.attrs.get("status", "")), brackets, impacts, around)
