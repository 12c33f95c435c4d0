"""Frequency sweeps: continuation, determinism (serial == parallel, resumed ==
uninterrupted), requested work only, the interval map, NetCDF round trip, bad input."""
import numpy as np
import pytest
import xarray as xr

import vibimpact as vi
from vibimpact.io import read_netcdf, write_netcdf
from vibimpact.sweeps import SweepSettings, analyse_point, parse_range
from vibimpact.engine.store import fingerprint
from conftest import continued_state, preset

FIG8 = preset("fig8")
GRID = np.round(np.arange(1.16, 1.24 + 1e-9, 0.01), 12)  # crosses into the chaotic interval
#: start on the impacting branch (reached by continuation from eta = 1.0)
X0 = continued_state("fig8", 1.16)


def _same(a, b):
    """Every data variable equal to the bit (NaN == NaN)."""
    assert set(a.data_vars) == set(b.data_vars)
    for v in a.data_vars:
        x, y = a[v].values, b[v].values
        if x.dtype.kind == "f":
            assert np.array_equal(x, y, equal_nan=True), v
        else:
            assert (x == y).all(), v
    return True


@pytest.fixture(scope="module")
def serial():
    return vi.sweep(FIG8, GRID, state0=X0,
                    continuation=vi.Continuation(blocks=3, seed_periods=10),
                    execution=vi.Execution(workers=1))


def test_parallel_sweep_is_bit_identical_to_serial(serial):
    """Blocks are seeded by the same serial pass, so 2 worker processes give exactly the
    serial numbers."""
    par = vi.sweep(FIG8, GRID, state0=X0,
                   continuation=vi.Continuation(blocks=3, seed_periods=10),
                   execution=vi.Execution(workers=2))
    assert _same(serial, par)


def test_one_block_is_plain_continuation():
    """blocks=1: every point starts from the previous point's final state."""
    grid = GRID[:4]
    ds = vi.sweep(FIG8, grid, continuation=vi.Continuation(blocks=1))
    x = None
    for k, eta in enumerate(grid):
        r = analyse_point(FIG8.replace(eta=float(eta)), x, SweepSettings())
        x = r.final_state
        assert ds["regime"].values[k] == r.regime
        assert ds["X_m"].values[k] == r.X_m
        np.testing.assert_array_equal(ds["final_state"].values[k], r.final_state)


def test_continuation_reaches_impacting_branch_that_rest_start_misses():
    """Hysteresis: at eta = 1.18, sweeping up from 1.0 follows the impacting branch (two
    bottom impacts A and B), while starting every point from rest lands on the impactless
    low branch."""
    grid = np.round(np.arange(1.0, 1.18 + 1e-9, 0.02), 12)
    cont = vi.sweep(FIG8, grid, analyses=("period", "impacts"),
                    continuation=vi.Continuation(blocks=1))
    fixed = vi.sweep(FIG8, grid, continuation=False, analyses=("period", "impacts"))
    assert cont["impacts_per_period"].values[-1] == 2.0
    assert cont["label"].values[-1].startswith("P1, 2 impacts")
    assert fixed["impacts_per_period"].values[-1] == 0.0


def test_sweep_labels_the_pinned_chaotic_point_and_the_periodic_orbit_below(serial):
    """At the pinned configuration (conftest.MEASURED_AT), the fig8 sweep labels eta =
    1.22 chaotic with a positive exponent and eta = 1.16 P1 with two impacts."""
    lab = dict(zip(serial["eta"].values.round(3), serial["label"].values))
    assert lab[1.16] == "P1, 2 impacts, 2 small arcs"
    k = int(np.argmin(abs(serial["eta"].values - 1.22)))
    assert serial["regime"].values[k] == 3 and serial["lyapunov"].values[k] > 0


def test_only_requested_work_is_done(serial):
    """Exponents are computed only where no period was found; a period-only sweep computes
    no exponent, no 0-1 test and no response; periodic transients end early, at the
    latest after the transient and its record when shooting decided them."""
    per = serial["period"].values > 0
    assert np.all(np.isnan(serial["lyapunov"].values[per]))
    assert np.all(np.isfinite(serial["lyapunov"].values[~per]))
    shot = np.isfinite(serial["shoot_residual"].values)
    st = SweepSettings()
    assert np.all(serial["transient"].values[per & ~shot] < st.transient_max)
    assert np.all(serial["transient"].values[per & shot] <= st.transient_max + st.record + 2)
    lean = vi.sweep(FIG8, GRID[:3], analyses=("period",))
    for v in ("lyapunov", "k01", "X_m", "impacts_per_period"):
        assert np.all(np.isnan(lean[v].values)), v


def test_both_directions_have_their_own_dimension_and_order():
    """direction='both' gives a direction dim; the down sweep starts at the top eta from
    rest, so its first point equals a fixed-state point there."""
    grid = GRID[:3]
    ds = vi.sweep(FIG8, grid, direction="both", analyses=("period", "impacts"),
                  continuation=vi.Continuation(blocks=1))
    assert ds["regime"].dims == ("direction", "eta")
    top = analyse_point(FIG8.replace(eta=float(grid[-1])), None,
                        SweepSettings(analyses=("period", "impacts")))
    assert ds["final_state"].sel(direction="down").values[-1].tolist() == \
        top.final_state.tolist()
    iv = vi.intervals(ds)
    assert set(iv["direction"].values) == {"up", "down"}


def test_netcdf_round_trip_with_plain_xarray(serial, tmp_path):
    """The dataset written atomically opens with plain xarray and holds the same values,
    with CF units/long names and the regime flags."""
    path = tmp_path / "sweep.nc"
    write_netcdf(serial, path)
    with xr.open_dataset(path) as back:
        back.load()
    assert _same(serial, back)
    assert back["regime"].attrs["flag_meanings"].split()[2] == "chaotic"
    assert back["X_m"].attrs["units"] == "1"
    assert _same(serial, read_netcdf(path))


def test_intervals_group_consecutive_equal_labels():
    """Consecutive points with the same label form one interval; start/end are the first
    and last eta; a down sweep's intervals run downward."""
    eta = np.array([1.0, 1.1, 1.2, 1.3, 1.4])
    lab = np.array(["P1 impactless", "P1 impactless", "chaotic, impacting, whole circle",
                    "P3, 8 impacts, whole circle", "P3, 8 impacts, whole circle"],
                   dtype=object)
    ds = xr.Dataset({"label": ("eta", lab), "regime": ("eta", [1, 1, 3, 1, 1]),
                     "period": ("eta", [1, 1, 0, 3, 3]),
                     "impacts_per_period": ("eta", [0.0, 0.0, 2.4, 8.0, 8.0]),
                     "arcs": ("eta", ["none", "none", "whole circle", "whole circle",
                                      "whole circle"])}, coords={"eta": eta},
                    attrs={"sweep_direction": "up"})
    iv = vi.intervals(ds)
    assert iv["start"].values.tolist() == [1.0, 1.2, 1.3]
    assert iv["end"].values.tolist() == [1.1, 1.2, 1.4]
    assert iv["period"].values.tolist() == [1, 0, 3]
    assert iv["points"].values.tolist() == [2, 1, 2]
    ds.attrs["sweep_direction"] = "down"
    assert vi.intervals(ds)["start"].values.tolist() == [1.4, 1.2, 1.1]


def test_resumed_sweep_equals_uninterrupted_and_reuses_saved_points(serial, tmp_path):
    """A checkpointed sweep whose last points were lost (as after a kill) resumes from the
    saved points without recomputing them and gives the uninterrupted numbers."""
    ckdir = tmp_path / "ck"
    vi.sweep(FIG8, GRID, state0=X0, continuation=vi.Continuation(blocks=3),
             execution=vi.Execution(checkpoint=ckdir))
    files = sorted(ckdir.glob("up_*.npz"))  # one entry per point, in sweep order
    assert len(files) == GRID.size
    for f in files[5:]:
        f.unlink()
    kept = {f.name: f.stat().st_mtime_ns for f in files[:5]}
    again = vi.sweep(FIG8, GRID, state0=X0, continuation=vi.Continuation(blocks=3),
                     execution=vi.Execution(checkpoint=ckdir, resume=True))
    assert _same(serial, again)
    assert {f.name: f.stat().st_mtime_ns for f in files[:5]} == kept


def test_checkpoint_refuses_other_request_or_missing_resume(tmp_path):
    """A checkpoint belongs to one request: reusing it without resume, or for another
    grid, raises ValueError naming the checkpoint."""
    ckdir = tmp_path / "ck"
    vi.sweep(FIG8, GRID[:2], execution=vi.Execution(checkpoint=ckdir))
    with pytest.raises(ValueError, match="checkpoint"):
        vi.sweep(FIG8, GRID[:2], execution=vi.Execution(checkpoint=ckdir))
    with pytest.raises(ValueError, match="checkpoint"):
        vi.sweep(FIG8, GRID[:3], execution=vi.Execution(checkpoint=ckdir, resume=True))
    assert fingerprint({"a": 1}) != fingerprint({"a": 2})


def test_blow_up_is_labelled_diverged_not_stored_as_data():
    """A point that escapes (strong softening, weak contact) is DIVERGED with NaN response,
    and the reason says where it happened."""
    p = FIG8.replace(k3=-0.5, kh=1.0, Ec=2.0)
    ds = vi.sweep(p, [1.0, 1.1], state0=[5.0, 0.0, 0.0, 0.0], continuation=False)
    assert list(ds["label"].values) == ["diverged", "diverged"]
    assert np.all(np.isnan(ds["X_m"].values))
    assert "diverged" in ds["reason"].values[0]


def test_eta_range_includes_stop_on_the_grid():
    """START:STOP:STEP includes STOP when it lies on the grid."""
    assert parse_range("0.9:1.5:0.002").size == 301
    assert parse_range("1:1.05:0.02").tolist() == [1.0, 1.02, 1.04]


def test_eta_list_is_taken_as_written():
    """A comma-separated list (as --vary takes) gives exactly those values, unrounded, and
    a single number gives a one-point grid."""
    assert parse_range("1.0,1.1,1.25").tolist() == [1.0, 1.1, 1.25]
    assert parse_range("1.0000000000001").tolist() == [1.0000000000001]


@pytest.mark.parametrize("kwargs, name", [
    (dict(eta=[1.2, 1.1]), "eta"), (dict(eta=[]), "eta"), (dict(eta=[1.0, np.nan]), "eta"),
    (dict(direction="sideways"), "direction"), (dict(analyses=("fft",)), "analyses"),
    (dict(continuation="yes"), "continuation"), (dict(execution="2 workers"), "execution"),
    (dict(state0=[1.0, 2.0]), "state0")])
def test_bad_arguments_raise_value_error_naming_them(kwargs, name):
    """Invalid sweep arguments raise ValueError naming the argument."""
    args = dict(eta=[1.0, 1.1])
    args.update(kwargs)
    eta = args.pop("eta")
    with pytest.raises(ValueError, match=name):
        vi.sweep(FIG8, eta, **args)


@pytest.mark.parametrize("text", ["1:0.5:0.1", "a:b:c", "1:2:0", "1:2", "-1:1:0.1"])
def test_bad_eta_range_text_raises_naming_eta(text):
    """Malformed START:STOP:STEP raises ValueError naming eta."""
    with pytest.raises(ValueError, match="eta"):
        parse_range(text)


def test_rolling_on_the_retainer_is_permanent_contact_not_impactless():
    """Above the chaotic interval the continued fig8 branch rolls on the retainer
    (R > 1 throughout, no contact entry): labelled 'permanent contact', not impactless,
    while the low branch reached from rest is free flight (R_m < 1)."""
    eta = 1.35
    x = continued_state("fig8", eta)
    ds = vi.sweep(FIG8, [eta], state0=x, analyses=("period", "impacts", "response"))
    assert int(ds["contact"].values[0]) == 2 and ds["R_m"].values[0] > 1.0
    assert ds["label"].values[0] == "P1, permanent contact"
    rest = vi.sweep(FIG8, [eta], analyses=("period", "impacts", "response"))
    assert int(rest["contact"].values[0]) == 0 and rest["R_m"].values[0] < 1.0
    assert rest["label"].values[0] == "P1 impactless"


def test_runs_joined_from_chunks_equal_one_run():
    """Hypothesis: a trajectory integrated in chunks of whole periods, each from the last
    one's final state, and joined (run.join_runs) has the strobe, the contact records
    (a contact spanning two chunks is one record, its period counted from the start), the
    dense samples and the events of the same trajectory integrated in one run, to the
    integrator's tolerance (the chunks restart the step size, so not bit for bit)."""
    from vibimpact.core.run import join_runs
    from vibimpact.sweeps import continued_state

    p = FIG8.replace(eta=1.185)  # two bottom impacts per period (paper, fig. 8)
    kw = dict(solver=vi.SolverSettings(rtol=1e-10, atol=1e-13))
    x0 = continued_state(p, 1.185)
    whole = vi.simulate(p, periods=30, state0=x0, dense=16, **kw)
    chunks, x = [], x0
    for m in (7, 10, 13):
        chunks.append(vi.simulate(p, periods=m, state0=x, dense=16, **kw))
        x = chunks[-1].final_state
    joined = join_runs(chunks, 2 * np.pi / p.eta)
    assert joined.strobe.shape == whole.strobe.shape
    assert np.allclose(joined.strobe, whole.strobe, rtol=0, atol=1e-6)
    assert np.allclose(joined.dense, whole.dense, rtol=0, atol=1e-6)
    assert np.allclose(joined.t_dense, whole.t_dense, rtol=0, atol=1e-12)
    assert whole.impacts.size >= 30
    assert joined.impacts.size == whole.impacts.size
    assert np.array_equal(joined.impacts["period"], whole.impacts["period"])
    for f in ("t_entry", "t_exit", "theta", "v_impact", "penetration"):
        assert np.allclose(joined.impacts[f], whole.impacts[f], rtol=0, atol=1e-5), f
    assert np.array_equal(joined.events["which"], whole.events["which"])
    assert np.allclose(joined.final_state, whole.final_state, rtol=0, atol=1e-6)


def test_progress_is_a_callback_counting_every_point_once(tmp_path):
    """``progress`` may be a callable: it is called in this process with the points
    finished, every computed point once (and loaded points not at all)."""
    got = []
    grid = GRID[:3]
    ds = vi.sweep(FIG8, grid, direction="both",
                  settings=SweepSettings(transient_max=60),
                  continuation=vi.Continuation(blocks=2),
                  execution=vi.Execution(workers=2, progress=got.append,
                                         checkpoint=tmp_path / "ck"))
    assert sum(got) == 2 * grid.size and set(got) == {1}
    again = []
    vi.sweep(FIG8, grid, direction="both", settings=SweepSettings(transient_max=60),
             continuation=vi.Continuation(blocks=2),
             execution=vi.Execution(workers=2, progress=again.append,
                                    checkpoint=tmp_path / "ck", resume=True))
    assert sum(again) == 0
    assert ds.sizes["direction"] == 2


def test_a_dead_worker_process_is_an_error_not_a_hang(monkeypatch):
    """A worker process that dies (killed, out of memory) ends a parallel sweep with a
    RuntimeError saying so, instead of waiting for it forever."""
    import os

    from vibimpact.engine import policy

    def die(*args, **kwargs):
        os._exit(3)

    monkeypatch.setattr(policy, "analyse_point", die)  # forked workers inherit it
    with pytest.raises(RuntimeError, match="worker process died"):
        vi.sweep(FIG8, GRID[:4], continuation=vi.Continuation(blocks=2),
                 execution=vi.Execution(workers=2))


def test_grid_is_the_command_lines_grid():
    """Hypothesis: vi.grid gives exactly the values the command line parses for the same
    text (not np.arange's, which differ by rounding), refuses eta <= 0, lets another
    parameter's grid cross zero, and refuses what is not a range's text, naming it."""
    from vibimpact.sweeps import parse_range

    for text in ("0.9:1.5:0.002", "1.29:1.395:0.005", "1.0,1.1,1.25"):
        assert np.array_equal(vi.grid(text), parse_range(text))
    assert not np.array_equal(vi.grid("0.9:1.5:0.002"), np.arange(0.9, 1.5 + 1e-12, 0.002))
    np.testing.assert_array_equal(vi.grid("-0.002:0:0.001", name="k3"),
                                  [-0.002, -0.001, 0.0])
    with pytest.raises(ValueError, match="eta"):
        vi.grid("-1:1:1")
    with pytest.raises(ValueError, match="kh"):
        vi.grid(120.0, name="kh")
