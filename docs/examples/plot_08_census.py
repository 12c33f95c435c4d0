"""
Attractor census
================

At one rotor speed several attractors can coexist; a sweep shows the one its
continuation reaches.  :func:`vibimpact.attractors` integrates many starting states,
each only until it is known which attractor it reaches, and gives every attractor its
basin fraction with a standard error.
"""

# %%
# fig11 at η = 1.06: two periodic orbits share the starting states about equally.
import vibimpact as vi
from vibimpact.census.dataset import attractor_table
from vibimpact.plotting.census import plot_census

system = vi.System(vi.presets.get("fig11"))
census = vi.attractors(system.with_params(eta=1.06), starts=200)
for index, gid, name, fraction, se, period, extra in attractor_table(census):
    print(f"A{gid}: {name:35s} {fraction:.3f} +- {se:.3f}  {extra}")

# %%
# How each start was decided: most entered an attractor found by an earlier start and
# stopped there; the settling evidence decided the others (the 16 of the first round
# among them).
import numpy as np

print("entered a known attractor:", int((census.decided_by == 0).sum()),
      "of", census.sizes["start"])
print("median forcing periods per start:", float(np.median(census.periods)))

# %%
# Over a few speeds the attractors are matched from one η to the next (``global_id``):
# the figure stacks the basin fractions above each attractor's own bifurcation diagram.
grid = vi.attractors(system, eta=[1.05, 1.06], starts=60)
fig_census = plot_census(grid)
