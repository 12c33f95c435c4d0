"""The ``vibimpact`` command line, the NetCDF writer and the (X, Y) plot.

The commands run in subprocesses (``python -m vibimpact.cli``) exactly as a user runs them,
with small runs (5 + 5 periods) so that the file stays fast once numba's cache is warm.
"""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
SMALL = ["--periods", "5", "--transient", "5"]


def cli(*args, cwd):
    """Run ``python -m vibimpact.cli ARGS`` in ``cwd``; the CompletedProcess."""
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-m", "vibimpact.cli", *map(str, args)], cwd=cwd,
                          env=env, capture_output=True, text=True, timeout=600)


@pytest.fixture(scope="module")
def simulated(tmp_path_factory):
    """One small run with --set and --plot, shared by the tests that read its files."""
    d = tmp_path_factory.mktemp("sim")
    r = cli("simulate", "--preset", "fig10", "--eta", "1.25", "--set", "BT=0.07",
            "--set", "Ec=0.3", *SMALL, "-o", "run.nc", "--plot", "xy.png", cwd=d)
    return d, r


@pytest.mark.parametrize("args", [["--help"], ["simulate", "--help"], ["presets", "--help"]])
def test_help_is_instant_and_light(args):
    """--help exits 0, shows an example, and imports neither numba nor numpy."""
    code = ("import sys\nfrom vibimpact.cli import main\n"
            "try:\n    main(%r)\nexcept SystemExit as e:\n    rc = e.code\n"
            "heavy = [m for m in ('numba', 'numpy', 'xarray', 'matplotlib') "
            "if m in sys.modules]\nprint('HEAVY', heavy, 'RC', rc)\n" % (args,))
    r = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert "HEAVY [] RC 0" in r.stdout
    assert "example" in r.stdout and "vibimpact " in r.stdout


def test_presets_lists_all(tmp_path):
    """`vibimpact presets` prints one row per preset with its parameters and description:
    the paper's nine in the table, every other built-in model's preset with its own
    parameter set's name."""
    import vibimpact as vi
    from vibimpact.builtin_models import rotor

    r = cli("presets", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert all(col in lines[0].split() for col in ("name", "kh", "G", "Bh", "BT", "f", "Rr"))
    for name in vi.presets.names():
        row = [ln for ln in lines if ln.split()[:1] == [name]]
        assert len(row) == 1, name
        assert vi.presets.describe(name) in row[0]
    assert len(rotor.paper_names()) == 9
    for name in set(vi.presets.names()) - set(rotor.paper_names()):
        row = [ln for ln in lines if ln.split()[:1] == [name]]
        assert type(vi.presets.get(name)).__name__ in row[0], name
    assert "not values from the paper" in r.stdout


def test_simulate_writes_self_describing_netcdf(simulated):
    """The file opens with plain xarray, has strobe (periods+1, 4), params and command."""
    import xarray as xr

    d, r = simulated
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""
    with xr.open_dataset(d / "run.nc") as ds:
        assert ds["strobe"].shape == (6, 4)
        assert list(ds["state"].values) == ["X", "Y", "dX", "dY"]
        assert ds.attrs["param_BT"] == 0.07 and ds.attrs["param_eta"] == 1.25
        assert ds.attrs["param_kh"] == 120.0 and ds.attrs["param_Ec"] == 0.3
        assert ds.sizes["impact"] > 0
        assert "--set BT=0.07" in ds.attrs["command"]
        assert ds.attrs["command"].startswith("vibimpact simulate")
        assert ds.attrs["status"] == "ok" and ds.attrs["solver_method"] == "dop853"
        assert ds.attrs["vibimpact_version"]
        assert ds["strobe"].attrs["units"] == "1"
        assert ds["impact_theta"].attrs["units"] == "degree"
        assert ds["trajectory"].shape == (5 * 64 + 1, 4)  # --plot keeps dense output
        assert np.all(np.isfinite(ds["strobe"].values))
    assert sorted(p.name for p in d.iterdir()) == ["run.nc", "xy.png"]  # no temp files


def test_dense_trajectory_is_the_recorded_window():
    """The dense trajectory after a transient equals the same window of a run from tau = 0
    (what --plot draws), and its every 64th sample is the stroboscopic sample."""
    import vibimpact as vi

    p = vi.presets.get("fig8").replace(eta=1.25, Ec=0.3)
    full = vi.simulate(p, periods=10, transient=0, dense=64)
    part = vi.simulate(p, periods=5, transient=5, dense=64)
    np.testing.assert_allclose(part.dense[::64], part.strobe, atol=1e-9)
    np.testing.assert_allclose(part.dense, full.dense[5 * 64:], atol=1e-6)


def test_plot_writes_png(simulated):
    """--plot writes a non-trivial PNG next to the NetCDF file."""
    d, r = simulated
    data = (d / "xy.png").read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_existing_output_needs_overwrite(simulated):
    """An existing output is refused (exit 2, file untouched) and replaced with --overwrite."""
    d, _ = simulated
    before = (d / "run.nc").read_bytes()
    r = cli("simulate", "--eta", "1.1", *SMALL, "-o", "run.nc", cwd=d)
    assert r.returncode == 2 and "--overwrite" in r.stderr
    assert (d / "run.nc").read_bytes() == before
    r = cli("simulate", "--eta", "1.1", *SMALL, "-o", "run.nc", "--overwrite", cwd=d)
    assert r.returncode == 0, r.stderr
    assert (d / "run.nc").read_bytes() != before


BAD = {
    "unknown preset": (["--preset", "fig99", "--eta", "1.2"], "fig99"),
    "unknown parameter": (["--eta", "1.2", "--set", "kq=3"], "kq"),
    "non-numeric --set": (["--eta", "1.2", "--set", "kh=abc"], "abc"),
    "--set without =": (["--eta", "1.2", "--set", "kh"], "NAME=VALUE"),
    "negative stiffness": (["--eta", "1.2", "--set", "kh=-1"], "kh"),
    "non-finite value": (["--eta", "1.2", "--set", "G=nan"], "G"),
    "eta <= 0": (["--eta", "0"], "eta"),
    "non-numeric eta": (["--eta", "fast"], "fast"),
    "eta NaN": (["--eta", "nan"], "nan"),
    "periods 0": (["--eta", "1.2", "--periods", "0"], "periods"),
    "bad method": (["--eta", "1.2", "--method", "euler"], "euler"),
    "negative rtol": (["--eta", "1.2", "--rtol", "-1e-9"], "rtol"),
    "eta via --set": (["--eta", "1.2", "--set", "eta=1.3"], "--eta"),
    "missing directory": (["--eta", "1.2", "-o", "no/such/dir/run.nc"], "does not exist"),
    "output is a directory": (["--eta", "1.2", "-o", "."], "directory"),
    "bad plot extension": (["--eta", "1.2", "--plot", "xy.xyz"], "xy.xyz"),
}


@pytest.mark.parametrize("case", list(BAD))
def test_bad_input_is_one_line_exit_2(case, tmp_path):
    """Bad input: exit 2, one stderr line 'vibimpact: error: ...', no traceback, no file."""
    args, needle = BAD[case]
    if "-o" not in args:
        args = args + ["-o", "run.nc"]
    r = cli("simulate", *args, *SMALL, cwd=tmp_path)
    assert r.returncode == 2, (r.stdout, r.stderr)
    lines = r.stderr.splitlines()
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith("vibimpact: error: ") and needle in lines[0]
    assert "Traceback" not in r.stderr and r.stdout == ""
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_diverged_run_is_written_with_a_warning(tmp_path):
    """A run that blows up (no contact stiffness, strong softening) still writes its file
    with status 'diverged' and the reason, warns on one stderr line and exits 0."""
    import xarray as xr

    r = cli("simulate", "--eta", "1.0", "--set", "kh=0", "--set", "k3=-0.5", "--set", "Ec=3",
            *SMALL, "-o", "div.nc", "--plot", "div.png", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stderr.startswith("vibimpact: warning: run DIVERGED") and \
        len(r.stderr.splitlines()) == 1
    with xr.open_dataset(tmp_path / "div.nc") as ds:
        assert ds.attrs["status"] == "diverged" and "bound" in ds.attrs["reason"]
        assert ds["strobe"].shape[1] == 4
    assert (tmp_path / "div.png").exists()


def test_main_in_process(capsys):
    """main(argv) returns the exit status instead of exiting (console-script entry)."""
    from vibimpact.cli import main

    assert main(["presets"]) == 0
    assert "fig11" in capsys.readouterr().out


def test_unknown_command_is_one_line(tmp_path):
    """An unknown subcommand is an argparse error: exit 2 and one stderr line."""
    r = cli("simulat", cwd=tmp_path)
    assert r.returncode == 2 and len(r.stderr.splitlines()) == 1
    assert r.stderr.startswith("vibimpact: error: ")


def test_dataset_round_trip(tmp_path):
    """run_to_dataset -> write_netcdf -> open_dataset gives back equal arrays and attributes,
    including the impact records, the dense trajectory and NaN exit times."""
    import xarray as xr

    import vibimpact as vi
    from vibimpact.io import run_to_dataset, write_netcdf

    # pinned: a configuration whose run ends inside a contact (a NaN exit time)
    p = vi.presets.get("fig8").replace(eta=1.25, Ec=0.3, B=0.07)
    run = vi.simulate(p, periods=5, transient=5, dense=8)
    assert len(run.impacts) > 0 and np.isnan(run.impacts["t_exit"]).any()
    ds = run_to_dataset(run, command="test", attrs={"flag": True, "nothing": None})
    assert ds.attrs["flag"] == 1 and ds.attrs["nothing"] == ""
    path = tmp_path / "rt.nc"
    write_netcdf(ds, path)
    with xr.open_dataset(path) as back:
        np.testing.assert_array_equal(back["strobe"].values, run.strobe)
        np.testing.assert_array_equal(back["t_strobe"].values, run.t_strobe)
        np.testing.assert_array_equal(back["trajectory"].values, run.dense)
        np.testing.assert_array_equal(back["time"].values, run.t_dense)
        for field in run.impacts.dtype.names:
            np.testing.assert_array_equal(back[f"impact_{field}"].values, run.impacts[field])
        assert back["impact_period"].dtype == np.int32
        for k, v in p.as_dict().items():
            assert back.attrs[f"param_{k}"] == v
        for k, v in run.counters.items():
            assert back.attrs[f"counter_{k}"] == v
        assert back.attrs["command"] == "test" and back.attrs["model"] == "rotor"
    with pytest.raises(ValueError, match="rt.nc"):
        write_netcdf(ds, path)
    write_netcdf(ds, path, overwrite=True)
    assert [f.name for f in tmp_path.iterdir()] == ["rt.nc"]


def test_write_failure_leaves_nothing(tmp_path):
    """A dataset NetCDF cannot store fails the write and leaves no partial or temp file."""
    import xarray as xr

    from vibimpact.io import write_netcdf

    ds = xr.Dataset({"a": ("x", np.arange(3.0))}, attrs={"bad": {"a": 1}})
    with pytest.raises(TypeError):
        write_netcdf(ds, tmp_path / "bad.nc")
    assert list(tmp_path.iterdir()) == []


def test_no_impacts_round_trip(tmp_path):
    """A run without contacts gives empty impact variables that survive the round trip."""
    import xarray as xr

    import vibimpact as vi
    from vibimpact.io import run_to_dataset, write_netcdf

    run = vi.simulate(vi.presets.get("fig8").replace(eta=0.5, Ec=0.01), periods=3,
                      transient=2)
    assert len(run.impacts) == 0
    write_netcdf(run_to_dataset(run), tmp_path / "e.nc")
    with xr.open_dataset(tmp_path / "e.nc") as back:
        assert back.sizes["impact"] == 0 and "trajectory" not in back


def test_plot_xy_reads_only_the_dataset(tmp_path):
    """plot_xy draws from a dataset read back from disk: Y inverted, equal aspect, impacts
    drawn on the unit circle."""
    import xarray as xr

    from vibimpact.plotting import plot_xy

    ds = xr.Dataset(
        {"strobe": (("sample", "state"), [[0.0, 0.5, 0.0, 0.0], [0.1, 0.6, 0.0, 0.0]]),
         "impact_theta": ("impact", [90.0, 45.0])},
        coords={"state": ["X", "Y", "dX", "dY"]}, attrs={"model": "rotor", "param_eta": 1.2})
    ax = plot_xy(ds, tmp_path / "p.png")
    assert ax.yaxis_inverted() and ax.get_xlabel() == "X"
    assert (tmp_path / "p.png").stat().st_size > 1000
    imp = [ln for ln in ax.get_lines() if ln.get_label().startswith("impacts")][0]
    np.testing.assert_allclose(np.hypot(imp.get_xdata(), imp.get_ydata()), 1.0)
    assert [f.name for f in tmp_path.iterdir()] == ["p.png"]


def test_version_prints_the_package_version_and_the_kernel_cache_status(tmp_path):
    """`vibimpact --version` prints 'vibimpact <__version__>' and, on a second line, the
    kernel cache's status as the package states it (cache_stamp.status: whether the cache
    filled at install is in use, and why not), then exits 0.  It loads numba only for
    that line (the cache's key holds numba's version and the processor); `--help` stays
    without it (test_help_is_instant_and_light)."""
    import vibimpact
    from vibimpact._kernel import cache_stamp

    r = subprocess.run([sys.executable, "-m", "vibimpact", "--version"], cwd=tmp_path,
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.strip().splitlines()
    assert lines[0] == f"vibimpact {vibimpact.__version__}"
    assert lines[1] == f"precompiled kernel: {cache_stamp.status()}"


@pytest.mark.slow  # two real sweeps in subprocesses; tests/test_verbose_log.py is the fast check
@pytest.mark.parametrize("where", ["before", "after"])
def test_verbose_reports_through_logging_and_quiet_by_default(where, tmp_path):
    """-v (before or after the command name) sends INFO records of the 'vibimpact' logger
    to stderr (the executor and the number of points); -vv adds DEBUG records; without
    it no log line is printed and the output file is the same."""
    sweep = ["classify", "--eta", "1.0,1.02", "--analyses", "period", "--workers", "1",
             "--no-progress"]
    runs = {}
    for flag in ("", "-v", "-vv"):
        args = [*sweep, "-o", f"c{flag}.nc"]
        if flag:
            args = [flag, *args] if where == "before" else [*args, flag]
        runs[flag] = cli(*args, cwd=tmp_path)
        assert runs[flag].returncode == 0, runs[flag].stderr
    assert "vibimpact: INFO" not in runs[""].stderr
    assert "vibimpact: INFO: 2 tasks (2 points to compute) on serial" in runs["-v"].stderr
    assert "DEBUG" not in runs["-v"].stderr
    assert "vibimpact: DEBUG:" in runs["-vv"].stderr
    from vibimpact.io import differences, read_netcdf

    assert differences(read_netcdf(tmp_path / "c.nc"), read_netcdf(tmp_path / "c-v.nc"))[0] == []


@pytest.mark.parametrize("argv, count", [
    (["-v", "classify", "-v"], 2), (["-v", "-v", "classify"], 2), (["classify", "-vv"], 2),
    (["--verbose", "classify", "-vv"], 3), (["classify"], 0), (["-v", "rerun", "x.nc"], 1)])
def test_verbose_counts_before_and_after_the_command(argv, count):
    """Hypothesis: argparse copies a command parser's own namespace over the main one, so
    `-v classify -v` would count 1 (INFO) instead of 2 (DEBUG); every -v counts wherever
    it stands."""
    from vibimpact.cli.common.args import verbosity
    from vibimpact.cli import build_parser

    args = [*argv, "--eta", "1.0"] if "classify" in argv else argv
    assert verbosity(build_parser().parse_args(args)) == count


def test_verbosity_does_not_outlive_an_in_process_run(tmp_path, monkeypatch, capsys):
    """Hypothesis: main(['-v', ...]) leaves the logger's level and stderr handler behind,
    so a later main() without -v in the same process still logs, and the handler keeps
    writing to the stderr of the first call instead of the current one."""
    import contextlib
    import io

    from vibimpact.cli.common.args import set_verbosity
    from vibimpact.cli import main

    monkeypatch.chdir(tmp_path)
    run = ["classify", "--eta", "1.0", "--analyses", "period", "--workers", "1",
           "--no-progress", "-o"]
    try:
        assert main(["-v", *run, "a.nc"]) == 0
        assert "vibimpact: INFO:" in capsys.readouterr().err
        assert main([*run, "b.nc"]) == 0
        assert "vibimpact: INFO:" not in capsys.readouterr().err
        assert main(["-v", *run, "c.nc"]) == 0
        capsys.readouterr()
        redirected = io.StringIO()
        with contextlib.redirect_stderr(redirected):
            assert main(["-v", *run, "d.nc"]) == 0
        assert "vibimpact: INFO:" in redirected.getvalue()
        assert "vibimpact: INFO:" not in capsys.readouterr().err
    finally:
        set_verbosity(0)


@pytest.mark.parametrize("expr", ["vi.maps.open_map", "vi.plotting.plot_xy",
                                  "vi.io.read_netcdf", "vi.sweeps.parse_range",
                                  "vi.analysis.detect_period"])
def test_subpackages_are_attributes_of_a_fresh_import(expr, tmp_path):
    """A fresh `import vibimpact as vi` reaches the user-facing subpackages as attributes
    (as the README shows vi.maps.open_map) without importing them first, and the bare
    import still loads no numba."""
    code = ("import sys\nimport vibimpact as vi\nassert 'numba' not in sys.modules\n"
            f"assert callable({expr})\n")
    r = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr
