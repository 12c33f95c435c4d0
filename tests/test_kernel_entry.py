"""Kernel calls typed once per kind of arguments (issue 41, item 1): a Routine asks numba's
dispatcher for the compiled overload once per :func:`type_key` (or per key the boundary
gives) and then calls its entry point; the argument checks still come first."""
import threading
from types import SimpleNamespace

import numpy as np
import pytest
from numba import typeof

from vibimpact._kernel import boundary
from vibimpact._kernel.dispatch import builtin
from vibimpact._kernel.precompiled import Routine, type_key


class _Counting:
    """A dispatcher that counts the calls that reach it (typing and overload lookup)."""

    def __init__(self, jit):
        self.jit, self.calls = jit, 0

    def __call__(self, *args):
        self.calls += 1
        return self.jit(*args)

    def __getattr__(self, name):
        return getattr(self.jit, name)


def _solve_routine():
    """The kernel's linear solve (a Routine with an argument check) and arguments."""
    for routine, args in boundary.array_routine_calls():
        if routine.name == "solve":
            return routine, args
    raise AssertionError("no solve routine")


def test_one_kind_of_arguments_is_typed_once_and_gives_the_dispatchers_result():
    """Hypothesis: repeated calls with arguments of one kind reach numba's dispatcher
    once (the first); the entry point called afterwards returns exactly what the
    dispatcher returns; arguments of another kind (a read-only matrix, which numba types
    apart) reach the dispatcher again, once."""
    routine, args = _solve_routine()
    counting = _Counting(routine.jit)
    fresh = Routine(routine.name, counting)
    a = np.array([[4.0, 1.0], [2.0, 3.0]])
    b = np.array([1.0, 2.0])
    want = routine.jit(a, b)
    outs = [fresh(a.copy(), b.copy()) for _ in range(5)]
    assert counting.calls == 1
    for out in outs:
        assert np.array_equal(np.asarray(out[0] if isinstance(out, tuple) else out),
                              np.asarray(want[0] if isinstance(want, tuple) else want))
    frozen = a.copy()
    frozen.flags.writeable = False
    fresh(frozen, b.copy())
    fresh(frozen, b.copy())
    assert counting.calls == 2


def test_a_wrong_argument_is_refused_after_its_kind_was_cached():
    """Hypothesis: the argument check runs before the cached entry point: once a kind is
    cached, a float32 matrix or one of the wrong shape is still a ValueError naming the
    kernel argument, and nothing reaches the compiled code."""
    routine, _ = _solve_routine()
    counting = _Counting(routine.jit)
    fresh = Routine(routine.name, counting)
    a, b = np.eye(3), np.ones(3)
    fresh(a, b)
    with pytest.raises(ValueError, match="kernel argument"):
        fresh(a.astype(np.float32), b)
    with pytest.raises(ValueError, match="kernel argument"):
        fresh(np.eye(3)[:, :2].copy(), b)
    assert counting.calls == 1


_VALUES = [np.zeros(3), np.zeros(3, np.float32), np.zeros(3, np.int64), np.zeros((2, 3)),
           np.zeros((3, 2)).T, np.zeros((4, 4))[::2, ::2], np.zeros(6)[::2],
           np.asfortranarray(np.zeros((2, 3))), 1, 2**63, -1, 1.0, True, 1 + 2j,
           np.float64(1.0), np.int32(1), (1, 2.0), (1, np.zeros(2)), (np.zeros(2), 1),
           (1, (2.0, np.zeros((1, 1)))), builtin("rotor"), builtin("rotor", True),
           builtin("duffing")]


def _readonly(a):
    a = a.copy()
    a.flags.writeable = False
    return a


@pytest.mark.parametrize("i", range(len(_VALUES) + 1))
def test_equal_keys_are_equal_numba_types(i):
    """Hypothesis: type_key is at least as fine as numba's typeof: values with equal
    keys have equal numba types (checked over every pair of a set of arrays of other
    dtypes, dimensions, memory orders and flags, scalars, nested tuples and built-in
    models), so an entry point found for one key fits every value of that key."""
    values = _VALUES + [_readonly(np.zeros(3))]
    v = values[i]
    for w in values:
        if type_key(v) == type_key(w):
            assert typeof(v) == typeof(w), (v, w)
    assert type_key(builtin("rotor")) == type_key(builtin("rotor", True))
    assert type_key(np.zeros(3)) != type_key(_readonly(np.zeros(3)))


def test_the_run_key_tells_user_models_apart_and_builtin_ones_by_family():
    """Hypothesis: the integration loop's key is one per built-in family (a model and
    its variational equations share the compiled loop) and one per user model's
    functions (two user models with other functions have other keys)."""
    p = np.zeros(3)

    def problem(model):  # what the key reads of a boundary.Problem
        return SimpleNamespace(model=model, p=p)

    def f():
        pass

    def g():
        pass

    rotor = boundary._run_key(problem(builtin("rotor")))
    assert rotor == boundary._run_key(problem(builtin("rotor", True)))
    assert rotor != boundary._run_key(problem(builtin("duffing")))
    assert boundary._run_key(problem((f, f, f))) != boundary._run_key(problem((g, f, f)))


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
