"""
Simulate the rotor
==================

Simulations of the ``fig8`` preset: the rotor is brought onto the impacting branch by a
short continuation in the rotor speed η, then run at two speeds, where the paper reports
a periodic motion with two impacts at the bottom of the retainer (η = 1.185) and chaos
(η = 1.25).  The printed output below is what this model computes there.
"""

# %%
# Parameters
# ----------
# :func:`vibimpact.models.presets.get` returns a frozen, validated :class:`vibimpact.Params`;
# ``replace`` makes a changed copy.

import vibimpact as vi
from vibimpact.analysis import contact_arcs, detect_period, impact_count
from vibimpact.io import run_to_dataset
from vibimpact.plotting import plot_xy

p = vi.presets.get("fig8")
print(p)

# %%
# Reaching the impacting branch
# -----------------------------
# From rest the rotor may settle on the small impactless orbit.  The impacting orbit of
# the paper is reached by continuation, as a sweep does: each speed starts from the
# final state of the previous one.
state = None
for eta in vi.grid("1.0:1.18:0.02"):
    run = vi.simulate(p.replace(eta=eta), periods=1, transient=100, state0=state)
    state = run.final_state

# %%
# A periodic orbit with two impacts
# ---------------------------------
# ``strobe`` holds the stroboscopic samples at :math:`\tau_k = 2\pi k/\eta`, ``impacts``
# one record per contact (entry time, angle θ, impact speed, penetration, duration).
# ``dense`` keeps evenly spaced samples for the plot (the plot integrates again with
# finer samples when these are too coarse).  :func:`vibimpact.analysis.contact_arcs`
# of the run gives the loaded arcs of the retainer, each contact from entry to exit.
p1 = p.replace(eta=1.185)
run = vi.simulate(p1, periods=40, transient=400, state0=state, dense=100)
print(run.status, run.strobe.shape, len(run.impacts), "impacts")
n = detect_period(run.strobe, tol=1e-6)
print("period:", n)
print(impact_count(run.impacts["period"], len(run.strobe) - 1, period=max(n, 1)))
print(contact_arcs(run))

# %%
# :func:`vibimpact.plotting.plot_xy` draws the orbit in the clearance plane from the
# dataset of the run (:func:`vibimpact.io.run_to_dataset`); the bottom of the retainer
# (θ = +90°, along gravity) is at the bottom.
ax_periodic = plot_xy(run_to_dataset(run))

# %%
# Chaos with impacts on the whole circle
# --------------------------------------
state = run.final_state
for eta in vi.grid("1.19:1.24:0.01"):
    state = vi.simulate(p.replace(eta=eta), periods=1, transient=100,
                        state0=state).final_state
run2 = vi.simulate(p.replace(eta=1.25), periods=60, transient=200, state0=state, dense=200)
print("period:", detect_period(run2.strobe, tol=1e-6), "(0: none found)")
print(len(run2.impacts), "impacts, angles from", run2.impacts["theta"].min().round(1),
      "to", run2.impacts["theta"].max().round(1), "degrees")
ax_chaotic = plot_xy(run_to_dataset(run2))
