"""Issue 32: a continuation step below what floats and the corrector can resolve
(``continue --ds 1e-300`` wrote 400 points at one eta and 158 "folds") is refused,
naming the option or field, before any work; and a stability change between two points
at one parameter value is no bifurcation."""
import numpy as np
import pytest

from test_bad_input_round3_cli import _refused

import vibimpact as vi
from vibimpact.analysis import Steps
from vibimpact.analysis.continuation import (STEP_ULPS, _branch_events, continue_orbit,
                                             smallest_step)


@pytest.mark.parametrize("argv, option", [
    (["--eta", "1.12", "--stop", "1.13", "--ds", "1e-300"], "--ds"),
    (["--eta", "1.12", "--stop", "1.13", "--ds", "1e-17"], "--ds"),   # below an ulp
    (["--eta", "1.12", "--stop", "1.13", "--ds", "1e-12"], "--ds"),   # below the tolerance
    (["--eta", "1.1", "--param", "kh", "--stop", "60", "--ds", "1e-8"], "--ds"),  # kh ~ 100
    (["--eta", "1.12", "--stop", "1.13", "--ds", "1e-300", "--ds-max", "1e-300"], "--ds"),
], ids=["1e-300", "below-ulp", "below-tol", "kh-scale", "ds-max"])
def test_continue_refuses_a_step_it_cannot_resolve(argv, option, tmp_path, monkeypatch,
                                                   capfd):
    """A --ds below the corrector's tolerance or the float resolution at the start value
    (scaled to the parameter) is refused naming the option; nothing is written."""
    line = _refused(["continue"] + argv, tmp_path, monkeypatch, capfd)
    assert f"{option} must be >= " in line


def test_continue2_refuses_a_step_it_cannot_resolve(tmp_path, monkeypatch, capfd):
    """continue2 --step whose 64th (the smallest step it takes) is below the float
    resolution over --range2, and a --step <= 0, are refused naming --step."""
    for step in ("1e-300", "-1", "0"):
        line = _refused(["continue2", "--kind", "grazing", "--param2", "BT", "--range2",
                         "0:1", "--step", step], tmp_path, monkeypatch, capfd)
        assert "--step must be" in line


def test_steps_refuse_a_smallest_step_below_the_tolerance():
    """Steps(ds_min < newton_tol) is refused naming ds_min."""
    with pytest.raises(ValueError, match="^ds_min must be >= newton_tol"):
        Steps(ds=1e-12, ds_min=1e-12)


def test_continue_orbit_refuses_a_step_below_the_float_resolution():
    """With the tolerance out of the way (newton_tol tiny), a ds_min below STEP_ULPS ulps
    of the start value is refused naming steps.ds_min, before the orbit is shot."""
    system = vi.System(vi.presets.get("fig8")).with_param("eta", 1.12)
    steps = Steps(ds=1e-15, ds_min=1e-15, newton_tol=1e-300)
    assert smallest_step(steps, 1.12) == STEP_ULPS * np.spacing(1.12) > 1e-15
    with pytest.raises(ValueError, match=r"^steps.ds_min must be >= "):
        continue_orbit(system, np.zeros(4), stop=1.13, steps=steps)


def test_stability_changes_at_one_parameter_value_are_no_bifurcation():
    """Points at one eta whose stability flips (noise) give no event; a flip between two
    values does (so the rule cannot pass by finding nothing)."""
    stable, unstable = np.array([0.5, 0.1]), np.array([1.5, 0.1])
    mults = np.array([stable, unstable, stable, unstable])
    stab = np.array([True, False, True, False])
    assert _branch_events(np.full(4, 1.12), stab, mults) == []
    assert len(_branch_events(np.array([1.0, 1.1, 1.2, 1.3]), stab, mults)) == 3
