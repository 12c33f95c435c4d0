"""The kernel compiled ahead of time at install time (vibimpact._kernel.precompiled).

The precompiled functions must be used where they apply, give the bits numba's JIT gives,
be refused when they were built from other sources, compilers or processors, and never
receive arguments of other types (they do not check them: the JIT runs those calls).
"""
import pickle

import numpy as np
import pytest

import vibimpact as vi
from vibimpact._kernel import aot_build
from vibimpact._kernel import boundary as kb
from vibimpact._kernel import precompiled


def _fig8(eta):
    return vi.presets.get("fig8").replace(eta=eta)


def test_install_built_a_precompiled_kernel_that_loads_here():
    """The install (setup.py) built the extension module for these sources, this numba
    and this processor: every export is loaded."""
    assert precompiled.status() == "loaded"
    for name in aot_build.exports():
        assert precompiled.available(name), name


def _equal(a, b):
    """Bit equality of two nested structures of arrays, numbers and dicts."""
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_equal(a[k], b[k]) for k in a)
    if isinstance(a, (tuple, list)):
        return len(a) == len(b) and all(_equal(x, y) for x, y in zip(a, b))
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype.names:  # structured (the impacts table): field by field
        return a.dtype == b.dtype and all(_equal(a[f], b[f]) for f in a.dtype.names)
    if a.dtype.kind not in "fc":
        return np.array_equal(a, b)
    return np.array_equal(a, b, equal_nan=True)


class _Spy:
    """Stands in for boundary._integrate: records whether each call ran the precompiled
    function (``jit=True``: runs the JIT-compiled one instead)."""

    def __init__(self, routine, jit=False):
        self.routine, self.use_jit, self.precompiled = routine, jit, []

    def __call__(self, *args):
        fn = self.routine.jit if self.use_jit else self.routine.pick(args)
        self.precompiled.append(fn is not self.routine.jit)
        return fn(*args)


def _run(monkeypatch, jit, fn):
    spy = _Spy(kb._integrate, jit)
    with monkeypatch.context() as m:
        m.setattr(kb, "_integrate", spy)
        return fn(), spy.precompiled


@pytest.mark.parametrize("eta,method", [(1.2, "dop853"), (1.13, "dp5"), (1.3, "rk4")])
def test_precompiled_integrate_gives_the_bits_of_the_jit(monkeypatch, eta, method):
    """A rotor run with impacts (chaotic at 1.2, P1 at 1.13, permanent contact at 1.3)
    gives bit-identical stroboscopic and dense samples, events, counters and final state
    through the precompiled integration loop and through numba's JIT-compiled one; every
    call of the package picks the precompiled one."""
    def run():
        r = vi.simulate(_fig8(eta), periods=20, transient=10, dense=16,
                        state0=[1.1, 0.0, 0.0, 1.3],
                        solver=vi.SolverSettings(method=method))
        return (r.strobe, r.dense, r.events, r.counters, r.final_state, r.impacts)

    (a, picked), (b, _) = _run(monkeypatch, False, run), _run(monkeypatch, True, run)
    assert picked and all(picked)
    assert _equal(a, b)
    assert a[3]["events"] > 0


def test_precompiled_benettin_loop_gives_the_bits_of_the_jit(monkeypatch):
    """The Lyapunov spectrum (variational rotor with saltation matrices, QR after each
    period: the Benettin mode of the same loop) is bit-identical both ways, and the
    variational calls pick the precompiled loop too."""
    def run():
        res = vi.analysis.lyapunov_spectrum(vi.System(_fig8(1.2)),
                                            state0=[1.1, 0.0, 0.0, 1.3],
                                            averaging=vi.analysis.Averaging(
                                                transient=3, min_periods=8,
                                                max_periods=8, block=4, align=2),
                                            floquet=False)
        return res.exponents, res.history

    (a, picked), (b, _) = _run(monkeypatch, False, run), _run(monkeypatch, True, run)
    assert picked and all(picked)
    assert _equal(a, b)


def test_precompiled_array_routines_give_the_bits_of_the_jit():
    """dot, matmul, lstsq, solve, eigvals and the recurrence residuals give the same bits
    precompiled and JIT-compiled, on random inputs."""
    rng = np.random.default_rng(3)
    a = rng.standard_normal((5, 5))
    b = rng.standard_normal((5, 3))
    v = rng.standard_normal(5)
    x = rng.standard_normal((12, 4))
    calls = [(kb.dot, (v, v)), (kb.matmul, (a, b)), (kb.lstsq, (a, b, 1e-12)),
             (kb.solve, (a, v)), (kb.eigvals, (a,))]
    for fn, args in calls:
        assert fn.pick(args) is not fn.jit, fn
        got, want = fn(*args), fn.jit(*args)
        for g, w in zip(got if isinstance(got, tuple) else (got,),
                        want if isinstance(want, tuple) else (want,)):
            assert np.array_equal(g, w), fn
    outs = []
    for f in (kb.suffix_lag_residuals, kb.suffix_lag_residuals.jit):
        res, hi, lo, mag = (np.empty((12, 3)), np.empty((12, 4)), np.empty((12, 4)),
                            np.empty(12))
        f(x, 3, res, hi, lo, mag)
        outs.append((res, hi, lo, mag))
    for u, w in zip(*outs):
        assert np.array_equal(u, w)


@pytest.mark.parametrize("args", [
    (np.arange(4), np.arange(4)),                       # int64: other dtype
    (np.ones(8)[::2], np.ones(4)),                      # strided view: other layout
    (np.ones((2, 2)), np.ones((2, 2))),                 # 2-D: other dimension
    (np.ones(4, dtype=np.float32), np.ones(4)),         # float32
])
def test_arguments_of_other_types_run_the_jit(args):
    """A call whose argument types differ from the precompiled signature in dtype,
    layout or dimension is given to the JIT-compiled function (the precompiled one would
    read the memory as float64 C arrays)."""
    assert kb.dot.pick(args) is kb.dot.jit


def test_a_foreign_build_is_refused_with_its_reason():
    """A description from other kernel sources, other numba/llvmlite versions or another
    processor is refused, each with a reason naming what differs; the right one is
    accepted."""
    good = {"sources": precompiled.current_digest(), "versions": precompiled.versions(),
            "host": precompiled.host()}
    assert precompiled.mismatch(good) is None
    assert "sources" in precompiled.mismatch(dict(good, sources="0" * 64))
    assert "numba" in precompiled.mismatch(dict(good, versions={"numba": "0.1",
                                                                "llvmlite": "0.1"}))
    other = dict(good["host"], features=good["host"]["features"].replace("+", "-"))
    assert "processor" in precompiled.mismatch(dict(good, host=other))
    assert precompiled.mismatch([1, 2]) is not None


def test_turned_off_by_the_environment(monkeypatch):
    """VIBIMPACT_PRECOMPILED=0 loads nothing and says so."""
    monkeypatch.setenv(precompiled.ENV, "0")
    module, exports, reason = precompiled._load()
    assert module is None and exports == {} and precompiled.ENV in reason


def test_routine_pickles_to_the_same_routine():
    """A kernel routine travels to worker processes (pickled) and runs there the same."""
    r = pickle.loads(pickle.dumps(kb.dot))
    v = np.arange(3.0)
    assert r.name == "dot" and r(v, v) == kb.dot(v, v) == 5.0
    init = pickle.loads(pickle.dumps(vi.ROTOR.init_mode))
    assert init.name == "rotor_init_mode"
