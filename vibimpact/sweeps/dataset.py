"""Sweep results as a CF-style ``xarray.Dataset``, and the labelled interval map.

All lengths and times are the model's dimensionless ones (units "1"; for the built-in
rotor, lengths in units of the radial clearance and times in ``tau``).  ``regime`` is an
integer flag variable (CF ``flag_values`` / ``flag_meanings``) and ``label`` its readable
form, so the file opens with plain xarray and any NetCDF tool.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

import json
import sys

import numpy as np

from .. import __version__
from ..base import _validate as _v
from ..base._fill import complex_parts, not_computed
from ..base._text import count
from ..analysis.classify import Label
from ..core.run import state_text
from ..core.system import param_dict, to_system
from ..models.words import file_words
from ..points.point import (point_system, CONTACT_FLAGS, CONTACT_IMPACTING, CONTACT_NONE,
                            CONTACT_PERMANENT, REGIME_CODES, REGIME_FLAGS, SCALARS)

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Mapping, Sequence

    import xarray as xr

    from ..models.params import DuffingParams, Params
    from .interval_table import Intervals
    from ..points.point import SweepSettings
    from ..core.system import System

#: what a function that takes a sweep's dataset asks for, in its TypeError
SWEEP_DATASET = "the xarray.Dataset of a sweep (vibimpact.sweep)"

#: variable -> (dtype, units, long_name with the model's words in its ``{fields}``,
#: :func:`vibimpact.models.words.file_words`)
VARIABLES = {
    "regime": ("i1", "1", "kind of motion (flag)"),
    "period": ("i4", "1", "period n of the motion in forcing periods, T = n 2 pi / {freq} "
               "(0: none or not resolved)"),
    "confidence": ("f8", "1", "agreement of the classifier's tests, 0..1"),
    "impacts_per_period": ("f8", "1", "contacts per motion period (per forcing period "
                           "when period = 0)"),
    "impacts_constant": ("i1", "1", "1 when every motion period has the same number of "
                         "contacts"),
    "contact": ("i1", "1", "contact with the {obstacle} (flag; -1: not computed)"),
    "lyapunov": ("f8", "1", "largest Lyapunov exponent per unit {time} (NaN: not computed)"),
    "lyapunov_err": ("f8", "1", "standard error of the largest Lyapunov exponent"),
    "k01": ("f8", "1", "Gottwald-Melbourne 0-1 test K (NaN: not computed)"),
    "X_m": ("f8", "1", "response amplitude max |{x}|{unit}"),
    "Y_m": ("f8", "1", "response amplitude max |{y}|{unit}"),
    "R_m": ("f8", "1", "largest radial displacement max R{unit}"),
    "min_gap": ("f8", "1", "smallest gap to the {obstacle} (negative: penetration)"),
    "n_arcs": ("i4", "1", "number of loaded arcs of the {obstacle}"),
    "v_impact_max": ("f8", "1", "largest normal impact speed"),
    "v_impact_mean": ("f8", "1", "mean normal impact speed"),
    "penetration_max": ("f8", "1", "largest penetration{unit}"),
    "transient": ("i4", "1", "forcing periods of transient integrated"),
    "recorded": ("i4", "1", "forcing periods recorded after the transient"),
    # --- issue 8: Floquet multipliers ("floquet" analysis) ---
    "floquet_abs_max": ("f8", "1", "largest |Floquet multiplier| of the periodic orbit "
                        "(NaN: not computed or not periodic)"),
    "stable": ("i1", "1", "periodic orbit stable, all |multipliers| < 1 (1 yes, 0 no, "
               "-1 not computed)"),
    "floquet_exponent": ("f8", "1", "largest Floquet exponent ln|mu|max / (n T) of the "
                         "periodic orbit per unit {time} (exact; NaN: not computed)"),
    "contraction": ("f8", "1", "contraction rate ln|mu| / n of the stroboscopic points "
                    "per forcing period, measured on the record (NaN: not measured)"),
    "settle_periods": ("f8", "1", "forcing periods an unsettled motion would still need "
                       "to settle to the period test's tolerance (NaN: not estimated)"),
    "shoot_residual": ("f8", "1", "residual max|P^n(x) - x| of the orbit found by Newton "
                       "shooting from a slowly settling transient (NaN: not shot)"),
    "orbit_distance": ("f8", "1", "distance of the transient's last point from the orbit "
                       "found by shooting, relative to the motion's size"),
}


def _flags(fill, codes, meanings):
    """``(values, meanings)`` of a flag variable: ``codes`` with their words, then the
    fill value of a point not computed ("not_computed") when it is no code.  The fill
    comes last, so that the codes keep the positions in ``flag_meanings`` they had
    before it was declared."""
    words = meanings.split()
    if len(words) != len(codes):
        raise ValueError(f"flag meanings {meanings!r} do not match the codes {codes}")
    if fill not in codes:
        codes, words = tuple(codes) + (fill,), words + ["not_computed"]
    return tuple(codes), " ".join(words)


#: flag variable -> (flag_values, flag_meanings): every value a dataset can hold, the
#: fill value of a point not computed included (CF flags)
FLAGS = {
    "regime": _flags(SCALARS["regime"], tuple(sorted(REGIME_CODES.values())), REGIME_FLAGS),
    "contact": _flags(SCALARS["contact"], (CONTACT_NONE, CONTACT_IMPACTING,
                                           CONTACT_PERMANENT), CONTACT_FLAGS),
    "impacts_constant": _flags(SCALARS["impacts_constant"], (0, 1),
                               "varying_or_not_computed constant"),
    "stable": _flags(SCALARS["stable"], (0, 1), "unstable stable"),
}


#: the one special value of a ``period`` variable: 0, no period (not periodic, not
#: resolved or not computed); every other value is the period n itself
PERIOD_FLAGS = ((0,), "none")


def period_attrs(dtype):
    """The CF attributes that declare ``period`` = 0 (no period) of a ``period``
    variable of ``dtype``: ``flag_values`` = [0], ``flag_meanings`` = "none" and a
    ``comment`` saying that the other values are periods (CF 3.5 lets a variable declare
    its special values so; a ``_FillValue`` would turn the integers into floats in
    readers that mask it)."""
    values, meanings = PERIOD_FLAGS
    return dict(flag_values=np.array(values, dtype=dtype), flag_meanings=meanings,
                comment="0: no period (not periodic, not resolved or not computed); any "
                        "other value is the period n in forcing periods")


def flag_attrs(name, dtype):
    """The CF attributes ``flag_values`` (of ``dtype``, the variable's) and
    ``flag_meanings`` of the flag variable ``name`` (:data:`FLAGS`)."""
    values, meanings = FLAGS[name]
    return dict(flag_values=np.array(values, dtype=dtype), flag_meanings=meanings)


def label_text(code, n, ipp, arcs, contact=-1):
    label = {v: k for k, v in REGIME_CODES.items()}.get(int(code))
    if label is None:
        return "not computed"
    if label is Label.PERIODIC:
        head = f"P{n}" if n else "periodic (long period)"
    else:
        head = label.value
    if label is Label.DIVERGED:
        return head
    if not np.isfinite(ipp):
        return head
    if ipp == 0:
        return f"{head}, permanent contact" if contact == CONTACT_PERMANENT else \
            f"{head} impactless"
    if label is Label.PERIODIC and float(ipp).is_integer():
        text = f"{head}, {count(ipp, 'impact')}"
    else:  # a mean count varies from point to point: it would split every interval
        text = f"{head}, impacting"
    return f"{text}, {arcs}" if arcs else text


@_v.checks_flags
def to_dataset(p: Params | DuffingParams | System, etas: np.ndarray, dirs: Sequence[str],
               results: Mapping[str, Sequence[Mapping[str, Any] | None]],
               settings: SweepSettings,
               *, direction: str, continuation: bool, blocks: int,
               command: str | None = None) -> xr.Dataset:
    """Assemble per-point results into a Dataset (dims ``eta`` [, ``direction``])."""
    import xarray as xr

    n = etas.size
    ns = settings.n_samples

    def stack(key, fill, dtype):
        arr = not_computed((len(dirs), n), dtype, fill)
        for a, d in enumerate(dirs):
            order = np.arange(n) if d == "up" else np.arange(n)[::-1]
            for i, r in enumerate(results[d]):
                if r is not None:
                    arr[a, order[i]] = r.get(key, fill)
        return arr

    words = file_words(to_system(p).model)
    data = {}
    for key, (dt, units, long) in VARIABLES.items():
        fill = SCALARS[key]
        data[key] = (stack(key, fill, dt), dict(units=units, long_name=long.format(**words)))
    names = to_system(p).model.state_names
    d_state = len(names)
    samples = not_computed((len(dirs), n, ns, d_state))
    final = not_computed((len(dirs), n, d_state))
    arcs = not_computed((len(dirs), n), object)
    reason = not_computed((len(dirs), n), object)
    for a, d in enumerate(dirs):
        order = np.arange(n) if d == "up" else np.arange(n)[::-1]
        for i, r in enumerate(results[d]):
            if r is None:
                continue
            samples[a, order[i]] = r["samples"]
            final[a, order[i]] = r["final_state"]
            arcs[a, order[i]] = str(r.get("arcs", ""))
            reason[a, order[i]] = str(r.get("reason", ""))
    labels = np.empty((len(dirs), n), dtype=object)
    for a in range(len(dirs)):
        for j in range(n):
            labels[a, j] = label_text(data["regime"][0][a, j], data["period"][0][a, j],
                                       data["impacts_per_period"][0][a, j], arcs[a, j],
                                       data["contact"][0][a, j])
    dims = ("direction", "eta")
    ds = xr.Dataset(
        {k: (dims, v, attrs) for k, (v, attrs) in data.items()},
        coords={"eta": ("eta", etas, to_system(p).model.frequency_attrs()),
                "direction": ("direction", np.array(dirs, dtype=object),
                              dict(long_name="sweep direction"))})
    for name in FLAGS:
        ds[name].attrs.update(flag_attrs(name, ds[name].dtype))
    ds["period"].attrs.update(period_attrs(ds["period"].dtype))
    ds["label"] = (dims, labels, dict(long_name="regime in words"))
    ds["arcs"] = (dims, arcs, dict(long_name="loaded arcs of the {obstacle}, in "
                                             "words".format(**words)))
    ds["reason"] = (dims, reason, dict(long_name="classifier's decision branch"))
    model = to_system(p).model
    for j in range(samples.shape[-1]):  # every state: poincare_X and poincare_Y hold the
        # first two, whatever the model calls them; the others under their own names (a
        # Poincare section of a state against its velocity needs them)
        text = state_text(model, names[j])
        var = ("poincare_X", "poincare_Y")[j] if j < 2 else f"poincare_{names[j]}"
        ds[var] = (dims + ("sample",), samples[..., j], dict(
            units="1", long_name=f"stroboscopic samples of {names[j]}"
                                 + (f": {text}" if text else "")))
    ds["final_state"] = (dims + ("state",), final,
                         dict(units="1", long_name=f"state ({', '.join(names)}) at the "
                              "end of the point, the next point's initial state"))
    ds = ds.assign_coords(state=("state", np.array(names, dtype=object), dict(
        long_name="state variable of the model (" + ", ".join(names) + ")")))
    # --- issue 8: Floquet multipliers, complex split into real and imaginary parts ---
    if "floquet" in settings.analyses:
        mu = not_computed((len(dirs), n, d_state), complex)
        for a, d in enumerate(dirs):
            order = np.arange(n) if d == "up" else np.arange(n)[::-1]
            for i, r in enumerate(results[d]):
                if r is not None and "multipliers" in r:
                    mu[a, order[i]] = np.asarray(r["multipliers"], dtype=complex)
        for part, arr in zip(("real", "imag"), complex_parts(mu)):
            ds[f"floquet_{part}"] = (dims + ("multiplier",), arr, dict(
                units="1", long_name=f"Floquet multipliers of the periodic orbit, {part} "
                                     "part, by decreasing modulus (shooting, monodromy from "
                                     "the variational equations)"))
    # the loaded arcs' start, end, width (degrees) and loaded share, on dimension "arc"
    if model.contact is not None:
        from .arc_vars import add_arc_variables
        ds = add_arc_variables(ds, results, dirs, n, dims, words)
    if direction != "both":
        ds = ds.isel(direction=0, drop=True)
        ds.attrs["direction"] = direction
    params = param_dict(p)
    params.pop(model.frequency_name, None)
    ds.attrs.update(
        title="vibimpact frequency sweep",
        Conventions="CF-1.8",
        source=f"vibimpact {__version__}",
        model=model.name, frequency_name=model.frequency_name,
        params=json.dumps(params, sort_keys=True),
        settings=json.dumps(settings.as_attrs(), sort_keys=True, default=str),
        sweep_direction=direction, continuation=int(bool(continuation)),
        blocks=int(blocks), command=command if command is not None else " ".join(sys.argv),
    )
    for k, v in params.items():
        ds.attrs[f"param_{k}"] = float(v)
    # the integrator that ran (a System's own solver settings win over the sweep's), as
    # run, orbit and branch files record it; "" for a setting left to the integrator, a
    # flag as 0 or 1 (NetCDF has no boolean attribute)
    for k, v in point_system(p, settings).solver.filled().as_dict().items():
        ds.attrs[f"solver_{k}"] = "" if v is None else int(v) if isinstance(v, bool) else v
    return ds


def sweep_params(ds: xr.Dataset, eta: float | None = None, *, name: str = "ds") -> Params:
    """The parameters a sweep dataset records (its ``params`` attribute), as its model's
    parameter set.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`vibimpact.sweep` or ``vibimpact classify``.
    eta : float, optional
        The forcing frequency to set (the attribute leaves it out); the default of the
        model's parameter set otherwise (e.g. :class:`~vibimpact.Params`'s ``eta`` for the
        built-in rotor).
    name : str
        How the messages name ``ds`` (an interface that reads it from a file: "the
        file").

    Returns
    -------
    parameter set
        Of the model the dataset records (:class:`~vibimpact.Params` for the built-in
        rotor).

    Raises
    ------
    ValueError
        When the file's parameters are not what the command line would accept
        (:func:`vibimpact.io.recorded.recorded_params`): its ``params`` attribute or a
        ``param_NAME`` attribute missing, text, not finite, outside the parameter's
        domain, the two disagreeing, or a model this installation does not know.
    """
    from ..io.recorded import recorded_model, recorded_params

    _v.dataset(name, ds, SWEEP_DATASET)
    if eta is None:  # the records leave the forcing frequency out: the set's default
        model = recorded_model(ds.attrs, name, required=True)
        assert model.param_set is not None  # recorded_model(required=True) refuses none
        eta = getattr(model.param_set(), model.param_names[model.omega_index])
    return recorded_params(ds.attrs, name, omega=eta)


def _registered(name):
    """The registered model called ``name``; None for another name or none."""
    from .. import models

    return models.get(name) if isinstance(name, str) and name in models.names() else None


def intervals(ds: xr.Dataset, direction: str | None = None) -> Intervals:
    """The labelled frequency-interval map of a sweep.

    Consecutive grid points with the same label (kind of motion, period, impacts per
    period, loaded arcs) form one interval.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`vibimpact.sweep`.
    direction : {"up", "down"}, optional
        For a ``direction="both"`` sweep: which one (both, one after the other, if None).

    Returns
    -------
    Intervals
        An ``xarray.Dataset`` (:class:`~vibimpact.sweeps.interval_table.Intervals`, a
        subclass) on dim ``interval``: ``start``, ``end`` (eta of the first and last
        point), ``label``, ``regime``, ``period``, ``impacts``, ``arcs``, ``points``,
        ``direction``.  ``print()`` shows it as the table of :func:`format_intervals`,
        ``.to_markdown()`` as Markdown, ``.dataset`` is the plain Dataset.
    """
    import xarray as xr

    from .interval_table import as_intervals

    _v.dataset("ds", ds, SWEEP_DATASET)
    if "label" not in ds or "eta" not in ds.dims:
        raise ValueError("ds must be a sweep dataset (variables label, regime; dim eta)")
    if "direction" in ds.dims:
        dirs = [direction] if direction else list(ds["direction"].values)
        rows = []
        for d in dirs:
            sub = ds.sel(direction=d).drop_vars("direction")
            sub.attrs["sweep_direction"] = d
            rows.append(intervals(sub).dataset)
        return as_intervals(xr.concat(rows, dim="interval"))
    eta = ds["eta"].values
    lab = ds["label"].values
    order = np.arange(eta.size)
    if ds.attrs.get("sweep_direction", ds.attrs.get("direction")) == "down":
        order = order[::-1]
    cols: dict[str, list] = {k: [] for k in ("start", "end", "label", "regime", "period",
                                             "impacts", "arcs", "points")}
    i = 0
    while i < order.size:
        j = i
        while j + 1 < order.size and lab[order[j + 1]] == lab[order[i]]:
            j += 1
        a, b = order[i], order[j]
        cols["start"].append(eta[a])
        cols["end"].append(eta[b])
        cols["label"].append(lab[a])
        cols["regime"].append(int(ds["regime"].values[a]))
        cols["period"].append(int(ds["period"].values[a]))
        cols["impacts"].append(float(ds["impacts_per_period"].values[a]))
        cols["arcs"].append(str(ds["arcs"].values[a]))
        cols["points"].append(j - i + 1)
        i = j + 1
    d = ds.attrs.get("sweep_direction", "up")
    words = file_words(_registered(ds.attrs.get("model")))
    out = xr.Dataset(
        {"start": ("interval", np.array(cols["start"]), dict(
            units="1", long_name="first {freq}".format(**words))),
         "end": ("interval", np.array(cols["end"]), dict(
             units="1", long_name="last {freq}".format(**words))),
         "label": ("interval", np.array(cols["label"], dtype=object),
                   dict(long_name="regime in words")),
         "regime": ("interval", np.array(cols["regime"], dtype="i1"),
                    flag_attrs("regime", "i1")),
         "period": ("interval", np.array(cols["period"], dtype="i4"), dict(
             units="1", long_name="period n in forcing periods", **period_attrs("i4"))),
         "impacts": ("interval", np.array(cols["impacts"]), dict(
             units="1", long_name="contacts per motion period")),
         "arcs": ("interval", np.array(cols["arcs"], dtype=object),
                  dict(long_name="loaded arcs of the {obstacle}, in "
                                 "words".format(**words))),
         "points": ("interval", np.array(cols["points"], dtype="i4"),
                    dict(units="1", long_name="grid points in the interval")),
         "direction": ("interval", np.array([d] * len(cols["start"]), dtype=object),
                       dict(long_name="sweep direction"))},
        attrs=dict(title="vibimpact frequency-interval map", source=ds.attrs.get("source",
                                                                              "")))
    if "model" in ds.attrs:  # whose forcing frequency the table's columns name
        out.attrs["model"] = ds.attrs["model"]
    return as_intervals(out)


def format_intervals(iv: xr.Dataset) -> str:
    """The interval map as an aligned text table.

    Parameters
    ----------
    iv : xarray.Dataset
        The intervals of :func:`intervals`.

    Returns
    -------
    str
    """
    from .interval_table import table

    _v.dataset("iv", iv, "the xarray.Dataset of intervals(ds)")
    return table(iv)
