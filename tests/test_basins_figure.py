"""The basins figure of the rotor is drawn as its XY figures are: the retainer marked,
equal axes, Y down; a model without a circular obstacle gets none."""
import numpy as np
import pytest

import vibimpact as vi
from vibimpact.plotting.basins import plot_basins


@pytest.fixture(scope="module")
def rotor_basins():
    """A 5 x 5 basin image of fig11 at eta = 1.06 in the (X, Y) plane."""
    return vi.basins(vi.System(vi.presets.get("fig11")), eta=1.06, grid=(5, 5),
                     plane=("X", "Y"))


def test_rotor_basins_mark_the_retainer_with_equal_axes_and_y_down(rotor_basins):
    """Hypothesis: on the rotor's (X, Y) plane the figure draws the retainer circle of
    radius 1 (every point of the dashed line at distance 1 from the origin, in the
    legend), with equal axes spanning it, and the Y axis inverted as in plot_xy."""
    fig = plot_basins(rotor_basins)
    ax = fig.axes[0]
    circles = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--"]
    assert len(circles) == 1
    r = np.hypot(*circles[0].get_data())
    np.testing.assert_allclose(r, 1.0, atol=1e-12)
    assert "retainer" in circles[0].get_label()
    assert ax.get_aspect() == 1.0 and ax.yaxis_inverted()
    lo, hi = sorted(ax.get_ylim())
    assert lo <= -1.0 and hi >= 1.0
    legend = fig.legends[0] if fig.legends else ax.get_legend()
    assert any("retainer" in t.get_text() for t in legend.get_texts())


def test_a_model_without_a_circle_gets_no_circle(tmp_path):
    """Hypothesis: a Duffing basin image (no circular obstacle) has no dashed circle and
    keeps its vertical axis upward."""
    ds = vi.basins(vi.System(vi.DuffingParams(delta=0.3, alpha=-1.0, beta=1.0, gamma=0.0,
                                              omega=1.0)), grid=(5, 5))
    ax = plot_basins(ds).axes[0]
    assert not [ln for ln in ax.get_lines() if ln.get_linestyle() == "--"]
    assert not ax.yaxis_inverted()


def test_a_one_eta_census_draws_a_bar_per_attractor_on_a_log_axis():
    """Hypothesis: the census figure of one eta draws one bar per attractor whose width
    is its basin fraction (a small basin stays visible on the log axis, down to half a
    start), labelled A<global id>, and its eta axis has the one tick of that eta."""
    from matplotlib.patches import Rectangle

    from vibimpact.census import Box
    from vibimpact.plotting.census import plot_census

    system = vi.System(vi.DuffingParams(delta=0.3, alpha=-1.0, beta=1.0, gamma=0.0,
                                        omega=1.0))
    ds = vi.attractors(system, starts=24, box=Box([-2.0, -2.0], [2.0, 2.0]))
    fig = plot_census(ds)
    top, bottom = fig.axes[:2]
    bars = [p for p in top.patches if isinstance(p, Rectangle)]
    frac = np.sort(ds.fraction.values[0][np.isfinite(ds.fraction.values[0])])
    np.testing.assert_allclose(np.sort([b.get_width() for b in bars]), frac)
    assert top.get_xscale() == "log" and top.get_xlim()[0] == 0.5 / 24
    labels = {t.get_text() for t in top.get_yticklabels()}
    assert labels == {f"A{int(g)}" for g in ds.global_id.values[0] if g >= 0}
    np.testing.assert_allclose(bottom.get_xticks(), ds.eta.values)


def test_basins_named_after_a_census_share_its_names_and_colours():
    """Hypothesis: a basin image named after a census of the same point gives each
    attractor the census' id of the same attractor (the double well's wells, told by
    the sign of x), its legend names it A<id>, and the basins and census figures fill
    it with the same colour."""
    from matplotlib.colors import to_rgba

    from vibimpact.census import Box
    from vibimpact.census.locate import name_after
    from vibimpact.plotting.census import plot_census
    from vibimpact.plotting.style import attractor_colour

    system = vi.System(vi.DuffingParams(delta=0.3, alpha=-1.0, beta=1.0, gamma=0.0,
                                        omega=1.0))
    census = vi.attractors(system, starts=24, box=Box([-2.0, -2.0], [2.0, 2.0]), seed=4)
    raw = vi.basins(system, grid=(6, 6))  # no cell on the saddle at 0
    named = name_after(raw, census)
    side = {int(g): np.sign(census.representative.values[0, a, 0])
            for a, g in enumerate(census.global_id.values[0]) if g >= 0}
    for a, g in enumerate(named.global_id.values):
        assert side[int(g)] == np.sign(named.representative.values[a, 0])
    fig = plot_basins(named)
    texts = [t.get_text() for t in (fig.legends[0] if fig.legends else
                                    fig.axes[0].get_legend()).get_texts()]
    for g in named.global_id.values:
        assert any(t.startswith(f"A{int(g)}: ") for t in texts)
    cfig = plot_census(census)
    bars = {t.get_text(): None for t in cfig.axes[0].get_yticklabels()}
    for p, label in zip(sorted(cfig.axes[0].patches, key=lambda p: p.get_y()),
                        [t.get_text() for t in cfig.axes[0].get_yticklabels()]):
        bars[label] = p.get_facecolor()
    for g in named.global_id.values:
        assert bars[f"A{int(g)}"] == to_rgba(attractor_colour(int(g)))


@pytest.mark.parametrize("make, words", [
    (lambda p: vi.save(vi.sweep(vi.presets.get("soft-impact"), [0.8]), p),
     "not an attractor census"),
    (lambda p: vi.save(vi.attractors(vi.System(vi.presets.get("soft-impact")), 0.9,
                                     starts=4), p), "holds no point at eta")])
def test_basins_census_option_refuses_what_cannot_name_it(make, words, tmp_path, capsys):
    """Hypothesis: 'vibimpact basins --census FILE' with a file that is no census, or a
    census without the basins' eta, exits 2 with one line before any work and writes
    nothing."""
    from vibimpact.cli import main

    make(tmp_path / "c.nc")
    out = tmp_path / "b.nc"
    assert main(["basins", "--preset", "soft-impact", "--eta", "0.8", "--grid", "5x5",
                 "--census", str(tmp_path / "c.nc"), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0]
    assert not out.exists()


def test_rotor_basins_start_only_the_disk_inside_the_retainer(rotor_basins):
    """Hypothesis: by default the rotor's (X, Y) image starts exactly the cells with
    X^2 + Y^2 <= 1 (inside the retainer clearance): the others hold -2, count as
    not_started, are not started in the census (its fractions, over the started cells,
    add up to 1) and are left out of the boundary cells."""
    ds = rotor_basins
    x, y = np.meshgrid(ds.X.values, ds.Y.values)
    inside = x ** 2 + y ** 2 <= 1.0
    assert not inside.all() and inside.any()
    np.testing.assert_array_equal(ds.basin.values == -2, ~inside)
    np.testing.assert_array_equal(ds.started.values, inside)
    assert int(ds.not_started) == int((~inside).sum())
    assert np.nansum(ds.fraction.values) + float(ds.failed_fraction) == pytest.approx(1.0)
    assert not ds.boundary.values[~inside].any()
    assert np.all(ds.periods.values[~inside] == 0)


def test_the_figure_greys_the_cells_not_started_and_says_so(rotor_basins):
    """Hypothesis: the cells not started are masked in the drawn image (so drawn in the
    colour map's 'bad' grey, not in an attractor's colour) and the legend says how many
    there are."""
    fig = plot_basins(rotor_basins)
    ax = fig.axes[0]
    drawn = ax.get_images()[0].get_array()
    np.testing.assert_array_equal(np.ma.getmaskarray(drawn),
                                  rotor_basins.basin.values == -2)
    legend = fig.legends[0] if fig.legends else ax.get_legend()
    n = int(rotor_basins.not_started)
    assert any(t.get_text().startswith(f"not started ({n} cells)")
               for t in legend.get_texts())


def test_everywhere_starts_the_corners_too():
    """Hypothesis: with everywhere=True no cell is left out (a 3 x 3 image of fig8 at
    eta = 1.25 whose corners lie at R = sqrt(2))."""
    ds = vi.basins(vi.System(vi.presets.get("fig8")), eta=1.25, grid=(3, 3), eps=1,
                   everywhere=True)
    assert int(ds.not_started) == 0 and np.all(ds.basin.values >= -1)
    assert bool(ds.started.values.all())
