"""NaN means "not computed" in every written file, for every dtype (issue 23, failure 2).

A point that was not computed (DIVERGED, an analysis not requested, a map row not saved
yet) holds NaN in every float variable -- both parts of a complex result split into
``*_real`` / ``*_imag`` included --, the declared fill or flag value in every integer
variable and the empty string in text; never a computed-looking 0.  The fills are made in
one place, :mod:`vibimpact.base._fill`.  The commands run in this process on small grids.
"""
import contextlib
import io as stdio
import math

import numpy as np
import pytest
import xarray as xr

import vibimpact as vi
from vibimpact.base import _fill
from vibimpact.cli import main
from vibimpact.maps.store import open_map
from vibimpact.points.point import ANALYSES, SCALARS, SweepSettings
from vibimpact.sweeps.dataset import to_dataset

#: fig8 without the magnetic bearing's stiffness and with a stiff contact: DIVERGED points
DIVERGING = ["--set", "kh=0", "--set", "Ec=3"]
#: variables a DIVERGED point fills with something other than the "not computed" value
DECIDED = {"regime", "confidence", "label", "reason"}


def run(*args):
    """``vibimpact ARGS`` in this process: ``(status, stderr)``."""
    err = stdio.StringIO()
    with contextlib.redirect_stdout(stdio.StringIO()), contextlib.redirect_stderr(err):
        try:
            rc = main([str(a) for a in args])
        except SystemExit as exc:
            rc = exc.code
    return rc, err.getvalue()


def fill_of(name, var):
    """The declared "not computed" value of the variable ``name``."""
    return _fill.fill_value(var.dtype, SCALARS.get(name))


def wrong_fills(ds, where):
    """Names of the variables of ``ds`` whose entries at the mask ``where`` (over the
    leading dims of ``regime``) are not their "not computed" value."""
    bad = []
    for name, var in ds.data_vars.items():
        if name in DECIDED or name == "row_done":
            continue
        a = var.values[where]
        fill = fill_of(name, var)
        ok = np.isnan(a) if a.dtype.kind == "f" else (a == fill)
        if not np.all(ok):
            bad.append(name)
    return bad


def split_pairs_agree(ds):
    """Names of ``*_real`` variables whose NaN entries differ from their ``*_imag``'s."""
    return [k for k in ds.data_vars if k.endswith("_real") and not np.array_equal(
        np.isnan(ds[k].values), np.isnan(ds[k[:-5] + "_imag"].values))]


def test_fill_value_of_every_dtype():
    """Hypothesis: the one fill maker gives NaN for floats, NaN in both parts for complex,
    '' for text and the declared fill for integers, and refuses an integer without one."""
    assert math.isnan(_fill.fill_value(np.float64))
    z = _fill.not_computed(3, complex)
    assert np.all(np.isnan(z.real)) and np.all(np.isnan(z.imag))
    assert _fill.fill_value(object) == ""
    assert _fill.fill_value(np.int8, -1) == -1
    with pytest.raises(ValueError, match="declared fill"):
        _fill.fill_value(np.int32)
    real, imag = _fill.complex_parts([complex(math.nan, 0.0), 1 + 2j])
    assert math.isnan(imag[0]) and (real[1], imag[1]) == (1.0, 2.0)


def test_a_sweep_of_points_not_computed_holds_only_fills():
    """Hypothesis: a sweep dataset whose points are all not computed (a map's row not
    saved yet) holds the "not computed" value in every variable of every analysis; the
    Floquet multipliers' imaginary part is NaN, not 0."""
    settings = SweepSettings(analyses=ANALYSES)
    etas = np.array([1.0, 1.1])
    ds = to_dataset(vi.presets.get("fig8"), etas, ("up", "down"),
                    {"up": [None, None], "down": [None, None]}, settings,
                    direction="both", continuation=True, blocks=1, command="")
    assert "floquet_imag" in ds
    assert wrong_fills(ds, np.ones(ds["regime"].shape, bool)) == []
    assert set(ds["label"].values.ravel()) == {"not computed"}


def test_diverged_points_of_a_classify_file_are_not_computed(tmp_path):
    """Hypothesis: every DIVERGED point of a written classify file (every analysis) holds
    NaN in every float variable (floquet_imag included), the declared fill in the integer
    ones and '' in the text ones -- the reproducer of the issue on a small grid."""
    out = tmp_path / "c.nc"
    rc, err = run("classify", "--eta", "0.9:1.0:0.05", *DIVERGING, "--direction", "both",
                  "--analyses", ",".join(ANALYSES), "--workers", "1", "--no-progress",
                  "-o", out)
    assert rc == 0, err
    ds = xr.load_dataset(out)
    diverged = ds["regime"].values == 4
    assert diverged.sum() >= 2
    assert wrong_fills(ds, diverged) == []
    assert split_pairs_agree(ds) == []


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """Every file kind written once, small: ``{kind: dataset}``; the map's partial view
    has one of its two rows removed from the checkpoint (not computed)."""
    d = tmp_path_factory.mktemp("fills")
    cmds = {
        "simulate": ["simulate", "--eta", "1.0", *DIVERGING, "--periods", "3",
                     "--transient", "3", "-o", d / "s.nc"],
        "bifurcation": ["bifurcation", "--eta", "0.9:1.0:0.05", *DIVERGING, "--workers", "1",
                        "--no-progress", "-o", d / "b.png"],
        "map": ["map", "--eta", "0.9:1.0:0.05", "--vary", "kh=0:10:10", "--set", "Ec=3",
                "--analyses", ",".join(ANALYSES), "--workers", "1", "--no-progress",
                "-o", d / "m.nc"],
        "continue": ["continue", "--eta", "1.18", "--stop", "1.2", "--approach", "1.1",
                     "--transient", "100", "-o", d / "k.nc"],
    }
    for kind, args in cmds.items():
        rc, err = run(*args)
        assert rc in (0, 1) if kind == "simulate" else rc == 0, (kind, err)
    out = {k: xr.load_dataset(d / f) for k, f in (("simulate", "s.nc"),
                                                  ("bifurcation", "b.nc"),
                                                  ("map", "m.nc"), ("continue", "k.nc"))}
    ckpt = d / "p.partial"
    p = vi.presets.get("fig8").replace(Ec=3.0)
    vi.map2d(p, eta=np.array([0.9, 0.95]), vary={"kh": np.array([0.0, 10.0])},
             analyses=ANALYSES, execution=vi.Execution(checkpoint=ckpt, workers=1))
    for f in ckpt.glob("up_000001_*.npz"):
        f.unlink()
    out["partial"] = open_map(ckpt)
    return out


@pytest.mark.parametrize("kind", ["simulate", "bifurcation", "map", "continue", "partial"])
def test_every_file_kind_splits_complex_results_with_nan_in_both_parts(files, kind):
    """Hypothesis: in every file kind, a ``*_real`` entry is NaN exactly where its
    ``*_imag`` entry is (a multiplier not computed is never stored as imaginary part 0)."""
    assert split_pairs_agree(files[kind]) == []


@pytest.mark.parametrize("kind", ["bifurcation", "map", "partial"])
def test_sweep_like_files_fill_every_point_not_computed(files, kind):
    """Hypothesis: in the bifurcation file, a map file and a map's partial view, every
    DIVERGED point and every point of a row not saved holds the "not computed" value in
    every variable; the bifurcation file's analyses not requested are NaN throughout."""
    ds = files[kind]
    where = ds["regime"].values == 4
    if kind == "partial":
        assert int(ds["row_done"].sum()) == 1
        where |= (ds["row_done"].values == 0)[..., None]
        assert np.all(ds["floquet_imag"].isel(kh=1).isnull())
    assert where.any()
    assert wrong_fills(ds, where) == []
    if kind == "bifurcation":
        assert bool(ds["X_m"].isnull().all()) and bool(ds["lyapunov"].isnull().all())
