"""Each interval claim of the paper against the attractor census, the orbit hunt and a
simulation from rest (issue 30, part 7).

For every claim of :data:`vibimpact.paper.claims.CLAIMS`, at the claimed eta (the one eta
of a claim "at" or "near" a value; the ends and the middle of an interval, on the sweeps'
0.005 grid) this computes

1. the attractor census (:func:`vibimpact.attractors`, :data:`STARTS` random starts, seed
   0) under the shipped defaults (the presets as they are);
2. the census (:data:`READING_STARTS` starts, at the claim's middle eta: the census
   budget) under each damping reading of the calibration for the claim's figure
   (``reports/calibration.nc``: the reading's dampings and its best ``(B, Ec)``;
   readings that give one parameter set are run once);
3. a simulation from rest at every eta (``vi.sweep(..., continuation=False)``: every eta
   starts from the same state, as the paper's authors may have run it);
4. for a periodic claim, the orbit hunt (:func:`vibimpact.orbits.hunt_orbits`) for the
   claimed period and its divisors under the defaults, seeded by the census's attractors
   and random states: stable and unstable orbits with their Floquet multipliers;

and gives the claim one outcome (:data:`OUTCOMES`):

* ``reached``: reached by the up/down sweep (the detection of ``paper.py`` agrees, or the
  sweep's label at a claimed eta is the claimed motion);
* ``exists``: an attractor of some census (basin fraction ± standard error, and under
  which reading), reached from rest, or an orbit of the hunt (stable or unstable, with
  its largest multiplier);
* ``absent``: none of these, with the nearest motion found.

A census attractor matches a claim by the claim's own rule
(:func:`vibimpact.paper.claims.match_points`, applied to the attractors as if they were
sweep points): *irregular* = impacting and chaotic, quasi-periodic, unsettled or periodic
beyond the detector's longest period; *periodic* = periodic with the claimed period and
impacts per period (impacting); *impactless* = periodic without impacts.

The computation is cached as JSON in the paper cache (``--fresh`` recomputes); the
outcomes are decided from it and the sweeps each time.  ``paper.py`` inserts
:func:`render` of :func:`outcomes` into ``reports/paper.md`` and stores it in
``reports/paper.json``; run alone it writes the JSON and prints the section::

    python analyses/paper/census_claims.py [--fresh] [--smoke DIR]

References
----------
G. Datseris, K. Luiz Rossi, A. Wagemakers, "Framework for global stability analysis of
dynamical systems", Chaos 33, 073151 (2023) (basin fractions of a census of starts).
L. Půst, J. Kozánek, "Vibrations of rotor supported in magnetic bearings with impacts".
"""
from __future__ import annotations

import functools
import hashlib
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

import vibimpact as vi
from vibimpact.paper import claims as C

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # analyses/: _common
sys.path.insert(0, str(HERE))  # calibrate_search
from _common import smoke  # noqa: E402

import calibrate_search as S  # noqa: E402
from census_claims_report import _fmt_att, render  # noqa: E402

ROOT = HERE.parents[1]
CALIBRATION = ROOT / "reports" / "calibration.nc"
#: the three outcomes of a claim
#: census starts under the shipped defaults, and under each calibration reading
STARTS = 200
READING_STARTS = 48
SEED = 0
#: the sweeps' grid step (claimed etas are put on it)
STEP = 0.005
#: random seeds of the orbit hunt (besides the defaults census's attractors), its other
#: settings (:func:`vibimpact.orbits.hunt_orbits`) and the stroboscopic points of each
#: census attractor that seed it besides its representative
HUNT_RANDOM = 96
HUNT = dict(transient=100, max_return=0.5, starts=3)
SEED_SAMPLES = 8
#: the claims computed (None: all); a smoke run takes two
ONLY = None
#: calibration readings per figure at most (None: all)
MAX_READINGS = None
#: the subpackages whose sources key the cache of a census, and of a hunt
CENSUS_CODE = ("census", "points", "engine", "_kernel", "analysis")
HUNT_CODE = ("orbits", "census", "points", "engine", "_kernel", "analysis")


# --- what is computed -----------------------------------------------------------------


def claim_etas(claim, step=STEP):
    """The claim's etas: its one value, or its ends and middle on the ``step`` grid."""
    if claim.lo == claim.hi:
        return [round(claim.lo, 6)]
    mid = round(round(0.5 * (claim.lo + claim.hi) / step) * step, 6)
    return sorted({round(claim.lo, 6), mid, round(claim.hi, 6)})


def middle_eta(claim, step=STEP):
    """The claim's one eta, or the middle of its interval on the ``step`` grid (where the
    readings' censuses are taken)."""
    etas = claim_etas(claim, step)
    return etas[len(etas) // 2]


def divisors(n):
    """Divisors of ``n`` in increasing order."""
    return [k for k in range(1, n + 1) if n % k == 0]


def selected_claims():
    """The claims this run computes (:data:`ONLY`)."""
    return tuple(c for c in C.CLAIMS if ONLY is None or c.key in ONLY)


def _best(land):
    return S.best_pair(land) if land else None


def calibration_readings(path=CALIBRATION):
    """Reading key -> ``{preset: (dampings, B, Ec)}`` at each reading's best pair.

    Readings (a)-(c) from the pairs of ``calibration.nc``, the per-figure readings (d)
    from its ``fig_pair`` rows, each best pair chosen as the calibration does
    (:func:`calibrate_search.best_pair`: least objective, then most agreeing claims).
    """
    import xarray as xr

    if not Path(path).exists():
        return {}
    cal = xr.load_dataset(path)
    out = {}
    for r in S.readings():
        if r.kind == "d":
            m = np.flatnonzero(cal["fig_reading"].values == r.key)
            land = {(float(cal["fig_B"][i]), float(cal["fig_Ec"][i])):
                    (float(cal["fig_objective"][i]), int(cal["fig_agree_count"][i]))
                    for i in m}
        else:
            m = np.flatnonzero(cal["reading"].values == r.key)
            land = {(float(cal["B"][i]), float(cal["Ec"][i])):
                    (float(cal["objective"][i]), int(cal["agree_count"][i])) for i in m}
        best = _best(land)
        if best is not None:
            out[r.key] = {f.preset: (f.damp, 0.0 if f.b_zero else best[0], best[1])
                          for f in r.figures}
    return out


def parameter_sets(preset, readings):
    """The parameter sets of one figure: the defaults first, then one per distinct set of
    the calibration readings, each with the readings that give it.

    Returns
    -------
    list of dict
        ``name`` (``"defaults"`` or the first reading's key), ``params`` (dict),
        ``readings`` (keys), ``starts``.
    """
    base = vi.presets.get(preset)
    sets = [dict(name="defaults", params=base.as_dict(), readings=["defaults"],
                 starts=STARTS)]
    for key, figs in readings.items():
        if preset not in figs:
            continue
        damp, B, Ec = figs[preset]
        p = base.replace(B=B, Ec=Ec, **S.damping_values(damp)).as_dict()
        same = [s for s in sets if s["params"] == p]
        if same:
            same[0]["readings"].append(key)
        elif MAX_READINGS is None or len(sets) <= MAX_READINGS:
            sets.append(dict(name=key, params=p, readings=[key], starts=READING_STARTS))
    return sets


def _attractor_rows(ds, k):
    """The attractors of eta index ``k`` of a census dataset, as dicts."""
    rows = []
    for a in range(ds.sizes["attractor"]):
        frac = float(ds["fraction"].values[k, a])
        name = str(ds["name"].values[k, a])
        if not math.isfinite(frac) or frac <= 0 or not name:
            continue
        rows.append(dict(
            name=name, regime=int(ds["regime"].values[k, a]),
            period=int(ds["period"].values[k, a]),
            impacts=float(ds["impacts_per_period"].values[k, a]),
            n_arcs=int(ds["n_arcs"].values[k, a]), fraction=frac,
            se=float(ds["fraction_se"].values[k, a]),
            abs_mu=float(ds["floquet_abs_max"].values[k, a]),
            lyapunov=float(ds["lyapunov"].values[k, a])))
    return sorted(rows, key=lambda r: -r["fraction"])


@functools.lru_cache(maxsize=None)
def code_hash(subs):
    """First 12 hex digits of the SHA-256 of the sources of the subpackages ``subs`` of
    vibimpact (:data:`CENSUS_CODE`, :data:`HUNT_CODE`), read once per process: a change
    there (e.g. the census's stopping rule, which moves basin fractions) recomputes what
    they computed."""
    h = hashlib.sha256()
    for sub in subs:
        for f in sorted((ROOT / "vibimpact" / sub).rglob("*.py")):
            h.update(f.relative_to(ROOT).as_posix().encode())
            h.update(f.read_bytes())
    return h.hexdigest()[:12]


def _memo(cache, kind, inputs, fresh, make, code):
    """``make()`` (a JSON-able dict), kept in ``cache/census_claims/KIND_HASH.json`` where
    HASH is that of ``inputs``, the package version and :func:`code_hash` of ``code``;
    read back unless ``fresh``."""
    key = hashlib.sha1(json.dumps([inputs, vi.__version__, code_hash(code)],
                                  sort_keys=True).encode()).hexdigest()[:16]
    path = Path(cache) / "census_claims" / f"{kind}_{key}.json"
    if path.exists() and not fresh:
        return json.loads(path.read_text())
    t = time.perf_counter()
    out = make()
    out["seconds"] = time.perf_counter() - t
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(out, sort_keys=True))
    os.replace(tmp, path)
    return out


def census(params, etas, starts, cache, fresh=False):
    """Attractors at each eta, cached: ``{"rows": [rows per eta], "seeds": [states per
    eta], "seconds"}`` (``seeds``: each attractor's representative and up to
    :data:`SEED_SAMPLES` of its stroboscopic points, for the hunt)."""
    def make():
        ds = vi.attractors(vi.System(vi.Params(**params)), eta=np.asarray(etas, float),
                           starts=starts, seed=SEED, execution=vi.Execution(workers=1))
        seeds = []
        for k in range(len(etas)):
            pts = [np.asarray(ds["representative"].values[k], float)]
            smp = np.asarray(ds["samples"].values[k], float)  # (attractor, sample, state)
            pick = np.linspace(0, smp.shape[1] - 1, SEED_SAMPLES).astype(int)
            pts.append(smp[:, pick].reshape(-1, smp.shape[-1]))
            pts = np.concatenate(pts)
            pts = np.unique(pts[np.all(np.isfinite(pts), axis=1)], axis=0)
            seeds.append(pts.tolist())
        return dict(rows=[_attractor_rows(ds, k) for k in range(len(etas))], seeds=seeds)

    return _memo(cache, "census", [params, [float(e) for e in etas], starts, SEED], fresh,
                 make, CENSUS_CODE)


def from_rest(params, etas):
    """Labels of a simulation from rest at each eta (no continuation); ``params``: eq.
    (5)'s parameters as a dict, or any model's parameter set (the ring study's)."""
    p = params if hasattr(params, "as_dict") else vi.Params(**params)
    ds = vi.sweep(p, np.asarray(etas, float), analyses=("period", "impacts"),
                  continuation=False, execution=vi.Execution(workers=1))
    return [dict(name=str(ds["label"].values[k]), regime=int(ds["regime"].values[k]),
                 period=int(ds["period"].values[k]),
                 impacts=float(ds["impacts_per_period"].values[k]),
                 contact=int(ds["contact"].values[k]) if "contact" in ds else 0)
            for k in range(len(etas))]


def hunt(params, eta, periods, seeds, cache, fresh=False):
    """Orbits of the hunt at one eta (no continuation), cached, as dicts."""
    from vibimpact.orbits import hunt_orbits

    def make():
        h = hunt_orbits(vi.System(vi.Params(**{**params, "eta": eta})), periods=periods,
                        seeds=np.asarray(seeds) if len(seeds) else None,
                        random=HUNT_RANDOM, seed=SEED, continuation=False, **HUNT)
        return dict(orbits=[dict(period=int(o.period), impacts=int(o.impacts),
                                 stable=bool(o.stable), abs_mu=float(o.abs_max),
                                 arcs=o.arcs, label=o.label) for o in h.orbits],
                    shots=int(h.counts.get("shots", 0)), seeds=int(len(h.seeds)))

    return _memo(cache, "hunt", [params, float(eta), list(periods), seeds, HUNT_RANDOM,
                                 HUNT, SEED], fresh, make, HUNT_CODE)


def settings():
    """What the computation depends on."""
    return dict(starts=STARTS, reading_starts=READING_STARTS, seed=SEED, step=STEP,
                hunt_random=HUNT_RANDOM, hunt=HUNT, seed_samples=SEED_SAMPLES, only=ONLY,
                max_readings=MAX_READINGS, version=vi.__version__)


def compute(cache, fresh=False, log=sys.stderr):
    """Censuses, simulations from rest and hunts for every selected claim.

    Each census and hunt is cached on its own (:func:`_memo`); ``fresh`` recomputes them.

    Returns
    -------
    dict
        ``settings``, ``sets`` (preset -> parameter sets), ``census`` (preset -> set name
        -> eta (str) -> attractor rows), ``from_rest`` (preset -> eta -> label row),
        ``hunt`` (claim key -> eta -> hunt), ``timings`` (seconds each part took when
        computed, cached or not).
    """
    claims = selected_claims()
    readings = calibration_readings()
    presets = sorted({c.preset for c in claims})
    sets = {p: parameter_sets(p, readings) for p in presets}
    out = dict(settings=settings(), sets=sets, census={}, from_rest={}, hunt={},
               timings=dict(census_s=0.0, from_rest_s=0.0, hunt_s=0.0))
    seeds = {}
    for p in presets:
        etas = sorted({e for c in claims if c.preset == p for e in claim_etas(c)})
        mids = sorted({middle_eta(c) for c in claims if c.preset == p})
        out["census"][p] = {}
        for s in sets[p]:
            at = etas if s["name"] == "defaults" else mids
            res = census(s["params"], at, s["starts"], cache, fresh)
            out["census"][p][s["name"]] = {f"{e:g}": rr for e, rr in zip(at, res["rows"])}
            out["timings"]["census_s"] += res["seconds"]
            if s["name"] == "defaults":
                seeds[p] = dict(zip(at, res["seeds"]))
            print(f"  census {p} {s['name']}: {len(at)} eta x {s['starts']} starts, "
                  f"{res['seconds']:.1f} s", file=log)
        t = time.perf_counter()
        rest = from_rest(sets[p][0]["params"], etas)
        out["from_rest"][p] = {f"{e:g}": r for e, r in zip(etas, rest)}
        out["timings"]["from_rest_s"] += time.perf_counter() - t
    for c in claims:
        if c.motion != "periodic" or not c.period:
            continue
        base = sets[c.preset][0]["params"]
        out["hunt"][c.key] = {}
        for e in claim_etas(c):
            h = hunt(base, e, divisors(c.period), seeds[c.preset][e], cache, fresh)
            out["hunt"][c.key][f"{e:g}"] = h
            out["timings"]["hunt_s"] += h["seconds"]
        print(f"  hunt {c.key}: periods {divisors(c.period)}", file=log)
    return out


# --- matching and outcomes ----------------------------------------------------------------


def matches(rows, claim):
    """Which of ``rows`` (attractors or labels: ``regime``, ``period``, ``impacts``,
    optional ``contact``) show the claim's motion (:func:`claims.match_points`)."""
    import xarray as xr

    if not rows:
        return np.zeros(0, bool)
    ds = xr.Dataset({
        "regime": ("eta", [r["regime"] for r in rows]),
        "period": ("eta", [r["period"] for r in rows]),
        "impacts_per_period": ("eta", [r["impacts"] for r in rows]),
        "contact": ("eta", [r.get("contact", 0) for r in rows])})
    return C.match_points(ds, claim)


def _distance(row, claim):
    """How far an attractor is from the claimed motion (for the nearest motion)."""
    ipp = row["impacts"] if math.isfinite(row["impacts"]) else 0.0
    periodic = row["regime"] == 1 and row["period"] > 0
    if claim.motion == "periodic":
        if not periodic or ipp <= 0:
            return 10.0 + (0.0 if ipp > 0 else 1.0)
        d = abs(math.log(row["period"] / (claim.period or 1)))
        if claim.impacts:
            d += abs(ipp - claim.impacts) / claim.impacts
        return d
    if claim.motion == "irregular":
        return 1.0 / row["period"] if periodic and ipp > 0 else 2.0
    return ipp if periodic else 10.0


def _sweep_reached(ds, claim, etas):
    """Whether the up/down sweep reaches the claim, with its evidence."""
    det = C.detect(ds, claim)[0]
    if det.agree and not claim.at_speed:  # a one-speed claim: its point, below
        return True, (f"the sweep's detection agrees: {det.start:.3f}–{det.end:.3f} "
                      f"({det.direction})")
    dirs = [str(d) for d in ds["direction"].values] if "direction" in ds.dims else ["up"]
    if claim.direction is not None and claim.direction in dirs:
        dirs = [claim.direction]
    for d in dirs:
        sub = ds.sel(direction=d) if "direction" in ds.dims else ds
        eta = sub["eta"].values
        ok = C.match_points(sub, claim)
        for e in etas:
            k = int(np.argmin(np.abs(eta - e)))
            if abs(eta[k] - e) <= 0.5 * STEP + 1e-9 and ok[k]:
                return True, (f"{d} sweep at η = {eta[k]:.3f}: {sub['label'].values[k]}")
    return False, ""


def decide(claim, computed, ds):
    """One claim's outcome and its evidence from the computation and the sweep."""
    p, etas = claim.preset, claim_etas(claim)
    sets = computed["sets"][p]
    by_name = {s["name"]: s for s in sets}
    cen = computed["census"][p]
    at = {s["name"]: [e for e in etas if f"{e:g}" in cen[s["name"]]] for s in sets}
    found = []  # (set name, eta, row) of matching attractors
    for s in sets:
        for e in at[s["name"]]:
            rows = cen[s["name"]][f"{e:g}"]
            for r, ok in zip(rows, matches(rows, claim)):
                if ok:
                    found.append((s["name"], e, r))
    rest = [(e, computed["from_rest"][p][f"{e:g}"]) for e in etas]
    rest_ok = [(e, r) for (e, r), ok in zip(rest, matches([r for _, r in rest], claim)) if ok]
    orbits = []
    for e, h in computed["hunt"].get(claim.key, {}).items():
        for o in h["orbits"]:
            if o["period"] == claim.period and o["impacts"] > 0 and (
                    not claim.impacts or o["impacts"] == claim.impacts):
                orbits.append((float(e), o))
    with_it = sorted({name for name, _, _ in found})
    n_readings = sum(len(by_name[n]["readings"]) for n in with_it)
    out = dict(key=claim.key, preset=p, statement=claim.statement, motion=claim.motion,
               period=claim.period, impacts=claim.impacts, etas=etas,
               sets=len(sets), readings_total=sum(len(s["readings"]) for s in sets),
               readings_with=n_readings, sets_with=with_it,
               defaults={f"{e:g}": cen["defaults"][f"{e:g}"] for e in etas},
               from_rest={f"{e:g}": r["name"] for e, r in rest},
               hunt={e: [o["label"] + f", |μ|max {o['abs_mu']:.3g}" for o in h["orbits"]]
                     for e, h in computed["hunt"].get(claim.key, {}).items()})
    reached, why = _sweep_reached(ds, claim, etas) if ds is not None else (False, "")
    if reached:
        out.update(outcome="reached", evidence=why)
    elif found:
        name, e, r = max(found, key=lambda f: (f[0] == "defaults", f[2]["fraction"]))
        sub = "" if len(with_it) == 1 else \
            f"; with it in {len(with_it)} of {len(sets)} parameter sets"
        out.update(outcome="exists", evidence=(
            f"attractor {_fmt_att(r)} at η = {e:g} ({_set_text(by_name[name])}, "
            f"{by_name[name]['starts']} starts){sub}"), fraction=r["fraction"], se=r["se"])
    elif rest_ok:
        e, r = rest_ok[0]
        out.update(outcome="exists", evidence=f"attractor {r['name']} reached from rest at "
                   f"η = {e:g} (defaults), in no census")
    elif orbits:
        e, o = min(orbits, key=lambda eo: eo[1]["abs_mu"])
        kind = "stable orbit (basin below one census start)" if o["stable"] else \
            "unstable orbit"
        out.update(outcome="exists", evidence=f"{kind} {o['label']} at η = {e:g} "
                   f"(hunt, defaults), |μ|max = {o['abs_mu']:.3g}", abs_mu=o["abs_mu"])
    else:
        cands = [(s["name"], e, r) for s in sets for e in at[s["name"]]
                 for r in cen[s["name"]][f"{e:g}"]]
        n = sum(s["starts"] * len(at[s["name"]]) for s in sets)
        hunted = f" and the hunt for periods {divisors(claim.period)}" \
            if claim.key in computed["hunt"] else ""
        if cands:
            name, e, r = min(cands, key=lambda f: (round(_distance(f[2], claim), 9),
                                                   f[0] != "defaults", -f[2]["fraction"]))
            near = (f"nearest: {_fmt_att(r)} at η = {e:g} "
                    f"({_set_text(by_name[name])})")
        else:
            near = "nothing settled"
        out.update(outcome="absent", evidence=f"absent among {n} starts{hunted}; {near}",
                   nearest=near)
    return out


def _set_text(s):
    """``"defaults"`` or ``"reading (a), B = .., Ec = .."``."""
    if s["name"] == "defaults":
        return "shipped defaults"
    keys = ", ".join(f"({k})" for k in s["readings"])
    return f"reading {keys} B = {s['params']['B']:g}, Ec = {s['params']['Ec']:g}"


def outcomes(computed, sweeps):
    """The outcome of every computed claim: a dict for :func:`render` and the JSON.

    Parameters
    ----------
    computed : dict
        From :func:`compute`.
    sweeps : dict
        Preset -> up/down sweep dataset (``paper.py``'s); a claim whose preset has none
        cannot be "reached".
    """
    claims = [c for c in C.CLAIMS if any(c.preset == p for p in computed["census"])
              and (computed["settings"]["only"] is None
                   or c.key in computed["settings"]["only"])]
    rows = [decide(c, computed, sweeps.get(c.preset)) for c in claims]
    return dict(settings=computed["settings"], timings=computed["timings"],
                sets={p: [dict(name=s["name"], readings=s["readings"], starts=s["starts"],
                               B=s["params"]["B"], Ec=s["params"]["Ec"],
                               damp=S.variant(tuple(d for d in S.DAMPINGS
                                                    if s["params"][d] > 0)))
                          for s in v] for p, v in computed["sets"].items()},
                claims=rows)


def tiny(smoke_dir):
    """In a smoke run (``smoke_dir`` not None): two claims, 16 starts, one reading."""
    smoke.shrink(globals(), smoke_dir, STARTS=16, READING_STARTS=16, HUNT_RANDOM=4,
                 ONLY=("fig8-AB", "fig11-P1"), MAX_READINGS=1)


def _finite(x):
    """``x`` with every NaN float replaced by None (strict JSON)."""
    if isinstance(x, float):
        return x if math.isfinite(x) else None
    if isinstance(x, dict):
        return {k: _finite(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_finite(v) for v in x]
    return x


def section(sweeps, cache, fresh=False, smoke_dir=None):
    """Compute (or read from the cache) and decide: ``(markdown, summary)``.

    Parameters
    ----------
    sweeps : dict
        Preset -> up/down sweep dataset.
    cache : path
        Directory of the JSON cache.
    fresh : bool
        Recompute even when cached.
    smoke_dir : path, optional
        A smoke run (:func:`tiny`).
    """
    tiny(smoke_dir)
    summary = _finite(outcomes(compute(cache, fresh), sweeps))
    return render(summary), summary


def main(argv=None):
    ap = smoke.parser(__doc__)
    ap.add_argument("--cache", type=Path, default=ROOT / ".paper-cache")
    ap.add_argument("--fresh", action="store_true", help="recompute the census")
    args = ap.parse_args(argv)
    step = STEP
    if args.smoke is not None:  # two claims, 16 starts, one reading, coarse sweeps
        tiny(args.smoke)
        args.cache, args.fresh, step = args.smoke / "cache", True, 0.1
    import paper_sweeps

    Path(args.cache).mkdir(parents=True, exist_ok=True)
    sweeps = {}
    for p in sorted({c.preset for c in selected_claims()}):
        sweeps[p] = paper_sweeps.sweep_one((p, step, str(args.cache), False, {}))[1]
    text, summary = section(sweeps, args.cache, args.fresh, args.smoke)
    out = smoke.moved(Path(args.cache) / "census_claims.json", args.smoke)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(summary, indent=1, sort_keys=True) + "\n")
    print(text)


if __name__ == "__main__":
    main()
