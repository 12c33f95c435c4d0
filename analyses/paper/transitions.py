"""The type of every interval boundary of fig8, fig10 and fig11, and the checks behind it.

Run as ``python analyses/paper/transitions.py`` (minutes: it shoots and continues the
orbit on each side of every boundary); writes
``reports/transitions.md`` and ``reports/figures/branches_fig8.png``.  The sweeps are the
paper report's (``analyses/paper/paper.py``: eta = 0.9:1.5:0.005, up and down, pure
continuation): read from its cache ``.paper-cache/`` when there, else computed and put
there, so the interval boundaries typed here are those of ``reports/paper.md``.

Sections (issue 8):

* ``duffing`` -- the period doubling of the double-well Duffing oscillator located by
  shooting, against an independent brute-force reference;
* ``floquet`` -- Floquet multipliers of fig8 periodic points against the variational
  Lyapunov exponents and the finite-difference Jacobian of the stroboscopic map; what the
  "floquet" sweep analysis costs;
* ``fig8``, ``fig10``, ``fig11`` -- the transition tables;
* ``branches`` -- pseudo-arclength continuation of fig8's period-1 orbits (unstable parts
  dashed) over the sweep's response curve.
"""
from __future__ import annotations

import datetime
import math
import sys
import time
from multiprocessing import get_context
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # analyses/: _common
from _common import smoke  # noqa: E402
from _common.report import write_section  # noqa: E402

import vibimpact as vi
from vibimpact.analysis import (Averaging, Steps, continue_orbit, locate_bifurcation,
                                lyapunov_spectrum, shoot_periodic_orbit, strobe_map_jacobian)
from vibimpact.sweeps import continued_state, parse_range
from vibimpact.sweeps.transitions import format_transitions, transition_types

ROOT = Path(__file__).resolve().parents[2]
REPORT = ROOT / "reports" / "transitions.md"
FIGURES = ROOT / "reports" / "figures"
CACHE = ROOT / ".paper-cache"
PRESETS = ("fig8", "fig10", "fig11")
STEP = 0.005
TOL = 1e-4
#: least periods of the exponents the multipliers are compared with; the grid of the
#: Floquet step's cost; most points of the low and of the impacting branches
FLOQUET_LYAP_PERIODS, FLOQUET_COST_GRID = 400, "0.9:1.5:0.002"
BRANCH_POINTS_LOW, BRANCH_POINTS_IMPACTING = 200, 150


def _sweep(name):
    """The paper report's sweep of ``name`` (cached), or the same sweep computed here."""
    try:
        from paper_sweeps import sweep_one  # the paper report's own sweep (and cache)
        CACHE.mkdir(exist_ok=True)
        return sweep_one((name, STEP, str(CACHE), False, {}))[1]
    except ImportError:
        eta = np.round(np.arange(0.9, 1.5 + 1e-9, STEP), 6)
        return vi.sweep(vi.presets.get(name), eta, direction="both",
                        continuation=vi.Continuation(blocks=1))


def _types(name):
    t0 = time.perf_counter()
    ds = _sweep(name)
    t1 = time.perf_counter()
    tt = transition_types(ds, tol=TOL)
    return name, ds, tt, t1 - t0, time.perf_counter() - t1


# --- Duffing period doubling -----------------------------------------------------------

def duffing():
    """Shooting + multipliers against a brute-force reference (no Newton, no tangents)."""
    p = vi.DuffingParams(delta=0.3, alpha=-1.0, beta=1.0, gamma=0.25, omega=1.2)
    t = time.perf_counter()
    bif = locate_bifurcation(vi.System(p), [1.0, 0.0], param="gamma", start=0.25,
                             stop=0.28, tol=1e-7)
    t_shoot = time.perf_counter() - t
    x = vi.simulate(p.replace(gamma=0.26), periods=1, transient=300,
                    state0=[1.0, 0.0]).final_state
    gs = np.array([0.268, 0.270, 0.272, 0.274, 0.276])
    s2 = []
    for g in gs:
        r = vi.simulate(p.replace(gamma=float(g)), periods=4, transient=3000, state0=x,
                        solver=vi.SolverSettings(rtol=1e-11, atol=1e-13))
        s2.append(np.sum((r.strobe[1] - r.strobe[0]) ** 2))
    roots = np.roots(np.polyfit(gs, s2, 2)).real
    ref = float(roots[np.argmin(np.abs(roots - 0.27))])
    lin = float(np.roots(np.polyfit(gs, s2, 1))[0].real)
    mu = bif.orbit.multipliers[0]
    return [
        "## Duffing oscillator: period doubling located by shooting", "",
        "`x'' + 0.3 x' - x + x^3 = gamma cos 1.2 t` (the double-well oscillator of the "
        "classic period-doubling route; Thompson & Stewart 1986, *Nonlinear Dynamics and "
        "Chaos*, ch. 14).  The period-1 orbit in one well is followed in `gamma` by "
        "Newton shooting; the bracket where its multiplier crosses -1 is bisected to "
        "1e-7.  The reference uses simulation only: past a supercritical period doubling "
        "the period-2 splitting obeys `s^2 ~ c (gamma - gamma*)`; `s^2` at five values "
        "(3000 periods of transient each) extrapolated to 0.", "",
        "| route | gamma at the period doubling |", "| --- | ---: |",
        f"| shooting + Floquet multiplier (`locate_bifurcation`, {t_shoot:.2f} s) | "
        f"{bif.value:.7f} |",
        f"| brute force, quadratic fit of s^2 | {ref:.7f} |",
        f"| brute force, linear fit of s^2 | {lin:.7f} |", "",
        f"Difference {abs(bif.value - ref):.1e} (acceptance: 1e-3).  Kind found: "
        f"**{bif.kind}**; multiplier at the bracket mu = {mu.real:+.6f}{mu.imag:+.1e}j.",
        ""]


# --- Floquet multipliers of fig8 periodic points ---------------------------------------

def floquet(ds8):
    """ln|mu|/T against the variational Lyapunov exponent, M against finite differences."""
    sub = ds8.sel(direction="up")
    etas = sub["eta"].values
    per = sub["period"].values
    idx = [i for i in range(etas.size) if per[i] > 0 and sub["regime"].values[i] == 1]
    # every sixth point, eta = 1.185 (impacts A, B) and points next to bifurcations,
    # where the multipliers are not all on the circle |mu| = exp(-B T / 2)
    lab = sub["label"].values
    near = [i for i in idx if (i > 0 and lab[i - 1] != lab[i]) or
            (i + 1 < lab.size and lab[i + 1] != lab[i])]  # next to a boundary
    cases = [("fig8", ds8, i) for i in sorted(set(idx[::6]) | set(near))]
    ds10 = _sweep("fig10")
    s10 = ds10.sel(direction="up")
    idx10 = [i for i in range(s10.sizes["eta"]) if s10["period"].values[i] > 0
             and s10["regime"].values[i] == 1]
    cases += [("fig10", ds10, i) for i in idx10[::8]]
    cases.append(("fig8 (B = Ec = 0.1)", None, 1.185))
    rows, worst_z, worst_d, worst_fd = [], 0.0, 0.0, 0.0
    seen = set()
    for name, ds, i in cases:
        if ds is None:  # the pinned configuration, reached by continuation
            eta, n = i, 1
            p = vi.presets.get("fig8").replace(B=0.1, Ec=0.1, eta=eta)
            x = continued_state(p, eta)
        else:
            sub = ds.sel(direction="up")
            eta, n = float(sub["eta"].values[i]), int(sub["period"].values[i])
            if (name, i) in seen or n < 1:
                continue
            seen.add((name, i))
            p = vi.presets.get(name).replace(eta=eta)
            x = sub["final_state"].values[i]
        orb = shoot_periodic_orbit(vi.System(p), x, n)
        if not orb.converged or orb.minimal_period != n or not orb.stable:
            rows.append(f"| {name} | {eta:.3f} | {n} | no stable period-{n} orbit "
                        f"(converged {orb.converged}, minimal period "
                        f"{orb.minimal_period}, abs(mu) {orb.abs_max:.3f}) | | | | | |")
            continue
        ly = lyapunov_spectrum(vi.System(p), state0=orb.state, n_exponents=1,
                               averaging=Averaging(transient=0,
                                                   min_periods=FLOQUET_LYAP_PERIODS,
                                                   target_stderr=1e-3))
        lam = math.log(orb.abs_max) / orb.period
        d = lam - ly.exponents[0]
        fd = strobe_map_jacobian(vi.System(p), orb.state, n=n)
        rel = float(np.abs(orb.monodromy - fd).max() / np.abs(fd).max())
        worst_d, worst_fd = max(worst_d, abs(d)), max(worst_fd, rel)
        if ly.stderr[0] >= 1e-5:  # below that the error bar is no yardstick
            z = abs(d) / ly.stderr[0]
            worst_z = max(worst_z, z)
            ztxt = f"{z:.1f}"
        else:
            ztxt = "(error < 1e-5)"
        rows.append(f"| {name} | {eta:.3f} | {n} | {orb.abs_max:.5f} | {lam:+.5f} | "
                    f"{ly.exponents[0]:+.5f} ± {ly.stderr[0]:.5f} | {d:+.1e} | {ztxt} | "
                    f"{rel:.1e} |")
    cost = _floquet_cost()
    return [
        "## Floquet multipliers of fig8 periodic points", "",
        "Every sixth periodic point of the fig8 up sweep and every one next to an "
        "interval boundary, every eighth periodic point of "
        "fig10, at the presets' B = "
        f"{vi.presets.get('fig8').B:g}, Ec = {vi.presets.get('fig8').Ec:g}; and fig8 at "
        "eta = 1.185 with B = Ec = 0.1 (the configuration of issue 8's quoted -0.0500).  "
        "Without contact damping (fig8) a stable orbit often has all four multipliers on "
        "the circle |mu| = exp(-B T / 2) (the flow is symplectic up to the uniform "
        "damping B), so all its exponents are -B/2; near a bifurcation, and with the "
        "tangential damping of fig10, they differ.  "
        "The orbit is shot from the sweep's final state; `ln|mu|max / (n T)` is compared "
        "with the largest exponent of `lyapunov_spectrum` (variational equations, "
        "saltation matrices, QR; 400+ periods, target error 1e-3), and the monodromy "
        "matrix with `strobe_map_jacobian` (central differences, rtol 1e-12).", "",
        "| preset | eta | n | abs(mu) max | ln abs(mu) / nT | Lyapunov | difference | "
        "z = abs(difference) / error | max rel. diff. M vs FD |",
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |", *rows, "",
        f"Largest difference {worst_d:.1e} per unit tau; largest z {worst_z:.1f} standard "
        f"errors (rows with an error bar >= 1e-5); monodromy vs finite differences at most "
        f"{worst_fd:.1e} relative.", "",
        "### Cost of the sweep analysis \"floquet\"", "",
        cost, ""]


def _floquet_cost():
    """CPU time of the Floquet step inside a serial 301-point fig8 sweep."""
    import vibimpact.points.measure as pt

    orig, acc = pt.floquet, [0.0]

    def timed(*a):
        t = time.process_time()
        out = orig(*a)
        acc[0] += time.process_time() - t
        return out

    pt.floquet = timed
    try:
        t = time.process_time()
        ds = vi.sweep(vi.presets.get("fig8"), parse_range(FLOQUET_COST_GRID),
                      execution=vi.Execution(workers=1))
        total = time.process_time() - t
    finally:
        pt.floquet = orig
    n = int((ds["stable"].values >= 0).sum())
    return (f"In the default 301-point fig8 classify (serial, all analyses), the Floquet "
            f"step ran at {n} periodic points and took {acc[0]:.2f} s of {total:.2f} s CPU "
            f"({100 * acc[0] / total:.1f} %), {1e3 * acc[0] / max(n, 1):.1f} ms per point: "
            f"it is part of the default analyses.")


# --- continuation ----------------------------------------------------------------------

def branches(ds8):
    """fig8 period-1 branches by pseudo-arclength continuation over the response curve."""
    from matplotlib.figure import Figure

    from vibimpact.plotting import plot_response
    from vibimpact.plotting.branch import plot_branch

    p8 = vi.presets.get("fig8")
    out = []
    t = time.perf_counter()
    low = p8.replace(eta=1.3)
    x = vi.simulate(low, periods=1, transient=300).final_state
    out.append(("low branch from eta = 1.3, down",
                continue_orbit(vi.System(low), x, stop=(0.9, 1.5), direction=-1,
                               steps=Steps(ds=0.01, ds_max=0.015,
                                           max_points=BRANCH_POINTS_LOW))))
    up = p8.replace(eta=1.1)
    xu = continued_state(p8, 1.1)
    for d in (1, -1):
        out.append((f"impacting branch from eta = 1.1, {'up' if d > 0 else 'down'}",
                    continue_orbit(vi.System(up), xu, stop=(0.9, 1.5), direction=d,
                                   steps=Steps(ds=0.01, ds_max=0.015,
                                               max_points=BRANCH_POINTS_IMPACTING))))
    cost = time.perf_counter() - t
    fig = Figure(figsize=(10.5, 7.5))
    axes = [fig.add_subplot(2, 1, 1), fig.add_subplot(2, 1, 2)]
    fig.subplots_adjust(right=0.74, bottom=0.14)
    plot_response(ds8, ax=axes)
    for k, (_, br) in enumerate(out):
        for a, var in zip(axes, ("X_m", "Y_m")):
            plot_branch(a, br, var, color=("0.2", "tab:purple", "tab:purple")[k],
                        label=("continued P1 (low)", "continued P1 (impacting)", None)[k]
                        if var == "X_m" else None)
    axes[0].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")
    FIGURES.mkdir(parents=True, exist_ok=True)
    fig.savefig(FIGURES / "branches_fig8.png", dpi=110)
    rows = []
    for name, br in out:
        marks = "; ".join(f"{k} at {v:.4f}" for _, k, v in br.bifurcations) or "none"
        rows.append(f"| {name} | {br.values.size} | {br.values.min():.3f}..{br.values.max():.3f}"
                    f" | {int((~br.stable).sum())} | {marks} | {br.status} |")
    return [
        "## Continuation of fig8's period-1 orbits (pseudo-arclength in eta)", "",
        f"Three branches in {cost:.0f} s.  Unstable orbits (dashed) are those a brute-force "
        "sweep never shows; the low branch turns at its grazing-induced fold and goes on "
        "as an unstable impacting orbit.", "",
        "| branch | points | eta range | unstable points | bifurcations on it | end |",
        "| --- | ---: | --- | ---: | --- | --- |", *rows, "",
        "![fig8 branches](figures/branches_fig8.png)", ""]


def _summary(tt):
    kinds = {}
    for t in tt["type"].values:
        for part in str(t).split(" + "):
            kinds[part] = kinds.get(part, 0) + 1
    return ", ".join(f"{k} {v}" for k, v in sorted(kinds.items(), key=lambda kv: -kv[1]))


def main(argv=None):
    global REPORT, FIGURES
    out = smoke.parser(__doc__).parse_args(argv).smoke
    REPORT = smoke.moved(REPORT, out)
    if out is not None:
        FIGURES = out / "figures"
    smoke.shrink(globals(), out, CACHE=None if out is None else out / "cache", STEP=0.1,
                 FLOQUET_LYAP_PERIODS=20, FLOQUET_COST_GRID="1.0:1.2:0.1",
                 BRANCH_POINTS_LOW=5, BRANCH_POINTS_IMPACTING=5)
    t_all = time.perf_counter()
    from paper import warm_up  # the kernel compiled here before the pool forks

    warm_up()
    with get_context("fork").Pool(2) as pool:
        res = {name: (ds, tt, ts, tr) for name, ds, tt, ts, tr in
               pool.imap_unordered(_types, PRESETS)}
    head = ["# Transition types of the interval maps (issue 8)", "",
            "Written by `python analyses/paper/transitions.py`; every number is measured by it.",
            f"Date {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC.", "",
            "At each boundary of `vi.intervals` (sweep order, up and down) "
            "`vi.transition_types` follows the periodic orbit of the from side by Newton "
            "shooting towards the next grid point, bisects the first value where it stops "
            "persisting to "
            f"{TOL:g} in eta, and names the event by the Floquet multipliers (through -1: "
            "period doubling; through +1 / no orbit beyond: fold; complex pair: "
            "Neimark–Sacker; contacts change: grazing).  A chaotic from side is typed by "
            "following the to side's orbit backwards (its fold: intermittency; stable "
            "back into the chaos: crisis); two non-periodic sides are bisected by "
            "re-running the sweep's point analysis (crisis).  'none' means the orbit is "
            "the same on both sides and only the sweep's label changed (loaded arcs "
            "regrouped, or a slowly converging orbit read as another period).  `|mu|` is "
            "the largest multiplier of the followed orbit at the bracket's persisting end.",
            "", "Sweeps: eta = 0.9:1.5:0.005, up and down, pure continuation (the paper "
            "report's).", ""]
    write_section(REPORT, "head", "\n".join(head))
    for name in PRESETS:
        ds, tt, ts, tr = res[name]
        L = [f"## {name}: {vi.presets.describe(name)}", "",
             f"{tt.sizes['boundary']} boundaries; types: {_summary(tt)}.  Sweep "
             f"{'cached' if ts < 1 else f'{ts:.0f} s'}, typing {tr:.0f} s.", "",
             format_transitions(tt), ""]
        write_section(REPORT, name, "\n".join(L))
        print("\n".join(L))
    L = duffing()
    write_section(REPORT, "duffing", "\n".join(L))
    print("\n".join(L))
    L = floquet(res["fig8"][0])
    write_section(REPORT, "floquet", "\n".join(L))
    print("\n".join(L))
    L = branches(res["fig8"][0])
    write_section(REPORT, "branches", "\n".join(L))
    print("\n".join(L))
    print(f"total {time.perf_counter() - t_all:.0f} s", file=sys.stderr)


if __name__ == "__main__":
    sys.exit(main())
