"""Parameter maps (issue 9): ``vi.map2d``, its Dask execution, checkpoints and resume,
the ``vibimpact map`` command and the map plot.

The maps are small (a few rows of fig8 x 16 eta points, short transients through
``SweepSettings``) but cross the impacting, quasi-periodic and chaotic regimes near
eta = 1.2, so that equality between runs is a statement about non-trivial data.  The
Dask tests start a ``LocalCluster`` of two single-threaded worker processes in-process.
"""
import importlib
import os
import signal
import subprocess
import sys
import threading
import time
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.base._text import count
from vibimpact.cli import main
from vibimpact.engine import cluster as dask_executor
from vibimpact.engine import plan
from vibimpact.engine.store import Checkpoint
from vibimpact.maps import open_map, write_map
from vibimpact.maps import store as mstore
from vibimpact.sweeps import SweepSettings, parse_range

#: the module (``vibimpact.maps.map2d`` is the function)
M = importlib.import_module("vibimpact.maps.map2d")
ROOT = Path(__file__).resolve().parents[1]
P = vi.presets.get("fig8")
ETA = np.round(np.arange(1.0, 1.3 + 1e-9, 0.02), 12)
VARY = {"kh": [40.0, 80.0, 120.0]}
FAST = SweepSettings(transient_max=100, record=48, lyap_min=40, lyap_max=150)


def saved_rows(path):
    """Rows completely saved in a map checkpoint."""
    return Checkpoint(path).saved()[1]


def fake_tasks(k, n):
    """``k`` plan tasks of ``n`` points (rows of a map), for the grouping."""
    return [plan.Task(i, "up", 0, n, None, None, None, None, False) for i in range(k)]


def assert_same(a, b):
    """Every data variable and coordinate of ``a`` and ``b`` is exactly equal (NaN equal to
    NaN), with the same dtype."""
    assert set(a.data_vars) == set(b.data_vars)
    assert set(a.coords) == set(b.coords)
    for name in list(a.data_vars) + list(a.coords):
        x, y = a[name].values, b[name].values
        assert x.shape == y.shape, name
        if x.dtype == object or y.dtype == object:
            assert x.dtype == y.dtype and x.tolist() == y.tolist(), name
        else:
            assert x.dtype == y.dtype, name
            assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), name


@pytest.fixture(scope="module")
def serial():
    """The reference map: serial, in this process, both directions."""
    return vi.map2d(P, ETA, VARY, direction="both", settings=FAST)


@pytest.fixture(scope="module")
def cluster():
    """A LocalCluster of 2 single-threaded worker processes and its client."""
    import logging

    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=":0", silence_logs=logging.ERROR) as cl, \
            Client(cl, set_as_default=False) as client:
        yield cl, client


def test_map_rows_are_the_one_dimensional_sweeps(serial):
    """Hypothesis: row kh = v of a map is, bit for bit, ``vi.sweep`` at kh = v with pure
    serial continuation (blocks=1) in each direction, and the map is not trivial (it holds
    periodic points and points that are not)."""
    reg = serial["regime"].values
    assert (reg == 1).any() and (reg >= 2).any()
    assert serial["regime"].dims == ("direction", "kh", "eta")
    row = vi.sweep(P.replace(kh=120.0), ETA, direction="both", analyses=M.MAP_ANALYSES,
                   settings=FAST, continuation=vi.Continuation(blocks=1))
    assert np.isnan(row["poincare_X"].values).all()  # not computed: the map leaves it out
    assert_same(serial.sel(kh=120.0, drop=True),
                row.drop_vars([v for v in row.data_vars if v.startswith("poincare_")]))
    assert serial.attrs["map_vary"] == "kh" and "param_kh" not in serial.attrs
    iv = vi.intervals(serial.sel(kh=120.0, drop=True), direction="up")
    assert iv.sizes["interval"] >= 3


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_cluster_survives_a_killed_worker_and_equals_serial(serial, cluster):
    """Hypothesis: rows run as Dask tasks on a cluster give the serial map bit for bit,
    even when a worker process is SIGKILLed while it holds tasks: the scheduler hands its
    tasks to a worker again (at least one task goes to 'processing' twice)."""
    cl, client = cluster
    out = {}

    def run():
        try:
            out["ds"] = vi.map2d(P, ETA, VARY, direction="both", settings=FAST,
                                 execution=vi.Execution(scheduler=client, task_points=1))
        except BaseException as exc:  # reported by the assertion below
            out["exc"] = exc

    pids = client.run(os.getpid)
    th = threading.Thread(target=run)
    th.start()
    victim, deadline = None, time.monotonic() + 60
    while victim is None and th.is_alive() and time.monotonic() < deadline:
        for w, keys in client.processing().items():
            if any(str(k).startswith("vibimpact-map") for k in keys):
                victim = w
                break
        time.sleep(0.01)
    assert victim is not None, "no task reached a worker"
    os.kill(pids[victim], signal.SIGKILL)
    th.join(120)
    assert "exc" not in out, out.get("exc")
    assert_same(out["ds"], serial)

    def log(dask_scheduler):
        return [(str(e[0]), e[2]) for e in dask_scheduler.transition_log]

    runs = Counter(k for k, finish in client.run_on_scheduler(log)
                   if k.startswith("vibimpact-map") and finish == "processing")
    assert max(runs.values()) >= 2, runs
    client.wait_for_workers(2, timeout=60)
    assert pids[victim] not in client.run(os.getpid).values()


def test_scheduler_address_and_task_grouping_do_not_change_the_map(serial, cluster):
    """Hypothesis: connecting by address, and grouping three rows per task, give the same
    map as serial: which rows share a task never changes a number."""
    cl, client = cluster
    ds = vi.map2d(P, ETA, VARY, direction="both", settings=FAST,
                  execution=vi.Execution(scheduler=cl.scheduler_address, task_points=40))
    assert_same(ds, serial)
    assert [len(job) for job in plan.group(fake_tasks(6, 16), 40, None)] == [3, 3]


def test_a_sweep_on_the_cluster_equals_the_serial_sweep(cluster, tmp_path):
    """Hypothesis: ``vi.Execution(scheduler=...)`` runs a sweep's blocks on Dask as well
    (its executor is the map's); the sweep, checkpointed there task by task, equals the
    serial sweep bit for bit and its checkpoint holds every point."""
    cl, client = cluster
    cont = vi.Continuation(blocks=3)
    ref = vi.sweep(P, ETA[:7], direction="both", settings=FAST, continuation=cont)
    ds = vi.sweep(P, ETA[:7], direction="both", settings=FAST, continuation=cont,
                  execution=vi.Execution(scheduler=client, checkpoint=tmp_path / "ck"))
    assert_same(ds, ref)
    assert Checkpoint(tmp_path / "ck").saved() == (2 * 7, 2)


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_local_processes_equal_serial(serial):
    """Hypothesis: the default local execution (workers=2: a LocalCluster of two
    processes started for the run) gives the serial map bit for bit."""
    ds = vi.map2d(P, ETA, VARY, direction="both", settings=FAST,
                  execution=vi.Execution(workers=2, task_points=1))
    assert_same(ds, serial)


def _entries(store, at):
    """The entry files of the row ``at`` (indices in the leading dims) in a checkpoint."""
    d, row = (("up", "down")[at[0]], at[1]) if len(at) == 2 else ("up", at[0])
    return sorted(store.glob(f"{d}_{row:06d}_*.npz"))


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_interrupted_map_resumes_without_recomputing_saved_rows(serial, tmp_path,
                                                                 monkeypatch):
    """Hypothesis: a map interrupted after two rows has exactly those rows in its
    checkpoint, readable as a map (finished rows equal to the serial map's, the others
    not computed); resuming computes only the other rows (plus one whose entry was
    damaged, listed by the resume; a write cut short, a temporary file, is ignored),
    leaves the saved rows' entries untouched and equals the uninterrupted map."""
    store = tmp_path / "rows"
    real = plan.run_job
    calls = []

    def dying(job, on_point=None):
        if len(calls) == 2:
            raise KeyboardInterrupt
        calls.append(job)
        return real(job, on_point)

    monkeypatch.setattr(plan, "run_job", dying)
    with pytest.raises(KeyboardInterrupt):
        vi.map2d(P, ETA, VARY, direction="both", settings=FAST,
                 execution=vi.Execution(checkpoint=store, task_points=1))
    assert saved_rows(store) == 2
    part = open_map(store)
    done = part["row_done"].values == 1
    assert done.sum() == 2 and part["regime"].dims == ("direction", "kh", "eta")
    for name in serial.data_vars:
        x, y = part[name].values[done], serial[name].values[done]
        assert (x.tolist() == y.tolist()) if x.dtype == object else \
            np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), name
    assert (part["regime"].values[~done] == 0).all()  # not computed
    (keep, damaged) = [tuple(int(k) for k in at) for at in np.argwhere(done)]
    kept = {f: f.stat().st_mtime_ns for f in _entries(store, keep)}
    assert len(kept) == 1  # one entry per row
    victim = _entries(store, damaged)[0]
    victim.write_bytes(victim.read_bytes()[:-3])
    (store / ".tmp-cut.npz").write_bytes(b"half")  # a write cut short by a kill

    computed = []

    def counting(job, on_point=None):
        computed.extend((t.row, t.direction) for t in job)
        return real(job, on_point)

    monkeypatch.setattr(plan, "run_job", counting)
    ds = vi.map2d(P, ETA, VARY, direction="both", settings=FAST,
                  execution=vi.Execution(checkpoint=store, resume=True, task_points=1))
    assert len(computed) == 6 - 1
    assert all(f.stat().st_mtime_ns == t for f, t in kept.items())
    assert Checkpoint(store).last_resume()["damaged"] == [victim.name + ".corrupt"]
    assert saved_rows(store) == 6
    assert_same(ds, serial)
    with pytest.raises(ValueError, match="different map request"):
        vi.map2d(P, ETA, {"kh": [40.0, 81.0, 120.0]}, direction="both", settings=FAST,
                 execution=vi.Execution(checkpoint=store, resume=True))


def test_foreign_directory_is_not_taken_for_a_checkpoint(tmp_path):
    """Hypothesis: resuming from a directory that is not a map checkpoint (an old or
    foreign directory) is refused with a ValueError naming it, and the directory is
    left as it was."""
    store = tmp_path / "rows"
    store.mkdir()
    (store / "row_up_000000.npz").write_bytes(b"old")
    with pytest.raises(ValueError, match="is not a vibimpact map checkpoint"):
        vi.map2d(P, ETA, VARY, settings=FAST,
                 execution=vi.Execution(checkpoint=store, resume=True))
    assert [f.name for f in store.iterdir()] == ["row_up_000000.npz"]
    with pytest.raises(ValueError, match="already exists"):
        vi.map2d(P, ETA, VARY, settings=FAST, execution=vi.Execution(checkpoint=store))


@pytest.mark.parametrize("fmt", ["zarr", "nc"])
def test_map_file_round_trip(serial, tmp_path, fmt):
    """Hypothesis: a map written as Zarr or NetCDF reads back bit for bit (strings as
    str objects), and an existing output is never replaced without overwrite."""
    path = tmp_path / f"map.{fmt}"
    write_map(serial, path)
    assert_same(open_map(path), serial)
    with pytest.raises(ValueError, match="exists"):
        write_map(serial, path)
    write_map(serial, path, overwrite=True)
    assert_same(open_map(path), serial)
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]


@pytest.mark.parametrize("vary, needle", [
    ({"kx": [1.0]}, "unknown parameter 'kx'"),
    ({"eta": [1.0]}, "eta is the map's other axis"),
    ({"kh": [1.0], "f": [0.1]}, "one entry"),
    ([("kh", [1.0])], "one entry"),
    ({"kh": [10.0, np.nan]}, "kh: values must be finite"),
    ({"kh": [20.0, 10.0]}, "kh: values must be strictly increasing"),
    ({"kh": []}, "kh: no values"),
    ({"kh": ["a"]}, "kh: values must be numbers"),
    ({"kh": [-10.0, 10.0]}, "kh must be >= 0"),
    ({"kh": np.arange(200_001.0)}, "kh grid has 200001 points"),
    ({"kh": np.arange(30_000.0)}, "at most 2000000"),
])
def test_bad_vary_is_refused_naming_it(vary, needle):
    """Hypothesis: vary accepts only one Params field (not eta) with finite, strictly
    increasing values in the parameter's domain, and maps of absurd size are refused
    before any work; the ValueError names the problem."""
    eta = np.linspace(0.9, 1.5, 100)
    with pytest.raises(ValueError, match=None) as err:
        vi.map2d(P, eta, vary)
    assert needle in str(err.value)


def test_unreachable_scheduler_is_a_value_error():
    """Hypothesis: a scheduler that does not answer is reported as a ValueError naming its
    address (the CLI's exit 2), not a hang or a traceback from deep inside Dask."""
    with pytest.raises(ValueError, match="cannot connect to the Dask scheduler"):
        dask_executor.connect("tcp://127.0.0.1:9", timeout=1)


def _main(capsys, *args):
    try:
        rc = main(list(args))
    except SystemExit as exc:  # argparse errors
        rc = exc.code
    cap = capsys.readouterr()
    return rc, cap.out, cap.err


@pytest.mark.parametrize("args, needle", [
    (["--vary", "kx=1:2:1"], "unknown parameter 'kx'"),
    (["--vary", "eta=1:2:1"], "set its grid with --eta"),
    (["--vary", "kh=-10:10:5"], "--vary kh: kh must be >= 0"),
    (["--vary", "kh=10:1:1"], "STOP must be >= START"),
    (["--vary", "kh=1:2:0"], "STEP must be > 0"),
    (["--vary", "kh=a:b:c"], "three numbers"),
    (["--vary", "kh=1,x"], "must be numbers"),
    (["--vary", "kh"], "NAME=START:STOP:STEP"),
    (["--vary", "kh=0:1e9:1"], "at most 100000"),
    (["--eta", "0.5:1.5:0.0001", "--vary", "kh=1:300:1"], "at most 2000000"),
    (["--vary", "kh=1:2:1", "--vary", "f=0:0.1:0.05"], "exactly one --vary"),
    (["--vary", "kh=1:2:1", "--set", "kh=5"], "both --set and --vary"),
    (["--vary", "kh=1:2:1", "-o", "map.txt"], "use .zarr"),
    (["--vary", "kh=1:2:1", "--workers", "2", "--scheduler", "tcp://x:1"], "--workers"),
    (["--vary", "kh=1:2:1", "--preset", "nope"], "nope"),
    (["--vary", "kh=1:2:1", "--analyses", "bogus"], "unknown 'bogus'"),
])
def test_cli_bad_input_is_one_line_exit_2_nothing_written(args, needle, tmp_path, capsys,
                                                           monkeypatch):
    """Hypothesis: bad input to 'vibimpact map' ends with exit status 2 and one line
    'vibimpact: error: ...' naming the problem, no traceback, and no file written."""
    monkeypatch.chdir(tmp_path)

    def computed(*a, **k):  # a refusal comes before any work
        raise AssertionError("the map was computed")

    monkeypatch.setattr(M, "map2d", computed)
    rc, out, err = _main(capsys, "map", "--eta", "1.0:1.1:0.05", "--no-progress", *args)
    assert rc == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("vibimpact: error: "), err
    assert needle in lines[0], lines[0]
    assert "Traceback" not in err and out == ""
    assert list(tmp_path.iterdir()) == []


def test_cli_existing_output_is_refused(tmp_path, capsys, monkeypatch):
    """Hypothesis: an existing map is not replaced without --overwrite (exit 2, nothing
    written, the old store intact)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "m.zarr").mkdir()
    (tmp_path / "m.zarr" / "zarr.json").write_text("{}")
    rc, out, err = _main(capsys, "map", "--vary", "kh=1:2:1", "-o", "m.zarr")
    assert rc == 2 and "exists; pass --overwrite" in err
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["m.zarr", "zarr.json"]


def _cli(*args, cwd):
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH",
                                                                           ""))
    return subprocess.Popen([sys.executable, "-m", "vibimpact.cli", *map(str, args)],
                            cwd=cwd, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


@pytest.mark.slow
def test_cli_killed_map_resumes_to_the_uninterrupted_map(tmp_path, capsys):
    """Hypothesis: 'vibimpact map' SIGKILLed after some rows keeps them in its Zarr
    checkpoint OUT.partial, which 'vibimpact plot --kind map' can draw; '--resume' loads
    them without recomputing (their chunks untouched), writes a Zarr map equal to the
    API's uninterrupted one, and 'vibimpact plot --kind map' draws it."""
    eta, kh = "1.0:1.1:0.02", "20:160:20"
    args = ["map", "--eta", eta, "--vary", f"kh={kh}", "--workers", "1", "--no-progress",
            "-o", "m.zarr", "--keep-checkpoint"]
    proc = _cli(*args, cwd=tmp_path)
    part = tmp_path / "m.zarr.partial"
    deadline = time.monotonic() + 120
    while proc.poll() is None and time.monotonic() < deadline:
        if saved_rows(part) >= 2:
            proc.send_signal(signal.SIGKILL)
            break
        time.sleep(0.005)
    proc.wait(60)
    assert proc.returncode == -signal.SIGKILL, proc.stderr.read()
    n = saved_rows(part)
    assert 2 <= n < 8 and not (tmp_path / "m.zarr").exists()
    done = [i for i, flag in enumerate(open_map(part)["row_done"].values) if flag == 1]
    saved = {f: f.stat().st_mtime_ns for i in done for f in _entries(part, (i,))}
    rc, out, err = _main(capsys, "plot", str(part), "--kind", "map", "-o",
                         str(tmp_path / "partial.png"))
    assert rc == 0, err

    proc = _cli(*args, "--resume", cwd=tmp_path)
    out, err = proc.communicate(timeout=300)
    assert proc.returncode == 0, err
    assert f"{count(n, 'row')} loaded, not recomputed" in err
    assert all(f.stat().st_mtime_ns == t for f, t in saved.items())
    ds = open_map(tmp_path / "m.zarr")
    ref = vi.map2d(P, parse_range(eta), {"kh": parse_range(kh)})
    assert_same(ds, ref)
    assert ds.attrs["vary_range"] == f"kh={kh}"

    rc, out, err = _main(capsys, "plot", str(tmp_path / "m.zarr"), "-o",
                         str(tmp_path / "m.png"))
    assert rc == 0, err
    assert (tmp_path / "m.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_boundaries_lie_exactly_between_different_labels():
    """Hypothesis: the plot's boundary segments are the vertical lines between
    neighbouring eta points of different label in a row (the interval boundaries) and the
    horizontal lines between rows whose labels differ at the same eta; nothing else."""
    from vibimpact.plotting.map2d import _edges, boundaries

    lab = np.array([["a", "a", "b"],
                    ["a", "c", "c"]], dtype=object)
    xe, ye = _edges([1.0, 2.0, 3.0]), _edges([10.0, 20.0])
    assert xe.tolist() == [0.5, 1.5, 2.5, 3.5] and ye.tolist() == [5.0, 15.0, 25.0]
    segs = sorted(tuple(map(tuple, s)) for s in boundaries(lab, xe, ye))
    assert segs == sorted([((2.5, 5.0), (2.5, 15.0)),     # row 0: a | b
                           ((1.5, 15.0), (1.5, 25.0)),    # row 1: a | c
                           ((1.5, 15.0), (2.5, 15.0)),    # eta 2: a / c
                           ((2.5, 15.0), (3.5, 15.0))])   # eta 3: b / c


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_plot_map_draws_every_panel(serial, tmp_path):
    """Hypothesis: plot_map draws, per sweep direction, the four panels (regime, period,
    impacts, exponent) with the boundary lines of that direction's labels, and saves a
    PNG."""
    from matplotlib.collections import LineCollection

    from vibimpact.plotting.map2d import _edges, boundaries, plot_map

    fig = plot_map(serial, direction="up", path=tmp_path / "map.png")
    panels = [ax for ax in fig.axes if ax.get_title()]
    assert len(panels) == 4
    up = serial.sel(direction="up")
    want = len(boundaries(up["regime"].values, _edges(ETA), _edges(VARY["kh"])))
    assert want > 0
    for ax in panels:
        lines = [c for c in ax.collections if isinstance(c, LineCollection)]
        assert len(lines) == 1 and len(lines[0].get_segments()) == want
    assert (tmp_path / "map.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len([ax for ax in plot_map(serial).axes if ax.get_title()]) == 8


def test_cli_task_points_default_is_the_api_default():
    """`vibimpact map` groups rows like `map2d`: its --task-points default (a literal, so
    that --help imports nothing heavy) equals :data:`DEFAULT_TASK_POINTS`, and the task
    grouping gives a 151-point row a task of its own only when rows are long enough."""
    from vibimpact.cli import build_parser
    from vibimpact.maps import DEFAULT_TASK_POINTS

    args = build_parser().parse_args(["map", "--eta", "1:1.1:0.01", "--vary", "kh=10,20"])
    assert args.task_points == DEFAULT_TASK_POINTS
    assert [len(j) for j in plan.group(fake_tasks(10, 151), DEFAULT_TASK_POINTS, 0)] == \
        [-(-DEFAULT_TASK_POINTS // 151)] * (10 // -(-DEFAULT_TASK_POINTS // 151))
    assert [len(j) for j in plan.group(fake_tasks(10, 400), DEFAULT_TASK_POINTS, 0)] == \
        [1] * 10
