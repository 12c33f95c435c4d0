"""Bad input through the Python API: every public function raises a ``ValueError`` (or a
``TypeError`` for a wrong type) whose message names the offending argument; a STOP off
an eta grid is not an error.  (The command line's cases are in test_bad_input.py.)"""
import math
import os
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

from test_bad_input import listing


# --- API: id -> (callable, needle) --------------------------------------------------------

def _params(**kw):
    import vibimpact as vi

    return vi.Params(**kw)


def _replace(**kw):
    import vibimpact as vi

    return vi.presets.get("fig8").replace(**kw)


def _parse(text):
    from vibimpact.sweeps import parse_range

    return parse_range(text)


def _sweep(eta, **kw):
    import vibimpact as vi

    return vi.sweep(vi.presets.get("fig8"), eta, **kw)


def _simulate(**kw):
    import vibimpact as vi

    return vi.simulate(vi.presets.get("fig8"), **kw)


def _preset(name):
    import vibimpact as vi

    return vi.presets.get(name)


def _system(**kw):
    import vibimpact as vi

    return vi.System(vi.presets.get("fig8"), **kw)


def _analyse(name, *args, system=True, **kw):
    """Call analyser ``name`` of vibimpact.analysis (or vibimpact.points) on fig8 (a
    System unless told)."""
    import vibimpact as vi
    from vibimpact import analysis, points

    first = _system() if system else vi.presets.get("fig8")
    return getattr(analysis if hasattr(analysis, name) else points, name)(first, *args, **kw)


def _averaging(**kw):
    from vibimpact.analysis import Averaging

    return Averaging(**kw)


def _steps(**kw):
    from vibimpact.analysis import Steps

    return Steps(**kw)


def _follow(**kw):
    import vibimpact as vi
    from vibimpact.branches import follow_branch

    return follow_branch(vi.presets.get("fig8"), stop=1.1, **kw)


def _branch_io(name, what):
    """branches.NAME given a Run (branch_to_dataset) or a foreign dataset."""
    import xarray as xr

    import vibimpact as vi
    from vibimpact import branches

    if what == "run":
        run = vi.simulate(vi.presets.get("fig8"), periods=1)
        return branches.branch_to_dataset(run, vi.System(vi.presets.get("fig8")))
    return getattr(branches, name)(xr.Dataset({"x": ("t", [1.0])}))


API_CASES = {
    "Params kh < 0": (lambda: _params(kh=-1.0), "kh"),
    "Params B < 0": (lambda: _params(B=-0.1), "B "),
    "Params Bh < 0": (lambda: _params(Bh=-0.1), "Bh"),
    "Params BT < 0": (lambda: _params(BT=-0.1), "BT"),
    "Params f < 0": (lambda: _params(f=-0.1), "f "),
    "Params Ec < 0": (lambda: _params(Ec=-0.1), "Ec"),
    "Params eta = 0": (lambda: _params(eta=0.0), "eta"),
    "Params eta NaN": (lambda: _params(eta=math.nan), "eta"),
    "Params G inf": (lambda: _params(G=math.inf), "G"),
    "Params kh string": (lambda: _params(kh="120"), "kh"),
    "replace kh < 0": (lambda: _replace(kh=-5.0), "kh"),
    "replace eta < 0": (lambda: _replace(eta=-1.0), "eta"),
    "replace Ec NaN": (lambda: _replace(Ec=math.nan), "Ec"),
    "replace unknown name": (lambda: _replace(kq=1.0), "kq"),
    "unknown preset": (lambda: _preset("fig99"), "fig99"),
    "parse_range reversed": (lambda: _parse("1.2:1.0:0.01"), "eta"),
    "parse_range zero step": (lambda: _parse("1:2:0"), "eta"),
    "parse_range NaN": (lambda: _parse("1:nan:0.1"), "eta"),
    "parse_range words": (lambda: _parse("one:two:three"), "eta"),
    "parse_range 1e9 points": (lambda: _parse("0.5:1000000000.5:1"), "about"),
    "sweep huge array": (lambda: _sweep(np.linspace(1.0, 2.0, 100_001)), "eta"),
    "sweep decreasing eta": (lambda: _sweep([1.2, 1.1]), "eta"),
    "sweep eta <= 0": (lambda: _sweep([0.0, 1.0]), "eta"),
    "sweep NaN eta": (lambda: _sweep([1.0, math.nan]), "eta"),
    "sweep direction": (lambda: _sweep([1.0], direction="sideways"), "direction"),
    "sweep analysis": (lambda: _sweep([1.0], analyses=("spectrum",)), "analyses"),
    "simulate 1e9 periods": (lambda: _simulate(periods=10**9), "periods"),
    "simulate 1e9 transient": (lambda: _simulate(periods=1, transient=10**9), "transient"),
    "simulate periods 0": (lambda: _simulate(periods=0), "periods"),
    "System rtol < 0": (lambda: _system(rtol=-1e-9), "rtol"),
    "System unknown method": (lambda: _system(method="euler"), "method"),
    "System unknown solver setting": (lambda: _system().with_solver(tol=1.0), "solver"),
    "System unknown parameter": (lambda: _system().param("kq"), "param"),
    "analyser given Params": (lambda: _analyse("lyapunov_spectrum", system=False), "system"),
    "shooting given Params": (lambda: _analyse("shoot_periodic_orbit", [0.0] * 4,
                                               system=False), "system"),
    "classify_params given Params": (lambda: _analyse("classify_params", system=False),
                                     "system"),
    "classify_params unknown setting": (lambda: _analyse("classify_params", periods=10),
                                        "periods"),
    "shooting state0 too short": (lambda: _analyse("shoot_periodic_orbit", [0.0]), "state0"),
    "monodromy rk4": (lambda: _system(method="rk4").monodromy([0.0] * 4), "method"),
    "continuation unknown parameter": (lambda: _analyse("continue_orbit", [0.0] * 4,
                                                        param="kq", stop=1.2), "param"),
    "Averaging block 1": (lambda: _averaging(block=1), "block"),
    "Averaging max < min": (lambda: _averaging(min_periods=10, max_periods=5),
                            "max_periods"),
    "Steps ds 0": (lambda: _steps(ds=0.0), "ds"),
    "Steps max_points 1": (lambda: _steps(max_points=1), "max_points"),
    "continuation refine < 0": (lambda: _analyse("continue_orbit", [0.0] * 4, stop=1.2,
                                                 refine=-1.0), "refine"),
    "refine_stability_change same stability": (
        lambda: _analyse("refine_stability_change", "eta", 1, (1.0, 1.01),
                         ([0.0] * 4, [0.0] * 4)), "values"),
    "follow_branch approach 0": (lambda: _follow(approach=0.0), "approach"),
    "follow_branch transient < 0": (lambda: _follow(transient=-1), "transient"),
    "branch_to_dataset of a Run": (lambda: _branch_io("branch_to_dataset", "run"),
                                   "branch"),
    "branch_from_dataset foreign": (lambda: _branch_io("branch_from_dataset", "foreign"),
                                    "ds"),
}


@pytest.mark.parametrize("case", list(API_CASES))
def test_api_raises_value_error_naming_the_parameter(case):
    """The public API refuses bad input with a ValueError whose message names it."""
    call, needle = API_CASES[case]
    with pytest.raises(ValueError) as info:
        call()
    assert needle in str(info.value), str(info.value)


def _run_to(name):
    """Call ``name`` with a Run where it expects an array or a dataset."""
    import vibimpact as vi
    from vibimpact.plotting import plot_xy

    from vibimpact.plotting.map2d import plot_map

    run = vi.simulate(vi.presets.get("fig8").replace(eta=1.2), periods=3)
    call = {"classify": vi.analysis.classify, "intervals": vi.intervals, "plot_xy": plot_xy,
            "classify diverged": lambda r: vi.analysis.classify(r, diverged=True),
            "plot_response": vi.plotting.plot_response,
            "plot_bifurcation": vi.plotting.plot_bifurcation,
            "plot_intervals": vi.plotting.plot_intervals, "plot_map": plot_map,
            "write_netcdf": lambda r: vi.io.write_netcdf(r, "never.nc"),
            "format_intervals": vi.sweeps.format_intervals}
    return call[name](run)


@pytest.mark.parametrize("name, needle", [("classify", "points"), ("intervals", "ds")])
def test_a_run_where_an_array_or_dataset_is_expected_is_a_clear_type_error(name, needle):
    """A Run handed to classify (points) or intervals (a sweep dataset) raises a
    TypeError that names the argument and says what to pass, not a raw error from deep
    inside (plot_xy and write_netcdf take a Run: tests/test_sweep_start.py)."""
    with pytest.raises(TypeError) as info:
        _run_to(name)
    assert needle in str(info.value) and "Run" in str(info.value), str(info.value)


@pytest.mark.parametrize("name, needle", [
    ("classify diverged", "points"), ("plot_response", "ds"), ("plot_bifurcation", "ds"),
    ("plot_intervals", "ds"), ("plot_map", "ds"), ("format_intervals", "iv")])
def test_a_run_given_to_the_other_dataset_functions_is_a_clear_type_error(
        name, needle, tmp_path, monkeypatch):
    """Hypothesis: the Run check covered only classify and intervals; the sibling
    functions that expect a sweep (classify with diverged=True, which returned DIVERGED
    before looking at points, the sweep and map figures, format_intervals) still failed
    with a raw AttributeError from inside (or none at all), and left no file."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(TypeError) as info:
        _run_to(name)
    assert needle in str(info.value) and "Run" in str(info.value), str(info.value)
    assert listing(tmp_path) == []


def test_simulate_periods_message_has_the_estimate():
    """A run of 10^9 periods is refused at once with the estimated time (the measured cost
    per period of vibimpact._limits)."""
    import re

    from vibimpact._limits import SECONDS_PER_PERIOD, human_duration

    cost = human_duration(10**9 * SECONDS_PER_PERIOD)
    with pytest.raises(ValueError, match=rf"periods=1000000000 .*about {re.escape(cost)}"):
        _simulate(periods=10**9)


@pytest.mark.parametrize("text,grid", [("1.0:1.05:0.02", [1.0, 1.02, 1.04]),
                                       ("1.0:1.06:0.02", [1.0, 1.02, 1.04, 1.06]),
                                       ("1.0:1.0:0.5", [1.0])])
def test_stop_off_the_grid_is_accepted(text, grid):
    """STOP off the grid is not an error: the grid stops before it (STOP on the grid is
    included)."""
    assert _parse(text).tolist() == grid


