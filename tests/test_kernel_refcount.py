"""The kernel's inner loops run without numba's reference counting (``_kernel.jitopts``)."""
import numba
import numpy as np
import pytest

import vibimpact as vi
from vibimpact._kernel import dispatch, events, integrator, rotor
from vibimpact._kernel.boundary import Method
from vibimpact.models import resolve


def _calls(f, *args, **change):
    """The LLVM IR of ``f`` for these arguments, compiled afresh with ``f``'s own options
    (and ``change``): numba gives no IR for a function loaded from its disk cache, so
    ``f`` itself cannot be inspected once the cache is warm."""
    # with a wrapper for Python (the INNER functions have none; it is not part of the
    # function's own body, whose IR is inspected)
    opts = {k: v for k, v in f.targetoptions.items()
            if k not in ("nopython", "no_cpython_wrapper", "no_cfunc_wrapper")}
    fresh = numba.njit(**dict(opts, **change))(f.py_func)
    fresh(*args)
    ir = fresh.inspect_llvm(fresh.signatures[-1])
    assert f.py_func.__name__ in ir  # real IR, not the placeholder of cached code
    return ir


def _stage_args(model, n):
    p = vi.presets.get("fig8").replace(eta=1.22)
    _, pvec = resolve(p)
    method, A, B, C, E, E3, D, P, order, n_stages = Method.named("dop853").kernel_args()
    y = np.zeros(n)
    y[:4] = (1.01, 0.1, 0.2, 0.3)
    y[4:] = 1.0
    K = np.zeros((16, n))
    mode = np.array([1, 1])
    return (model, pvec, mode, A, B, C, n_stages, True, 0.0, y, 0.01, K, np.empty(n),
            np.empty(n)), (method, E, E3)


@pytest.mark.parametrize("model, n", [(dispatch.builtin("rotor"), 4), (dispatch.builtin("rotor", True), 8)],
                         ids=["rotor", "rotor_variational"])
@pytest.mark.slow  # among the fast suite's longest tests: run on CI's slow line
def test_stage_step_and_event_functions_do_no_reference_counting(model, n):
    """A Runge--Kutta step (with the model dispatch and the rotor's right-hand side, plain
    or variational, inside), its error norm, the event detection over a step and the
    Hertz step cap make no call to NRT_incref or NRT_decref: with the runtime on, numba
    wraps every call it does not inline in an atomic increment and decrement per array
    argument, which cost more than the rotor's right-hand side itself.  A function that
    starts to allocate, or loses its LEAF options, fails here."""
    args, (method, E, E3) = _stage_args(model, n)
    _, pvec, mode, A, B, C, n_stages, fsal, s0, y, h, K, ytmp, y1 = args
    K[0] = 0.1
    irs = {"rk_step": _calls(integrator.rk_step, *args)}
    irs["error_norm"] = _calls(integrator.error_norm, method, E, E3, K, n_stages, h, y, y1,
                               1e-8, 1e-11, 4, 1e3)
    G = np.zeros((5, 3))
    flag = np.zeros(3, dtype=np.int64)
    irs["detect"] = _calls(events.detect, model, pvec, mode, rotor.TERMINAL, s0, h, y, K[0],
                           y1, K[0], G, ytmp, flag, np.zeros(3), np.zeros(3), False)
    irs["step_cap"] = _calls(rotor.step_cap, y, pvec, mode, K[0], True, 1e-8, 1e-11, 4,
                             1e-4, 1e-2)
    for name, ir in irs.items():
        assert "call void @NRT_incref" not in ir, name
        assert "call void @NRT_decref" not in ir, name
    # the check can fail: the same step compiled with the runtime counts references
    assert "call void @NRT_incref" in _calls(integrator.rk_step, *args, _nrt=True)
