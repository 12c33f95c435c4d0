"""The rotor's hand-written variational functions against the generic ones (issue 42,
item 4: one saltation).

Run as ``python analyses/performance/variational_bench.py`` (or through
``performance.py``); replaces the section ``variational`` of ``reports/performance.md``
(``--smoke DIR``: a tiny run writing under DIR).  Every number written is measured here, in
one run, on the fig11 parameters (friction and tangential damping on):

(a) the variational right-hand side (state plus 4 tangent vectors, the Lyapunov
    spectrum's size) in contact, slipping: the rotor's hand-written
    :func:`vibimpact._kernel.rotor.var_rhs` (its Jacobian as scalars) against the
    generic :func:`vibimpact._kernel.variational.tangent_rhs` over the rotor's ``rhs``
    and ``jac`` (a Jacobian array per call);
(b) the variational mode change at a contact entry (saltation of 4 tangent vectors):
    the rotor's hand-written ``var_transition`` as it was at commit ``e349227`` (read
    from git, with the saltation it called) against the one generic
    :func:`vibimpact._kernel.variational.saltation_transition` that replaced it;
(c) what each costs per forcing period of a variational run: a run at fig11, eta =
    1.06 (200 periods after 200 of transient) counts its right-hand sides and events per
    period; each count times (a) and (b).

The right-hand side runs at every stage of every step, the mode change only at events.

Each is the best of 5 repetitions of a compiled loop of calls (the copy of the state
each call needs is in both loops).  A hand-written function is kept when what it saves
per period, (c), is more than :data:`KEEP` of the right-hand side's time per period.
"""
from __future__ import annotations

import ast
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # analyses/: _common
from _common import smoke  # noqa: E402
from _common.report import write_section  # noqa: E402

import vibimpact as vi  # noqa: E402
from vibimpact._kernel import jitopts, rotor, variational  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
REPORT = ROOT / "reports" / "performance.md"
SECTION = "variational"
OLD_COMMIT = "e349227"
CALLS, REPEATS, COLUMNS = 200_000, 5, 4
#: a hand-written function is kept when it saves more than this share of a period
KEEP = 0.01


def _old_functions():
    """The hand-written ``var_transition`` of ``rotor.py`` at :data:`OLD_COMMIT` and the
    ``apply_saltation`` of ``variational.py`` it called, compiled here (not cached)."""
    ns = {"np": np, "njit": njit}
    for k in ("INNER", "INNER_ALLOC", "LEAF"):
        ns[k] = {o: v for o, v in getattr(jitopts, k).items() if o != "cache"}
    for path, names in (("vibimpact/_kernel/variational.py", ("apply_saltation", "fd_step")),
                        ("vibimpact/_kernel/rotor.py", ("var_transition",))):
        src = subprocess.run(["git", "show", f"{OLD_COMMIT}:{path}"], cwd=ROOT, check=True,
                             capture_output=True, text=True).stdout
        lines = src.splitlines()
        for node in ast.parse(src).body:
            if isinstance(node, ast.FunctionDef) and node.name in names:
                first = min(d.lineno for d in node.decorator_list) - 1
                exec("\n".join(lines[first:node.end_lineno]), ns)
    ns.update(rhs=rotor.rhs, switches=rotor.switches, transition=rotor.transition,
              N_SWITCH=rotor.N_SWITCH)
    return ns["var_transition"]


@njit
def _loop_rhs(f, calls, s, y, p, mode, out):
    acc = 0.0
    for k in range(calls):
        f(s + 1e-9 * k, y, p, mode, out)
        acc += out[-1]
    return acc


@njit
def _loop_transition(f, calls, s, y0, p, mode0, which):
    acc = 0.0
    y = y0.copy()
    mode = mode0.copy()
    for _ in range(calls):
        y[:] = y0
        mode[:] = mode0
        f(s, y, p, mode, which)
        acc += y[-1]
    return acc


def _best(fn):
    fn()  # compiled, warm
    best = float("inf")
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best / CALLS * 1e9, out


def measure():
    """``{name: (hand-written ns per call, generic ns per call, results equal)}``."""
    p = vi.presets.get("fig11").replace(eta=1.06).as_array()
    rng = np.random.default_rng(1)
    tang = rng.standard_normal(4 * COLUMNS)
    y_in = np.r_[1.01 * np.cos(0.3), 1.01 * np.sin(0.3), -0.2, 0.4, tang]
    mode_in = np.array([1, 1], dtype=np.int64)
    out = np.empty_like(y_in)
    generic_rhs = variational.tangent_rhs(rotor.rhs, rotor.jac, rotor.N_STATE)
    hand = _best(lambda: _loop_rhs(rotor.var_rhs, CALLS, 0.3, y_in, p, mode_in, out))
    gen = _best(lambda: _loop_rhs(generic_rhs, CALLS, 0.3, y_in, p, mode_in, out))
    res = {"var_rhs": (hand[0], gen[0], hand[1] == gen[1])}
    y_ev = np.r_[np.cos(0.3), np.sin(0.3), 0.3 * np.cos(0.3) - 0.2 * np.sin(0.3),
                 0.3 * np.sin(0.3) + 0.2 * np.cos(0.3), tang]
    mode_ev = np.array([0, 0], dtype=np.int64)
    old = _old_functions()
    generic_tr = rotor.KERNEL_MODEL.var_transition
    hand = _best(lambda: _loop_transition(old, CALLS, 0.3, y_ev, p, mode_ev, 0))
    gen = _best(lambda: _loop_transition(generic_tr, CALLS, 0.3, y_ev, p, mode_ev, 0))
    res["var_transition"] = (hand[0], gen[0], hand[1] == gen[1])
    run = vi.simulate(vi.presets.get("fig11").replace(eta=1.06), periods=200,
                      transient=200)
    per = {k: run.counters[k] / 200 for k in ("rhs_evals", "events")}
    return res, per


def report(measured):
    res, per = measured
    rows = ["| function | hand-written, ns/call | generic, ns/call | generic / hand | "
            "same result |", "|---|---|---|---|---|"]
    verdicts = []
    counts = {"var_rhs": per["rhs_evals"], "var_transition": per["events"]}
    budget = per["rhs_evals"] * res["var_rhs"][0]  # ns per period, hand-written rhs
    for name, (hand, gen, same) in res.items():
        rows.append(f"| `{name}` | {hand:.1f} | {gen:.1f} | {gen / hand:.2f} | "
                    f"{'yes' if same else 'no'} |")
        share = counts[name] * (gen - hand) / budget
        verdicts.append(f"* `{name}`: the hand-written one saves {share:.1%} of a "
                        "variational period's right-hand-side time: "
                        + ("kept (more than 1 %), tested equal to the generic one"
                           if share > KEEP else "the generic one replaces it (1 % or less)"))
    return "\n".join([
        "# The rotor's variational functions: hand-written against generic (issue 42)",
        "",
        "Written by `analyses/performance/variational_bench.py` (fig11 parameters, "
        f"{COLUMNS} tangent vectors, best of {REPEATS} loops of {CALLS:,} calls; "
        f"`var_transition`'s hand-written version is the one of commit {OLD_COMMIT}).",
        "", *rows, "", *verdicts, "",
        f"(c) Per forcing period at fig11, eta 1.06: {per['rhs_evals']:.0f} right-hand sides, "
        f"{per['events']:.1f} events.  The right-hand side costs "
        f"{per['rhs_evals'] * res['var_rhs'][0] / 1e3:.1f} us (hand-written) or "
        f"{per['rhs_evals'] * res['var_rhs'][1] / 1e3:.1f} us (generic) per period; the mode "
        f"change {per['events'] * res['var_transition'][0] / 1e3:.2f} us (hand-written) or "
        f"{per['events'] * res['var_transition'][1] / 1e3:.2f} us (generic)."])


def main(argv=None):
    opts = smoke.parser(__doc__).parse_args(argv)
    smoke.shrink(globals(), opts.smoke, CALLS=1000, REPEATS=1)
    text = report(measure())
    write_section(smoke.moved(REPORT, opts.smoke), SECTION, text)
    print(text)


if __name__ == "__main__":
    main()
