"""A reviewer's points on the figures of a paper, checked on the drawn artists:

* the map: ticks of the varied parameter at its sampled values, the grey cells of the
  exponent panel explained, outlines only between different regimes;
* the XY plot: a loaded-arc legend that does not call gapped arcs the whole circle, the
  last periods of a long trajectory drawn prominently, the stroboscopic points on top;
* the bifurcation diagram: regime bands from the dataset in the response plot's colours,
  and up and down sweeps that both show where they coincide;
* the response plot in the paper style: markers that do not crowd their neighbours.

Every dataset is small and made by hand (one short run for the XY trajectory): the plots
only read datasets.
"""
import numpy as np
import pytest
import xarray as xr
from matplotlib.collections import LineCollection
from matplotlib.colors import to_rgb, to_rgba
from matplotlib.patches import Rectangle

import vibimpact as vi
from vibimpact.analysis import contact_arcs
from vibimpact.plotting import plot_bifurcation, plot_response, plot_xy
from vibimpact.plotting._sweep import REGIME_NAMES
from vibimpact.plotting.map2d import MAX_VALUE_TICKS, _edges, plot_map
from vibimpact.plotting.map_panels import MISSING
from vibimpact.plotting.style import class_color
from vibimpact.plotting.xy_dense import LAST_PERIODS

ETA = np.array([1.0, 1.1, 1.2, 1.3])


# --- small datasets ------------------------------------------------------------------

def map_ds(values, reg=None, per=None, lam=None, name="kh"):
    """A one-direction map over ``name`` = ``values`` (a range: ``vary_range`` with a
    colon) and :data:`ETA`; by default every row P1, P1, P2, chaotic (the label changes
    inside the periodic regime), exponents only at the chaotic points."""
    n = len(values)
    reg = np.tile([1, 1, 1, 3], (n, 1)) if reg is None else np.asarray(reg)
    per = np.tile([1, 1, 2, 0], (n, 1)) if per is None else np.asarray(per)
    if lam is None:
        lam = np.where(reg == 3, 0.1, np.nan)
    ipp = np.where(reg == 1, 2.0 * per, 3.5)
    lab = np.array([[f"r{r} P{p}" for r, p in zip(R, Pp)] for R, Pp in zip(reg, per)],
                   dtype=object)
    dims = (name, "eta")
    return xr.Dataset(
        {"regime": (dims, reg.astype("i1")), "period": (dims, per.astype("i4")),
         "impacts_per_period": (dims, ipp), "lyapunov": (dims, np.asarray(lam, float)),
         "label": (dims, lab)},
        coords={name: np.asarray(values, float), "eta": ETA},
        attrs={"model": "rotor", "map_vary": name, "preset": "fig8",
               "sweep_direction": "up",
               "vary_range": f"{name}={values[0]:g}:{values[-1]:g}:"
                             f"{values[1] - values[0]:g}"})


def run_ds(theta_min, theta_max):
    """A run's dataset with two stroboscopic samples and contacts from ``theta_min`` to
    ``theta_max`` (degrees), no trajectory."""
    return xr.Dataset(
        {"strobe": (("sample", "state"), [[0.0, 0.5, 0.0, 0.0], [0.1, 0.6, 0.0, 0.0]]),
         "impact_theta": ("impact", np.asarray(theta_min, float)),
         "impact_theta_min": ("impact", np.asarray(theta_min, float)),
         "impact_theta_max": ("impact", np.asarray(theta_max, float))},
        coords={"state": ["X", "Y", "dX", "dY"]},
        attrs={"model": "rotor", "param_eta": 1.2, "preset": "fig8"})


def sweep_ds(n=4, same=False):
    """A two-direction sweep of ``n`` eta points from 0.9 to 1.5: the up sweep's regimes
    P1, chaotic, P2, quasi-periodic, ... and the down sweep's P1, P3, unsettled, ...;
    8 Poincaré samples a point, the same in both sweeps with ``same``."""
    eta = np.linspace(0.9, 1.5, n)
    up_r, up_p = np.resize([1, 3, 1, 2], n), np.resize([1, 0, 2, 0], n)
    dn_r, dn_p = np.resize([1, 1, 5], n), np.resize([1, 3, 0], n)
    reg, per = np.stack([up_r, dn_r]), np.stack([up_p, dn_p])
    lab = np.array([[f"r{r} P{p}" for r, p in zip(R, Pp)] for R, Pp in zip(reg, per)],
                   dtype=object)
    px = np.sin(np.arange(n)[:, None] + np.linspace(0.0, 1.0, 8)[None, :])
    dims = ("direction", "eta")
    ds = xr.Dataset(
        {"regime": (dims, reg.astype("i1")), "period": (dims, per.astype("i4")),
         "label": (dims, lab), "impacts_per_period": (dims, np.full(reg.shape, 2.0)),
         "arcs": (dims, np.full(reg.shape, "2 small arcs", dtype=object)),
         "X_m": (dims, np.stack([0.5 + 0.01 * np.arange(n)] * 2)),
         "Y_m": (dims, np.stack([0.6 + 0.01 * np.arange(n)] * 2)),
         "poincare_X": (dims + ("sample",), np.stack([px, px if same else -px])),
         "poincare_Y": (dims + ("sample",), np.stack([px, px if same else 0.5 * px]))},
        coords={"eta": eta, "direction": ["up", "down"]})
    ds.attrs.update(model="rotor", preset="fig8", param_kh=120.0, param_G=0.3)
    return ds


def _panels(fig):
    return [ax for ax in fig.axes if ax.get_title()]


# --- the map ---------------------------------------------------------------------------

def test_map_parameter_ticks_are_the_sampled_values_on_the_cells_extent():
    """Hypothesis: a map over kh = 10, 65, 120 has its kh ticks exactly at 10, 65, 120,
    labelled with them (matplotlib's automatic ticks were 0, 20, ..., 140), and its kh
    axis spans the cells, half a step beyond the end values, in every panel."""
    values = [10.0, 65.0, 120.0]
    fig = plot_map(map_ds(values))
    ye = _edges(values)
    for ax in _panels(fig):
        assert ax.get_yticks().tolist() == values, ax.get_title()
        assert ax.get_ylim() == pytest.approx((ye[0], ye[-1]))
    left = [ax for ax in _panels(fig) if ax.get_ylabel() == "kh"]
    assert left
    for ax in left:
        assert [t.get_text() for t in ax.get_yticklabels()] == ["10", "65", "120"]


def test_map_parameter_ticks_are_thinned_keeping_both_ends():
    """Hypothesis: with more sampled values than fit (kh = 10, 20, ..., 150) the ticks
    are a subset of the sampled values, at most MAX_VALUE_TICKS of them, more than two,
    the first and the last value among them."""
    values = list(np.arange(10.0, 151.0, 10.0))
    assert len(values) > MAX_VALUE_TICKS
    ticks = _panels(plot_map(map_ds(values)))[0].get_yticks().tolist()
    assert 2 < len(ticks) <= MAX_VALUE_TICKS
    assert set(ticks) <= set(values)
    assert ticks[0] == values[0] and ticks[-1] == values[-1]


def _swatches(fig):
    """The figure's axes (insets of its panels included) that hold a patch of the missing
    grey, with their tick texts."""
    out = []
    for ax in fig.axes + [c for a in fig.axes for c in a.child_axes]:
        grey = [p for p in ax.patches
                if np.allclose(p.get_facecolor(), to_rgba(MISSING))]
        if grey:
            out.append((ax, " ".join(t.get_text() for t in ax.get_yticklabels())))
    return out


@pytest.mark.parametrize("chaotic_nan", [False, True])
def test_map_grey_exponent_cells_are_explained_beside_the_bar(chaotic_nan):
    """Hypothesis: the exponent panel, which draws the points without an exponent grey,
    has a grey swatch beside it (under its colour bar) that says "not computed" and names
    the regimes of those points in the dataset: "periodic" when only periodic points lack
    one, "periodic, chaotic" when a chaotic point's exponent is NaN too."""
    ds = map_ds([10.0, 65.0, 120.0])
    if chaotic_nan:
        ds["lyapunov"][0, 3] = np.nan
    fig = plot_map(ds)
    (panel,) = [ax for ax in fig.axes if ax.get_title().startswith("largest")]
    grey = ~np.isfinite(ds["lyapunov"].values)
    names = [REGIME_NAMES[int(c)] for c in np.unique(ds["regime"].values[grey])]
    fig.draw_without_rendering()
    near = [(ax, text) for ax, text in _swatches(fig)
            if ax.get_position().x0 >= panel.get_position().x1
            and panel.get_position().y0 <= ax.get_position().y0 <= panel.get_position().y1]
    assert len(near) == 1, _swatches(fig)
    text = near[0][1]
    assert "not computed" in text and f"({', '.join(names)})" in text


def _cell(edges, x):
    """Index of the cell between ``edges`` whose edge ``x`` is the upper one."""
    return int(np.argmin(np.abs(np.asarray(edges) - x))) - 1


def test_map_outlines_lie_only_between_different_regimes():
    """Hypothesis: where the label changes inside one regime (P1 to P2, periodic both)
    no outline is drawn: every segment of every panel's outlines (and of the regime map
    under bifurcation curves) separates two cells of different regime, and every pair of
    neighbouring cells of different regime is separated by one."""
    from vibimpact.plotting.bifurcation_curves import _draw_map

    values = [10.0, 65.0, 120.0]
    reg = np.array([[1, 1, 1, 3], [1, 1, 3, 3], [1, 1, 1, 1]])
    per = np.array([[1, 1, 2, 0], [1, 2, 0, 0], [1, 1, 2, 2]])
    ds = map_ds(values, reg=reg, per=per)
    xe, ye = _edges(ETA), _edges(values)
    want = int((reg[:, 1:] != reg[:, :-1]).sum() + (reg[1:] != reg[:-1]).sum())
    from matplotlib.figure import Figure

    under = Figure().subplots()
    _draw_map(under, ds, "kh", None)
    for ax in _panels(plot_map(ds)) + [under]:
        (lines,) = [c for c in ax.collections if isinstance(c, LineCollection)]
        segs = lines.get_segments()
        assert len(segs) == want, ax.get_title()
        for (x0, y0), (x1, y1) in segs:
            if x0 == x1:      # vertical: between eta cells i and i + 1 of row j
                i, j = _cell(xe, x0), _cell(ye, max(y0, y1))
                assert reg[j, i] != reg[j, i + 1]
            else:             # horizontal: between rows j and j + 1 at eta cell i
                i, j = _cell(xe, max(x0, x1)), _cell(ye, y0)
                assert reg[j, i] != reg[j + 1, i]


# --- the XY plot -----------------------------------------------------------------------

def _arc_label(ax):
    (label,) = [ln.get_label() for ln in ax.get_lines()
                if str(ln.get_label()).startswith("loaded arcs")]
    return label


def test_xy_arc_legend_does_not_call_gapped_arcs_the_whole_circle():
    """Hypothesis: two arcs, -97..-88 and -14..-160 degrees, whose gaps are all under
    90 degrees (the analysis calls them "whole circle"), are listed in the legend with
    their count, their extents as the analysis writes them and their largest gap, and
    without the words "whole circle"; contacts that do cover the circle are called the
    whole circle, with no contradicting extent."""
    ds = run_ds([-97.0, -14.0], [-88.0, 200.0])
    arcs = contact_arcs(ds)
    assert arcs.summary == "whole circle" and arcs.n_arcs == 2   # the case of the review
    label = _arc_label(plot_xy(ds, figsize=(3.0, 3.3), dpi=60))
    assert "whole circle" not in label
    extents = str(arcs).removeprefix(arcs.summary).strip()
    assert "2 arcs" in label and extents in label
    assert f"{arcs.largest_gap:.0f}°" in label
    full = _arc_label(plot_xy(run_ds([0.0, 170.0], [180.0, 370.0]), figsize=(3.0, 3.3),
                              dpi=60))
    assert contact_arcs(run_ds([0.0, 170.0], [180.0, 370.0])).width[0] == 360.0
    assert full == "loaded arcs: whole circle"


@pytest.fixture(scope="module")
def long_run():
    """fig8 at eta = 1.25 (chaotic), 30 recorded periods of 16 dense samples, as a
    dataset without its start (its own samples are drawn: nothing integrated again)."""
    p = vi.presets.get("fig8").replace(eta=1.25)
    run = vi.simulate(p, periods=30, transient=20, state0=[1.0, 0.0, 0.0, 1.25], dense=16)
    return run.to_dataset().drop_vars("state0")


def test_xy_draws_the_last_periods_prominently_and_the_strobe_on_top(long_run):
    """Hypothesis: of a 30-period trajectory the line labelled as the trajectory holds
    exactly the samples of the last LAST_PERIODS periods and says so; the earlier samples
    (joined at the sample between) are one fainter, thinner, grey line whose label names
    its periods; the stroboscopic points are drawn above both lines and the impacts."""
    ax = plot_xy(long_run, figsize=(3.0, 3.3), dpi=60)
    traj = long_run["trajectory"].values
    n = long_run.sizes["sample"] - 1
    per = (len(traj) - 1) // n
    lines = {str(ln.get_label()): ln for ln in ax.get_lines()}
    (recent,) = [ln for k, ln in lines.items() if k.startswith("trajectory")]
    (earlier,) = [ln for k, ln in lines.items() if k.startswith("earlier")]
    assert recent.get_label() == f"trajectory, last {LAST_PERIODS} of {n} periods"
    assert earlier.get_label() == f"earlier {n - LAST_PERIODS} periods (faint)"
    cut = (n - LAST_PERIODS) * per
    np.testing.assert_array_equal(recent.get_xdata(), traj[cut:, 0])
    np.testing.assert_array_equal(earlier.get_xdata(), traj[:cut + 1, 0])
    assert earlier.get_alpha() < recent.get_alpha()
    assert earlier.get_linewidth() < recent.get_linewidth()
    r, g, b = to_rgb(earlier.get_color())
    assert r == g == b
    (strobe,) = [ln for k, ln in lines.items() if k.startswith("stroboscopic")]
    (impacts,) = [ln for k, ln in lines.items() if k.startswith("impacts")]
    assert strobe.get_zorder() > max(recent.get_zorder(), earlier.get_zorder(),
                                     impacts.get_zorder())


# --- the bifurcation diagram -------------------------------------------------------------

def _half(p):
    """0 for a band in the upper half of its axes (the up sweep's), 1 for the lower."""
    return 0 if p.get_y() >= 0.5 - 1e-12 else 1


@pytest.mark.parametrize("style", [None, "paper"])
def test_bifurcation_bands_have_the_regime_colours_of_the_dataset(style):
    """Hypothesis: behind the Poincaré points of every panel, the band around each eta
    of each sweep (up sweep: upper half, down: lower half) has the colour the response
    and interval plots give that point's regime and period (class_color), and the legend
    below names each class present."""
    ds = sweep_ds(6)
    fig = plot_bifurcation(ds, style=style)
    names = set()
    for ax in fig.axes:
        bands = [p for p in ax.patches if isinstance(p, Rectangle)]
        assert bands
        for row, d in enumerate(["up", "down"]):
            sub = ds.sel(direction=d)
            for e, r, per in zip(ds["eta"].values, sub["regime"].values,
                                 sub["period"].values):
                color, name, _ = class_color(int(r), int(per))
                names.add(name)
                (band,) = [p for p in bands if _half(p) == row and
                           p.get_x() < e < p.get_x() + p.get_width()]
                assert np.allclose(band.get_facecolor()[:3], to_rgb(color)), (d, e)
    texts = {t.get_text() for leg in fig.legends for t in leg.get_texts()}
    assert names <= texts


@pytest.mark.parametrize("style", [None, "paper"])
def test_coinciding_up_and_down_points_both_show(style):
    """Hypothesis: where the up and down sweeps find the same Poincaré points, both are
    drawn at those points and both show: the up sweep's filled dot is smaller than the
    inside of the down sweep's hollow ring (dot size < ring size - ring edge), and the
    legend tells the two marks apart."""
    ds = sweep_ds(4, same=True)
    fig = plot_bifurcation(ds, style=style)
    for ax in fig.axes:
        up, down = [ln for ln in ax.get_lines() if str(ln.get_label()).startswith("sweep")]
        np.testing.assert_array_equal(up.get_ydata(), down.get_ydata())
        np.testing.assert_array_equal(up.get_xdata(), down.get_xdata())
        assert down.get_markerfacecolor() == "none"
        assert up.get_markerfacecolor() != "none"
        assert up.get_markersize() < down.get_markersize() - down.get_markeredgewidth()
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert len(set(labels)) == 2 and all(lab.startswith("sweep") for lab in labels)


# --- the response plot in the paper style ------------------------------------------------

def test_paper_response_markers_do_not_overlap_their_neighbours():
    """Hypothesis: in the paper style (one 3.5 inch column) a sweep of 61 points from
    0.9 to 1.5 (as `vibimpact classify --eta 0.9:1.5:0.01`) draws every marker of the
    response curves (dots, and the crosses of chaotic, quasi-periodic and unsettled
    points) narrower than the distance between neighbouring points on the laid-out
    figure."""
    fig = plot_response(sweep_ds(61), style="paper")
    fig.draw_without_rendering()
    for ax in fig.axes:
        x0, x1 = ax.transData.transform([[0.9, 0.0], [0.91, 0.0]])[:, 0]
        spacing_pt = (x1 - x0) * 72.0 / fig.dpi
        marked = [ln for ln in ax.get_lines() if ln.get_marker() not in ("None", None, "")]
        assert {ln.get_marker() for ln in marked} >= {".", "x", "+", "1"}
        for ln in marked:
            assert ln.get_markersize() < spacing_pt, (ln.get_label(), spacing_pt)
