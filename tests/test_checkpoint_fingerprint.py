"""A checkpoint loads only its own entries (issue 23, failure 5).

Every point file of a sweep checkpoint and every row file of a map checkpoint carries the
request's fingerprint and its own grid indices; a file copied from another sweep (another
preset), one renamed to another place of the grid, or one beyond the grid is set aside as
``*.corrupt`` and its points are computed again, and the resume's messages count what was
loaded, what was set aside and what was computed again.  The resumed result is
bit-identical to an uninterrupted run.  The commands run in this process on 5-point grids.
"""
import contextlib
import io as stdio
import shutil

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.cli import main
from vibimpact.engine.store import Checkpoint, entry_name, set_aside_line
from vibimpact.io import differences, read_netcdf

ETA = ["--eta", "1.0:1.04:0.01", "--workers", "1", "--no-progress",
       "--analyses", "period,impacts,response,poincare"]


def run(*args):
    """``vibimpact ARGS`` in this process: ``(status, stderr)``."""
    err = stdio.StringIO()
    with contextlib.redirect_stdout(stdio.StringIO()), contextlib.redirect_stderr(err):
        try:
            rc = main([str(a) for a in args])
        except SystemExit as exc:
            rc = exc.code
    return rc, err.getvalue()


@pytest.fixture(scope="module")
def sweeps(tmp_path_factory):
    """Two uninterrupted 5-point sweeps, fig8 (``a``) and fig10 (``b``), checkpoints kept."""
    d = tmp_path_factory.mktemp("fp")
    for name, preset in (("a", "fig8"), ("b", "fig10")):
        rc, err = run("classify", *ETA, "--preset", preset, "--keep-checkpoint",
                      "-o", d / f"{name}.nc")
        assert rc == 0, err
    return d


def test_foreign_and_misplaced_points_are_recomputed_bit_identically(sweeps):
    """Hypothesis: in a checkpoint of fig8 holding a fig10 point file under a fig8 name, a
    fig8 file renamed to another grid place and a fig10 file beyond the grid, --resume
    loads only the 2 genuine points, sets the 3 files aside with their reasons, counts
    the 2 grid points they stood for as computed again, and writes a file bit-identical to the
    uninterrupted run."""
    a, b, c = sweeps / "a.nc.partial", sweeps / "b.nc.partial", sweeps / "c.nc.partial"
    shutil.rmtree(c, ignore_errors=True)
    shutil.copytree(a, c)
    for k in (2, 3, 4):
        (c / entry_name(0, "up", k, k + 1)).unlink()
    shutil.copy(b / entry_name(0, "up", 2, 3), c / entry_name(0, "up", 2, 3))
    shutil.copy(a / entry_name(0, "up", 0, 1), c / entry_name(0, "up", 3, 4))
    shutil.copy(b / entry_name(0, "up", 1, 2), c / entry_name(0, "up", 7, 8))
    rc, err = run("classify", *ETA, "--resume", "-o", sweeps / "c.nc")
    assert rc == 0, err
    lines = [ln for ln in err.splitlines() if ln.startswith("vibimpact:")]
    assert lines[0] == (
        f"vibimpact: warning: 3 point files in {c} were set aside as *.corrupt "
        f"({entry_name(0, 'up', 2, 3)}: from another request; {entry_name(0, 'up', 3, 4)}: "
        f"indices not its own; {entry_name(0, 'up', 7, 8)}: from another request); "
        "their 2 points were computed again")
    assert lines[1] == f"vibimpact: resumed from {c}: 2 points loaded, not recomputed"
    diffs, total = differences(read_netcdf(sweeps / "a.nc"), read_netcdf(sweeps / "c.nc"))
    assert diffs == [] and total > 10
    assert not c.exists()


def test_a_foreign_point_over_a_genuine_one_is_not_counted_as_recomputed(tmp_path):
    """Hypothesis: a set-aside file whose points another entry of the checkpoint holds
    (or that lies beyond the grid) makes no point "computed again": the line says so,
    and the loaded count is that of distinct grid points."""
    ck = Checkpoint(tmp_path / "ck").open("sweep", {"a": 1}, {"rows": 1, "directions":
                                                                 ["up"], "points": 3}, False)
    for k in range(3):
        ck.save(0, "up", [(k, {"regime": 1, "final_state": np.zeros(4)})])
    other = Checkpoint(tmp_path / "o").open("sweep", {"a": 2}, {"rows": 1, "directions":
                                                                   ["up"], "points": 9}, False)
    other.save(0, "up", [(5, {"regime": 1, "final_state": np.ones(4)})])
    shutil.copy(other.path / entry_name(0, "up", 5, 6), ck.path / entry_name(0, "up", 5, 6))
    done = ck.load()
    assert sorted(done[(0, "up")]) == [0, 1, 2]
    last = ck.last_resume()
    assert (last["points"], last["recomputed_points"]) == (3, 0)
    assert last["reasons"] == {entry_name(0, "up", 5, 6) + ".corrupt": "foreign"}
    line = set_aside_line(last, "ck")
    assert line.endswith("; none of their points needed computing again") and "1 point file " in line


def test_a_map_row_from_another_map_is_recomputed(tmp_path):
    """Hypothesis: a map checkpoint holding a row file of another map (another preset)
    under one of its row names sets it aside as foreign, computes that row again (1 row
    counted) and gives the uninterrupted map bit for bit."""
    eta, vary = np.array([1.0, 1.02]), {"kh": np.array([40.0, 80.0])}
    kw = dict(analyses=("period", "impacts"))
    own = vi.map2d(vi.presets.get("fig8"), eta=eta, vary=vary,
                   execution=vi.Execution(checkpoint=tmp_path / "a"), **kw)
    vi.map2d(vi.presets.get("fig10"), eta=eta, vary=vary,
             execution=vi.Execution(checkpoint=tmp_path / "b"), **kw)
    name = entry_name(1, "up", 0, 2)
    shutil.copy(tmp_path / "b" / name, tmp_path / "a" / name)
    again = vi.map2d(vi.presets.get("fig8"), eta=eta, vary=vary,
                     execution=vi.Execution(checkpoint=tmp_path / "a", resume=True), **kw)
    last = Checkpoint(tmp_path / "a").last_resume()
    assert last["reasons"] == {name + ".corrupt": "foreign"}
    assert (last["streams"], last["recomputed_streams"]) == (1, 1)
    assert "their 1 row was computed again" in set_aside_line(last, "a", "rows")
    diffs, _ = differences(own, again)
    assert diffs == []


def test_saved_counts_distinct_grid_points(tmp_path):
    """Hypothesis: the interrupt line's count (Checkpoint.saved) counts distinct grid
    points: an entry beyond the grid or one overlapping another adds nothing (it said
    "13 points" of an 11-point grid)."""
    ck = Checkpoint(tmp_path / "ck").open("sweep", {"a": 1}, {"rows": 1, "directions":
                                                                 ["up"], "points": 3}, False)
    for k in range(3):
        ck.save(0, "up", [(k, {"regime": 1, "final_state": np.zeros(4)})])
    shutil.copy(ck.path / entry_name(0, "up", 1, 2), ck.path / entry_name(0, "up", 1, 3))
    shutil.copy(ck.path / entry_name(0, "up", 2, 3), ck.path / entry_name(0, "up", 5, 6))
    assert ck.saved() == (3, 1)
