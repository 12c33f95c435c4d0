"""The integration loop typed once per model (issue 41, item 1): the boundary asks numba's
dispatcher for the loop's compiled overload once per key (the model's family, a user
model's functions) and then calls its entry point; its argument checks still come first,
and its scratch arrays are made once per thread."""
import threading
from types import SimpleNamespace

import numpy as np
import pytest

import vibimpact as vi
from vibimpact._kernel import boundary
from vibimpact._kernel.dispatch import builtin
from vibimpact._kernel.precompiled import Routine


class _Counting:
    """A dispatcher that counts the calls that reach it (typing and overload lookup)."""

    def __init__(self, jit):
        self.jit, self.calls = jit, 0

    def __call__(self, *args):
        self.calls += 1
        return self.jit(*args)

    def __getattr__(self, name):
        return getattr(self.jit, name)


@pytest.fixture
def counted(monkeypatch):
    """The boundary's integration loop behind a fresh Routine whose dispatcher counts
    the calls that reach it."""
    counting = _Counting(boundary._integrate.jit)
    monkeypatch.setattr(boundary, "_integrate", Routine("integrate", counting))
    return counting


def test_a_model_is_typed_once_and_runs_as_through_the_dispatcher(counted):
    """Hypothesis: runs of one model reach numba's dispatcher once (the first call) and
    give bit for bit the states and counters of runs through the dispatcher; another
    family is typed once more."""
    system = vi.System(vi.presets.get("fig8").replace(eta=1.2))
    runs = [system.simulate(periods=3, transient=2) for _ in range(3)]
    assert counted.calls == 1
    plain = boundary._integrate.jit.jit
    boundary._integrate.entries.clear()
    counted.jit = _Always(plain)
    again = system.simulate(periods=3, transient=2)
    for run in runs:
        assert np.array_equal(run.strobe, again.strobe)
        assert run.counters == again.counters
    counted.jit = plain
    calls = counted.calls
    duffing = vi.DuffingParams(delta=0.3, alpha=1.0, beta=0.0, gamma=0.2, omega=1.3)
    for _ in range(3):
        vi.simulate(duffing, periods=2)
    assert counted.calls - calls == 1


class _Always:
    """A dispatcher whose overloads are never found: every call goes through it."""

    def __init__(self, jit):
        self.jit = jit
        self.overloads = {}

    def __call__(self, *args):
        return self.jit(*args)

    def __getattr__(self, name):
        return getattr(self.jit, name)


def test_a_wrong_argument_is_refused_after_the_model_was_typed(counted):
    """Hypothesis: the boundary's checks run before the cached entry point: once the
    model is typed, a float32 state, a clock of the wrong length or a mode of the wrong
    size is still a ValueError naming the kernel argument, and nothing more reaches the
    compiled code."""
    system = vi.System(vi.presets.get("fig8").replace(eta=1.2))
    system.simulate(periods=1, transient=0)
    held = {}
    way_in = boundary.integrate

    def grab(*a, **k):
        held["call"] = (a, k)
        return way_in(*a, **k)

    boundary.integrate = grab
    try:
        system.simulate(periods=1, transient=0)
    finally:
        boundary.integrate = way_in
    (problem, method, options, y, mode, clock, k_end), k = held["call"][0][:7], \
        held["call"][1]
    reached = counted.calls
    for bad in (dict(y=y.astype(np.float32)), dict(clock=np.zeros(2)),
                dict(mode=np.zeros(5, dtype=np.int64))):
        args = dict(y=y.copy(), mode=mode.copy(), clock=clock.copy(), **{})
        args.update(bad)
        with pytest.raises(ValueError, match="kernel argument"):
            way_in(problem, method, options, args["y"], args["mode"], args["clock"],
                   k_end, **k)
    assert counted.calls == reached


def test_the_run_key_tells_user_models_apart_and_builtin_ones_by_family():
    """Hypothesis: the integration loop's key is one per built-in family (a model and
    its variational equations share the compiled loop), one per user model's functions
    (two user models with other functions have other keys) and apart for a read-only
    parameter vector (numba types it apart)."""
    p = np.zeros(3)

    def problem(model, params=p):  # what the key reads of a boundary.Problem
        return SimpleNamespace(model=model, p=params)

    def f():
        pass

    def g():
        pass

    rotor = boundary._run_key(problem(builtin("rotor")))
    assert rotor == boundary._run_key(problem(builtin("rotor", True)))
    assert rotor != boundary._run_key(problem(builtin("duffing")))
    assert boundary._run_key(problem((f, f, f))) != boundary._run_key(problem((g, f, f)))
    frozen = p.copy()
    frozen.flags.writeable = False
    assert rotor != boundary._run_key(problem(builtin("rotor"), frozen))


def test_each_thread_has_its_own_workspace_made_once():
    """Hypothesis: the integration loop's scratch arrays are made once per thread and
    size (the same object on a second call) and never shared between threads (a data
    race); another size gets another workspace."""
    mine = boundary._scratch(4, 3, 2)
    assert boundary._scratch(4, 3, 2) is mine
    assert boundary._scratch(5, 3, 2) is not mine
    theirs = []
    t = threading.Thread(target=lambda: theirs.append(boundary._scratch(4, 3, 2)))
    t.start()
    t.join()
    assert theirs and theirs[0] is not mine


def _flagged(a, adaptive: bool = True, /, b=0, *, quiet: bool | None = None):
    return a, adaptive, b, quiet


def _flagged_kw(a, loud: bool = False, **more):
    return a, loud, more


@pytest.mark.parametrize("fn,args,kwargs", [
    (_flagged, (1,), {}), (_flagged, (1, "no"), {}), (_flagged, (1, True, 2), {}),
    (_flagged, (1,), {"quiet": "yes"}), (_flagged, (1,), {"quiet": None}),
    (_flagged, (1, True, 2, 3), {}), (_flagged, (1,), {"adaptive": "no"}),
    (_flagged, (1,), {"b": 1, "c": 2}), (_flagged, (1, 1), {"b": 1}),
    (_flagged_kw, (1, "x"), {}), (_flagged_kw, (1,), {"loud": 1}),
    (_flagged_kw, (1,), {"other": "x"}), (_flagged_kw, (1, True), {"loud": True}),
    (_flagged_kw, (), {"a": 1, "loud": None})])
def test_the_flag_check_decides_as_signature_binding(fn, args, kwargs):
    """Hypothesis: checks_flags, which finds the flags of a call without inspect (the
    kernel's hot path goes through it), refuses exactly the calls that inspect's
    bind_partial would have it refuse: a bad flag in a call that fits the signature is
    a TypeError naming it; a call that does not fit is left to the function's own
    TypeError; a good call passes."""
    import inspect

    from vibimpact.base._validate import checks_flags, flag, flag_annotation

    sig = inspect.signature(fn)
    try:
        given = sig.bind_partial(*args, **kwargs).arguments
    except TypeError:
        given = {}
    want = None
    for name, p in sig.parameters.items():
        kind = flag_annotation(p.annotation)
        if kind is not None and name in given and not (kind and given[name] is None):
            try:
                flag(name, given[name])
            except TypeError as exc:
                want = str(exc)
                break
    try:
        got = checks_flags(fn)(*args, **kwargs)
        err = None
    except TypeError as exc:
        got, err = None, str(exc)
    if want is not None:
        assert err == want
    else:
        try:
            expected, fn_err = fn(*args, **kwargs), None
        except TypeError as exc:
            expected, fn_err = None, str(exc)
        assert (got, err) == (expected, fn_err)
