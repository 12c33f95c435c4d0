"""Continuation at a bound of a parameter's domain (issue 33, part 2).

Every preset has ``Bh = BT = f = Rr = 0``, on the bound of their domain (``>= 0``), so a
branch in one of them starts on the bound.  The central difference of the map in the
parameter stepped to ``-1e-6`` there and the continuation failed with "BT must be >= 0,
got -1e-06".  The domain of each parameter is stated once (:class:`vibimpact.models.params.Domain`,
read by :meth:`vibimpact.System.param_domain`); the continuation takes a one-sided
second-order difference where the central one would leave it, ends a branch that
reaches a bound on it, and never computes an orbit outside it.

Known values: the map's derivative in the damping of a linear oscillator (Duffing with
``beta = 0``) is analytic (Van Loan's block exponential of the forced system), at the
bound ``delta = 0`` as inside.
"""
import math

import numpy as np
import pytest
import scipy.linalg

import vibimpact as vi
from vibimpact.analysis import Steps, continue_orbit, refine_stability_change
from vibimpact.analysis.bifurcation import CONTINUATION_SOLVER
from vibimpact.analysis.continuation import _map_derivative
from vibimpact.models.params import Domain

from test_continue_cli import run as run_cli
from test_user_model import _init_mode, _jac, _rhs, _switches, _transition

#: fig8 at the issue's start: eta = 1.12, reached by stepping eta up from 1.1
ETA, APPROACH = 1.12, 1.1
#: the rotor parameters that are 0 in every preset (on their bound)
AT_ZERO = ("BT", "f", "Bh", "Rr")


@pytest.fixture(scope="module")
def fig8():
    """fig8 at eta = 1.12 and a state on its impacting period-1 orbit (approached from
    eta = 1.1 as a sweep does)."""
    from vibimpact.sweeps import continued_state

    p = vi.presets.get("fig8").replace(eta=ETA)
    return vi.System(p), continued_state(p, ETA, eta_start=APPROACH, transient=200)


def _residual(system, param, value, state):
    """``max |P(x) - x|`` of the orbit at ``param = value`` (integrated at tighter
    tolerances than the continuation's)."""
    run = system.with_param(param, value).simulate(
        periods=1, state0=state, solver=vi.SolverSettings(rtol=1e-12, atol=1e-14))
    assert run.ok
    return float(np.abs(run.final_state - state).max())


def _assert_in_domain(system, branch):
    dom = system.param_domain(branch.param)
    assert all(v in dom for v in branch.values), branch.values


@pytest.mark.parametrize("param", AT_ZERO)
def test_a_branch_starts_on_the_bound_zero_and_moves_into_the_domain(fig8, param):
    """Hypothesis: from fig8's impacting P1 at eta = 1.12, where ``param`` = 0 (its
    bound, ``>= 0``), continuation towards 0.1 starts at exactly 0, steps into the
    domain (every further value > 0 and increasing), never leaves it, and every point is
    a period-1 orbit (``|P(x) - x| < 1e-7`` at tighter tolerances)."""
    system, start = fig8
    assert system.param(param) == 0.0
    br = continue_orbit(system, start, param=param, stop=0.1,
                        steps=Steps(max_points=4), amplitude=False)
    assert br.values.size == 4, br.status
    assert br.values[0] == 0.0
    assert np.all(np.diff(br.values) > 0.0), br.values
    _assert_in_domain(system, br)
    for v, x in zip(br.values, br.states):
        assert _residual(system, param, v, x) < 1e-7


@pytest.mark.parametrize("stop", [0.0, -0.01])
def test_a_branch_continued_down_to_B_zero_ends_on_the_bound(fig8, stop):
    """Hypothesis: fig8's P1 followed from B = 0.003 down (stop at the bound B = 0, or
    past it) reaches B = 0 exactly, computes nothing below it, ends there with the
    reason in its status, and its last point is a period-1 orbit at B = 0."""
    system, start = fig8
    br = continue_orbit(system.with_param("B", 0.003), start, param="B", stop=stop,
                        direction=-1, steps=Steps(max_points=20), amplitude=False)
    assert br.status == "reached the bound B = 0 (B must be >= 0)"
    assert br.values[-1] == 0.0
    assert np.all(np.diff(br.values) < 0.0), br.values
    _assert_in_domain(system, br)
    assert _residual(system, "B", 0.0, br.states[-1]) < 1e-7


# --- the one-sided derivative against the analytic one ----------------------------------

LINEAR = dict(alpha=1.0, beta=0.0, gamma=0.5, omega=1.3)


def _exact_map(delta, x0):
    """``(P(x0), dP/d delta)`` of ``x'' + delta x' + alpha x = gamma cos(omega t)`` over
    one forcing period, exactly: the forcing as the states ``(cos, sin)`` of a rotation
    makes the system linear and autonomous, ``y' = A y``, so ``P = exp(A T) y0`` and
    ``d exp(A T) / d delta`` is the upper-right block of ``exp([[A, E], [0, A]] T)`` with
    ``E = dA / d delta`` (Van Loan 1978)."""
    a, g, w = LINEAR["alpha"], LINEAR["gamma"], LINEAR["omega"]
    A = np.array([[0.0, 1.0, 0.0, 0.0], [-a, -delta, g, 0.0], [0.0, 0.0, 0.0, -w],
                  [0.0, 0.0, w, 0.0]])
    E = np.zeros((4, 4))
    E[1, 1] = -1.0
    T = 2.0 * math.pi / w
    big = scipy.linalg.expm(np.block([[A, E], [np.zeros((4, 4)), A]]) * T)
    y0 = np.array([x0[0], x0[1], 1.0, 0.0])
    return (big[:4, :4] @ y0)[:2], (big[:4, 4:] @ y0)[:2]


def _derivative(delta, x0, domain=None):
    """``G_lambda`` in ``delta`` as the continuation takes it (its solver settings, its
    step ``h = 1e-6``), in the model's domain or in ``domain``."""
    system = vi.System(vi.DuffingParams(delta=delta, **LINEAR)).resolved(
        **CONTINUATION_SOLVER)
    dom = system.param_domain("delta") if domain is None else domain
    return _map_derivative(system, "delta", dom, np.asarray(x0, float), delta, 1,
                           Steps().fd_step)


def test_the_map_of_the_linear_oscillator_is_the_exact_one():
    """Hypothesis: the Duffing kernel with beta = 0 at delta = 0 integrates the linear
    oscillator whose exact map the next test differentiates (same equation, phase and
    period): its one-period map agrees with the closed form to 1e-9."""
    x0 = [0.3, -0.2]
    run = vi.simulate(vi.DuffingParams(delta=0.0, **LINEAR), periods=1, state0=x0,
                      solver=vi.SolverSettings(rtol=1e-12, atol=1e-14))
    np.testing.assert_allclose(run.final_state, _exact_map(0.0, x0)[0], atol=1e-9)


def test_the_one_sided_derivative_at_the_bound_is_as_accurate_as_the_central_one():
    """Hypothesis: at the bound delta = 0 the continuation's G_lambda is one-sided
    (``delta - h`` would leave the domain) and matches the exact derivative to 1e-6 of
    its size; slightly inside (delta = 1e-3) the central difference matches the exact
    one as well, and the one-sided formula taken there (a domain that starts at 1e-3)
    agrees with the central one: second order both, so no accuracy is lost at the
    bound."""
    x0 = [0.3, -0.2]
    at_bound = _derivative(0.0, x0)
    exact0 = _exact_map(0.0, x0)[1]
    assert at_bound is not None
    np.testing.assert_allclose(at_bound, exact0, atol=1e-6 * np.abs(exact0).max())
    central = _derivative(1e-3, x0)
    one_sided = _derivative(1e-3, x0, domain=Domain.at_least(1e-3))
    exact1 = _exact_map(1e-3, x0)[1]
    np.testing.assert_allclose(central, exact1, atol=1e-6 * np.abs(exact1).max())
    np.testing.assert_allclose(one_sided, central, atol=1e-6 * np.abs(exact1).max())
    assert not np.array_equal(one_sided, central)  # a different formula indeed


# --- open bounds, starts on a bound, the domain in one place ------------------------------

def test_an_open_bound_is_approached_but_never_reached():
    """Hypothesis: continued towards omega <= 0 (past the open bound omega > 0), the
    linear oscillator's branch ends next to the bound with every omega > 0 and a status
    that names the bound."""
    system = vi.System(vi.DuffingParams(delta=0.3, **{**LINEAR, "omega": 0.3}))
    br = continue_orbit(system, [0.0, 0.0], param="omega", stop=-1.0, direction=-1,
                        steps=Steps(ds=0.05, ds_max=0.1, max_points=30), amplitude=False)
    assert np.all(br.values > 0.0), br.values
    assert "next to the bound (omega must be > 0)" in br.status, br.status
    assert br.values[-1] < 1e-3


def test_a_start_on_the_bound_pointing_out_of_the_domain_ends_at_once():
    """Hypothesis: started on delta = 0 with direction -1 (out of the domain), the
    branch is its start alone and says it is on the bound; nothing below 0 is run."""
    system = vi.System(vi.DuffingParams(delta=0.0, **LINEAR))
    br = continue_orbit(system, [0.0, 0.0], param="delta", stop=(0.0, 0.2), direction=-1,
                        steps=Steps(max_points=5), amplitude=False)
    assert br.values.tolist() == [0.0]
    assert br.status == "reached the bound delta = 0 (delta must be >= 0)"


def test_param_domain_reads_each_models_own_statement():
    """Hypothesis: System.param_domain gives the rotor's and the Duffing oscillator's
    domains as their parameter sets validate them (the same words in the error), and a
    user model's vector unbounded but for its forcing frequency (> 0)."""
    rotor = vi.System(vi.presets.get("fig8"))
    assert rotor.param_domain("BT") == Domain.at_least(0.0)
    assert rotor.param_domain("eta") == Domain.above(0.0)
    assert rotor.param_domain("k3") == Domain()
    with pytest.raises(ValueError, match=r"^BT must be >= 0, got -1e-06$"):
        vi.presets.get("fig8").replace(BT=-1e-6)
    assert rotor.param_domain("BT").rule("BT") == "BT must be >= 0"
    duff = vi.System(vi.DuffingParams())
    assert duff.param_domain("delta") == Domain.at_least(0.0)
    assert duff.param_domain("omega").rule("omega") == "omega must be > 0"
    model = vi.Model.from_functions("linear", _rhs, _jac, _switches, _transition,
                                    _init_mode, terminal=[0], state_names=("x", "v"),
                                    param_names=("c", "k", "F", "w"), omega_index=3)
    user = vi.System(np.array([0.3, 1.0, 0.5, 1.7]), model=model)
    assert user.param_domain(0) == Domain() and user.param_domain("c") == Domain()
    assert user.param_domain(3) == Domain.above(0.0)
    assert 0.0 not in user.param_domain("w") and -5.0 in user.param_domain("k")
    with pytest.raises(ValueError, match="param"):
        rotor.param_domain("kq")


def test_refine_refuses_an_end_outside_the_domain():
    """Hypothesis: refine_stability_change shoots only between its two ends, so it
    refuses an end outside the parameter's domain, naming ``values`` and the rule."""
    system = vi.System(vi.DuffingParams(delta=0.0, **LINEAR))
    with pytest.raises(ValueError, match=r"^values: delta must be >= 0, got -0.01$"):
        refine_stability_change(system, "delta", 1, (-0.01, 0.1),
                                ([0.0, 0.0], [0.0, 0.0]))


# --- the command line ---------------------------------------------------------------------

def test_the_issue_command_continues_BT_from_zero(tmp_path):
    """Hypothesis: the issue's command, ``vibimpact continue --eta 1.12 --approach 1.1
    --param BT --stop 0.1``, exits 0 and prints a branch from BT = 0 to 0.1, and its
    file holds only values in [0, 0.1]."""
    import xarray as xr

    out = tmp_path / "bt.nc"
    rc, text, err = run_cli("continue", "--eta", "1.12", "--approach", "1.1", "--param",
                            "BT", "--stop", "0.1", "-o", out)
    assert rc == 0, err
    assert text.startswith("P1 branch in BT from 0 to 0.1: "), text
    with xr.open_dataset(out) as ds:
        bt = ds["BT"].values
    assert bt[0] == 0.0 and np.all((bt >= 0.0) & (bt <= 0.1)), bt


@pytest.mark.parametrize("args, needle", [
    (["--param", "BT", "--stop", "-0.1"], "--stop: BT must be >= 0, got -0.1"),
    (["--param", "BT", "--set", "BT=-1", "--stop", "0.1"],
     "--set BT: BT must be >= 0, got -1.0"),
    (["--eta", "-1", "--stop", "1.2"], "--eta: eta must be > 0, got -1.0"),
], ids=["stop below BT = 0", "start BT < 0", "start eta < 0"])
def test_a_start_or_stop_outside_the_domain_is_one_line_naming_the_option(tmp_path, args,
                                                                          needle):
    """Hypothesis: a --stop, --set or --eta outside the parameter's domain is refused
    before any computation: exit 2, one line naming the option and the rule, nothing
    written."""
    rc, text, err = run_cli("continue", *args, "-o", tmp_path / "x.nc")
    assert rc == 2 and text == ""
    assert err.splitlines() == [f"vibimpact: error: {needle}"], err
    assert not list(tmp_path.iterdir())


def test_a_plain_vector_of_the_rotor_has_the_rotors_domains():
    """Hypothesis: the domains belong to the model, not to the type of its parameters:
    a System of the rotor built from a plain parameter vector (model=vi.ROTOR) has the
    same domains as one built from Params, so its continuation from BT = 0 stays in
    BT >= 0 as well."""
    p = vi.presets.get("fig8")
    plain, typed = vi.System(p.as_array(), model=vi.ROTOR), vi.System(p)
    for name in vi.ROTOR.param_names:
        assert plain.param_domain(name) == typed.param_domain(name), name
    assert vi.System(np.ones(5), model=vi.DUFFING).param_domain("delta") == \
        Domain.at_least(0.0)
