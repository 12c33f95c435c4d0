"""Validation of the attractor census (issue 30, acceptance): basin fractions of the
forced double-well Duffing oscillator against brute-force SciPy integration of the same
starts; fig11 at eta 1.06 as shipped (the P8 with 11 impacts and the P14 with 21);
serial, parallel and resumed runs bit-identical."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import vibimpact as vi
from vibimpact.census.starts import Box

DELTA, GAMMA, OMEGA = 0.25, 0.1, 1.2
PERIODS = 100


def _system():
    return vi.System(vi.DuffingParams(delta=DELTA, alpha=-1.0, beta=1.0, gamma=GAMMA,
                                      omega=OMEGA))


def _rhs(t, y):
    x, v = y[0::2], y[1::2]
    out = np.empty_like(y)
    out[0::2] = v
    out[1::2] = -DELTA * v + x - x ** 3 + GAMMA * math.cos(OMEGA * t)
    return out


def _same(a, b):
    """Every data variable and coordinate bit-identical (NaN equal to NaN)."""
    assert set(a.variables) == set(b.variables)
    for name in a.variables:
        x, y = a[name].values, b[name].values
        if x.dtype.kind in "OUS":
            assert x.tolist() == y.tolist(), name
        else:
            assert np.array_equal(x, y, equal_nan=x.dtype.kind in "fc"), name


def test_duffing_fractions_agree_with_scipy_fixed_length_integration():
    """Hypothesis: for the forced double well (delta 0.25, gamma 0.1, omega 1.2: one P1
    in each well), 200 random starts in [-2, 2]^2 labelled by the census and by SciPy
    (DOP853, rtol 1e-10, every start integrated a fixed 100 forcing periods and labelled
    by the well -- the sign of x -- of its last stroboscopic point) give basin fractions
    within 3 standard errors, and the same label for at least 98 % of the starts."""
    ds = vi.attractors(_system(), starts=200, seed=3, box=Box([-2, -2], [2, 2]))
    sub = ds.isel(eta=0)
    x = sub.samples.sel(state="x").values
    well = np.sign(x[:, 0])
    assert np.all(np.sign(x) == well[:, None])  # each attractor in one well
    assert sorted(well.tolist()) == [-1.0, 1.0]
    y0 = sub.start_state.values.ravel()
    sol = solve_ivp(_rhs, (0, PERIODS * 2 * math.pi / OMEGA), y0, method="DOP853",
                    rtol=1e-10, atol=1e-10)
    scipy_well = np.sign(sol.y[0::2, -1])
    census_well = well[sub.label.values]
    agree = np.mean(scipy_well == census_well)
    assert agree >= 0.98
    for a, w in enumerate(well):
        f_scipy = np.mean(scipy_well == w)
        assert abs(float(sub.fraction[a]) - f_scipy) <= 3 * float(sub.fraction_se[a])


@pytest.mark.slow
def test_fig11_at_1_06_has_the_p8_and_the_p14():
    """Hypothesis: at fig11, eta = 1.06, with the shipped B = 0.01468 and Ec = 0.059, a
    census of 64 random starts finds both the P8 with 11 impacts per period and the P14
    with 21 (about half the starts each), told by their period and impact count."""
    p = vi.presets.get("fig11")
    assert (p.B, p.Ec) == (0.01468, 0.059)
    ds = vi.attractors(vi.System(p), 1.06, starts=64).isel(eta=0)
    found = {(int(ds.period[a]), float(ds.impacts_per_period[a])): float(ds.fraction[a])
             for a in range(ds.sizes["attractor"])}
    assert found.get((8, 11.0), 0) > 0.2
    assert found.get((14, 21.0), 0) > 0.2


def _basins(execution=None):
    # 16 x 16 starts: rounds of 16, 48 and 192 starts, the last one 3 tasks of 64
    return vi.basins(_system(), grid=(16, 16), plane=("x", "x'"),
                     ranges=((-2, 2), (-2, 2)), execution=execution)


@pytest.mark.slow
def test_serial_and_parallel_basins_are_bit_identical(monkeypatch):
    """Hypothesis: the basins of the forced double well computed in this process and on
    2 worker processes (the last round's 3 tasks do run on a process pool) are the same
    dataset, bit for bit (each round's starts are decided against the library of the
    rounds before, whoever runs them)."""
    from vibimpact.engine import executors

    used, choose = [], executors.choose
    monkeypatch.setattr(executors, "choose",
                        lambda w, n: used.append(choose(w, n)) or used[-1])
    serial = _basins()
    parallel = _basins(vi.Execution(workers=2))
    assert any(isinstance(e, executors.Processes) for e in used)
    _same(serial, parallel)


@pytest.mark.slow
def test_resume_after_lost_entries_is_bit_identical(tmp_path):
    """Hypothesis: a census checkpointed as it goes, then 'interrupted' (some of its
    saved entries deleted) and resumed, recomputes only what is missing and gives the
    same dataset, bit for bit, as an uninterrupted run without a checkpoint."""
    ckpt = tmp_path / "ck"
    first = _basins(vi.Execution(checkpoint=ckpt))
    entries = sorted(p for p in ckpt.iterdir() if p.suffix == ".npz")
    assert len(entries) >= 3
    for p in entries[::2]:
        p.unlink()
    resumed = _basins(vi.Execution(checkpoint=ckpt, resume=True))
    from vibimpact.engine.store import Checkpoint

    loaded = Checkpoint(ckpt).last_resume()["points"]
    assert 0 < loaded < 256  # some loaded, the deleted ones computed again
    plain = _basins()
    _same(first, plain)
    _same(resumed, plain)
