"""XY plots: loaded arcs drawn on the retainer from start to end, and trajectories sampled
finely enough for the eye (no polygon of sparse samples), on every path to the plot: the
API with a Run or a dataset, a NetCDF file read back, and ``vibimpact simulate --plot``."""
import numpy as np
import pytest

import vibimpact as vi
from vibimpact.analysis import contact_arcs
from vibimpact.io import read_netcdf, write_netcdf
from vibimpact.plotting import plot_xy
from vibimpact.plotting.xy_dense import MAX_SEGMENT_PX

#: dense samples per period the runs are made with: far too few for a chaotic motion
COARSE = 16
#: a small figure (fewer samples to draw: cheaper tests)
SMALL = dict(figsize=(3.0, 3.3), dpi=100)


def _line(ax, label):
    lines = [ln for ln in ax.get_lines() if str(ln.get_label()).startswith(label)]
    assert lines, [ln.get_label() for ln in ax.get_lines()]
    return lines


def _longest_segment_px(ax):
    """Longest straight segment of the drawn trajectory, in pixels of the laid-out
    figure."""
    ax.figure.draw_without_rendering()
    (line,) = _line(ax, "trajectory")
    xy = ax.transData.transform(np.column_stack(line.get_data()))
    return float(np.hypot(*np.diff(xy, axis=0).T).max()), line


@pytest.fixture(scope="module")
def chaos():
    """fig8 at eta = 1.25 (chaotic, impacts round the whole retainer), 16 dense samples a
    period."""
    p = vi.presets.get("fig8").replace(eta=1.25)
    return vi.simulate(p, periods=3, transient=40, state0=[1.0, 0.0, 0.0, 1.25],
                       dense=COARSE)


def _coarse_segment_px(run, ax):
    """Longest segment the run's own samples would draw in ``ax``."""
    xy = ax.transData.transform(run.dense[:, :2])
    return float(np.hypot(*np.diff(xy, axis=0).T).max())


def _assert_smooth_and_same_motion(ax, run):
    longest, line = _longest_segment_px(ax)
    assert longest <= MAX_SEGMENT_PX, longest
    assert _coarse_segment_px(run, ax) > 5.0 * MAX_SEGMENT_PX   # the polygon it replaces
    x, y = line.get_data()
    per = (x.size - 1) // (run.strobe.shape[0] - 1)
    assert per > COARSE and (x.size - 1) % per == 0
    # every per-th sample is a stroboscopic sample of the recorded run: the same motion
    np.testing.assert_allclose(np.column_stack([x[::per], y[::per]]), run.strobe[:, :2],
                               atol=1e-9)


def test_a_chaotic_trajectory_of_a_run_is_drawn_smooth_not_as_a_polygon(chaos):
    """Hypothesis: plot_xy(run) of a chaotic run with 16 samples a period draws it with
    segments of at most a few pixels (the run integrated again with more samples per
    period, chosen from the figure's size and resolution), and it is the recorded
    motion: its samples at the forcing periods are the run's stroboscopic samples."""
    _assert_smooth_and_same_motion(plot_xy(chaos, **SMALL), chaos)


def test_a_chaotic_trajectory_read_from_a_file_is_drawn_smooth(chaos, tmp_path):
    """Hypothesis: the dataset of a file written by simulate and read back (the path of
    'vibimpact plot --kind xy') is drawn as smoothly as the Run, and is the same
    motion."""
    write_netcdf(chaos, tmp_path / "run.nc")
    _assert_smooth_and_same_motion(plot_xy(read_netcdf(tmp_path / "run.nc"), **SMALL),
                                   chaos)


def test_simulate_plot_draws_a_smooth_trajectory(monkeypatch, tmp_path):
    """Hypothesis: 'vibimpact simulate --plot' (64 samples a period unless told) draws a
    chaotic run with segments of at most a few pixels, at the figure's resolution."""
    import vibimpact.plotting as plotting
    from vibimpact.cli import main

    drawn = []
    real = plotting.plot_xy

    def spy(*args, **kwargs):
        drawn.append(real(*args, **kwargs))
        return drawn[-1]

    monkeypatch.setattr(plotting, "plot_xy", spy)
    code = main(["simulate", "--preset", "fig8", "--eta", "1.25", "--periods", "3",
                 "--transient", "40", "--dense", str(COARSE), "--figsize", "3x3.3",
                 "--dpi", "100", "-o",
                 str(tmp_path / "r.nc"), "--plot", str(tmp_path / "xy.png")])
    assert code in (0, None) and (tmp_path / "xy.png").stat().st_size > 0
    assert len(drawn) == 1
    longest, _ = _longest_segment_px(drawn[0])
    assert longest <= MAX_SEGMENT_PX, longest


def test_a_run_that_cannot_be_made_again_draws_its_own_samples(chaos):
    """Hypothesis: a dataset without its recorded start (no state0) is drawn from its
    own samples, without error (nothing to integrate again from)."""
    ds = chaos.to_dataset().drop_vars("state0")
    (line,) = _line(plot_xy(ds, **SMALL), "trajectory")
    assert line.get_xdata().size == chaos.dense.shape[0]


def test_loaded_arcs_are_drawn_on_the_retainer_from_start_to_end():
    """Hypothesis: the XY plot of fig8 at eta = 1.185 draws each loaded arc as a band on
    the circle R = 1 covering the arc's angles from its start to its end (tens of
    degrees, not a mark at the entry angle), for a Run and for its dataset."""
    p = vi.presets.get("fig8").replace(eta=1.185)
    run = vi.simulate(p, periods=2, transient=300, state0=[1.0, 0.0, 0.0, 1.185])
    arcs = contact_arcs(run)
    assert arcs.n_arcs == 2
    for value in (run, run.to_dataset()):
        bands = [ln for ln in plot_xy(value, **SMALL).get_lines() if ln.get_color() == "C3"
                 and ln.get_linestyle() == "-"]
        assert len(bands) == arcs.n_arcs
        assert str(arcs) in bands[0].get_label()
        for band, s, w in zip(bands, arcs.start, arcs.width):
            x, y = band.get_data()
            np.testing.assert_allclose(np.hypot(x, y), 1.0)
            deg = np.degrees(np.unwrap(np.arctan2(y, x)))
            assert deg[0] == pytest.approx(s, abs=1e-6) or \
                deg[0] == pytest.approx(s - 360.0, abs=1e-6)
            assert deg[-1] - deg[0] == pytest.approx(w, abs=1e-6)
