"""A command's output named twice, or named as one of its inputs (issue 44, class 8).

``attractors``, ``basins``, ``orbits`` and ``continue2`` with ``-o`` and ``--plot`` naming
one file (``x.png`` and ``./x.png``) exited 0, one output overwriting the other;
``simulate`` compared the two names only as absolute paths (a symbolic link passed), and
no command compared an output with the file it reads (``simulate --from s.nc -o s.nc
--overwrite`` replaced the sweep it started from).  Now every such pair, however it is
spelled, is refused in one line before any work
(:func:`vibimpact.cli.common.inputs.check_distinct`).
"""
import os

import numpy as np
import pytest
import xarray as xr

from vibimpact.cli.common.inputs import same_file

from test_bad_input import run_cli


def _never(*args, **kwargs):
    raise AssertionError("the command started its work")


#: command -> (its arguments before -o, the module and function of its work)
COMMANDS = {
    "attractors": (["attractors", "--eta", "1.06", "--starts", "2", "--no-progress"],
                   ("vibimpact.census.census", "attractors")),
    "basins": (["basins", "--grid", "6x6", "--no-progress"],
               ("vibimpact.census.basins", "basins")),
    "orbits": (["orbits", "--period", "1", "--no-progress"],
               ("vibimpact.orbits", "hunt_orbits")),
    "continue2": (["continue2", "--kind", "grazing", "--param2", "kh", "--range2",
                   "110:130"], ("vibimpact.cli.continue2", "_seed")),
    "simulate": (["simulate", "--periods", "2"], ("vibimpact.core.simulation", "simulate")),
}


def _spelling(kind, d):
    """``(first, second, --overwrite needed)``: two names of the one file x.png."""
    if kind == "alike":
        return "x.png", "x.png", False
    if kind == "dot":
        return "x.png", "./x.png", False
    if kind == "up and down":
        (d / "sub").mkdir()
        return "x.png", "sub/../x.png", False
    if kind == "absolute":
        return "x.png", str(d / "x.png"), False
    (d / "x.png").write_bytes(b"mine")  # a link to an existing file
    os.symlink("x.png", d / "link.png")
    return "x.png", "link.png", True


SPELLINGS = ["alike", "dot", "up and down", "absolute", "symbolic link"]


def _refused(argv, d, capfd, work, monkeypatch):
    import importlib

    monkeypatch.setattr(importlib.import_module(work[0]), work[1], _never)
    before = {p.name: p.read_bytes() for p in d.iterdir() if p.is_file()}
    rc, out, err = run_cli(argv, capfd)
    assert rc == 2, (rc, out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("vibimpact: error: "), err
    assert "name the same file" in lines[0] or "is the file being rerun" in lines[0], err
    after = {p.name: p.read_bytes() for p in d.iterdir() if p.is_file()}
    assert after == before  # nothing written, nothing replaced
    return lines[0]


@pytest.mark.parametrize("spelling", SPELLINGS)
@pytest.mark.parametrize("command", list(COMMANDS))
def test_o_and_plot_naming_one_file_are_refused(command, spelling, tmp_path, monkeypatch,
                                                capfd):
    """Hypothesis: -o and --plot naming the same file (spelled alike, with ./, through
    sub/.., as an absolute path or through a symbolic link) exit 2 with one line naming
    both options, before any work, and no file is written or replaced."""
    monkeypatch.chdir(tmp_path)
    first, second, overwrite = _spelling(spelling, tmp_path)
    head, work = COMMANDS[command]
    line = _refused(head + ["-o", first, "--plot", second]
                    + (["--overwrite"] if overwrite else []), tmp_path, capfd, work,
                    monkeypatch)
    assert "-o" in line and "--plot" in line, line


def _netcdf(path):
    xr.Dataset({"regime": ("eta", np.ones(2, "i1"))}, coords={"eta": [1.0, 1.1]},
               attrs={"command": "vibimpact classify --eta 1.0,1.1 -o s.png"}
               ).to_netcdf(path)


#: an output that is the command's input: (argv, the work it must not start)
INPUTS = {
    "plot FILE -o FILE": (["plot", "s.png", "-o", "./s.png", "--overwrite"], None),
    "simulate --from": (["simulate", "--from", "s.png", "--eta", "1.0", "-o", "./s.png",
                         "--overwrite"], ("vibimpact.core.simulation", "simulate")),
    "attractors --sweep": (["attractors", "--eta", "1.06", "--starts", "2", "--sweep",
                            "s.png", "-o", "sub/../s.png", "--overwrite"],
                           ("vibimpact.census.census", "attractors")),
    "orbits --seeds": (["orbits", "--period", "1", "--seeds", "s.png", "-o", "link.png",
                        "--overwrite"], ("vibimpact.orbits", "hunt_orbits")),
    "continue2 --over": (["continue2", "--kind", "grazing", "--param2", "kh", "--range2",
                          "110:130", "--over", "s.png", "-o", "./s.png", "--plot",
                          "c.png", "--overwrite"], ("vibimpact.cli.continue2", "_seed")),
    "rerun -o FILE": (["rerun", "s.png", "-o", "link.png", "--overwrite"], None),
    "plot --branch": (["plot", "t.nc", "--branch", "s.png", "-o", "link.png",
                       "--overwrite"], None),
}


@pytest.mark.parametrize("case", list(INPUTS))
def test_an_output_that_is_an_input_is_refused(case, tmp_path, monkeypatch, capfd):
    """Hypothesis: an output that is the file the command reads (plot FILE -o FILE,
    simulate --from, attractors --sweep, orbits --seeds, continue2 --over, rerun -o,
    plot --branch), spelled otherwise or through a link, exits 2 with one line before
    any work and leaves the input as it was."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    _netcdf(tmp_path / "s.png")
    _netcdf(tmp_path / "t.nc")
    os.symlink("s.png", tmp_path / "link.png")
    argv, work = INPUTS[case]
    _refused(argv, tmp_path, capfd, work or ("vibimpact.plotting", "save_figure"),
             monkeypatch)


def test_continue_switch_output_linked_to_the_branch_file_is_refused(tmp_path,
                                                                     monkeypatch, capfd):
    """Hypothesis: continue --switch whose OUT_P2.nc is a link to OUT exits 2 with one
    line before the branch is computed (one file would replace the other)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "b.nc").write_bytes(b"old")
    os.symlink("b.nc", tmp_path / "b_P2.nc")
    line = _refused(["continue", "--stop", "1.1", "--switch", "-o", "b.nc", "--overwrite"],
                    tmp_path, capfd, ("vibimpact.continuation.branches", "follow_branch"), monkeypatch)
    assert "--switch" in line


def test_different_files_are_not_one(tmp_path):
    """Hypothesis: same_file tells two files apart, also when neither exists, and sees a
    hard link as the same file."""
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    assert not same_file(a, b)
    a.write_bytes(b"a")
    os.link(a, b)
    assert same_file(a, b) and same_file(a, tmp_path / "x" / ".." / "a.png")
    assert not same_file(a, tmp_path / "c.png")
