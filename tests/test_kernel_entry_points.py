"""Every way into the compiled kernel is validated: the public functions refuse arrays of
the wrong shape or dtype naming their argument, take any memory order with the same
numbers, and the kernel's own entry points (precompiled or JIT-compiled, neither of which
checks indices) refuse what their loops would read or write past."""
import numpy as np
import pytest

import vibimpact as vi
from vibimpact import analysis as an
from vibimpact._kernel import argcheck, aot_build
from vibimpact._kernel import boundary as kb
from vibimpact._kernel.driver import workspace

P = vi.presets.get("fig8").replace(eta=1.185)
SYSTEM = vi.System(P)
SHORT = an.Averaging(transient=2, min_periods=4, max_periods=4, align=0)

#: public functions that take a state of the model and run the kernel from it
STATE_ENTRIES = {
    "simulate": lambda x: vi.simulate(P, periods=2, state0=x),
    "System.simulate": lambda x: SYSTEM.simulate(periods=2, state0=x),
    "System.monodromy": lambda x: SYSTEM.monodromy(x, 1),
    "Solver": lambda x: vi.Solver(SYSTEM, x).advance(1),
    "Solver.variational": lambda x: vi.Solver.variational(
        SYSTEM, x, SYSTEM.settings(), tangents=4).advance(0, skip=1),
    "monodromy": lambda x: an.monodromy(SYSTEM, x, 1),
    "shoot_periodic_orbit": lambda x: an.shoot_periodic_orbit(SYSTEM, x, max_iter=1),
    "lyapunov_spectrum": lambda x: an.lyapunov_spectrum(SYSTEM, x, averaging=SHORT),
    "largest_lyapunov": lambda x: an.largest_lyapunov(SYSTEM, x, averaging=SHORT),
    "strobe_map_jacobian": lambda x: an.strobe_map_jacobian(SYSTEM, x),
    "floquet_lyapunov": lambda x: an.floquet_lyapunov(SYSTEM, x, max_iter=1),
    "continue_orbit": lambda x: an.continue_orbit(SYSTEM, x, stop=1.19,
                                                  steps=an.Steps(max_points=2)),
}

#: states a user might pass by mistake: (value, error type)
BAD_STATES = {
    "too short": (np.zeros(3), ValueError),
    "too long": (np.zeros(5), ValueError),
    "2-D": (np.zeros((4, 1)), ValueError),
    "complex": (np.zeros(4) + 1e-3j, TypeError),
    "strings of digits": (["0.1", "0", "0", "0"], TypeError),
    "object strings": (np.array(list("abcd"), dtype=object), TypeError),
    "booleans": (np.zeros(4, dtype=bool), TypeError),
    "not finite": (np.array([0.0, np.nan, 0.0, 0.0]), ValueError),
    "a string": ("0000", TypeError),
}


@pytest.mark.parametrize("bad", list(BAD_STATES))
@pytest.mark.parametrize("entry", list(STATE_ENTRIES))
def test_a_state_of_the_wrong_shape_or_dtype_is_refused_naming_state0(entry, bad):
    """Each public function that runs the kernel from a state refuses a state of the
    wrong length or dimension, complex values (whose imaginary part would be dropped),
    strings (also of digits), booleans and non-finite values, with a TypeError or
    ValueError that names state0 -- never a coercion, a kernel error or a write past the
    kernel's arrays."""
    value, error = BAD_STATES[bad]
    with pytest.raises(error, match=r"^state0\b"):
        STATE_ENTRIES[entry](value)


def _state():
    return vi.simulate(P, periods=1, transient=200).final_state


@pytest.mark.parametrize("layout", ["strided", "integers", "list"])
def test_any_memory_order_of_a_state_gives_the_same_numbers(layout):
    """A state given as a strided view, as integers or as a list is copied into a
    C-contiguous float64 array before the kernel sees it: simulate and the monodromy
    give the same bits as from the plain array."""
    x = _state()
    if layout == "integers":
        x = np.array([1, 0, 0, 0])
    wide = np.zeros((4, 2))
    wide[:, 0] = x
    given = {"strided": wide[:, 0], "integers": x.astype(np.int64),
             "list": [float(v) for v in x]}[layout]
    ref = np.asarray(x, dtype=np.float64)
    a, b = vi.simulate(P, periods=3, state0=given), vi.simulate(P, periods=3, state0=ref)
    np.testing.assert_array_equal(a.strobe, b.strobe)
    np.testing.assert_array_equal(SYSTEM.monodromy(given).matrix,
                                  SYSTEM.monodromy(ref).matrix)


def _points():
    rng = np.random.default_rng(1)
    cycle = rng.normal(size=(3, 4))
    return np.vstack([cycle] * 20) + 1e-13 * rng.normal(size=(60, 4))


#: public functions of arrays that run kernel array routines
ARRAY_ENTRIES = {
    "detect_period": (an.detect_period, "points", _points),
    "contraction_rate": (an.contraction_rate, "points", _points),
    "torus_evidence": (an.torus_evidence, "points", _points),
    "extrapolate_limit": (an.extrapolate_limit, "seq", lambda: _points()[:8]),
    "floquet_multipliers": (an.floquet_multipliers, "M",
                            lambda: np.array([[0.5, 0.1], [-0.2, 0.3]])),
    "lyapunov_from_jacobians": (an.lyapunov_from_jacobians, "jacobians",
                                lambda: np.stack([np.array([[1.1, 0.2], [0.0, 0.5]])] * 40)),
    "test01": (an.test01, "series", lambda: np.sin(np.arange(400) * 0.7)),
}


def _result_array(r):
    if r is None or isinstance(r, (int, float, np.ndarray)):
        return np.asarray(r if r is not None else np.nan, dtype=complex)
    fields = [v for v in vars(r).values() if isinstance(v, (int, float, np.ndarray))]
    return np.concatenate([np.ravel(np.asarray(v, dtype=complex)) for v in fields])


@pytest.mark.parametrize("entry", list(ARRAY_ENTRIES))
def test_array_analysers_give_the_same_numbers_in_any_memory_order(entry):
    """A Fortran-ordered copy, a strided view and an integer-valued array are analysed
    as their C-contiguous float64 equal: the kernel routines behind them (which take
    C-contiguous float64 arrays only) get the same numbers either way."""
    fn, _, make = ARRAY_ENTRIES[entry]
    x = make()
    ref = _result_array(fn(x))
    wide = np.repeat(x[..., None], 2, axis=-1)[..., 0]  # a strided view, same values
    for other in (np.asfortranarray(x), wide):
        np.testing.assert_array_equal(_result_array(fn(other)), ref)
    if entry != "test01":
        xi = np.round(x * 8)
        np.testing.assert_array_equal(_result_array(fn(xi.astype(np.int64))),
                                      _result_array(fn(xi)))


@pytest.mark.parametrize("bad", ["complex", "strings", "object", "3-D", "None"])
@pytest.mark.parametrize("entry", list(ARRAY_ENTRIES))
def test_array_analysers_refuse_wrong_dtypes_and_shapes_naming_the_argument(entry, bad):
    """Complex values, strings of digits, objects, an array of too many dimensions and
    None are refused with a TypeError or ValueError naming the argument (complex values
    and strings were coerced before)."""
    fn, name, make = ARRAY_ENTRIES[entry]
    x = make()
    value = {"complex": x + 1e-3j, "strings": x.astype(str), "object": x.astype(object)
             .astype(str).astype(object), "3-D": np.zeros((3, 3, 3, 3)), "None": None}[bad]
    with pytest.raises((TypeError, ValueError), match=rf"^{name}\b"):
        fn(value)


# --- the kernel's own entry points -------------------------------------------------------

def _routine_cases():
    """``(routine, good arguments, {case: bad arguments})`` of each array routine."""
    v, A = np.ones(3), np.eye(3)
    F = np.asfortranarray(np.arange(6.0).reshape(2, 3))
    W = np.zeros((4, 2))
    res, hi, lo, mag = np.empty((4, 2)), np.empty((4, 2)), np.empty((4, 2)), np.empty(4)
    return {
        "dot": (kb.dot, (v, v), {"shape": (v, np.ones(2)), "dtype": (v, np.ones(3, int)),
                                  "order": (v, np.ones(6)[::2])}),
        "matmul": (kb.matmul, (A, A), {"shape": (A, np.eye(2)), "dtype": (A, A + 0j),
                                        "order": (F, np.ones((3, 2)))}),
        "lstsq": (kb.lstsq, (A, A, 1e-10), {"shape": (A, np.eye(2), 1e-10),
                                            "dtype": (A.astype(np.float32), A, 1e-10),
                                            "order": (np.asfortranarray(A), A, 1e-10)}),
        "solve": (kb.solve, (A, v), {"shape": (A, np.ones(4)),
                                     "dtype": (A, np.ones(3, int)),
                                     "order": (np.asfortranarray(A + 1), v)}),
        "eigvals": (kb.eigvals, (A,), {"shape": (np.ones((2, 3)),), "dtype": (A + 0j,),
                                       "order": (np.asfortranarray(A + np.eye(3, k=1)),)}),
        "suffix_lag_residuals": (
            kb.suffix_lag_residuals, (W, 2, res, hi, lo, mag),
            {"shape": (W, 3, res, hi, lo, mag), "dtype": (W.astype(int), 2, res, hi, lo,
                                                          mag),
             "order": (np.asfortranarray(W), 2, res, hi, lo, mag)}),
        "qr_growth": (kb.qr_growth, (np.stack([A] * 2), np.empty((2, 3))),
                      {"shape": (np.stack([A] * 2), np.empty((3, 3))),
                       "dtype": (np.stack([A] * 2).astype(int), np.empty((2, 3))),
                       "order": (np.asfortranarray(np.stack([A] * 2)), np.empty((2, 3)))}),
    }


@pytest.mark.parametrize("case", ["shape", "dtype", "order"])
@pytest.mark.parametrize("name", ["dot", "matmul", "lstsq", "solve", "eigvals",
                                  "suffix_lag_residuals", "qr_growth"])
def test_kernel_array_routines_refuse_wrong_shapes_dtypes_and_orders(name, case):
    """The kernel's array routines (precompiled where possible) check their arguments
    before running: a size their loops would read past, another dtype or a
    non-C-contiguous array is a ValueError naming the kernel argument; the good
    arguments run."""
    routine, good, bad = _routine_cases()[name]
    routine(*good)
    with pytest.raises(ValueError, match="^kernel argument"):
        routine(*bad[case])


def test_every_precompiled_export_is_checked():
    """Every function the install precompiles has an argument check: the array routines
    and every built-in model's initial mode in argcheck.ROUTINES, the integration loop
    where boundary.integrate_args builds its arguments -- so no export is reachable
    unchecked; and the fill compiles the loop of every built-in model."""
    names = set(aot_build.exports())
    loops = {n for n in names if n.startswith("integrate[")}
    assert names - loops <= set(argcheck.ROUTINES)
    assert loops == {f"integrate[{m.kernel_model.family}]" for m in
                     (vi.models.get(name) for name in vi.models.names())}
    for routine, _ in kb.array_routine_calls():
        assert routine.check is argcheck.ROUTINES[routine.name]
    for name in vi.models.names():
        model = vi.models.get(name)
        assert model.init_mode.check is argcheck.ROUTINES[f"{name}_init_mode"]


def _run_args(**changes):
    """A rotor run's kernel arguments through boundary.integrate_args, some replaced."""
    problem = vi.ROTOR.problem(P.as_array())
    method = kb.Method.named("dop853")
    options = kb.Options(rtol=1e-9, atol=1e-12, h_fixed=0.01, max_step=0.1, bound=1e3,
                         event_tol=1e-12, max_steps_per_period=100_000)
    n = changes.pop("n", 4)
    args = dict(problem=problem, method=method, options=options,
                ws=workspace(n, 3, 2),
                y=np.zeros(n), mode=np.zeros(2, dtype=np.int64),
                clock=kb.new_clock(problem, options), k_end=2, k_record=0,
                strobe=np.empty((3, n)), log_arrays=kb.EventLog(64, n, 2).arrays(),
                dense_m=0, dense=np.empty((1, n)), count=kb.counters())
    args.update(changes)
    return args


RUN_CASES = {
    "a state of 3": dict(n=3),
    "a strobe of 3 columns": dict(strobe=np.empty((3, 3))),
    "a Fortran strobe": dict(strobe=np.asfortranarray(np.empty((3, 4)))),
    "a mode of 1": dict(mode=np.zeros(1, dtype=np.int64)),
    "a float mode": dict(mode=np.zeros(2)),
    "an int state": dict(y=np.zeros(4, dtype=np.int64)),
    "a read-only state": dict(y=np.zeros(4)),
    "a short clock": dict(clock=np.zeros(2)),
    "dense rows of 2 columns": dict(dense_m=4, dense=np.empty((9, 2))),
    "a log of 5 state columns": dict(log_arrays=kb.EventLog(64, 5, 2).arrays()),
    "short counters": dict(count=np.zeros(3, dtype=np.int64)),
    "a workspace of another size": dict(ws=workspace(5, 3, 2)),
    "a workspace of fewer switches": dict(ws=workspace(4, 2, 2)),
}


@pytest.mark.parametrize("case", list(RUN_CASES))
def test_the_integration_loop_refuses_arguments_it_would_write_past(case):
    """boundary.integrate_args -- the one place where calls of the (precompiled)
    integration loop are built, for plain, Benettin and install-time calls -- refuses a
    state, mode, clock, sample array, event log or counter array whose size, dtype or
    memory order the loop does not expect; the same arguments with the right sizes
    pass."""
    kb.integrate_args(**_run_args())
    args = _run_args(**RUN_CASES[case])
    if case == "a read-only state":
        args["y"].setflags(write=False)
    with pytest.raises(ValueError, match="^kernel"):
        kb.integrate_args(**args)


def test_a_problem_of_a_builtin_model_must_have_its_sizes():
    """A built-in model's problem with a parameter vector, mode count or switch list of
    another size, or a state size other than the model's, is refused when it is built:
    the rotor's functions index fixed positions."""
    t = vi.ROTOR.terminal
    with pytest.raises(ValueError, match="rotor problem"):
        kb.Problem(vi.ROTOR.kernel_model, t, 2, np.zeros(5), 1.0, n_state=4)
    with pytest.raises(ValueError, match="rotor problem"):
        kb.Problem(vi.ROTOR.kernel_model, t, 1, P.as_array(), 1.0, n_state=4)
    with pytest.raises(ValueError, match="rotor problem"):
        kb.Problem(vi.ROTOR.kernel_model, t, 2, P.as_array(), 1.0, n_state=2)
    with pytest.raises(ValueError, match="omega"):
        kb.Problem(vi.ROTOR.kernel_model, t, 2, P.as_array(), float("nan"), n_state=4)
