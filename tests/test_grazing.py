"""Grazing along a continued branch (issue 29, point 4).

Known result: fig8's impacting period-1 orbit (reached by stepping eta up from 1.1 as a
sweep does) has two impacts per period up to a grazing, where its free flight touches
the retainer with zero normal velocity and a third impact appears, a little below the
Neimark-Sacker point (eta ~ 1.1955) where the sweep's P1 interval ends.  No Floquet
multiplier crosses the unit circle at the grazing: only the impacts per period change.

Measured (refine_grazing from the branch's two orbits around it, tol 1e-10): the
grazing lies in [1.1914109734, 1.1914109736]; GRAZING_ETA below is that value to 8
decimals.  The tolerances of the tests follow from the refinement's width.
"""
import contextlib
import io as stdio

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.analysis.stability_change import impacts_per_period, refine_grazing
from vibimpact.base.bifurcation_kinds import BifurcationKind
from vibimpact.continuation.branches import branch_from_dataset
from vibimpact.cli import main

#: the grazing of fig8's P1, measured to 2e-10 (module docstring), rounded to 1e-8
GRAZING_ETA = 1.19141097
#: its rounding
ROUNDING = 5e-9
#: the command's refinement width (its --refine default)
REFINE = 1e-6
CONTINUE = ["continue", "--preset", "fig8", "--eta", "1.185", "--approach", "1.1",
            "--transient", "200", "--stop", "1.2"]


def run(*args):
    """``vibimpact ARGS`` in this process: ``(status, stdout, stderr)``."""
    out, err = stdio.StringIO(), stdio.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main([str(a) for a in args])
        except SystemExit as exc:
            rc = exc.code
    return rc, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def continued(tmp_path_factory):
    """fig8's P1 continued from eta 1.185 to 1.2 by the command line: (dataset, branch,
    printed output)."""
    path = tmp_path_factory.mktemp("grazing") / "p1.nc"
    rc, out, err = run(*CONTINUE, "-o", path)
    assert rc == 0, err
    ds = vi.io.read_netcdf(path)
    return ds, branch_from_dataset(ds), out


def _grazings(branch):
    """``(index, value, bracket, (before, after))`` of each grazing of ``branch``."""
    return [(i, v, b, imp) for (i, k, v), b, imp in
            zip(branch.bifurcations, branch.brackets, branch.event_impacts)
            if k is BifurcationKind.GRAZING]


def test_continuation_reports_the_grazing_where_a_third_impact_appears(continued):
    """Hypothesis: the fig8 P1 branch holds exactly one grazing, in [1.185, 1.1955],
    its bracket refined to the command's --refine width, with 2 impacts per period
    before it and 3 after; its value lies within half that width (plus the rounding
    of the measured value) of the grazing measured to 2e-10; no multiplier crosses the
    unit circle there (the orbits on both sides are stable)."""
    _, br, _ = continued
    [(i, value, (lo, hi), impacts)] = _grazings(br)
    assert 1.185 <= lo < hi <= 1.1955
    assert hi - lo <= REFINE
    assert impacts == (2, 3)
    assert abs(value - GRAZING_ETA) <= 0.5 * REFINE + ROUNDING
    assert list(br.impacts_per_period[i - 1:i + 1]) == [2, 3]
    assert br.stable[i - 1] and br.stable[i]


def test_the_command_prints_the_grazing_like_the_other_bifurcations(continued):
    """Hypothesis: the summary prints the grazing line as it prints a bifurcation
    (kind, value, bracket, |mu|max on both sides) with the impacts before and after,
    and the Neimark-Sacker point after it."""
    _, br, out = continued
    [(i, value, (lo, hi), _)] = _grazings(br)
    line = [s for s in out.splitlines() if s.strip().startswith("grazing")]
    assert line == [f"  grazing at eta = {value:.7g} in [{lo:.8g}, {hi:.8g}]; |mu|max "
                    f"{np.abs(br.multipliers[i - 1]).max():.6f} -> "
                    f"{np.abs(br.multipliers[i]).max():.6f}; impacts per period 2 -> 3"]
    assert "Neimark-Sacker at eta = 1.19" in out


def test_the_file_stores_the_grazing_with_its_kind_and_impacts(continued):
    """Hypothesis: the branch file holds the grazing as GRAZING's code with the impacts
    before and after, and the impacts per period of every orbit."""
    ds, br, _ = continued
    sel = ds["bifurcation_kind"].values == BifurcationKind.GRAZING.code
    assert sel.sum() == 1
    assert int(ds["bifurcation_impacts_before"].values[sel][0]) == 2
    assert int(ds["bifurcation_impacts_after"].values[sel][0]) == 3
    ipp = ds["impacts_per_period"].values
    assert set(ipp) == {2, 3} and np.all(np.diff(ipp) >= 0)


def test_plain_simulation_sees_the_impacts_change_across_the_bracket(continued):
    """Hypothesis: independent of shooting, the motion integrated 200 periods from the
    branch's orbits has 2 impacts per period 1e-5 below the bracket and 3 impacts per
    period 1e-5 above it."""
    _, br, _ = continued
    [(i, _, (lo, hi), _)] = _grazings(br)
    fig8 = vi.presets.get("fig8")
    counts = []
    for eta, x in ((lo - 1e-5, br.states[i - 1]), (hi + 1e-5, br.states[i])):
        run_ = vi.simulate(fig8.replace(eta=eta), periods=20, transient=200, state0=x,
                           solver=vi.SolverSettings(rtol=1e-10, atol=1e-12))
        counts.append(run_.impacts.size / 20)
    assert counts == [2.0, 3.0]


def test_a_finer_refinement_narrows_inside_the_bracket(continued):
    """Hypothesis: refine_grazing from the two branch orbits around the grazing at a
    width 100 times finer returns a bracket inside the command's (bisection keeps the
    side with each end's impacts), with the same impacts at its ends."""
    _, br, _ = continued
    [(i, _, (lo, hi), _)] = _grazings(br)
    system = vi.System(vi.presets.get("fig8"))
    fine = refine_grazing(system, "eta", 1, (br.values[i - 1], br.values[i]),
                          (br.states[i - 1], br.states[i]), tol=REFINE / 100)
    assert fine.kind is BifurcationKind.GRAZING
    assert fine.impacts == (2, 3)
    assert lo <= min(fine.bracket) < max(fine.bracket) <= hi
    assert abs(fine.bracket[1] - fine.bracket[0]) <= REFINE / 100
    for v, x, count in zip(fine.bracket, fine.states, fine.impacts):
        assert impacts_per_period(system.with_param("eta", v), x, 1) == count


def test_refine_grazing_refuses_two_ends_with_the_same_impacts(continued):
    """Hypothesis: two orbits with the same impacts per period bracket no grazing:
    refine_grazing raises ValueError naming values."""
    _, br, _ = continued
    system = vi.System(vi.presets.get("fig8"))
    with pytest.raises(ValueError, match="values"):
        refine_grazing(system, "eta", 1, (br.values[0], br.values[1]),
                       (br.states[0], br.states[1]))


def test_the_branch_plot_marks_the_grazing(continued):
    """Hypothesis: the branch figure draws a marker at the grazing's value with the
    grazing's words in the legend."""
    from matplotlib.figure import Figure

    from vibimpact.plotting.branch import BIFURCATION_MARKERS, plot_branch

    ds, br, _ = continued
    [(_, value, _, _)] = _grazings(br)
    ax = Figure().add_subplot()
    artists = plot_branch(ax, ds, "X_m", label="P1")
    marks = [a for a in artists
             if a.get_marker() == BIFURCATION_MARKERS[BifurcationKind.GRAZING]]
    assert len(marks) == 1 and marks[0].get_xdata()[0] == value
    assert BifurcationKind.GRAZING.words in ax.get_legend_handles_labels()[1]
