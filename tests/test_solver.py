"""The solver object and its settings (:mod:`vibimpact.core.solver`): one settings object a
System carries, one builder of the kernel's options, one place the kernel is entered, and
``simulate`` as a thin layer over :meth:`Solver.advance`."""
import ast
import inspect
import math
import pathlib

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.core.solver import SETTINGS, SIMULATE_DEFAULTS, Solver, SolverSettings

P = vi.presets.get("fig8").replace(eta=1.185)
SYSTEM = vi.System(P)
X0 = [0.2, -0.1, 0.5, 0.3]
PACKAGE = pathlib.Path(vi.__file__).parent


def test_simulate_takes_at_most_eight_parameters():
    """Hypothesis: the solver settings left simulate's signature, which now has eight
    parameters or fewer (issue 29)."""
    assert len(inspect.signature(vi.simulate).parameters) <= 8


@pytest.mark.parametrize("name", ["rtol", "method", "max_step", "steps_per_period"])
def test_an_old_solver_keyword_of_simulate_says_where_it_went(name):
    """Hypothesis: ``simulate(p, rtol=...)`` (the keywords before SolverSettings) raises a
    TypeError naming the keyword and SolverSettings, not a bare 'unexpected keyword'."""
    value = {"method": "dp5", "steps_per_period": 100}.get(name, 0.1)
    with pytest.raises(TypeError, match=rf"{name}.*SolverSettings"):
        vi.simulate(P, periods=1, **{name: value})


def test_an_unknown_keyword_of_simulate_is_a_type_error():
    """Hypothesis: a keyword that was never a setting is refused as Python does."""
    with pytest.raises(TypeError, match="unexpected keyword argument 'perods'"):
        vi.simulate(P, perods=1)


@pytest.mark.parametrize("name, value, error", [
    ("method", "euler", ValueError), ("method", 5, TypeError),
    ("rtol", 0.0, ValueError), ("atol", "1e-9", TypeError),
    ("steps_per_period", 0, ValueError), ("steps_per_period", 2.5, TypeError),
    ("adaptive", "no", TypeError), ("max_step", -1.0, ValueError),
    ("bound", math.inf, ValueError), ("event_tol", math.nan, ValueError),
    ("max_steps_per_period", True, TypeError),
])
def test_a_bad_setting_is_refused_naming_it(name, value, error):
    """Hypothesis: SolverSettings validates every field when made and names the field in
    the error (a TypeError for a value of the wrong type)."""
    with pytest.raises(error, match=rf"^{name}\b"):
        SolverSettings(**{name: value})


def test_an_unknown_setting_is_refused_listing_the_settings():
    """Hypothesis: replace and System.with_solver refuse a name that is no setting, and
    the message lists the settings there are."""
    for call in (lambda: SolverSettings().replace(tol=1.0),
                 lambda: SYSTEM.with_solver(tol=1.0)):
        with pytest.raises(ValueError, match="solver settings are method, rtol"):
            call()


def test_none_takes_the_analysis_default_then_simulates():
    """Hypothesis: filled() replaces a None setting by the caller's default, then by
    SIMULATE_DEFAULTS, and keeps a setting given; the kept result of filled() without
    defaults does not leak into a call with defaults, nor into the settings."""
    given = SolverSettings(atol=1e-7)
    assert given.filled().rtol == SIMULATE_DEFAULTS["rtol"]  # (kept for the next call)
    s = given.filled(rtol=1e-10, atol=1e-3)
    assert (s.rtol, s.atol, s.method) == (1e-10, 1e-7, "dop853")
    assert given.filled().rtol == SIMULATE_DEFAULTS["rtol"] and given.rtol is None
    assert s.steps_per_period == SIMULATE_DEFAULTS["steps_per_period"]
    assert s.max_step is None and s.bound is None  # a quarter period, the model's bound


def test_a_system_carries_one_settings_object_and_its_keywords_say_the_same():
    """Hypothesis: System(p, solver=...) keeps the settings; the old keywords still work,
    replace the same settings of ``solver`` and are read back as attributes; with_solver
    changes one setting and keeps the rest."""
    s = vi.System(P, solver=SolverSettings(method="dp5", rtol=1e-7, bound=5.0), rtol=1e-8)
    assert s.solver == SolverSettings(method="dp5", rtol=1e-8, bound=5.0)
    assert (s.method, s.rtol, s.atol) == ("dp5", 1e-8, None)
    t = s.with_solver(atol=1e-11)
    assert t.solver == SolverSettings(method="dp5", rtol=1e-8, atol=1e-11, bound=5.0)
    assert t.atol == 1e-11
    assert s.with_params(kh=50.0).solver == s.solver
    with pytest.raises(TypeError, match="solver must be a vibimpact.SolverSettings"):
        vi.System(P, solver={"rtol": 1e-8})


def test_the_options_are_built_from_the_settings_and_the_period():
    """Hypothesis: SolverSettings.options turns the settings into the kernel's options:
    the fixed step T / steps_per_period, max_step a quarter period and the model's bound
    when None, the rest as given."""
    T = SYSTEM.period
    o = SolverSettings(steps_per_period=64, event_tol=1e-11).options(T, 7.0)
    assert (o.h_fixed, o.max_step, o.bound, o.event_tol) == (T / 64, T / 4.0, 7.0, 1e-11)
    assert (o.rtol, o.atol, o.adaptive, o.n_bound, o.n_err) == (1e-9, 1e-12, True, 0, 0)
    o = SolverSettings(max_step=0.1, bound=3.0, adaptive=False).options(T, 7.0)
    assert (o.max_step, o.bound, o.adaptive) == (0.1, 3.0, False)


def test_simulate_is_one_advance_of_a_solver():
    """Hypothesis: simulate of a Params, of a System and one Solver.advance with the same
    settings give the same bits (simulate adds only the checks and the Run)."""
    settings = SolverSettings(method="dp5", rtol=1e-8)
    a = vi.simulate(P, periods=6, transient=4, state0=X0, dense=5, solver=settings)
    b = vi.simulate(vi.System(P, solver=settings), periods=6, transient=4, state0=X0,
                    dense=5)
    seg = Solver(SYSTEM, X0, settings).advance(6, skip=4, dense=5)
    for other in (b.strobe, seg.strobe):
        np.testing.assert_array_equal(a.strobe, other)
    np.testing.assert_array_equal(a.dense, seg.dense)
    np.testing.assert_array_equal(a.events["t"], seg.events["t"])
    assert b.params is P and a.solver["method"] == "dp5" and a.solver["rtol"] == 1e-8


def test_a_solver_advanced_in_pieces_continues_its_own_integration():
    """Hypothesis: the solver holds the state of the integration (state, mode, clock,
    counters), so advancing 3 then 4 periods continues where the first piece ended: the
    second piece starts at the first's last row, the clock reaches period 7, the counters
    accumulate, and the rows agree with one advance of 7 to the tolerance (the kernel
    ends its last step of a call on the period's end, so not bit for bit)."""
    one = Solver(SYSTEM, X0).advance(7)
    pieces = Solver(SYSTEM, X0)
    first = pieces.advance(3)
    steps = int(pieces.counters[0])
    second = pieces.advance(4)
    np.testing.assert_array_equal(second.strobe[0], first.strobe[-1])
    assert int(pieces.clock[0]) == 7 and int(pieces.counters[0]) > steps > 0
    np.testing.assert_allclose(np.vstack([first.strobe, second.strobe[1:]]), one.strobe,
                               rtol=0, atol=1e-7)


def test_a_run_that_stops_returns_only_the_rows_it_computed():
    """Hypothesis: advance of a run that diverges returns the DIVERGED status, a reason
    with the time it stopped, and only the stroboscopic rows computed."""
    seg = Solver(SYSTEM, X0, SolverSettings(bound=0.5)).advance(50)
    assert seg.status is vi.Status.DIVERGED
    assert "at t =" in seg.reason
    assert 1 <= len(seg.strobe) < 51


@pytest.mark.parametrize("method", ["rk4", "rk4-fixed-noevents"])
def test_the_variational_solver_runs_a_fixed_step_method_on_its_own_steps(method):
    """Hypothesis: the variational equations and the two-trajectory pair run a
    fixed-step method too (so that every analysis runs on the method a study measures),
    at its fixed step (options not adaptive), and its monodromy at 800 steps per period
    is DOP853's to 1e-6; a tangent_tol below 1 is refused naming it."""
    settings = SolverSettings(method=method, steps_per_period=800)
    var = Solver.variational(SYSTEM, X0, settings, tangents=4)
    assert var.method.name == method and not var.method.adaptive
    assert all(s.method.name == method for s in Solver.pair(SYSTEM, X0, X0, settings))
    fixed = vi.System(P, solver=settings)
    np.testing.assert_allclose(fixed.monodromy(X0).matrix, SYSTEM.monodromy(X0).matrix,
                               atol=1e-6)
    with pytest.raises(ValueError, match="^tangent_tol must be"):
        Solver.check_tangents(SolverSettings(), 0.5)


def test_the_variational_solver_takes_adaptive_steps_whatever_the_system_says():
    """Hypothesis: ``adaptive=False`` (fixed steps, for measuring orders of plain runs)
    does not reach the variational equations or the pair: their options stay adaptive,
    and the monodromy of such a system is the default system's, bit for bit."""
    fixed = vi.System(P, solver=SolverSettings(adaptive=False))
    var = Solver.variational(fixed, X0, fixed.settings(), tangents=4)
    assert var.options.adaptive and var.settings.adaptive
    assert all(s.options.adaptive for s in Solver.pair(fixed, X0, X0, fixed.settings()))
    assert not Solver(fixed, X0).options.adaptive
    np.testing.assert_array_equal(fixed.monodromy(X0).matrix, SYSTEM.monodromy(X0).matrix)


def test_the_monodromy_of_a_solver_matches_finite_differences():
    """Hypothesis: Solver.variational's tangent vectors over one period (System.monodromy)
    are the Jacobian of the stroboscopic map: central differences of two simulate runs
    per column agree to 1e-5 relative at a state off any contact."""
    x = np.array(X0)
    M = SYSTEM.monodromy(x).matrix
    tight = SolverSettings(rtol=1e-12, atol=1e-14)
    eps = 1e-6
    fd = np.empty((4, 4))
    for j in range(4):
        dx = np.zeros(4)
        dx[j] = eps
        ends = [vi.simulate(P, periods=1, state0=x + s * dx, solver=tight).final_state
                for s in (1.0, -1.0)]
        fd[:, j] = (ends[0] - ends[1]) / (2 * eps)
    np.testing.assert_allclose(M, fd, rtol=1e-5, atol=1e-5 * np.abs(fd).max())


def _kernel_calls(path):
    """Names of the kernel's integration entry points called in ``path``."""
    tree = ast.parse(path.read_text())
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and \
                node.func.attr in ("integrate", "benettin", "two_trajectory", "new_clock",
                                   "Options", "integrate_args"):
            base = node.func.value
            if isinstance(base, ast.Name) and base.id in ("_kb", "kb", "boundary"):
                out.append(node.func.attr)
    return out


def test_the_kernel_is_entered_in_one_module():
    """Hypothesis: above vibimpact/_kernel, only vibimpact/core/solver.py calls the boundary's
    integration entry points (integrate, benettin, two_trajectory), makes a clock or
    builds kernel options; the scan finds them there (so it can fail)."""
    found = {}
    for path in PACKAGE.rglob("*.py"):
        if "_kernel" in path.parts:
            continue
        calls = _kernel_calls(path)
        if calls:
            found[str(path.relative_to(PACKAGE))] = sorted(set(calls))
    assert found == {"core/solver.py": ["Options", "benettin", "integrate", "new_clock",
                                   "two_trajectory"]}


def test_the_settings_names_are_the_dataclass_fields_in_order():
    """Hypothesis: SETTINGS lists the nine settings in the order the issue gives them."""
    assert SETTINGS == ("method", "rtol", "atol", "steps_per_period", "adaptive",
                        "max_step", "bound", "event_tol", "max_steps_per_period")
