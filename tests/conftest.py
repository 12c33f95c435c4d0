"""Shared fixtures: one impacting contact trajectory with tangential damping."""
import numpy as np
import pytest

import vibimpact as vi


@pytest.fixture(scope="session")
def contact_case():
    """fig10 (BT = 0.05) at eta = 1.0, Ec = 0.2: 7 contacts in 4 periods, with its
    reference solution (DOP853 at rtol 1e-14)."""
    p = vi.presets.get("fig10").replace(eta=1.0, Ec=0.2)
    s0 = vi.simulate(p, periods=1, transient=100, state0=[0.0, 1.0, 0.0, 0.0]).final_state
    ref = vi.simulate(p, periods=4, state0=s0, rtol=1e-14, atol=1e-16)
    return p, s0, ref


def continued_state(preset, eta_stop, eta_start=1.0, step=0.02, transient=200):
    """State on the branch reached by sweeping ``eta`` up from ``eta_start`` (from rest).

    With the default B = Ec = 0.1 the impacting upper branch of fig8-fig11 above
    eta ~ 1.18 is reached only by continuation: from rest the rotor stays on the low,
    impactless branch.
    """
    base = vi.presets.get(preset)
    x = None
    for eta in np.arange(eta_start, eta_stop + 1e-9, step):
        x = vi.simulate(base.replace(eta=float(eta)), periods=1, transient=transient,
                        state0=x).final_state
    if abs(eta_stop - eta) > 1e-9:
        x = vi.simulate(base.replace(eta=float(eta_stop)), periods=1, transient=transient,
                        state0=x).final_state
    return x


@pytest.fixture(scope="session")
def fig8_chaotic():
    """fig8 at eta = 1.22 on the continued (impacting) branch: inside the paper's chaotic
    interval (1.21, 1.29)."""
    p = vi.presets.get("fig8").replace(eta=1.22)
    return p, continued_state("fig8", 1.22)
