"""Bad input on the command line, second table (issue 23, failure 8's messages).

The same promise as tests/test_bad_input.py (whose helpers this file uses): exit status 2,
one line ``vibimpact: error: ...`` naming the problem, nothing on stdout, no file made or
removed.  Here: a parameter given twice with ``--set``, ``--eta`` values that the grid's
rounding to 12 decimals would change, and ``plot`` of a file whose every point diverged.
"""
import warnings
from pathlib import Path

import numpy as np
import pytest

from test_bad_input import CONT, ONE, SIM, assert_refused, listing, run_cli


def _all_diverged(d, name="d.nc"):
    """A sweep file whose points all diverged (every analysis requested, nothing finite)."""
    import json

    import xarray as xr

    from vibimpact.io import write_netcdf

    ds = xr.Dataset({"regime": ("eta", np.array([4, 4], dtype="i1")),
                     "X_m": ("eta", [np.nan, np.nan]),
                     "poincare_X": (("eta", "sample"), np.full((2, 64), np.nan))},
                    coords={"eta": [1.0, 1.01]},
                    attrs={"command": "vibimpact classify --eta 1.0:1.01:0.01 -o d.nc",
                           "settings": json.dumps({"analyses": "period,response,poincare"})})
    write_netcdf(ds, Path(d) / name)


MAP = ["map", "--eta", "1.0,1.1", "--vary", "kh=10,20", "--workers", "1", "--no-progress"]

#: id -> (argv, needle, setup)
CASES = {
    "--set twice (classify)": ([*ONE, "--set", "kh=10", "--set", "kh=200", "-o", "c.nc"],
                               "--set kh given twice", None),
    "--set twice, same value": ([*ONE, "--set", "Ec=0.1", "--set", "Ec=0.1", "-o", "c.nc"],
                                "--set Ec given twice", None),
    "--set twice (simulate)": ([*SIM, "--set", "f=0", "--set", "f=0.1", "-o", "s.nc"],
                               "--set f given twice", None),
    "--set twice (map)": ([*MAP, "--set", "G=0.1", "--set", "G=0.2", "-o", "m.nc"],
                          "--set G given twice", None),
    "--set twice (continue)": ([*CONT, "--set", "kh=10", "--set", "kh=20", "-o", "b.nc"],
                               "--set kh given twice", None),
    "--eta START with 13 decimals": (["classify", "--eta", "1.0000000000001:1.01:0.01",
                                      "-o", "c.nc"], "eta START 1.0000000000001 has more "
                                     "than 12 decimals", None),
    "--eta STEP of 1.5e-13": (["classify", "--eta", "1:1.00000001:1.5e-13", "-o", "c.nc"],
                              "eta STEP must be >= 1e-12 (the grid is rounded", None),
    "--eta STEP with 13 decimals": (["classify", "--eta", "1:1.1:0.0100000000001", "-o",
                                     "c.nc"], "eta value 2 1.0100000000001 has more than "
                                    "12 decimals", None),
    "--eta value changed by rounding (map)": ([*MAP[:1], "--eta", "1.1:1.2:0.0500000000001",
                                               *MAP[3:], "-o", "m.nc"],
                                              "has more than 12 decimals", None),
    "--vary values changed by rounding": ([*MAP[:3], "--vary", "kh=10.0000000000001:20:5",
                                           *MAP[5:], "-o", "m.nc"],
                                          "has more than 12 decimals", None),
    "plot all diverged (default kind)": (["plot", "d.nc", "-o", "p.png"],
                                         "has no response data (X_m) to draw: every point "
                                         "(2) diverged", _all_diverged),
    "plot all diverged (bifurcation)": (["plot", "d.nc", "--kind", "bifurcation", "-o",
                                         "p.png"], "has no Poincare points to draw: every "
                                        "point (2) diverged", _all_diverged),
}


@pytest.mark.parametrize("case", list(CASES))
def test_cli_refuses_with_a_message_that_names_the_problem(case, tmp_path, monkeypatch,
                                                           capfd):
    """Hypothesis: each of these inputs is refused before any work with exit 2 and one
    line naming its real problem (not a later, misleading one), leaving no file."""
    argv, needle, setup = CASES[case]
    if setup is not None:
        setup(tmp_path)
    before = listing(tmp_path)
    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(argv, capfd)
    assert_refused(rc, out, err, needle)
    assert listing(tmp_path) == before


@pytest.mark.parametrize("text, grid", [("1e300:1e300:1", [1e300]),
                                        ("20000:20000.2:0.1", [20000.0, 20000.1, 20000.2]),
                                        ("0.9:0.906:0.002", [0.9, 0.902, 0.904, 0.906])])
def test_large_range_values_parse_without_numpy_warnings(text, grid):
    """Hypothesis: values of 10^4 and more are not rounded to 12 decimals (which overflowed
    for 1e300 and printed numpy RuntimeWarning lines); the ordinary grids keep their
    rounded values.  Parsed as a grid of a parameter other than the forcing frequency,
    whose values are not bounded by the frequency range."""
    from vibimpact.sweeps import parse_range

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert parse_range(text, name="kh", positive=False).tolist() == grid


@pytest.mark.parametrize("text", ["1e300:1e300:1", "2e6", "1e-9,2e-9", "5e5:2e6:5e5"])
def test_eta_outside_the_frequency_range_is_refused_without_numpy_warnings(text):
    """Hypothesis: an eta grid outside the forcing-frequency range is refused by that
    range, naming eta, and no NumPy warning comes before the refusal."""
    from vibimpact.base._limits import ETA_RANGE
    from vibimpact.sweeps import parse_range

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=rf"eta must lie in \[{ETA_RANGE[0]:g}, "):
            parse_range(text)


def test_eta_step_below_a_floats_resolution_says_so():
    """Hypothesis: a STEP below the resolution of floats at large values is refused with
    that reason, not with the 12-decimal rounding's."""
    from vibimpact.sweeps import parse_range

    with pytest.raises(ValueError, match=r"STEP 1 is below a float.s resolution at 1e\+17"):
        parse_range("1e17:100000000000000032:1")


def test_interval_table_prints_large_eta_in_its_columns():
    """Hypothesis: the interval table prints an eta of 10^4 or more with 4 significant
    digits in its 8 columns (eta = 1e300, which the parser now accepts like --eta 1e300,
    printed 300 digits), and ordinary values with 4 decimals as before."""
    import xarray as xr

    from vibimpact.sweeps import format_intervals

    iv = xr.Dataset({"start": ("interval", [1e300, 1.1]), "end": ("interval", [1e300, 1.2]),
                     "points": ("interval", [1, 11]),
                     "label": ("interval", ["diverged", "P1 impactless"]),
                     "direction": ("interval", ["up", "up"])})
    lines = format_intervals(iv).splitlines()
    assert lines[1] == "up          1e+300   1e+300      1  diverged"
    assert lines[2] == "up          1.1000   1.2000     11  P1 impactless"
