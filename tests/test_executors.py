"""The engine takes any task and any executor (issue 29, part 3): an executor written
here, in the test, runs ``vi.sweep`` and ``vi.map2d`` with the package's numbers; many
starting states at one parameter point are a task of the same engine; the execution
settings are one validated object; the signatures stay small.

The grids are small but cross fig8's impacting, quasi-periodic and chaotic points near
eta = 1.2, so that equality is a statement about non-trivial data.
"""
import dataclasses
import inspect

import numpy as np
import pytest
import xarray as xr

import vibimpact as vi
from vibimpact.engine import executors, plan
from vibimpact.engine.policy import Continuation, Independent
from vibimpact.sweeps import SweepSettings, analyse_point
from conftest import continued_state, preset

FIG8 = preset("fig8")
GRID = np.round(np.arange(1.16, 1.24 + 1e-9, 0.02), 12)
FAST = SweepSettings(transient_max=100, record=48, lyap_min=40, lyap_max=150)


class Reverse:
    """An executor of the test's own: every job in this process, the jobs and the tasks
    in each job in reverse order, points reported only with their whole task."""

    def __init__(self):
        self.order = []

    def run(self, make_jobs, on_point, on_task):
        for job in reversed(make_jobs(None)):
            for task in reversed(job):
                self.order.append((task.row, task.direction, task.start))
                on_task(task, plan.run_task(task))


def assert_identical_data(a, b):
    """Every data variable and coordinate of ``a`` and ``b`` identical (values, NaN
    included, dtype, dims and attributes)."""
    assert set(a.data_vars) == set(b.data_vars)
    for name in list(a.data_vars) + list(a.coords):
        xr.testing.assert_identical(a[name], b[name])
        x, y = a[name].values, b[name].values
        if x.dtype.kind == "f":
            assert np.array_equal(x, y, equal_nan=True), name
        else:
            assert np.array_equal(x, y), name


def test_an_executor_written_here_gives_the_serial_sweep():
    """Hypothesis: a sweep run by a test's executor that runs its 6 tasks (2 directions x
    3 blocks) in reverse order is bit-identical, variable by variable, to the serial
    sweep; the executor really ran them, last block first."""
    cont = vi.Continuation(blocks=3)
    serial = vi.sweep(FIG8, GRID, direction="both", settings=FAST, continuation=cont)
    mine = Reverse()
    ds = vi.sweep(FIG8, GRID, direction="both", settings=FAST, continuation=cont,
                  execution=vi.Execution(executor=mine))
    assert mine.order == [(0, "down", 3), (0, "down", 2), (0, "down", 0),
                          (0, "up", 3), (0, "up", 2), (0, "up", 0)]
    assert_identical_data(ds, serial)
    assert ds.attrs == serial.attrs


def test_an_executor_written_here_gives_the_serial_map():
    """Hypothesis: a map run by a test's executor (rows in reverse order, one row per
    job) is bit-identical to the serial map, every variable and coordinate."""
    vary = {"kh": [40.0, 120.0]}
    serial = vi.map2d(FIG8, GRID, vary, settings=FAST)
    mine = Reverse()
    ds = vi.map2d(FIG8, GRID, vary, settings=FAST,
                  execution=vi.Execution(executor=mine, task_points=1))
    assert [row for row, _, _ in mine.order] == [1, 0]
    assert_identical_data(ds, serial)
    assert ds.attrs == serial.attrs


def test_many_starting_states_at_one_point_are_tasks_of_the_same_engine():
    """Hypothesis: the census task (three starting states at one parameter point, cut
    into two tasks) gives, through the serial executor and through the test's reversing
    one, exactly the point each state gives on its own; at eta = 1.18 rest and a state
    on the impacting branch land on different attractors, so the states matter."""
    settings = SweepSettings(analyses=("period", "impacts"))
    upper = continued_state("fig8", 1.18)
    states = np.array([np.zeros(4), upper, upper + [1e-3, 0.0, 0.0, 0.0]])
    tasks = plan.plan_states(FIG8, 1.18, states, settings, blocks=2)
    assert [(t.start, t.stop) for t in tasks] == [(0, 2), (2, 3)]
    assert all(isinstance(t.policy, Independent) for t in tasks)
    got = {}
    for executor in (executors.Serial(), Reverse()):
        out = {}
        executor.run(lambda slots: [[t] for t in tasks], None,
                     lambda task, res, out=out: out.update(dict(res)))
        got[type(executor).__name__] = out
    alone = [analyse_point(FIG8.replace(eta=1.18), s, settings).as_dict() for s in states]
    for out in got.values():
        assert sorted(out) == [0, 1, 2]
        for k, res in enumerate(alone):
            for key, value in res.items():
                assert np.array_equal(np.asarray(out[k][key]), np.asarray(value),
                                      equal_nan=np.asarray(value).dtype.kind in "fc"), key
    assert alone[0]["impacts_per_period"] != alone[1]["impacts_per_period"]


def test_the_executor_protocol_is_one_method():
    """Hypothesis: the package's executors and the test's satisfy the documented
    protocol (a ``run`` method), and an object without one is refused by Execution."""
    assert isinstance(executors.Serial(), executors.Executor)
    assert isinstance(executors.Processes(2), executors.Executor)
    assert isinstance(Reverse(), executors.Executor)
    assert not isinstance(object(), executors.Executor)


@pytest.mark.parametrize("kwargs, field", [
    (dict(workers=0), "workers"), (dict(workers=1.5), "workers"),
    (dict(task_points=0), "task_points"), (dict(resume=1), "resume"),
    (dict(resume=True), "resume"), (dict(checkpoint=5), "checkpoint"),
    (dict(progress=5), "progress"), (dict(executor=object()), "executor"),
    (dict(executor=Reverse(), workers=2), "executor"), (dict(scheduler=""), "scheduler")])
def test_execution_is_validated_naming_the_field(kwargs, field):
    """Hypothesis: every bad execution setting is a ValueError (a wrong type also a
    TypeError) whose message names the field."""
    with pytest.raises(ValueError, match=field):
        vi.Execution(**kwargs)


def test_execution_and_policies_are_frozen_and_validated():
    """Hypothesis: Execution, Continuation and Independent cannot be changed after
    construction; blocks and seed_periods below 1 are refused naming them; a path
    checkpoint is kept as a string."""
    run = vi.Execution(checkpoint=__import__("pathlib").Path("a/b"), resume=True)
    assert run.checkpoint == "a/b"
    for obj, name in ((run, "workers"), (Continuation(), "blocks"), (Independent(), "blocks")):
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(obj, name, 2)
    with pytest.raises(ValueError, match="blocks"):
        vi.Continuation(blocks=0)
    with pytest.raises(ValueError, match="seed_periods"):
        vi.Continuation(seed_periods=0)


def test_sweep_and_map2d_take_eight_parameters_or_fewer():
    """Hypothesis: the public signatures have at most 8 parameters, one of them the
    execution and (the sweep) one the continuation policy."""
    for func in (vi.sweep, vi.map2d):
        params = inspect.signature(func).parameters
        assert len(params) <= 8, func.__name__
        assert "execution" in params
    assert "continuation" in inspect.signature(vi.sweep).parameters


@pytest.mark.parametrize("func, keyword, where", [
    ("sweep", "workers", "Execution(workers"), ("sweep", "blocks", "Continuation(blocks"),
    ("sweep", "checkpoint", "Execution(checkpoint"), ("sweep", "command", "attrs"),
    ("map2d", "store", "Execution(checkpoint"), ("map2d", "scheduler", "Execution(sched")])
def test_former_keywords_say_where_the_setting_went(func, keyword, where):
    """Hypothesis: a keyword of the former signatures is a TypeError (also a
    ValueError) naming it and the object that now takes it, before anything runs."""
    args = (FIG8, [1.0]) if func == "sweep" else (FIG8, [1.0], {"kh": [40.0]})
    with pytest.raises(TypeError, match=keyword) as info:
        getattr(vi, func)(*args, **{keyword: 1})
    assert where in str(info.value) and isinstance(info.value, ValueError)


def test_a_wrong_execution_or_policy_is_refused_naming_it():
    """Hypothesis: ``execution`` and ``continuation`` of the wrong kind are refused
    naming the argument."""
    with pytest.raises(ValueError, match="execution"):
        vi.sweep(FIG8, [1.0], execution={"workers": 2})
    with pytest.raises(ValueError, match="execution"):
        vi.map2d(FIG8, [1.0], {"kh": [40.0]}, execution=2)
    with pytest.raises(ValueError, match="continuation"):
        vi.sweep(FIG8, [1.0], continuation="blocks=1")
