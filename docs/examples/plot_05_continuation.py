"""
Continuation of periodic orbits
===============================

A sweep follows attractors only.  :func:`vibimpact.analysis.continue_orbit` follows a
periodic orbit by pseudo-arclength continuation, through folds and onto its unstable
parts, with the orbit's Floquet multipliers at every point.  Here: the forced response of
a hardening Duffing oscillator, the built-in second model, and the impacting period-1
orbit of the rotor.
"""

# %%
# Round the folds of a Duffing oscillator
# ---------------------------------------
import matplotlib.pyplot as plt
import numpy as np

import vibimpact as vi
from vibimpact.analysis import Steps, continue_orbit, locate_bifurcation
from vibimpact.plotting.branch import plot_branch

p = vi.DuffingParams(delta=0.1, alpha=1.0, beta=0.05, gamma=0.5, omega=0.8)
start = vi.simulate(p, periods=1, transient=400).final_state
branch = continue_orbit(vi.System(p), start, param="omega", stop=(0.8, 1.6),
                        steps=Steps(ds=0.02, ds_max=0.05))
for i, kind, value in branch.bifurcations:
    print(f"{kind} at omega = {value:.4f}")

fig, ax = plt.subplots(figsize=(6, 4))
plot_branch(ax, branch, "x_m", label="period 1")
ax.set_xlabel("omega")
ax.set_ylabel("x_m")
ax.legend()

# %%
# Where a rotor orbit loses stability
# -----------------------------------
# The impacting period-1 orbit of ``fig8`` (two impacts at the bottom), found by a short
# continuation from rest, followed up in η.  Where its largest Floquet multiplier
# leaves the unit circle the orbit loses stability: compare with the intervals of the
# sweep in :ref:`the sweep example <sphx_glr_auto_examples_plot_02_sweep_intervals.py>`.
rotor = vi.presets.get("fig8")
state = None
for eta in vi.grid("1.0:1.14:0.02"):
    state = vi.simulate(rotor.replace(eta=eta), periods=1, transient=100,
                        state0=state).final_state
system = vi.System(rotor.replace(eta=1.15))
state = system.simulate(periods=1, transient=300, state0=state).final_state
rbranch = continue_orbit(system, state, param="eta", stop=1.25,
                         steps=Steps(ds=0.01, ds_max=0.02, max_points=20))
mu = np.abs(rbranch.multipliers).max(axis=1)
for eta, m, stable in zip(rbranch.values, mu, rbranch.stable):
    print(f"eta = {eta:.4f}  |mu|max = {m:.4f}  {'stable' if stable else 'unstable'}")
print(rbranch.bifurcations)

fig2, ax2 = plt.subplots(figsize=(6, 4))
plot_branch(ax2, rbranch, "Y_m", label="P1, impacting")
ax2.set_xlabel("eta")
ax2.set_ylabel("Y_m")
ax2.legend()
