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
