"""Reproduce the paper: every figure's counterpart and the claim-by-claim report.

One command regenerates ``reports/paper.md`` and the figures in ``reports/figures/``::

    python analyses/paper/paper.py                 # all presets, eta = 0.9:1.5:0.005, 2 processes
    python analyses/paper/paper.py --step 0.002    # finer (slower)

For every preset (figs 4-11 and rr10) it runs an up-and-down sweep with pure continuation
(``blocks=1``) and all analysers, draws the response curves with regime bands
(``response_<preset>.png``), the bifurcation diagram (``bifurcation_<preset>.png``) and the
X-Y trajectories at the frequencies the paper shows (``xy_<preset>.png``), then checks each
claim of the paper: the interval claims of :data:`vibimpact.paper.claims.CLAIMS`
automatically (detected interval, labels, agreement within one sweep step), and the
comparative claims ("X and Y identical", "no considerable change from fig6", ...) by the
measures stated in the table.  Every interval boundary of fig8, fig10 and fig11 gets its
transition type (:func:`vibimpact.transition_types`: period doubling, fold, Neimark--Sacker,
grazing, crisis, intermittency), refined by bisection.  The sweeps and the transition types
are kept in ``.paper-cache/`` (``--fresh`` recomputes them).
"""
from __future__ import annotations

import json
import os
import sys
import time
from multiprocessing import get_context
from pathlib import Path

import numpy as np

import vibimpact as vi
from vibimpact.paper import claims as C

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # analyses/: _common
from _common import smoke  # noqa: E402
import census_claims  # noqa: E402
import paper_notes  # noqa: E402
import paper_sweeps  # noqa: E402
from paper_compare import ALIKE_CHAOS, ALIKE_RESPONSE, comparative_rows  # noqa: E402
from paper_sweeps import cache_path as _cache_path, sweep_one as _sweep_one  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
REPORTS = ROOT / "reports"
FIGURES = REPORTS / "figures"
#: the calibration's dataset (read only; written by calibrate.py)
CALIBRATION = REPORTS / "calibration.nc"
PRESETS = ("fig4", "fig5", "fig6", "fig7", "fig8", "fig9", "fig10", "fig11", "rr10")
#: presets whose interval boundaries get a transition type (the figures with interval
#: claims)
TYPED = ("fig8", "fig10", "fig11")
#: the presets as shipped before the low-damping calibration (B and Ec of the first
#: calibration, one contact damping per figure): their claims are counted in the same run
PREVIOUS = {"fig6": dict(B=0.07, Ec=0.11, Bh=0.0, BT=0.0, f=0.0),
            "fig8": dict(B=0.07, Ec=0.11, Bh=0.0, BT=0.0, f=0.0),
            "fig10": dict(B=0.07, Ec=0.11, Bh=0.0, BT=0.05, f=0.0),
            "fig11": dict(B=0.07, Ec=0.11, Bh=0.0, BT=0.0, f=0.05)}

#: X-Y panels: preset -> [(panel name, eta or a rule picking eta from the sweep)]
XY_POINTS = {
    "fig4": [("", 1.0), ("", 1.2)],
    "fig5": [("", 1.0), ("", 1.1), ("", 1.15), ("", 1.3)],
    "fig6": [("", 1.15), ("", 1.2)],
    "fig7": [("", 1.2)],
    "fig8": [("8a", 1.185), ("", 1.25)],
    "fig9": [("", 1.185), ("", 1.25)],
    "fig10": [("10a", "first irregular below 1.2"), ("10b", 1.22), ("10c", 1.42)],
    "fig11": [("11b", 1.06), ("11c", 1.165), ("11d", 1.315)],
    "rr10": [("", 1.06), ("", 1.165), ("", 1.315)],
}


def warm_up():
    """Compile (or load) the kernel in this process before forking workers: a sweep in a
    daemonic pool worker must not start the engine's own warm-up process (a daemonic
    process may not have children)."""
    vi.sweep(vi.presets.get("fig8"), [1.0, 1.2])


def sweeps(step, cache, fresh, workers, overrides):
    """Preset name -> sweep dataset (computed in parallel, one preset per process), and
    the claim figures at the previous defaults (:data:`PREVIOUS`, key ``"old:NAME"``)."""
    Path(cache).mkdir(parents=True, exist_ok=True)
    tasks = [(n, step, cache, fresh, overrides, False) for n in PRESETS]
    if not overrides:
        tasks += [(n, step, cache, fresh, PREVIOUS[n], True) for n in PREVIOUS]
    out, cost = {}, {}
    warm_up()
    with get_context("fork").Pool(workers) as pool:
        for name, ds, sec, old in pool.imap_unordered(_sweep_task, tasks):
            key = f"old:{name}" if old else name
            out[key], cost[key] = ds, sec
            print(f"  {key}: {'cached' if not sec else f'{sec:.0f} s'}", file=sys.stderr)
    return out, cost


def _sweep_task(task):
    return (*_sweep_one(task[:5]), task[5])


def _types_one(task):
    """The transition types of one preset's sweep (issue 8), cached beside the sweep."""
    name, ds, step, cache, fresh, overrides = task
    import xarray as xr

    _, path = _cache_path(name, step, cache, overrides, "_transitions")
    if path.exists() and not fresh:
        return name, xr.load_dataset(path), 0.0
    if paper_sweeps.CACHE_ONLY:
        raise paper_sweeps.NotCached(f"{path} is not in the cache")
    t = time.perf_counter()
    tt = vi.transition_types(ds, tol=1e-4)
    tmp = path.with_suffix(".tmp")
    tt.to_netcdf(tmp)
    os.replace(tmp, path)
    return name, tt, time.perf_counter() - t


def transitions(data, step, cache, fresh, workers, overrides):
    """Preset -> transition-type dataset for the presets with interval claims."""
    tasks = [(n, data[n], step, cache, fresh, overrides) for n in TYPED]
    out = {}
    with get_context("fork").Pool(workers) as pool:
        for name, tt, sec in pool.imap_unordered(_types_one, tasks):
            out[name] = tt
            print(f"  {name} transitions: {'cached' if not sec else f'{sec:.0f} s'}",
                  file=sys.stderr)
    return out


def transition_section(types):
    """Markdown: per figure, every interval boundary with its refined eta and type."""
    from collections import Counter

    lines = ["## Transition types (issue 8)", "",
             "Every boundary of the interval maps above, in sweep order, refined by "
             "bisection to 1e-4 in η and typed by the Floquet multipliers of the orbit "
             "followed by Newton shooting (through −1: period doubling; through +1 or no "
             "orbit beyond: fold; complex pair: Neimark–Sacker; contacts appear or vanish: "
             "grazing; no periodic orbit on either side: crisis; a fold into chaos: "
             "intermittency; 'none': the sweep relabelled the same orbit).  The evidence "
             "for each row (multipliers before and after, contact counts, coexistence) is "
             "in [transitions.md](transitions.md) (`python analyses/paper/transitions.py`).", ""]
    for name in TYPED:
        tt = types[name]
        kinds = Counter(t for v in tt["type"].values for t in str(v).split(" + "))
        lines += [f"### {name}", "",
                  f"{tt.sizes.get('boundary', 0)} boundaries: " +
                  ", ".join(f"{k} {c}" for k, c in kinds.most_common()) + ".", ""]
        rows = []
        for k in range(tt.sizes.get("boundary", 0)):
            mu = complex(float(tt["mu_real"].values[k]), float(tt["mu_imag"].values[k]))
            lo, hi = float(tt["eta_lo"].values[k]), float(tt["eta_hi"].values[k])
            rows.append((str(tt["direction"].values[k]), f"{0.5 * (lo + hi):.4f}",
                         str(tt["from_label"].values[k]), str(tt["to_label"].values[k]),
                         f"**{tt['type'].values[k]}**",
                         f"{abs(mu):.3f}" if np.isfinite(abs(mu)) else "—"))
        lines += [_md_table(("sweep", "η", "from", "to", "type", "|μ|max"), rows), ""]
    return "\n".join(lines)


# --- X-Y trajectories ---------------------------------------------------------------------


def _pick_eta(ds, rule):
    """The eta of a panel: a number, or the rule "first irregular below 1.2" (up sweep)."""
    if not isinstance(rule, str):
        return float(rule)
    sub = ds.sel(direction="up")
    ok = C.match_points(sub, C.IRREGULAR)
    eta = sub["eta"].values
    sel = np.flatnonzero(ok & (eta < 1.2))
    return float(eta[sel[0]]) if sel.size else 1.0


def trajectory(ds, eta, periods=None):
    """Run dataset of the up sweep's motion at the grid point nearest ``eta``.

    The sweep's final state at that point (a strobe instant, so at forcing phase 0) starts
    a run long enough to show the attractor: 4 periods of a periodic orbit, else 40.
    """
    from vibimpact.io import run_to_dataset

    sub = ds.sel(direction="up")
    k = int(np.argmin(np.abs(sub["eta"].values - eta)))
    e = float(sub["eta"].values[k])
    p = vi.Params(**json.loads(ds.attrs["params"]), eta=e)
    n = int(sub["period"].values[k])
    periods = periods or (max(4 * n, 4) if n else 40)
    run = vi.simulate(p, periods=periods, state0=sub["final_state"].values[k], dense=200)
    return run_to_dataset(run), str(sub["label"].values[k]), run


def xy_figure(name, ds, path, draw=True):
    """Panels of X-Y trajectories for one preset; returns the panel descriptions (the
    figure is saved to ``path`` only when ``draw``)."""
    from matplotlib.figure import Figure

    from vibimpact.analysis import contact_arcs
    from vibimpact.plotting import plot_xy, save_figure

    panels = XY_POINTS[name]
    fig = Figure(figsize=(4.6 * len(panels), 5.6), layout="constrained")
    axes = fig.subplots(1, len(panels), squeeze=False)[0]
    rows = []
    for ax, (tag, rule) in zip(axes, panels):
        eta = _pick_eta(ds, rule)
        rds, label, run = trajectory(ds, eta)
        plot_xy(rds, ax=ax)
        arcs = contact_arcs(run).to_text()
        ax.set_title(f"{'(' + tag + ') ' if tag else ''}η = {rds.attrs['param_eta']:.3f}\n"
                     f"{label}", fontsize="small")
        ax.get_legend().remove()
        rows.append((tag, float(rds.attrs["param_eta"]), label, arcs))
    fig.suptitle(f"{name}: X-Y trajectories (up sweep; +Y down, along gravity)",
                 fontsize="medium")
    if draw:
        save_figure(fig, path, dpi=150)
    return rows


# --- claims -----------------------------------------------------------------------------


def _fmt_span(a, b):
    return "—" if not np.isfinite(a) else (f"{a:.3f}" if a == b else f"{a:.3f}–{b:.3f}")


def _paper_span(c):
    if c.lo == c.hi:
        return f"near {c.lo:g}" if c.near else f"at {c.lo:g}"
    return f"{'near ' if c.near else ''}({c.lo:g}, {c.hi:g})"


def _what(c):
    if c.motion == "periodic":
        bits = [f"P{c.period}" if c.period else "periodic"]
        if c.impacts:
            bits.append(f"{c.impacts} impacts")
        return ", ".join(bits)
    return {"irregular": "chaos", "impactless": "impactless"}[c.motion]


def claim_rows(data, step, prefix=""):
    """One row per interval claim: paper, detection, agreement, reason (the sweeps
    ``data[prefix + preset]``)."""
    rows = []
    for c in C.CLAIMS:
        if prefix + c.preset not in data:
            continue
        ds = data[prefix + c.preset]
        verdict, best = C.judge(ds, c)
        eta = ds["eta"].values
        inside = (eta >= c.lo - 1e-9) & (eta <= c.hi + 1e-9)
        sub = ds.sel(direction=best.direction)
        found = sorted(set(str(x) for x in sub["label"].values[inside])) if inside.any() \
            else []
        if c.at_speed:
            k = int(np.argmin(np.abs(sub["eta"].values - c.lo)))
            reason = (f"one speed: at η = {float(sub['eta'].values[k]):.3f} the "
                      f"{best.direction} sweep shows {sub['label'].values[k]}")
        elif verdict == "agree":
            reason = f"both ends within {step:g}" if not c.near else \
                "starts within 0.02 of the stated eta"
        elif not np.isfinite(best.start):
            reason = (f"no {_what(c)} within ±{C.WINDOW:g} of the claim; the sweep shows "
                      + "; ".join(found[:4]) if found else "nothing there")
        else:
            reason = (f"start {best.start - c.lo:+.3f}, end {best.end - c.hi:+.3f} "
                      f"(Jaccard {best.score:.2f})")
        rows.append(dict(claim=c, det=best, found=found, verdict=verdict, reason=reason))
    return rows


# --- report -----------------------------------------------------------------------------


def figures(data, draw=True):
    """All figures (drawn only when ``draw``); returns preset -> X-Y panel rows."""
    from vibimpact.plotting import plot_bifurcation, plot_response

    FIGURES.mkdir(parents=True, exist_ok=True)
    panels = {}
    for name in PRESETS:
        ds = data[name]
        if draw:
            plot_response(ds, path=FIGURES / f"response_{name}.png")
            plot_bifurcation(ds, path=FIGURES / f"bifurcation_{name}.png")
        panels[name] = xy_figure(name, ds, FIGURES / f"xy_{name}.png", draw)
        print(f"  figures {name}{'' if draw else ' (rows only)'}", file=sys.stderr)
    return panels


def cached_census(data, path):
    """The census section from the census summary stored in ``path`` (``paper.json``),
    for a render-only run: the computed part (censuses, runs from rest, hunts) is kept,
    whether the up/down sweep reaches each claim is decided again on ``data`` (the claim
    detection may have changed since).

    Raises
    ------
    paper_sweeps.NotCached
        When a claim the stored summary found "reached" by the sweep is no longer reached:
        its other outcomes were never computed, so the census must be run again.
    """
    from census_claims_report import render

    summary = json.loads(Path(path).read_text())["census_claims"]
    for row in summary["claims"]:
        claim = next(c for c in C.CLAIMS if c.key == row["key"])
        reached, why = census_claims._sweep_reached(data[claim.preset], claim, row["etas"])
        if reached:
            row.update(outcome="reached", evidence=why)
        elif row["outcome"] == "reached":
            raise paper_sweeps.NotCached(
                f"{claim.key}: the sweep no longer reaches the claim and the census's "
                "other outcomes are not stored: run without --render-only")
    return render(summary), summary


def _md_table(head, rows):
    out = ["| " + " | ".join(head) + " |", "|" + " --- |" * len(head)]
    out += ["| " + " | ".join(str(c).replace("|", "/") for c in r) + " |" for r in rows]
    return "\n".join(out)


def _calibration(path=None):
    """``(dataset, claim keys whose stored scores are today's, keys left out)`` of
    ``calibration.nc`` (None without the file): scores stored under an older scoring rule
    (its ``claims_scoring`` attribute) are left out for the claims whose rule changed."""
    import xarray as xr

    path = CALIBRATION if path is None else path
    if not Path(path).exists():
        return None, [], []
    cal = xr.load_dataset(path)
    version = int(cal.attrs.get("claims_scoring", 1))
    by_key = {c.key: c for c in C.CLAIMS}
    keys = [str(k) for k in cal["claim"].values]
    ok = [k for k in keys if k in by_key and C.scored_alike(by_key[k], version)]
    return cal, ok, [k for k in keys if k not in ok]


def calibration_best(path=None):
    """Claim key -> its best score over every calibrated (B, Ec) of ``calibration.nc``
    (empty without the file; claims scored by an older rule left out)."""
    cal, keys, _ = _calibration(path)
    return {k: float(cal["score"].sel(claim=k).values.max()) for k in keys}


def evidence_section():
    """Best score of each claim over all calibrated (B, Ec) pairs, from calibration.nc."""
    cal, keys, stale = _calibration()
    if cal is None:
        return "(run `python analyses/paper/calibrate.py` for the evidence over B and Ec)"
    rows = []
    reading = cal["reading"].values if "reading" in cal else None
    for key in keys:
        sc = cal["score"].sel(claim=key).values
        k = int(np.argmax(sc))
        where = (f"({reading[k]}) " if reading is not None else "") + \
            f"B = {float(cal['B'][k]):g}, Ec = {float(cal['Ec'][k]):g}"
        rows.append((str(key), f"{sc.max():.2f}", where, f"{np.mean(sc > 0):.0%}"))
    left = (f"  Left out: {', '.join(stale)}, scored by the calibration under an earlier "
            f"rule (its `claims_scoring` {int(cal.attrs.get('claims_scoring', 1))}, today "
            f"{C.SCORING_VERSION}: one-speed claims are now scored as the motion at that "
            "speed); `calibrate.py` scores them again." if stale else "")
    B = cal["B"].values
    pos = B[B > 0]
    zero = " and B = 0" if np.any(B == 0) else ""
    return "\n".join([
        "## Over all calibrated (B, Ec): what eq. (5) produces", "",
        f"The calibration swept {cal.sizes['pair']} (reading, B, Ec) combinations (B "
        f"{pos.min():g}–{pos.max():g}{zero}, Ec {cal['Ec'].values.min():g}–"
        f"{cal['Ec'].values.max():g}; [calibration.md](calibration.md)).  Best score of "
        "each claim over all of them (1 = reproduced point for point; a P-n window found "
        "with another period scores at most 0.5), where it is reached, and the share of "
        "combinations where the claim scores at all: for a claim that disagrees at the "
        "defaults, the nearest the model comes to it." + left, "",
        _md_table(("claim", "best score", "at", "share > 0"), rows)])


def report(data, cost, panels, step, elapsed, overrides, types=None, census=None,
           notes=True):
    from vibimpact.sweeps.dataset import format_intervals

    p8 = vi.presets.get("fig8").replace(**overrides)
    crow = claim_rows(data, step)
    prev = {r["claim"].key: r for r in claim_rows(data, step, prefix="old:")}
    comp = comparative_rows(data)
    n_agree = sum(r["verdict"] == "agree" for r in crow)
    n_prev = sum(r["verdict"] == "agree" for r in prev.values())
    lines = [
        "# Reproducing Půst & Kozánek: claim by claim",
        "",
        f"Generated by `python analyses/paper/paper.py` (vibimpact {vi.__version__}): up and "
        f"down sweeps of every preset on η = 0.9:1.5:{step:g} with pure continuation, all "
        + (f"analysers; rendered from the cached sweeps in {elapsed / 60:.1f} min"
           if all(v == 0 for v in cost.values()) else
           f"analysers; {elapsed / 60:.1f} min on this machine"
           + (" (sweeps partly from the cache)" if any(v == 0 for v in cost.values())
              else ""))
        + ".",
        "",
        f"Parameters the paper does not state: **B = {p8.B:g}, Ec = {p8.Ec:g}**"
        + (" (set on the command line)" if overrides else
           " (the presets' defaults, calibrated in [calibration.md](calibration.md))")
        + ".  Everything else is the presets' table (`vibimpact.models.presets`).  \"Chaos\" in the paper is matched by our "
        "*irregular* motion: chaotic, quasi-periodic, unsettled (impacting, no test decided it) or periodic with a period above the detector's maximum "
        "(the paper judged from response curves and trajectories, on which these look "
        "alike); the labels column names which of ours make up each interval.",
        "",
        f"**Interval claims: {n_agree} of {len(crow)} agree within one sweep step** "
        "(claims \"near η\": start within 0.02)"
        + (f"; at the previous defaults (B = {PREVIOUS['fig8']['B']:g}, Ec = "
           f"{PREVIOUS['fig8']['Ec']:g}, one contact damping per figure), swept in this "
           f"run with the same detection: {n_prev} of {len(prev)}." if prev else "."),
        "",
        "## Interval claims (automated detection, `vibimpact/paper/claims.py`)",
        "",
    ]
    rows = []
    for r in crow:
        c, d = r["claim"], r["det"]
        rows.append((c.preset, c.statement, f"{_what(c)} {_paper_span(c)}",
                     f"{_fmt_span(d.start, d.end)} ({d.direction})" if np.isfinite(d.start)
                     else "—", "; ".join(d.labels[:3]) or "—", f"**{r['verdict']}**",
                     r["reason"], prev[c.key]["verdict"] if c.key in prev else "—"))
    lines.append(_md_table(("figure", "paper", "claimed", "detected", "labels", "verdict",
                            "reason", "previous defaults"), rows))
    if census:
        lines += ["", census[0]]
    lines += ["", "## Comparative and shape claims", ""]
    lines.append(_md_table(("figure", "paper", "measured", "verdict", "criterion / reason"),
                           [(a, b, c, f"**{d}**", e) for a, b, c, d, e, _ in comp]))
    lines += ["", evidence_section()]
    summary = dict(B=p8.B, Ec=p8.Ec, agree=n_agree, claims=len(crow),
                   agree_previous=n_prev, claims_previous=len(prev), previous=PREVIOUS,
                   verdicts={r["claim"].key: r["verdict"] for r in crow},
                   verdicts_previous={k: r["verdict"] for k, r in prev.items()},
                   comparative={f"{a}: {b}": d for a, b, c, d, e, _ in comp},
                   comparative_values={f"{a}: {b}": v for a, b, c, d, e, v in comp},
                   detections={r["claim"].key: dict(
                       direction=r["det"].direction, start=r["det"].start,
                       end=r["det"].end, score=r["det"].score,
                       labels=list(r["det"].labels), reason=r["reason"],
                       lo=r["claim"].lo, hi=r["claim"].hi) for r in crow},
                   calibration_best=calibration_best(),
                   step=step, grid=f"0.9:1.5:{step:g}",
                   alike=dict(response=ALIKE_RESPONSE, chaos=ALIKE_CHAOS),
                   partly=C.PARTLY, relaxed_credit=C.RELAXED_CREDIT)
    if census:
        summary.update(census_claims=census[1], census_outcomes={
            r["key"]: r["outcome"] for r in census[1]["claims"]})
    summary = census_claims._finite(summary)
    if overrides or not notes:
        lines += ["", "(The hand-written reading of `analyses/paper/paper_notes.md` is about "
                  "the shipped defaults on the full grid; left out of this run.)"]
    else:
        lines += ["", paper_notes.render(summary)]
    if types:
        lines += ["", transition_section(types)]
    lines += ["", "## Figures", ""]
    for name in PRESETS:
        ds = data[name]
        lines += [f"### {name}: {vi.presets.describe(name)}", "",
                  f"![response {name}](figures/response_{name}.png)", "",
                  f"![bifurcation {name}](figures/bifurcation_{name}.png)", "",
                  f"![xy {name}](figures/xy_{name}.png)", "",
                  _md_table(("panel", "η", "label", "loaded arcs (degrees, +90 = bottom)"),
                            [(t or "—", f"{e:.3f}", lab, arcs)
                             for t, e, lab, arcs in panels[name]]), "",
                  "<details><summary>interval map</summary>", "", "```",
                  format_intervals(vi.intervals(ds)), "```", "", "</details>", ""]
    out = REPORTS / "paper.md"
    tmp = out.with_suffix(".tmp")
    tmp.write_text("\n".join(lines) + "\n")
    os.replace(tmp, out)
    if not overrides:
        js = REPORTS / "paper.json"
        tmp = js.with_suffix(".tmp")
        tmp.write_text(json.dumps(summary, indent=1, sort_keys=True) + "\n")
        os.replace(tmp, js)
    return out, n_agree, len(crow)


def main(argv=None):
    from vibimpact.cli.common.args import parse_sets

    global REPORTS, FIGURES
    ap = smoke.parser(__doc__)
    ap.add_argument("--step", type=float, default=0.005)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--cache", default=str(ROOT / ".paper-cache"))
    ap.add_argument("--fresh", action="store_true", help="recompute cached sweeps")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="override a parameter of every preset (e.g. B=0.05)")
    ap.add_argument("--render-only", action="store_true",
                    help="render the report from the cached sweeps and transition types "
                    "and the census stored in reports/paper.json, computing nothing long "
                    "(a missing cache entry is an error) and redrawing no figure")
    args = ap.parse_args(argv)
    paper_sweeps.CACHE_ONLY = args.render_only
    if args.smoke is not None:  # coarse grid, fresh cache, outputs under the smoke dir
        REPORTS, FIGURES = args.smoke, args.smoke / "figures"
        REPORTS.mkdir(parents=True, exist_ok=True)
        args.step, args.cache, args.fresh = 0.1, str(args.smoke / "cache"), True
    overrides = parse_sets(args.set)
    t0 = time.perf_counter()
    data, cost = sweeps(args.step, args.cache, args.fresh, args.workers, overrides)
    types = transitions(data, args.step, args.cache, args.fresh, args.workers, overrides)
    panels = figures(data, draw=not args.render_only)
    if overrides:
        census = None
    elif args.render_only:
        census = cached_census(data, REPORTS / "paper.json")
    else:
        census = census_claims.section(data, args.cache, args.fresh, smoke_dir=args.smoke)
    out, k, n = report(data, cost, panels, args.step, time.perf_counter() - t0, overrides,
                       types, census, notes=args.smoke is None)
    print(f"{k}/{n} interval claims agree -> {out}")
    if not overrides:
        import readme_summary

        readme_summary.main([] if args.smoke is None else ["--smoke", str(args.smoke)])


if __name__ == "__main__":
    main()
