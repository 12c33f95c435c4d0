"""Cases of :mod:`reliability` from the fourth adversarial round (issue 44, classes 10, 11
and 12): files a command reads or replaces that it must not trust.

* **crafted values in an input file** -- ``simulate --from`` of a sweep whose parameters
  were edited (``param_kh = -5`` beside ``params``, both records at -5, ``param_B`` NaN or
  text, the ``param_*`` attributes removed, another model's name), whose ``final_state``
  is text or of three states; ``rerun`` of a ``simulate --from`` file whose start record
  was edited (``start_params`` out of its domain, ``start_eta`` disagreeing); ``plot`` of
  a sweep whose title parameters were edited: exit 2, one line, no output file;
* **declared sizes over the limits** -- a NetCDF file of a few kilobytes declaring a
  2**28 x 4 variable (fixed or unlimited dimension), three variables adding up, given to
  ``plot``, ``simulate --from``, ``rerun``, ``orbits --seeds`` and ``attractors
  --sweep``, and a Zarr store declaring an 8 GiB array given to ``plot``: exit 2 at once,
  one line;
* **overwrite of what the toolkit did not write** -- ``map --overwrite`` onto a store
  holding a user's file (beside ``zarr.json`` or among the chunks), a directory without
  ``zarr.json``, someone else's Zarr store, a symbolic link to a store, a regular file,
  a ``.nc`` output that is a directory: exit 2, one line, everything left as it was
  (``data_lost`` otherwise); and the toolkit's own store, which is replaced (exit 0).
"""
from __future__ import annotations

import json
import os
import shutil

#: the files the cases start from: a two-point sweep and a run started from it
SWEEP = ["classify", "--eta", "1.0,1.01", "--analyses", "period,response", "--workers",
         "1", "--no-progress", "-o", "s.nc"]
RUN = ["simulate", "--from", "s.nc", "--eta", "1.01", "--periods", "2", "--transient", "0",
       "-o", "r.nc"]
FROM = ["simulate", "--from", "c.nc", "--eta", "1.01", "--periods", "2", "--transient",
        "0", "-o", "o.nc"]


def _attrs(**changes):
    def change(path):
        import netCDF4

        with netCDF4.Dataset(path, "a") as nc:
            for key, value in changes.items():
                if value is None:
                    nc.delncattr(key)
                else:
                    nc.setncattr(key, value)
    return change


def _json(key, **entries):
    def change(path):
        import netCDF4

        with netCDF4.Dataset(path, "a") as nc:
            nc.setncattr(key, json.dumps({**json.loads(nc.getncattr(key)), **entries}))
    return change


def _no_param_attrs(path):
    import netCDF4

    with netCDF4.Dataset(path, "a") as nc:
        for key in [k for k in nc.ncattrs() if k.startswith("param_")]:
            nc.delncattr(key)


def _dataset(edit):
    def change(path):
        import xarray as xr

        with xr.open_dataset(path) as ds:
            ds = edit(ds.load())
        os.unlink(path)
        ds.to_netcdf(path)
    return change


def _both_kh(value):
    def change(path):
        _json("params", kh=value)(path)
        _attrs(param_kh=value)(path)
    return change


#: case -> (source file, its change, the command run on the changed copy c.nc)
CRAFTED = {
    "simulate --from, param_kh = -5 beside params kh = 120": (
        "s.nc", _attrs(param_kh=-5.0), FROM),
    "simulate --from, kh = -5 in both records": ("s.nc", _both_kh(-5.0), FROM),
    "simulate --from, param_B = NaN": ("s.nc", _attrs(param_B=float("nan")), FROM),
    "simulate --from, param_kh as text": ("s.nc", _attrs(param_kh="120"), FROM),
    "simulate --from, no param_* attributes": ("s.nc", _no_param_attrs, FROM),
    "simulate --from, no params attribute": ("s.nc", _attrs(params=None), FROM),
    "simulate --from, model 'duffing'": ("s.nc", _attrs(model="duffing"), FROM),
    "simulate --from, final_state as text": ("s.nc", _dataset(lambda ds: ds.assign(
        final_state=ds["final_state"].astype(str))), FROM),
    "simulate --from, final_state of 3 states": ("s.nc", _dataset(
        lambda ds: ds.isel(state=slice(0, 3))), FROM),
    "rerun, start_params kh = -5": ("r.nc", _json("start_params", kh=-5.0),
                                    ["rerun", "c.nc"]),
    "rerun, start_eta disagreeing": ("r.nc", _attrs(start_eta=1.3), ["rerun", "c.nc"]),
    "plot, kh = -5 in both records": ("s.nc", _both_kh(-5.0),
                                      ["plot", "c.nc", "-o", "o.png"]),
    "plot of a run, param_G = inf": ("r.nc", _attrs(param_G=float("inf")),
                                     ["plot", "c.nc", "-o", "o.png"]),
}


def _sources(kit, base, timeout):
    """A directory with the sweep s.nc and the run r.nc made from it."""
    d = kit._fresh(base, "r4files-src")
    for argv in (SWEEP, RUN):
        rc, _, err, _ = kit.run(argv, d, timeout)
        if rc != 0:
            raise RuntimeError(f"{' '.join(argv)} failed ({rc}): {err[-400:]}")
    return d


def crafted_cases(kit, base, timeout):
    klass = "crafted values in an input file"
    src, out = _sources(kit, base, timeout), []
    for case, (name, change, argv) in CRAFTED.items():
        d = kit._fresh(base, "crafted")
        shutil.copy(src / name, d / "c.nc")
        change(str(d / "c.nc"))
        rc, _, err, sec = kit.run(argv, d, timeout)
        o = kit.judge(klass, case, rc, err, sec, {2}, d, keep=("c.nc",))
        o.clean = o.clean and sorted(os.listdir(d)) == ["c.nc"]
        out.append(o)
    return out


HUGE = 2**28


def _declaring(path, variables, n=HUGE, unlimited=False):
    """A small NetCDF file declaring ``variables`` of ``n`` x 4 float64 values."""
    import netCDF4

    with netCDF4.Dataset(path, "w") as nc:
        nc.createDimension("eta", None if unlimited else n)
        nc.createDimension("state", 4)
        for name in variables:
            var = nc.createVariable(name, "f8", ("eta", "state"), chunksizes=(1024, 4))
            if unlimited:
                var[n - 1, 0] = 1.0


def _store_declaring(path):
    """A map store (written by the toolkit) with an 8 GiB array declared, never
    written."""
    import warnings

    import numpy as np
    import xarray as xr
    import zarr

    from vibimpact.maps import write_map

    write_map(xr.Dataset({"regime": (("kh", "eta"), np.ones((2, 2), "i1"))},
                         coords={"kh": [1.0, 2.0], "eta": [1.0, 1.1]},
                         attrs={"map_vary": "kh"}), path)
    zarr.open_group(path, mode="r+").create_array("huge", shape=(HUGE, 4),
                                                  chunks=(HUGE, 4), dtype="f8")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        zarr.consolidate_metadata(path)


#: file -> how it is made
BIG_FILES = {
    "a 2**28 x 4 variable": lambda p: _declaring(p, ["final_state"]),
    "an unlimited dimension written at 2**28": lambda p: _declaring(p, ["final_state"],
                                                                    unlimited=True),
    "three variables adding up to 6 GiB": lambda p: _declaring(p, ["a", "b", "c"],
                                                               n=HUGE // 4),
}
#: command -> argv reading big.nc
READERS = {
    "plot": ["plot", "big.nc", "-o", "p.png"],
    "simulate --from": ["simulate", "--from", "big.nc", "--eta", "1.0", "-o", "o.nc"],
    "rerun": ["rerun", "big.nc"],
    "orbits --seeds": ["orbits", "--preset", "fig8", "--eta", "1.0", "--seeds", "big.nc",
                       "-o", "o.nc"],
    "attractors --sweep": ["attractors", "--sweep", "big.nc", "--eta", "1.0", "-o",
                           "o.nc"],
}


def declared_cases(kit, base, timeout):
    klass = "declared sizes over the limits"
    runs = [(f"{cmd}, {what}", make, argv, "big.nc")
            for what, make in BIG_FILES.items() for cmd, argv in READERS.items()
            if what == next(iter(BIG_FILES)) or cmd in ("plot", "simulate --from")]
    runs.append(("plot of a Zarr store declaring 8 GiB", _store_declaring,
                 ["plot", "m.zarr", "--kind", "map", "-o", "p.png"], "m.zarr"))
    out = []
    for case, make, argv, name in runs:
        d = kit._fresh(base, "declared")
        make(str(d / name))
        rc, _, err, sec = kit.run(argv, d, timeout)
        o = kit.judge(klass, case, rc, err, sec, {2}, d, keep=(name,))
        o.clean = o.clean and sorted(os.listdir(d)) == [name] and "declares" in err
        out.append(o)
    return out


MAP = ["map", "--eta", "1.0,1.01", "--vary", "kh=100,120", "--analyses", "period",
       "--workers", "1", "--no-progress"]


def _ours(d):
    """The toolkit's own small store m.zarr in ``d`` (write_map)."""
    import numpy as np
    import xarray as xr

    from vibimpact.maps import write_map

    write_map(xr.Dataset({"regime": (("kh", "eta"), np.ones((2, 2), "i1"))},
                         coords={"kh": [100.0, 120.0], "eta": [1.0, 1.01]},
                         attrs={"map_vary": "kh"}), str(d / "m.zarr"))


def _user_file(rel):
    def make(d):
        _ours(d)
        (d / "m.zarr" / rel).write_text("the user's notes\n")
    return make


def _someone_elses(d):
    import zarr

    zarr.open_group(str(d / "m.zarr"), mode="w").create_array("a", shape=(2,),
                                                              dtype="f8")


def _link(d):
    _ours(d)
    os.rename(d / "m.zarr", d / "real.zarr")
    os.symlink("real.zarr", d / "m.zarr")


def _no_zarr_json(d):
    (d / "m.zarr").mkdir()
    (d / "m.zarr" / "data.csv").write_text("1,2\n")


def _nc_directory(d):
    (d / "m.nc").mkdir()
    (d / "m.nc" / "keep.txt").write_text("x")


#: case -> (what stands at the output, the output's name)
FOREIGN = {
    "zarr.json and a user file": (_user_file("notes.txt"), "m.zarr"),
    "a user file among the chunks": (_user_file(os.path.join("regime", "c", "notes")),
                                     "m.zarr"),
    "a directory without zarr.json": (_no_zarr_json, "m.zarr"),
    "a Zarr store someone else wrote": (_someone_elses, "m.zarr"),
    "a symbolic link to the toolkit's store": (_link, "m.zarr"),
    "a regular file m.zarr": (lambda d: (d / "m.zarr").write_text("x\n"), "m.zarr"),
    "a .nc output that is a directory": (_nc_directory, "m.nc"),
}


def _tree(d):
    return sorted((os.path.relpath(os.path.join(top, n), d),
                   os.path.islink(os.path.join(top, n)))
                  for top, dirs, files in os.walk(d) for n in dirs + files)


def overwrite_cases(kit, base, timeout):
    klass = "overwrite of what the toolkit did not write"
    out = []
    for case, (make, name) in FOREIGN.items():
        d = kit._fresh(base, "overwrite")
        make(d)
        before = _tree(d)
        rc, _, err, sec = kit.run([*MAP, "--overwrite", "-o", name], d, timeout)
        o = kit.judge(klass, f"map --overwrite onto {case}", rc, err, sec, {2}, d,
                      keep=(name, "real.zarr"))
        o.data_lost = _tree(d) != before
        o.clean = o.clean and not o.data_lost
        out.append(o)
    d = kit._fresh(base, "overwrite")
    _ours(d)
    rc, _, err, sec = kit.run([*MAP, "--overwrite", "-o", "m.zarr"], d, timeout)
    o = kit.judge(klass, "map --overwrite onto the toolkit's own store (replaced)", rc,
                  err, sec, {0}, d, keep=("m.zarr",))
    out.append(o)
    return out


#: class -> the function that runs its cases: ``func(kit, base, timeout)`` -> Outcomes
CLASSES = {
    "crafted values in an input file": crafted_cases,
    "declared sizes over the limits": declared_cases,
    "overwrite of what the toolkit did not write": overwrite_cases,
}


def shrink():
    """A smoke run: the first case of each table."""
    for table in (CRAFTED, BIG_FILES, READERS, FOREIGN):
        for key in list(table)[1:]:
            del table[key]
