"""The attractor census (``vi.attractors``): known attractors and fractions, symmetry,
deduplication, determinism and bad input."""
import numpy as np
import pytest

import vibimpact as vi
from vibimpact.census import Box, census as C
from vibimpact.census.library import Attractor, same
from vibimpact.census.dataset import attractor_table
from vibimpact.cli import main

DOUBLE_WELL = vi.DuffingParams(delta=0.3, alpha=-1.0, beta=1.0, gamma=0.0, omega=1.0)
LINEAR = vi.DuffingParams(delta=0.3, alpha=1.0, beta=0.0, gamma=0.5, omega=1.3)
BOX = Box([-2.0, -2.0], [2.0, 2.0])


@pytest.fixture(scope="module")
def double_well():
    """A census of the unforced double well from 40 starts and their mirror images."""
    half = vi.census.random_starts(BOX, 20, seed=3)
    starts = np.vstack([half, -half])
    return starts, vi.attractors(vi.System(DOUBLE_WELL), starts=starts, box=BOX)


def test_linear_oscillator_has_one_attractor_the_analytic_response():
    """Hypothesis: a damped linear oscillator has one attractor, its forced response; the
    census finds only it (fraction 1, standard error 0) and its representative state is
    the analytic response x(0) = Re X, x'(0) = -omega Im X with
    X = gamma / (alpha - omega^2 + i delta omega), to 1e-6."""
    ds = vi.attractors(vi.System(LINEAR), starts=20)
    rows = attractor_table(ds)
    assert len(rows) == 1 and rows[0][3] == 1.0 and rows[0][4] == 0.0
    p = LINEAR
    X = p.gamma / (p.alpha - p.omega ** 2 + 1j * p.delta * p.omega)
    rep = ds.representative.values[0, 0]
    np.testing.assert_allclose(rep, [X.real, -p.omega * X.imag], atol=1e-6)
    assert int(ds.period[0, 0]) == 1 and float(ds.floquet_abs_max[0, 0]) < 1.0


def test_double_well_wells_are_found_and_labels_are_mirror_symmetric(double_well):
    """Hypothesis: the unforced double well x'' + 0.3 x' - x + x^3 = 0 has two attractors,
    the rest states x = +-1; the census finds exactly these two, and, since the equation
    is symmetric under (x, v) -> (-x, -v), every start and its mirror image reach
    different wells (so the fractions are 1/2 each)."""
    starts, ds = double_well
    rows = attractor_table(ds)
    assert len(rows) == 2
    reps = np.sort(ds.representative.values[0, :2, 0])
    np.testing.assert_allclose(reps, [-1.0, 1.0], atol=1e-6)
    lab = ds.label.values[0]
    assert np.all(lab[:20] != lab[20:])
    np.testing.assert_allclose(ds.fraction.values[0, :2], [0.5, 0.5])


def test_a_start_is_labelled_by_where_it_settles(double_well):
    """Hypothesis: the label of each start is the well its own trajectory settles in: the
    sign of x after 200 forcing periods equals the sign of the labelled attractor's x."""
    starts, ds = double_well
    system = vi.System(DOUBLE_WELL)
    rep = ds.representative.values[0, :, 0]
    for k in range(0, 40, 7):
        run = vi.simulate(system, periods=1, transient=200, state0=starts[k])
        assert np.sign(run.final_state[0]) == np.sign(rep[ds.label.values[0, k]])


def test_a_cycle_met_at_another_phase_is_the_same_orbit():
    """Hypothesis: a period-3 orbit's cycle points in another order (met at another
    phase) are the same attractor; moved by more than the tolerance, or with another
    period, they are not."""
    cyc = np.array([[0.1, 0.2], [0.5, -0.3], [-0.4, 0.0]])
    a = Attractor(cyc, 3, 0.02, 8, {})
    assert same(a, Attractor(np.roll(cyc, 1, axis=0), 3, 0.02, 8, {}), 1e-6)
    assert not same(a, Attractor(cyc + 1e-3, 3, 0.02, 8, {}), 1e-4)
    assert not same(a, Attractor(np.vstack([cyc, cyc]), 6, 0.02, 8, {}), 1e-4)


def test_rounds_cover_every_start_once():
    """Hypothesis: the rounds of n starts are contiguous, cover 0..n once, start with the
    pilot round of 16 and grow fourfold."""
    for n in (1, 16, 17, 1000, 40000):
        r = C.rounds(n)
        assert r[0][0] == 0 and r[-1][1] == n
        assert all(a[1] == b[0] for a, b in zip(r, r[1:]))
        assert r[0][1] == min(n, C.PILOT)
        assert all(b <= 4 * a for (_, a), (_, b) in zip(r, r[1:]))


class Reversed:
    """An executor that runs the jobs in reverse order (in this process)."""

    def run(self, make_jobs, on_point, on_task):
        from vibimpact.engine.plan import run_task

        for job in reversed(make_jobs(None)):
            for task in job:
                on_task(task, run_task(task))


def test_census_is_the_same_whatever_runs_its_tasks():
    """Hypothesis: the census is a function of its request only: an executor that runs
    the tasks in reverse order gives the same dataset bit for bit, and the same seed gives
    the same starts."""
    system = vi.System(DOUBLE_WELL)
    settings = vi.CensusSettings(hold=4)
    a = vi.attractors(system, starts=80, seed=2, box=BOX, settings=settings)
    b = vi.attractors(system, starts=80, seed=2, box=BOX, settings=settings,
                      execution=vi.Execution(executor=Reversed()))
    for name in a.data_vars:
        assert np.array_equal(a[name].values, b[name].values,
                              equal_nan=a[name].dtype.kind == "f"), name
    assert (a.decided_by.values == 0).any()  # later rounds stopped on known attractors


@pytest.mark.parametrize("kwargs, name", [
    (dict(starts=0), "starts"), (dict(starts=True), "starts"),
    (dict(starts=np.zeros((3, 3))), "starts"), (dict(starts=[["a", "b"]]), "starts"),
    (dict(starts=np.full((2, 2), np.nan)), "starts"), (dict(seed=-1), "seed"),
    (dict(box=Box([0, 0, 0], [1, 1, 1])), "box"), (dict(box=(0, 1)), "box"),
    (dict(settings="fast"), "settings"), (dict(eta=[1.0, 0.9]), "eta"),
    (dict(eta=-1.0), "eta"), (dict(execution=2), "execution")])
def test_bad_input_is_refused_naming_the_argument(kwargs, name):
    """Hypothesis: every bad argument of vi.attractors raises a ValueError naming it,
    before any work."""
    with pytest.raises(ValueError, match=name):
        vi.attractors(vi.System(LINEAR), **kwargs)


@pytest.mark.parametrize("field, value", [("max_periods", 0), ("radius", -1.0),
                                          ("radius", float("nan")), ("hold", 1.5),
                                          ("dedup_tol", True), ("point", None)])
def test_bad_census_settings_are_refused_naming_the_field(field, value):
    """Hypothesis: CensusSettings refuses a bad value of each field with its name."""
    with pytest.raises(ValueError, match=field):
        vi.CensusSettings(**{field: value})


@pytest.mark.parametrize("argv", [["--starts", "0"], ["--eta", "1.1:1.0:0.01"],
                                  ["--eta", "abc"], ["--preset", "nope"],
                                  ["--set", "kh=-1"], ["--workers", "0"]])
def test_cli_bad_input_is_one_line_and_exit_2(argv, tmp_path, capsys):
    """Hypothesis: bad input to 'vibimpact attractors' ends with one line on stderr, exit
    2, and no file written."""
    out = tmp_path / "c.nc"
    try:
        status = main(["attractors", *argv, "-o", str(out)])
    except SystemExit as exc:  # argparse's own refusal of a typed option
        status = exc.code
    assert status == 2
    err = capsys.readouterr().err.strip()
    assert err and len(err.splitlines()) <= 2 and "Traceback" not in err
    assert not out.exists() and not list(tmp_path.iterdir())


def test_cli_writes_the_census_and_plots_it(tmp_path, capsys):
    """Hypothesis: 'vibimpact attractors' on the soft-impact oscillator writes a census
    file whose fractions sum to 1 at every eta, prints each attractor, and 'vibimpact plot'
    draws it; no temporary or checkpoint is left."""
    import xarray as xr

    out = tmp_path / "c.nc"
    assert main(["attractors", "--preset", "soft-impact", "--eta", "0.8,0.9",
                 "--starts", "6", "--no-progress", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "eta = 0.8" in text and "eta = 0.9" in text
    with xr.open_dataset(out) as ds:
        np.testing.assert_allclose(np.nansum(ds.fraction.values, axis=1), 1.0)
        assert ds.sizes["start"] == 6
    assert main(["plot", str(out), "-o", str(tmp_path / "c.png")]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.nc", "c.png"]


def test_locate_names_the_well_a_sweep_followed():
    """Hypothesis: in the weakly forced double well two periodic orbits coexist, one in
    each well; a sweep with continuation started in the right (left) well is located on
    the census attractor whose representative state has x > 0 (x < 0), at every eta."""
    system = vi.System(vi.DuffingParams(delta=0.3, alpha=-1.0, beta=1.0, gamma=0.1,
                                        omega=1.2))
    etas = np.array([1.2, 1.25])
    census = vi.attractors(system, eta=etas, starts=24, box=BOX)
    for x0, sign in (([1.0, 0.0], 1.0), ([-1.0, 0.0], -1.0)):
        sweep = vi.sweep(system, etas, state0=x0, analyses=("period", "poincare"))
        ids = vi.census.locate(census, sweep).values[0]
        for i, g in enumerate(ids):
            a = list(census.global_id.values[i]).index(g)
            assert np.sign(census.representative.values[i, a, 0]) == sign


def test_locate_refuses_what_it_cannot_place():
    """Hypothesis: locate refuses a census and a sweep that share no eta, and a file that
    is not a census, with a ValueError saying so."""
    system = vi.System(LINEAR)
    census = vi.attractors(system, starts=4)
    sweep = vi.sweep(system, np.array([2.0, 2.1]), analyses=("period", "poincare"))
    with pytest.raises(ValueError, match="share no eta"):
        vi.census.locate(census, sweep)
    with pytest.raises(ValueError, match="census"):
        vi.census.locate(sweep, sweep)


@pytest.mark.slow
def test_census_on_dask_and_on_processes_is_the_serial_census():
    """Hypothesis: a census run on a Dask LocalCluster of 2 processes, and on 2 local
    worker processes, equals the serial census bit for bit (the engine's executors never
    change a number)."""
    import logging

    from distributed import Client, LocalCluster

    system = vi.System(DOUBLE_WELL)
    kw = dict(eta=[1.0, 1.1], starts=100, box=BOX)
    serial = vi.attractors(system, **kw)
    procs = vi.attractors(system, **kw, execution=vi.Execution(workers=2))
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=":0", silence_logs=logging.ERROR) as cl, \
            Client(cl, set_as_default=False) as client:
        dask = vi.attractors(system, **kw, execution=vi.Execution(scheduler=client))
    for other in (procs, dask):
        for name in serial.data_vars:
            assert np.array_equal(serial[name].values, other[name].values,
                                  equal_nan=serial[name].dtype.kind == "f"), name


def _entered_point_by_point(points, atts, counts, first):
    """The entering rule written point by point (the definition)."""
    for k in range(points.shape[0]):
        for a, att in enumerate(atts):
            dist = float(att.distances(points[k:k + 1])[0])
            if dist < att.radius:
                if counts[a] == 0:
                    first[a] = dist
                counts[a] += 1
                if counts[a] >= att.hold and (not att.periodic or dist <= first[a]):
                    return a
            else:
                counts[a] = 0
    return -1


def test_entering_rule_is_its_point_by_point_definition():
    """Hypothesis: the vectorised entering test (library.entered) returns the attractor
    the point-by-point rule returns and carries the same streaks from chunk to chunk, on
    500 random libraries and trajectories."""
    from vibimpact.census.library import entered

    rng = np.random.default_rng(0)
    for _ in range(500):
        atts = [Attractor(rng.normal(size=(int(rng.integers(1, 4)), 2)) * 0.3,
                          int(rng.integers(0, 3)), 0.3, int(rng.integers(1, 6)), {})
                for _ in range(int(rng.integers(1, 4)))]
        c1, f1 = np.zeros(len(atts), np.int64), np.zeros(len(atts))
        c2, f2 = c1.copy(), f1.copy()
        for _ in range(4):
            pts = rng.normal(size=(int(rng.integers(1, 10)), 2)) * 0.4
            r1 = _entered_point_by_point(pts, atts, c1, f1)
            assert entered(pts, atts, (c2, f2)) == r1
            if r1 >= 0:
                break
            assert np.array_equal(c1, c2)
            np.testing.assert_allclose(f1[c1 > 0], f2[c2 > 0])
