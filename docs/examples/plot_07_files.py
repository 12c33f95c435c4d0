"""
Files: NetCDF, checkpoints and reruns
=====================================

Every result is a self-describing ``xarray.Dataset``: the data next to every parameter,
the solver settings, the vibimpact version and the command line, with CF-style units.
"""

# %%
# A run as NetCDF
# ---------------
import tempfile
from pathlib import Path


import vibimpact as vi
from vibimpact.io import differences, read_netcdf, run_to_dataset, write_netcdf

tmp = Path(tempfile.mkdtemp())
run = vi.simulate(vi.presets.get("fig10").replace(eta=1.1), periods=20, transient=100)
ds = run_to_dataset(run)
write_netcdf(ds, tmp / "run.nc")
back = read_netcdf(tmp / "run.nc")
print(back)
diffs, compared = differences(ds, back)
print(f"{compared} variables compared, {len(diffs)} differ")

# %%
# A sweep with a checkpoint
# -------------------------
# With ``checkpoint`` every finished point is saved at once; ``resume=True`` loads the
# saved points instead of recomputing them (after Ctrl-C or a killed job), and the result
# is identical to an uninterrupted run.
p = vi.presets.get("fig8")
eta = vi.grid("1.1:1.2:0.01")
first = vi.sweep(p, eta, execution=vi.Execution(checkpoint=tmp / "sweep.partial"))
again = vi.sweep(p, eta,
                 execution=vi.Execution(checkpoint=tmp / "sweep.partial", resume=True))
diffs, compared = differences(first, again)
print(f"{compared} variables compared, {len(diffs)} differ")
