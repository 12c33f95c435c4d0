"""Calibrate B and Ec (not stated in the paper) against the paper's interval claims.

The objective of a pair (B, Ec) is the weighted mean, over the paper's interval claims
of figs 8, 10 and 11 (``vibimpact.paper.claims.CLAIMS``), of one minus the Jaccard index
between the claimed grid points and those our sweep labels with the claimed kind of
motion (:func:`vibimpact.paper.claims.claim_score`); beside it the plain count of claims that
agree (both ends within one sweep step).  Each figure is an up-and-down sweep of the fig8
rotor with its contact dampings, on ``eta = 0.9 : 1.5 : STEP`` with pure continuation and
only the analyses the claims need; the sweeps are rows of the map engine
(:func:`vibimpact.map2d`, B varied along a map's rows) on one Dask cluster, cached by a
hash of the package's sources (``analyses/paper/calibrate_engine.py``).

The paper's text can be read several ways (``analyses/paper/calibrate_search.py``): (a) one
contact damping per figure, (b) fig11 at B = 0, (c) any superset of the damping a figure
names, (d) each figure alone.  Every reading starts on the coarse grid (B = 0 and B
log-spaced over 0.001-0.1, Ec over 0.02-0.15); the leading readings are refined around
their best pair, the grid extended outward where the best lies on its edge, until the
best is interior and a refinement changes the objective by less than 0.01.  The reading
whose converged optimum reproduces most claims (then: least objective) wins.

Writes ``OUT/calibration.md``, ``OUT/calibration.nc`` and ``OUT/figures/calibration.png``.

Usage::

    python analyses/paper/calibrate.py                 # full search, 2 processes, reports/
    python analyses/paper/calibrate.py --quick         # smoke run into .calibration-cache/quick
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import calibrate_report as R  # noqa: E402
import calibrate_search as S  # noqa: E402
from calibrate_engine import Engine, code_hash, eta_grid, local_client  # noqa: E402

import vibimpact as vi  # noqa: E402
from vibimpact.paper import claims as C  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
REPORTS = ROOT / "reports"
#: refined readings of kind (c) besides (a), (b) and (d): the best few by rank
N_CONTENDERS = 3


def _contenders(readings, lands, n):
    """Readings refined this round: every (a), (b), (d) and the best ``n`` of (c)."""
    def key(r):
        o, c = lands[r.key][S.best_pair(lands[r.key])]
        return S.rank_key(o, c)

    cs = sorted((r for r in readings if r.kind == "c"), key=key)[:n]
    return [r for r in readings if r.kind != "c" or r in cs]


def search(engine, readings, coarse_b, coarse_ec, max_iter=S.MAX_ITER, tol=S.TOL,
           n_contenders=N_CONTENDERS, ec_step=None, log=print):
    """Coarse grid for every reading, then refinements of the leading ones.

    Returns
    -------
    lands : dict
        Reading key -> landscape ``{(B, Ec): (objective, count)}``.
    state : dict
        Reading key -> ``history`` (best objective per stage), ``refinements``,
        ``status`` (:func:`calibrate_search.edge_status`), ``converged``, ``n_claims``.
    """
    claims = engine.claims
    ec_step = ec_step or (coarse_ec[1] - coarse_ec[0])
    b_factor = coarse_b[2] / coarse_b[1]
    pairs = {r.key: {(B, E) for B in coarse_b for E in coarse_ec} for r in readings}
    engine.ensure(set().union(*(S.rows_needed(r, pairs[r.key]) for r in readings)))
    lands, state = {}, {}
    for r in readings:
        land = lands[r.key] = S.landscape(r, pairs[r.key], engine.rows, claims)
        best = S.best_pair(land)
        state[r.key] = dict(history=[land[best][0]], refinements=0, converged=False,
                            status=S.edge_status(land, best),
                            n_claims=sum(c.preset in {f.preset for f in r.figures}
                                         for c in claims))
    log(f"\ncoarse grid: {len(engine.rows)} rows")
    for it in range(1, 2 * max_iter + 1):  # a late leader still gets its refinements
        active = [r for r in _contenders(readings, lands, n_contenders)
                  if not state[r.key]["converged"] and state[r.key]["refinements"] < max_iter]
        props = {r.key: S.propose(lands[r.key], b_factor=b_factor, ec_step=ec_step)
                 for r in active}
        active = [r for r in active if props[r.key]]
        if not active:
            break
        engine.ensure(set().union(*(S.rows_needed(r, props[r.key]) for r in active)))
        for r in active:
            pairs[r.key] |= set(props[r.key])
            land = lands[r.key] = S.landscape(r, pairs[r.key], engine.rows, claims)
            st = state[r.key]
            best = S.best_pair(land)
            st["history"].append(land[best][0])
            st["refinements"] += 1
            st["status"] = S.edge_status(land, best)
            st["converged"] = S.converged(st["history"], st["status"], tol)
        log(f"\nround {it}: " + ", ".join(
            f"{r.key} {state[r.key]['history'][-1]:.3f}"
            f"{' converged' if state[r.key]['converged'] else ''}" for r in active))
    return lands, state


def _client(args):
    if args.scheduler:
        from vibimpact.engine.cluster import connect

        client, _ = connect(args.scheduler)
        return client, None
    if args.workers > 1:
        return local_client(args.workers)
    return None, None


def main(argv=None):
    """Command line: run the search and write the report, dataset and figure."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--step", type=float, default=0.005, help="eta step of the sweeps")
    ap.add_argument("--workers", type=int, default=2, help="local worker processes")
    ap.add_argument("--scheduler", default=None,
                    help="a Dask scheduler address or file instead of local workers")
    ap.add_argument("--cache", default=str(ROOT / ".calibration-cache"),
                    help="directory for the rows (reused by later runs of the same code)")
    ap.add_argument("--out", default=None,
                    help="output directory (default reports/, with --quick "
                         ".calibration-cache/quick)")
    ap.add_argument("--max-iter", type=int, default=S.MAX_ITER, help="refinements at most")
    ap.add_argument("--quick", action="store_true",
                    help="smoke run: 3 x 2 coarse pairs, eta step 0.05, one refinement")
    ap.add_argument("--smoke", metavar="DIR", type=Path, default=None,
                    help="--quick on a 3-point eta grid (step 0.3) with one worker, its "
                         "cache and outputs under DIR (tests/test_analyses_smoke.py)")
    args = ap.parse_args(argv)
    if args.smoke is not None:
        args.quick, args.workers, args.out = True, 1, str(args.smoke)
        args.cache = str(args.smoke / "cache")
        argv = [*(argv if argv is not None else sys.argv[1:]), "--step", "0.3"]
        args.step = 0.3
    out = Path(args.out) if args.out else (
        Path(args.cache) / "quick" if args.quick else REPORTS)
    chash = code_hash(ROOT)
    cache = Path(args.cache) / chash
    if args.quick:
        coarse_b, coarse_ec, step, max_iter = (0.0, 0.01, 0.1), (0.06, 0.12), 0.05, 1
        n_cont = 1
        if "--step" in (argv if argv is not None else sys.argv):
            step = args.step
    else:
        coarse_b, coarse_ec, step = S.COARSE_B, S.COARSE_EC, args.step
        max_iter, n_cont = args.max_iter, N_CONTENDERS
    t0 = time.perf_counter()
    client, cluster = _client(args)
    try:
        engine = Engine(eta_grid(step), cache, scheduler=client)
        readings = S.readings()
        lands, state = search(engine, readings, coarse_b, coarse_ec, max_iter=max_iter,
                              n_contenders=n_cont, ec_step=S.COARSE_EC[1] - S.COARSE_EC[0],
                              log=lambda m: print(m, file=sys.stderr, flush=True))
        from vibimpact.models.params import DEFAULT_B, DEFAULT_EC

        ra = readings[0]
        engine.ensure(S.rows_needed(ra, [(DEFAULT_B, DEFAULT_EC)]))
        defaults = S.evaluate(ra, DEFAULT_B, DEFAULT_EC, engine.rows, engine.claims)
        win = rank_readings(readings, lands, state)[0][0]
        # each figure alone at the winner's pair, for the comparison of (d)
        engine.ensure(set().union(*(S.rows_needed(r, [(win["B"], win["Ec"])])
                                    for r in readings if r.kind == "d")))
    finally:
        if client is not None and cluster is not None:
            client.close()
            cluster.close()
    elapsed = time.perf_counter() - t0
    write_outputs(out, readings, lands, state, engine, defaults, step, elapsed, args,
                  chash, coarse_b, coarse_ec)


def rank_readings(readings, lands, state):
    """Summaries of the adoptable readings, best first (:func:`calibrate_search.rank_key`
    at each one's best pair), and of the per-figure readings (d)."""
    sums = {r.key: R.summary(r, state[r.key], lands[r.key]) for r in readings}
    adopt = sorted((sums[r.key] for r in readings if r.adoptable),
                   key=lambda s: S.rank_key(s["objective"], s["agree_count"]))
    return adopt, [sums[r.key] for r in readings if r.kind == "d"]


def write_outputs(out, readings, lands, state, engine, defaults, step, elapsed, args,
                  chash, coarse_b, coarse_ec):
    """Write the report, the dataset and the figure into ``out``."""
    from vibimpact.models.params import DEFAULT_B, DEFAULT_EC

    (out / "figures").mkdir(parents=True, exist_ok=True)
    by_key = {r.key: r for r in readings}
    adopt, figs = rank_readings(readings, lands, state)
    win = adopt[0]
    by_obj = min(adopt, key=lambda s: (s["objective"], -s["agree_count"]))
    attrs = dict(title="vibimpact calibration of B and Ec against the paper's claims",
                 source=f"vibimpact {vi.__version__}, analyses/paper/calibrate.py",
                 code_hash=chash, eta_step=step, winner=R.winner_json(win))
    R.save_dataset(out / "calibration.nc", readings, lands, engine.rows, engine.claims,
                   attrs)
    panel_keys = ["a", "b"] + ([win["reading"]] if win["reading"] not in ("a", "b") else [])
    panel_keys += [r.key for r in readings if r.kind == "d"]
    R.plot_landscapes(out / "figures" / "calibration.png",
                      [(S.title(by_key[k]), lands[k]) for k in panel_keys])
    b_step = coarse_b[2] / coarse_b[1]
    ec_step = coarse_ec[1] - coarse_ec[0]
    fig_table, fig_text = R.per_figure_section(figs, readings, win, engine.rows,
                                               engine.claims, b_step, ec_step)
    ok = win["converged"] and win["interior"]
    verdict = (f"**Winner: reading ({win['reading']}) — {win['text']} — at B = "
               f"{win['B']:g}, Ec = {win['Ec']:g}: {win['agree_count']} of "
               f"{win['claims']} claims agree, objective {win['objective']:.3f}.**  ")
    if ok:
        verdict += ("Its optimum is interior in B and Ec and converged (the last "
                    f"refinement changed the objective by less than {S.TOL:g}): these are "
                    "the values and contact dampings to adopt as the presets' defaults.")
    else:
        verdict += ("**Its optimum is "
                    + ("not interior" if not win["interior"] else "interior")
                    + (" and has not converged" if not win["converged"] else "")
                    + f" ({R._status_text(win)}, {win['refinements']} refinements, "
                    "objective history " + ", ".join(f"{h:.3f}" for h in win["history"])
                    + "): do not adopt it as it stands.**")
    if by_obj["reading"] != win["reading"]:
        verdict += (f"  By the objective alone reading ({by_obj['reading']}) would lead "
                    f"({by_obj['objective']:.3f} at {R._fmt_pair(by_obj)}, "
                    f"{by_obj['agree_count']} claims agree).")
    quick = " --quick" if args.quick else ""
    text = [
        "# Calibration of B and Ec against the paper's claims", "",
        f"Generated by `python analyses/paper/calibrate.py{quick}` (vibimpact {vi.__version__}, "
        f"sources {chash}): {len(readings)} readings, up and down sweeps on eta = "
        f"0.9:1.5:{step:g} run as rows of the map engine; this run computed "
        f"{engine.stats['computed']} rows and reused {engine.stats['cached']} from the "
        f"cache in {elapsed / 60:.1f} min on "
        + (f"the Dask scheduler {args.scheduler}" if args.scheduler
           else f"{args.workers} process{'es' if args.workers > 1 else ''}") + ".", "",
        "The paper states neither B (damping of the magnetic support) nor Ec (unbalance).  "
        "The objective is the weighted mean of 1 − Jaccard(claimed, detected grid points) "
        "over the interval claims of figs 8, 10 and 11 (`vibimpact/paper/claims.py`; 0 means "
        "every claimed interval is reproduced point for point; a claimed P-n window, "
        "n ≥ 2, found with another period earns half its Jaccard score); *agree* counts "
        "the claims whose detected interval has both ends within one sweep step of the "
        f"paper's (a claim \"near η\": start within {C.NEAR:g}).  Readings are ranked by "
        "agree, "
        "then by the objective.", "",
        f"Search: the coarse grid ({coarse_text(coarse_b, coarse_ec)}) for every reading; "
        "then, round by round, every reading of kinds (a), (b), (d) and the best "
        f"{N_CONTENDERS if not args.quick else 1} of (c) by rank at that round (each "
        f"reading at most {args.max_iter if not args.quick else 1} refinements) are refined "
        "around their best pair (geometric midpoints in B, arithmetic in Ec, "
        "B = 0 its own candidate) and the grid extended outward where the best lies on "
        "its edge.  A reading has converged when its best pair is interior (B = 0 counts "
        f"as interior: it is the bound of B) and a refinement changed its best objective "
        f"by less than {S.TOL:g}.", "",
        verdict, "",
        "```json", R.winner_json(win), "```", "",
        f"The presets' defaults (`vibimpact.models.params`: B = {DEFAULT_B:g}, Ec = "
        f"{DEFAULT_EC:g}) under reading (a): objective {defaults[0]:.3f}, "
        f"{defaults[1]} of {win['claims']} claims agree.", "",
        "![landscapes](figures/calibration.png)", "",
        "## Readings of the paper's text, best first", "",
        "(a) one contact damping at a time on top of fig8 (the presets today); (b) as (a) "
        "with fig11 at B = 0 (\"only dry friction damped the motion\"); (c) fig10 and "
        "fig11 with any set of contact dampings containing the one the paper names (each "
        f"{S.CONTACT_ON:g} when on; the key names fig10's set | fig11's set).  \"optimum\" "
        "says where the best pair lies in the searched grid.", "",
        R.readings_table(adopt), "",
        "## (d) Each figure alone (dampings of (a))", "",
        fig_table, "", fig_text, "",
        f"## Best pairs of the winner, reading ({win['reading']})", "",
        "Each cell: the claim's Jaccard score, the detected interval of the best "
        "direction, ✓ where the claim agrees.", "",
        R.pairs_table(by_key[win["reading"]], lands[win["reading"]], engine.rows,
                      engine.claims), "",
        "```json",
        json.dumps(dict(rows=len(engine.rows), computed=engine.stats["computed"],
                        cached=engine.stats["cached"], step=step,
                        seconds=round(elapsed, 1), code_hash=chash), indent=1),
        "```", ""]
    R.write_markdown(out / "calibration.md", "\n".join(text))
    print(f"winner ({win['reading']}) B={win['B']:g} Ec={win['Ec']:g} "
          f"objective={win['objective']:.3f} agree={win['agree_count']}/{win['claims']} "
          f"converged={win['converged']} ({elapsed:.0f} s) -> {out / 'calibration.md'}")


def coarse_text(coarse_b, coarse_ec):
    """The coarse grid in words."""
    pos = [b for b in coarse_b if b > 0]
    return (("B = 0 and " if 0.0 in coarse_b else "") + f"{len(pos)} values of B "
            f"log-spaced over {pos[0]:g}–{pos[-1]:g}, {len(coarse_ec)} values of Ec over "
            f"{coarse_ec[0]:g}–{coarse_ec[-1]:g}")


if __name__ == "__main__":
    main()
