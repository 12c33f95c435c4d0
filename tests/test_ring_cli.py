"""The ring model (a turning retainer ring, state X, Y, dX, dY, Vr) through every command
and the API: each command runs on ``--preset fig11-ring`` (and fig10-ring), writes a file
that records the model "ring" and its five states, and each file draws.

Tiny problems (a few points, a few starts) run in this process through
:func:`vibimpact.cli.main`, so that the file stays fast once numba's cache is warm.
"""
import dataclasses

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.cli import main
from vibimpact.plotting import plot_bifurcation

STATES = ["X", "Y", "dX", "dY", "Vr"]
PNG = b"\x89PNG\r\n\x1a\n"


def run_cli(argv, capfd):
    """``vibimpact ARGV`` in this process: (exit status, stdout, stderr)."""
    try:
        rc = main([str(a) for a in argv])
    except SystemExit as exc:
        rc = exc.code
    return (rc, *capfd.readouterr())


def ok(argv, capfd):
    rc, out, err = run_cli(argv, capfd)
    assert rc == 0, err
    return out


def is_png(path):
    return path.read_bytes()[:8] == PNG


def records_the_ring(path):
    """The file at ``path`` read back: model "ring", the five states as its coordinate."""
    ds = vi.io.read_netcdf(path)
    assert ds.attrs["model"] == "ring"
    assert [str(s) for s in ds["state"].values] == STATES
    return ds


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """One file of each command on fig11-ring: classify (3 points), a census (8 starts) at
    eta 1.06 and its orbit hunt, written once for the tests that read them."""
    d = tmp_path_factory.mktemp("ring")
    out = {}
    argv = [["classify", "--preset", "fig11-ring", "--eta", "1.04:1.08:0.02", "--workers",
             "1", "--no-progress", "-o", d / "sweep.nc"],
            ["attractors", "--preset", "fig11-ring", "--eta", "1.06", "--starts", "8",
             "--no-progress", "-o", d / "census.nc"],
            ["orbits", "--preset", "fig11-ring", "--eta", "1.06", "--period", "1:2",
             "--seeds", d / "census.nc", "--window", "0.01", "--no-progress", "-o",
             d / "orbits.nc", "--plot", d / "orbits.png"]]
    for a in argv:
        assert main([str(x) for x in a]) == 0, a[0]
        out[a[0]] = a[a.index("-o") + 1]
    return d, out


@pytest.mark.parametrize("preset", ["fig11-ring", "fig10-ring"])
def test_simulate_writes_the_five_states_and_reruns_bit_for_bit(preset, tmp_path, capfd):
    """Hypothesis: ``vibimpact simulate --preset <ring preset>`` writes a file whose strobe
    holds the five states (Vr included, finite), whose attributes name the model and its
    ring parameters as the preset has them, which draws as xy, and which ``vibimpact
    rerun`` reproduces bit for bit."""
    f = tmp_path / "run.nc"
    ok(["simulate", "--preset", preset, "--eta", "1.1", "--periods", "5", "--transient",
        "20", "-o", f, "--plot", tmp_path / "xy.png"], capfd)
    ds = records_the_ring(f)
    assert ds["strobe"].shape == (6, 5) and np.isfinite(ds["strobe"].values).all()
    p = vi.presets.get(preset)
    assert [ds.attrs[f"param_{k}"] for k in ("Jr", "cr", "Mr")] == [p.Jr, p.cr, p.Mr]
    assert is_png(tmp_path / "xy.png")
    ok(["plot", f, "-o", tmp_path / "again.png"], capfd)
    assert is_png(tmp_path / "again.png")
    assert "identical" in ok(["rerun", f], capfd)


def test_api_run_survives_a_netcdf_round_trip(tmp_path):
    """Hypothesis: a ring run of the API written with vi.io.write_netcdf and read back
    keeps its strobe bit for bit (all five states), the model's name, its state names
    and every parameter."""
    p = vi.presets.get("fig11-ring").replace(eta=1.1, Jr=0.2)
    run = vi.simulate(p, periods=5, transient=10)
    vi.io.write_netcdf(run, tmp_path / "api.nc")
    ds = records_the_ring(tmp_path / "api.nc")
    assert np.array_equal(ds["strobe"].values, run.strobe)
    assert ds.attrs["param_Jr"] == 0.2 and ds.attrs["param_Mr"] == p.Mr


def test_set_changes_a_ring_parameter_and_refuses_values_outside_its_domain(tmp_path,
                                                                           capfd):
    """Hypothesis: --set Jr=0.1 reaches the run (the file records it); --set Jr=0 (the
    ring needs inertia) and --set Mr=-1 (a drag is not negative) exit 2 with one line
    naming the parameter and its domain, and write nothing."""
    ok(["simulate", "--preset", "fig11-ring", "--eta", "1.1", "--set", "Jr=0.1",
        "--periods", "2", "--transient", "2", "-o", tmp_path / "j.nc"], capfd)
    assert vi.io.read_netcdf(tmp_path / "j.nc").attrs["param_Jr"] == 0.1
    for setting, domain in (("Jr=0", "Jr must be > 0"), ("Mr=-1", "Mr must be >= 0")):
        rc, out, err = run_cli(["simulate", "--preset", "fig11-ring", "--eta", "1.1",
                                "--set", setting, "-o", tmp_path / "bad.nc"], capfd)
        assert rc == 2 and out == ""
        assert len(err.strip().splitlines()) == 1 and domain in err, err
        assert not (tmp_path / "bad.nc").exists()


@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_classify_file_stores_vr_and_draws_every_sweep_kind(files, capfd):
    """Hypothesis: a ring sweep file holds the Poincaré samples of Vr with units and a
    long name, and the final state of every point with the five states; every kind of
    figure of a sweep file draws from it (response, bifurcation, intervals, poincare,
    lyapunov, and the bifurcation diagram of Vr)."""
    d, out = files
    ds = records_the_ring(out["classify"])
    assert ds["final_state"].shape == (3, 5)
    vr = ds["poincare_Vr"]
    assert vr.attrs["units"] == "1"
    assert vr.attrs["long_name"].startswith("stroboscopic samples of Vr")
    assert np.isfinite(vr.values).any()
    assert "Vr" in ds["final_state"].attrs["long_name"]
    for kind in ("response", "bifurcation", "intervals", "poincare", "lyapunov"):
        ok(["plot", out["classify"], "--kind", kind, "-o", d / f"{kind}.png"], capfd)
        assert is_png(d / f"{kind}.png"), kind
    ok(["plot", out["classify"], "--kind", "bifurcation", "--state", "Vr", "-o",
        d / "vr.png"], capfd)
    assert is_png(d / "vr.png")


def test_the_bifurcation_diagram_of_vr_draws_the_files_samples(files):
    """Hypothesis: plot_bifurcation(ds, states="Vr") draws one panel whose points are
    exactly the finite samples of the file's poincare_Vr (by eta, then sample), at their
    eta; states=("X", "Vr") draws poincare_X above them; an unknown state is refused
    naming the model's states."""
    ds = vi.io.read_netcdf(files[1]["classify"])
    v = ds["poincare_Vr"].transpose("eta", "sample").values
    e = np.broadcast_to(ds["eta"].values[:, None], v.shape)
    ok_ = np.isfinite(v)
    fig = plot_bifurcation(ds, states="Vr")
    (line,) = fig.axes[0].get_lines()
    assert len(fig.axes) == 1 and fig.axes[0].get_ylabel().split()[0] == "Vr"
    assert np.array_equal(line.get_ydata(), v[ok_])
    assert np.array_equal(line.get_xdata(), e[ok_])
    fig = plot_bifurcation(ds, states=("X", "Vr"))
    x = ds["poincare_X"].transpose("eta", "sample").values
    assert np.array_equal(fig.axes[0].get_lines()[0].get_ydata(), x[np.isfinite(x)])
    assert np.array_equal(fig.axes[1].get_lines()[0].get_ydata(), v[ok_])
    with pytest.raises(ValueError, match="X, Y, dX, dY, Vr"):
        plot_bifurcation(ds, states="W")


def test_plot_state_option_is_refused_where_it_cannot_apply(files, capfd):
    """Hypothesis: --state with another kind, or naming no state of the model, exits 2
    with one line."""
    d, out = files
    for extra, needle in ((["--kind", "response", "--state", "Vr"], "--state"),
                          (["--state", "W"], "no state of the model")):
        rc, _, err = run_cli(["plot", out["classify"], *extra, "-o", d / "no.png"], capfd)
        assert rc == 2 and needle in err and len(err.strip().splitlines()) == 1, err
        assert not (d / "no.png").exists()


def test_state_text_of_a_model_labels_its_samples(monkeypatch):
    """Hypothesis: a model that says in words what a state is (Model.state_text) gets
    that text in its sweep's long_name of the state's Poincaré samples and in its run
    file's state_<name> attribute; a state it says nothing of gets no words (none
    borrowed from the rotor), and the shipped ring says its X in its own words."""
    ring = vi.models.get("ring")
    said = dataclasses.replace(ring, state_text={"Vr": "the ring's surface speed"})
    monkeypatch.setitem(vi.models._loaded(), "ring", said)
    p = vi.presets.get("fig11-ring")
    ds = vi.sweep(p, [1.06], analyses=("period", "poincare"),
                  execution=vi.Execution(workers=1, progress=False))
    assert ds["poincare_Vr"].attrs["long_name"] == ("stroboscopic samples of Vr: the "
                                                    "ring's surface speed")
    run = vi.io.run_to_dataset(vi.simulate(p.replace(eta=1.06), periods=2))
    assert run.attrs["state_Vr"] == "the ring's surface speed"
    assert "state_X" not in run.attrs
    monkeypatch.setitem(vi.models._loaded(), "ring", ring)
    shipped = vi.io.run_to_dataset(vi.simulate(p.replace(eta=1.06), periods=2))
    assert shipped.attrs["state_X"] == ring.state_text["X"]


def test_bifurcation_command_sweeps_both_ways(tmp_path, capfd):
    """Hypothesis: ``vibimpact bifurcation --preset fig10-ring`` writes the image and the
    ring's sweep file next to it, up and down."""
    ok(["bifurcation", "--preset", "fig10-ring", "--eta", "1.1,1.12", "--workers", "1",
        "--no-progress", "-o", tmp_path / "bif.png"], capfd)
    ds = records_the_ring(tmp_path / "bif.nc")
    assert list(ds["direction"].values) == ["up", "down"]
    assert ds["poincare_Vr"].sizes["eta"] == 2 and is_png(tmp_path / "bif.png")


def test_map_varies_a_ring_parameter(tmp_path, capfd):
    """Hypothesis: ``vibimpact map --vary Jr=...`` accepts the ring's own parameters (the
    command listed eq. (5)'s only) and writes a 2 x 2 map over (Jr, eta) that draws."""
    ok(["map", "--preset", "fig11-ring", "--eta", "1.06,1.08", "--vary", "Jr=0.05,1",
        "--workers", "1", "--no-progress", "-o", tmp_path / "map.nc"], capfd)
    ds = vi.io.read_netcdf(tmp_path / "map.nc")
    assert ds.attrs["model"] == "ring" and ds.attrs["map_vary"] == "Jr"
    assert list(ds["Jr"].values) == [0.05, 1.0] and ds["regime"].shape == (2, 2)
    ok(["plot", tmp_path / "map.nc", "--kind", "map", "-o", tmp_path / "map.png"], capfd)
    assert is_png(tmp_path / "map.png")
    rc, _, err = run_cli(["map", "--preset", "fig11-ring", "--vary", "Q=1,2", "-o",
                          tmp_path / "q.nc"], capfd)
    assert rc == 2 and "Jr, cr, Mr" in err


def test_continue_follows_a_ring_orbit(tmp_path, capfd):
    """Hypothesis: ``vibimpact continue`` on fig11-ring shoots a P1 orbit of the five
    states and follows it over a short window; the branch draws."""
    ok(["continue", "--preset", "fig11-ring", "--eta", "1.1", "--stop", "1.11", "-o",
        tmp_path / "p1.nc"], capfd)
    ds = records_the_ring(tmp_path / "p1.nc")
    assert ds["orbit_state"].sizes["state"] == 5 and ds.sizes["point"] >= 2
    assert np.isfinite(ds["orbit_state"].values).all()
    ok(["plot", tmp_path / "p1.nc", "-o", tmp_path / "p1.png"], capfd)
    assert is_png(tmp_path / "p1.png")


def test_census_and_orbit_hunt_find_the_ring_attractor(files, capfd):
    """Hypothesis: the census of 8 starts (Vr drawn with the other states) finds an
    attractor whose representative has five states, the census draws, and the orbit
    hunt seeded by it finds a stable P1 with a finite Vr."""
    d, out = files
    census = records_the_ring(out["attractors"])
    assert census["fraction"].sum() == pytest.approx(1.0)
    assert census["representative"].sizes["state"] == 5
    ok(["plot", out["attractors"], "-o", d / "census.png"], capfd)
    assert is_png(d / "census.png")
    hunt = records_the_ring(out["orbits"])
    stable = hunt["stable"].values == 1
    assert stable.any() and 1 in hunt["period"].values[stable]
    assert is_png(d / "orbits.png")


def test_basins_in_a_plane_of_x_and_vr(tmp_path, capfd):
    """Hypothesis: ``vibimpact basins --plane X,Vr`` spans a grid in the ring's speed
    (its coordinates named X and Vr) and labels every cell."""
    ok(["basins", "--preset", "fig11-ring", "--eta", "1.06", "--grid", "5x5", "--plane",
        "X,Vr", "--no-progress", "-o", tmp_path / "b.nc", "--plot", tmp_path / "b.png"],
       capfd)
    ds = records_the_ring(tmp_path / "b.nc")
    assert ds["X"].dims == ("column",) and ds["Vr"].dims == ("row",)
    assert np.array_equal(ds["Vr"].values, np.linspace(-1.0, 1.0, 5))
    assert ds["basin"].shape == (5, 5) and (ds["basin"].values >= 0).all()
    assert is_png(tmp_path / "b.png")


def test_orbit_hunt_from_random_seeds_needs_the_ring_to_settle(tmp_path, capfd):
    """Hypothesis: a light ring's speed settles over tens of periods, so the hunt's
    default five periods from random states leave Newton's method too far from any orbit
    (no stable orbit found), while ``--transient 100`` lets the same 12 seeds settle and
    the hunt finds the stable P1 with 2 impacts that the census sees at eta = 1.06; a
    negative ``--transient`` is refused with exit status 2."""
    found = {}
    for transient in (5, 100):
        out = tmp_path / f"o{transient}.nc"
        ok(["orbits", "--preset", "fig11-ring", "--eta", "1.06", "--period", "1:2",
            "--random", "12", "--transient", transient, "--no-continue", "--no-progress",
            "-o", out], capfd)
        ds = records_the_ring(out)
        stable = ds["stable"].values == 1
        found[transient] = {(int(n), int(i)) for n, i in
                            zip(ds["period"].values[stable],
                                   ds["impacts_per_period"].values[stable])}
    assert (1, 2) not in found[5]
    assert (1, 2) in found[100]
    rc, _, err = run_cli(["orbits", "--preset", "fig11-ring", "--eta", "1.06",
                          "--transient", "-1"], capfd)
    assert rc == 2 and "--transient" in err and len(err.strip().splitlines()) == 1
