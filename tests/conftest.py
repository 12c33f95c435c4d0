"""Shared fixtures: one impacting contact trajectory with tangential damping."""
import pytest

import vibimpact as vi

#: The configuration the analysers' tests use: B = Ec = 0.1, a fixed, known configuration
#: (the first defaults), not whatever the calibration picks.  These tests say so in their
#: docstrings; what the shipped defaults produce is tested in test_shipped_defaults.py
#: (the paper's claims the report says agree) and test_report_sources.py.
MEASURED_AT = dict(B=0.1, Ec=0.1)


def preset(name):
    """A paper preset with B and Ec pinned to :data:`MEASURED_AT`."""
    return vi.presets.get(name).replace(**MEASURED_AT)


@pytest.fixture(scope="session")
def contact_case():
    """fig10 (BT = 0.05) at eta = 1.0, Ec = 0.2: 7 contacts in 4 periods, with its
    reference solution (DOP853 at rtol 1e-14)."""
    p = preset("fig10").replace(eta=1.0, Ec=0.2)
    s0 = vi.simulate(p, periods=1, transient=100, state0=[0.0, 1.0, 0.0, 0.0]).final_state
    ref = vi.simulate(p, periods=4, state0=s0,
                      solver=vi.SolverSettings(rtol=1e-14, atol=1e-16))
    return p, s0, ref


def continued_state(preset, eta_stop, eta_start=1.0, step=0.02, transient=200):
    """State on the impacting branch of ``preset`` at ``eta_stop``, reached by continuation
    from ``eta_start`` (:func:`vibimpact.sweeps.continued_state`)."""
    from vibimpact.sweeps import continued_state as _continued
    return _continued(globals()["preset"](preset), eta_stop, eta_start=eta_start, step=step,
                      transient=transient)


@pytest.fixture(scope="session")
def fig8_chaotic():
    """fig8 at eta = 1.22 on the continued (impacting) branch, at the pinned configuration:
    a chaotic point."""
    p = preset("fig8").replace(eta=1.22)
    return p, continued_state("fig8", 1.22)


def pytest_configure(config):
    """The suite runs with SIGINT as from a terminal (Python's own KeyboardInterrupt
    handler), however it was started: a test run started as a shell script's background
    job inherits SIGINT ignored, and the commands the tests start (and signal) would
    inherit that and rightly ignore the tests' SIGINT.  tests/test_ignored_signals.py
    checks the ignored case on purpose."""
    import signal

    if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)


@pytest.fixture(autouse=True)
def _no_signal_state_leaks(request):
    """Every test leaves SIGINT's and SIGTERM's handlers, the package's signal guard
    (its depth, deferral and the signal it recorded) and ``sys.unraisablehook`` as it
    found them; a test that does not fails, naming what it left, and the state is put
    back so that the tests after it start clean.  A handler or guard left behind turns
    a later test's Ctrl-C into nothing (an ignored SIGINT) or into the guard's
    exception, far from its cause."""
    import signal
    import sys

    from vibimpact.engine.signals import StopWorkersOnSignal as guard

    sigs = (signal.SIGINT, signal.SIGTERM)
    handlers = {s: signal.getsignal(s) for s in sigs}
    hook = sys.unraisablehook
    state = (guard.depth, guard.deferring, guard.pending)
    yield
    left = [f"{signal.Signals(s).name} handler {signal.getsignal(s)!r}" for s in sigs
            if signal.getsignal(s) is not handlers[s]]
    if sys.unraisablehook is not hook:
        left.append(f"sys.unraisablehook {sys.unraisablehook!r}")
    if (guard.depth, guard.deferring, guard.pending) != state:
        left.append(f"signal guard depth/deferring/pending "
                    f"{(guard.depth, guard.deferring, guard.pending)} (was {state})")
    for s, h in handlers.items():
        signal.signal(s, h)
    sys.unraisablehook = hook
    guard.depth, guard.deferring, guard.pending = state
    if left:
        pytest.fail(f"{request.node.nodeid} left: " + "; ".join(left), pytrace=False)
