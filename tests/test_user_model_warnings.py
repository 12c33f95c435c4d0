"""Compiling a user model gives no NumbaExperimentalFeatureWarning (issue 32).

The cause was the kernel's tuple of a user model's functions: numba types a tuple whose
first entry is a function as a candidate first-class function tuple and warns each time
("First-class function type feature is experimental"), even where it then calls the
functions as ordinary dispatchers.  The kernel now receives the tuple behind a number
(:func:`vibimpact._kernel.dispatch.kernel_model`).
"""
import math
import warnings

import numpy as np
import pytest
from numba import njit, typeof
from numba.core.errors import NumbaExperimentalFeatureWarning

import vibimpact as vi
from vibimpact._kernel import dispatch


def experimental_warnings(call):
    """``(result, [messages])``: ``call()`` with every NumbaExperimentalFeatureWarning it
    emits recorded (whatever the test run's filters say)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = call()
    return out, [str(w.message) for w in caught
                 if issubclass(w.category, NumbaExperimentalFeatureWarning)]


def _functions():
    """Fresh numba functions of a damped forced linear oscillator (new objects, so that
    numba compiles the kernel for them in the test that asks)."""
    @njit
    def rhs(s, y, p, mode, out):
        out[0] = y[1]
        out[1] = p[2] * math.cos(p[3] * s) - p[0] * y[1] - p[1] * y[0]

    @njit
    def jac(s, y, p, mode, J):
        J[0, 0], J[0, 1], J[1, 0], J[1, 1] = 0.0, 1.0, -p[1], -p[0]

    @njit
    def switches(s, y, p, mode, g):
        g[0] = y[1]

    @njit
    def transition(s, y, p, mode, which):
        return

    @njit
    def init_mode(s, y, p, mode):
        mode[0] = 0

    return rhs, jac, switches, transition, init_mode


def test_the_kernels_user_model_tuple_types_without_the_warning():
    """Hypothesis: the tuple the kernel receives for a user model (plain and variational)
    types without the warning, while the bare tuple of functions, which the kernel used
    to receive, draws it: the cause, checked without compiling the kernel."""
    rhs, jac, switches, transition, _ = _functions()
    plain = (rhs, switches, transition)
    var = (rhs, switches, transition, jac, 2, 1)
    for model in (plain, var):
        _, got = experimental_warnings(lambda model=model: typeof(
            dispatch.kernel_model(model)))
        assert got == []
    _, old = experimental_warnings(lambda: typeof(plain))
    assert old and "First-class function type" in old[0]


@pytest.mark.slow  # a user model compiles its whole kernel (plain and variational)
def test_compiling_a_user_model_emits_no_experimental_feature_warning():
    """Hypothesis: simulating a user model and computing its Lyapunov spectrum (the
    variational kernel) compile without a single NumbaExperimentalFeatureWarning and give
    the linear oscillator's numbers (strobe = closed-form steady state, exponents
    -c/2)."""
    from vibimpact.analysis import Averaging, lyapunov_spectrum

    rhs, jac, switches, transition, init_mode = _functions()
    model = vi.Model.from_functions("linear", rhs, jac, switches, transition, init_mode,
                                    terminal=[0], state_names=("x", "v"),
                                    param_names=("c", "k", "F", "w"), omega_index=3)
    c, k, f, w = 0.3, 1.0, 0.5, 1.7
    p = np.array([c, k, f, w])
    run, got = experimental_warnings(lambda: vi.simulate(p, periods=5, transient=60,
                                                         model=model))
    assert got == []
    a = f / (k - w ** 2 + 1j * c * w)
    np.testing.assert_allclose(run.strobe[:, 0], a.real, atol=1e-9)
    res, got = experimental_warnings(lambda: lyapunov_spectrum(
        vi.System(p, model=model),
        averaging=Averaging(transient=10, min_periods=50, max_periods=50)))
    assert got == []
    np.testing.assert_allclose(res.exponents, [-c / 2, -c / 2], atol=5e-3)
