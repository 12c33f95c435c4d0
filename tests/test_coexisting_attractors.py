"""Coexisting attractors (issue 24): ``simulate --from SWEEP.nc``, ``Run.to_dataset()`` and a
Run accepted where the dataset of a run is expected.

fig8 at eta = 1.25 (shipped defaults) has two attractors: swept up from eta = 1.1 the rotor
is chaotic and hits the whole retainer, while from rest it settles on the impactless
period-1 orbit.  A two-point classify sweep (1.1, 1.25, about a second) reaches the
chaotic one; the commands run in this process through :func:`vibimpact.cli.main`.
"""
import contextlib
import datetime
import io as stdio
import os
from pathlib import Path

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.analysis import classify, contact_arcs
from vibimpact.cli import main
from vibimpact.io import differences, read_netcdf, write_netcdf
from vibimpact.points.codes import REGIME_CODES
from vibimpact.sweeps.dataset import label_text

from test_cf_conventions import cf_problems

def cli(*args):
    """``vibimpact ARGS`` in this process: ``(status, stdout, stderr)``."""
    out, err = stdio.StringIO(), stdio.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main([str(a) for a in args])
        except SystemExit as exc:
            rc = exc.code
    return rc, out.getvalue(), err.getvalue()


def label_of(ds):
    """The sweep's label for the run file ``ds``: the array classifier on its
    stroboscopic points (the 0-1 test decides where no period is found), its impacts
    per forcing period and loaded arcs, worded as the sweep words a point."""
    periods = ds.sizes["sample"] - 1
    ipp = ds.sizes["impact"] / periods
    regime = classify(ds["strobe"].values, impacts_per_period=ipp)
    arcs = contact_arcs(ds).summary
    return label_text(REGIME_CODES[regime.label], regime.n, regime.impacts_per_period, arcs)


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A directory with ``sweep.nc`` (classify --eta 1.1,1.25, both directions), and the
    runs at 1.25 ``from.nc`` (simulate --from the up sweep, with --plot) and ``rest.nc``
    (simulate from rest), with simulate's default periods and transient; the time before
    the first write."""
    d = tmp_path_factory.mktemp("coexist")
    # the directory's creation as the file system stamped it, not a clock the test reads
    since = datetime.datetime.fromtimestamp(int(d.stat().st_mtime), datetime.timezone.utc)
    cwd = os.getcwd()
    os.chdir(d)
    try:
        for args in (["classify", "--eta", "1.1,1.25", "--direction", "both",
                      "--no-progress", "--workers", "1", "-o", "sweep.nc"],
                     ["simulate", "--from", "sweep.nc", "--eta", "1.25", "--direction", "up",
                      "-o", "from.nc", "--plot", "from.png"],
                     ["simulate", "--preset", "fig8", "--eta", "1.25", "-o", "rest.nc"]):
            rc, out, err = cli(*args)
            assert rc == 0, (args, err)
    finally:
        os.chdir(cwd)
    return d, since


def test_from_reproduces_the_sweeps_chaotic_label_where_rest_is_impactless(files):
    """Hypothesis: at fig8, eta = 1.25 the up sweep's point is chaotic (impacting, whole
    circle) and the run from rest is impactless P1; a run started --from the sweep there
    stays on the sweep's attractor, so the sweep's own wording of the run's motion is the
    sweep's label, and the run from rest gets another one."""
    d, _ = files
    sweep = read_netcdf(d / "sweep.nc").sel(direction="up")
    i = int(np.flatnonzero(sweep["eta"].values == 1.25)[0])
    label = str(sweep["label"].values[i])
    assert label.startswith("chaotic, impacting"), label
    run = read_netcdf(d / "from.nc")
    assert label_of(run) == label
    rest = read_netcdf(d / "rest.nc")
    assert rest.sizes["impact"] == 0 and label_of(rest) == "P1 impactless"
    # the run starts from the sweep's state and parameters, bit for bit
    assert run["state0"].values.tolist() == sweep["final_state"].values[i].tolist()
    assert run.attrs["param_eta"] == sweep["eta"].values[i]
    for name, value in vi.sweeps.sweep_params(sweep).as_dict().items():
        if name != "eta":
            assert run.attrs[f"param_{name}"] == value, name
    assert run.attrs["start_label"] == label and run.attrs["start_direction"] == "up"


def test_from_the_down_direction_starts_from_the_down_sweeps_state(files, tmp_path):
    """Hypothesis: --direction picks the sweep direction; the down sweep (from 1.25 at
    rest) is impactless at 1.25, and a run from its state is too, starting from the down
    sweep's final_state, not the up one's."""
    d, _ = files
    sweep = read_netcdf(d / "sweep.nc").sel(direction="down")
    rc, out, err = cli("simulate", "--from", d / "sweep.nc", "--eta", "1.25", "--direction",
                       "down", "-o", tmp_path / "down.nc")
    assert rc == 0, err
    run = read_netcdf(tmp_path / "down.nc")
    assert run["state0"].values.tolist() == sweep["final_state"].values[1].tolist()
    assert label_of(run) == str(sweep["label"].values[1]) == "P1 impactless"
    assert "(down), where the sweep found 'P1 impactless'" in out


def test_set_with_from_is_applied_and_recorded(files, tmp_path):
    """Hypothesis: --set with --from changes the named parameter on top of the sweep's
    (the run's param_BT is the new value, start_params keeps the sweep's), starting from
    the sweep's state, and the summary line says so."""
    import json

    d, _ = files
    rc, out, err = cli("simulate", "--from", d / "sweep.nc", "--eta", "1.25", "--direction",
                       "up", "--set", "BT=0.02", "--periods", "5", "--transient", "0",
                       "-o", tmp_path / "bt.nc")
    assert rc == 0, err
    run = read_netcdf(tmp_path / "bt.nc")
    assert run.attrs["param_BT"] == 0.02
    assert json.loads(run.attrs["start_params"])["BT"] == 0.0
    assert "parameters changed from the sweep's: BT=0.02" in out
    sweep = read_netcdf(d / "sweep.nc").sel(direction="up")
    assert run["strobe"].values[0].tolist() == sweep["final_state"].values[1].tolist()


@pytest.mark.parametrize("name", ["from.nc", "rest.nc"])
def test_written_runs_pass_the_cf_checker(files, name):
    """Hypothesis: the file of simulate --from (its start_* attributes, state0) and of
    simulate from rest, both now written through Run.to_dataset(), pass the CF checker
    of tests/test_cf_conventions.py."""
    d, since = files
    assert cf_problems(d / name, since=since) == []


def test_rerun_starts_from_the_record_not_the_sweep_file(files, tmp_path):
    """Hypothesis: rerun of a simulate --from file is identical with the sweep file in
    place, and still identical when the sweep file has been replaced by garbage (the rerun
    starts from the state and parameters the run's file records, never reading the
    sweep); a file whose start record was stripped is refused in one line."""
    d, _ = files
    work = tmp_path / "work"
    work.mkdir()
    for name in ("sweep.nc", "from.nc"):
        (work / name).write_bytes((d / name).read_bytes())
    cwd = os.getcwd()
    os.chdir(work)
    try:
        rc, out, err = cli("rerun", "from.nc")
        assert rc == 0 and out.startswith("identical: "), (out, err)
        Path("sweep.nc").write_bytes(b"not a sweep any more\n" * 10)
        rc, out, err = cli("rerun", "from.nc")
        assert rc == 0 and out.startswith("identical: "), (out, err)
        Path("sweep.nc").unlink()
        rc, out, err = cli("rerun", "from.nc")
        assert rc == 0 and out.startswith("identical: "), (out, err)
        stripped = read_netcdf("from.nc")
        del stripped.attrs["start_params"]
        write_netcdf(stripped, "stripped.nc")
        rc, out, err = cli("rerun", "stripped.nc")
    finally:
        os.chdir(cwd)
    assert rc == 2 and out == ""
    assert err.splitlines() == [err.strip()] and "start_params" in err, err
    assert sorted(p.name for p in work.iterdir()) == ["from.nc", "stripped.nc"]


def test_run_to_dataset_is_the_dataset_simulate_writes(files):
    """Hypothesis: Run.to_dataset() of the run simulate --from made (the same start,
    periods, transient and dense samples through the API) has the data variables and
    coordinates of the written file bit for bit, and each of its attributes has the
    file's value, the command line (which only the CLI knows) aside."""
    d, _ = files
    sweep = read_netcdf(d / "sweep.nc")
    start = vi.sweeps.sweep_start(sweep, 1.25, "up")
    run = vi.simulate(start.params, periods=200, transient=500, state0=start.state,
                      dense=64)
    ds = run.to_dataset()
    written = read_netcdf(d / "from.nc")
    diffs, total = differences(written, ds)
    assert diffs == [] and total >= 12
    assert {"state0", "strobe", "trajectory", "impact_theta"} <= set(ds.variables)
    other = {k: (v, written.attrs.get(k)) for k, v in ds.attrs.items()
             if k != "command" and written.attrs.get(k) != v}
    assert other == {}
    assert ds.attrs["periods"] == 200 and ds.attrs["transient"] == 500
    assert ds.attrs["dense"] == 64


def test_a_run_is_accepted_where_the_dataset_of_a_run_is_expected(tmp_path):
    """Hypothesis: plot_xy and write_netcdf take a Run as its dataset: the figure draws
    the same lines as from run.to_dataset(), the file holds the same data; the functions
    that expect a sweep still refuse the Run with a TypeError."""
    from vibimpact.plotting import plot_response, plot_xy

    run = vi.simulate(vi.presets.get("fig8").replace(eta=1.15), periods=20, transient=50,
                      dense=16)
    ax_run, ax_ds = plot_xy(run), plot_xy(run.to_dataset())
    lines = [[line.get_xydata().tolist() for line in ax.get_lines()]
             for ax in (ax_run, ax_ds)]
    assert len(lines[0]) >= 3 and lines[0] == lines[1]
    assert ax_run.get_title() == ax_ds.get_title()
    write_netcdf(run, tmp_path / "run.nc")
    write_netcdf(run.to_dataset(), tmp_path / "ds.nc")
    diffs, total = differences(read_netcdf(tmp_path / "run.nc"),
                               read_netcdf(tmp_path / "ds.nc"))
    assert diffs == [] and total >= 10
    for call in (plot_response, vi.intervals, lambda r: vi.sweeps.sweep_start(r, 1.15)):
        with pytest.raises(TypeError, match="Run"):
            call(run)


def test_sweep_start_api(files):
    """Hypothesis: sweep_start takes the grid value itself for an eta within 1e-9 of it
    (the run's parameters are the sweep point's bit for bit), needs a direction for a
    sweep with both, and raises ValueError naming the argument for an eta off the grid."""
    d, _ = files
    sweep = read_netcdf(d / "sweep.nc")
    start = vi.sweeps.sweep_start(sweep, 1.25 + 3e-10, "up")
    assert start.eta == 1.25 and start.params.eta == 1.25 and start.direction == "up"
    assert start.state.tolist() == sweep["final_state"].sel(direction="up").values[1].tolist()
    with pytest.raises(ValueError, match="^direction: the sweep has up and down"):
        vi.sweeps.sweep_start(sweep, 1.25)
    with pytest.raises(ValueError, match="^eta = 1.3 is not on .* nearest grid values: 1.25$"):
        vi.sweeps.sweep_start(sweep, 1.3, "up")
    one = vi.sweeps.sweep_start(sweep.isel(eta=[1]), direction="down")
    assert one.eta == 1.25 and one.label == "P1 impactless"


def test_simulate_help_documents_from_with_examples():
    """Hypothesis: simulate --help explains --from and --direction and shows a
    classify-then-simulate --from example."""
    rc, out, err = cli("simulate", "--help")
    assert rc == 0
    assert "--from SWEEP.nc" in out and "--direction {up,down}" in out
    assert "vibimpact simulate --from sweep.nc --eta 1.25" in out
    assert "--preset and --state0 cannot be given with --from" in " ".join(out.split())
