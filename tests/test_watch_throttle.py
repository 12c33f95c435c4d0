"""The watch of child processes against a throttle (review of issue 32): a child counts
as stopped only when its state is ``T`` (or ``t``) at every check of the grace *and* its
CPU time did not advance since the first of them.

``psutil`` is replaced by a fake whose process answers a scripted state and CPU time at
each look, and the watch's clock by a list the test advances: no process, no sleep, no
race.
"""
import sys
from types import SimpleNamespace

import pytest

from vibimpact.engine import watch as w

PID = 4242


class FakePsutil:
    """A ``psutil`` stand-in: ``Process(PID)`` answers, at its n-th look, the n-th
    ``(status, cpu seconds)`` of ``script`` (the last one from then on)."""

    STATUS_STOPPED, STATUS_TRACING_STOP, STATUS_RUNNING = "stopped", "tracing-stop", "running"

    class Error(Exception):
        pass

    def __init__(self, script):
        self.script, self.looks = list(script), 0

    def Process(self, pid):
        status, cpu = self.script[min(self.looks, len(self.script) - 1)]
        self.looks += 1
        if status == "gone":
            raise self.Error("no such process")
        return SimpleNamespace(status=lambda: status,
                               cpu_times=lambda: SimpleNamespace(user=cpu, system=0.0))


@pytest.fixture
def clock(monkeypatch):
    now = [100.0]
    monkeypatch.setattr(w.time, "monotonic", lambda: now[0])
    return now


def _watch(monkeypatch, script):
    monkeypatch.setitem(sys.modules, "psutil", FakePsutil(script))
    return w.Watch(lambda: {PID: "a worker process"}, grace=1.0)


def _checks(watch, clock, n, step=0.25):
    """``n`` checks ``step`` seconds apart; the number made before StoppedChild."""
    for k in range(n):
        try:
            watch.check()
        except w.StoppedChild:
            return k
        clock[0] += step
    return n


def test_a_throttled_child_seen_stopped_at_every_check_is_not_lost(monkeypatch, clock):
    """Hypothesis: a child caught stopped at every check for ten graces (a throttle at a
    tenth of the time can be) whose CPU time advances between checks is never counted
    stopped: the watch starts its grace again whenever the CPU time moved."""
    script = [("stopped", 0.01 * k) for k in range(60)]
    assert _checks(_watch(monkeypatch, script), clock, 40) == 40


def test_a_child_alternating_stopped_and_running_is_not_lost(monkeypatch, clock):
    """Hypothesis: a child seen stopped and running at alternate checks (its CPU time
    unchanged, as a throttle's short stops between reads can show it) is forgotten at
    every running look and never reported, however long the run waits."""
    script = [("stopped" if k % 2 == 0 else "running", 3.0) for k in range(60)]
    assert _checks(_watch(monkeypatch, script), clock, 40) == 40


@pytest.mark.parametrize("state", ["stopped", "tracing-stop"])
def test_a_child_stopped_without_cpu_time_for_the_grace_is_lost(monkeypatch, clock, state):
    """Hypothesis: a child in state T (SIGSTOP) or t (a tracer's stop) whose CPU time does
    not move is reported once a whole grace passed since it was first seen so, not
    before: checks at 0, 0.25, 0.5, 0.75 pass, the one at 1.0 raises, naming it."""
    watch = _watch(monkeypatch, [(state, 7.5)])
    assert _checks(watch, clock, 10) == 4
    with pytest.raises(w.StoppedChild, match="a worker process was stopped"):
        watch.check()


def test_cpu_time_that_moves_once_restarts_the_grace(monkeypatch, clock):
    """Hypothesis: a stopped child whose CPU time moves once (it ran between two checks)
    gets a whole new grace from that check: first seen at 0, ran before 0.5, then still:
    reported at 1.5, not at 1.0."""
    script = [("stopped", 1.0), ("stopped", 1.0), ("stopped", 1.2)] + [("stopped", 1.2)] * 10
    assert _checks(_watch(monkeypatch, script), clock, 20) == 6


def test_a_gone_or_running_child_is_not_stopped(monkeypatch):
    """Hypothesis: is_stopped is False for a running child and for one psutil cannot
    read (gone), True for states T and t."""
    for status, expect in [("running", False), ("gone", False), ("stopped", True),
                           ("tracing-stop", True)]:
        monkeypatch.setitem(sys.modules, "psutil", FakePsutil([(status, 0.0)]))
        assert w.is_stopped(PID) is expect, status
