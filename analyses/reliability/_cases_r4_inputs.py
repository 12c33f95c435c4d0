"""Cases of :mod:`reliability` from the fourth adversarial round (issue 44, classes 7, 8
and 9): inputs checked before any work, an output named twice, and the refusals of
``continue2`` and ``plot``.

* **checked before work** -- ``continue --switch`` whose switch fails (soft-impact at
  k = 1e6) or finds no period doubling; ``attractors --sweep`` of a sweep without
  ``poincare_Y``, with ``poincare_X`` as text or all NaN, of the ring model, of other
  parameters; ``continue --refine 1e-300`` (it bisected for ever); ``continue2
  --range2`` outside the domain; ``basins --range`` of an overflowing width: exit 2, one
  line, nothing written (a file left: not clean);
* **outputs named twice** -- ``-o`` and ``--plot`` naming one file (``x.png`` and
  ``./x.png``, a symbolic link, ``sub/..``, an absolute path) for ``attractors``,
  ``basins``, ``orbits``, ``continue2`` and ``simulate``, and an output that is the
  command's input (``simulate --from``, ``attractors --sweep``, ``plot FILE -o FILE``,
  ``rerun -o``): exit 2, one line, the input unchanged (``data_lost`` otherwise);
* **refusals of continue2 and plot** -- ``continue2 --state0`` of the wrong size,
  ``--approach 0`` and ``-1``, a ``--step`` larger than the window; ``plot`` of a census
  with ``--kind xy`` or ``branch``, of a map with ``--kind lyapunov`` or ``census``, of
  a branch with ``--kind census``: exit 2, one line naming what the figure needs
  (clean only with those words).
"""
from __future__ import annotations

import hashlib
import os
import shutil

from _cases_r4_files import _dataset as _edit  # rewrites a NetCDF file with edit(ds)

#: the files the cases start from (name -> command line), made once in one directory
SOURCES = {
    "s.nc": ["classify", "--preset", "fig11", "--eta", "1.05,1.06", "--analyses",
             "period,poincare", "--workers", "1", "--no-progress", "-o", "s.nc"],
    "ring.nc": ["classify", "--preset", "fig8-ring", "--eta", "1.05,1.06", "--analyses",
                "period,poincare", "--workers", "1", "--no-progress", "-o", "ring.nc"],
    "census.nc": ["attractors", "--eta", "1.06", "--starts", "4", "--no-progress", "-o",
                  "census.nc"],
    "map.zarr": ["map", "--eta", "1.1,1.11", "--vary", "kh=110,120", "--workers", "1",
                 "--no-progress", "-o", "map.zarr"],
    "branch.nc": ["continue", "--stop", "1.05", "--max-points", "3", "-o", "branch.nc"],
}


def _text_x(ds):
    import numpy as np

    return ds.assign(poincare_X=(ds.poincare_X.dims,
                                 np.full(ds.poincare_X.shape, "a", dtype=object)))


ATTRACTORS = ["attractors", "--eta", "1.05,1.06", "--starts", "4", "--no-progress",
              "--sweep", "in.nc", "-o", "out.nc"]
CONTINUE2 = ["continue2", "--preset", "fig8", "--eta", "1.12", "--kind", "grazing",
             "--param2", "kh", "--range2", "110:130", "-o", "out.nc"]

#: case -> (source copied as in.nc or None, its edit or None, command line)
BEFORE = {
    "continue --switch, soft-impact k = 1e6": (
        None, None, ["continue", "--preset", "soft-impact", "--set", "k=1e6", "--stop",
                     "0.9", "--switch", "-o", "out.nc"]),
    "continue --switch, no period doubling": (
        None, None, ["continue", "--stop", "1.05", "--max-points", "3", "--switch", "-o",
                     "out.nc"]),
    "attractors --sweep without poincare_Y": (
        "s.nc", _edit(lambda ds: ds.drop_vars("poincare_Y")), ATTRACTORS),
    "attractors --sweep, poincare_X as text": ("s.nc", _edit(_text_x), ATTRACTORS),
    "attractors --sweep, poincare_X all NaN": (
        "s.nc", _edit(lambda ds: ds.assign(poincare_X=ds.poincare_X * float("nan"))),
        ATTRACTORS),
    "attractors --sweep of the ring model": ("ring.nc", None, ATTRACTORS),
    "attractors --sweep of other parameters": (
        "s.nc", None, ATTRACTORS + ["--set", "kh=100"]),
    "continue --refine 1e-300": (
        None, None, ["continue", "--stop", "1.2", "--refine", "1e-300", "-o", "out.nc"]),
    "continue2 --range2 outside the domain": (
        None, None, ["continue2", "--kind", "grazing", "--param2", "kh",
                     "--range2=-1e308:1e308", "-o", "out.nc"]),
    "basins --range of an overflowing width": (
        None, None, ["basins", "--grid", "6x6", "--range=-1e308:1e308,-1:1", "-o",
                     "out.nc"]),
}


def _link(d):
    os.symlink("x.png", d / "link.png")
    (d / "x.png").write_bytes(b"a user's image")


#: case -> (source copied as in.nc or None, preparation or None, command line)
TWICE = {
    "attractors -o x.png --plot ./x.png": (
        None, None, ["attractors", "--eta", "1.06", "--starts", "4", "-o", "x.png",
                     "--plot", "./x.png"]),
    "basins -o x.png --plot, a link to it": (
        None, _link, ["basins", "--grid", "6x6", "-o", "x.png", "--plot", "link.png",
                      "--overwrite"]),
    "orbits -o x.png --plot sub/../x.png": (
        None, lambda d: (d / "sub").mkdir(),
        ["orbits", "--period", "1", "-o", "x.png", "--plot", "sub/../x.png"]),
    "continue2 -o x.png --plot ABSOLUTE": (None, None, CONTINUE2[:-2] + [
        "-o", "x.png", "--plot", "ABS/x.png"]),
    "simulate -o x.png --plot ./x.png": (
        None, None, ["simulate", "--periods", "2", "-o", "x.png", "--plot", "./x.png"]),
    "simulate --from in.nc -o ./in.nc": (
        "s.nc", None, ["simulate", "--from", "in.nc", "--eta", "1.06", "-o", "./in.nc",
                       "--overwrite"]),
    "attractors --sweep in.nc -o in.nc": (
        "s.nc", None, ATTRACTORS[:-2] + ["-o", "in.nc", "--overwrite"]),
    "plot in.nc -o ./in.nc": (
        "census.nc", None, ["plot", "in.nc", "-o", "./in.nc", "--overwrite"]),
    "rerun in.nc -o ABSOLUTE": (
        "branch.nc", None, ["rerun", "in.nc", "-o", "ABS/in.nc", "--overwrite"]),
}

#: case -> (source copied as in.nc or None, command line, words the line must hold)
REFUSALS = {
    "continue2 --state0 of three values": (
        None, CONTINUE2 + ["--state0", "0", "0", "0"], "--state0 expects 4 numbers"),
    "continue2 --state0 of two for the ring": (
        None, CONTINUE2 + ["--preset", "fig8-ring", "--state0", "0", "0"],
        "--state0 expects 5 numbers"),
    "continue2 --approach 0": (None, CONTINUE2 + ["--approach", "0"], "--approach"),
    "continue2 --approach -1": (None, CONTINUE2 + ["--approach=-1"], "--approach"),
    "continue2 --step larger than the window": (
        None, CONTINUE2 + ["--step", "50"], "larger than the window"),
    "plot census --kind xy": (
        "census.nc", ["plot", "in.nc", "--kind", "xy", "-o", "o.png"],
        "needs a 'vibimpact simulate' file"),
    "plot census --kind branch": (
        "census.nc", ["plot", "in.nc", "--kind", "branch", "-o", "o.png"],
        "needs a continued branch ('vibimpact continue')"),
    "plot map --kind lyapunov": (
        "map.zarr", ["plot", "in.zarr", "--kind", "lyapunov", "-o", "o.png"],
        "needs a sweep file"),
    "plot map --kind census": (
        "map.zarr", ["plot", "in.zarr", "--kind", "census", "-o", "o.png"],
        "needs an attractor census"),
    "plot branch --kind census": (
        "branch.nc", ["plot", "in.nc", "--kind", "census", "-o", "o.png"],
        "is a continued branch"),
}


def _sources(kit, base, timeout, names):
    """A directory with the source files ``names`` (see :data:`SOURCES`)."""
    d = kit._fresh(base, "r4inputs-src")
    for name in names:
        rc, _, err, _ = kit.run(SOURCES[name], d, timeout)
        if rc != 0:
            raise RuntimeError(f"{' '.join(SOURCES[name])} failed ({rc}): {err[-400:]}")
    return d


def _digest(path):
    """The bytes of a file, or of every file below a directory, as one hash."""
    h = hashlib.sha256()
    paths = [path] if os.path.isfile(path) else sorted(
        os.path.join(r, f) for r, _, fs in os.walk(path) for f in fs)
    for p in paths:
        with open(p, "rb") as fh:
            h.update(fh.read())
    return h.hexdigest()


def _case(kit, base, timeout, klass, case, src, source, argv, needle=None, edit=None,
          prepare=None):
    """Run one case in a fresh directory holding a copy of ``source`` as in.nc (in.zarr),
    changed by ``edit(path)``, and what ``prepare(directory)`` makes: exit 2, one line
    (holding ``needle``), the directory as it was before (nothing written, the input
    unchanged)."""
    d = kit._fresh(base, "r4inputs")
    inp = None
    if source is not None:
        inp = d / ("in.zarr" if source.endswith(".zarr") else "in.nc")
        copy = shutil.copytree if os.path.isdir(src / source) else shutil.copy
        copy(src / source, inp)
        if edit is not None:
            edit(inp)
    if prepare is not None:
        prepare(d)
    argv = [a.replace("ABS", str(d)) for a in argv]
    before = {n: _digest(d / n) for n in os.listdir(d)}
    rc, _, err, sec = kit.run(argv, d, timeout)
    o = kit.judge(klass, case, rc, err, sec, {2}, d, keep=tuple(before))
    after = {n: _digest(d / n) for n in os.listdir(d)}
    o.data_lost = None if inp is None else after.get(inp.name) != before[inp.name]
    o.clean = o.clean and after == before and (needle is None or needle in o.message)
    return o


def before_cases(kit, base, timeout):
    klass = "checked before work"
    src = _sources(kit, base, timeout, ("s.nc", "ring.nc"))
    return [_case(kit, base, timeout, klass, case, src, source, argv, edit=edit)
            for case, (source, edit, argv) in BEFORE.items()]


def twice_cases(kit, base, timeout):
    klass = "outputs named twice"
    src = _sources(kit, base, timeout, ("s.nc", "census.nc", "branch.nc"))
    return [_case(kit, base, timeout, klass, case, src, source, argv, prepare=prepare,
                  needle="being rerun" if argv[0] == "rerun" else "name the same file")
            for case, (source, prepare, argv) in TWICE.items()]


def refusal_cases(kit, base, timeout):
    klass = "refusals of continue2 and plot"
    src = _sources(kit, base, timeout, ("census.nc", "map.zarr", "branch.nc"))
    return [_case(kit, base, timeout, klass, case, src, source, argv, needle)
            for case, (source, argv, needle) in REFUSALS.items()]


#: class -> the function that runs its cases: ``func(kit, base, timeout)`` -> Outcomes
CLASSES = {
    "checked before work": before_cases,
    "outputs named twice": twice_cases,
    "refusals of continue2 and plot": refusal_cases,
}


def shrink():
    """A smoke run: the first case of each table."""
    for table in (BEFORE, TWICE, REFUSALS):
        for key in list(table)[1:]:
            del table[key]
