"""Fingerprints of a fixed set of results, to show that a change of the code's structure
left every number as it was.

Runs simulations (rotor presets, Duffing), the analysers (Lyapunov spectrum and largest
exponent, shooting, monodromy, Floquet exponents, continuation), the point pipeline, a
sweep (serial and on two workers) and a small map, and writes the SHA-256 of every
resulting array (its bytes, shape and dtype) to a JSON file.  Run it on two versions of
the code and compare the files::

    python analyses/tools/bit_identity.py -o before.json      # on the old checkout
    python analyses/tools/bit_identity.py -o after.json --compare before.json

``--compare`` prints the entries that differ and exits 1 if any does.
"""
from __future__ import annotations

import argparse
import hashlib
import json
import sys

from pathlib import Path

import numpy as np


def _digest(value):
    a = np.ascontiguousarray(np.asarray(value))
    h = hashlib.sha256()
    h.update(str(a.dtype).encode())
    h.update(str(a.shape).encode())
    # objects (strings) by their text: their bytes are addresses
    h.update("\x1f".join(map(str, a.ravel())).encode() if a.dtype == object
             else a.tobytes())
    return h.hexdigest()[:20]


def _api(vi):
    """Whether the analysers take a System (the redesigned API) or ``p`` and keywords."""
    return hasattr(vi, "System")


def results():
    """Name -> array of every result fingerprinted."""
    import vibimpact as vi
    from vibimpact import analysis as an

    out = {}
    fig8 = vi.presets.get("fig8")
    for name, eta in (("fig8", 1.0), ("fig8", 1.185), ("fig8", 1.25), ("fig10", 1.2),
                      ("fig11", 1.06), ("fig4", 1.1)):
        p = vi.presets.get(name).replace(eta=eta)
        for method in ("dop853", "dp5", "rk4"):
            solver = (dict(solver=vi.SolverSettings(method=method))
                      if hasattr(vi, "SolverSettings") else dict(method=method))
            run = vi.simulate(p, periods=40, transient=100, dense=16, **solver)
            key = f"simulate/{name}/{eta}/{method}"
            out[key + "/strobe"] = run.strobe
            out[key + "/dense"] = run.dense
            out[key + "/events_t"] = run.events["t"]
            out[key + "/events_state"] = run.events["state"]
            out[key + "/counters"] = np.array(list(run.counters.values()))
    dp = vi.DuffingParams() if hasattr(vi, "DuffingParams") else None
    run = vi.simulate(dp, periods=50, transient=100, dense=8)
    out["simulate/duffing/strobe"] = run.strobe
    out["simulate/duffing/dense"] = run.dense

    p = fig8.replace(eta=1.25)
    p1 = fig8.replace(eta=1.12)
    x1 = vi.simulate(p1, periods=1, transient=600).strobe[-1]
    if _api(vi):  # the same settings as the keyword API's defaults below
        s, s1 = vi.System(p), vi.System(p1)
        lyap = an.lyapunov_spectrum(s, averaging=an.Averaging(max_periods=2000))
        largest = an.largest_lyapunov(s, averaging=an.Averaging(align=20, max_periods=2000))
        shot = an.shoot_periodic_orbit(s1, x1)
        mono = an.monodromy(s1, shot.state)
        fl = an.floquet_lyapunov(s1, shot.state)
        br = an.continue_orbit(s1, shot.state, stop=1.16, steps=an.Steps(max_points=12))
        # classify_params is now the sweeps' point pipeline and returns (Regime, point
        # result): not the old (Regime, Run) of simulate(p, 200, 500) + classify, so
        # this entry cannot match a reference of the keyword API
        cp = vi.classify_params(s)
    else:
        lyap = an.lyapunov_spectrum(p, max_periods=2000)
        largest = an.largest_lyapunov(p, max_periods=2000)
        shot = an.shoot_periodic_orbit(p1, x1)
        mono = an.monodromy(p1, shot.state)
        fl = an.floquet_lyapunov(p1, shot.state)
        br = an.continue_orbit(p1, shot.state, stop=1.16, max_points=12)
        cp = an.classify_params(p)
    out["lyapunov_spectrum/exponents"] = lyap.exponents
    out["lyapunov_spectrum/stderr"] = lyap.stderr
    out["largest_lyapunov/exponents"] = largest.exponents
    out["shoot/state"] = shot.state
    out["shoot/multipliers"] = shot.multipliers
    out["monodromy"] = mono[0] if isinstance(mono, tuple) else getattr(mono, "matrix", mono)
    out["floquet_lyapunov"] = fl.exponents
    for f in ("eta", "params", "values", "states", "multipliers", "stable"):
        if hasattr(br, f):
            out[f"continue_orbit/{f}"] = np.asarray(getattr(br, f))
    out["classify_params/regime"] = np.array([str(cp[0] if isinstance(cp, tuple) else cp)])

    ds = vi.sweep(fig8, np.arange(1.10, 1.30, 0.01), direction="both",
                  continuation=vi.Continuation(blocks=4))
    ds2 = vi.sweep(fig8, np.arange(1.10, 1.30, 0.01), direction="both",
                   continuation=vi.Continuation(blocks=4),
                   execution=vi.Execution(workers=2))
    for name in sorted(ds.data_vars):
        out[f"sweep/{name}"] = ds[name].values
        out[f"sweep_workers2/{name}"] = ds2[name].values
    m = vi.map2d(fig8, np.arange(1.1, 1.3, 0.02), {"kh": [10.0, 40.0]},
                 execution=vi.Execution(workers=1))
    for name in sorted(m.data_vars):
        out[f"map/{name}"] = m[name].values
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", help="the JSON file of fingerprints (required)")
    ap.add_argument("--compare")
    # the fixed set of results is already small: a smoke run computes all of it
    ap.add_argument("--smoke", metavar="DIR", type=Path, default=None,
                    help="write the fingerprints to DIR/bit_identity.json "
                         "(tests/test_analyses_smoke.py)")
    args = ap.parse_args(argv)
    if args.smoke is not None:
        args.smoke.mkdir(parents=True, exist_ok=True)
        args.output = args.output or str(args.smoke / "bit_identity.json")
    if args.output is None:
        ap.error("the following arguments are required: -o/--output")
    digests = {k: _digest(v) for k, v in results().items()}
    with open(args.output, "w") as fh:
        json.dump(digests, fh, indent=1, sort_keys=True)
    print(f"{len(digests)} results fingerprinted -> {args.output}")
    if args.compare:
        with open(args.compare) as fh:
            ref = json.load(fh)
        diff = sorted(k for k in set(ref) | set(digests) if ref.get(k) != digests.get(k))
        for k in diff:
            print(f"differs: {k}")
        print(f"{len(diff)} of {len(set(ref) | set(digests))} differ")
        return 1 if diff else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
