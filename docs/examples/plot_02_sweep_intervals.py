"""
Sweep the rotor speed and label the intervals
=============================================

:func:`vibimpact.sweep` classifies every point of a grid of rotor speeds η, with
continuation: inside each of the grid's blocks (16 by default, each seeded by a short
serial pass) every point starts from the previous point's final state, so hysteresis and
jumps show as in the paper.  :func:`vibimpact.intervals` turns the labels into a
frequency-interval map.
"""

# %%
# The sweep
# ---------
# A short grid of the ``fig8`` preset, up and down.  The dataset holds, per point, the
# regime, period, impacts per period, largest Lyapunov exponent, Floquet multipliers,
# response maxima, contact arcs and Poincaré samples.

import vibimpact as vi
from vibimpact.plotting import plot_intervals, plot_response

p = vi.presets.get("fig8")
eta = vi.grid("1.0:1.32:0.01")
ds = vi.sweep(p, eta, direction="both")
print(ds[["regime", "period", "impacts_per_period", "lyapunov", "X_m", "Y_m"]])

# %%
# Intervals and labels
# --------------------
# Consecutive points with the same label — kind of motion, period, impacts per period,
# loaded arcs of the retainer — form one interval.
iv = vi.intervals(ds)
print(iv.to_dataframe()[["direction", "start", "end", "label"]].to_string())

# %%
# One point on its own
# --------------------
# :func:`vibimpact.classify_params` runs the sweeps' point pipeline on one parameter
# point of a :class:`vibimpact.System`, here from the final state the up sweep reached
# at the previous grid point.
system = vi.System(p.replace(eta=1.25))
start = ds.final_state.sel(direction="up", eta=1.24).values
regime, point = vi.classify_params(system, start)
print(regime)

# %%
# Response curves with the regimes as bands
# -----------------------------------------
fig_response = plot_response(ds)

# %%
# The interval map of both directions
# -----------------------------------
fig_intervals = plot_intervals(ds)
