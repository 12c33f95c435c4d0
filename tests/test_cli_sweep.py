"""The sweep commands of the command line: ``classify``, ``bifurcation`` and ``plot``.

The commands run in subprocesses (``python -m vibimpact.cli``) exactly as a user runs them,
on tiny grids (a few points of fig8, quick once numba's disk cache is warm).  The
interrupt tests send real signals (SIGINT, SIGKILL) to a running sweep and check that
``--resume`` finishes it without recomputing the saved points, bit-identical to an
uninterrupted run.
"""
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from vibimpact.base._text import count

ROOT = Path(__file__).resolve().parents[1]
TINY = ["--eta", "1.0:1.02:0.01", "--preset", "fig8"]
ONE = ["--eta", "1.0:1.0:0.01", "--preset", "fig8", "--no-progress"]
PNG = b"\x89PNG\r\n\x1a\n"


def _env():
    return dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH",
                                                                           ""))


def cli(*args, cwd):
    """Run ``python -m vibimpact.cli ARGS`` in ``cwd``; the CompletedProcess."""
    return subprocess.run([sys.executable, "-m", "vibimpact.cli", *map(str, args)], cwd=cwd,
                          env=_env(), capture_output=True, text=True, timeout=600)


def assert_usage_error(r, needle, cwd=None, before=()):
    """Exit 2, one stderr line 'vibimpact: error: ...' containing ``needle``, no
    traceback, nothing on stdout, and (with ``cwd``) no new file."""
    assert r.returncode == 2, (r.stdout, r.stderr)
    lines = r.stderr.splitlines()
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith("vibimpact: error: ") and needle in lines[0], lines[0]
    assert "Traceback" not in r.stderr and r.stdout == ""
    if cwd is not None:
        assert sorted(p.name for p in Path(cwd).iterdir()) == sorted(before)


def assert_same_data(a, b):
    """Every data variable and coordinate of ``a`` and ``b`` is exactly equal (NaN equal
    to NaN), with the same dtype (strings: object or fixed-width unicode alike)."""
    assert set(a.data_vars) == set(b.data_vars)
    assert set(a.coords) == set(b.coords)
    for name in list(a.data_vars) + list(a.coords):
        x, y = a[name].values, b[name].values
        assert x.shape == y.shape, name
        if x.dtype.kind in "OUS" or y.dtype.kind in "OUS":
            assert x.astype(str).tolist() == y.astype(str).tolist(), name
            continue
        assert x.dtype == y.dtype, name
        if x.dtype.kind in "fc":
            assert np.array_equal(x, y, equal_nan=True), name
        else:
            assert np.array_equal(x, y), name


@pytest.fixture(scope="module")
def classified(tmp_path_factory):
    """`vibimpact classify` on three fig8 points (default workers and progress bar)."""
    d = tmp_path_factory.mktemp("classify")
    t0 = time.perf_counter()
    r = cli("classify", *TINY, "-o", "c.nc", cwd=d)
    return d, r, time.perf_counter() - t0


# --- help -----------------------------------------------------------------------------

@pytest.mark.parametrize("command", ["classify", "bifurcation", "plot"])
def test_help_is_instant_and_light(command):
    """`COMMAND --help` exits 0, shows an example, and imports neither numba, numpy,
    xarray nor matplotlib (so it is instant)."""
    code = ("import sys\nfrom vibimpact.cli import main\n"
            "try:\n    main([%r, '--help'])\nexcept SystemExit as e:\n    rc = e.code\n"
            "heavy = [m for m in ('numba', 'numpy', 'xarray', 'matplotlib') "
            "if m in sys.modules]\nprint('HEAVY', heavy, 'RC', rc)\n" % command)
    r = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert "HEAVY [] RC 0" in r.stdout
    assert "example" in r.stdout and f"vibimpact {command} " in r.stdout


def test_main_help_lists_the_sweep_commands(tmp_path):
    """`vibimpact --help` lists classify, bifurcation and plot."""
    r = cli("--help", cwd=tmp_path)
    assert r.returncode == 0
    for command in ("classify", "bifurcation", "plot"):
        assert command in r.stdout


# --- classify -------------------------------------------------------------------------

def test_classify_writes_netcdf_and_interval_table(classified):
    """classify writes a NetCDF that plain xarray opens (one value per eta of the grid,
    STOP included), prints the interval table and 'wrote c.nc', and leaves no checkpoint
    directory or temporary file behind."""
    import xarray as xr

    d, r, _ = classified
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0].split()[:3] == ["direction", "eta", "from"]
    assert lines[-1] == "wrote c.nc"
    assert any(ln.split()[:2] == ["up", "1.0000"] for ln in lines[1:-1])
    assert sorted(p.name for p in d.iterdir()) == ["c.nc"]  # no c.nc.partial
    with xr.open_dataset(d / "c.nc") as ds:
        np.testing.assert_allclose(ds["eta"].values, [1.0, 1.01, 1.02])
        for name in ("regime", "label", "period", "impacts_per_period", "lyapunov",
                     "lyapunov_err", "k01", "X_m", "Y_m", "R_m", "min_gap", "arcs",
                     "poincare_X", "poincare_Y"):
            assert name in ds, name
        assert ds["poincare_X"].dims == ("eta", "sample")
        assert ds.attrs["command"] == "vibimpact classify " + " ".join(TINY) + " -o c.nc"
        assert ds.attrs["preset"] == "fig8" and ds.attrs["param_kh"] == 120.0
        assert set(ds["regime"].values) <= set(ds["regime"].attrs["flag_values"].tolist())
        assert np.all(np.isfinite(ds["X_m"].values))


def test_classify_file_is_the_api_sweep_lossless(classified):
    """The file holds exactly what vi.sweep returns for the same request (the command
    line adds nothing and the NetCDF round trip loses nothing; workers do not matter):
    plain xarray.open_dataset, read_netcdf and the in-memory dataset agree bit for bit."""
    import xarray as xr

    import vibimpact as vi
    from vibimpact.io import read_netcdf
    from vibimpact.sweeps import parse_range

    d, _, _ = classified
    mem = vi.sweep(vi.presets.get("fig8"), parse_range("1.0:1.02:0.01"),
                   execution=vi.Execution(workers=1))
    back = read_netcdf(d / "c.nc")
    with xr.open_dataset(d / "c.nc") as plain:
        assert_same_data(plain, back)
    assert_same_data(mem, back)
    assert list(back["label"].values) == list(mem["label"].values)


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_eta_list_sweeps_exactly_the_listed_values(tmp_path):
    """--eta V1,V2 (as --vary takes lists) sweeps exactly those values: the file's eta
    coordinate is the list and its labels equal the API sweep over the same list."""
    import vibimpact as vi
    from vibimpact.io import read_netcdf

    r = cli("classify", "--eta", "1.0,1.03", "--analyses", "period,impacts", "--workers",
            "1", "--no-progress", "-o", "c.nc", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    ds = read_netcdf(tmp_path / "c.nc")
    assert ds["eta"].values.tolist() == [1.0, 1.03]
    mem = vi.sweep(vi.presets.get("fig8"), [1.0, 1.03], analyses=("period", "impacts"),
                   execution=vi.Execution(workers=1))
    assert list(ds["label"].values) == list(mem["label"].values)


BAD_ETA = ["1:0.5:0.1", "a:b:c", "1:2:0", "1:2:-0.1", "1.0:1.1", "0:1:0.1", "1:nan:0.1"]


@pytest.mark.parametrize("eta", BAD_ETA)
def test_bad_eta_is_one_line_exit_2(eta, tmp_path):
    """A bad --eta range (reversed, not numbers, zero or negative step, two parts,
    eta <= 0, NaN) is refused before any work: exit 2, one line naming eta, no file."""
    r = cli("classify", "--eta", eta, "-o", "c.nc", cwd=tmp_path)
    assert_usage_error(r, "eta", tmp_path)


BAD_INPUT = {
    "unknown analysis": (["--analyses", "period,spectrum"], "spectrum"),
    "empty analyses": (["--analyses", ","], "--analyses"),
    "unknown preset": (["--preset", "fig99"], "fig99"),
    "bad --set": (["--set", "kh=abc"], "abc"),
    "unknown parameter": (["--set", "kq=1"], "kq"),
    "eta via --set": (["--set", "eta=1.2"], "--eta"),
    "workers 0": (["--workers", "0"], "workers"),
    "blocks 0": (["--blocks", "0"], "blocks"),
    "bad direction": (["--direction", "sideways"], "sideways"),
    "missing directory": (["-o", "no/such/dir/c.nc"], "does not exist"),
}


@pytest.mark.parametrize("case", list(BAD_INPUT))
def test_classify_bad_input_is_one_line_exit_2(case, tmp_path):
    """Bad classify input: exit 2, one stderr line naming the problem, no file."""
    args, needle = BAD_INPUT[case]
    if "-o" not in args:
        args = args + ["-o", "c.nc"]
    r = cli("classify", *ONE, *args, cwd=tmp_path)
    assert_usage_error(r, needle, tmp_path)


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_existing_output_needs_overwrite(tmp_path):
    """An existing output is refused before computing (exit 2, file untouched, no
    checkpoint made) and replaced with --overwrite."""
    out = tmp_path / "c.nc"
    out.write_bytes(b"old")
    r = cli("classify", *ONE, "-o", "c.nc", cwd=tmp_path)
    assert_usage_error(r, "--overwrite", tmp_path, ["c.nc"])
    assert out.read_bytes() == b"old"
    r = cli("classify", *ONE, "-o", "c.nc", "--overwrite", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert out.read_bytes()[:4] == b"\x89HDF"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.nc"]


def test_existing_checkpoint_needs_resume(tmp_path):
    """A checkpoint directory left by an interrupted run is never silently reused or
    overwritten: without --resume the command stops (exit 2) and suggests --resume."""
    (tmp_path / "c.nc.partial").mkdir()
    r = cli("classify", *ONE, "-o", "c.nc", cwd=tmp_path)
    assert_usage_error(r, "--resume", tmp_path, ["c.nc.partial"])


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_resume_refuses_a_checkpoint_of_another_sweep(tmp_path):
    """--resume with a checkpoint made for a different grid is refused (exit 2, one line)
    instead of mixing two sweeps; --keep-checkpoint keeps the checkpoint after writing."""
    r = cli("classify", *ONE, "-o", "c.nc", "--keep-checkpoint", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert list((tmp_path / "c.nc.partial").glob("up_*.npz"))  # one entry per point
    before = (tmp_path / "c.nc").read_bytes()
    r = cli("classify", "--eta", "1.0:1.01:0.01", "--no-progress", "-o", "c.nc",
            "--resume", cwd=tmp_path)
    assert_usage_error(r, "different", tmp_path, ["c.nc", "c.nc.partial"])
    assert (tmp_path / "c.nc").read_bytes() == before


# --- interrupt and resume with real signals -------------------------------------------

LONG = ["--eta", "0.95:1.25:0.01", "--preset", "fig8"]
N_LONG = 31


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The uninterrupted sweep the interrupted-and-resumed runs must reproduce."""
    from vibimpact.io import read_netcdf

    d = tmp_path_factory.mktemp("reference")
    r = cli("classify", *LONG, "--workers", "1", "-o", "ref.nc", cwd=d)
    assert r.returncode == 0, r.stderr
    return read_netcdf(d / "ref.nc")


def _points(ckpt):
    """Finished point files of a checkpoint -> (mtime_ns, inode)."""
    try:
        names = [f for f in os.listdir(ckpt) if f.endswith(".npz") and not f.startswith(".")]
    except OSError:
        return {}
    out = {}
    for f in names:
        try:
            st = os.stat(os.path.join(ckpt, f))
        except FileNotFoundError:
            continue
        out[f] = (st.st_mtime_ns, st.st_ino)
    return out


@pytest.mark.slow
@pytest.mark.parametrize("sig,workers", [("SIGINT", 1), ("SIGKILL", 1), ("SIGINT", 2)])
def test_interrupted_sweep_resumes_bit_identical(sig, workers, tmp_path, reference):
    """A classify run stopped by a real signal after >= 5 saved points (SIGINT: exit 130
    and the 'interrupted: N points saved ...; rerun with --resume' line; SIGKILL: no
    chance to clean up) keeps its points; rerunning with --resume loads them without
    recomputing (their files untouched, the progress bar counts only the missing points)
    and writes a file whose data equals the uninterrupted run's bit for bit.  With two
    workers, Ctrl-C (SIGINT to the process group, as a terminal sends it) stops the
    workers too: no point is saved after the command exits."""
    signum = getattr(signal, sig)
    ckpt = tmp_path / "X.nc.partial"
    cmd = ["classify", *LONG, "--workers", str(workers), "-o", "X.nc"]
    proc = subprocess.Popen([sys.executable, "-m", "vibimpact.cli", *cmd], cwd=tmp_path,
                            env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True)
    try:
        deadline = time.monotonic() + 300  # includes a first numba compilation
        while len(_points(ckpt)) < 5:
            assert proc.poll() is None, ("finished before the signal", proc.stderr.read())
            if time.monotonic() > deadline:
                pytest.fail("no checkpoint points appeared")
            time.sleep(0.005)
        if workers > 1:
            os.killpg(proc.pid, signum)  # what Ctrl-C in a terminal does
        else:
            proc.send_signal(signum)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    saved = _points(ckpt)
    if signum == signal.SIGINT:
        assert proc.returncode == 130, err
        assert err.splitlines()[-1] == (f"vibimpact: interrupted: "
                                        f"{count(len(saved), 'point')} saved "
                                        f"in X.nc.partial; rerun with --resume")
        assert "Traceback" not in err
    else:
        assert proc.returncode == -signal.SIGKILL
    assert 5 <= len(saved) < N_LONG, len(saved)
    assert not (tmp_path / "X.nc").exists()
    time.sleep(0.5)
    assert _points(ckpt) == saved  # nothing (no orphaned worker) goes on computing

    r = cli(*cmd, cwd=tmp_path)  # the checkpoint is not reused without --resume
    assert_usage_error(r, "--resume")

    r = cli(*cmd, "--resume", "--keep-checkpoint", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[-1] == "wrote X.nc"
    counts = re.findall(r"(\d+)/(\d+) \[", r.stderr)
    assert counts and counts[-1] == (str(N_LONG - len(saved)),) * 2, r.stderr[-500:]
    after = _points(ckpt)
    assert len(after) == N_LONG
    assert {f: after[f] for f in saved} == saved  # not rewritten: same mtime and inode

    from vibimpact.io import read_netcdf

    resumed = read_netcdf(tmp_path / "X.nc")
    assert_same_data(resumed, reference)
    assert resumed.attrs["command"].endswith("-o X.nc --resume --keep-checkpoint")


# --- bifurcation and plot -------------------------------------------------------------

@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_bifurcation_writes_png_and_its_data(tmp_path):
    """bifurcation writes the PNG and the data next to it (same stem, .nc) with up and
    down sweeps and the analyses that decide a label (those of classify) but not the
    response; 'plot --kind bifurcation' redraws it, and '--kind response' is refused
    (the file has no response data)."""
    from vibimpact.cli.bifurcation import LABEL_ANALYSES
    from vibimpact.plotting.needs import recorded_analyses
    import xarray as xr

    r = cli("bifurcation", *TINY, "-o", "bif.png", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "wrote bif.png and bif.nc"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bif.nc", "bif.png"]
    data = (tmp_path / "bif.png").read_bytes()
    assert data[:8] == PNG and len(data) > 10_000
    with xr.open_dataset(tmp_path / "bif.nc") as ds:
        assert list(ds["direction"].values) == ["up", "down"]
        assert ds["poincare_X"].dims == ("direction", "eta", "sample")
        assert np.all(np.isfinite(ds["poincare_X"].values))
        assert recorded_analyses(ds) == set(LABEL_ANALYSES)
        assert np.all(np.isnan(ds["X_m"].values))
        assert ds.attrs["command"].startswith("vibimpact bifurcation --eta")
    r = cli("plot", "bif.nc", "--kind", "bifurcation", "-o", "again.png", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "again.png").read_bytes()[:8] == PNG
    r = cli("plot", "bif.nc", "--kind", "response", "-o", "resp.png", cwd=tmp_path)
    assert_usage_error(r, "response")
    r = cli("bifurcation", *TINY, "-o", "bif.png", cwd=tmp_path)
    assert_usage_error(r, "--overwrite")


@pytest.mark.parametrize("args,needle", [(["-o", "bif.nc"], "extension"),
                                         (["--eta", "2:1:0.1"], "eta")])
def test_bifurcation_bad_input(args, needle, tmp_path):
    """bifurcation refuses a non-image output and a bad range: exit 2, one line."""
    r = cli("bifurcation", "--no-progress", *args, cwd=tmp_path)
    assert_usage_error(r, needle, tmp_path)


@pytest.mark.parametrize("kind", ["response", "bifurcation", "intervals"])
def test_plot_each_kind_from_classify_output(kind, classified):
    """plot draws every sweep kind from the classify file (default name FILE_KIND.png)."""
    d, r, _ = classified
    assert r.returncode == 0, r.stderr
    out = d / f"c_{kind}.png"
    if out.exists():
        out.unlink()
    r = cli("plot", "c.nc", "--kind", kind, cwd=d)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == f"wrote c_{kind}.png"
    data = out.read_bytes()
    assert data[:8] == PNG and len(data) > 10_000


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_plot_xy_of_a_simulate_file(tmp_path):
    """plot --kind xy (also the default) draws a simulate file; a sweep kind is refused."""
    r = cli("simulate", "--eta", "1.25", "--periods", "5", "--transient", "5", "-o",
            "run.nc", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    r = cli("plot", "run.nc", "-o", "xy.png", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "xy.png").read_bytes()[:8] == PNG
    r = cli("plot", "run.nc", "--kind", "intervals", "-o", "iv.png", cwd=tmp_path)
    assert_usage_error(r, "simulate")


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_plot_bad_input(classified, tmp_path):
    """plot: a missing file, a file that is not NetCDF, an unknown kind, xy of a sweep,
    an unknown image extension and an existing image: exit 2 with one line."""
    d, _, _ = classified
    (tmp_path / "junk.nc").write_text("not netcdf\n")
    src = str(d / "c.nc")
    cases = [(["missing.nc", "--kind", "response"], "no such file"),
             (["junk.nc", "--kind", "response"], "cannot read"),
             ([src, "--kind", "spectrum"], "spectrum"),
             ([src, "--kind", "xy", "-o", "x.png"], "sweep"),
             ([src, "--kind", "response", "-o", "r.xyz"], "extension")]
    for args, needle in cases:
        r = cli("plot", *args, cwd=tmp_path)
        assert_usage_error(r, needle, tmp_path, ["junk.nc"])
    (tmp_path / "r.png").write_bytes(b"old")
    r = cli("plot", src, "--kind", "response", "-o", "r.png", cwd=tmp_path)
    assert_usage_error(r, "--overwrite")
    assert (tmp_path / "r.png").read_bytes() == b"old"


def _fake_sweep(both=True):
    """A small sweep-shaped dataset built by hand: the plots need no computation."""
    import xarray as xr

    eta = np.array([1.0, 1.1, 1.2, 1.3])
    regime = np.array([1, 1, 3, 2], dtype="i1")
    period = np.array([1, 2, 0, 0], dtype="i4")
    labels = np.array(["P1 impactless", "P2, 4 impacts", "chaotic, impacting",
                       "quasi-periodic, impacting"], dtype=object)
    px = np.tile(np.array([0.1, 0.2, 0.3, 0.4])[:, None], (1, 8))
    data = {"regime": regime, "period": period, "label": labels,
            "impacts_per_period": np.array([0.0, 4.0, 3.5, 2.0]),
            "arcs": np.array(["", "2 small arcs", "whole circle", "3 arcs"], dtype=object),
            "X_m": np.array([0.5, 0.9, 1.05, 1.02]), "Y_m": np.array([0.6, 0.95, 1.1, 1.0])}
    if both:
        ds = xr.Dataset({k: (("direction", "eta"), np.stack([v, v])) for k, v in data.items()},
                        coords={"eta": eta, "direction": ["up", "down"]})
        ds["poincare_X"] = (("direction", "eta", "sample"), np.stack([px, -px]))
        ds["poincare_Y"] = (("direction", "eta", "sample"), np.stack([px, px]))
    else:
        ds = xr.Dataset({k: ("eta", v) for k, v in data.items()}, coords={"eta": eta},
                        attrs={"sweep_direction": "down"})
        ds["poincare_X"] = (("eta", "sample"), px)
        ds["poincare_Y"] = (("eta", "sample"), px)
    ds.attrs.update(model="rotor", preset="fig8", param_kh=120.0, param_G=0.3)
    return ds


@pytest.mark.parametrize("both", [True, False])
def test_plot_functions_read_only_the_dataset(both, tmp_path):
    """plot_bifurcation, plot_response and plot_intervals draw a hand-made dataset (no
    sweep run): up and down in two colours, chaotic points marked, one band per interval
    and one row per direction; they save atomically when given a path."""
    import matplotlib.colors as mcolors

    from vibimpact.plotting import plot_bifurcation, plot_intervals, plot_response

    ds = _fake_sweep(both)
    fig = plot_bifurcation(ds, path=tmp_path / "b.png")
    top = fig.axes[0]
    colours = {mcolors.to_hex(ln.get_color()) for ln in top.get_lines()}
    assert len(fig.axes) == 2 and len(colours) == (2 if both else 1)
    assert sum(len(ln.get_xdata()) for ln in top.get_lines()) == (2 if both else 1) * 32

    fig = plot_response(ds, path=tmp_path / "r.png")
    chaotic = [ln for ln in fig.axes[0].get_lines() if ln.get_marker() == "x"]
    assert chaotic and all(list(ln.get_xdata()) == [1.2] for ln in chaotic)
    assert len(chaotic) == (2 if both else 1)

    fig = plot_intervals(ds, path=tmp_path / "i.png")
    ax = fig.axes[0]
    assert len(ax.collections) == (8 if both else 4)  # 4 intervals per direction
    assert len(ax.get_yticks()) == (2 if both else 1)
    for name in ("b.png", "r.png", "i.png"):
        assert (tmp_path / name).read_bytes()[:8] == PNG
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.png", "i.png", "r.png"]
