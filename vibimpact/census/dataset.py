"""A census as an xarray Dataset, and the global continuation of its attractors.

Dimensions: ``eta`` (the grid), ``start`` (the starting states, the same at every eta),
``attractor`` (the attractors of each eta in the order found, padded to the most at any
eta), ``state``, ``sample`` (stroboscopic points of each attractor) and ``multiplier``.

Per start: ``start_state (start, state)``, ``label (eta, start)`` (the attractor index
at that eta; -1: its integration failed), ``decided_by`` and ``periods`` (how and after
how many forcing periods its attractor was known).

Per eta: ``unseen`` (the basin mass the census may have missed, never 0:
:func:`vibimpact.census.unseen.unseen_mass`), ``unseen_good_turing`` and
``singletons`` (attractors reached by one start); ``failed`` and ``failed_fraction``
(starts whose integration failed: the solver could not go on, a step-size underflow,
say; they are on no attractor, so that the attractors' fractions and
``failed_fraction`` sum to 1) and ``failure`` (the solver's reason for the first of
them; empty when none failed).  A start whose motion diverged
(the state left the solver's bound or became non-finite) is on the pseudo-attractor
"diverged", with its basin fraction like any attractor.

Per attractor: ``fraction`` and ``fraction_se`` (basin fraction and its binomial
standard error), ``regime``, ``period``, ``impacts_per_period``, ``n_arcs``, ``name``
(its label in words), ``lyapunov``, ``floquet_abs_max``, ``multiplier_re/_im``,
``representative (eta, attractor, state)``, ``samples (eta, attractor, sample, state)``
and ``global_id``: the same number for the same attractor followed from one eta to the
next (:func:`continue_attractors`).
"""
from __future__ import annotations

import logging
import math
from typing import Any

import numpy as np
import xarray as xr

from ..points.point import REGIME_CODES, REGIME_FLAGS
from ..analysis.classify import Label
from ..core.system import param_dict
from ..models.words import file_words
from ..sweeps.dataset import label_text, period_attrs
from .reach import DECIDED_FLAGS, ESCAPED_LABEL, FAILED_LABEL
from .library import nearest_distances
from .unseen import CONFIDENCE, unseen_mass

_log = logging.getLogger(__name__)

__all__ = ["census_dataset", "continue_attractors", "attractor_table", "failed_note",
           "N_SAMPLES"]

#: stroboscopic samples stored per attractor (a cycle repeated to fill)
N_SAMPLES = 128
#: attractors at neighbouring eta are one (global continuation) when their clouds' mean
#: distance is below this many box scales
MATCH_DISTANCE = 0.3


def _samples(att, d):
    cloud = np.asarray(att.cloud)
    if cloud.shape[0] == 0:
        return np.full((N_SAMPLES, d), np.nan)
    reps = -(-N_SAMPLES // cloud.shape[0])
    return np.tile(cloud, (reps, 1))[:N_SAMPLES] if att.periodic else \
        cloud[np.linspace(0, cloud.shape[0] - 1, N_SAMPLES).astype(int)]


def _cloud_distance(a, b):
    """Symmetric mean nearest distance of two attractors' clouds."""
    return 0.5 * (float(nearest_distances(a.cloud, b.cloud).mean())
                  + float(nearest_distances(b.cloud, a.cloud).mean()))


def _impacting(att):
    ipp = float(att.result.get("impacts_per_period", math.nan))
    return None if not math.isfinite(ipp) else ipp > 0


def continue_attractors(libraries, scale, tol=MATCH_DISTANCE):
    """Global ids of the attractors of consecutive parameter points.

    Attractor ``a`` of point ``i`` and ``b`` of point ``i + 1`` are matched when both are
    periodic with one period, or both non-periodic, both impacting or both not, and
    their clouds lie within ``tol``
    box scales of each other (mean nearest distance, both ways); matching is greedy in
    order of distance, one to one.  An unmatched attractor gets a new id (it is born
    there).

    Returns
    -------
    list of list of int
        ``ids[i][a]``.
    """
    ids: list[list[int]] = []
    next_id = 0
    for i, lib in enumerate(libraries):
        cur = [-1] * len(lib)
        if i > 0 and lib and libraries[i - 1]:
            pairs = []
            for a, prev in enumerate(libraries[i - 1]):
                for b, att in enumerate(lib):
                    if prev.period != att.period or _impacting(prev) != _impacting(att):
                        continue
                    dist = _cloud_distance(prev, att)
                    if dist <= tol * scale:
                        pairs.append((dist, a, b))
            used = set()
            for _, a, b in sorted(pairs):
                if a not in used and cur[b] < 0:
                    cur[b] = ids[i - 1][a]
                    used.add(a)
        for b in range(len(lib)):
            if cur[b] < 0:
                cur[b] = next_id
                next_id += 1
        ids.append(cur)
    return ids


def _name(res, period):
    if res is None:
        return "diverged"
    ipp = float(res.get("impacts_per_period", math.nan))
    text = label_text(int(res["regime"]), period, ipp, str(res.get("arcs", "")),
                      int(res.get("contact", -1)))
    return text


_START, _ATT = ("eta", "start"), ("eta", "attractor")
#: census variable -> (dims, long_name, units or None); every one described (CF)
_VARIABLES = {
    "start_state": (("start", "state"), "starting state", "1"),
    "label": (_START, "attractor reached (index along attractor; -1: the integration "
                      "failed)", "1"),
    "decided_by": (_START, "how the start's attractor was known", None),
    "periods": (_START, "forcing periods integrated", "1"),
    "fraction": (_ATT, "basin fraction", "1"),
    "fraction_se": (_ATT, "standard error of the basin fraction", "1"),
    "regime": (_ATT, "kind of motion (flag)", None),
    "period": (_ATT, "period n (T = n 2 pi / {freq}); 0: not periodic", "1"),
    "impacts_per_period": (_ATT, "contacts per motion period (per forcing period when "
                                 "period = 0)", "1"),
    "n_arcs": (_ATT, "number of loaded arcs of the {obstacle} (-1: not measured)", "1"),
    "lyapunov": (_ATT, "largest Lyapunov exponent (non-periodic attractors)", "1"),
    "floquet_abs_max": (_ATT, "largest |Floquet multiplier| (periodic attractors)", "1"),
    "multiplier_re": (_ATT + ("multiplier",), "Floquet multipliers, real part", "1"),
    "multiplier_im": (_ATT + ("multiplier",), "Floquet multipliers, imaginary part", "1"),
    "representative": (_ATT + ("state",), "one stroboscopic point of the attractor", "1"),
    "samples": (_ATT + ("sample", "state"), "stroboscopic points on the attractor", "1"),
    "name": (_ATT, "attractor in words", None),
    "found_by": (_ATT, "the start that found the attractor (-1: none)", "1"),
    "global_id": (_ATT, "attractor followed across eta (global continuation)", "1"),
    "failed": (("eta",), "starts whose integration failed (on no attractor)", "1"),
    "failed_fraction": (("eta",), "share of the starts whose integration failed", "1"),
    "failure": (("eta",), "the solver's reason for the first failed start", None),
    "unseen": (("eta",), "basin mass the census may have missed: the larger of "
                         "unseen_good_turing and the resolution of n_starts starts", "1"),
    "unseen_good_turing": (("eta",), "Good-Turing estimate of the basin mass of "
                                     "attractors no start reached (singletons / starts)",
                           "1"),
    "singletons": (("eta",), "attractors reached by exactly one start", "1"),
}


def _var_attrs(name, values, words):
    """The CF attributes of census variable ``name`` holding ``values`` (``words``: the
    model's, :func:`vibimpact.models.words.file_words`)."""
    _, long_name, units = _VARIABLES[name]
    out: dict[str, Any] = dict(long_name=long_name.format(**words))
    if units is not None:
        out["units"] = units
    if name == "decided_by":
        out.update(flag_values=np.arange(4, dtype=values.dtype), flag_meanings=DECIDED_FLAGS)
    elif name == "regime":
        # 0: no attractor in this slot (the census pads every eta to the most attractors)
        out.update(flag_values=np.array([1, 2, 3, 4, 5, 0], dtype=values.dtype),
                   flag_meanings=REGIME_FLAGS + " none")
    elif name == "period":
        out.update(period_attrs(values.dtype))
    elif name in ("n_arcs", "found_by", "label"):  # -1 (not measured, none): outside the valid
        out["valid_min"] = np.zeros((), values.dtype)[()]  # range, missing to CF readers
    return out


def census_dataset(system, etas, states, box, seed, settings, libraries, labels, results,
                   until_unseen=None):
    """The census Dataset (module docstring) of :func:`vibimpact.census.attractors`."""
    m, n, d = etas.size, states.shape[0], states.shape[1]
    diverged = [bool(np.any(lab == ESCAPED_LABEL)) for lab in labels]
    A = max(1, max(len(lib) + dv for lib, dv in zip(libraries, diverged)))
    shape = (m, A)
    f = np.full(shape, np.nan)
    se = np.full(shape, np.nan)
    regime = np.zeros(shape, dtype=np.int8)
    period = np.zeros(shape, dtype=np.int32)
    ipp = np.full(shape, np.nan)
    n_arcs = np.full(shape, -1, dtype=np.int32)
    lyap = np.full(shape, np.nan)
    fam = np.full(shape, np.nan)
    mre = np.full((m, A, d), np.nan)
    mim = np.full((m, A, d), np.nan)
    rep = np.full((m, A, d), np.nan)
    samples = np.full((m, A, N_SAMPLES, d), np.nan)
    names = np.full(shape, "", dtype=object)
    # int32, not int64: the integer types of CF-1.8 (byte, short, int) hold every count
    first = np.full(shape, -1, dtype=np.int32)
    gid = np.full(shape, -1, dtype=np.int32)
    label = np.stack(labels).astype(np.int32)
    decided = np.array([[int(r["decided_by"]) for r in row] for row in results], np.int8)
    periods = np.array([[int(r["periods"]) for r in row] for row in results], np.int32)
    ids = continue_attractors(libraries, box.scale)
    next_gid = max([max(x) for x in ids if x] + [-1]) + 1
    for i, lib in enumerate(libraries):
        counts = np.bincount(label[i][label[i] >= 0], minlength=len(lib))
        for a, att in enumerate(lib):
            res = att.result
            frac = counts[a] / n
            f[i, a], se[i, a] = frac, math.sqrt(frac * (1.0 - frac) / n)
            regime[i, a] = int(res["regime"])
            period[i, a] = att.period
            ipp[i, a] = float(res.get("impacts_per_period", np.nan))
            n_arcs[i, a] = int(res.get("n_arcs", -1))
            lyap[i, a] = float(res.get("lyapunov", np.nan))
            fam[i, a] = float(res.get("floquet_abs_max", np.nan))
            mult = np.asarray(res.get("multipliers", np.full(d, np.nan)))
            if np.iscomplexobj(mult):
                mre[i, a, :mult.size] = mult.real[:d]
                mim[i, a, :mult.size] = mult.imag[:d]
            elif mult.size:
                mre[i, a, :min(d, mult.size)] = np.asarray(mult, float).ravel()[:d]
            rep[i, a] = np.asarray(att.cloud)[0] if np.asarray(att.cloud).size else np.nan
            samples[i, a] = _samples(att, d)
            names[i, a] = _name(res, att.period)
            first[i, a] = att.first
            gid[i, a] = ids[i][a]
        if diverged[i]:
            a = len(lib)
            k = int(np.sum(label[i] == ESCAPED_LABEL))
            label[i][label[i] == ESCAPED_LABEL] = a
            f[i, a], se[i, a] = k / n, math.sqrt((k / n) * (1 - k / n) / n)
            regime[i, a] = REGIME_CODES[Label.DIVERGED]
            names[i, a] = "diverged"
            gid[i, a] = next_gid  # one id for divergence at every eta
    failed = np.sum(label == FAILED_LABEL, axis=1).astype(np.int32)
    unseen = np.array([unseen_mass(np.bincount(row[row >= 0]), n) for row in label])
    failure = np.array([_first_failure(row, lab) for row, lab in zip(results, label)],
                       dtype=object)
    for i, lib in enumerate(libraries):
        _log.info("census at eta %g: %d attractors from %d starts (%s)%s", etas[i],
                  len(lib), n, "; ".join(f"{names[i, a]}: {f[i, a]:.3f}" for a in range(A)
                                         if np.isfinite(f[i, a])),
                  f"; {failed[i]} failed: {failure[i]}" if failed[i] else "")
    model = system.model
    states_names = list(model.state_names)
    values = dict(start_state=states, label=label, decided_by=decided, periods=periods,
                  fraction=f, fraction_se=se, regime=regime, period=period,
                  impacts_per_period=ipp, n_arcs=n_arcs, lyapunov=lyap,
                  floquet_abs_max=fam, multiplier_re=mre, multiplier_im=mim,
                  representative=rep, samples=samples, name=names.astype(str),
                  found_by=first, global_id=gid, failed=failed,
                  failed_fraction=failed / float(n), failure=failure.astype(str),
                  unseen=unseen[:, 0], unseen_good_turing=unseen[:, 1],
                  singletons=unseen[:, 2].astype(np.int32))
    ds = xr.Dataset(
        {k: (_VARIABLES[k][0], v, _var_attrs(k, v, file_words(model)))
         for k, v in values.items()},
        coords=dict(eta=("eta", etas, model.frequency_attrs()),
                    start=("start", np.arange(n, dtype=np.int32), dict(
                        long_name="starting state index", units="1")),
                    attractor=("attractor", np.arange(A, dtype=np.int32), dict(
                        long_name=f"attractor index at each {model.frequency_name}",
                        units="1")),
                    state=("state", states_names, dict(
                        long_name="state variable of the model ("
                                  + ", ".join(states_names) + ")")),
                    sample=("sample", np.arange(N_SAMPLES, dtype=np.int32), dict(
                        long_name="stroboscopic sample index", units="1")),
                    multiplier=("multiplier", np.arange(d, dtype=np.int32), dict(
                        long_name="Floquet multiplier index", units="1"))),
        attrs=dict(kind="census", model=model.name, frequency_name=model.frequency_name,
                   seed=int(seed), box=box.describe(),
                   box_lo=box.lo, box_hi=box.hi, box_scale=box.scale,
                   n_starts=int(n), unseen_confidence=CONFIDENCE,
                   until_unseen=np.nan if until_unseen is None else float(until_unseen),
                   **{f"param_{k}": v for k, v in param_dict(system).items()
                      if k != model.frequency_name},
                   **{f"census_{k}": v for k, v in settings.as_attrs().items()}))
    return ds


def _first_failure(results, label):
    """The reason of the first start of ``label`` whose integration failed ("": none)."""
    hit = np.flatnonzero(label == FAILED_LABEL)
    return str(results[hit[0]].get("reason", "")) if hit.size else ""


def failed_note(ds) -> str | None:
    """The warning about the starts of a census or basins dataset whose integration
    failed (how many, of how many, and the solver's first reason), or None when none
    failed (or the file predates the count)."""
    if "failed" not in ds:
        return None
    failed = np.atleast_1d(ds["failed"].values)
    total = int(failed.sum())
    if total == 0:
        return None
    per_eta = int(ds.attrs.get("n_starts", 0)) or \
        int(np.prod([ds.sizes[k] for k in ("start", "row", "column") if k in ds.sizes]))
    reasons = [str(r) for r in np.atleast_1d(ds["failure"].values) if str(r)] \
        if "failure" in ds else []
    where = f" at {int(np.count_nonzero(failed))} of {failed.size} eta" \
        if failed.size > 1 else ""
    return (f"{total} of {per_eta * failed.size} starts{where} failed to integrate "
            f"({reasons[0] if reasons else 'solver failure'}); they are on no attractor "
            "and counted apart (failed, failed_fraction)")


def attractor_table(ds, eta_index=0):
    """Rows ``(index, global id, name, fraction, se, period, extra)`` of one eta,
    largest fraction first (the CLI's table)."""
    rows = []
    for a in range(ds.sizes["attractor"]):
        f = float(ds.fraction[eta_index, a])
        if not math.isfinite(f):
            continue
        extra = ""
        if int(ds.period[eta_index, a]) > 0:
            fam = float(ds.floquet_abs_max[eta_index, a])
            if math.isfinite(fam):
                extra = f"|mu|max {fam:.3g}"
        elif math.isfinite(float(ds.lyapunov[eta_index, a])):
            extra = f"lambda {float(ds.lyapunov[eta_index, a]):.3g}"
        rows.append((a, int(ds.global_id[eta_index, a]), str(ds.name.values[eta_index, a]), f,
                     float(ds.fraction_se[eta_index, a]), int(ds.period[eta_index, a]),
                     extra))
    return sorted(rows, key=lambda r: -r[3])
