"""Every figure of a sweep refuses what it cannot draw right, from Python and from the
command line alike, and the bifurcation command's labels are those of classify."""
import numpy as np
import pytest

import vibimpact as vi
from vibimpact.cli import main
from vibimpact.plotting.needs import NEEDS, missing

#: fig8's chaos band: points the period test alone leaves unsettled
GRID = "1.1:1.26:0.04"


@pytest.fixture(scope="module")
def sweeps():
    """fig8 sweeps over its chaos band, each without one analysis a figure needs."""
    p = vi.presets.get("fig8")
    eta = vi.grid(GRID)
    return {a: vi.sweep(p, eta, analyses=a, direction="up") for a in
            [("period", "poincare"), ("period", "lyapunov", "floquet"),
             ("period", "poincare", "lyapunov", "test01", "floquet", "response")]}


CASES = [  # (figure, its function, analyses of the sweep, the analysis it names)
    ("lyapunov", "plot_lyapunov", ("period", "poincare"), "lyapunov"),
    ("intervals", "plot_intervals", ("period", "poincare"), "lyapunov"),
    ("poincare", "plot_poincare", ("period", "lyapunov", "floquet"), "poincare"),
    ("bifurcation", "plot_bifurcation", ("period", "lyapunov", "floquet"), "poincare"),
    ("response", "plot_response", ("period", "lyapunov", "floquet"), "response"),
]


@pytest.mark.parametrize("kind, func, analyses, name", CASES)
def test_a_plot_function_refuses_a_sweep_without_its_analysis(kind, func, analyses, name,
                                                             sweeps, tmp_path):
    """Hypothesis: a plotting function given a sweep that did not run the analysis its
    figure shows raises a one-line ValueError naming that analysis, and writes no
    image; the sweep with every analysis is drawn."""
    ds = sweeps[analyses]
    assert missing(ds, kind) is not None
    out = tmp_path / "f.png"
    with pytest.raises(ValueError, match=name) as err:
        getattr(vi.plotting, func)(ds, path=out)
    assert "\n" not in str(err.value) and not out.exists()
    full = sweeps[("period", "poincare", "lyapunov", "test01", "floquet", "response")]
    assert missing(full, kind) is None
    getattr(vi.plotting, func)(full, path=out)
    assert out.exists()


@pytest.mark.parametrize("kind, func, analyses, name", CASES)
def test_the_cli_refuses_the_same_in_one_line(kind, func, analyses, name, sweeps,
                                             tmp_path, capsys):
    """Hypothesis: 'vibimpact plot FILE --kind K' of the same file exits 2 with one line
    naming the analysis to add (--analyses including it), and writes no image."""
    path = tmp_path / "s.nc"
    vi.io.write_netcdf(sweeps[analyses], path)
    out = tmp_path / "f.png"
    assert main(["plot", str(path), "--kind", kind, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"--analyses including {name}" in err[0]
    assert not out.exists()


def test_every_sweep_figure_of_plot_has_its_needs_declared():
    """Hypothesis: every figure 'vibimpact plot' draws from a sweep file except xy (a run)
    has its needs in the one table the plots and the command line read."""
    from vibimpact.cli.plot import DRAWS

    assert set(DRAWS["sweep"]) == set(NEEDS)


def test_bifurcation_labels_are_those_of_classify(tmp_path, capsys):
    """Hypothesis: 'vibimpact bifurcation' computes what a label needs, so that at every
    eta and direction of fig8's chaos band its labels and regimes equal classify's on
    the same grid, none of them 'unsettled' where classify says chaotic, and its
    --kind intervals figure is drawn (not refused)."""
    argv = ["--eta", GRID, "--preset", "fig8", "--no-progress"]
    assert main(["bifurcation", *argv, "-o", str(tmp_path / "b.png")]) == 0
    assert main(["classify", *argv, "--direction", "both", "-o",
                 str(tmp_path / "c.nc")]) == 0
    b, c = (vi.io.read_netcdf(tmp_path / f) for f in ("b.nc", "c.nc"))
    np.testing.assert_array_equal(b.label.values, c.label.values)
    np.testing.assert_array_equal(b.regime.values, c.regime.values)
    assert (c.label.values.astype(str) != "").all()
    assert main(["plot", str(tmp_path / "b.nc"), "--kind", "intervals", "-o",
                 str(tmp_path / "i.png")]) == 0
    capsys.readouterr()


def test_a_user_model_sweep_gets_no_rotor_response_plot(tmp_path):
    """Hypothesis: plot_response of a Duffing sweep (no planar contact: no X_m, Y_m)
    raises a ValueError naming X_m and writes nothing, instead of drawing empty axes."""
    ds = vi.sweep(vi.System(vi.DuffingParams(gamma=0.35)), vi.grid("1.29:1.32:0.015"),
                  direction="up")
    with pytest.raises(ValueError, match="X_m"):
        vi.plotting.plot_response(ds, path=tmp_path / "r.png")
    assert not (tmp_path / "r.png").exists()
