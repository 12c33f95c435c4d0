"""Cases of :mod:`reliability` from the fourth adversarial round (issue 44, classes 13
and 14): failed integrations in a census, and API arguments.

* **failed integrations in a census** -- ``attractors`` of the turning ring at
  ``Jr = 1e-300``, ``cr = 1e300``, ``Mr = 1e12`` and of the soft-impact oscillator at
  ``k = 1e300`` (every start fails), the soft-impact one over two eta (some fail, some
  reach an orbit), with ``--sweep`` of a classify of the same parameters, ``basins``
  whose ``--range`` reaches ``X = 1e300`` and ``orbits`` of the ring at ``Jr = 1e-300``:
  the file is written and the command says one line ``vibimpact: warning: ... failed to
  integrate (...)`` and exits 0 (the documented behaviour: a failed start is on no
  attractor, counted apart in ``failed``/``failed_fraction``; a "diverged" attractor or
  no warning is not clean);
* **API arguments** -- one Python process per call (``vi.attractors`` with a census box
  whose disk indexes past the state, ``Box`` with a negative or NaN radius or a disk of
  one index twice, ``vi.sweep`` of eta 1e-300..1e300, ``vi.grid`` with ``name=5`` or a
  float, ``vi.hunt_orbits`` of a preset's name, with ``random=10**12``, ``max_iter``
  of a million, ``vi.Execution(workers=10**6)``, ``vi.basins`` at a system frequency of
  1e-9, ``follow_branch`` to ``stop=1e7``, ``CensusSettings(max_periods=10**12)``, a
  user model whose ``terminal`` is longer than its switching functions, a census whose
  fractions add up above 1 given to the figure): clean when the call raises
  ``ValueError``/``TypeError`` whose message names the argument as the function's
  parameter is named.
"""
from __future__ import annotations

import os

#: command line, output -> a census, basin image or hunt whose integrations fail
FAILED = {
    "attractors, ring Jr=1e-300": (["attractors", "--preset", "fig8-ring", "--set",
                                    "Jr=1e-300", "--eta", "1.2", "--starts", "4"], "a.nc"),
    "attractors, ring cr=1e300": (["attractors", "--preset", "fig8-ring", "--set",
                                   "cr=1e300", "--eta", "1.2", "--starts", "4"], "a.nc"),
    "attractors, ring Mr=1e12": (["attractors", "--preset", "fig8-ring", "--set",
                                  "Mr=1e12", "--eta", "1.2", "--starts", "4"], "a.nc"),
    "attractors, soft-impact k=1e300": (["attractors", "--preset", "soft-impact", "--set",
                                         "k=1e300", "--eta", "1.2", "--starts", "4"],
                                        "a.nc"),
    "attractors, some starts fail (two eta)": (
        ["attractors", "--preset", "soft-impact", "--set", "k=1e300", "--eta", "1.2,1.3",
         "--starts", "4"], "a.nc"),
    "attractors --sweep, some starts fail": (
        ["attractors", "--preset", "soft-impact", "--set", "k=1e300", "--eta", "1.2,1.3",
         "--starts", "4", "--sweep", "s.nc"], "a.nc"),
    "basins reaching X = 1e300": (["basins", "--preset", "fig8", "--eta", "1.2", "--grid",
                                   "2x2", "--eps", "1", "--range=-0.5:1e300,-0.5:0.5"],
                                  "b.nc"),
    "orbits, ring Jr=1e-300": (["orbits", "--preset", "fig8-ring", "--set", "Jr=1e-300",
                                "--eta", "1.2", "--period", "1", "--random", "2",
                                "--no-continue"], "o.nc"),
}
#: the sweep the --sweep case reads
SWEEP = ["classify", "--preset", "soft-impact", "--set", "k=1e300", "--eta", "1.2,1.3",
         "--analyses", "period,poincare", "--workers", "1", "--no-progress", "-o", "s.nc"]


def failed_cases(kit, base, timeout):
    out = []
    for case, (argv, output) in FAILED.items():
        d = kit._fresh(base, "failed")
        keep = (output,)
        if "--sweep" in argv:
            rc, _, err, _ = kit.run(SWEEP, d, timeout)
            if rc != 0:
                raise RuntimeError(f"the sweep of {case!r} failed ({rc}): {err[-300:]}")
            keep += ("s.nc",)
        rc, so, err, sec = kit.run([*argv, "--no-progress", "-o", output], d, timeout)
        o = kit.judge("failed integrations in a census", case, rc, err, sec, {0}, d,
                      keep=keep)
        warned = [ln for ln in err.splitlines() if ln.startswith("vibimpact: warning:")]
        if warned:
            o.message = warned[0][:160]
        o.clean = (o.clean and len(warned) == 1 and "failed to integrate" in warned[0]
                   and os.path.exists(d / output) and "diverged" not in so)
        out.append(o)
    return out


#: case -> (the call, the argument its message must name)
API = {
    "attractors, box disk (0, 9)": (
        "vi.attractors(vi.System(vi.presets.get('fig8')), 1.2, 2, box=Box([-1]*4, [1]*4, "
        "disk=(0, 9)))", "disk"),
    "Box radius -1": ("Box([-1]*4, [1]*4, disk=(0, 1), radius=-1.0)", "radius"),
    "Box radius NaN": ("Box([-1]*4, [1]*4, disk=(0, 1), radius=float('nan'))", "radius"),
    "Box disk (0, 0)": ("Box([-1]*4, [1]*4, disk=(0, 0))", "disk"),
    "sweep eta 1e-300..1e300": ("vi.sweep(vi.presets.get('fig8'), [1e-300, 1e300])",
                                "eta"),
    "grid name=5": ("vi.grid('1:2:0.1', name=5)", "name"),
    "grid of a float": ("vi.grid(1.0)", "text"),
    "hunt_orbits of a preset name": ("vi.hunt_orbits('fig8', [1])", "system"),
    "hunt_orbits random=10**12": (
        "vi.hunt_orbits(vi.presets.get('fig8'), [1], random=10**12)", "random"),
    "hunt_orbits max_iter=10**6": (
        "vi.hunt_orbits(vi.presets.get('fig8'), [1], max_iter=10**6)", "max_iter"),
    "Execution workers=10**6": ("vi.Execution(workers=10**6)", "workers"),
    "basins at a system eta of 1e-9": (
        "vi.basins(vi.System(vi.presets.get('fig8').replace(eta=1e-9)), grid=(2, 2), "
        "eps=1)", "system"),
    "follow_branch stop=1e7": (
        "__import__('vibimpact.continuation.branches').continuation.branches.follow_branch("
        "vi.presets.get('fig8'), stop=1e7)", "stop"),
    "CensusSettings max_periods=10**12": ("vi.CensusSettings(max_periods=10**12)",
                                          "max_periods"),
    "user model terminal longer than its switches": (
        "check_model(vi.Model.from_functions('m', rhs, jac, sw, tr, im, [0, 1, 1], "
        "('x', 'v'), ('w',), 0), np.array([1.0]))", "terminal"),
    "census fractions adding above 1, drawn": (
        "plot_census(census_above_one())", "fraction"),
}

API_CODE = '''
import re
import numpy as np
import vibimpact as vi
from numba import njit
from vibimpact.census import Box
from vibimpact.models.model_probe import check_model
from vibimpact.plotting.census import plot_census


@njit
def rhs(s, y, p, mode, out):
    out[0] = y[1]
    out[1] = -y[0] + np.cos(p[0] * s)


@njit
def jac(s, y, p, mode, J):
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0] = -1.0
    J[1, 1] = 0.0


@njit
def sw(s, y, p, mode, g):
    g[0] = y[1]


@njit
def tr(s, y, p, mode, which):
    return


@njit
def im(s, y, p, mode):
    mode[0] = 0


def census_above_one():
    system = vi.System(vi.DuffingParams(delta=0.1, alpha=1.0, beta=-1.0, gamma=5.0,
                                        omega=1.0))
    ds = vi.attractors(system, None, starts=2)
    ds["failed_fraction"].values[:] = 0.5  # with the diverged fraction 1: 1.5 in all
    return ds


try:
    CALL
except (ValueError, TypeError) as exc:
    named = re.search(r"(^|\\W)NAME\\W", str(exc))
    print(("refused: " if named else "not naming NAME: ") + type(exc).__name__ + ": "
          + str(exc))
else:
    print("accepted")
'''


def api_cases(kit, base, timeout):
    return [kit.python_case(base, "api", "API arguments", case,
                            API_CODE.replace("CALL", call).replace("NAME", name),
                            timeout, ("refused:",))
            for case, (call, name) in API.items()]


#: class -> the function that runs its cases: ``func(kit, base, timeout)`` -> Outcomes
CLASSES = {"failed integrations in a census": failed_cases, "API arguments": api_cases}


def shrink():
    """A smoke run: the first case of each table."""
    global FAILED, API
    FAILED = dict(list(FAILED.items())[:1])
    API = dict(list(API.items())[:1])
