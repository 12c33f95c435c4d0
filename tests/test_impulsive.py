"""Impulsive contact laws in the generic code (issue 42, item 3): a contact declared as a
restitution (:class:`vibimpact.models.contact.Restitution`), the jump of Newton's impact law
applied by the kernel at the located impact, its saltation matrix in the variational
equations, impact records, chattering ended at its accumulation point and the sticking
mode (:mod:`vibimpact._kernel.impulsive`).

The model is defined here, through the user-model path: the impact oscillator
``x'' + 2 zeta x' + x = A cos(w t)`` with a rigid stop at ``x = d`` (free while
``x < d``) and ``x'+ = -r x'-``.  With ``zeta = A = 0`` its flights are arcs of
``x(t) = d cos t - u sin t`` (leaving the stop at speed ``u``): each lasts
``2 atan(u / |d|)`` for a stop above the rest position (``d < 0``) and returns at speed
``u`` (energy is conserved in flight), the closed form every chattering check uses.
"""
import math

import numpy as np
import pytest
from numba import njit

import vibimpact as vi
from vibimpact import analysis as an
from vibimpact._kernel.impulsive import (CHATTER, HELD, N_MODE, STICK, SW_CHATTER,
                                         TERMINAL, chatter_remainder, stop_model)
from vibimpact.models.contact import Contact, ContactLaw, Restitution

# every test here integrates a model declared in this file, whose kernel numba compiles in
# the test process (it would be the fast suite's longest step): the slow line runs them
# (pyproject.toml's marker); the fast suite keeps the impulsive law through the built-in
# hard-impact oscillator, whose kernel is in the install's cache (tests/test_hard_impact.py)
pytestmark = pytest.mark.slow


@njit
def _accel(s, y, p):
    return p[3] * math.cos(p[4] * s) - 2.0 * p[0] * y[1] - y[0]


@njit
def _free_rhs(s, y, p, out):
    out[0] = y[1]
    out[1] = _accel(s, y, p)


@njit
def _free_jac(s, y, p, J):
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0] = -1.0
    J[1, 1] = -2.0 * p[0]


def _stop(law):
    return Contact(switch=0, mode=0, penetration=lambda q, p: q[:, 0] - p[1],
                   normal_speed=lambda q, p: q[:, 1].copy(),
                   angle=lambda q, p: 0.0 * q[:, 0], extremum=1, positions=(0,), law=law)


MODEL = vi.Model.from_functions(
    "impact oscillator", *stop_model(_free_rhs, _free_jac, _accel, 2, 0, 1, 1, 2,
                                     cache=False),
    terminal=TERMINAL, state_names=("x", "v"), param_names=("zeta", "d", "r", "A", "w"),
    omega_index=4, n_mode=N_MODE, contact=_stop(Restitution("r")))


def _run(p, state0, **kw):
    return vi.simulate(np.asarray(p, float), periods=1, state0=np.asarray(state0, float),
                       model=MODEL, **kw)


@pytest.mark.parametrize("r, u0", [(0.5, 0.01), (0.8, 0.02), (0.3, 0.05)])
def test_chattering_accumulates_at_the_geometric_series_and_sticks(r, u0):
    """Hypothesis: leaving the stop (``d = -1``, the spring pressing the body into it)
    at speed ``u0`` without damping or forcing, the body hits it at speeds ``u0 r^k``
    (energy conserved in flight) after flights of ``2 atan(u0 r^k)`` (both to 1e-8), until
    the predicted remainder is below the chattering time; the envelope that replaces the
    rest ends the sequence in the sticking mode at the accumulation time: within 1e-6
    (relative; the flights' integration tolerance) of the exact series
    ``sum_k 2 atan(u0 r^k)`` (the envelope is exact for a constant force, the flights'
    ``atan`` differs from its argument by ``O(u^3)``), and
    within 1 % of Budd & Dux's geometric series ``2 u0 / (a (1 - r))`` (``a = 1``, first
    order in ``u0``).  The body then stays at rest on the stop (strobe ``(d, 0)``
    exactly); the impacts last no time, the last one until the end (still held)."""
    run = _run([0.0, -1.0, r, 0.0, 1.0], [-1.0, -u0])
    assert run.ok
    ev = run.events
    stuck = np.flatnonzero(ev["which"] == SW_CHATTER)
    assert stuck.size == 1
    assert tuple(ev["mode_before"][stuck[0]]) == (HELD, CHATTER)
    assert tuple(ev["mode_after"][stuck[0]]) == (HELD, STICK)
    t_stick = ev["t"][stuck[0]]
    exact = sum(2.0 * math.atan(u0 * r ** k) for k in range(2000))
    assert abs(t_stick - exact) <= 1e-6 * exact
    assert abs(t_stick - 2.0 * u0 / (1.0 - r)) <= 0.01 * 2.0 * u0 / (1.0 - r)
    impacts = run.impacts
    assert impacts.size >= 3
    k = np.arange(impacts.size)
    np.testing.assert_allclose(impacts["v_impact"], u0 * r ** k, rtol=1e-9, atol=1e-8)
    np.testing.assert_allclose(np.diff(np.r_[0.0, impacts["t_entry"]]),
                               2.0 * np.arctan(u0 * r ** k), rtol=1e-9, atol=1e-8)
    assert np.all(impacts["duration"][:-1] == 0.0) and np.isnan(impacts["duration"][-1])
    np.testing.assert_array_equal(run.strobe[-1], [-1.0, 0.0])


def test_the_stop_releases_the_body_where_the_force_changes_sign_and_records_it():
    """Hypothesis: a chattering sequence under the force ``A cos t + 1`` (``A = 2``,
    ``d = -1``) sticks, and the stop holds the body until that force changes sign, at
    ``t = acos(-1/A) = 2 pi / 3`` (to 1e-9); then it flies free.  The impact records
    give every bounce a duration 0 (exit = entry) and the impact that ended the sequence
    the time until the release."""
    run = _run([0.0, -1.0, 0.5, 2.0, 1.0], [-1.0, -0.01])
    ev = run.events
    release = np.flatnonzero((ev["which"] == 0) & (ev["mode_before"][:, 0] == HELD))
    assert release.size == 1
    assert abs(ev["t"][release[0]] - 2.0 * math.pi / 3.0) < 1e-9
    assert tuple(ev["mode_before"][release[0]]) == (HELD, STICK)
    assert ev["mode_after"][release[0], 0] == 0
    imp = run.impacts
    last = imp[-1] if imp["t_entry"][-1] < ev["t"][release[0]] else imp[-2]
    assert np.all(imp["duration"][imp["t_entry"] < last["t_entry"]] == 0.0)
    assert abs(last["t_exit"] - 2.0 * math.pi / 3.0) < 1e-9
    assert last["duration"] > 1.0


def test_the_remainder_of_a_chattering_sequence_is_the_geometric_series():
    """Hypothesis: the predicted remainder is ``2 r u / (a (1 - r))``; no accumulation
    (inf) for a force pulling away or an elastic stop; none left (0) after a plastic
    impact or at rest."""
    assert chatter_remainder(0.1, 2.0, 0.5) == pytest.approx(2 * 0.5 * 0.1 / (2.0 * 0.5))
    assert chatter_remainder(0.1, -1.0, 0.5) == math.inf
    assert chatter_remainder(0.1, 1.0, 1.0) == math.inf
    assert chatter_remainder(0.1, 1.0, 0.0) == 0.0
    assert chatter_remainder(0.0, 1.0, 0.5) == 0.0


def test_a_restitution_is_declared_and_checked_like_a_force_law():
    """Hypothesis: a restitution law names its parameter (a ValueError naming
    ``coefficient`` otherwise, and naming ``contact`` when the parameter is not the
    model's); a user model declaring one gets the domain [0, 1] for it (r = 1.5 and
    r = -0.1 refused with a ValueError naming r); the kernel builder refuses an index
    outside the state, a side other than +-1 and a non-positive chattering time, naming
    each; force laws are not impulsive."""
    assert Restitution("r").parameters() == {"restitution": "r"}
    assert Restitution("r").impulsive and not ContactLaw("k").impulsive
    for bad in ("", 3, None):
        with pytest.raises(ValueError, match="^coefficient must name a parameter"):
            Restitution(bad)
    with pytest.raises(ValueError, match="^contact: the law's restitution 'e'"):
        _stop(Restitution("e")).check(2, 3, 2, ("zeta", "d", "r", "A", "w"))
    for r in (1.5, -0.1):
        with pytest.raises(ValueError, match=r"^r must be >= 0 and <= 1"):
            MODEL.check_params(np.array([0.0, -1.0, r, 0.0, 1.0]))
    args = (_free_rhs, _free_jac, _accel, 2)
    with pytest.raises(ValueError, match="^pos must index the 2 states"):
        stop_model(*args, 2, 1, 1, 2)
    with pytest.raises(ValueError, match="^side must be"):
        stop_model(*args, 0, 1, 1, 2, side=0.0)
    with pytest.raises(ValueError, match="^chatter_time must be > 0"):
        stop_model(*args, 0, 1, 1, 2, chatter_time=0.0)


def test_the_saltation_of_an_impact_matches_the_flow_maps_differences():
    """Hypothesis: through an impact (the state jumps by ``R(x, v) = (d, -r v)``, the
    field too) the monodromy matrix of the variational equations, with the saltation
    ``S = DR + (f+ - DR f-) n^T / (n^T f-)``, equals the central differences of the
    stroboscopic map of plain runs to 1e-7 on an impacting periodic orbit (``zeta =
    0.05``, ``d = 0.5``, ``r = 0.7``, ``A = 1``, ``w = 1.3``); a monodromy without the
    jump's saltation (``DR`` alone, or the identity) would differ in its second row by
    the ``(1 + r)`` reversal."""
    p = np.array([0.05, 0.5, 0.7, 1.0, 1.3])
    sol = vi.SolverSettings(rtol=1e-12, atol=1e-13)
    x0 = vi.simulate(p, periods=1, transient=300, model=MODEL).strobe[-1]
    assert np.count_nonzero(_run(p, x0, solver=sol).events["which"] == 0) == 1

    def step(x):
        return _run(p, x, solver=sol).strobe[-1]
    h = 1e-6
    fd = np.column_stack([(step(x0 + h * e) - step(x0 - h * e)) / (2 * h)
                          for e in np.eye(2)])
    M = an.monodromy(vi.System(p, model=MODEL, solver=sol), x0).matrix
    np.testing.assert_allclose(M, fd, atol=1e-7)


@njit
def _accel_mirror(s, y, p):
    return -p[3] * math.cos(p[4] * s) - 2.0 * p[0] * y[1] - y[0]


@njit
def _free_rhs_mirror(s, y, p, out):
    out[0] = y[1]
    out[1] = _accel_mirror(s, y, p)


def test_a_stop_below_the_coordinate_is_the_mirror_image():
    """Hypothesis: the oscillator mirrored (``z = -x``: the force ``-A cos t``, the stop
    at ``z = -d`` below the coordinate, ``side = -1``) chatters, sticks and is released
    at the same times as the original (to 1e-12), with the mirrored states and impact
    speeds."""
    mirror = vi.Model.from_functions(
        "mirrored impact oscillator",
        *stop_model(_free_rhs_mirror, _free_jac, _accel_mirror, 2, 0, 1, 1, 2, side=-1.0,
                    cache=False),
        terminal=TERMINAL, state_names=("z", "w"), param_names=("zeta", "d", "r", "A", "w"),
        omega_index=4, n_mode=N_MODE)
    run = _run([0.0, -1.0, 0.5, 2.0, 1.0], [-1.0, -0.01])
    image = vi.simulate(np.array([0.0, 1.0, 0.5, 2.0, 1.0]), periods=1,
                        state0=np.array([1.0, 0.01]), model=mirror)
    for key in ("which", "mode_before", "mode_after"):
        np.testing.assert_array_equal(image.events[key], run.events[key])
    np.testing.assert_allclose(image.events["t"], run.events["t"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(image.events["state"], -run.events["state"], atol=1e-12)
    np.testing.assert_allclose(image.strobe, -run.strobe, atol=1e-12)
