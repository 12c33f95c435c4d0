"""The paper's comparative and shape claims ("fig9 changes fig8 insignificantly", "the
rising part of the response curve in (0.97, 1.12)", ...), measured on the paper report's
sweeps.  Each row keeps its measured numbers, which ``paper.py`` stores in
``reports/paper.json`` for the checks of the hand-written notes (``paper_notes.py``).
"""
from __future__ import annotations

import numpy as np

from vibimpact.paper import claims as C


def _fmt_span(a, b):
    return "—" if not np.isfinite(a) else (f"{a:.3f}" if a == b else f"{a:.3f}–{b:.3f}")


def _curve_diff(a, b, var):
    """Largest |a - b| of a response variable over both directions (NaN-safe)."""
    d = np.abs(np.asarray(a[var].values, float) - np.asarray(b[var].values, float))
    return float(np.nanmax(d)) if np.isfinite(d).any() else float("nan")


def _label_agreement(a, b):
    la, lb = a["label"].values, b["label"].values
    return float(np.mean(la == lb))


def _irregular(ds):
    ok = []
    for d in ds["direction"].values:
        ok.append(C.match_points(ds.sel(direction=d), C.IRREGULAR))
    return np.array(ok)


def _irregular_spans(ds, direction="up"):
    sub = ds.sel(direction=direction)
    ok = C.match_points(sub, C.IRREGULAR)
    eta = sub["eta"].values
    return ", ".join(_fmt_span(eta[a], eta[b]) for a, b in C.runs(ok)) or "none"


#: the comparisons of two figures that the paper calls alike: (reference, compared, the
#: paper's words)
ALIKE = (("fig6", "fig7", "kh = 80: no considerable change from fig6"),
         ("fig8", "fig9", "Bh = 0.05: insignificant change from fig8"),
         ("fig11", "rr10", "Rr = 10: similar properties as fig11 (graphs not published)"))
#: criterion of "alike": largest response difference below this (the clearance is 1) ...
ALIKE_RESPONSE = 0.1
#: ... and the irregular motion overlapping (Jaccard) by at least this
ALIKE_CHAOS = 0.5


def comparative_rows(data):
    """The claims that compare figures or describe a curve's shape, measured.

    Returns
    -------
    list of tuple
        ``(figure, paper's words, measured (text), verdict, criterion, values)``;
        ``values`` holds the measured numbers (stored in ``paper.json``, read by the
        notes' checks).
    """
    rows = []
    f4 = data["fig4"]
    up = f4.sel(direction="up")
    hi = np.asarray(up["R_m"].values) >= 0.98
    eta_hi = up["eta"].values[hi]
    rise = float(np.ptp(up["X_m"].values[hi])) if hi.any() else float("nan")
    slope = rise / float(np.ptp(eta_hi)) if hi.sum() > 1 else float("nan")
    whirl = float(np.mean(up["contact"].values[hi] == 2)) if hi.any() else 0.0
    rows.append(("fig4", "upper branch almost horizontal: the mass circulating in the "
                 "central symmetric field",
                 f"upper branch (R_m ≥ 0.98, η {_fmt_span(*_span(up, hi))}): permanent-"
                 f"contact whirl at {whirl:.0%} of its points; X_m rises by {rise:.2f} "
                 f"(slope {slope:.2f} per unit η)",
                 "agree" if whirl >= 0.8 else "disagree",
                 "the upper branch is the circulating motion (permanent contact); its slope "
                 "is the growing Hertz penetration (soft contact, kh = 10)",
                 dict(whirl_share=whirl, rise=rise, slope=slope)))
    f5 = data["fig5"]
    dxy5 = _curve_diff(f5.assign(Y_m=f5["X_m"]), f5.assign(X_m=f5["Y_m"]), "X_m")
    rows.append(("fig5", "Y differs from X (G = 0.3)", f"max |X_m − Y_m| = {dxy5:.3f}",
                 "agree" if dxy5 > 0.05 else "disagree", "gravity shifts the orbit along +Y",
                 dict(max_xy_diff=dxy5)))
    a, b = _rising(f5.sel(direction="up"))
    ok = abs(a - 0.97) <= 0.02 and abs(b - 1.12) <= 0.02
    rows.append(("fig5", "rising part of the response curve in (0.97, 1.12)",
                 f"Y_m rises on the impacting branch over {_fmt_span(a, b)} (up sweep)",
                 "agree" if ok else "partly", "ends compared within 0.02",
                 dict(rise_start=a, rise_end=b)))
    for name in ("fig5", "fig6"):
        spans = _multi_spans(data[name], 1.1, 1.3)
        rows.append((name, "double line near η = 1.2" if name == "fig5" else
                     "double line gone",
                     f"motion other than P1 with a repeated orbit (Poincaré section "
                     f"multi-valued) in 1.1–1.3: {spans}",
                     "see note", "we read the paper's double line as a response that "
                     "is not a single closed curve (P2 or longer, QP); the report shows "
                     "the bifurcation diagram", dict(multi_spans=spans)))
    for x, y, text in ALIKE:
        A, B = data[x], data[y]
        d = max(_curve_diff(A, B, "X_m"), _curve_diff(A, B, "Y_m"))
        same = _label_agreement(A, B)
        ia, ib = _irregular(A), _irregular(B)
        jac = float((ia & ib).sum() / max((ia | ib).sum(), 1))
        rows.append((y, text, f"max |Δ response| = {d:.3f}; same label at {same:.0%} of the "
                     f"points; chaos overlap (Jaccard) {jac:.2f}; chaos in {y}: "
                     f"{_irregular_spans(B)} vs {x}: {_irregular_spans(A)}",
                     "agree" if d < ALIKE_RESPONSE and jac >= ALIKE_CHAOS else "partly",
                     f"response within {ALIKE_RESPONSE:g} clearance and chaos overlapping "
                     f"by {ALIKE_CHAOS:.0%}",
                     dict(max_response_diff=d, same_label=same, chaos_jaccard=jac)))
    return rows


def _span(sub, mask):
    eta = sub["eta"].values[mask]
    return (float(eta.min()), float(eta.max())) if eta.size else (np.nan, np.nan)


def _rising(sub):
    """The rising stretch of Y_m on the impacting branch around eta = 1 (up sweep)."""
    eta = sub["eta"].values
    y = np.asarray(sub["Y_m"].values, float)
    imp = np.asarray(sub["impacts_per_period"].values, float) > 0
    k0 = int(np.argmin(np.abs(eta - 1.03)))
    if not imp[k0]:
        return np.nan, np.nan
    a = b = k0
    while a > 0 and imp[a - 1] and y[a - 1] <= y[a] + 1e-3:
        a -= 1
    while b + 1 < eta.size and imp[b + 1] and y[b + 1] >= y[b] - 1e-3:
        b += 1
    return float(eta[a]), float(eta[b])


def _multi_spans(ds, lo, hi):
    out = []
    for d in ds["direction"].values:
        sub = ds.sel(direction=d)
        eta = sub["eta"].values
        per = sub["period"].values
        ok = (eta >= lo) & (eta <= hi) & (per != 1) & (sub["regime"].values != 4)
        spans = ", ".join(_fmt_span(eta[a], eta[b]) for a, b in C.runs(ok))
        out.append(f"{d}: {spans or 'none'}")
    return "; ".join(out)


