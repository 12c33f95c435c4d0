"""
Bifurcation diagram
===================

The stroboscopic (Poincaré) samples X and Y of every point of a sweep, against η, up and
down: one dot per sample for a periodic motion of period *n* gives *n* dots, a chaotic
or quasi-periodic one a cloud.  This is what ``vibimpact bifurcation`` draws.
"""

# %%
# A sweep that computes only the period and the Poincaré samples (what the bifurcation
# command asks for) runs faster than a full classification.

import vibimpact as vi
from vibimpact.plotting import plot_bifurcation

p = vi.presets.get("fig10")
eta = vi.grid("1.05:1.35:0.005")
ds = vi.sweep(p, eta, direction="both", analyses=("period", "poincare"))
print(vi.intervals(ds, direction="up").to_dataframe()[["start", "end", "label"]].to_string())

# %%
fig_bifurcation = plot_bifurcation(ds)

# %%
# Transitions between intervals
# -----------------------------
# :func:`vibimpact.transition_types` names what happens at each boundary of the interval
# map (grazing, period doubling, fold, ...); without ``refine`` it only names the type
# at the grid points, refining bisects every boundary in η.
tt = vi.transition_types(ds, p, refine=False, direction="up")
print(tt[["eta_from", "eta_to", "from_label", "to_label", "type"]].to_dataframe().to_string())
