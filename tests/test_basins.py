"""Basins of attraction in a plane of states (vi.basins, issue 30 part 2): the boundary
measures on images with known values, the unforced double-well Duffing oscillator
against SciPy and against its known basin boundary (the saddle's stable manifold), the
NetCDF file, the plot and the command line."""
import math
import os
import subprocess
import sys

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.stats import binom

import vibimpact as vi
from vibimpact.census.basins import (boundary_cells, boundary_measures, plane_axes,
                                     write_basins)

DELTA = 0.25
GRID = 24
SPAN = 2.0


# --- boundary measures on synthetic images ----------------------------------------

def _entropy(p):
    p = np.asarray(p, dtype=float)
    p = p[p > 0]
    return float(-(p * np.log(p)).sum())


def test_straight_vertical_boundary_has_known_entropies():
    """Hypothesis: a 20 x 20 image split at column 12 (labels 0 | 1) has boundary cells in
    columns 11 and 12 only (fraction 40/400), and with 5 x 5 boxes only the 4 boxes of
    columns 10-14 are mixed, each 2/5 : 3/5, so Sbb = H(0.4) < log 2 and Sb = 4/16 H(0.4)
    (Daza et al. 2016, eqs. 1-4); the log 2 criterion does not call it fractal."""
    img = np.zeros((20, 20), dtype=int)
    img[:, 12:] = 1
    m = boundary_measures(img, eps=5)
    h = _entropy([0.4, 0.6])
    assert m["boundary_fraction"] == pytest.approx(40 / 400)
    assert np.array_equal(np.nonzero(boundary_cells(img).any(axis=0))[0], [11, 12])
    assert m["boxes"] == 16 and m["boundary_boxes"] == 4
    assert m["boundary_basin_entropy"] == pytest.approx(h, rel=1e-12)
    assert m["basin_entropy"] == pytest.approx(4 / 16 * h, rel=1e-12)
    assert m["boundary_basin_entropy"] < math.log(2) and not m["fractal_by_log2"]


def test_smooth_diagonal_boundary_is_below_log2():
    """Hypothesis: a straight diagonal boundary (smooth) on a 100 x 100 image gives
    Sbb < log 2 (each mixed box's entropy is at most log 2, and most are lopsided), and
    its value is the mean entropy of the mixed boxes, recomputed here box by box."""
    r, c = np.mgrid[0:100, 0:100]
    img = (r > 0.6 * c + 17).astype(int)
    m = boundary_measures(img, eps=5)
    s = []
    for i in range(20):
        for j in range(20):
            box = img[5 * i:5 * i + 5, 5 * j:5 * j + 5].ravel()
            s.append(_entropy(np.bincount(box, minlength=2) / 25))
    s = np.array(s)
    assert m["basin_entropy"] == pytest.approx(s.mean(), rel=1e-12)
    assert m["boundary_basin_entropy"] == pytest.approx(s[s > 0].mean(), rel=1e-12)
    assert m["boundary_basin_entropy"] < math.log(2) and not m["fractal_by_log2"]


def test_random_checkerboard_has_the_binomial_entropy():
    """Hypothesis: a 200 x 200 image of independent fair coin labels has Sb equal to the
    expected entropy of a 5 x 5 box, E[H(K/25)] with K ~ Binomial(25, 1/2) (about 0.675,
    close to log 2), within 4 standard errors of the mean over its 1600 boxes."""
    rng = np.random.default_rng(7)
    img = rng.integers(0, 2, size=(200, 200))
    m = boundary_measures(img, eps=5)
    k = np.arange(26)
    hk = np.array([_entropy([x / 25, 1 - x / 25]) for x in k])
    w = binom.pmf(k, 25, 0.5)
    mean, var = float((w * hk).sum()), float((w * hk ** 2).sum() - (w * hk).sum() ** 2)
    assert abs(m["basin_entropy"] - mean) <= 4 * math.sqrt(var / m["boxes"])
    assert abs(m["basin_entropy"] - math.log(2)) < 0.03
    assert m["boundary_fraction"] > 0.9


def test_one_basin_has_no_boundary():
    """Hypothesis: an image of one label has no boundary cell, Sb = 0, Sbb undefined
    (NaN: no mixed box) and is not called fractal."""
    m = boundary_measures(np.full((10, 10), 3), eps=5)
    assert m["boundary_fraction"] == 0 and m["basin_entropy"] == 0
    assert math.isnan(m["boundary_basin_entropy"]) and not m["fractal_by_log2"]


def test_measures_refuse_bad_input():
    """Hypothesis: a non-integer image, a 1-D one or boxes larger than the image are
    refused with a ValueError naming the argument."""
    with pytest.raises(ValueError, match="image"):
        boundary_measures(np.zeros((4, 4)) + 0.5)
    with pytest.raises(ValueError, match="image"):
        boundary_measures(np.zeros(4, dtype=int))
    with pytest.raises(ValueError, match="eps"):
        boundary_measures(np.zeros((4, 4), dtype=int), eps=5)


# --- the unforced damped double well ------------------------------------------------

def _duffing(gamma=0.0, omega=1.0):
    return vi.System(vi.DuffingParams(delta=DELTA, alpha=-1.0, beta=1.0, gamma=gamma,
                                      omega=omega))


@pytest.fixture(scope="module")
def well():
    """The basins of the unforced double well, x in [-2, 2], dx in [-2, 2], 24 x 24."""
    return vi.basins(_duffing(), grid=(GRID, GRID), plane=("x", "dx"),
                     ranges=((-SPAN, SPAN), (-SPAN, SPAN)))


def _rhs(t, y):
    x, v = y[0::2], y[1::2]
    out = np.empty_like(y)
    out[0::2] = v
    out[1::2] = -DELTA * v + x - x ** 3
    return out


def _well_of(ds):
    """+1 / -1: the well (sign of x) of each attractor of a basins dataset."""
    x = ds.samples.sel(state="x").values
    sign = np.sign(x[:, 0])
    assert np.all(np.sign(x) == sign[:, None]), "an attractor visits both wells"
    return sign


def test_basin_image_agrees_with_scipy_except_on_the_boundary(well):
    """Hypothesis: every cell's start integrated by SciPy (DOP853, rtol 1e-10) for a
    fixed 150 time units -- by then each has negative energy, trapped in one well -- ends
    in the well of the attractor the census gave it, on every cell off the boundary; and
    on all but a few boundary cells."""
    xs, vs = well.x.values, well.dx.values
    X, V = np.meshgrid(xs, vs)
    y0 = np.column_stack([X.ravel(), V.ravel()]).ravel()
    sol = solve_ivp(_rhs, (0, 150), y0, method="DOP853", rtol=1e-10, atol=1e-10)
    xe, ve = sol.y[0::2, -1], sol.y[1::2, -1]
    assert np.all(ve ** 2 / 2 - xe ** 2 / 2 + xe ** 4 / 4 < 0), "not trapped yet"
    scipy_img = np.sign(xe).reshape(GRID, GRID)
    census_img = _well_of(well)[well.basin.values]
    differ = census_img != scipy_img
    boundary = well.boundary.values
    assert not np.any(differ & ~boundary)
    assert differ.sum() <= 0.05 * boundary.sum()
    assert 0.1 < boundary.mean() < 0.6  # the image has a boundary to test


def test_negative_energy_cells_stay_in_their_well(well):
    """Hypothesis: a start of energy E = v^2/2 - x^2/2 + x^4/4 < 0 cannot cross the
    saddle at E = 0 (damping only lowers E), so its cell is labelled with the well of
    its own sign of x."""
    X, V = np.meshgrid(well.x.values, well.dx.values)
    energy = V ** 2 / 2 - X ** 2 / 2 + X ** 4 / 4
    sign = _well_of(well)[well.basin.values]
    inside = energy < 0
    assert inside.sum() > 20
    assert np.array_equal(sign[inside], np.sign(X[inside]))


def _stable_manifold():
    """Both branches of the saddle (0, 0)'s stable manifold: SciPy backward in time from
    +-1e-7 along the stable eigenvector (lambda^2 + delta lambda - 1 = 0, lambda < 0)
    until their energy exceeds the largest in the plotted square (backward in time the
    energy only grows, so the branch never comes back into the square)."""
    lam = (-DELTA - math.sqrt(DELTA ** 2 + 4)) / 2
    e = np.array([1.0, lam]) / math.hypot(1.0, lam)

    def back(t, y):
        return [-y[1], DELTA * y[1] - y[0] + y[0] ** 3]

    def out(t, y):
        return y[1] ** 2 / 2 - y[0] ** 2 / 2 + y[0] ** 4 / 4 - (SPAN ** 4 / 4 + 0.5)
    out.terminal = True
    pieces = []
    for s in (1.0, -1.0):
        sol = solve_ivp(back, (0, 200), s * 1e-7 * e, method="DOP853", rtol=1e-10,
                        atol=1e-12, events=out, max_step=0.01)
        pieces.append(sol.y.T)
    return pieces


def _distance_to_polyline(points, line):
    a, b = line[:-1], line[1:]
    ab = b - a
    t = np.clip(((points[:, None, :] - a) * ab).sum(-1) / np.maximum((ab * ab).sum(-1),
                                                                     1e-300), 0, 1)
    near = a + t[..., None] * ab
    return np.sqrt(((points[:, None, :] - near) ** 2).sum(-1)).min(axis=1)


def test_boundary_cells_lie_on_the_saddles_stable_manifold(well):
    """Hypothesis: the basin boundary of the unforced double well is the stable manifold
    of the saddle (0, 0); a boundary cell and its neighbour of the other basin lie on
    either side of it, so every boundary cell's centre is within one cell spacing of the
    manifold computed independently by SciPy."""
    X, V = np.meshgrid(well.x.values, well.dx.values)
    cells = np.column_stack([X[well.boundary.values], V[well.boundary.values]])
    h = 2 * SPAN / (GRID - 1)
    dist = np.min([_distance_to_polyline(cells, p) for p in _stable_manifold()], axis=0)
    assert cells.shape[0] > 50
    assert dist.max() <= h * (1 + 1e-9)


# --- arguments, file, plot -----------------------------------------------------------

def test_plane_names_and_aliases():
    """Hypothesis: plane names are the model's state names, X' stands for dX, case is
    ignored when unique; an unknown name or the same state twice is a ValueError naming
    the plane."""
    assert plane_axes(vi.ROTOR, ("X", "Y")) == (0, 1)
    assert plane_axes(vi.ROTOR, "X,X'") == (0, 2)
    assert plane_axes(vi.ROTOR, ("y", "dY")) == (1, 3)
    assert plane_axes(vi.DUFFING, ("x", "x'")) == (0, 1)
    with pytest.raises(ValueError, match="plane"):
        plane_axes(vi.ROTOR, ("X", "Z"))
    with pytest.raises(ValueError, match="plane"):
        plane_axes(vi.ROTOR, ("X", "x"))


@pytest.mark.parametrize("kw, name", [(dict(grid=(1, 5)), "grid"),
                                      (dict(ranges=((1, 0), (0, 1))), "ranges"),
                                      (dict(eta=[1.0, 1.1]), "eta"),
                                      (dict(base=[0.0]), "base"),
                                      (dict(grid=(4, 4)), "grid")])
def test_basins_refuses_bad_arguments(kw, name):
    """Hypothesis: bad grids (under 2 cells, or smaller than the entropy's boxes),
    ranges with lo >= hi, an eta grid and a base of the wrong size are ValueErrors naming
    the argument, raised before any integration."""
    with pytest.raises(ValueError, match=name):
        vi.basins(_duffing(), **dict(dict(plane=("x", "dx")), **kw))


def test_file_and_plot(well, tmp_path):
    """Hypothesis: the basins dataset round-trips through its NetCDF file (image,
    plane coordinates, names, measures, the boolean criterion) with no temporary file
    left, and the plot has one legend entry per attractor naming it with its fraction,
    and the plane's state names on its axes."""
    path = tmp_path / "b.nc"
    write_basins(well, path)
    assert sorted(os.listdir(tmp_path)) == ["b.nc"]
    back = vi.io.read_netcdf(path)
    assert np.array_equal(back.basin.values, well.basin.values)
    assert np.array_equal(back.x.values, well.x.values)
    assert list(back.name.values) == list(well.name.values)
    assert bool(back.fractal_by_log2) == bool(well.fractal_by_log2)
    assert float(back.basin_entropy) == float(well.basin_entropy)
    from vibimpact.plotting.basins import plot_basins

    fig = plot_basins(back, path=tmp_path / "b.png")
    ax = fig.axes[0]
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("x", "dx")
    legend = fig.legends[0] if fig.legends else ax.get_legend()
    texts = [t.get_text() for t in legend.get_texts()]
    assert len(texts) == back.sizes["attractor"]
    for a, t in enumerate(texts):
        assert str(back.name.values[a]) in t
        assert f"{100 * float(back.fraction[a]):.1f}" in t
    assert (tmp_path / "b.png").stat().st_size > 0


# --- command line --------------------------------------------------------------------

def _cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "vibimpact", *args], capture_output=True,
                          text=True, cwd=cwd)


@pytest.mark.parametrize("args, words", [
    (["--plane", "X,Z"], "--plane"), (["--grid", "1x5"], "--grid"),
    (["--range", "1:0,0:1"], "--range"), (["--range", "-1:1"], "--range"),
    (["--base", "0,0"], "--base"), (["--grid", "3x3"], "--eps")])
def test_cli_bad_input_is_one_line_exit_2(args, words, tmp_path, capsys):
    """Hypothesis: bad --plane, --grid, --range or --base give one line naming the
    option and exit 2, with nothing written."""
    from vibimpact.cli import main

    status = main(["basins", *args, "-o", str(tmp_path / "o.nc"), "--no-progress"])
    assert status == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and words in lines[0]
    assert not os.listdir(tmp_path)


@pytest.mark.slow
def test_cli_writes_file_plot_and_table(tmp_path):
    """Hypothesis: 'vibimpact basins' on fig11 at eta 1.06 with an 8 x 6 grid and a
    negative --range writes the NetCDF file (the image of the asked shape, plane X, Y)
    and the image, removes its checkpoint, and prints every attractor and the measures."""
    proc = _cli("basins", "--preset", "fig11", "--eta", "1.06", "--grid", "8x6", "--plane",
                "X,Y", "--range", "-0.5:0.5,-0.5:0.5", "-o", "b.nc", "--plot", "b.png",
                "--no-progress", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    ds = vi.io.read_netcdf(tmp_path / "b.nc")
    assert ds.basin.shape == (6, 8) and ds.attrs["plane"] == "X,Y"
    assert float(ds.X.min()) == -0.5 and float(ds.Y.max()) == 0.5
    assert sorted(os.listdir(tmp_path)) == ["b.nc", "b.png"]
    for name in ds.name.values:
        assert str(name) in proc.stdout
    assert "basin entropy Sb" in proc.stdout and "log 2" in proc.stdout


def test_cells_not_started_change_no_boundary_measure():
    """Hypothesis: padding a basin image with box-aligned blocks of cells not started
    (-2) leaves its boundary fraction, basin entropy and boundary basin entropy as they
    were: those cells are no label, no neighbour and no box."""
    from vibimpact.census.basins import NOT_STARTED, boundary_measures

    rng = np.random.default_rng(3)
    img = (rng.random((10, 10)) < 0.4).astype(np.int64)
    img[:5, :5] = 2
    padded = np.full((10, 20), NOT_STARTED, dtype=np.int64)
    padded[:, 5:15] = img
    a, b = boundary_measures(img, 5), boundary_measures(padded, 5)
    for key in ("boundary_fraction", "basin_entropy", "boundary_basin_entropy",
                "boxes", "boundary_boxes", "attractors"):
        assert b[key] == pytest.approx(a[key]), key
    with pytest.raises(ValueError, match="no cell was started"):
        boundary_measures(np.full((5, 5), NOT_STARTED), 5)
