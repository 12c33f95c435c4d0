"""Start a run where a sweep left the motion: coexisting attractors.

A sweep with continuation follows one attractor through ``eta``; a run started from rest
at the same ``eta`` may settle on another one that coexists with it.  For example, the
built-in rotor's preset fig8 at ``eta = 1.25``: swept up from ``eta = 1.1`` the rotor is
chaotic and hits the whole retainer, while from rest it settles on the impactless
period-1 orbit.  :func:`sweep_start` gives the parameters and the state the sweep had at
one grid point and direction (the point's ``final_state``, a point of the attractor the
sweep found there), so that a run from it stays on that attractor:

>>> import vibimpact as vi
>>> ds = vi.sweep(vi.presets.get("fig8"), [1.1, 1.25])       # doctest: +SKIP
>>> start = vi.sweeps.sweep_start(ds, 1.25)                  # doctest: +SKIP
>>> run = vi.simulate(start.params, periods=200, transient=500,
...                   state0=start.state)                    # doctest: +SKIP

``vibimpact simulate --from sweep.nc --eta 1.25`` does the same and records the start in
the file it writes (:meth:`SweepStart.attrs`, and the ``state0`` variable), so that
``vibimpact rerun`` redoes the run from the recorded state without the sweep's file
(:meth:`SweepStart.from_run_dataset`).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import json
import math
from dataclasses import dataclass

import numpy as np

from ..analysis.classify import Label
from ..points.codes import REGIME_CODES
from ..base import _validate as _v
from ..io.recorded import recorded_model, recorded_params, recorded_state
from .dataset import SWEEP_DATASET, sweep_params

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Mapping

    import xarray as xr

    from ..models.params import Params

__all__ = ["SweepStart", "sweep_start"]

#: an eta within this (relative to max(1, |eta|)) of a grid value is that grid value
ETA_MATCH = 1e-9

#: global attribute of a run file -> SweepStart field, the start's provenance
_ATTRS = {"start_sweep": "source", "start_eta": "eta", "start_direction": "direction",
          "start_label": "label", "start_sweep_command": "sweep_command"}


@dataclass(frozen=True)
class SweepStart:
    """Where a sweep left the motion at one grid point: what a run needs to start there.

    Attributes
    ----------
    params : parameter set
        The sweep's parameters at the grid point's ``eta`` (the grid value itself), as
        its model's parameter set (:class:`~vibimpact.Params` for the built-in rotor).
    state : ndarray, shape (n_state,)
        The point's ``final_state`` (the model's state; the built-in rotor's X, Y, X',
        Y') at the start of a forcing period.
    eta : float
        The grid value.
    direction : str
        "up" or "down".
    label : str
        What the sweep found there (its ``label``), e.g. "chaotic, impacting, whole
        circle".
    source : str
        The sweep's file, when read from one ("" otherwise).
    sweep_command : str
        The command line that made the sweep ("" when it records none).
    """

    params: Params
    state: np.ndarray
    eta: float
    direction: str
    label: str
    source: str = ""
    sweep_command: str = ""

    def attrs(self) -> dict[str, str | float]:
        """The start's provenance, as the global attributes of a run's file.

        Returns
        -------
        dict
            ``start_sweep``, ``start_eta``, ``start_direction``, ``start_label``,
            ``start_sweep_command`` and ``start_params`` (the sweep's parameters as
            JSON); the state itself is the run's ``state0`` variable.
        """
        out = {key: getattr(self, name) for key, name in _ATTRS.items()}
        out["start_params"] = json.dumps(self.params.as_dict(), sort_keys=True)
        return out

    @classmethod
    def from_run_dataset(cls, ds: xr.Dataset, *, name: str = "ds") -> SweepStart:
        """The start recorded in the dataset of a run made from a sweep.

        Parameters
        ----------
        ds : xarray.Dataset
            A file written by ``vibimpact simulate --from`` (its ``start_*``
            attributes and ``state0`` variable).
        name : str
            How the messages name ``ds`` (``vibimpact rerun``: "it", the file).

        Returns
        -------
        SweepStart

        Raises
        ------
        ValueError
            When ``ds`` records no complete start.
        """
        from ..io.recorded import recorded_number

        a = ds.attrs
        missing = [k for k in (*_ATTRS, "start_params") if k not in a]
        if missing or "state0" not in ds:
            raise ValueError(f"{name} records no start from a sweep (missing "
                             f"{', '.join(missing + ([] if 'state0' in ds else ['state0']))})")
        try:  # every value as if typed: the parameters, the state, eta and direction
            params = recorded_params(a, name, key="start_params", prefix=None)
            model = recorded_model(a, name, required=True)
            state = recorded_state(ds["state0"].values, model, f"{name}'s state0")
            eta = recorded_number(a["start_eta"], f"{name}'s start_eta")
            freq = model.param_names[model.omega_index]
            if eta != getattr(params, freq):
                raise ValueError(f"start_eta = {eta!r} is not the {freq} of its "
                                 f"start_params ({getattr(params, freq)!r})")
            if a["start_direction"] not in ("up", "down"):
                raise ValueError(f"start_direction is {str(a['start_direction'])[:40]!r}, "
                                 "not up or down")
        except ValueError as exc:
            raise ValueError(f"{name} has a damaged start record ({exc})") from None
        return cls(params=params, state=state, eta=eta,
                   direction=str(a["start_direction"]), label=str(a["start_label"]),
                   source=str(a["start_sweep"]), sweep_command=str(a["start_sweep_command"]))


def _directions(ds):
    if "direction" in ds.dims:
        return [str(d) for d in ds["direction"].values]
    return [str(ds.attrs.get("sweep_direction", ds.attrs.get("direction", "up")))]


#: how the messages of :func:`sweep_start` name its arguments by default
ARGUMENT_NAMES = {"ds": "ds", "eta": "eta", "direction": "direction"}


def _check_sweep(ds, name="ds"):
    hint = "; a Run is one simulation, not a sweep" if hasattr(ds, "strobe") else ""
    _v.dataset(name, ds, SWEEP_DATASET, hint)
    if "map_vary" in ds.attrs:
        raise ValueError(f"{name} is a parameter map (vibimpact map), not a sweep")
    missing = [n for n in ("regime", "label", "final_state") if n not in ds]
    if "eta" not in ds.dims or missing:
        what = f"no {', '.join(missing)}" if missing else "no dimension eta"
        raise ValueError(f"{name} is not a sweep dataset ({what}); use a file from "
                         "'vibimpact classify' or 'vibimpact bifurcation'")
    if not set(ds["final_state"].dims) <= {"direction", "eta", "state"}:
        raise ValueError(f"{name} is not a sweep dataset (final_state has dims "
                         f"{ds['final_state'].dims})")
    # what the file holds must be of the types the sweep wrote: numbers, not text
    for var, kinds, what in (("eta", "iuf", "real numbers"), ("regime", "iu", "integers"),
                             ("final_state", "iuf", "real numbers")):
        if ds[var].dtype.kind not in kinds:
            raise ValueError(f"{name}'s {var} holds {ds[var].dtype} values, not {what}")
    model = recorded_model(ds.attrs, name, required=True)
    if ds["final_state"].dims[-1:] != ("state",) or \
            ds.sizes["state"] != len(model.state_names):
        raise ValueError(f"{name}'s final_state has shape {ds['final_state'].shape}; model "
                         f"{model.name!r} has {len(model.state_names)} states "
                         f"({', '.join(model.state_names)})")


def grid_index(grid: np.ndarray, eta: float) -> int:
    """Index of the grid value ``eta`` stands for (within :data:`ETA_MATCH`).

    Raises
    ------
    ValueError
        Naming ``eta``, the grid's range and the nearest grid values, when ``eta`` is
        not on the grid.
    """
    try:
        eta = float(eta)
    except (TypeError, ValueError):
        raise ValueError(f"eta must be a number, got {eta!r}") from None
    if not math.isfinite(eta):
        raise ValueError(f"eta must be a finite number, got {eta!r}")
    grid = np.asarray(grid, dtype=np.float64)
    dist = np.abs(grid - eta)
    i = int(np.argmin(dist))
    if dist[i] <= ETA_MATCH * max(1.0, abs(eta)):
        return i
    below, above = grid[grid < eta], grid[grid > eta]
    near = ([f"{below.max():.12g}"] if below.size else []) + (
        [f"{above.min():.12g}"] if above.size else [])
    raise ValueError(f"eta = {eta:.12g} is not on the sweep's grid ({grid.size} points "
                     f"from {grid.min():.12g} to {grid.max():.12g}); nearest grid values: "
                     f"{' and '.join(near)}")


def sweep_start(ds: xr.Dataset, eta: float | None = None, direction: str | None = None, *,
                source: str = "", names: Mapping[str, str] | None = None) -> SweepStart:
    """The parameters and state a sweep had at one grid point and direction.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep of any model (:func:`vibimpact.sweep`, ``vibimpact classify`` or
        ``bifurcation``), with ``regime``, ``label`` and ``final_state``.
    eta : float, optional
        A value of the sweep's grid (to within 1e-9 relative): the start takes the grid
        value itself, so that the run's parameters are the sweep point's bit for bit.
        Required unless the grid has one point.
    direction : {"up", "down"}, optional
        Of a ``direction="both"`` sweep, which one (required there); a one-direction
        sweep's own by default.
    source : str
        The sweep's file, recorded in :attr:`SweepStart.source`.
    names : dict, optional
        How the messages name ``ds``, ``eta`` and ``direction`` (default
        :data:`ARGUMENT_NAMES`: as the arguments); an interface that takes them otherwise
        names its own (the command line: "the file", "--eta", "--direction").

    Returns
    -------
    SweepStart

    Raises
    ------
    TypeError
        When ``ds`` is not a Dataset (a Run, say).
    ValueError
        Naming ``ds`` (not a sweep, a map, no parameters of a known model), ``eta``
        (not on the grid: the message gives the nearest grid values) or ``direction``
        (not in the sweep, or not given for a sweep with both); also when the sweep did
        not compute the point or it diverged there (no state to start from).

    Examples
    --------
    >>> import vibimpact as vi
    >>> ds = vi.sweep(vi.presets.get("fig8"), [1.1, 1.25])
    >>> start = vi.sweeps.sweep_start(ds, 1.25)
    >>> start.label, start.direction
    ('chaotic, impacting, whole circle', 'up')
    """
    n = {**ARGUMENT_NAMES, **(names or {})}
    _check_sweep(ds, n["ds"])
    dirs = _directions(ds)
    if direction is None:
        if len(dirs) > 1:
            raise ValueError(f"{n['direction']}: the sweep has {' and '.join(dirs)}; give "
                             "one")
        direction = dirs[0]
    elif not isinstance(direction, str):
        raise _v.WrongType(f"{n['direction']} must be a str, one of {', '.join(dirs)}, "
                           f"got {type(direction).__name__} {direction!r}")
    elif direction not in dirs:
        raise ValueError(f"{n['direction']} {direction!r} is not in the sweep (it has "
                         f"{' and '.join(dirs)})")
    sub = ds.sel(direction=direction) if "direction" in ds.dims else ds
    grid = sub["eta"].values
    if eta is None and grid.size != 1:
        raise ValueError(f"{n['eta']}: give one of the sweep's {grid.size} grid values "
                         f"(from {grid.min():.12g} to {grid.max():.12g})")
    i = 0 if eta is None else grid_index(grid, _v.finite(n["eta"], eta))
    at = float(sub["eta"].values[i])
    where = f"eta = {at:.12g} ({direction})"
    regime = int(sub["regime"].values[i])
    if regime == REGIME_CODES[Label.DIVERGED]:
        why = str(sub["reason"].values[i]) if "reason" in sub else ""
        raise ValueError(f"the sweep diverged at {where}" + (f": {why}" if why else "")
                         + "; no state to start from")
    state = np.asarray(sub["final_state"].values[i], dtype=np.float64)
    if regime not in REGIME_CODES.values() or not np.all(np.isfinite(state)):
        raise ValueError(f"the sweep did not compute {where}; no state to start from")
    params = sweep_params(ds, eta=at, name=n["ds"])
    state = recorded_state(state, recorded_model(ds.attrs, n["ds"], required=True),
                           f"{n['ds']}'s final_state at {where}")
    return SweepStart(params=params, state=state.copy(), eta=at, direction=direction,
                      label=str(sub["label"].values[i]), source=str(source),
                      sweep_command=str(ds.attrs.get("command", "")))
