"""``vibimpact continue`` and the branch figures (issue 24, part 2).

Known result: fig8's impacting period-1 orbit (two impacts per period), reached at
eta = 1.12 by stepping eta up from 1.1 as a sweep does, loses stability through a
complex pair of Floquet multipliers (Neimark-Sacker) where the sweep's P1 interval
ends.  The command's value is checked against the API
(:func:`vibimpact.analysis.continue_orbit` from the same start), against a
``vibimpact classify`` sweep, and against the branch's own multipliers.
"""
import contextlib
import io as stdio
import subprocess
import sys

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.base.bifurcation_kinds import BifurcationKind
from vibimpact.cli import main

START = ["--preset", "fig8", "--eta", "1.12", "--approach", "1.1", "--transient", "200"]
CONTINUE = ["continue", *START, "--stop", "1.25"]
SWEEP = ["classify", "--eta", "1.1:1.21:0.002", "--analyses", "period,response",
         "--workers", "1", "--no-progress"]


def run(*args):
    """``vibimpact ARGS`` in this process: ``(status, stdout, stderr)``."""
    out, err = stdio.StringIO(), stdio.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main([str(a) for a in args])
        except SystemExit as exc:
            rc = exc.code
    return rc, out.getvalue(), err.getvalue()


def test_help_has_examples_and_is_light():
    """Hypothesis: 'vibimpact continue --help' exits 0 with examples of the command and
    of the plots of its file, without importing numpy, numba, xarray or matplotlib."""
    code = ("import sys\nfrom vibimpact.cli import main\ntry:\n    main(['continue', "
            "'--help'])\nexcept SystemExit as e:\n    rc = e.code\nheavy = [m for m in "
            "('numba', 'numpy', 'xarray', 'matplotlib') if m in sys.modules]\n"
            "print('HEAVY', heavy, 'RC', rc)\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       timeout=60)
    assert "HEAVY [] RC 0" in r.stdout, r.stderr
    for example in ("vibimpact continue --preset fig8 --eta 1.12 --stop 1.25",
                    "vibimpact plot p1.nc", "--kind response --branch p1.nc"):
        assert example in r.stdout


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """The branch of CONTINUE and the sweep of SWEEP, written by the command line."""
    d = tmp_path_factory.mktemp("continue")
    rc, out, err = run(*CONTINUE, "-o", d / "p1.nc")
    assert rc == 0, err
    rc2, _, err2 = run(*SWEEP, "-o", d / "sweep.nc")
    assert rc2 == 0, err2
    return d, out


def _ns(ds):
    """The one Neimark-Sacker bifurcation of a branch file: (value, lower, upper)."""
    sel = ds["bifurcation_kind"].values == BifurcationKind.NEIMARK_SACKER.code
    assert sel.sum() == 1, ds["bifurcation_kind"].values
    return tuple(float(ds[v].values[sel][0]) for v in
                 ("bifurcation_value", "bifurcation_lower", "bifurcation_upper"))


def test_cli_finds_the_neimark_sacker_point_the_api_finds(files):
    """Hypothesis: the command continues the same orbit as the API does from the same
    start (the state reached by continued_state from 1.1), so its file holds the same
    Neimark-Sacker value bit for bit (after the grazing where the orbit gains its
    third impact), and the printed summary names both."""
    from vibimpact.analysis import continue_orbit
    from vibimpact.sweeps import continued_state

    d, out = files
    ds = vi.io.read_netcdf(d / "p1.nc")
    p = vi.presets.get("fig8").replace(eta=1.12)
    x0 = continued_state(p, 1.12, eta_start=1.1, transient=200)
    np.testing.assert_array_equal(ds["start_state"].values, x0)
    br = continue_orbit(vi.System(p), x0, param="eta", stop=1.25, refine=1e-6)
    kinds = [k for _, k, _ in br.bifurcations]
    assert kinds == [BifurcationKind.GRAZING, BifurcationKind.NEIMARK_SACKER]
    value, lo, hi = _ns(ds)
    assert value == br.bifurcations[1][2]
    assert (lo, hi) == tuple(sorted(br.brackets[1]))
    np.testing.assert_array_equal(ds["eta"].values, br.values)
    assert f"Neimark-Sacker at eta = {value:.7g}" in out
    graze = br.bifurcations[0][2]
    assert f"grazing at eta = {graze:.7g}" in out
    assert "impacts per period 2 -> 3" in out


def test_the_bifurcation_is_where_the_multipliers_leave_the_unit_circle(files):
    """Hypothesis: the refined interval is at most --refine wide and holds the value;
    every orbit below it is stable and every orbit above it unstable (|mu|max < 1 and
    > 1), and at the unstable end the largest multipliers are a complex pair."""
    d, _ = files
    ds = vi.io.read_netcdf(d / "p1.nc")
    value, lo, hi = _ns(ds)
    assert lo <= value <= hi and 0 < hi - lo <= 1e-6
    eta, mu = ds["eta"].values, ds["floquet_abs_max"].values
    stable = ds["stable"].values.astype(bool)
    assert np.all(stable[eta <= lo]) and not np.any(stable[eta >= hi])
    assert np.all(mu[eta <= lo] < 1.0) and np.all(mu[eta >= hi] > 1.0)
    k = int(np.flatnonzero(eta == hi)[0])
    top = ds["floquet_real"].values[k, :2] + 1j * ds["floquet_imag"].values[k, :2]
    assert abs(top[0].imag) > 0.1 and np.isclose(top[0], np.conj(top[1]))


def test_the_bifurcation_ends_the_sweeps_p1_interval(files):
    """Hypothesis: the sweep follows the same orbit while it is stable, so the last
    period-1 point of the sweep's first interval run (from 1.1) lies below the
    Neimark-Sacker value and the next grid point, no longer period 1, above it."""
    d, _ = files
    value, _, _ = _ns(vi.io.read_netcdf(d / "p1.nc"))
    sweep = vi.io.read_netcdf(d / "sweep.nc")
    eta = sweep["eta"].values
    p1 = (sweep["regime"].values == 1) & (sweep["period"].values == 1)
    assert p1[0]
    end = int(np.argmin(p1)) - 1  # the last point of the first run of P1
    assert 0 < end < eta.size - 1
    assert eta[end] < value < eta[end + 1]


def test_sweep_and_branch_agree_while_the_orbit_is_stable(files):
    """Hypothesis: on the stable part of the branch the sweep's response amplitudes are
    those of the continued orbit (same attractor): X_m and Y_m of the sweep, interpolated
    on its 0.002 grid at the branch's orbits up to its last P1 point, differ by less than
    1e-3 clearance from the orbits' (measured: a few 1e-4, the sweep's sampled maxima)."""
    d, _ = files
    br = vi.io.read_netcdf(d / "p1.nc")
    sweep = vi.io.read_netcdf(d / "sweep.nc")
    eta = sweep["eta"].values
    p1 = (sweep["regime"].values == 1) & (sweep["period"].values == 1)
    last = eta[int(np.argmin(p1)) - 1]
    on = br["eta"].values <= last
    assert on.sum() > 10 and np.all(br["stable"].values[on] == 1)
    for name in ("X_m", "Y_m"):
        s = np.interp(br["eta"].values[on], eta, sweep[name].values)
        assert np.abs(s - br[name].values[on]).max() < 1e-3, name


def _styles(lines):
    """``(colour, linestyle, marker, marker edge and face colours)`` of each matplotlib
    Line2D: what a reader sees of it."""
    from matplotlib.colors import to_rgba

    return {(to_rgba(h.get_color()), h.get_linestyle(), str(h.get_marker()),
             to_rgba(h.get_markeredgecolor()), to_rgba(h.get_markerfacecolor()))
            for h in lines}


def _assert_legend_explains_every_line(fig):
    """Every line or marker style drawn on the figure's axes has a legend entry."""
    drawn, shown = set(), set()
    for ax in fig.axes:
        drawn |= _styles(line for line in ax.get_lines() if len(line.get_xdata()))
        leg = ax.get_legend()
        if leg is not None:
            shown |= _styles(h for h in leg.legend_handles if hasattr(h, "get_marker"))
    assert drawn and drawn <= shown, drawn - shown


def test_overlay_legend_explains_every_line_and_marker(files):
    """Hypothesis: over the response curves, each style drawn (the sweep's curve and
    markers, the clearance, the branch's stable and unstable parts, the Neimark-Sacker
    marker) has a legend entry with that style, and the branch's parts are drawn solid
    and dashed."""
    from vibimpact.plotting import plot_response
    from vibimpact.plotting.branch import overlay_branches

    d, _ = files
    fig = plot_response(vi.io.read_netcdf(d / "sweep.nc"))
    arts = overlay_branches(fig.axes[:2], [vi.io.read_netcdf(d / "p1.nc")], ["p1.nc"])
    assert {a.get_linestyle() for a in arts if len(a.get_xdata()) > 1} == {"-", "--"}
    _assert_legend_explains_every_line(fig)
    labels = fig.axes[0].get_legend_handles_labels()[1]
    assert any(lab.startswith("Neimark") for lab in labels)
    assert "P1 branch, p1.nc (unstable)" in labels


def test_branch_figure_legend_explains_every_line_and_marker(files):
    """Hypothesis: the figure of 'plot --kind branch' draws X_m, Y_m and |mu|max with
    the stability boundary |mu| = 1, and every style drawn is in its legend."""
    from vibimpact.plotting.branch import plot_branch_figure

    d, _ = files
    fig = plot_branch_figure(vi.io.read_netcdf(d / "p1.nc"))
    assert len(fig.axes) == 3
    _assert_legend_explains_every_line(fig)


def test_plot_commands_write_the_branch_figures(files):
    """Hypothesis: 'vibimpact plot' draws a branch file as --kind branch by default and
    overlays --branch files on a sweep's response curves; each writes its PNG."""
    d, _ = files
    rc, out, err = run("plot", d / "p1.nc")
    assert rc == 0, err
    assert (d / "p1_branch.png").stat().st_size > 10_000
    rc, out, err = run("plot", d / "sweep.nc", "--kind", "response", "--branch",
                       d / "p1.nc", "-o", d / "overlay.png")
    assert rc == 0, err
    assert (d / "overlay.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_dataset_round_trip_gives_the_branch_back(files):
    """Hypothesis: branch_from_dataset inverts branch_to_dataset through a file: the
    parameter, states, multipliers, stability, amplitudes and bifurcations come back
    equal."""
    from vibimpact.continuation.branches import branch_from_dataset, branch_to_dataset

    d, _ = files
    back = branch_from_dataset(vi.io.read_netcdf(d / "p1.nc"))
    again = branch_to_dataset(back, vi.System(vi.presets.get("fig8").replace(eta=1.12)))
    first = vi.io.read_netcdf(d / "p1.nc")
    for name in again.data_vars:
        np.testing.assert_array_equal(again[name].values, first[name].values, name)
    assert back.param == "eta" and back.n == 1
    assert [k for _, k, _ in back.bifurcations] == [BifurcationKind.GRAZING,
                                                    BifurcationKind.NEIMARK_SACKER]
    assert back.event_impacts[0] == (2, 3)
    np.testing.assert_array_equal(back.impacts_per_period, first["impacts_per_period"])


def test_refine_off_gives_the_interpolated_value_of_the_plain_branch():
    """Hypothesis: without refinement the branch is continue_orbit's unrefined one; its
    interpolated Neimark-Sacker value lies within one continuation step of the refined
    one (the steps are at most ds_max = 0.02 apart)."""
    from vibimpact.analysis import continue_orbit
    from vibimpact.continuation.branches import follow_branch

    p = vi.presets.get("fig8").replace(eta=1.12)
    br, x0 = follow_branch(p, stop=1.25, approach=1.1, transient=200, refine=None)
    plain = continue_orbit(vi.System(p), x0, param="eta", stop=1.25)
    np.testing.assert_array_equal(br.values, plain.values)
    fine = continue_orbit(vi.System(p), x0, param="eta", stop=1.25, refine=1e-6)
    [(i, v)] = [(i, v) for i, k, v in br.bifurcations
                if k is BifurcationKind.NEIMARK_SACKER]
    [vf] = [v for _, k, v in fine.bifurcations if k is BifurcationKind.NEIMARK_SACKER]
    assert br.values[i - 1] < v < br.values[i]
    assert abs(v - vf) < 0.02 and fine.values.size == br.values.size + 2


def test_folds_of_a_duffing_branch_are_turning_points_in_file_and_figure():
    """Hypothesis: a branch round the two folds of a hardening Duffing oscillator's
    response (omega 0.8 to 1.6) is written with two turning_point bifurcations (flag 1)
    whose interval is the point itself, the middle part between them unstable and the
    outer parts stable; refinement leaves turning points alone; the branch figure (no
    rotor amplitudes: x_m and |mu|max) explains both line styles and the fold marker."""
    from vibimpact.analysis import Steps, continue_orbit
    from vibimpact.continuation.branches import branch_to_dataset
    from vibimpact.plotting.branch import plot_branch_figure

    p = vi.DuffingParams(delta=0.1, alpha=1.0, beta=0.05, gamma=0.5, omega=0.8)
    x0 = vi.simulate(p, periods=1, transient=400).final_state
    br = continue_orbit(vi.System(p), x0, param="omega", stop=(0.8, 1.6),
                        steps=Steps(ds=0.02, ds_max=0.05), refine=1e-6)
    ds = branch_to_dataset(br, vi.System(p))
    kinds = ds["bifurcation_kind"].values
    assert list(kinds) == [BifurcationKind.TURNING_POINT.code] * 2
    np.testing.assert_array_equal(ds["bifurcation_lower"].values,
                                  ds["bifurcation_upper"].values)
    i, j = ds["bifurcation_point"].values
    st = ds["stable"].values
    assert np.all(st[:i] == 1) and np.all(st[i + 1:j] == 0) and np.all(st[j + 1:] == 1)
    fig = plot_branch_figure(ds)
    assert len(fig.axes) == 3  # x_m, dx_m, |mu|max
    _assert_legend_explains_every_line(fig)
    labels = fig.axes[0].get_legend_handles_labels()[1]
    assert "fold (turning point)" in labels
