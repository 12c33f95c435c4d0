"""The retainer's inner ring as a degree of freedom against the paper's claims (issue 31).

One command regenerates ``reports/ring.md``, ``reports/ring.json`` and
``reports/figures/ring_map.png``::

    python analyses/ring/ring_study.py [--workers 2] [--fresh] [--smoke DIR]

At the calibrated B and Ec (the presets' values) it

1. sweeps fig10 and fig11 up and down on eta = 0.9:1.5:STEP with pure continuation and
   every analyser of the paper report, for eq. (5) (the held ring) and the ring model
   (``fig10-ring``, ``fig11-ring``) over the ring's inertia Jr (:data:`JR`) and its
   bearing's Coulomb drag Mr (:data:`MR` at the Jr of :data:`MR_AT`; cr fixed), and
   detects each interval claim as ``reports/paper.md`` does
   (:func:`vibimpact.paper.claims.detect`, ``claim_score`` and the verdict of
   ``analyses/paper/paper.py``);
2. looks for the paper's P3 (fig10), P6 and P10 (fig11) windows (:data:`WINDOWS`) in each
   variant's sweep, in the attractor census at the claim's middle eta
   (:func:`vibimpact.attractors`) and, for :data:`WINDOW_HUNT`, in the orbit hunt
   (:func:`vibimpact.hunt_orbits`) for the claimed period and its divisors;
3. maps fig11-ring over (eta, Jr) (:func:`vibimpact.map2d`, both directions), kept as
   NetCDF in the cache and drawn as ``reports/figures/ring_map.png``;
4. scores all 12 interval claims for eq. (5), the ring presets (figs 6 and 8, which have
   no ring preset of their own and no tangential force, take the ring of fig8-ring) and a
   lighter ring (:data:`LIGHT`): the sweep's verdict and the census outcome of
   ``analyses/paper/census_claims.py`` (reached / exists / absent) under the presets'
   parameters (the calibration's other damping readings are not rerun).

Every number of the report comes from ``reports/ring.json`` (``ring_report.render``);
``tests/test_ring_report.py`` renders it again and compares.  The computations are
cached in ``.paper-cache/ring/`` (``--fresh`` recomputes).
"""
from __future__ import annotations

import json
import math
import os
import sys
import time
from multiprocessing import get_context
from pathlib import Path

import numpy as np

import vibimpact as vi
from vibimpact.paper import claims as C

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # analyses/: _common
sys.path.insert(0, str(HERE.parent / "paper"))
sys.path.insert(0, str(HERE))
from _common import smoke  # noqa: E402

import census_claims as K  # noqa: E402
import paper as P  # noqa: E402
import ring_compute as RC  # noqa: E402
import ring_report  # noqa: E402

ROOT = HERE.parents[1]
REPORTS = ROOT / "reports"
FIGURES = REPORTS / "figures"
PAPER_JSON = REPORTS / "paper.json"
CACHE = ROOT / ".paper-cache" / "ring"

#: sweep grid step (eta = 0.9:1.5:STEP)
STEP = 0.002
#: the ring's inertia over which fig10-ring and fig11-ring are swept (plus eq. (5))
JR = (10.0, 1.0, 0.1, 0.05, 0.01)
#: the bearing's Coulomb drag swept at each Jr of MR_AT (the presets' Mr is in JR's row)
MR = (1e-4, 1e-2, 1e-1)
MR_AT = (0.05, 1.0)
#: the lighter ring of the claims table
LIGHT = 0.01
#: the windows of part 2, and the variants hunted for them
WINDOWS = ("fig10-P3", "fig11-P6", "fig11-P10")
WINDOW_HUNT = ("held", "Jr=0.05", "Jr=0.01")
#: the map: fig11-ring over eta (MAP_STEP) and Jr (log-spaced)
MAP_PRESET = "fig11-ring"
MAP_JR = tuple(float(f"{v:.3g}") for v in np.geomspace(0.005, 100.0, 12))
MAP_STEP = 0.002
#: the claims scored with the census (None: all 12)
ONLY = None
#: the sources every cached piece is keyed by; the run fails when they change under it
CODE = tuple(dict.fromkeys(RC.SWEEP_CODE + RC.CENSUS_CODE + RC.HUNT_CODE))


def variants():
    """The parameter variants, in report order: eq. (5), then Jr, then Mr.

    Returns
    -------
    list of dict
        ``key``, ``model`` ("eq5" or "ring"), ``Jr``, ``cr``, ``Mr`` (None for eq. (5)),
        ``figs`` (the figures swept).
    """
    ring = RC.ring_params("fig11")
    out = [dict(key="held", model="eq5", Jr=None, cr=None, Mr=None,
                figs=list(RC.FIGURES))]
    for jr in JR:
        figs = list(RC.FIGURES) if jr in (ring.Jr, LIGHT) else ["fig10", "fig11"]
        out.append(dict(key=f"Jr={jr:g}", model="ring", Jr=jr, cr=ring.cr, Mr=ring.Mr,
                        figs=figs))
    for jr in MR_AT:
        for mr in MR:
            out.append(dict(key=f"Jr={jr:g}, Mr={mr:g}", model="ring", Jr=jr, cr=ring.cr,
                            Mr=mr, figs=["fig10", "fig11"]))
    return out


def _preset_key():
    return f"Jr={RC.ring_params('fig11').Jr:g}"


def tiny(smoke_dir):
    """In a smoke run: a coarse grid, two variants, two windows, few starts."""
    smoke.shrink(globals(), smoke_dir, STEP=0.05, JR=(0.05,), MR=(1e-2,), MR_AT=(0.05,),
                 LIGHT=0.05, WINDOWS=("fig11-P6",), WINDOW_HUNT=("Jr=0.05",),
                 MAP_JR=(0.05, 1.0), MAP_STEP=0.1, ONLY=("fig8-AB", "fig11-P6"))
    K.tiny(smoke_dir)


# --- computing ------------------------------------------------------------------------


def _pool(fn, tasks, workers, what, log):
    """Results of ``fn`` over ``tasks`` (forked pool when ``workers`` > 1)."""
    out = []
    if workers <= 1 or len(tasks) <= 1:
        return [fn(t) for t in tasks]
    with get_context("fork").Pool(workers) as pool:
        for k, r in enumerate(pool.imap_unordered(fn, tasks), 1):
            out.append(r)
            if k % 10 == 0 or k == len(tasks):
                print(f"  {what}: {k}/{len(tasks)}", file=log, flush=True)
    return out


def _dedupe(tasks, key):
    seen, out = set(), []
    for t in tasks:
        k = key(t)
        if k not in seen:
            seen.add(k)
            out.append(t)
    return out


def _pkey(p):
    return (RC.model_of(p), json.dumps(p.as_dict(), sort_keys=True))


def compute(cache, fresh, workers, log=sys.stderr):
    """Every sweep, census, simulation from rest, hunt and the map (cached).

    Returns
    -------
    dict
        ``sweeps`` ("VARIANT:FIG" -> dataset), ``census`` ((model key, eta) -> result),
        ``hunt`` ((model key, eta, periods) -> result), ``from_rest`` (variant ->
        fig -> eta -> row), ``map`` (dataset, path), ``timings``.
    """
    Path(cache).mkdir(parents=True, exist_ok=True)
    vs = variants()
    t0 = time.perf_counter()
    import vibimpact.orbits  # noqa: F401 -- loaded (and the keys' source hashes taken)
    for code in (RC.SWEEP_CODE, RC.CENSUS_CODE, RC.HUNT_CODE):  # before the workers fork
        K.code_hash(code)
    vi.sweep(vi.presets.get("fig8"), [1.0, 1.2])  # compile before forking
    vi.sweep(vi.presets.get("fig8-ring"), [1.0, 1.2])
    tasks = [(f"{v['key']}:{f}", RC.variant_params(f, v), STEP, str(cache), fresh)
             for v in vs for f in v["figs"]]
    sweeps, cost = {}, 0.0
    for tag, ds, sec in _pool(RC.sweep, tasks, workers, "sweeps", log):
        sweeps[tag] = ds
        cost += sec
    t1 = time.perf_counter()
    claims = [c for c in C.CLAIMS if ONLY is None or c.key in ONLY]
    scored = [v for v in vs if v["key"] in ("held", _preset_key())]
    ctasks = []
    for v in scored:
        for c in claims:
            p = RC.variant_params(c.preset, v)
            ctasks += [(_pkey(p), p, e, K.STARTS, str(cache), fresh) for e in K.claim_etas(c)]
    for key in WINDOWS:
        c = next(c for c in C.CLAIMS if c.key == key)
        for v in vs:
            p = RC.variant_params(c.preset, v)
            ctasks.append((_pkey(p), p, K.middle_eta(c), K.STARTS, str(cache), fresh))
    ctasks = _dedupe(ctasks, lambda t: (t[0], t[2]))
    cen = {(tag, eta): r for tag, eta, r in _pool(RC.census_task, ctasks, workers,
                                                   "census", log)}
    t2 = time.perf_counter()
    rest = {}
    for v in scored:
        rest[v["key"]] = {}
        for f in RC.FIGURES:
            etas = sorted({e for c in claims if c.preset == f for e in K.claim_etas(c)})
            if etas:
                rows = K.from_rest(RC.variant_params(f, v), etas)
                rest[v["key"]][f] = {f"{e:g}": r for e, r in zip(etas, rows)}
    t3 = time.perf_counter()
    htasks = []
    for v in scored:
        for c in claims:
            if c.motion == "periodic" and c.period:
                p = RC.variant_params(c.preset, v)
                for e in K.claim_etas(c):
                    htasks.append((_pkey(p), p, e, tuple(K.divisors(c.period)),
                                   cen[(_pkey(p), e)]["seeds"], str(cache), fresh))
    for key in WINDOWS:
        c = next(c for c in C.CLAIMS if c.key == key)
        for v in vs:
            if v["key"] in WINDOW_HUNT:
                p, e = RC.variant_params(c.preset, v), K.middle_eta(c)
                htasks.append((_pkey(p), p, e, tuple(K.divisors(c.period)),
                               cen[(_pkey(p), e)]["seeds"], str(cache), fresh))
    htasks = _dedupe(htasks, lambda t: (t[0], t[2], t[3]))
    hunts = dict(_pool(_hunt_keyed, htasks, workers, "hunt", log))
    t4 = time.perf_counter()
    mds, mpath, msec = RC.regime_map(vi.presets.get(MAP_PRESET), MAP_STEP, MAP_JR, cache,
                                     fresh, lambda f, t: _pool(f, t, workers, "map", log))
    t5 = time.perf_counter()
    return dict(sweeps=sweeps, census=cen, hunt=hunts, from_rest=rest, map=(mds, mpath),
                timings=dict(
                    workers=workers, sweeps_s=t1 - t0, census_s=t2 - t1,
                    from_rest_s=t3 - t2, hunt_s=t4 - t3, map_s=t5 - t4,
                    sweeps_compute_s=cost,
                    census_compute_s=sum(r["seconds"] for r in cen.values()),
                    hunt_compute_s=sum(r["seconds"] for r in hunts.values()),
                    map_compute_s=msec))


def _hunt_keyed(task):
    tag, eta, r = RC.hunt_task(task)
    return (tag, eta, task[3]), r


# --- the summary (reports/ring.json) ----------------------------------------------------


def _f(x):
    x = float(x)
    return x if math.isfinite(x) else None


def _claim_rows(sweeps, prefix):
    """Claim key -> the detection of ``paper.py`` on the sweeps ``prefix + fig``."""
    out = {}
    for r in P.claim_rows(sweeps, STEP, prefix=prefix):
        c, d = r["claim"], r["det"]
        out[c.key] = dict(start=_f(d.start), end=_f(d.end), direction=d.direction,
                          jaccard=_f(d.score), agree=bool(d.agree), verdict=r["verdict"],
                          score=_f(C.claim_score(sweeps[prefix + c.preset], c)),
                          reason=r["reason"], labels=list(d.labels[:3]),
                          found=list(r["found"][:4]))
    return out


def _computed(comp, v, claims):
    """The structure :func:`census_claims.decide` reads, for one variant (the presets'
    parameters as the only parameter set, named "defaults")."""
    sets, cen, hunts = {}, {}, {}
    for f in sorted({c.preset for c in claims}):
        p = RC.variant_params(f, v)
        etas = sorted({e for c in claims if c.preset == f for e in K.claim_etas(c)})
        sets[f] = [dict(name="defaults", params=p.as_dict(), readings=["defaults"],
                        starts=K.STARTS)]
        cen[f] = {"defaults": {f"{e:g}": comp["census"][(_pkey(p), e)]["rows"]
                               for e in etas}}
    for c in claims:
        if c.motion == "periodic" and c.period:
            p = RC.variant_params(c.preset, v)
            per = tuple(K.divisors(c.period))
            hunts[c.key] = {f"{e:g}": comp["hunt"][(_pkey(p), e, per)]
                            for e in K.claim_etas(c)}
    return dict(settings=K.settings(), sets=sets, census=cen, hunt=hunts,
                from_rest=comp["from_rest"][v["key"]])


def _outcomes(comp, v, claims):
    computed = _computed(comp, v, claims)
    out = {}
    for c in claims:
        d = K.decide(c, computed, comp["sweeps"].get(f"{v['key']}:{c.preset}"))
        out[c.key] = dict(outcome=d["outcome"], evidence=d["evidence"])
    return out


def _window(comp, key, vs):
    """Part 2: the window ``key`` in each variant's sweep, census and hunt."""
    c = next(c for c in C.CLAIMS if c.key == key)
    eta = K.middle_eta(c)
    rows = []
    for v in vs:
        p = RC.variant_params(c.preset, v)
        ds = comp["sweeps"][f"{v['key']}:{c.preset}"]
        det = C.detect(ds, c)[0]
        res = comp["census"][(_pkey(p), eta)]
        att = res["rows"]
        ok = K.matches(att, c)
        match = [dict(name=a["name"], fraction=a["fraction"], se=a["se"],
                      abs_mu=_f(a["abs_mu"])) for a, m in zip(att, ok) if m]
        near = None
        if not match and att:
            a = min(att, key=lambda a: (round(K._distance(a, c), 9), -a["fraction"]))
            near = dict(name=a["name"], fraction=a["fraction"], se=a["se"])
        h = comp["hunt"].get((_pkey(p), eta, tuple(K.divisors(c.period))))
        orbits = None if h is None else [
            dict(label=o["label"], stable=o["stable"], abs_mu=o["abs_mu"])
            for o in h["orbits"] if o["period"] == c.period and o["impacts"] > 0 and (
                not c.impacts or o["impacts"] == c.impacts)]
        rows.append(dict(variant=v["key"], sweep=dict(
            start=_f(det.start), end=_f(det.end), direction=det.direction,
            labels=list(det.labels[:3])), census=match, nearest=near,
            attractors=len(att), hunt=orbits,
            hunt_periods=None if h is None else sorted({o["period"] for o in h["orbits"]})))
    return dict(key=key, preset=c.preset, statement=c.statement, eta=eta,
                period=c.period, impacts=c.impacts, rows=rows)


def _map_rows(mds):
    """Per Jr of the map: the detection of each fig11 claim on that row."""
    out = []
    for jr in mds["Jr"].values:
        row = mds.sel(Jr=jr)
        dets = {}
        for c in C.claims("fig11"):
            d = C.detect(row, c)[0]
            dets[c.key] = dict(start=_f(d.start), end=_f(d.end), direction=d.direction,
                               agree=bool(d.agree))
        out.append(dict(Jr=float(jr), claims=dets, tail=_tail(row)))
    return out


#: kinds of motion of the motion figure and the tail table, in drawing order
MOTIONS = ("impactless", "permanent contact", "periodic, impacting", "irregular", "other")
#: the claim whose interval the tail table looks at
TAIL = "fig11-impactless"


def motion_kinds(sub):
    """Index into :data:`MOTIONS` of each point of a one-direction sweep: the rotor rolling
    on the ring (permanent contact) first, then impactless, the paper's chaos
    (:data:`claims.IRREGULAR`), periodic impacting, anything else (diverged, ...)."""
    reg = np.asarray(sub["regime"].values, int)
    per = np.asarray(sub["period"].values, int)
    ipp = np.asarray(sub["impacts_per_period"].values, float)
    con = np.asarray(sub["contact"].values, int)
    out = np.full(reg.shape, 4)
    per_imp = (reg == 1) & (per > 0) & np.isfinite(ipp) & (ipp > 0)
    out[per_imp] = 2
    out[C.match_points(sub, C.IRREGULAR)] = 3
    out[(reg == 1) & (ipp == 0) & (con == 0)] = 0
    out[con == 2] = 1
    return out


def _tail(ds):
    """Shares of each kind of motion over the interval of :data:`TAIL` in its
    direction."""
    c = next(c for c in C.CLAIMS if c.key == TAIL)
    sub = ds.sel(direction=c.direction or "up")
    eta = sub["eta"].values
    inside = (eta >= c.lo - 1e-9) & (eta <= c.hi + 1e-9)
    kinds = motion_kinds(sub)[inside]
    return {m: float(np.mean(kinds == k)) for k, m in enumerate(MOTIONS)}


def _same(sweeps, fig, key):
    """eq. (5) against the ring variant ``key`` on ``fig``: the share of sweep points
    with the same label and the ring's largest speed at a sweep point (a held ring:
    0)."""
    a, b = sweeps.get(f"held:{fig}"), sweeps.get(f"{key}:{fig}")
    if a is None or b is None:
        return {}
    vr = np.abs(np.asarray(b["final_state"].values, float)[..., -1])
    return dict(same_label=float(np.mean(a["label"].values == b["label"].values)),
                vr_max=float(np.nanmax(vr)))


def _paper_md():
    """The eq. (5) verdicts and census outcomes of reports/paper.md (paper.json)."""
    if not PAPER_JSON.exists():
        return {}
    pj = json.loads(PAPER_JSON.read_text())
    step = float(pj.get("census_claims", {}).get("settings", {}).get("step", float("nan")))
    return dict(step=step, verdicts=pj.get("verdicts", {}),
                outcomes=pj.get("census_outcomes", {}))


def summary(comp, elapsed, box):
    """Everything the report shows, JSON-able (``reports/ring.json``)."""
    vs = variants()
    ring = RC.ring_params("fig11")
    claims = [c for c in C.CLAIMS if ONLY is None or c.key in ONLY]
    sweeps = comp["sweeps"]
    columns = {"eq5": "held", "ring": _preset_key(), "light": f"Jr={LIGHT:g}"}
    det = {v["key"]: _claim_rows(sweeps, f"{v['key']}:") for v in vs}
    outcomes = {col: _outcomes(comp, next(v for v in vs if v["key"] == key), claims)
                for col, key in columns.items() if col != "light"}
    rows = []
    for c in C.CLAIMS:
        row = dict(key=c.key, preset=c.preset, statement=c.statement,
                   claimed=f"{P._what(c)} {P._paper_span(c)}")
        for col, key in columns.items():
            row[col] = dict(det[key].get(c.key, {}))
            if col in outcomes and c.key in outcomes[col]:
                row[col].update(outcomes[col][c.key])
        rows.append(row)
    mds, mpath = comp["map"]
    tail = next(c for c in C.CLAIMS if c.key == TAIL)
    return K._finite(dict(
        settings=dict(
            step=STEP, eta=[0.9, 1.5], analyses=list(RC.ANALYSES), B=ring.B, Ec=ring.Ec,
            preset_ring=dict(Jr=ring.Jr, cr=ring.cr, Mr=ring.Mr), jr=list(JR),
            mr=list(MR), mr_at=list(MR_AT), light=LIGHT, windows=list(WINDOWS),
            window_hunt=list(WINDOW_HUNT), census=K.settings(), box=box,
            map=dict(preset=MAP_PRESET, step=MAP_STEP, jr=list(MAP_JR),
                     file=os.path.relpath(mpath, ROOT) if ROOT in Path(mpath).parents
                     else str(mpath)),
            version=vi.__version__, columns=columns,
            states=list(vi.models.get("ring").state_names),
            tangential={f: dict(BT=RC.ring_params(f).BT, f=RC.ring_params(f).f,
                                preset=f"{f}-ring" in vi.presets.names(),
                                **_same(sweeps, f, columns["ring"]))
                        for f in RC.FIGURES}),
        timings=dict(comp["timings"], total_s=elapsed),
        variants=[{k: v[k] for k in ("key", "model", "Jr", "cr", "Mr", "figs")}
                  for v in vs],
        intervals={v["key"]: {k: d for k, d in det[v["key"]].items()
                              if k.startswith(("fig10", "fig11"))} for v in vs},
        claims=rows,
        tail=dict(claim=TAIL, motions=list(MOTIONS), lo=tail.lo, hi=tail.hi,
                  direction=tail.direction or "up", variants={
            v["key"]: _tail(sweeps[f"{v['key']}:fig11"]) for v in vs}),
        counts={col: sum(det[key].get(c.key, {}).get("verdict") == "agree"
                         for c in C.CLAIMS) for col, key in columns.items()},
        windows=[_window(comp, k, vs) for k in WINDOWS],
        map=_map_rows(mds),
        paper_md=_paper_md()))


def figure(comp, path):
    """The regime map over (eta, Jr) of :data:`MAP_PRESET` (``vibimpact.plotting``)."""
    from vibimpact.plotting.map2d import plot_map

    path.parent.mkdir(parents=True, exist_ok=True)
    plot_map(comp["map"][0], path=path)


def motion_figure(comp, path):
    """The map's kinds of motion (:data:`MOTIONS`) over (eta, Jr), one panel per sweep
    direction, with the fig11 claims' intervals above (the library's map draws rolling
    and impactless motion alike: both periodic without impacts)."""
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    ds = comp["map"][0]
    colours = ("#9ecae1", "#3182bd", "#31a354", "#de2d26", "#bdbdbd")
    cmap = ListedColormap(colours)
    jr = ds["Jr"].values
    eta = ds["eta"].values
    h = 0.5 * float(np.median(np.diff(eta))) if eta.size > 1 else 0.05
    dirs = [str(d) for d in ds["direction"].values]
    fig = Figure(figsize=(9.0, 3.0 * len(dirs) + 0.8), layout="constrained")
    axes = fig.subplots(len(dirs), 1, sharex=True, squeeze=False)[:, 0]
    for ax, d in zip(axes, dirs):
        sub = ds.sel(direction=d)
        grid = np.array([motion_kinds(sub.sel(Jr=v)) for v in jr])
        ax.pcolormesh(np.r_[eta - h, eta[-1] + h], np.arange(jr.size + 1) - 0.5, grid,
                      cmap=cmap, vmin=-0.5, vmax=len(MOTIONS) - 0.5)
        ax.set_yticks(np.arange(jr.size), [f"{v:g}" for v in jr])
        ax.set_ylabel("Jr")
        ax.set_title(f"sweep {d}", loc="left", fontsize="medium")
        for k, c in enumerate(C.claims("fig11")):
            y = jr.size - 0.5 + 0.35 * (1 + k % 2)
            ax.plot([c.lo, c.hi], [y, y], color="k", lw=2, clip_on=False)
            ax.annotate(c.key.replace("fig11-", ""), (0.5 * (c.lo + c.hi), y),
                        xytext=(0, 2), textcoords="offset points", ha="center",
                        fontsize="x-small", annotation_clip=False)
        ax.set_ylim(-0.5, jr.size + 1.1)
    axes[-1].set_xlabel("η")
    fig.legend(handles=[Patch(color=c, label=m) for c, m in zip(colours, MOTIONS)],
               loc="outside lower center", ncol=len(MOTIONS), fontsize="small")
    fig.suptitle(f"{MAP_PRESET}: kind of motion over η and Jr (bars: the paper's claims)",
                 fontsize="medium")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)


def main(argv=None):
    global REPORTS, FIGURES
    ap = smoke.parser(__doc__)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--cache", type=Path, default=CACHE)
    ap.add_argument("--fresh", action="store_true", help="recompute the cached pieces")
    args = ap.parse_args(argv)
    if args.smoke is not None:
        tiny(args.smoke)
        REPORTS, FIGURES = args.smoke, args.smoke / "figures"
        REPORTS.mkdir(parents=True, exist_ok=True)
        args.cache, args.fresh, args.workers = args.smoke / "cache", True, 1
    t0 = time.perf_counter()
    code = K.code_hash.__wrapped__(CODE)
    comp = compute(args.cache, args.fresh, args.workers)
    if K.code_hash.__wrapped__(CODE) != code:  # results keyed by sources they may not be
        sys.exit("vibimpact's sources changed during the run: its cached pieces may mix "
                 "two versions; rerun with --fresh (no report written)")
    box = next(r["box"] for (pk, _), r in comp["census"].items() if pk[0] == "ring")
    figure(comp, FIGURES / "ring_map.png")
    motion_figure(comp, FIGURES / "ring_motion.png")
    data = summary(comp, time.perf_counter() - t0, box)
    data["settings"]["code"] = code
    js = REPORTS / "ring.json"
    text = json.dumps(data, indent=1, sort_keys=True) + "\n"
    data = json.loads(text)  # the report renders the JSON as it is read back
    tmp = js.with_suffix(".tmp")
    tmp.write_text(text)
    os.replace(tmp, js)
    md = REPORTS / "ring.md"
    tmp = md.with_suffix(".tmp")
    tmp.write_text(ring_report.render(data))
    os.replace(tmp, md)
    print(f"{data['counts']} interval claims agree -> {md}")


if __name__ == "__main__":
    main()
