"""
A parameter map
===============

:func:`vibimpact.map2d` runs one η sweep per value of a second parameter — here the
Hertz contact stiffness ``kh`` — and shows how the regimes move.  Rows are independent
and run as tasks on Dask when ``workers > 1`` or a scheduler is given; this small map runs
serially in this process.
"""

# %%
import tempfile
from pathlib import Path


import vibimpact as vi
from vibimpact.maps import open_map, write_map
from vibimpact.plotting.map2d import plot_map

p = vi.presets.get("fig8")
eta = vi.grid("1.0:1.32:0.02")
ds = vi.map2d(p, eta, vary={"kh": [40.0, 80.0, 120.0]})
print(ds.period.to_pandas())

# %%
# A row of the map is an ordinary sweep dataset:
for kh in ds.kh.values:
    print(f"kh = {kh:g}")
    print(vi.intervals(ds.sel(kh=kh)).to_dataframe()[["start", "end", "label"]].to_string())

# %%
# Four panels over (η, ``kh``): regime, period, impacts per period and the largest
# exponent, with the interval boundaries drawn as lines.
fig_map = plot_map(ds)

# %%
# Map files
# ---------
# A map is written as a Zarr store (``.zarr``) or NetCDF (``.nc``) and read back with
# :func:`vibimpact.maps.open_map`.
with tempfile.TemporaryDirectory() as tmp:
    path = Path(tmp) / "map.zarr"
    write_map(ds, path)
    back = open_map(path)
    print(bool((back.regime == ds.regime).all()))
