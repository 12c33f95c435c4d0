"""Numerical stress tests of the kernel (issue 6, part 3).

Run as ``python analyses/performance/stress.py``; replaces the ``stress`` section of
``reports/performance.md`` (other sections are kept).  Every number in the table is measured
by this script in the same run; nothing is copied in by hand.  Takes about two minutes, most
of it the 1e5-period run.

Cases (all with ``vibimpact.simulate``, DOP853, default tolerances unless stated):

* **kh** from 1 to 1e5 on fig8 at eta = 1.0 (impacting), and the same stiffness in a
  conservative run (B = Bh = BT = f = Ec = G = 0, start (0, 0, 1.5, 0.5), rtol 1e-12) whose
  energy must stay constant to 1e-8 over 50 periods.
* **Bh** so large that ``1 + Bh R'`` turns negative during contact (the paper's formula is not
  clipped): the check value is the smallest ``1 + Bh R'`` at contact exits.
* **f** up to 1 with Rr = 0 on fig11 at eta = 1.0: Filippov stick phases counted (friction
  switches into stick), steps per period must stay bounded (< 5000).
* **grazing**: fig8 at eta = 0.9 from rest, Ec chosen by bisection so that the steady orbit's
  maximum radius is 1 -+ 1e-4, 1e-5 and 1e-6 (measured on dense output, 20000 samples per
  period, refined by a parabola through the three largest samples, after
  ``GRAZE_TRANSIENT`` periods: at the low default damping the transient decays as
  ``exp(-B tau / 2)`` and must have fallen far below 1e-6); no impact below, one impact per
  period above (the steady orbit is period 1), at default settings and with a smaller
  ``max_step``.  The bisection's bracket is checked: an Ec range that does not contain the
  grazing point stops the script instead of reporting a meaningless Ec.
* **1e5 periods** of free conservative motion with impacts (kh = 120, B = Bh = BT = f = Ec =
  G = 0, start (0, 0, 1.5, 0.5), rtol 1e-14, atol 1e-16), in 10 chunks of 1e4 periods, each
  continuing the last state: energy drift < 1e-7 relative, CPU time of the last chunk within
  20 % of the first, steps per period constant, peak RSS flat after the first chunk.
* **eta** from 0.01 to 10 on fig8.
* **Ec = 0** on fig8 at eta = 1.0 from rest: the run must settle on the static equilibrium
  ``Y (1 + k3 Y^2) = G`` (free flight, |Y| < 1) to 1e-10.

A case passes when it ends OK with finite data and its check holds, or ends with a clear
DIVERGED/FAILED status and reason (reported as such).  A failed check is reported as FAIL.
"""
import datetime
import os
import platform
import resource
import sys
import time
from pathlib import Path

import numpy as np
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # analyses/: _common
from _common import smoke  # noqa: E402
from _common.report import write_section  # noqa: E402

import vibimpact as vi
from vibimpact._kernel.rotor import energy

ROOT = Path(__file__).resolve().parents[2]
REPORT = ROOT / "reports" / "performance.md"

SWITCH_TOL = 1e-10          # |R - 1| at every located contact switch
CONS_START = [0.0, 0.0, 1.5, 0.5]
#: the long run of the conservative rotor: chunks of this many periods, this many chunks
LONG_CHUNK, LONG_CHUNKS = 10_000, 10


def timed(p, **kw):
    solver = vi.SolverSettings(**{k: kw.pop(k) for k in ("rtol", "atol", "max_step")
                                  if k in kw})
    t0 = time.perf_counter()
    run = vi.simulate(p, **kw, solver=solver)
    return run, time.perf_counter() - t0


def switch_error(run):
    """Largest |R - 1| at contact entries and exits (0 when there are none)."""
    sw = run.events["state"][run.events["which"] == 0]
    return float(np.abs(np.hypot(sw[:, 0], sw[:, 1]) - 1.0).max()) if len(sw) else 0.0


def sane(run):
    """OK with finite data, or a clearly labelled stop (status not OK with a reason)."""
    if run.ok:
        return bool(np.all(np.isfinite(run.strobe)))
    return bool(run.reason) and bool(np.all(np.isfinite(run.strobe)))


def energy_drift(p, states, e0):
    pa = p.as_array()
    e = np.array([energy(s, pa) for s in states])
    return float(np.abs(e - e0).max() / abs(e0))


def static_y(G, k3):
    """Root of Y (1 + k3 Y^2) = G near G (Newton)."""
    y = G
    for _ in range(50):
        y -= (y + k3 * y ** 3 - G) / (1.0 + 3.0 * k3 * y * y)
    return y


ROWS = []


def row(case, settings, run, wall, periods, check, ok, note=""):
    status = run.status.value.upper() + (f" ({run.reason})" if run.reason else "")
    if ok and not run.ok:
        verdict = "labelled stop"
    else:
        verdict = "PASS" if ok else "**FAIL**"
    if note:
        verdict += f" - {note}"
    ROWS.append((case, settings, status, f"{run.counters['steps'] / periods:.1f}",
                 str(run.counters["events"]), f"{wall:.3f}", check, verdict))
    print(" | ".join(ROWS[-1]), flush=True)


def case_kh():
    base = vi.presets.get("fig8").replace(eta=1.0)
    for kh in (1.0, 10.0, 120.0, 1e3, 1e4, 1e5):
        run, wall = timed(base.replace(kh=kh), periods=200)
        sw = switch_error(run)
        pen = float(run.impacts["penetration"].max()) if len(run.impacts) else 0.0
        pc = vi.Params(B=0.0, Bh=0.0, BT=0.0, f=0.0, Ec=0.0, G=0.0, kh=kh, eta=1.0)
        cons = vi.simulate(pc, periods=50, state0=CONS_START,
                           solver=vi.SolverSettings(rtol=1e-12, atol=1e-15))
        de = energy_drift(pc, cons.strobe, energy(np.array(CONS_START), pc.as_array()))
        ok = sane(run) and run.ok and sw < SWITCH_TOL and cons.ok and de < 1e-8
        row("stiff/soft Hertz", f"fig8 eta=1, kh={kh:g}, 200 T", run, wall, 200,
            f"max pen={pen:.2e}; \\|R-1\\|sw={sw:.0e}; conservative dE/E(50 T)={de:.1e}", ok)


def case_bh():
    base = vi.presets.get("fig8").replace(eta=1.0)
    for bh in (10.0, 20.0, 100.0):   # Bh = 5 keeps 1 + Bh R' > 0 here (min 0.18)
        run, wall = timed(base.replace(Bh=bh), periods=200)
        ev = run.events
        exits = ev["state"][(ev["which"] == 0) & (ev["mode_before"][:, 0] == 1)]
        R = np.hypot(exits[:, 0], exits[:, 1])
        rd = (exits[:, 0] * exits[:, 2] + exits[:, 1] * exits[:, 3]) / R
        fmin = float((1.0 + bh * rd).min()) if len(rd) else float("nan")
        sw = switch_error(run)
        ok = sane(run) and (not run.ok or sw < SWITCH_TOL)
        note = "" if fmin < 0 else "1+Bh*R' stayed > 0 (regime not reached)"
        row("large Hertz damping", f"fig8 eta=1, Bh={bh:g}, 200 T", run, wall, 200,
            f"min(1+Bh R') at exits={fmin:.2f}; \\|R-1\\|sw={sw:.0e}", ok and fmin < 0, note)


def case_friction():
    base = vi.presets.get("fig11").replace(eta=1.0, Rr=0.0)
    for f in (0.3, 0.6, 1.0):
        run, wall = timed(base.replace(f=f), periods=200)
        ev = run.events
        stick = int(np.sum((ev["which"] == 1) & (ev["mode_after"][:, 1] == 0)))
        spp = run.counters["steps"] / 200
        sw = switch_error(run)
        ok = sane(run) and run.ok and spp < 5000 and sw < SWITCH_TOL
        row("Coulomb friction, Rr=0", f"fig11 eta=1, f={f:g}, 200 T", run, wall, 200,
            f"stick entries={stick}; impacts={len(run.impacts)}; \\|R-1\\|sw={sw:.0e}", ok,
            "" if stick else "no stick phase at this eta")


#: periods from rest before the orbit counts as steady: the transient's factor
#: exp(-B GRAZE_TRANSIENT pi / eta) at the presets' B is below 1e-8
GRAZE_TRANSIENT = 400


def graze_rmax(p, Ec):
    """Max radius of the steady orbit (one period after GRAZE_TRANSIENT from rest), dense
    output refined by a parabola."""
    run = vi.simulate(p.replace(Ec=Ec), periods=1, transient=GRAZE_TRANSIENT, dense=20000)
    R = np.hypot(run.dense[:, 0], run.dense[:, 1])
    i = int(np.argmax(R[1:-1])) + 1
    a, b, c = R[i - 1], R[i], R[i + 1]
    return b - (a - c) ** 2 / (8.0 * (a - 2.0 * b + c))


def graze_ec(p, target, lo=0.05, hi=0.20, iters=45, scan=31):
    """The smallest Ec where the steady orbit's maximum radius reaches ``target``: the first
    sign change of ``max radius - target`` on ``scan`` values of Ec over ``[lo, hi]``,
    refined by bisection (above grazing the maximum radius is not monotonic in Ec: a
    bisection over the whole range can land on a jump of it)."""
    grid = np.linspace(lo, hi, scan)
    g = [graze_rmax(p, e) - target for e in grid]
    cell = next((i for i in range(scan - 1) if (g[i] < 0) != (g[i + 1] < 0)), None)
    if cell is None:
        raise SystemExit(f"stress.py: the grazing radius {target} is not reached for Ec in "
                         f"[{lo}, {hi}]")
    lo, hi, glo = grid[cell], grid[cell + 1], g[cell]
    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        g = graze_rmax(p, mid) - target
        if (g < 0) == (glo < 0):
            lo, glo = mid, g
        else:
            hi = mid
    return 0.5 * (lo + hi)


def case_grazing():
    base = vi.presets.get("fig8").replace(eta=0.9)
    per, tr = 50, GRAZE_TRANSIENT
    cases = [(d, None) for d in (-1e-4, -1e-5, -1e-6, 1e-6, 1e-5, 1e-4, 1e-3)]
    cases += [(1e-4, 50), (1e-5, 200)]     # the workaround: a smaller max_step (T / n)
    found = {}
    for delta, n_max in cases:
        t0 = time.perf_counter()
        if delta not in found:
            found[delta] = graze_ec(base, 1.0 + delta)
        ec = found[delta]
        t_bis = time.perf_counter() - t0
        kw = {} if n_max is None else {"max_step": base.period / n_max}
        run, wall = timed(base.replace(Ec=ec), periods=per, transient=tr, dense=20000, **kw)
        R = np.hypot(run.dense[:, 0], run.dense[:, 1])
        rm = float(R.max())
        n = len(run.impacts)
        pen = float(run.impacts["penetration"].max()) if n else float("nan")
        sw = switch_error(run)
        # the steady orbit is period 1 with one contact per period above grazing
        side_ok = (n == 0) if delta < 0 else (n == per and abs(pen - delta) < 0.05 * delta)
        ok = sane(run) and run.ok and side_ok and sw < SWITCH_TOL
        ms = "" if n_max is None else f", max_step=T/{n_max}"
        row("grazing", f"fig8 eta=0.9, Ec={ec:.10f} (Rmax=1{delta:+.0e}){ms}, {tr}+{per} T",
            run, wall, tr + per, f"impacts={n} (expected {0 if delta < 0 else per}); "
            f"max pen={pen:.3e}; max dense R-1={rm - 1:.2e}; \\|R-1\\|sw={sw:.0e}; "
            f"bisection {t_bis:.1f}s", ok,
            "" if ok or delta < 0 else "shallow contacts missed by the event detector")


def case_long():
    p = vi.Params(B=0.0, Bh=0.0, BT=0.0, f=0.0, Ec=0.0, G=0.0, kh=120.0, eta=1.0)
    y = np.array(CONS_START)
    e0 = energy(y, p.as_array())
    chunk, n_chunks = LONG_CHUNK, LONG_CHUNKS
    walls, cpus, spps, drift, rss, events, impacts = [], [], [], 0.0, [], 0, 0
    status_run = None
    for _ in range(n_chunks):
        c0 = time.process_time()
        run, wall = timed(p, periods=chunk, state0=y, rtol=1e-14, atol=1e-16)
        cpus.append(time.process_time() - c0)
        status_run = run
        walls.append(wall)
        spps.append(run.counters["steps"] / chunk)
        events += run.counters["events"]
        impacts += len(run.impacts)
        drift = max(drift, energy_drift(p, run.strobe, e0))
        if not sane(run) or not run.ok:
            break
        y = run.final_state
        del run
        rss.append(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0)  # MiB (Linux)
    slow = cpus[-1] / cpus[0]     # CPU time: robust to other processes on the machine
    spp_var = (max(spps) - min(spps)) / min(spps)
    growth = rss[-1] - rss[0] if rss else float("nan")
    ok = (status_run.ok and len(walls) == n_chunks and drift < 1e-7 and 0.8 <= slow <= 1.2
          and spp_var < 0.01 and growth < 20.0)
    status_run.counters["steps"] = int(round(np.mean(spps) * chunk * len(walls)))
    status_run.counters["events"] = events
    row("1e5 periods", "free conservative, kh=120, start (0,0,1.5,0.5), rtol 1e-14, "
        f"{n_chunks} x 1e4 T", status_run, sum(walls), chunk * len(walls),
        f"dE/E={drift:.1e}; impacts={impacts}; last/first chunk CPU time={slow:.2f} "
        f"(all chunks {min(cpus):.1f}-{max(cpus):.1f} s); "
        f"steps/T spread={spp_var:.1e}; maxRSS growth after chunk 1={growth:.1f} MiB", ok)


def case_eta():
    base = vi.presets.get("fig8")
    for eta, (tr, per) in ((0.01, (3, 10)), (0.1, (20, 50)), (1.0, (100, 100)),
                           (10.0, (300, 300))):
        p = base.replace(eta=eta)
        run, wall = timed(p, periods=per, transient=tr)
        sw = switch_error(run)
        rmax = float(np.hypot(run.strobe[:, 0], run.strobe[:, 1]).max())
        check = f"impacts={len(run.impacts)}; max strobe R={rmax:.4f}; \\|R-1\\|sw={sw:.0e}"
        ok = sane(run) and run.ok and sw < SWITCH_TOL
        if eta == 0.01:   # quasi-static: the strobe sits on the static equilibrium
            ys = static_y(p.G, p.k3)
            dev = float(np.abs(run.strobe[:, 1] - ys).max())
            check += f"; \\|Y-Y_static\\|={dev:.1e} (forcing Ec eta^2={p.Ec * eta ** 2:.0e})"
            ok = ok and dev < 2 * p.Ec * eta ** 2
        row("forcing frequency", f"fig8 eta={eta:g}, {tr}+{per} T", run, wall, tr + per,
            check, ok)


def case_ec0():
    p = vi.presets.get("fig8").replace(eta=1.0, Ec=0.0)
    ys = static_y(p.G, p.k3)
    run, wall = timed(p, periods=50, transient=100)
    dev = float(np.abs(run.strobe - [0.0, ys, 0.0, 0.0]).max())
    ok = sane(run) and run.ok and dev < 1e-10 and len(run.impacts) == 0
    row("no unbalance", "fig8 eta=1, Ec=0, from rest, 100+50 T", run, wall, 150,
        f"Y_static={ys:.12f}; max\\|s - s_static\\|={dev:.1e}; impacts={len(run.impacts)}", ok)
    run, wall = timed(p, periods=50, state0=[0.0, ys, 0.0, 0.0])
    dev = float(np.abs(run.strobe - [0.0, ys, 0.0, 0.0]).max())
    ok = sane(run) and run.ok and dev < 1e-10
    row("no unbalance", "fig8 eta=1, Ec=0, from static equilibrium, 50 T", run, wall, 50,
        f"max\\|s - s_static\\|={dev:.1e}", ok)


def main(argv=None):
    global REPORT
    out = smoke.parser(__doc__).parse_args(argv).smoke
    REPORT = smoke.moved(REPORT, out)
    smoke.shrink(globals(), out, LONG_CHUNK=100, LONG_CHUNKS=2)
    t_all = time.perf_counter()
    vi.simulate(vi.presets.get("fig8").replace(eta=1.0), periods=2, dense=2)   # compile
    for fn in (case_kh, case_bh, case_friction, case_grazing, case_eta, case_ec0, case_long):
        fn()
    total = time.perf_counter() - t_all
    n_fail = sum("FAIL" in r[-1] for r in ROWS)
    head = ("| case | settings | status | steps/period | events | wall [s] | check | verdict |\n"
            "| --- | --- | --- | --- | --- | --- | --- | --- |\n")
    table = head + "\n".join("| " + " | ".join(r) + " |" for r in ROWS)
    text = f"""## Numerical stress tests

Generated by `python analyses/performance/stress.py` on {datetime.date.today()} ({platform.machine()},
{os.cpu_count()} CPUs, Python {sys.version.split()[0]}, numba warm); total {total:.0f} s.
DOP853 at rtol 1e-9, atol 1e-12 unless the settings say otherwise.  "steps/period" counts
accepted steps per forcing period (transient included); "events" counts located switching
events (contact entries/exits, friction switches); `|R-1|sw` is the largest distance from the
retainer circle at a located contact switch (required < {SWITCH_TOL:g}).  A case passes when
it ends OK with finite data and its check holds, or stops with a DIVERGED/FAILED label and a
reason.  Fast versions of these checks are in `tests/test_stress.py`.

{table}

{n_fail} of {len(ROWS)} cases failed their check{': ' + ', '.join(r[0] + ' (' + r[1] + ')' for r in ROWS if 'FAIL' in r[-1]) if n_fail else ''}.

Grazing contacts: the switching functions are sampled at five points per step, so a
contact shorter than a quarter step does not show at the samples.  It shows at the located
peak of R (an observer event) lying beyond the retainer; the kernel then locates the entry
before that peak and resolves the contact with shorter steps
(`vibimpact/_kernel/integrator.py`, step 2).  The grazing rows check that every contact down
to 1e-6 deep is logged once per period at the default step, with the right penetration.
"""
    write_section(REPORT, "stress", text)
    print(f"wrote {REPORT} ({total:.0f} s, {n_fail} failures)")


if __name__ == "__main__":
    main()
