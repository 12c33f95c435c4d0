"""The plot kinds of issue 30, part 6: ``vibimpact plot FILE --kind poincare`` (every
point's stored Poincaré samples, coloured by eta) and ``--kind lyapunov`` (the largest
exponent against eta, periodic points by their Floquet exponent), for a sweep file of
any model.

The figures are read back from matplotlib's artists and compared with the file's
variables, read with xarray in the test.  One tiny real sweep (the double-well Duffing
oscillator, 4 points, both directions, short transients) is made once; the other
datasets are made by hand, since the plots only read datasets.
"""
import json
import os

import numpy as np
import pytest
import xarray as xr
from matplotlib.colors import to_rgba

import vibimpact as vi
from vibimpact.cli import main
from vibimpact.plotting import plot_intervals, plot_lyapunov, plot_poincare
from vibimpact.plotting.lyapunov_plot import FLOQUET_LABEL, LYAPUNOV_LABEL

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def duffing_file(tmp_path_factory):
    """A two-direction Duffing sweep (gamma = 0.35) over omega = 1.25..1.40: chaotic at
    1.25, long-period or P16 at 1.30, P2 and P1 above, with every analysis, written by
    vibimpact.io as a sweep file."""
    system = vi.System(vi.DuffingParams(gamma=0.35))
    settings = vi.SweepSettings(transient_max=200, lyap_min=20, lyap_max=60, n_samples=16)
    ds = vi.sweep(system, np.array([1.25, 1.30, 1.35, 1.40]), direction="both",
                  settings=settings, execution=vi.Execution(workers=1, progress=False))
    path = tmp_path_factory.mktemp("plot_kinds") / "duffing.nc"
    vi.io.write_netcdf(ds, path)
    return path


def run_cli(argv, capfd):
    try:
        rc = main([str(a) for a in argv])
    except SystemExit as exc:
        rc = exc.code
    return (rc, *capfd.readouterr())


def _collection(ax, label):
    (found,) = [c for c in ax.collections if c.get_label() == label]
    return found


def _section_ds(states, extra=None, regime=(1, 3, 4), model="rotor"):
    """A hand-made one-direction sweep of 3 points with 2 samples each, a NaN in the
    second point's samples; states named ``states``; ``extra``: more variables; the
    ``model`` attribute (None: none)."""
    px = np.array([[0.1, 0.2], [0.3, np.nan], [5.0, 6.0]])
    py = np.array([[1.1, 1.2], [1.3, 1.4], [7.0, 8.0]])
    ds = xr.Dataset({"regime": ("eta", np.array(regime, dtype="i1")),
                     "poincare_X": (("eta", "sample"), px),
                     "poincare_Y": (("eta", "sample"), py)},
                    coords={"eta": [1.0, 1.1, 1.2],
                            "state": ("state", np.array(states, dtype=object))},
                    attrs={"sweep_direction": "up"})
    if model is not None:
        ds.attrs["model"] = model
    for name, values in (extra or {}).items():
        ds[name] = (("eta", "sample"), values)
    return ds


# --- Poincaré section -------------------------------------------------------------------

def test_poincare_scatter_holds_exactly_the_files_finite_samples(duffing_file, tmp_path):
    """Hypothesis: each direction's panel holds one scatter whose points are exactly the
    finite (poincare_X, poincare_Y) pairs of that direction in the file (count and
    coordinates, ordered by eta then sample) and whose colour values are their points'
    eta, on one colour scale over both panels, with a colour bar named by the model's own
    forcing frequency (the Duffing oscillator's omega: ω, not the rotor's η)."""
    ds = xr.open_dataset(duffing_file)
    fig = plot_poincare(ds, path=tmp_path / "p.png")
    panels = [a for a in fig.axes if a.get_label() != "<colorbar>"]
    assert len(panels) == 2
    norms = set()
    for ax, d in zip(panels, ("up", "down")):
        x = ds.poincare_X.sel(direction=d).values
        y = ds.poincare_Y.sel(direction=d).values
        ok = np.isfinite(x) & np.isfinite(y)
        eta = np.broadcast_to(ds.eta.values[:, None], x.shape)
        sc = _collection(ax, f"sweep {d}")
        assert sc.get_offsets().shape == (int(ok.sum()), 2)
        np.testing.assert_array_equal(sc.get_offsets(), np.column_stack([x[ok], y[ok]]))
        np.testing.assert_array_equal(sc.get_array(), eta[ok])
        norms.add((sc.norm.vmin, sc.norm.vmax))
    assert norms == {(1.25, 1.40)}
    (bar,) = [a for a in fig.axes if a.get_label() == "<colorbar>"]
    assert bar.get_ylabel() == "ω"
    assert (tmp_path / "p.png").read_bytes()[:8] == PNG


def test_poincare_axes_are_the_models_state_names(duffing_file):
    """Hypothesis: the axes are named after the file's model: the Duffing oscillator's x
    against its velocity dx; the rotor (a file naming no states: its model's X, Y, dX,
    dY) X against Y, since its sweep files store no dX samples.  A file naming neither
    its states nor a model is refused in one line, not read as the rotor's."""
    fig = plot_poincare(xr.open_dataset(duffing_file))
    assert fig.axes[0].get_xlabel().split()[0] == "x"
    assert fig.axes[0].get_ylabel().split()[0] == "dx"
    rotor = _section_ds(["X", "Y", "dX", "dY"]).drop_vars("state")
    ax = plot_poincare(rotor).axes[0]
    assert (ax.get_xlabel().split()[0], ax.get_ylabel().split()[0]) == ("X", "Y")
    nameless = _section_ds(["X", "Y", "dX", "dY"], model=None).drop_vars("state")
    with pytest.raises(ValueError, match=r"^ds names no model \(no 'model' attribute\)"):
        plot_poincare(nameless)


def test_poincare_draws_a_user_models_velocity_where_the_file_stores_it():
    """Hypothesis: for a user model with states (q, p, dq), the section is q against dq
    when the file holds poincare_dq, and q against p (the second stored state) when it
    does not; the vertical coordinates are those of the variable named."""
    dq = np.array([[9.1, 9.2], [9.3, 9.4], [9.5, 9.6]])
    with_dq = plot_poincare(_section_ds(["q", "p", "dq"], {"poincare_dq": dq},
                                        model="user")).axes[0]
    assert with_dq.get_ylabel().split()[0] == "dq"
    np.testing.assert_array_equal(_collection(with_dq, "sweep up").get_offsets()[:, 1],
                                  [9.1, 9.2, 9.3])
    without = plot_poincare(_section_ds(["q", "p", "dq"], model="user")).axes[0]
    assert (without.get_xlabel().split()[0], without.get_ylabel().split()[0]) == ("q", "p")
    np.testing.assert_array_equal(_collection(without, "sweep up").get_offsets()[:, 1],
                                  [1.1, 1.2, 1.3])


def test_poincare_leaves_out_diverged_points_and_nan_samples():
    """Hypothesis: a diverged point's samples (here finite and far off) and samples with
    a NaN coordinate are not drawn; every other sample is."""
    ax = plot_poincare(_section_ds(["X", "Y", "dX", "dY"])).axes[0]
    np.testing.assert_array_equal(_collection(ax, "sweep up").get_offsets(),
                                  [[0.1, 1.1], [0.2, 1.2], [0.3, 1.3]])


# --- largest Lyapunov exponent ----------------------------------------------------------

def test_lyapunov_points_are_the_files_exponents(duffing_file):
    """Hypothesis: in each direction's panel the circles are exactly (eta, lyapunov) of
    the points with a finite exponent, the diamonds (eta, floquet_exponent) of the
    periodic points with a finite one, the error bars span lyapunov -/+ lyapunov_err
    where that error is finite, and a zero line is drawn."""
    ds = xr.open_dataset(duffing_file)
    fig = plot_lyapunov(ds)
    for ax, d in zip(fig.axes, ("up", "down")):
        sub = ds.sel(direction=d)
        eta, lam, err = sub.eta.values, sub.lyapunov.values, sub.lyapunov_err.values
        fe = sub.floquet_exponent.values
        ok = np.isfinite(lam)
        np.testing.assert_array_equal(_collection(ax, LYAPUNOV_LABEL).get_offsets(),
                                      np.column_stack([eta[ok], lam[ok]]))
        per = np.isfinite(fe) & (sub.regime.values == 1)
        np.testing.assert_array_equal(_collection(ax, FLOQUET_LABEL).get_offsets(),
                                      np.column_stack([eta[per], fe[per]]))
        bars = ok & np.isfinite(err)
        segs = [s for c in ax.collections if c.get_label() not in
                (LYAPUNOV_LABEL, FLOQUET_LABEL) for s in c.get_segments()]
        want = {(e, lo, hi) for e, lo, hi in zip(eta[bars], lam[bars] - err[bars],
                                                 lam[bars] + err[bars])}
        assert {(s[0, 0], s[0, 1], s[1, 1]) for s in segs} == want
        assert any(np.allclose(line.get_ydata(), 0.0) for line in ax.lines)
    # the sweep has both kinds of point, so neither check above is vacuous
    assert np.isfinite(ds.lyapunov.values).any()
    assert np.isfinite(ds.floquet_exponent.values).any()


def test_lyapunov_markers_have_the_interval_bands_colours(duffing_file):
    """Hypothesis: every marker has the colour of the band that plot_intervals draws for
    its point (same direction row, the band's eta span holding the point)."""
    ds = xr.open_dataset(duffing_file)
    bands = []
    for bar in plot_intervals(ds).axes[0].collections:
        v = bar.get_paths()[0].vertices
        row = int(round(v[:, 1].mean()))
        bands.append((row, v[:, 0].min(), v[:, 0].max(), tuple(bar.get_facecolor()[0])))
    checked = 0
    for row, ax in enumerate(plot_lyapunov(ds).axes[:2]):
        for label in (LYAPUNOV_LABEL, FLOQUET_LABEL):
            sc = _collection(ax, label)
            for (e, _), color in zip(sc.get_offsets(), sc.get_facecolors()):
                (want,) = [c for r, a, b, c in bands if r == row and a < e < b]
                assert to_rgba(want) == tuple(color)
                checked += 1
    assert checked == np.isfinite(ds.lyapunov.values).sum() + \
        np.isfinite(ds.floquet_exponent.values).sum()


# --- the command ------------------------------------------------------------------------

@pytest.mark.parametrize("kind", ["poincare", "lyapunov"])
def test_plot_command_writes_the_figure_atomically(kind, duffing_file, tmp_path,
                                                   monkeypatch, capfd):
    """Hypothesis: 'vibimpact plot FILE --kind K' writes one PNG and leaves no temporary
    file; when saving fails half-way, neither the image nor a temporary file is left
    and the command exits 2 with one line."""
    from matplotlib.figure import Figure

    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(["plot", duffing_file, "--kind", kind, "-o", "a.png"], capfd)
    assert rc == 0, err
    assert (tmp_path / "a.png").read_bytes()[:8] == PNG
    assert sorted(os.listdir(tmp_path)) == ["a.png"]

    def half_written(self, fname, **kwargs):
        with open(fname, "wb") as f:
            f.write(PNG)
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Figure, "savefig", half_written)
    rc, out, err = run_cli(["plot", duffing_file, "--kind", kind, "-o", "b.png"], capfd)
    assert rc == 2 and len(err.strip().splitlines()) == 1, err
    assert sorted(os.listdir(tmp_path)) == ["a.png"]


def _without(path, tmp_path, drop, analyses):
    """The sweep file with the variables ``drop`` set to NaN, as a sweep whose settings
    list ``analyses`` writes them."""
    ds = xr.open_dataset(path).load()
    for name in drop:
        ds[name] = ds[name] * np.nan
    settings = json.loads(ds.attrs["settings"])
    settings["analyses"] = analyses
    ds.attrs["settings"] = json.dumps(settings)
    out = tmp_path / "without.nc"
    ds.to_netcdf(out)
    return out


@pytest.mark.parametrize("kind, drop, analyses, words", [
    ("lyapunov", ["lyapunov", "floquet_exponent"], "period,poincare",
     "--analyses including lyapunov"),
    ("poincare", ["poincare_X", "poincare_Y"], "period,lyapunov",
     "--analyses including poincare")])
def test_a_file_without_the_data_gets_one_line_and_exit_2(kind, drop, analyses, words,
                                                          duffing_file, tmp_path, capfd):
    """Hypothesis: a sweep file without the variable a kind draws (its analysis not run)
    is refused with exit status 2 and one line naming the analysis to run, no traceback
    and no image."""
    path = _without(duffing_file, tmp_path, drop, analyses)
    rc, out, err = run_cli(["plot", path, "--kind", kind, "-o", tmp_path / "x.png"], capfd)
    assert rc == 2
    assert len(err.strip().splitlines()) == 1 and words in err, err
    assert "Traceback" not in err and not (tmp_path / "x.png").exists()


@pytest.mark.parametrize("kind", ["poincare", "lyapunov"])
def test_a_map_file_is_told_what_it_holds(kind, tmp_path, capfd):
    """Hypothesis: --kind poincare or lyapunov on a parameter map exits 2 with one line
    that says a map is not a sweep file and that --kind map draws it (poincare: a map
    stores no Poincaré samples; lyapunov: its exponent is a panel of --kind map)."""
    path = tmp_path / "m.nc"
    xr.Dataset({"regime": (("eta", "f"), np.ones((2, 2), dtype="i1"))},
               coords={"eta": [1.0, 1.1], "f": [0.0, 0.1]},
               attrs={"map_vary": "f"}).to_netcdf(path)
    rc, out, err = run_cli(["plot", path, "--kind", kind], capfd)
    assert rc == 2 and len(err.strip().splitlines()) == 1, err
    assert "parameter map" in err and "--kind map" in err and "needs a sweep file" in err
    assert ("Poincare" in err) == (kind == "poincare")
    assert ("exponent" in err) == (kind == "lyapunov")
