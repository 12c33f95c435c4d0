"""The figures (issue 24, part 4): one colour scale per quantity across a map's panels,
discrete scales for integers, a categorical axis for listed values, legends that list
exactly what is drawn (hatchings explained) and stay off the data, and the size,
resolution and style asked for, in every plot kind of the API and of ``vibimpact plot``.

Every dataset here is small and made by hand: the plots only read datasets.
"""
import math

import numpy as np
import pytest
import xarray as xr
from matplotlib.collections import QuadMesh
from matplotlib.colors import BoundaryNorm, ListedColormap

from vibimpact.cli import main
from vibimpact.plotting import plot_bifurcation, plot_intervals, plot_response, plot_xy
from vibimpact.plotting.branch import plot_branch_figure
from vibimpact.plotting.map2d import is_listed, plot_map
from vibimpact.plotting.style import COLUMN_WIDTH, PAPER_STYLE

PNG = b"\x89PNG\r\n\x1a\n"


# --- small datasets ------------------------------------------------------------------

def sweep_ds(both=True, permanent=False):
    """Four eta points: P1 impactless, P2 with 4 impacts, chaotic, quasi-periodic (the
    first permanent contact instead with ``permanent``)."""
    eta = np.array([1.0, 1.1, 1.2, 1.3])
    first = "P1, permanent contact" if permanent else "P1 impactless"
    data = {"regime": np.array([1, 1, 3, 2], dtype="i1"),
            "period": np.array([1, 2, 0, 0], dtype="i4"),
            "label": np.array([first, "P2, 4 impacts", "chaotic, impacting",
                               "quasi-periodic, impacting"], dtype=object),
            "impacts_per_period": np.array([0.0, 4.0, 3.5, 2.0]),
            "arcs": np.array(["", "2 small arcs", "whole circle", "3 arcs"], dtype=object),
            "X_m": np.array([0.5, 0.9, 1.05, 1.02]), "Y_m": np.array([0.6, 0.95, 1.1, 1.0])}
    px = np.tile(np.array([0.1, 0.2, 0.3, 0.4])[:, None], (1, 8))
    if both:
        ds = xr.Dataset({k: (("direction", "eta"), np.stack([v, v])) for k, v in
                         data.items()}, coords={"eta": eta, "direction": ["up", "down"]})
        ds["poincare_X"] = (("direction", "eta", "sample"), np.stack([px, -px]))
        ds["poincare_Y"] = (("direction", "eta", "sample"), np.stack([px, px]))
    else:
        ds = xr.Dataset({k: ("eta", v) for k, v in data.items()}, coords={"eta": eta},
                        attrs={"sweep_direction": "up"})
        ds["poincare_X"] = (("eta", "sample"), px)
        ds["poincare_Y"] = (("eta", "sample"), px)
    ds.attrs.update(model="rotor", preset="fig8", param_kh=120.0, param_G=0.3)
    return ds


def run_ds():
    return xr.Dataset(
        {"strobe": (("sample", "state"), [[0.0, 0.5, 0.0, 0.0], [0.1, 0.6, 0.0, 0.0]]),
         "impact_theta": ("impact", [90.0, 45.0])},
        coords={"state": ["X", "Y", "dX", "dY"]},
        attrs={"model": "rotor", "param_eta": 1.2, "preset": "fig8"})


def branch_ds():
    """A hand-made P1 branch in eta, stable then unstable past a period doubling."""
    import vibimpact as vi
    from vibimpact.analysis import Branch
    from vibimpact.continuation.branches import branch_to_dataset

    k = 6
    mu = np.tile(np.array([0.5 + 0.1j, 0.5 - 0.1j, 0.3, 0.2]), (k, 1))
    mu[3:, 2] = -1.2
    amp = {"X_m": np.linspace(0.5, 0.9, k), "Y_m": np.linspace(0.6, 1.0, k),
           "R_m": np.linspace(0.7, 1.1, k)}
    br = Branch("eta", np.linspace(1.1, 1.2, k), np.zeros((k, 4)), mu,
                np.arange(k) < 3, amp, 1, ((3, "period doubling", 1.15),), "window end",
                ((1.14, 1.16),))
    return branch_to_dataset(br, vi.presets.get("fig8"), attrs={"preset": "fig8"})


def map_ds(vary_range="f=0,0.05"):
    """A two-direction map over f = 0, 0.05 whose exponents reach 0.15 in the up sweep
    and only 1e-4 in the down sweep, periods 1-4 and whole and mean impact counts."""
    reg = np.array([[[1, 1, 3, 2], [1, 5, 3, 1]], [[1, 1, 3, 3], [1, 1, 1, 1]]], "i1")
    per = np.array([[[1, 2, 0, 0], [1, 0, 0, 3]], [[1, 2, 0, 0], [4, 1, 1, 1]]], "i4")
    ipp = np.array([[[0, 2, 3.5, np.nan], [1, np.nan, 2.25, 3]],
                    [[0, 2, 1.5, 2.5], [4, 1, 1, 1]]])
    lam = np.array([[[np.nan, np.nan, 0.15, 0.0], [np.nan, 1e-4, 0.1, np.nan]],
                    [[np.nan, np.nan, 1e-4, -1e-4], [np.nan] * 4]])
    lab = np.array([[[f"r{a} p{b} i{c}" for a, b, c in zip(r, p, i)]
                     for r, p, i in zip(R, P, I)] for R, P, I in zip(reg, per, ipp)],
                   dtype=object)
    dims = ("direction", "f", "eta")
    attrs = {"model": "rotor", "map_vary": "f", "preset": "fig11"}
    if vary_range:
        attrs["vary_range"] = vary_range
    return xr.Dataset({"regime": (dims, reg), "period": (dims, per),
                       "impacts_per_period": (dims, ipp), "lyapunov": (dims, lam),
                       "label": (dims, lab)},
                      coords={"direction": ["up", "down"], "f": [0.0, 0.05],
                              "eta": [1.0, 1.1, 1.2, 1.3]}, attrs=attrs)


def _meshes(fig, title):
    """The QuadMesh of every panel titled ``title``, in drawing order (up, then down)."""
    return [m for ax in fig.axes if ax.get_title().startswith(title)
            for m in ax.collections if isinstance(m, QuadMesh)]


def _legend_texts(legend):
    return [t.get_text() for t in legend.get_texts()]


def _legends(fig):
    return list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]


def _renderer(fig):
    """An Agg renderer of the laid-out figure."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    return canvas.get_renderer()


# --- maps ----------------------------------------------------------------------------

def test_map_exponent_has_one_colour_scale_over_both_sweeps():
    """Hypothesis: the exponent panels of the up sweep (|lambda| up to 0.15) and the down
    sweep (up to 1e-4) share one symmetric scale, +-0.15 (it was +-0.15 and +-1e-4)."""
    fig = plot_map(map_ds())
    meshes = _meshes(fig, "largest Lyapunov exponent")
    assert len(meshes) == 2
    limits = {(m.norm.vmin, m.norm.vmax) for m in meshes}
    assert limits == {(-0.15, 0.15)}


@pytest.mark.parametrize("title, want", [
    ("period", ["no period", "P1", "P2", "P3", "P4"]),
    ("impacts", ["not computed", "0", "1", "2", "3", "4", "non-integer mean"])])
def test_map_integers_get_one_colour_per_value_present(title, want):
    """Hypothesis: period and impacts per period are drawn with a ListedColormap and a
    BoundaryNorm holding one colour per value present in either sweep (and one for
    "none"/"not computed"/mean counts when there are such points), the same scale in
    both sweeps' panels, and colour bars that name exactly those values."""
    fig = plot_map(map_ds())
    meshes = _meshes(fig, title)
    assert len(meshes) == 2
    for m in meshes:
        assert isinstance(m.cmap, ListedColormap) and isinstance(m.norm, BoundaryNorm)
        assert m.cmap.N == len(want) == m.norm.Ncmap
        np.testing.assert_array_equal(m.norm.boundaries, np.arange(len(want) + 1) - 0.5)
        assert m.colorbar is not None
        assert [t.get_text() for t in m.colorbar.ax.get_yticklabels()] == want
    rgba = [m.cmap(np.arange(len(want))) for m in meshes]
    np.testing.assert_array_equal(rgba[0], rgba[1])
    assert len({tuple(c) for c in rgba[0]}) == len(want)  # distinct colours
    codes = np.concatenate([np.ravel(m.get_array()) for m in meshes])
    assert sorted(set(codes.tolist())) == list(range(len(want)))  # every colour is used


def test_map_period_colours_do_not_depend_on_the_other_sweep():
    """Hypothesis: a period has the same colour in the up and the down panels (the down
    sweep alone has P4, which used to shift the colours of the up sweep's periods)."""
    fig = plot_map(map_ds())
    up, down = _meshes(fig, "period")
    ds = map_ds()
    for m, d in ((up, "up"), (down, "down")):
        per = ds["period"].sel(direction=d).values.ravel()
        reg = ds["regime"].sel(direction=d).values.ravel()
        codes = np.asarray(m.get_array()).ravel()
        colours = m.cmap(m.norm(codes))
        one = colours[(per == 1) & (reg == 1)]
        assert len(one) and np.allclose(one, one[0])
        if d == "up":
            p1 = one[0]
        else:
            np.testing.assert_allclose(one[0], p1)


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_listed_values_get_a_categorical_axis():
    """Hypothesis: values listed on the command line (vary_range "f=0,0.05") are rows
    0, 1 labelled with the values themselves; a range (":") keeps a numeric axis; for a
    map made in Python, unevenly spaced values are categories; categorical= decides."""
    fig = plot_map(map_ds())
    panels = [ax for ax in fig.axes if ax.get_ylabel() == "f"]
    assert panels
    for ax in panels:
        assert [t.get_text() for t in ax.get_yticklabels()] == ["0", "0.05"]
        np.testing.assert_allclose(ax.get_yticks(), [0, 1])
        assert ax.get_ylim() == (-0.5, 1.5)
    fig = plot_map(map_ds("f=0:0.05:0.05"))
    ax = [a for a in fig.axes if a.get_ylabel() == "f"][0]
    np.testing.assert_allclose(ax.get_ylim(), (-0.025, 0.075))
    assert is_listed(map_ds(None), [10.0, 20.0, 40.0, 80.0])
    assert not is_listed(map_ds(None), [10.0, 20.0, 30.0])
    ax = [a for a in plot_map(map_ds(), categorical=False).axes if a.get_ylabel() == "f"][0]
    np.testing.assert_allclose(ax.get_ylim(), (-0.025, 0.075))


def test_map_regime_legends_list_only_the_regimes_present():
    """Hypothesis: each regime panel's legend names exactly the kinds of motion in that
    panel (no entry for one that is absent)."""
    fig = plot_map(map_ds())
    legends = [ax.get_legend() for ax in fig.axes if ax.get_title() == "regime"]
    assert [_legend_texts(leg) for leg in legends] == [
        ["periodic", "quasi-periodic", "chaotic", "unsettled"], ["periodic", "chaotic"]]


# --- sweeps: legends -------------------------------------------------------------------

@pytest.mark.parametrize("permanent", [False, True])
def test_interval_legend_is_the_categories_present_and_explains_hatching(permanent):
    """Hypothesis: the interval map's legend holds one entry per colour drawn and one per
    hatching drawn, saying what the hatching means; none for absent categories (it
    always listed "impactless" and "permanent contact")."""
    fig = plot_intervals(sweep_ds(permanent=permanent))
    (leg,) = _legends(fig)
    hatch = ("dotted ...: permanent contact" if permanent else "hatched ///: impactless")
    assert _legend_texts(leg) == ["P1", "P2", "quasi-periodic", "chaotic", hatch]
    patches = leg.get_patches()
    assert patches[-1].get_hatch() == hatch.split()[1].rstrip(":")
    assert all(p.get_hatch() is None for p in patches[:-1])


def test_response_band_legend_explains_hatching_too():
    """Hypothesis: the response curves' band legend lists the same categories present
    and the hatching of impactless bands (it had no hatching entry)."""
    fig = plot_response(sweep_ds())
    bands = [leg for leg in fig.legends]
    assert len(bands) == 1
    assert _legend_texts(bands[0]) == ["P1", "P2", "quasi-periodic", "chaotic",
                                       "hatched ///: impactless"]


def _kinds():
    return {"response": lambda **kw: plot_response(sweep_ds(), **kw),
            "bifurcation": lambda **kw: plot_bifurcation(sweep_ds(), **kw),
            "intervals": lambda **kw: plot_intervals(sweep_ds(), **kw),
            "xy": lambda **kw: plot_xy(run_ds(), **kw).figure,
            "map": lambda **kw: plot_map(map_ds(), **kw),
            "branch": lambda **kw: plot_branch_figure(branch_ds(), **kw)}


@pytest.mark.parametrize("style", [None, "paper"])
@pytest.mark.parametrize("kind", list(_kinds()))
def test_legends_do_not_cover_the_data(kind, style):
    """Hypothesis: every legend of every plot kind lies outside every axes (data panels
    and colour bars) of its figure, in both styles."""
    fig = _kinds()[kind](style=style)
    renderer = _renderer(fig)
    legends = _legends(fig)
    assert legends
    for leg in legends:
        box = leg.get_window_extent(renderer)
        for ax in fig.axes:
            assert not box.overlaps(ax.get_window_extent(renderer)), (kind, ax.get_title())


# --- size, resolution, style ---------------------------------------------------------

def _png_size(path):
    from PIL import Image

    with Image.open(path) as im:
        return im.size, im.info.get("dpi")


@pytest.mark.parametrize("kind", list(_kinds()))
def test_saved_file_has_the_size_and_resolution_asked_for(kind, tmp_path):
    """Hypothesis: figsize and dpi of every plot kind give the saved PNG its pixel size
    (width x dpi, height x dpi) and resolution; the paper style's default is one column,
    3.5 inches (the map two), at 300 dpi."""
    out = tmp_path / "f.png"
    figsize = (10.0, 12.0) if kind == "map" else (4.0, 3.0)  # eight panels need room
    _kinds()[kind](path=out, figsize=figsize, dpi=20)
    size, dpi = _png_size(out)
    assert size == (figsize[0] * 20, figsize[1] * 20)
    assert dpi == pytest.approx((20, 20), rel=1e-3)
    _kinds()[kind](path=out, style="paper")
    (w, _), dpi = _png_size(out)
    columns = 2 if kind == "map" else 1
    assert w == round(COLUMN_WIDTH * columns * 300) and dpi == pytest.approx((300, 300),
                                                                            rel=1e-3)


@pytest.mark.parametrize("kind", list(_kinds()))
def test_paper_style_is_serif_thin_and_untitled(kind):
    """Hypothesis: in the paper style every text of the figure (tick labels made at
    drawing time included) is in the style's serif fonts and sizes, the title naming
    the preset is left out, and the axes lines are thinner than in the default style."""
    plain, paper = _kinds()[kind](), _kinds()[kind](style="paper")
    serif = list(PAPER_STYLE["font.family"])
    for ax in paper.axes:
        for text in [ax.xaxis.label, ax.yaxis.label] + ax.get_xticklabels() + \
                ax.get_yticklabels():
            if text.get_text():
                assert text.get_fontfamily() == serif, text.get_text()
        for t in ax.get_yticklabels():
            assert t.get_fontsize() == PAPER_STYLE["ytick.labelsize"], t.get_text()
    assert "fig" not in " ".join(ax.get_title() for ax in paper.axes)
    assert paper.get_suptitle() == ""
    assert "fig" in " ".join([ax.get_title() for ax in plain.axes] + [plain.get_suptitle()])
    assert paper.axes[0].spines["left"].get_linewidth() == PAPER_STYLE["axes.linewidth"]
    assert plain.axes[0].spines["left"].get_linewidth() > PAPER_STYLE["axes.linewidth"]


def test_paper_lines_are_thinner_than_default_lines():
    """Hypothesis: the response curves' lines scale with the style's line width."""
    plain = plot_response(sweep_ds(both=False), bands=False)
    paper = plot_response(sweep_ds(both=False), bands=False, style="paper")
    w = [max(ln.get_linewidth() for ln in f.axes[0].get_lines()) for f in (plain, paper)]
    assert w[1] == pytest.approx(w[0] * PAPER_STYLE["lines.linewidth"] / 1.5)


# --- bad figure options ----------------------------------------------------------------

@pytest.mark.parametrize("kw, name", [
    ({"figsize": (0, 3)}, "figsize"), ({"figsize": "abc"}, "figsize"),
    ({"figsize": (3, math.inf)}, "figsize"), ({"figsize": (1, 2, 3)}, "figsize"),
    ({"dpi": -1}, "dpi"), ({"dpi": 0}, "dpi"), ({"dpi": "high"}, "dpi"),
    ({"style": "nope"}, "style")])
@pytest.mark.parametrize("kind", list(_kinds()))
def test_bad_figure_options_are_refused_naming_them(kind, kw, name, tmp_path):
    """Hypothesis: every plotting function refuses a bad figsize, dpi or style with a
    ValueError naming it, before drawing, and writes nothing."""
    with pytest.raises(ValueError, match=rf"^{name} must"):
        _kinds()[kind](path=tmp_path / "f.png", **kw)
    assert list(tmp_path.iterdir()) == []


def test_given_axes_keep_their_legends_on_them():
    """Hypothesis: drawn into the caller's axes (panels of a larger figure), plot_xy and
    plot_intervals put their legend on those axes, below them, and none on the figure,
    so that several panels do not pile their legends up."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 4), layout="constrained")
    left, right = fig.subplots(1, 2)
    plot_xy(run_ds(), ax=left)
    plot_xy(run_ds(), ax=right)
    assert fig.legends == []
    for ax in (left, right):
        assert "impacts (2)" in _legend_texts(ax.get_legend())
    ax = Figure().add_subplot()
    plot_intervals(sweep_ds(), ax=ax)
    assert ax.figure.legends == [] and "P1" in _legend_texts(ax.get_legend())


def test_figsize_with_given_axes_is_refused():
    """Hypothesis: a figsize cannot size axes the caller made (their figure has its
    size), so it is refused naming figsize."""
    from matplotlib.figure import Figure

    ax = Figure().add_subplot()
    with pytest.raises(ValueError, match="figsize"):
        plot_intervals(sweep_ds(), ax=ax, figsize=(3, 2))


# --- the command line ----------------------------------------------------------------

def run_cli(argv, capfd):
    try:
        rc = main([str(a) for a in argv])
    except SystemExit as exc:
        rc = exc.code
    return (rc, *capfd.readouterr())


@pytest.mark.parametrize("name, kind, make", [
    ("s.nc", "response", lambda p: sweep_ds().to_netcdf(p)),
    ("s.nc", "bifurcation", lambda p: sweep_ds().to_netcdf(p)),
    ("s.nc", "intervals", lambda p: sweep_ds().to_netcdf(p)),
    ("r.nc", "xy", lambda p: run_ds().to_netcdf(p)),
    ("m.nc", "map", lambda p: map_ds().to_netcdf(p)),
    ("c.nc", "branch", lambda p: branch_ds().to_netcdf(p))])
def test_plot_command_takes_figsize_dpi_and_style(name, kind, make, tmp_path, monkeypatch,
                                                  capfd):
    """Hypothesis: 'vibimpact plot --figsize WxH --dpi N' gives every kind's PNG W*N x H*N
    pixels at N dpi, and '--style paper' one journal column at 300 dpi."""
    monkeypatch.chdir(tmp_path)
    make(tmp_path / name)
    w, h = (10, 12.5) if kind == "map" else (4, 2.5)
    rc, out, err = run_cli(["plot", name, "--kind", kind, "-o", "a.png", "--figsize",
                            f"{w}x{h}", "--dpi", "20"], capfd)
    assert rc == 0, err
    size, dpi = _png_size(tmp_path / "a.png")
    assert size == (w * 20, h * 20) and dpi == pytest.approx((20, 20), rel=1e-3)
    rc, out, err = run_cli(["plot", name, "--kind", kind, "-o", "b.png", "--style",
                            "paper"], capfd)
    assert rc == 0, err
    (w, _), dpi = _png_size(tmp_path / "b.png")
    assert w == round(COLUMN_WIDTH * (2 if kind == "map" else 1) * 300)


@pytest.mark.parametrize("argv, image", [
    (["simulate", "--eta", "1.2", "--periods", "3", "--transient", "3", "-o", "r.nc",
      "--plot", "xy.png"], "xy.png"),
    (["bifurcation", "--eta", "1.0,1.01", "--workers", "1", "--no-progress", "-o",
      "b.png"], "b.png")])
def test_drawing_commands_take_figsize_and_dpi(argv, image, tmp_path, monkeypatch, capfd):
    """Hypothesis: simulate --plot and bifurcation, which compute and then draw, size
    and resolve their image as --figsize and --dpi say."""
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(argv + ["--figsize", "3x2", "--dpi", "30"], capfd)
    assert rc == 0, err
    size, dpi = _png_size(tmp_path / image)
    assert size == (90, 60) and dpi == pytest.approx((30, 30), rel=1e-3)


def test_map_colour_bars_sit_beside_their_own_panels():
    """Hypothesis: every colour bar of a map (period, impacts per period, exponent) lies
    right beside the panel it belongs to -- its left edge within 2 % of the figure's width
    of the panel's right edge, at the panel's height -- and no bar of the left column has
    a side label, which would stand between the columns and read as the right panel's
    y-axis label.  (Bars given the panel with ``ax=`` floated into the column gap when
    the regime legend widened the column's margin.)"""
    fig = plot_map(map_ds())
    _renderer(fig)
    panels = [ax for ax in fig.axes if ax.get_title() in (
        "period n", "impacts per period") or ax.get_title().startswith("largest")]
    assert len(panels) == 6
    left_column = min(ax.get_position().x0 for ax in panels)
    for ax in panels:
        meshes = [m for m in ax.collections if isinstance(m, QuadMesh)]
        bar = meshes[0].colorbar
        assert bar is not None
        p, b = ax.get_position(), bar.ax.get_position()
        assert 0.0 <= b.x0 - p.x1 <= 0.02, ax.get_title()
        assert p.y0 <= b.y0 and b.y1 <= p.y1
        if p.x0 == left_column:
            assert bar.ax.get_ylabel() == ""
