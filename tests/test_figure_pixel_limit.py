"""The plotting API refuses a figure too large to draw before it draws anything: a
``figsize`` or ``dpi`` that would make more pixels than the renderer can hold ended in
``MemoryError`` from Agg."""
import pytest

import vibimpact as vi
from vibimpact.base import _limits


@pytest.fixture(scope="module")
def sweep():
    return vi.sweep(vi.presets.get("fig8"), [1.0, 1.01], analyses=())


@pytest.fixture(scope="module")
def run():
    return vi.simulate(vi.presets.get("fig8"), periods=3, transient=0, dense=16)


@pytest.mark.parametrize("kw", [dict(figsize=(1e9, 1e9)), dict(dpi=1e6),
                                dict(figsize=(100.0, 100.0), dpi=1000.0),
                                dict(figsize=(70000.0, 1.0), dpi=1.0 + 0.5)],
                         ids=["figsize", "dpi", "both", "one side"])
@pytest.mark.parametrize("name", ["plot_xy", "plot_response", "plot_bifurcation"])
def test_a_figure_beyond_the_pixel_limit_is_a_value_error_naming_figsize_and_dpi(run, sweep,
                                                                                 name, kw):
    """Hypothesis: every size whose pixels exceed the limit in total or along one side
    raises ValueError naming figsize and dpi, with the size in pixels (a run's figure
    and a sweep's alike)."""
    import vibimpact.plotting as P

    with pytest.raises(ValueError, match=r"^figsize, dpi: .*pixels"):
        getattr(P, name)(run if name == "plot_xy" else sweep, **kw)


def test_a_figure_just_inside_the_limit_is_drawn(run):
    """Hypothesis: the limit refuses only what exceeds it: a figure of exactly
    MAX_SIDE_PIXELS along one side (and few pixels in all) is drawn."""
    from vibimpact.plotting import plot_xy

    fig = plot_xy(run, figsize=(_limits.MAX_SIDE_PIXELS / 100.0, 3.0), dpi=100.0).figure
    w, h = fig.get_size_inches() * fig.dpi
    assert round(w) == _limits.MAX_SIDE_PIXELS and w * h <= _limits.MAX_PIXELS


@pytest.mark.parametrize("kw", [dict(dpi=1e-300), dict(dpi=1.0), dict(dpi=10.0),
                                dict(figsize=(0.001, 0.001), dpi=1.0),
                                dict(figsize=(65536.0, 1.0), dpi=1.0),
                                dict(figsize=(0.004, 0.004)),
                                dict(figsize=(3.0, 1e-300), dpi=300.0)],
                         ids=["dpi-1e-300", "dpi-1", "dpi-10", "tiny-both", "wide-dpi-1",
                              "tiny-figsize", "flat"])
@pytest.mark.parametrize("name", ["plot_xy", "plot_response", "plot_bifurcation"])
def test_a_figure_too_small_to_draw_is_a_value_error_before_drawing(run, sweep, name, kw):
    """Hypothesis: a side under one pixel (at the style's smallest resolution when dpi
    is not given), or a dpi at which the styles' smallest text is under one pixel
    (FreeType cannot raster it: "invalid ppem", "cannot write empty image"), raises
    ValueError naming figsize and dpi, for a run's figure and a sweep's alike."""
    import vibimpact.plotting as P

    with pytest.raises(ValueError, match=r"^figsize, dpi: .*(1 pixel)"):
        getattr(P, name)(run if name == "plot_xy" else sweep, **kw)


def test_the_smallest_resolution_allowed_draws_the_smallest_text(run, tmp_path):
    """Hypothesis: the lower limits are the renderer's, not too strict: at the smallest
    dpi allowed (the smallest text exactly one pixel) and a figure one pixel high at the
    styles' smallest resolution, the figures are written, in both styles; the
    one-pixel figure has no room for its layout, which matplotlib says."""
    from vibimpact.plotting import plot_xy
    from vibimpact.plotting.style import DPI, smallest_text_pt

    dpi = 72.0 / smallest_text_pt()
    for style in ("default", "paper"):
        plot_xy(run, figsize=(3.0, 3.0), dpi=dpi, style=style, path=tmp_path / "a.png")
        with pytest.warns(UserWarning, match="constrained_layout not applied"):
            plot_xy(run, figsize=(3.0, 1.0 / min(DPI.values())), style=style,
                    path=tmp_path / "b.png")
    assert (tmp_path / "a.png").stat().st_size > 0 and (tmp_path / "b.png").stat().st_size > 0


def test_the_smallest_text_is_the_styles_smallest_font_shrunk_for_subscripts():
    """Hypothesis: smallest_text_pt follows the styles: it is below every font size a
    style sets (so a style with smaller text lowers it) and is the paper style's
    'small' 8 pt text shrunk by mathtext for subscripts."""
    from matplotlib._mathtext import SHRINK_FACTOR
    from matplotlib.font_manager import font_scalings

    from vibimpact.plotting.style import PAPER_STYLE, STYLES, smallest_text_pt

    sizes = [v for st in STYLES.values() for k, v in st.items()
             if k.endswith(("fontsize", "labelsize", "titlesize", "font.size"))
             and isinstance(v, float)]
    assert smallest_text_pt() < min(sizes)
    assert smallest_text_pt() == pytest.approx(
        PAPER_STYLE["font.size"] * font_scalings["small"] * SHRINK_FACTOR)


@pytest.mark.parametrize("argv", [
    ["bifurcation", "--eta", "1.0:1.1:0.05", "--dpi", "1e-300", "-o", "b.png"],
    ["bifurcation", "--eta", "1.0:1.1:0.05", "--figsize", "0.001x0.001", "--dpi", "1",
     "-o", "b.png"],
    ["bifurcation", "--eta", "1.0:1.1:0.05", "--figsize", "65536x1", "--dpi", "1",
     "-o", "b.png"],
    ["simulate", "--periods", "1", "-o", "s.nc", "--plot", "s.png", "--figsize",
     "0.004x0.004"],
    ["map", "--eta", "1.0:1.01:0.01", "--vary", "B=0:0.01:0.01", "--plot", "m.png",
     "--dpi", "10"],
], ids=["dpi-1e-300", "tiny", "wide", "simulate-figsize", "map-dpi"])
def test_the_command_line_refuses_a_figure_too_small_before_any_work(argv, tmp_path,
                                                                     monkeypatch, capfd):
    """Hypothesis: every drawing command refuses, before it computes anything, a
    --figsize/--dpi whose image has a side or its smallest text under one pixel (one
    error line naming the options, exit 2, nothing written)."""
    from test_bad_input_round3_cli import _refused

    line = _refused(argv, tmp_path, monkeypatch, capfd)
    assert "--" in line and "1 pixel" in line and "larger" in line
