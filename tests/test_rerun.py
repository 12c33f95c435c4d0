"""Reproducibility: ``vibimpact rerun`` reproduces simulate, classify and bifurcation
outputs bit for bit and reports an altered file; a checkpoint with damaged point files
resumes to the uninterrupted result."""
import math
import os
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

from vibimpact.cli import main

from test_bad_input import SIM, assert_refused, listing, run_cli  # noqa: F401


# --- rerun ---------------------------------------------------------------------------------

def test_rerun_simulate_is_identical(tmp_path, monkeypatch, capfd):
    """A simulate file (with --plot, which implies dense samples) reruns bit-identical;
    the temporary rerun file is removed and the plot is not redrawn."""
    monkeypatch.chdir(tmp_path)
    rc, _, err = run_cli([*SIM, "--set", "Ec=0.3", "-o", "run.nc", "--plot", "xy.png"], capfd)
    assert rc == 0, err
    rc, out, err = run_cli(["rerun", "run.nc"], capfd)
    assert rc == 0, err
    assert out.startswith("identical: ") and out.strip().endswith("attributes of the run")
    assert int(out.split()[1]) >= 10
    assert listing(tmp_path) == ["run.nc", "xy.png"]


@pytest.fixture(scope="module")
def classified(tmp_path_factory):
    """classify with STOP off the grid (1.025: the grid is 1.00, 1.01, 1.02), keeping its
    checkpoint for the damaged-checkpoint test."""
    d = tmp_path_factory.mktemp("rerun")
    mp = pytest.MonkeyPatch()
    mp.chdir(d)
    try:
        rc = main(["classify", "--eta", "1.0:1.025:0.01", "--no-progress", "--workers", "1",
                   "--analyses", "period,impacts,response,poincare", "-o", "c.nc",
                   "--keep-checkpoint"])
    finally:
        mp.undo()
    assert rc == 0
    return d


def test_stop_off_the_grid_classifies(classified):
    """The off-grid STOP is accepted by classify: three points, STOP excluded."""
    from vibimpact.io import read_netcdf

    ds = read_netcdf(classified / "c.nc")
    assert ds["eta"].values.tolist() == [1.0, 1.01, 1.02]


def test_rerun_classify_identical_and_altered_copy_differs(classified, monkeypatch, capfd):
    """classify's file reruns identical (exit 0); a copy with one altered value is reported
    as different, naming the variable (exit 1); -o keeps the rerun file."""
    from vibimpact.io import read_netcdf, write_netcdf

    monkeypatch.chdir(classified)
    rc, out, err = run_cli(["rerun", "c.nc"], capfd)
    assert rc == 0, err
    assert out.startswith("identical: ")
    ds = read_netcdf("c.nc")
    ds["X_m"].values[1] = np.nextafter(ds["X_m"].values[1], 2.0)  # one bit
    write_netcdf(ds, "altered.nc", overwrite=True)
    rc, out, err = run_cli(["rerun", "altered.nc", "-o", "again.nc", "--overwrite"], capfd)
    assert rc == 1, err
    lines = out.splitlines()
    assert lines[0].startswith("different: 1 of ")
    assert lines[1].split(":")[0].strip() == "X_m"
    assert (classified / "again.nc").is_file()
    assert not [n for n in listing(classified) if "rerun" in n]


def test_rerun_bifurcation_data(tmp_path, monkeypatch, capfd):
    """bifurcation's data file reruns identical without drawing an image."""
    monkeypatch.chdir(tmp_path)
    rc, _, err = run_cli(["bifurcation", "--eta", "1.0:1.01:0.01", "--no-progress",
                          "--workers", "1", "-o", "b.png"], capfd)
    assert rc == 0, err
    rc, out, err = run_cli(["rerun", "b.nc"], capfd)
    assert rc == 0, err
    assert out.startswith("identical: ")
    assert listing(tmp_path) == ["b.nc", "b.png"]


@pytest.mark.parametrize("flag", ["-v", "-vv", "--verbose"])
def test_rerun_of_a_command_with_verbose_before_its_name(flag, tmp_path, monkeypatch,
                                                          capfd):
    """Hypothesis: a file written by `vibimpact -v simulate ...` (-v before the command
    name, as the README shows) records that command line, and rerun took the word after
    'vibimpact' for the command, refusing the file as 'not a vibimpact ... command'."""
    from vibimpact.cli.common.args import set_verbosity

    monkeypatch.chdir(tmp_path)
    try:
        rc, _, err = run_cli([flag, *SIM, "-o", "r.nc"], capfd)
        assert rc == 0, err
        rc, out, err = run_cli(["rerun", "r.nc"], capfd)
    finally:
        set_verbosity(0)
    assert rc == 0, err
    assert out.startswith("identical: ")
    assert listing(tmp_path) == ["r.nc"]


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
@pytest.mark.parametrize("out", ["m.zarr", "m.nc"])
def test_rerun_map_store_and_netcdf(out, tmp_path, monkeypatch, capfd):
    """A map, as a Zarr store or a NetCDF file, reruns identical (exit 0) with no image
    redrawn and no temporary store left; -o keeps the rerun output in the same format."""
    monkeypatch.chdir(tmp_path)
    rc, _, err = run_cli(["map", "--eta", "1.0:1.02:0.02", "--vary", "kh=60,120",
                          "--workers", "1", "--no-progress", "-o", out, "--plot", "m.png"],
                         capfd)
    assert rc == 0, err
    rc, text, err = run_cli(["rerun", out], capfd)
    assert rc == 0, err
    assert text.startswith("identical: ") and int(text.split()[1]) >= 10
    assert listing(tmp_path) == sorted([out, "m.png"])
    again = "again" + out[1:]
    rc, text, err = run_cli(["rerun", out, "-o", again], capfd)
    assert rc == 0, err
    assert (tmp_path / again).exists() and text.strip().endswith(f"wrote {again}")


# --- damaged checkpoint points ----------------------------------------------------------------

def test_damaged_checkpoint_points_are_recomputed(classified, monkeypatch, capfd):
    """Garbage and truncated point files in a checkpoint are set aside as *.corrupt and
    recomputed (one warning line); the resumed file equals the uninterrupted one."""
    from vibimpact.io import differences as _differences
    from vibimpact.io import read_netcdf

    monkeypatch.chdir(classified)
    if os.path.exists("d.nc.partial"):
        shutil.rmtree("d.nc.partial")
    shutil.copytree("c.nc.partial", "d.nc.partial")
    ck = classified / "d.nc.partial"
    first, second = sorted(ck.glob("up_*.npz"))[:2]  # one entry per point
    first.write_bytes(b"garbage")
    good = second.read_bytes()
    second.write_bytes(good[: len(good) // 2])
    rc, out, err = run_cli(["classify", "--eta", "1.0:1.025:0.01", "--no-progress",
                            "--workers", "1", "--analyses", "period,impacts,response,poincare",
                            "-o", "d.nc", "--resume"], capfd)
    assert rc == 0, err
    assert "Traceback" not in err
    assert "vibimpact: warning: 2 point files in d.nc.partial were set aside as *.corrupt" in err
    assert err.count(": damaged") == 2 and "their 2 points were computed again" in err
    assert "1 point loaded" in err  # one, not "1 points"
    assert out.splitlines()[-1] == "wrote d.nc"
    assert not ck.exists()
    diffs, total = _differences(read_netcdf("c.nc"), read_netcdf("d.nc"))
    assert diffs == [] and total > 10


def test_load_sets_aside_a_foreign_npz(tmp_path):
    """An entry that loads but is not one (missing fields), or one of another request,
    counts as not done: set aside as *.corrupt and listed by the resume."""
    from vibimpact.engine.store import Checkpoint, entry_name

    ck = Checkpoint(tmp_path / "ck").open("sweep", {"a": 1}, {"points": 5}, False)
    np.savez(ck.path / entry_name(0, "up", 3, 4), a=np.arange(3))
    ck.save(0, "up", [(1, {"regime": 1, "final_state": np.zeros(4)})])
    other = Checkpoint(tmp_path / "other").open("sweep", {"a": 2}, {"points": 5}, False)
    other.save(0, "up", [(2, {"regime": 1, "final_state": np.ones(4)})])
    os.replace(other.path / entry_name(0, "up", 2, 3), ck.path / entry_name(0, "up", 2, 3))
    done = ck.load()
    assert list(done) == [(0, "up")] and list(done[(0, "up")]) == [1]
    assert done[(0, "up")][1]["final_state"].tolist() == [0.0] * 4
    assert ck.last_resume()["damaged"] == [entry_name(0, "up", 2, 3) + ".corrupt",
                                           entry_name(0, "up", 3, 4) + ".corrupt"]
    assert ck.saved() == (1, 0)
    assert list(ck.load()) == [(0, "up")]  # now simply absent


def test_rerun_help_is_light():
    """`rerun --help` exits 0 with an example and imports no heavy module."""
    import subprocess

    code = ("import sys\nfrom vibimpact.cli import main\n"
            "try:\n    main(['rerun', '--help'])\nexcept SystemExit as e:\n    rc = e.code\n"
            "heavy = [m for m in ('numba', 'numpy', 'xarray', 'matplotlib') "
            "if m in sys.modules]\nprint('HEAVY', heavy, 'RC', rc)\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       timeout=60, cwd=Path(__file__).resolve().parents[1])
    assert r.returncode == 0, r.stderr
    assert "HEAVY [] RC 0" in r.stdout and "vibimpact rerun " in r.stdout
