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


def _execution(**kw):
    import vibimpact as vi

    return vi.Execution(**kw)


def _simulate(**kw):
    import vibimpact as vi

    return vi.simulate(vi.presets.get("fig8"), **kw)


def _settings(**kw):
    import vibimpact as vi

    return vi.simulate(vi.presets.get("fig8"), periods=1, solver=vi.SolverSettings(**kw))


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
    from vibimpact.continuation.branches import follow_branch

    return follow_branch(vi.presets.get("fig8"), stop=1.1, **kw)


def _branch_io(name, what):
    """branches.NAME given a Run (branch_to_dataset) or a foreign dataset."""
    import xarray as xr

    import vibimpact as vi
    from vibimpact.continuation import branches

    if what == "run":
        run = vi.simulate(vi.presets.get("fig8"), periods=1)
        return branches.branch_to_dataset(run, vi.System(vi.presets.get("fig8")))
    if what is None:
        return getattr(branches, name)(None, *((vi.System(vi.presets.get("fig8")),)
                                              if name == "branch_to_dataset" else ()))
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
    "monodromy rk5": (lambda: _system(method="rk5").monodromy([0.0] * 4), "method"),
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
    per period of vibimpact.base._limits)."""
    import re

    from vibimpact.base._limits import SECONDS_PER_PERIOD, human_duration

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




# --- issue 23, failure 7: wrong types are TypeErrors, wrong values and shapes ValueErrors ---

def _map(eta=(1.0,), vary=None, **kw):
    import vibimpact as vi

    return vi.map2d(vi.presets.get("fig8"), eta, {"kh": [40.0]} if vary is None else vary,
                    **kw)


def _plot(name):
    import vibimpact as vi

    return getattr(vi.plotting, name)(None, "never.png")


def _continue(state, **kw):
    return _analyse("continue_orbit", state, **{"stop": 1.2, **kw})


#: id -> (callable, exact class: TypeError or ValueError, needle naming the argument)
CONTRACT_CASES = {
    "Params kh 10**400 (overflow)": (lambda: _params(kh=10**400), ValueError, "kh"),
    "Params G -10**400": (lambda: _params(G=-10**400), ValueError, "G"),
    "Params kh None": (lambda: _params(kh=None), TypeError, "kh"),
    "Params kh list": (lambda: _params(kh=[1.0]), TypeError, "kh"),
    "Params kh complex": (lambda: _params(kh=1 + 2j), TypeError, "kh"),
    "Params kh bool": (lambda: _params(kh=True), TypeError, "kh"),
    "Params kh string": (lambda: _params(kh="120"), TypeError, "kh"),
    "replace Ec string": (lambda: _replace(Ec="0.1"), TypeError, "Ec"),
    "simulate method list": (lambda: _settings(method=["dp5"]), TypeError, "method"),
    "simulate method int": (lambda: _settings(method=5), TypeError, "method"),
    "simulate rtol string": (lambda: _settings(rtol="1e-6"), TypeError, "rtol"),
    "simulate old keyword rtol": (lambda: _simulate(rtol=1e-6, periods=1), TypeError,
                                  "rtol"),
    "simulate max_step string": (lambda: _settings(max_step="0.1"), TypeError,
                                 "max_step"),
    "simulate state0 (2, 2)": (lambda: _simulate(state0=np.zeros((2, 2)), periods=1),
                               ValueError, "state0"),
    "simulate state0 string": (lambda: _simulate(state0="0,0,0,0", periods=1), TypeError,
                               "state0"),
    "simulate periods float": (lambda: _simulate(periods=2.0), TypeError, "periods"),
    "simulate p None": (lambda: __import__("vibimpact").simulate(None), TypeError, "p "),
    "System rtol string": (lambda: _system(rtol="1e-6"), TypeError, "rtol"),
    "System method list": (lambda: _system(method=["dp5"]), TypeError, "method"),
    "System of None": (lambda: __import__("vibimpact").System(None), TypeError, "p "),
    "intervals None": (lambda: __import__("vibimpact").intervals(None), TypeError, "ds"),
    "sweep analyses 5": (lambda: _sweep([1.0], analyses=5), TypeError, "analyses"),
    "sweep analyses of ints": (lambda: _sweep([1.0], analyses=[1, 2]), TypeError,
                               "analyses"),
    "sweep analyses unknown in string": (lambda: _sweep([1.0], analyses="period,spectrum"),
                                         ValueError, "analyses"),
    "sweep eta 2-D": (lambda: _sweep(np.array([[1.0, 1.1]])), ValueError, "eta"),
    "sweep eta string": (lambda: _sweep("1.0"), TypeError, "eta"),
    "sweep eta None": (lambda: _sweep(None), TypeError, "eta"),
    "sweep state0 (2, 2)": (lambda: _sweep([1.0], state0=np.zeros((2, 2))), ValueError,
                            "state0"),
    "sweep direction int": (lambda: _sweep([1.0], direction=5), TypeError, "direction"),
    "sweep workers float": (lambda: _sweep([1.0], execution=_execution(workers=1.5)),
                            TypeError, "workers"),
    "sweep settings dict": (lambda: _sweep([1.0], settings={}), TypeError, "settings"),
    "map2d eta 2-D": (lambda: _map(eta=np.array([[1.0, 1.1]])), ValueError, "eta"),
    "map2d vary values 2-D": (lambda: _map(vary={"kh": [[40.0, 80.0]]}), ValueError, "kh"),
    "map2d vary values string": (lambda: _map(vary={"kh": "40"}), TypeError, "kh"),
    "map2d analyses 5": (lambda: _map(analyses=5), TypeError, "analyses"),
    "classify_params None": (lambda: __import__("vibimpact").classify_params(None),
                             TypeError, "system"),
    "classify_params analyses int": (lambda: _analyse("classify_params", analyses=3),
                                     TypeError, "analyses"),
    "continue_orbit state0 (2, 2)": (lambda: _continue(np.zeros((2, 2))), ValueError,
                                     "state0"),
    "continue_orbit stop string": (lambda: _continue(np.zeros(4), stop="1.2"), TypeError,
                                   "stop"),
    "lyapunov_spectrum None": (lambda: __import__("vibimpact").analysis.lyapunov_spectrum(
        None), TypeError, "system"),
    "detect_period None": (lambda: __import__("vibimpact").analysis.detect_period(None),
                           TypeError, "points"),
    "detect_period tol string": (lambda: __import__("vibimpact").analysis.detect_period(
        np.zeros((10, 4)), tol="1e-6"), TypeError, "tol"),
    "detect_period 3-D": (lambda: __import__("vibimpact").analysis.detect_period(
        np.zeros((10, 4, 2))), ValueError, "points"),
    "classify None": (lambda: __import__("vibimpact").analysis.classify(None), TypeError,
                      "points"),
    "presets.get None": (lambda: _preset(None), TypeError, "name"),
    "plot_response None": (lambda: _plot("plot_response"), TypeError, "ds"),
    "plot_intervals None": (lambda: _plot("plot_intervals"), TypeError, "ds"),
    "plot_bifurcation None": (lambda: _plot("plot_bifurcation"), TypeError, "ds"),
    "plot_xy None": (lambda: _plot("plot_xy"), TypeError, "ds"),
    "sweep p None": (lambda: __import__("vibimpact").sweep(None, [1.0]), TypeError, "p "),
    "sweep continuation string": (lambda: _sweep([1.0], continuation="no"), TypeError,
                                  "continuation"),
    "sweep resume 1": (lambda: _sweep([1.0], execution=_execution(resume=1)), TypeError,
                       "resume"),
    "sweep checkpoint int": (lambda: _sweep([1.0], execution=_execution(checkpoint=5)),
                             TypeError, "checkpoint"),
    "map2d p None": (lambda: __import__("vibimpact").map2d(None, [1.0], {"kh": [1.0]}),
                     TypeError, "p "),
    "map2d checkpoint int": (lambda: _map(execution=_execution(checkpoint=5)), TypeError,
                             "checkpoint"),
    "System model string": (lambda: _system(model="rotor"), TypeError, "model"),
    "System.param None": (lambda: _system().param(None), TypeError, "param"),
    "System.param unknown": (lambda: _system().param("kq"), ValueError, "param"),
    "test01 None": (lambda: __import__("vibimpact").analysis.test01(None), TypeError,
                    "series"),
    "test01 string": (lambda: __import__("vibimpact").analysis.test01("abc"), TypeError,
                      "series"),
    "test01 2-D": (lambda: __import__("vibimpact").analysis.test01(np.zeros((100, 2))),
                   ValueError, "series"),
    "contact_arcs None": (lambda: __import__("vibimpact").analysis.contact_arcs(None),
                          TypeError, "angles"),
    "contact_arcs 2-D": (lambda: __import__("vibimpact").analysis.contact_arcs(
        np.zeros((3, 2))), ValueError, "angles"),
    "open_map None": (lambda: __import__("vibimpact").maps.open_map(None), TypeError,
                      "path"),
    "read_netcdf None": (lambda: __import__("vibimpact").io.read_netcdf(None), TypeError,
                         "path"),
    "write_netcdf path None": (lambda: __import__("vibimpact").io.write_netcdf(
        __import__("xarray").Dataset(), None), TypeError, "path"),
    "sweep progress int": (lambda: _sweep([1.0], execution=_execution(progress=5)),
                           TypeError, "progress"),
    "sweep_start eta string": (lambda: _sweep_start(eta="1.0"), TypeError, "eta"),
    "sweep_start direction int": (lambda: _sweep_start(direction=1), TypeError,
                                  "direction"),
    "sweep_params None": (lambda: __import__("vibimpact").sweeps.sweep_params(None),
                          TypeError, "ds"),
    "follow_branch stop string": (lambda: _follow_to("1.2"), TypeError, "stop"),
    "branch_to_dataset None": (lambda: _branch_io("branch_to_dataset", None), TypeError,
                               "branch"),
    "branch_from_dataset None": (lambda: _branch_io("branch_from_dataset", None),
                                 TypeError, "ds"),
    "plot_response ax int": (lambda: _plot_with(ax=5), TypeError, "ax"),
    "plot_response figsize string": (lambda: _plot_with(figsize="4x3"), TypeError,
                                     "figsize"),
    "plot_response figsize of 3": (lambda: _plot_with(figsize=(1, 2, 3)), ValueError,
                                   "figsize"),
    "plot_response dpi string": (lambda: _plot_with(dpi="100"), TypeError, "dpi"),
    "plot_response dpi -1": (lambda: _plot_with(dpi=-1), ValueError, "dpi"),
    "plot_response style int": (lambda: _plot_with(style=1), TypeError, "style"),
    "impact_count None": (lambda: __import__("vibimpact").analysis.impact_count(None, 10),
                          TypeError, "impact_period"),
    "impact_count impact records": (lambda: __import__("vibimpact").analysis.impact_count(
        np.zeros(0, dtype=[("t_entry", "f8")]), 10), TypeError, "impact_period"),
    "impact_count negative": (lambda: __import__("vibimpact").analysis.impact_count(
        [-1], 10), ValueError, "impact_period"),
    "impact_statistics None": (lambda: __import__("vibimpact").analysis.impact_statistics(
        None), TypeError, "impacts"),
}


def _sweep_ds():
    """A two-point sweep dataset made by hand (no computation)."""
    import vibimpact as vi
    from vibimpact.points.point import PointResult, SweepSettings
    from vibimpact.sweeps.dataset import to_dataset

    res = PointResult.empty(4, 64).as_dict()
    res.update(regime=1, period=1, final_state=np.zeros(4))
    return to_dataset(vi.presets.get("fig8"), np.array([1.0, 1.1]), ("up",),
                      {"up": [res, res]}, SweepSettings(), direction="up",
                      continuation=True, blocks=1, command="")


def _sweep_start(**kw):
    import vibimpact as vi

    return vi.sweeps.sweep_start(_sweep_ds(), **{"eta": 1.0, "direction": "up", **kw})


def _plot_with(**kw):
    import vibimpact as vi

    kw.setdefault("ax", None)
    return vi.plotting.plot_response(_sweep_ds(), kw.pop("ax"), **kw)


def _follow_to(stop):
    import vibimpact as vi
    from vibimpact.continuation.branches import follow_branch

    return follow_branch(vi.presets.get("fig8"), stop=stop)


@pytest.mark.parametrize("case", list(CONTRACT_CASES))
def test_api_error_contract_type_or_value_error_naming_the_argument(case, tmp_path,
                                                                    monkeypatch):
    """Hypothesis: a wrong type (string, None, list, complex, bool, float for an integer)
    raises a TypeError and a wrong value or shape (overflow, a (2, 2) state, a 2-D grid)
    a ValueError that is no TypeError, each naming the argument, before any work and
    without writing a file."""
    monkeypatch.chdir(tmp_path)
    call, cls, needle = CONTRACT_CASES[case]
    with pytest.raises(cls) as info:
        call()
    assert needle in str(info.value), str(info.value)
    if cls is ValueError:
        assert not isinstance(info.value, TypeError), type(info.value)
    assert listing(tmp_path) == []


def test_analyses_given_as_one_string_is_a_list_of_names_not_letters():
    """Hypothesis: ``analyses="period"`` means the one analysis "period" (and
    "period,impacts" two), as on the command line, not the letters p, e, r, ..."""
    from vibimpact.sweeps.sweep import check_request

    settings, _ = check_request("up", "period", None, None)
    assert settings.analyses == ("period",)
    settings, _ = check_request("up", "impacts, period", None, None)
    assert settings.analyses == ("period", "impacts")
