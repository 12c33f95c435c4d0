"""One saltation (issue 42, item 4): the saltation matrix is written once
(:mod:`vibimpact._kernel.variational`), for every model; the rotor keeps only its
hand-written variational right-hand side, which the benchmark
(``analyses/performance/variational_bench.py``) finds faster, and which must equal the
generic one built from the rotor's ``rhs`` and ``jac``.
"""
import numpy as np
import pytest
from numba import njit

import vibimpact as vi
from vibimpact import analysis as an
from vibimpact._kernel import rotor, variational
from vibimpact._kernel.registry import families, family

_GENERIC_RHS = variational.tangent_rhs(rotor.rhs, rotor.jac, rotor.N_STATE)


@njit
def _both(s, y, p, mode):
    a = np.empty_like(y)
    b = np.empty_like(y)
    rotor.var_rhs(s, y, p, mode, a)
    _GENERIC_RHS(s, y, p, mode, b)
    return a, b


@pytest.mark.parametrize("preset, eps", [("fig8", 0.0), ("fig11", 0.0), ("fig11", 1e-3)])
@pytest.mark.parametrize("mode", [(0, 0), (1, 1), (1, -1), (1, 0)])
def test_the_rotors_hand_written_variational_rhs_equals_the_generic_one(preset, eps, mode):
    """Hypothesis: the rotor's hand-written variational right-hand side (its Jacobian as
    eight scalars) gives the same numbers, bit for bit, as the generic
    ``tangent_rhs(rhs, jac)`` over its analytic Jacobian, for 3 tangent vectors, in free
    flight, slipping either way and sticking, with exact and regularised friction, at
    states in and out of contact."""
    p = vi.presets.get(preset).replace(eta=1.1, eps=eps).as_array()
    rng = np.random.default_rng(7)
    for R in (0.7, 1.0, 1.02):
        th = rng.uniform(-np.pi, np.pi)
        y = np.r_[R * np.cos(th), R * np.sin(th), rng.standard_normal(2),
                  rng.standard_normal(12)]
        a, b = _both(0.4, y, p, np.array(mode, dtype=np.int64))
        assert np.all(np.isfinite(a))
        np.testing.assert_array_equal(a, b)


def test_every_built_in_family_takes_its_mode_change_from_the_one_saltation():
    """Hypothesis: no built-in kernel module carries a saltation of its own: the
    variational mode change of every family with a terminal switch is a function built by
    :func:`vibimpact._kernel.variational.saltation_transition` (its body is the one
    ``_saltation_body``), and a smooth family's is its plain transition."""
    for name in families():
        entry = family(name)
        closure = getattr(entry.var_transition.py_func, "__closure__", None) or ()
        bodies = [c.cell_contents for c in closure
                  if getattr(c.cell_contents, "__name__", "") == "body"]
        if entry.terminal.any():
            assert entry.var_transition.py_func.__qualname__.startswith(
                "saltation_transition."), name
            assert bodies and bodies[0].py_func.__qualname__.startswith(
                "_saltation_body."), name
        else:
            assert entry.var_transition is entry.transition, name


def _fd_jacobian(p, x0, solver, h=1e-6):
    """Central differences of the one-period stroboscopic map (plain runs)."""
    def step(x):
        return vi.simulate(p, periods=1, state0=x, solver=solver).strobe[-1]
    return np.column_stack([(step(x0 + h * e) - step(x0 - h * e)) / (2 * h)
                            for e in np.eye(x0.size)])


def test_saltation_of_a_force_law_switch_matches_the_flow_maps_differences():
    """Hypothesis: across the rotor's contact entries and exits with tangential damping
    (``BT = 0.05``: the field jumps by ``BT v_t`` along the tangent at the surface, the
    state stays continuous) the monodromy matrix of the variational equations (the
    saltation ``S = I + (f+ - f-) n^T / (n^T f- + dg/ds)`` at every switch) equals the
    central differences of the stroboscopic map of plain runs to 1e-7 (the matrix's
    entries are of order 1; the field's jump at an entry is of order ``BT v_t``, 1e-2)."""
    p0 = vi.presets.get("fig11").replace(eta=1.06)
    x0 = vi.simulate(p0, periods=1, transient=300).strobe[-1]
    p = p0.replace(BT=0.05, f=0.0)
    sol = vi.SolverSettings(rtol=1e-12, atol=1e-13)
    run = vi.simulate(p, periods=1, state0=x0, solver=sol)
    contact = run.events["which"] == rotor.SW_CONTACT
    assert set(run.events["mode_before"][contact, 0]) == {0, 1}  # entries and exits
    M = an.monodromy(vi.System(p, solver=sol), x0).matrix
    np.testing.assert_allclose(M, _fd_jacobian(p, x0, sol), atol=1e-7)
