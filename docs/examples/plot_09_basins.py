"""
Basins of attraction and the basin entropy
==========================================

:func:`vibimpact.basins` colours every cell of a grid of starting states in a plane by
the attractor it reaches (an attractor census over the grid), and measures how tangled
the boundary is: the share of boundary cells, the basin entropy ``Sb`` and the boundary
basin entropy ``Sbb`` of Daza et al., Sci. Rep. 6, 31416 (2016), where ``Sbb > log 2``
shows a fractal boundary.  First the damped double-well Duffing oscillator, whose
boundary is the smooth stable manifold of its saddle, then the rotor of the paper at
fig11, eta = 1.06, where a P8 and a P14 orbit share the plane X, Y at rest.
"""

# %%
# The double well: two basins with a smooth boundary
# --------------------------------------------------
import matplotlib.pyplot as plt

import vibimpact as vi
from vibimpact.plotting.basins import plot_basins

p = vi.DuffingParams(delta=0.25, alpha=-1.0, beta=1.0, gamma=0.0, omega=1.0)
well = vi.basins(vi.System(p), grid=(60, 60), plane=("x", "x'"),
                 ranges=((-2, 2), (-2, 2)))
print(f"boundary cells {float(well.boundary_fraction):.3f}, Sb "
      f"{float(well.basin_entropy):.3f}, Sbb {float(well.boundary_basin_entropy):.3f}, "
      f"fractal by the log 2 criterion: {bool(well.fractal_by_log2)}")
fig, ax = plt.subplots(figsize=(6.5, 6.5), layout="constrained")
plot_basins(well, ax=ax)
plt.show()

# %%
# The rotor at fig11, eta = 1.06, X and Y at rest
# -----------------------------------------------
# A small grid here (24 x 24 cells); ``vibimpact basins --grid 200x200 --workers 2``
# draws the full figure.
rotor = vi.basins(vi.System(vi.presets.get("fig11")), 1.06, grid=(24, 24),
                  plane=("X", "Y"))
for a in range(rotor.sizes["attractor"]):
    print(f"{str(rotor.name.values[a]):32s} {float(rotor.fraction[a]):.3f} "
          f"+- {float(rotor.fraction_se[a]):.3f}")
print(f"boundary cells {float(rotor.boundary_fraction):.3f}, Sb "
      f"{float(rotor.basin_entropy):.3f}, Sbb {float(rotor.boundary_basin_entropy):.3f}")
fig, ax = plt.subplots(figsize=(6.5, 6.5), layout="constrained")
plot_basins(rotor, ax=ax)
plt.show()
