"""The orbit hunt (issue 30, part 3): multi-start Newton shooting for periodic orbits,
deduplication, multipliers, existence intervals, the file, the query and the command.

References computed here: the Floquet multipliers of a found orbit against a monodromy
matrix by central finite differences of SciPy's ``solve_ivp`` flow, and the orbit's
periodicity under that flow (the forced Duffing oscillator is smooth, so the flow's
Jacobian is the monodromy matrix).
"""
import contextlib
import io as stdio
import subprocess
import sys

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import vibimpact as vi
from vibimpact.cli import main
from vibimpact.orbits import (find_orbit, hunt_orbits, hunt_to_dataset, read_orbits,
                              same_orbit, write_orbits)

#: the chaotic forced double-well Duffing oscillator (Guckenheimer & Holmes 1983,
#: sec. 2.2): its periodic orbits are saddles embedded in the attractor
CHAOTIC = vi.DuffingParams(delta=0.3, alpha=-1.0, beta=1.0, gamma=0.3, omega=1.2)


def run(*args):
    """``vibimpact ARGS`` in this process: ``(status, stdout, stderr)``."""
    out, err = stdio.StringIO(), stdio.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main([str(a) for a in args])
        except SystemExit as exc:
            rc = exc.code
    return rc, out.getvalue(), err.getvalue()


def _flow(p, x, t_end):
    """SciPy's solution of the Duffing equation from ``x`` at t = 0 to ``t_end``."""
    def rhs(t, y):
        return [y[1], -p.delta * y[1] - p.alpha * y[0] - p.beta * y[0] ** 3
                + p.gamma * np.cos(p.omega * t)]
    sol = solve_ivp(rhs, (0.0, t_end), x, method="DOP853", rtol=1e-12, atol=1e-12)
    return sol.y[:, -1]


@pytest.fixture(scope="module")
def chaotic_p1():
    """The P1 (and P2) hunt of the chaotic Duffing oscillator, not continued."""
    return hunt_orbits(CHAOTIC, periods=[1, 2], random=6, seed=1, continuation=False)


def test_found_orbit_agrees_with_scipy_flow_and_finite_difference_monodromy(chaotic_p1):
    """Hypothesis: every P1 orbit the hunt finds is a fixed point of SciPy's period map
    (to 1e-7), and its Floquet multipliers agree with the eigenvalues of a monodromy
    matrix by central finite differences of SciPy's flow (to 1e-5 relative); at least
    one is a saddle (a multiplier outside the unit circle) and marked unstable."""
    T = 2 * np.pi / CHAOTIC.omega
    p1 = [o for o in chaotic_p1.orbits if o.period == 1]
    assert p1
    for o in p1:
        x = o.state
        assert np.abs(_flow(CHAOTIC, x, T) - x).max() < 1e-7
        h = 1e-6
        M = np.column_stack([(_flow(CHAOTIC, x + h * e, T) - _flow(CHAOTIC, x - h * e, T))
                             / (2 * h) for e in np.eye(2)])
        ref = np.linalg.eigvals(M)
        ref = ref[np.argsort(-np.abs(ref))]
        assert np.allclose(np.abs(o.multipliers), np.abs(ref), rtol=1e-5)
        assert np.isclose(np.prod(o.multipliers).real, np.linalg.det(M), rtol=1e-5)
        assert o.stable == (o.abs_max < 1.0)
    saddles = [o for o in p1 if not o.stable]
    assert saddles and all(o.abs_max > 1.0 for o in saddles)
    assert all(o.label.startswith("P1, unstable") for o in saddles)


def test_an_orbit_seeded_at_two_phases_is_one_orbit(chaotic_p1):
    """Hypothesis: a P2 orbit given as seeds at both points of its cycle is found once,
    with the same canonical cycle (to 1e-8) as from either point alone; shot for
    period 4 from its point, it is reported as the P2 (minimal period), not a P4."""
    p2 = [o for o in chaotic_p1.orbits if o.period == 2][0]
    both = hunt_orbits(CHAOTIC, [2], seeds=p2.cycle, random=0, continuation=False)
    mine = [o for o in both.orbits if same_orbit(o.cycle, p2.cycle, 1e-6)]
    assert len(mine) == 1
    for k in range(2):
        alone = hunt_orbits(CHAOTIC, [2], seeds=p2.cycle[k], random=0, continuation=False)
        hit = [o for o in alone.orbits if same_orbit(o.cycle, p2.cycle, 1e-6)]
        assert len(hit) == 1 and np.abs(hit[0].cycle - mine[0].cycle).max() < 1e-8
    four = hunt_orbits(CHAOTIC, [4], seeds=p2.cycle[1], random=0, continuation=False)
    first = [o for o in four.orbits if o.seed == 0 and same_orbit(o.cycle, p2.cycle, 1e-6)]
    assert first and first[0].period == 2 and first[0].found_as == 4
    for a in range(len(both.orbits)):  # no two orbits of a hunt are one
        for b in range(a):
            assert not same_orbit(both.orbits[a].cycle, both.orbits[b].cycle)


def test_same_seed_same_bits_and_another_seed_other_starts(tmp_path):
    """Hypothesis: two hunts with the same seed give identical datasets (timings
    aside); another seed draws other random states, all in the documented box."""
    kw = dict(periods=[1], random=3, continuation=False)
    a = hunt_to_dataset(hunt_orbits(CHAOTIC, seed=5, **kw), vi.System(CHAOTIC))
    b = hunt_to_dataset(hunt_orbits(CHAOTIC, seed=5, **kw), vi.System(CHAOTIC))
    c = hunt_orbits(CHAOTIC, seed=6, **kw)
    for name in a.data_vars:
        np.testing.assert_array_equal(a[name].values, b[name].values)
    assert not np.array_equal(a["seed_state"].values, c.seeds)
    assert np.all(np.abs(c.seeds) <= 1.0)
    rotor = vi.orbits.random_seeds(vi.ROTOR, 200, seed=0)
    assert np.all(np.hypot(rotor[:, 0], rotor[:, 1]) <= 1.0)
    assert np.all(np.abs(rotor[:, 2:]) <= 1.0)


def test_intervals_file_and_query(tmp_path):
    """Hypothesis: a stable P1 of the weakly forced Duffing oscillator, continued in
    omega within +-0.05, exists and is stable over the whole window (no fold there:
    its branch's |mu|max stays below 1); the file round-trips; find_orbit answers yes
    for it, with where, and no for a P5, naming the orbits found instead."""
    p = vi.DuffingParams(gamma=0.1)
    hunt = hunt_orbits(p, [1], random=4, window=0.05)
    stable = [o for o in hunt.orbits if o.stable]
    assert stable
    for o in stable:
        e = o.extent
        assert e.lo == pytest.approx(1.15, abs=1e-4)
        assert e.hi == pytest.approx(1.25, abs=1e-4)
        assert e.lo_reason == e.hi_reason == "end of the window"
        assert len(e.stable) == 1 and e.stable[0] == pytest.approx((e.lo, e.hi))
        assert np.all(e.abs_max < 1.0) and np.all(np.diff(e.values) > 0)
    path = tmp_path / "orbits.nc"
    write_orbits(hunt_to_dataset(hunt, vi.System(p)), path)
    ds = read_orbits(path)
    assert ds.sizes["orbit"] == len(hunt.orbits)
    yes = find_orbit(ds, period=1, stable=True, within=(1.16, 1.24))
    assert yes.found and len(yes.orbits) == len(stable)
    assert yes.where[0][0][0] <= 1.16 + 0.02 and yes.where[0][0][1] >= 1.24 - 0.02
    no = find_orbit(ds, period=5, impacts=0)
    assert not no.found and "no P5" in str(no) and "#0" in str(no)


def test_bad_input_names_the_argument():
    """Hypothesis: bad arguments raise ValueError naming the argument."""
    for kwargs, name in [(dict(periods=0), "periods"), (dict(periods=[]), "periods"),
                         (dict(random=-1), "random"), (dict(seed=-2), "seed"),
                         (dict(seeds=[[0.0, 0.0, 1.0]]), "seeds"),
                         (dict(window=0.0), "window"), (dict(max_iter=0), "max_iter"),
                         (dict(periods=[1], record=0), "record"),
                         (dict(box=[[0, 1]]), "box")]:
        with pytest.raises(ValueError, match=name):
            hunt_orbits(CHAOTIC, **{"periods": [1], "random": 0, **kwargs})
    ds = hunt_to_dataset(hunt_orbits(CHAOTIC, [1], random=0, continuation=False),
                         vi.System(CHAOTIC))
    for kwargs, name in [(dict(period=0), "period"), (dict(impacts=-1), "impacts"),
                         (dict(within=(2.0, 1.0)), "within"), (dict(arcs=3), "arcs")]:
        with pytest.raises(ValueError, match=name):
            find_orbit(ds, **kwargs)
    with pytest.raises(ValueError, match="ds"):
        find_orbit(ds.drop_vars("period").assign_attrs(title="x"))


def test_cli_bad_input_is_one_line_exit_2(tmp_path):
    """Hypothesis: bad input to 'vibimpact orbits' exits 2 with one line on stderr and
    writes nothing."""
    out = tmp_path / "o.nc"
    for args in (["--period", "0"], ["--period", "x"], ["--period", "3:1"],
                 ["--random", "-1"], ["--window", "0"], ["--preset", "nope"],
                 ["--seeds", tmp_path / "missing.nc"], ["--plot", tmp_path / "a.nc"],
                 ["--dpi", "100"], ["--preset", "soft-impact", "--set", "zeta=-1"]):
        rc, _, err = run("orbits", *args, "-o", out)
        assert rc == 2, (args, err)
        assert len(err.strip().splitlines()) == 1 and err.startswith("vibimpact: error:")
        assert not out.exists()


def test_cli_writes_file_table_and_plot(tmp_path):
    """Hypothesis: 'vibimpact orbits' on the soft-impact oscillator writes a file whose
    orbits are the API's for the same arguments, prints one table row per orbit, and
    draws the plot; '--help' imports nothing heavy and its default random count is the
    API's."""
    out, png = tmp_path / "o.nc", tmp_path / "o.png"
    rc, text, err = run("orbits", "--preset", "soft-impact", "--period", "1:2",
                        "--random", "4", "--no-continue", "-o", out, "--plot", png)
    assert rc == 0, err
    ds = read_orbits(out)
    api = hunt_orbits(vi.presets.get("soft-impact"), [1, 2], random=4,
                      continuation=False)
    assert list(ds["label"].values) == [o.label for o in api.orbits]
    np.testing.assert_array_equal(ds["orbit_point"].values[:, 0],
                                  [o.state for o in api.orbits])
    for label in ds["label"].values:
        assert label in text
    assert png.stat().st_size > 0
    from vibimpact.cli.orbits import DEFAULT_RANDOM
    from vibimpact.orbits.hunt import DEFAULT_RANDOM as API_RANDOM

    assert DEFAULT_RANDOM == API_RANDOM
    code = ("import sys\nfrom vibimpact.cli import main\ntry:\n    main(['orbits', "
            "'--help'])\nexcept SystemExit as e:\n    rc = e.code\nheavy = [m for m in "
            "('numba', 'numpy', 'xarray', 'matplotlib') if m in sys.modules]\n"
            "print('HEAVY', heavy, 'RC', rc)\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       timeout=60)
    assert "HEAVY [] RC 0" in r.stdout, r.stderr


@pytest.mark.slow
def test_fig11_hunt_finds_the_p8_with_11_impacts_and_the_p14_from_random_seeds():
    """Hypothesis (issue 30): at fig11, eta = 1.06 (B, Ec as shipped), the hunt from
    random seeds alone finds the stable P8 with 11 impacts and the stable P14 with 21
    impacts that 120 random simulations find as attractors, with |mu|max < 1."""
    p = vi.presets.get("fig11").replace(eta=1.06)
    hunt = hunt_orbits(p, range(1, 17), continuation=False)
    assert hunt.n_user == 0
    labels = [o.label for o in hunt.orbits]
    assert "P8, 11 impacts, stable" in labels, labels
    assert "P14, 21 impacts, stable" in labels, labels
    for o in hunt.orbits:
        assert o.stable == (o.abs_max < 1.0)


def test_a_census_seeds_the_hunt_with_its_attractors_only():
    """Hypothesis: a census file given as seeds contributes exactly its attractors'
    representative states (not its thousands of starts and samples), and the hunt seeded
    with them finds every periodic attractor of the census again as a stable orbit."""
    from vibimpact.orbits import seeds_from_dataset

    system = vi.System(vi.DuffingParams(delta=0.3, alpha=-1.0, beta=1.0, gamma=0.1,
                                        omega=1.2))
    census = vi.attractors(system, starts=24, box=vi.census.Box([-2, -2], [2, 2]))
    seeds = seeds_from_dataset(census, 2)
    reps = census.representative.values.reshape(-1, 2)
    np.testing.assert_array_equal(seeds, reps[np.all(np.isfinite(reps), axis=1)])
    hunt = hunt_orbits(system, [1], seeds=seeds, random=0, continuation=False)
    stable = [o for o in hunt.orbits if o.stable]
    for rep in seeds:
        assert any(np.abs(o.cycle - rep).max() < 1e-6 for o in stable)


def test_an_orbit_rolling_on_the_retainer_is_labelled_permanent_contact():
    """Hypothesis: at fig10, eta = 1.4, a period-1 orbit without impacts that stays in
    contact (R > 1 along the whole period, checked on a dense run) is labelled
    "permanent contact", and the impactless one (R < 1 throughout) "0 impacts": the two
    are different orbits, not one orbit counted twice."""
    system = vi.System(vi.presets.get("fig10").replace(eta=1.4))
    seeds = np.array([[0.5213919, -0.88028323, 1.1388129, 0.65084732],
                      [-0.12037702, 0.29749812, 0.00360356, -0.16846478]])
    hunt = hunt_orbits(system, [1], seeds=seeds, random=0, continuation=False)
    labels = {}
    for o in hunt.orbits:
        run = vi.simulate(system, periods=1, state0=o.cycle[0], dense=200)
        r = np.hypot(run.dense[:, 0], run.dense[:, 1])
        labels[o.label] = (r.min(), r.max())
    assert labels["P1, permanent contact, stable"][0] > 1.0
    assert labels["P1, 0 impacts, stable"][1] < 1.0


def test_continuations_on_workers_and_resumed_are_the_serial_ones(tmp_path):
    """Hypothesis: the orbits' continuations run as engine tasks: on 2 worker processes,
    and resumed from a checkpoint that lost an entry, they give the serial hunt's
    existence and stability intervals bit for bit."""
    system = vi.System(vi.DuffingParams(delta=0.3, alpha=-1.0, beta=1.0, gamma=0.1,
                                        omega=1.2))
    serial = hunt_orbits(system, [1], random=6)
    parallel = hunt_orbits(system, [1], random=6, execution=vi.Execution(workers=2))
    ckpt = tmp_path / "ck"
    hunt_orbits(system, [1], random=6, execution=vi.Execution(checkpoint=ckpt))
    entries = sorted(ckpt.glob("*.npz"))
    assert len(entries) == len(serial.orbits) >= 2
    entries[0].unlink()
    resumed = hunt_orbits(system, [1], random=6,
                          execution=vi.Execution(checkpoint=ckpt, resume=True))
    for other in (parallel, resumed):
        assert len(other.orbits) == len(serial.orbits)
        for a, b in zip(serial.orbits, other.orbits):
            ea, eb = a.extent, b.extent
            assert (ea.lo, ea.hi, ea.lo_reason, ea.hi_reason, ea.stable,
                    ea.same_impacts) == (eb.lo, eb.hi, eb.lo_reason, eb.hi_reason,
                                         eb.stable, eb.same_impacts)
            for name in ("values", "stable_points", "impacts", "abs_max"):
                assert np.array_equal(getattr(ea, name), getattr(eb, name)), name


def test_the_file_says_which_orbit_rolls_on_the_retainer(tmp_path):
    """Hypothesis: an orbit file keeps the permanent-contact flag (1 for the rolling P1
    of fig10 at eta = 1.4, 0 for the impactless one), and it survives the NetCDF round
    trip."""
    system = vi.System(vi.presets.get("fig10").replace(eta=1.4))
    seeds = np.array([[0.5213919, -0.88028323, 1.1388129, 0.65084732],
                      [-0.12037702, 0.29749812, 0.00360356, -0.16846478]])
    hunt = hunt_orbits(system, [1], seeds=seeds, random=0, continuation=False)
    ds = hunt_to_dataset(hunt, system)
    write_orbits(ds, tmp_path / "o.nc")
    back = read_orbits(tmp_path / "o.nc")
    flags = dict(zip(back["label"].values, back["permanent_contact"].values))
    assert flags == {"P1, permanent contact, stable": 1, "P1, 0 impacts, stable": 0}
