"""The plotting API refuses a figure too large to draw before it draws anything: a
``figsize`` or ``dpi`` that would make more pixels than the renderer can hold ended in
``MemoryError`` from Agg."""
import pytest

import vibimpact as vi
from vibimpact import _limits


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
