"""Label-level work-precision: how coarse may the integration be before the labels change,
and do the paper's missing windows appear under the integrator of its time?

For fig8, fig10 and fig11, the main job's sweep (eta 0.9:1.5:0.002 up, with
continuation, every analysis) is run on each integration method over its settings and
compared with a reference sweep (DOP853 at rtol 1e-12):

* the fraction of the 301 labels equal to the reference's;
* the largest shift of an interval end: the Hausdorff distance between the etas where
  the label changes (midway between the two grid points) in the sweep and in the
  reference (none on one side and some on the other: not finite);
* the paper's interval claims of the preset (:mod:`vibimpact.paper.claims`) judged on
  the sweep, and which of them change their verdict with the method;

against the sweep's CPU time (``time.process_time`` of a serial sweep; ``--workers``
sweeps at a time in worker processes).  The rotor is multistable, so a continued sweep whose state
differs by round-off at one point may follow another attractor from there on; the
reference's own reproducibility (DOP853 a decade looser and tighter) measures that floor,
and a *pointwise* comparison takes it out: every method analyses every eta from the
same start, the reference sweep's final state at the eta before, and its labels are
compared with the reference method's from those starts.  The methods:
``rk4-fixed-noevents`` (the era's integrator: RK4 at a fixed step, the contact switch
inside the right-hand side, no event location) at 50 ... 3,200 steps per period, the
event-located ``rk4`` at 50 ... 1,600, ``dp5`` and ``dop853`` over their tolerances
(``atol = rtol / 1000``).

Then the era question: under ``rk4-fixed-noevents`` at 50, 100, 200 and 400 steps per
period, with the shipped B and Ec and with the two best other readings of the
calibration (``reports/calibration.nc``), do the paper's claims of fig10 and fig11 hold
(both directions, judged as the paper report judges them)?

Run as ``python analyses/performance/label_precision.py [--workers N] [--smoke DIR]``
(its run time is in the section it writes).  It writes ``reports/label_precision.json``
(every number of the section), the section ``label-precision`` of
``reports/performance.md`` (rendered from that file by :func:`render`;
``tests/test_label_precision_report.py`` fails when they drift) and
``reports/figures/label_precision.png``.
"""
from __future__ import annotations

import datetime
import json
import os
import platform
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # analyses/: _common
from _common import smoke  # noqa: E402
from _common.report import write_section  # noqa: E402

ROOT = HERE.parents[1]
REPORT = ROOT / "reports" / "performance.md"
DATA = ROOT / "reports" / "label_precision.json"
FIGURE = ROOT / "reports" / "figures" / "label_precision.png"
SECTION = "label-precision"

PRESETS = ("fig8", "fig10", "fig11")
ETA = "0.9:1.5:0.002"
#: the reference sweep's method and settings
REFERENCE = ("dop853", {"rtol": 1e-12, "atol": 1e-14})
#: the reference's own reproducibility: DOP853 a decade looser and a decade tighter
FLOOR = (("dop853", {"rtol": 1e-11, "atol": 1e-13}), ("dop853", {"rtol": 1e-13, "atol": 1e-15}))
#: each method's settings, coarsest first
SETTINGS = {
    "rk4-fixed-noevents": [{"steps_per_period": n}
                           for n in (50, 100, 200, 400, 800, 1600, 3200)],
    "rk4": [{"steps_per_period": n} for n in (50, 100, 200, 400, 800, 1600)],
    "dp5": [{"rtol": r, "atol": r * 1e-3} for r in (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9)],
    "dop853": [{"rtol": r, "atol": r * 1e-3}
               for r in (1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)],
}
#: the era question: its presets, steps per period and how many calibration readings
#: besides the shipped one
ERA_PRESETS = ("fig10", "fig11")
ERA_STEPS = (50, 100, 200, 400)
ERA_READINGS = 2


#: the measured orders of the era's integrator: (preset, eta, start, periods, what the
#: contact law does at the switch), against DOP853 at rtol 1e-13
ORDER_CASES = (
    ("fig8", 0.6, (0.0, 0.0, 0.0, 0.0), 10, "no contact (impactless run)"),
    ("fig8", 1.0, (0.9, 0.0, 0.0, 0.9), 2, "Hertz force d^(3/2) alone (continuous)"),
    ("fig10", 1.2, (0.9, 0.0, 0.0, 0.9), 2, "Hertz and viscous tangential damping (jumps "
     "at entry)"),
    ("fig11", 1.06, (0.9, 0.0, 0.0, 0.9), 2, "Hertz and Coulomb friction"),
    ("soft-impact", 0.8, (0.0, 0.0), 2, "linear spring (a kink at entry)"),
    ("hard-impact", 1.3, (0.0, 0.0), 2, "restitution (an impulsive jump)"),
)
#: steps per period of the order fits: 100 ... 3200 in steps of sqrt(2) (50 ... 400
#: without contact, where RK4's error reaches round-off sooner)
ORDER_STEPS = tuple(int(x) for x in np.unique(np.round(100 * 2 ** (np.arange(11) / 2))))
ORDER_STEPS_SMOOTH = tuple(int(x) for x in np.unique(np.round(50 * 2 ** (np.arange(7) / 2))))


def orders():
    """The fitted global order of ``rk4-fixed-noevents`` on each of :data:`ORDER_CASES`:
    the least-squares slope of log(largest stroboscopic error) against log(steps)."""
    import vibimpact as vi

    out = []
    for preset, eta, state0, periods, law in ORDER_CASES:
        p = vi.presets.get(preset).replace(eta=eta)
        ref = vi.simulate(vi.System(p, solver=vi.SolverSettings(rtol=1e-13, atol=1e-15)),
                          periods=periods, transient=0, state0=list(state0))
        steps = ORDER_STEPS_SMOOTH if len(ref.impacts) == 0 else ORDER_STEPS
        err = []
        for n in steps:
            run = vi.simulate(vi.System(p, solver=vi.SolverSettings(
                method="rk4-fixed-noevents", steps_per_period=n)), periods=periods,
                transient=0, state0=list(state0))
            err.append(float(np.abs(run.strobe[1:] - ref.strobe[1:]).max()))
        slope = -float(np.polyfit(np.log(steps), np.log(err), 1)[0])
        out.append({"preset": preset, "eta": eta, "law": law, "periods": periods,
                    "contacts": int(len(ref.impacts)), "steps": list(steps),
                    "errors": err, "order": slope})
    return out


def setting_text(method, setting):
    """``400 steps`` or ``rtol 1e-08``: a setting in the report's words."""
    if "steps_per_period" in setting:
        return f"{setting['steps_per_period']} steps"
    return f"rtol {setting['rtol']:.0e}"


def _params(preset, reading=None):
    import vibimpact as vi

    p = vi.presets.get(preset)
    if reading is not None:
        p = p.replace(**reading["presets"][preset])
        p = p.replace(Ec=reading["Ec"])
    return p


def _sweep(job):
    """One sweep, serial, in a worker: its labels and claims, and its CPU time."""
    import vibimpact as vi
    from vibimpact.paper import claims as C

    preset, method, setting, direction, reading, eta = job
    params = _params(preset, reading)
    system = vi.System(params, solver=vi.SolverSettings(method=method, **setting))
    t0 = time.process_time()
    ds = vi.sweep(system, vi.grid(eta), direction=direction,
                  execution=vi.Execution(workers=1, progress=False))
    cpu = time.process_time() - t0
    up = ds.sel(direction="up") if "direction" in ds.dims else ds
    claims = {}
    for c in C.claims(preset):
        verdict, det = C.judge(ds, c)
        claims[c.key] = {"verdict": verdict, "start": _num(det.start), "end": _num(det.end)}
    return {"preset": preset, "method": method, "setting": setting,
            "direction": direction, "reading": None if reading is None else reading["name"],
            "cpu_s": cpu, "eta": [float(x) for x in up["eta"].values],
            "labels": [str(x) for x in up["label"].values], "claims": claims,
            "final_state": np.asarray(up["final_state"].values, dtype=float).tolist()}


def _pointwise(job):
    """Every eta analysed from a given start (no continuation), serial, in a worker: the
    labels and the CPU time."""
    import vibimpact as vi
    from vibimpact.core.system import with_frequency
    from vibimpact.points.point import analyse_point
    from vibimpact.sweeps.dataset import to_dataset

    preset, method, setting, eta, starts = job
    params = _params(preset)
    system = vi.System(params, solver=vi.SolverSettings(method=method, **setting))
    settings = vi.SweepSettings()
    grid = vi.grid(eta)
    t0 = time.process_time()
    results = [analyse_point(with_frequency(system, float(e)), np.asarray(x), settings)
               .as_dict() for e, x in zip(grid, starts)]
    cpu = time.process_time() - t0
    ds = to_dataset(system, grid, ["up"], {"up": results}, settings, direction="up",
                    continuation=False, blocks=1, command="")
    return {"preset": preset, "method": method, "setting": setting, "cpu_s": cpu,
            "eta": [float(x) for x in grid], "labels": [str(x) for x in ds["label"].values]}


def _num(x):
    return None if not np.isfinite(x) else float(x)


def boundaries(eta, labels):
    """The etas where the label changes, midway between the two grid points."""
    eta = np.asarray(eta, dtype=float)
    lab = np.asarray(labels, dtype=object)
    i = np.flatnonzero(lab[1:] != lab[:-1])
    return 0.5 * (eta[i] + eta[i + 1])


def hausdorff(a, b):
    """The Hausdorff distance between two sets of etas (0 for two empty ones, inf for one
    empty one)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.size == 0 and b.size == 0:
        return 0.0
    if a.size == 0 or b.size == 0:
        return float("inf")
    d = np.abs(a[:, None] - b[None, :])
    return float(max(d.min(axis=1).max(), d.min(axis=0).max()))


def compare(run, ref):
    """The comparison of one sweep with the reference: labels agreeing, the largest
    interval-end shift, the claims whose verdict differs."""
    ref_labels = np.asarray(ref["labels"], dtype=object)
    same = np.asarray(run["labels"], dtype=object) == ref_labels
    periodic = np.array([str(x).startswith("P") for x in ref_labels])
    shift = hausdorff(boundaries(run["eta"], run["labels"]),
                      boundaries(ref["eta"], ref["labels"]))
    changed = sorted(k for k, v in run["claims"].items()
                     if v["verdict"] != ref["claims"][k]["verdict"])
    return {"agree": float(same.mean()), "n_differ": int((~same).sum()),
            "n_differ_periodic": int((~same & periodic).sum()),
            "shift": None if not np.isfinite(shift) else shift, "claims_changed": changed}


def _pointwise_row(run, ref):
    """A pointwise run against the reference method's from the same starts: the labels
    that differ (all, and where the reference is periodic) and the CPU time."""
    lab, rlab = np.asarray(run["labels"], dtype=object), np.asarray(ref["labels"], dtype=object)
    periodic = np.array([str(x).startswith("P") for x in rlab])
    return {"n_differ": int((lab != rlab).sum()),
            "n_differ_periodic": int(((lab != rlab) & periodic).sum()),
            "cpu_s": run["cpu_s"]}


def _calibration_readings(n):
    """The ``n`` best readings of ``reports/calibration.nc`` other than the shipped
    winner's: ``{"name", "B", "Ec", "presets": {fig: {"B", "Bh", "BT", "f"}}}``."""
    import xarray as xr

    sys.path.insert(0, str(HERE.parent / "paper"))
    import calibrate_search as S

    with xr.open_dataset(ROOT / "reports" / "calibration.nc") as cal:
        winner = json.loads(cal.attrs["winner"])
        reading = cal["reading"].values
        objective = cal["objective"].values
        B, Ec = cal["B"].values, cal["Ec"].values
    by_name = {r.key: r for r in S.readings() if r.adoptable}
    best = []
    for name in dict.fromkeys(str(x) for x in reading):
        if name == winner["reading"] or name not in by_name:
            continue
        sel = np.flatnonzero(reading == name)
        k = sel[np.argmin(objective[sel])]
        best.append((float(objective[k]), name, float(B[k]), float(Ec[k])))
    out = []
    for obj, name, b, ec in sorted(best)[:n]:
        presets = {}
        for fig in by_name[name].figures:
            damp = S.damping_values(fig.damp)
            presets[fig.preset] = dict(damp, B=0.0 if fig.b_zero else b)
        out.append({"name": name, "text": by_name[name].text, "B": b, "Ec": ec,
                    "objective": obj, "presets": presets})
    return out


def jobs(workers):
    """Every sweep of the study, the longest first."""
    out = []
    for preset in PRESETS:
        out.append((preset, REFERENCE[0], REFERENCE[1], "up", None, ETA))
        for method, setting in FLOOR:
            out.append((preset, method, setting, "up", None, ETA))
        for method, settings in SETTINGS.items():
            for s in settings:
                out.append((preset, method, s, "up", None, ETA))
    readings = [None] + _calibration_readings(ERA_READINGS)
    for reading in readings:
        for preset in ERA_PRESETS:
            out.append((preset, REFERENCE[0], REFERENCE[1], "both", reading, ETA))
            for n in ERA_STEPS:
                out.append((preset, "rk4-fixed-noevents", {"steps_per_period": n}, "both",
                            reading, ETA))

    def cost(job):
        s = job[2]
        return s.get("steps_per_period", 0) + (1000 if s.get("rtol", 1) < 1e-10 else 0)

    return sorted(out, key=cost, reverse=True), readings


def run(workers):
    """Run the study; returns the data written to ``label_precision.json``."""
    todo, readings = jobs(workers)
    t0 = time.perf_counter()
    with ProcessPoolExecutor(workers) as pool:
        results = list(pool.map(_sweep, todo))
    key = {(r["preset"], r["method"], json.dumps(r["setting"], sort_keys=True),
            r["direction"], r["reading"]): r for r in results}
    point_jobs = []
    for preset in PRESETS:
        ref = key[(preset, REFERENCE[0], json.dumps(REFERENCE[1], sort_keys=True), "up",
                   None)]
        final = np.asarray(ref["final_state"], dtype=float)
        starts = np.vstack([np.zeros((1, final.shape[1])), final[:-1]])
        for method, setting in [REFERENCE, *FLOOR, *((m, s) for m, ss in SETTINGS.items()
                                                     for s in ss)]:
            point_jobs.append((preset, method, setting, ETA, starts))
    with ProcessPoolExecutor(workers) as pool:
        points = list(pool.map(_pointwise, sorted(point_jobs, key=lambda j: -j[2].get(
            "steps_per_period", 0))))
    wall = time.perf_counter() - t0
    pkey = {(r["preset"], r["method"], json.dumps(r["setting"], sort_keys=True)): r
            for r in points}

    def pointwise(preset, method, setting):
        return pkey[(preset, method, json.dumps(setting, sort_keys=True))]

    def get(preset, method, setting, direction="up", reading=None):
        return key[(preset, method, json.dumps(setting, sort_keys=True), direction,
                    reading)]

    precision = {}
    for preset in PRESETS:
        ref = get(preset, *REFERENCE)
        pref = pointwise(preset, *REFERENCE)
        rows = []
        for method, settings in SETTINGS.items():
            for s in settings:
                r = get(preset, method, s)
                rows.append(dict(method=method, setting=s, text=setting_text(method, s),
                                 cpu_s=r["cpu_s"], claims={k: v["verdict"] for k, v
                                                            in r["claims"].items()},
                                 pointwise=_pointwise_row(pointwise(preset, method, s),
                                                          pref),
                                 **compare(r, ref)))
        floor = [dict(method=m, setting=s, text=setting_text(m, s),
                      cpu_s=get(preset, m, s)["cpu_s"],
                      pointwise=_pointwise_row(pointwise(preset, m, s), pref),
                      **compare(get(preset, m, s), ref)) for m, s in FLOOR]
        precision[preset] = {"reference_cpu_s": ref["cpu_s"], "rows": rows,
                             "floor": floor,
                             "pointwise_reference_differ": int(sum(
                                 a != b for a, b in zip(pref["labels"], ref["labels"]))),
                             "reference_periodic": int(sum(str(x).startswith("P")
                                                           for x in ref["labels"])),
                             "reference_claims": {k: v["verdict"]
                                                  for k, v in ref["claims"].items()},
                             "reference_intervals": int(boundaries(
                                 ref["eta"], ref["labels"]).size + 1)}
    era = []
    for reading in readings:
        name = None if reading is None else reading["name"]
        for preset in ERA_PRESETS:
            ref = get(preset, *REFERENCE, "both", name)
            for c in ref["claims"]:
                row = {"reading": name or "shipped", "preset": preset, "claim": c,
                       "reference": ref["claims"][c]["verdict"], "era": {}}
                for n in ERA_STEPS:
                    r = get(preset, "rk4-fixed-noevents", {"steps_per_period": n}, "both",
                            name)
                    row["era"][str(n)] = r["claims"][c]
                era.append(row)
    import vibimpact as vi

    return {"date": datetime.date.today().isoformat(), "machine": _machine(),
            "workers": workers, "wall_s": wall, "eta": ETA, "points": int(vi.grid(ETA).size),
            "era_presets": list(ERA_PRESETS),
            "reference": {"method": REFERENCE[0], **REFERENCE[1]},
            "B": vi.presets.get("fig8").B, "Ec": vi.presets.get("fig8").Ec,
            "precision": precision, "readings": [r for r in readings if r is not None],
            "era_steps": list(ERA_STEPS), "era": era, "orders": orders()}


def _machine():
    return f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}"


def coarsest(rows, method):
    """The coarsest setting of ``method`` from which on every finer one gives all labels
    equal to the reference's (None: not even the finest)."""
    return coarsest_within(rows, method, 0)


def floor_differ(p):
    """The most labels a reference-quality sweep (:data:`FLOOR`) differs from the
    reference by: how far the labels are reproducible at all."""
    return max(f["n_differ"] for f in p["floor"])


def coarsest_within(rows, method, limit):
    """The coarsest setting of ``method`` from which on every finer one differs from the
    reference at no more than ``limit`` labels (None: not even the finest)."""
    best = None
    for r in reversed([r for r in rows if r["method"] == method]):  # finest first
        if r["n_differ"] > limit:
            break
        best = r
    return best


def _coarsest_cells(rows, methods, limit, cpu=lambda r: r["cpu_s"]):
    """One table row's cells: each method's :func:`coarsest_within` ``limit``, with its
    CPU time."""
    cells = []
    for method in methods:
        best = coarsest_within(rows, method, limit)
        cells.append("none of the settings" if best is None else
                     f"{best['text']} ({cpu(best):.1f} s)")
    return cells


def _cell(text):
    """Text for a Markdown table cell (a reading's name holds ``|``)."""
    return str(text).replace("|", "\\|")


def _fmt_shift(x):
    return "none shared" if x is None else f"{x:.3f}"


def render(data):
    """The report section, from the study's data (nothing else)."""
    lines = [
        f"Label-level work-precision ({data['date']}, {data['machine']}; "
        f"`analyses/performance/label_precision.py`, each sweep serial, "
        f"{data['workers']} at a time in worker processes, {data['wall_s'] / 60:.1f} min "
        "wall). "
        f"Each sweep is the main job's: η {data['eta']} up with continuation, every "
        f"analysis, B = {data['B']:g}, Ec = {data['Ec']:g}. Reference: "
        f"{data['reference']['method']} at rtol {data['reference']['rtol']:.0e}. "
        f"*Labels equal*: the share of the {data['points']} labels equal to the "
        "reference's. "
        "*Largest end shift*: the Hausdorff distance between the etas where the label "
        "changes in the sweep and in the reference. *Claims changed*: the paper's claims "
        "of the preset whose verdict differs from the reference's. CPU time: the "
        "serial sweep's process time.",
        "",
        "![labels equal and interval-end shift against CPU time](figures/label_precision.png)",
        "",
    ]
    lines += ["Measured global order of `rk4-fixed-noevents` (least-squares slope of the "
              "largest stroboscopic error against DOP853 at rtol 1e-13, over the steps per "
              "period shown):", "", "| preset | η | contact law at the switch | periods | "
              "contacts | steps per period | order |", "| --- | ---: | --- | ---: | ---: | "
              "--- | ---: |"]
    for o in data["orders"]:
        lines.append(f"| {o['preset']} | {o['eta']:g} | {o['law']} | {o['periods']} | "
                     f"{o['contacts']} | {o['steps'][0]}–{o['steps'][-1]} | "
                     f"{o['order']:.2f} |")
    lines.append("")
    for preset, p in data["precision"].items():
        lines += [f"**{preset}** (reference: {p['reference_cpu_s']:.1f} s CPU, "
                  f"{p['reference_intervals']} intervals, {p['reference_periodic']} of "
                  f"{data['points']} points periodic; pointwise from its own final "
                  f"states, the reference method gives {p['pointwise_reference_differ']} "
                  "other labels than its continued sweep). The first rows are the "
                  "reference's own reproducibility: DOP853 a decade looser and a decade "
                  "tighter.", "",
                  "| method | setting | CPU s | labels equal | of them where the reference "
                  "is periodic | largest end shift | claims changed | pointwise: labels "
                  "that differ (where periodic) |",
                  "| --- | --- | ---: | ---: | ---: | ---: | --- | ---: |"]
        for r in p["floor"] + p["rows"]:
            pw = r["pointwise"]
            lines.append(f"| {r['method']} | {r['text']} | {r['cpu_s']:.1f} | "
                         f"{r['agree']:.3f} ({r['n_differ']} differ) | "
                         f"{r['n_differ_periodic']} differ | "
                         f"{_fmt_shift(r['shift'])} | "
                         f"{', '.join(r['claims_changed']) or '—'} | "
                         f"{pw['n_differ']} ({pw['n_differ_periodic']}) |")
        lines.append("")
    methods = list(dict.fromkeys(r["method"] for p in data["precision"].values()
                                 for r in p["rows"]))
    lines += [f"Coarsest setting from which on every finer one gives all {data['points']} "
              "labels of the reference:", "", "| preset | " + " | ".join(methods) + " |",
              "| --- |" + " --- |" * len(methods)]
    for preset, p in data["precision"].items():
        cells = _coarsest_cells(p["rows"], methods, 0)
        lines.append(f"| {preset} | " + " | ".join(cells) + " |")
    lines += ["", "Coarsest setting from which on every finer one differs from the reference "
              "at no more labels than a reference-quality sweep does (the most of the "
              "reference-quality DOP853 sweeps above, in brackets):", "",
              "| preset | " + " | ".join(methods) + " |", "| --- |" + " --- |" * len(methods)]
    for preset, p in data["precision"].items():
        limit = floor_differ(p)
        cells = _coarsest_cells(p["rows"], methods, limit)
        lines.append(f"| {preset} ({limit}) | " + " | ".join(cells) + " |")
    lines += ["", "Pointwise (every η from the same start): coarsest setting from which on "
              "every finer one differs from the reference method at no more labels than the "
              "reference-quality DOP853 runs do pointwise (that most, in brackets):", "",
              "| preset | " + " | ".join(methods) + " |", "| --- |" + " --- |" * len(methods)]
    for preset, p in data["precision"].items():
        limit = max(f["pointwise"]["n_differ"] for f in p["floor"])
        rows = [dict(r, n_differ=r["pointwise"]["n_differ"]) for r in p["rows"]]
        cells = _coarsest_cells(rows, methods, limit, lambda r: r["pointwise"]["cpu_s"])
        lines.append(f"| {preset} ({limit}) | " + " | ".join(cells) + " |")
    lines += ["", "Claims whose verdict changes with the method (reference verdict → the "
              "settings that give another):", ""]
    any_change = False
    for p in data["precision"].values():
        for claim, ref in p["reference_claims"].items():
            other = [f"{r['method']} {r['text']}: {r['claims'][claim]}" for r in p["rows"]
                     if r["claims"][claim] != ref]
            if other:
                any_change = True
                lines.append(f"- {claim} ({ref}): " + "; ".join(other))
    if not any_change:
        lines.append("- none")
    lines += ["", "**Under the era's integrator** (`rk4-fixed-noevents`, both directions, "
              "judged as `reports/paper.md` judges): the verdict on each claim of " +
              " and ".join(data["era_presets"]) + " at " +
              ", ".join(str(n) for n in data["era_steps"]) +
              " steps per period, beside the reference's, for the shipped B and Ec and the "
              "calibration's next-best readings:", ""]
    for r in data["readings"]:
        lines.append(f"- reading {r['name']} ({r['text']}): B = {r['B']:g}, Ec = "
                     f"{r['Ec']:g}, calibration objective {r['objective']:.3f}")
    lines += ["", "| reading | claim | reference | " +
              " | ".join(f"{n} steps" for n in data["era_steps"]) + " | appears? |",
              "| --- | --- | --- |" + " --- |" * len(data["era_steps"]) + " --- |"]
    for row in data["era"]:
        cells = []
        for n in data["era_steps"]:
            e = row["era"][str(n)]
            span = "" if e["start"] is None else f" ({e['start']:.3f}–{e['end']:.3f})"
            cells.append(f"{e['verdict']}{span}")
        appears = [n for n in data["era_steps"] if row["era"][str(n)]["verdict"] == "agree"]
        yes = (f"yes at {', '.join(map(str, appears))}" if appears and
               row["reference"] != "agree" else "held by the reference too" if appears
               else "no")
        lines.append(f"| {_cell(row['reading'])} | {row['claim']} | {row['reference']} | " +
                     " | ".join(cells) + f" | {yes} |")
    return "\n".join(lines)


def plot(data, path):
    """Labels equal and the largest interval-end shift against CPU time, per preset."""
    import matplotlib
    import matplotlib.ticker

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    presets = list(data["precision"])
    fig, axes = plt.subplots(3, len(presets), figsize=(4.2 * len(presets), 9.2),
                             squeeze=False, sharex="col")
    for j, preset in enumerate(presets):
        rows = data["precision"][preset]["rows"]
        for method in dict.fromkeys(r["method"] for r in rows):
            mine = [r for r in rows if r["method"] == method]
            t = [r["cpu_s"] for r in mine]
            axes[0, j].plot(t, [r["agree"] for r in mine], "o-", ms=4, label=method)
            shift = [np.nan if r["shift"] is None else max(r["shift"], 1e-4) for r in mine]
            axes[1, j].plot(t, shift, "o-", ms=4, label=method)
            axes[2, j].plot([r["pointwise"]["cpu_s"] for r in mine],
                            [max(r["pointwise"]["n_differ"], 0.5) for r in mine], "o-",
                            ms=4, label=method)
        floor_pw = max(f["pointwise"]["n_differ"] for f in data["precision"][preset]["floor"])
        axes[2, j].axhline(max(floor_pw, 0.5), color="0.3", lw=0.8, ls=":")
        axes[2, j].set_yscale("log")
        axes[0, j].axvline(data["precision"][preset]["reference_cpu_s"], color="0.6",
                           lw=0.8, ls="--")
        worst = min(f["agree"] for f in data["precision"][preset]["floor"])
        axes[0, j].axhline(worst, color="0.3", lw=0.8, ls=":",
                           label="DOP853 a decade from the reference")
        axes[0, j].set_title(preset)
        axes[0, j].set_ylim(0, 1.02)
        axes[1, j].set_yscale("log")
        axes[1, j].set_xscale("log")
        axes[2, j].set_xlabel("CPU time of the sweep or pointwise run (s)")
        for ax in axes[:, j]:
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    axes[0, 0].set_ylabel("labels equal to the reference")
    axes[1, 0].set_ylabel("largest interval-end shift (η)")
    axes[2, 0].set_ylabel("pointwise: labels that differ")
    axes[0, 0].legend(fontsize=7)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.stem + ".tmp" + path.suffix)
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, path)


def write(data, report, data_path, figure):
    """Write the data, the figure and the section (each replaced atomically)."""
    tmp = data_path.with_name(data_path.name + ".tmp")
    tmp.write_text(json.dumps(data, indent=1) + "\n")
    os.replace(tmp, data_path)
    plot(data, figure)
    write_section(report, SECTION, render(data))


def main(argv=None):
    ap = smoke.parser(__doc__)
    ap.add_argument("--workers", type=int, default=2, help="sweeps at a time (default 2)")
    args = ap.parse_args(argv)
    report, data_path, figure = REPORT, DATA, FIGURE
    if args.smoke is not None:
        smoke.shrink(globals(), args.smoke, PRESETS=("fig10",), ETA="1.19:1.21:0.01",
                     FLOOR=(("dop853", {"rtol": 1e-7, "atol": 1e-10}),),
                     SETTINGS={"rk4-fixed-noevents": [{"steps_per_period": 50}],
                               "dop853": [{"rtol": 1e-6, "atol": 1e-9}]},
                     ERA_PRESETS=("fig10",), ERA_STEPS=(50,), ERA_READINGS=1,
                     ORDER_CASES=ORDER_CASES[:2], ORDER_STEPS=(100, 200, 400),
                     ORDER_STEPS_SMOOTH=(50, 100, 200))
        report = smoke.moved(REPORT, args.smoke)
        data_path = smoke.moved(DATA, args.smoke)
        figure = smoke.moved(FIGURE, args.smoke)
    data = run(args.workers)
    write(data, report, data_path, figure)
    print(render(data))


if __name__ == "__main__":
    main()
