"""Outputs of the calibration: NetCDF dataset, landscape figure and Markdown report.

Every number of the report is computed here from the search's results; nothing is typed
by hand.  Files are written to a temporary name and renamed.
"""
from __future__ import annotations

import json
import os

import numpy as np

from calibrate_search import best_pair, damping_values, evaluate, is_interior

from vibimpact.paper import claims as C


def _atomic(path, write):
    tmp = path.with_name(path.name + ".tmp")
    write(tmp)
    os.replace(tmp, path)


def summary(reading, st, land):
    """The machine-readable result of one reading (its best pair and its search)."""
    B, E = best_pair(land)
    obj, count = land[(B, E)]
    presets = {}
    for f in reading.figures:
        d = damping_values(f.damp)
        d["B"] = 0.0 if f.b_zero else B
        presets[f.preset] = d
    bs = [b for b, _ in land]
    es = [e for _, e in land]
    return dict(reading=reading.key, text=reading.text, B=B, Ec=E, objective=obj,
                agree_count=count, claims=st["n_claims"], presets=presets,
                interior=is_interior(st["status"]), edge=st["status"],
                converged=st["converged"], refinements=st["refinements"],
                history=[round(h, 6) for h in st["history"]],
                B_range=[min(bs), max(bs)], Ec_range=[min(es), max(es)], pairs=len(land))


def save_dataset(path, readings, lands, rows, claims, attrs):
    """``calibration.nc``: every evaluated pair of every adoptable reading (dim ``pair``,
    per-claim scores) and of the per-figure readings (dim ``fig_pair``)."""
    import xarray as xr

    keys = [c.key for c in claims]
    adopt, fig = [], []
    for r in readings:
        for (B, E), (obj, n) in sorted(lands[r.key].items()):
            (adopt if r.adoptable else fig).append((r, B, E, obj, n))
    sc = np.full((len(adopt), len(keys)), np.nan)
    ag = np.zeros((len(adopt), len(keys)), dtype=np.int8)
    for i, (r, B, E, _, _) in enumerate(adopt):
        for f in r.figures:
            row = rows[(_variant(f), 0.0 if f.b_zero else B, E)]
            for j, c in enumerate(claims):
                if c.preset == f.preset:
                    sc[i, j] = row[c.key].score
                    ag[i, j] = row[c.key].agree
    ds = xr.Dataset(
        {"reading": ("pair", np.array([a[0].key for a in adopt], dtype=object)),
         "B": ("pair", np.array([a[1] for a in adopt])),
         "Ec": ("pair", np.array([a[2] for a in adopt])),
         "objective": ("pair", np.array([a[3] for a in adopt]),
                       dict(long_name="weighted mean of 1 - Jaccard over the claims")),
         "agree_count": ("pair", np.array([a[4] for a in adopt], dtype=np.int32),
                         dict(long_name="claims whose both ends agree")),
         "score": (("pair", "claim"), sc, dict(long_name="Jaccard index per claim")),
         "agree": (("pair", "claim"), ag, dict(long_name="1 where the claim agrees")),
         "fig_reading": ("fig_pair", np.array([a[0].key for a in fig], dtype=object)),
         "fig_B": ("fig_pair", np.array([a[1] for a in fig])),
         "fig_Ec": ("fig_pair", np.array([a[2] for a in fig])),
         "fig_objective": ("fig_pair", np.array([a[3] for a in fig])),
         "fig_agree_count": ("fig_pair", np.array([a[4] for a in fig], dtype=np.int32))},
        coords={"claim": keys}, attrs={**attrs, "claims_scoring": C.SCORING_VERSION})
    _atomic(path, lambda tmp: ds.to_netcdf(tmp, format="NETCDF4"))


def _variant(fig):
    from calibrate_search import variant

    return variant(fig.damp)


def _panel(fig, spec, land, title, best, vmax):
    """Two axes: a strip for B = 0 and the log-B axis, Ec upwards, colour = objective,
    the number = agreeing claims."""
    sub = spec.subgridspec(1, 2, width_ratios=(1, 6), wspace=0.08)
    a0 = fig.add_subplot(sub[0])
    a1 = fig.add_subplot(sub[1], sharey=a0)
    pts = np.array([(B, E, o, n) for (B, E), (o, n) in land.items()])
    sc = None
    for ax, sel in ((a0, pts[:, 0] == 0.0), (a1, pts[:, 0] > 0.0)):
        q = pts[sel]
        x = np.zeros(len(q)) if ax is a0 else q[:, 0]
        if len(q):
            sc = ax.scatter(x, q[:, 1], c=q[:, 2], cmap="viridis_r", vmin=0.0, vmax=vmax,
                            s=40, edgecolors="k", linewidths=0.3)
            for xx, yy, n in zip(x, q[:, 1], q[:, 3]):
                ax.annotate(f"{int(n)}", (xx, yy), textcoords="offset points",
                            xytext=(0, 4), ha="center", fontsize=5.5)
    B, E = best
    (a0 if B == 0.0 else a1).plot(0.0 if B == 0.0 else B, E, marker="*", ms=14,
                                  mfc="none", mec="r", mew=1.2)
    a0.set_xlim(-0.5, 0.5)
    a0.set_xticks([0.0], ["0"])
    a0.set_ylabel("Ec")
    a0.set_xlabel("B = 0")
    a1.set_xscale("log")
    a1.tick_params(labelleft=False)
    a1.set_xlabel("B (log axis)")
    a1.set_title(title, fontsize="small", loc="left")
    return sc


def plot_landscapes(path, panels):
    """Landscapes of the given readings, one panel each (B = 0 in its own strip).

    Parameters
    ----------
    panels : list of (title, land)
    """
    from matplotlib.figure import Figure

    from vibimpact.plotting import save_figure

    ncol = min(3, len(panels))
    nrow = -(-len(panels) // ncol)
    fig = Figure(figsize=(4.4 * ncol + 1.0, 3.3 * nrow + 0.6))
    gs = fig.add_gridspec(nrow, ncol, left=0.06, right=0.9, bottom=0.1, top=0.88,
                          wspace=0.25, hspace=0.55)
    vmax = max(max(o for o, _ in land.values()) for _, land in panels)
    sc = None
    for k, (title, land) in enumerate(panels):
        sc = _panel(fig, gs[k // ncol, k % ncol], land, title, best_pair(land),
                    max(vmax, 1e-9)) or sc
    fig.suptitle("calibration objective (colour; 0 = every claimed interval reproduced), "
                 "agreeing claims (numbers), best pair (star)", fontsize="medium")
    if sc is not None:
        fig.colorbar(sc, cax=fig.add_axes((0.92, 0.15, 0.012, 0.68)), label="objective")
    save_figure(fig, path, dpi=150)


def _fmt_pair(s):
    return f"B = {s['B']:g}, Ec = {s['Ec']:g}"


def _presets_line(s):
    parts = []
    for name, d in s["presets"].items():
        on = [k for k in ("Bh", "BT", "f") if d[k] > 0]
        parts.append(f"{name}: {{{', '.join(on)}}}" + (" at B = 0" if d["B"] == 0.0
                                                          and s["B"] != 0.0 else ""))
    return "; ".join(parts)


def _status_text(s):
    e = s["edge"]
    where = []
    for k in ("B", "Ec"):
        where.append(f"{k} {'at the bound B = 0' if e[k] == 'zero' else e[k]}")
    return ", ".join(where)


def readings_table(summaries):
    """Markdown table of the readings' best pairs, in rank order."""
    head = ("| rank | reading | dampings | best B | best Ec | objective | agree | "
            "optimum | refinements | converged | searched B | searched Ec |")
    lines = [head, "|" + " --- |" * 12]
    for k, s in enumerate(summaries, 1):
        lines.append(
            f"| {k} | {s['reading']} | {_presets_line(s)} | {s['B']:g} | {s['Ec']:g} | "
            f"{s['objective']:.3f} | {s['agree_count']}/{s['claims']} | "
            f"{_status_text(s)} | {s['refinements']} | "
            f"{'yes' if s['converged'] else 'no'} | {s['B_range'][0]:g}–"
            f"{s['B_range'][1]:g} | {s['Ec_range'][0]:g}–{s['Ec_range'][1]:g} |")
    return "\n".join(lines)


def pairs_table(reading, land, rows, claims, top=10):
    """Per-claim cells of the ``top`` best pairs of ``reading``."""
    keys = [c for c in claims if c.preset in {f.preset for f in reading.figures}]
    head = "| B | Ec | objective | agree | " + " | ".join(c.key for c in keys) + " |"
    lines = [head, "|" + " --- |" * (4 + len(keys))]
    ranked = sorted(land, key=lambda pr: (land[pr][0], -land[pr][1]))[:top]
    figs = {f.preset: f for f in reading.figures}
    for B, E in ranked:
        cells = []
        for c in keys:
            f = figs[c.preset]
            r = rows[(_variant(f), 0.0 if f.b_zero else B, E)][c.key]
            span = "—" if not np.isfinite(r.start) else f"{r.start:.3f}–{r.end:.3f}"
            cells.append(f"{r.score:.2f} ({span}{' ✓' if r.agree else ''})")
        o, n = land[(B, E)]
        lines.append(f"| {B:g} | {E:g} | {o:.3f} | {n} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def per_figure_section(fig_summaries, readings, win, rows, claims, b_step, ec_step):
    """(d): each figure's own best pair against the winner's, and what that says."""
    lines = ["| figure | own best B | own best Ec | objective | agree | at the winner's "
             "(B, Ec): objective | agree |", "|" + " --- |" * 7]
    by_key = {r.key: r for r in readings}
    for s in fig_summaries:
        at = evaluate(by_key[s["reading"]], win["B"], win["Ec"], rows, claims)
        at_txt = ("—", "—") if at is None else (f"{at[0]:.3f}", f"{at[1]}/{s['claims']}")
        lines.append(f"| {s['reading'].split(':', 1)[1]} | {s['B']:g} | {s['Ec']:g} | "
                     f"{s['objective']:.3f} | {s['agree_count']}/{s['claims']} | "
                     f"{at_txt[0]} | {at_txt[1]} |")
    # a figure that scores nothing anywhere has no best pair to compare
    blank = [s["reading"].split(":", 1)[1] for s in fig_summaries if s["objective"] >= 1.0]
    scored = [s for s in fig_summaries if s["objective"] < 1.0]
    bs = [s["B"] for s in scored]
    es = [s["Ec"] for s in scored]

    def close(a, b):
        if a == 0.0 or b == 0.0:
            return a == b
        return max(a, b) / min(a, b) <= b_step * (1 + 1e-9)

    same = all(close(a, b) for a in bs for b in bs) and \
        (not es or max(es) - min(es) <= ec_step * (1 + 1e-9))
    own = sum(s["agree_count"] for s in fig_summaries)
    total = sum(s["claims"] for s in fig_summaries)
    text = (f"Each figure at its own best pair reproduces {own} of its {total} claims "
            f"together; the winner's common pair reproduces {win['agree_count']}.  ")
    if blank:
        text += (f"{', '.join(blank)} reproduce{'s' if len(blank) == 1 else ''} no claim "
                 "at any searched pair (objective 1): no best pair to compare.  ")
    if len(scored) < 2:
        text += "Fewer than two figures score anywhere: the comparison says nothing."
    elif same:
        text += ("The figures want the same (B, Ec) within one coarse grid step "
                 f"(B within a factor {b_step:.3g}, Ec within {ec_step:g}): a common pair "
                 "costs little, so what the fit misses is a limit of the model (or of the "
                 "claims' reading), not of parameters the paper leaves unstated.")
    else:
        text += ("The figures want different (B, Ec) (more than one coarse grid step "
                 f"apart: B by a factor over {b_step:.3g} or Ec by over {ec_step:g}): "
                 "part of the misfit may come from parameters the paper does not state "
                 "differing between its figures, not only from the model.")
    return "\n".join(lines), text


def write_markdown(path, text):
    """Write ``text`` to ``path`` atomically."""
    _atomic(path, lambda tmp: tmp.write_text(text))


def winner_json(win):
    """The JSON block that states the winning reading and pair (for the adoption)."""
    keys = ("reading", "text", "B", "Ec", "objective", "agree_count", "claims",
            "interior", "converged", "refinements", "presets")
    return json.dumps({k: win[k] for k in keys}, indent=1)

