"""
A turning retainer ring
=======================

The paper's eq. (5) treats the retainer as a ring at rest; its retainer is a ball bearing
whose inner ring turns after oblique impacts.  The model ``"ring"`` adds the ring's
surface speed ``Vr`` as a fifth state (:ref:`guide-ring`, derivation in
:ref:`model-ring`).  Here the paper's fig. 11 (friction f = 0.05) is swept with the ring
held (eq. (5), preset ``fig11``) and with a light turning ring (``fig11-ring``), on a
coarse grid: the response curves side by side, then the ring's speed against η.
"""

# %%
# Two sweeps on the same grid, up in η, each point continued from the previous one.  The
# period, the impacts, the amplitudes, the Poincaré samples and the Lyapunov exponent
# (which tells chaos from a motion still settling) are computed; the 0-1 test and the
# Floquet multipliers are left out, which keeps the example short.
import matplotlib.pyplot as plt
import numpy as np

import vibimpact as vi
from vibimpact.plotting import plot_bifurcation

eta = vi.grid("0.9:1.5:0.01")
analyses = ("period", "impacts", "response", "poincare", "lyapunov")
held = vi.sweep(vi.presets.get("fig11"), eta, analyses=analyses)
ring = vi.sweep(vi.presets.get("fig11-ring"), eta, analyses=analyses)
print(vi.intervals(ring).to_dataframe()[["start", "end", "label"]].to_string())

# %%
# Response curves
# ---------------
# The largest horizontal and vertical displacements X_m, Y_m (in clearances) at every η:
# the ring at rest (eq. (5)) in grey, the turning ring in blue.
fig, axes = plt.subplots(2, 1, figsize=(7, 5.5), sharex=True)
for ax, var in zip(axes, ("X_m", "Y_m")):
    ax.plot(eta, held[var], ".-", color="0.55", ms=3, lw=0.8, label="fig11 (ring at rest)")
    ax.plot(eta, ring[var], ".-", color="tab:blue", ms=3, lw=0.8,
            label="fig11-ring (turning ring)")
    ax.set_ylabel(var)
    ax.grid(True, alpha=0.4)
axes[0].legend(fontsize="small")
axes[-1].set_xlabel("η")
fig.tight_layout()

# %%
# The ring's speed
# ----------------
# The Poincaré samples of ``Vr`` against η: what ``vibimpact plot sweep.nc --kind
# bifurcation --state Vr`` draws.  ``Vr`` is the ring's inner-surface speed in the units
# of X' (positive in the rotor's sense of rotation); the contact's friction drags it
# towards the speed of the shaft's surface at the contact, so a periodic motion shows
# one value per forcing period and the ring's speed grows with the whirl.  Where the
# rotor never touches the ring, the ring's bearing has stopped it: ``Vr = 0``.
fig_vr = plot_bifurcation(ring, states="Vr")

# %%
# How close the ring comes to rolling: at every point the slip velocity at the end of
# the point, ``L/R + Rr η - Vr`` (``L = X Y' - Y X'``), is the speed of the shaft's
# surface relative to the ring's.  It is only defined in contact; here it is printed for
# the points whose last state touches the retainer.
X, Y, dX, dY, Vr = (ring["final_state"].sel(state=s).values for s in ("X", "Y", "dX",
                                                                        "dY", "Vr"))
R = np.hypot(X, Y)
slip = (X * dY - Y * dX) / R + vi.presets.get("fig11-ring").Rr * eta - Vr
touching = R >= 1.0
print(f"{touching.sum()} of {eta.size} points end in contact; their slip velocity "
      f"ranges over [{slip[touching].min():.3g}, {slip[touching].max():.3g}], "
      f"their Vr over [{Vr[touching].min():.3g}, {Vr[touching].max():.3g}]")
