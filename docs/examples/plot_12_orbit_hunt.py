"""
Hunting periodic orbits, stable or not
======================================

A sweep or a census sees attractors only.  :func:`vibimpact.hunt_orbits` looks for the
periodic orbits of the stroboscopic map themselves, stable or not, by Newton shooting
from many starts: the close returns of short trajectories from random states (and from
states you give).  Every orbit gets its minimal period, impacts per period, contact
arcs and Floquet multipliers, and is continued in the forcing frequency to the interval
where it exists and the one where it is stable.
"""

# %%
# The saddles inside a chaotic attractor
# --------------------------------------
# The forced double-well Duffing oscillator at ``gamma = 0.3`` is chaotic; its periodic
# orbits are all unstable, embedded in the attractor.
import vibimpact as vi
from vibimpact.orbits import find_orbit, hunt_to_dataset
from vibimpact.plotting.orbits import plot_orbits

duffing = vi.DuffingParams(gamma=0.3)
hunt = vi.hunt_orbits(duffing, periods=[1, 2, 3], random=8, seed=0)
print("\n".join(hunt.table()))
plot_orbits(hunt_to_dataset(hunt, vi.System(duffing)))

# %%
# Coexisting orbits of the rotor at fig11, eta = 1.06
# ---------------------------------------------------
# Random simulations settle here on a P8 with 11 impacts or a P14 with 21.  The hunt
# finds both (and whatever unstable orbits of these periods its seeds lead to); each
# orbit's bar shows where it exists (solid: stable, dashed: unstable) within +-0.005 of
# the hunt's eta.
p = vi.presets.get("fig11").replace(eta=1.06)
hunt = vi.hunt_orbits(p, periods=[6, 8, 14], random=12, seed=0, window=0.005)
print("\n".join(hunt.table()))
ds = hunt_to_dataset(hunt, vi.System(p))
plot_orbits(ds)

# %%
# Asking the dataset
# ------------------
# The paper reports a period 6 with 8 bottom impacts on 1.05-1.07 at fig11.
# :func:`vibimpact.orbits.find_orbit` answers with the evidence either way: the
# matches and where they hold, or what was found instead.
print(find_orbit(ds, period=6, impacts=8, stable=True, arcs="bottom", within=(1.05, 1.07)))
print(find_orbit(ds, period=8, impacts=11, stable=True, within=(1.05, 1.07)))
