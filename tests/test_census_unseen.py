"""How much basin a census may have missed: the Good–Turing estimate against mixtures whose
missing mass is known, the resolution of N starts, and the census' ``until_unseen``
rounds and its printed table."""
import re

import numpy as np
import pytest

import vibimpact as vi
from vibimpact.census import Box
from vibimpact.census import census as C
from vibimpact.census.unseen import good_turing, resolution, unseen_mass
from vibimpact.cli import main

DOUBLE_WELL = vi.DuffingParams(delta=0.3, alpha=-1.0, beta=1.0, gamma=0.0, omega=1.0)
BOX = Box([-2.0, -2.0], [2.0, 2.0])

#: basin fractions of a constructed census: two large basins and many small ones, as a
#: multistable rotor has (the small ones are what a census misses)
MIXTURE = np.r_[0.55, 0.38, 0.03, 0.02, np.full(10, 0.002)]


def _draws(p, n, reps, seed):
    rng = np.random.default_rng(seed)
    return [np.bincount(rng.choice(p.size, size=n, p=p / p.sum()), minlength=p.size)
            for _ in range(reps)]


@pytest.mark.parametrize("n", [50, 200, 1000])
def test_good_turing_mean_is_the_missing_mass_of_one_start_fewer(n):
    """Hypothesis: for multinomial starts, E[f1 / N] = sum p (1 - p)^(N - 1) exactly (the
    mean missing mass of N - 1 starts); over 4000 simulated censuses of a known mixture
    the mean Good–Turing estimate is within 4 standard errors of it, and within 4
    standard errors + the one-start difference of the true missing mass of N starts."""
    p = MIXTURE / MIXTURE.sum()
    counts = _draws(p, n, 4000, seed=n)
    gt = np.array([good_turing(c, n) for c in counts])
    missing = np.array([p[c == 0].sum() for c in counts])
    expected = float(np.sum(p * (1 - p) ** (n - 1)))
    se = gt.std(ddof=1) / np.sqrt(gt.size)
    assert abs(gt.mean() - expected) < 4 * se + 1e-12
    one_fewer = expected - float(np.sum(p * (1 - p) ** n))
    se_m = np.sqrt(gt.var(ddof=1) + missing.var(ddof=1)) / np.sqrt(gt.size)
    assert abs(gt.mean() - missing.mean()) < 4 * se_m + one_fewer


def test_good_turing_counts_singletons_only():
    """Hypothesis: f1 / N counts the classes seen exactly once (zeros and repeats do not
    count), and a census with none reports 0."""
    assert good_turing([5, 1, 0, 1, 2], 9) == pytest.approx(2 / 9)
    assert good_turing([10, 10], 20) == 0.0
    with pytest.raises(ValueError, match="n must be"):
        good_turing([1], 0)


@pytest.mark.parametrize("n", [1, 16, 200, 4096])
def test_an_attractor_at_the_resolution_is_missed_with_the_complement_probability(n):
    """Hypothesis: an attractor whose basin fraction equals resolution(n) is missed by n
    independent starts with probability exactly 1 - 0.95 (analytic, to 1e-12), one
    twice as large with less, and resolution(n) is close to 3 / n for large n."""
    r = resolution(n)
    assert (1 - r) ** n == pytest.approx(0.05, rel=1e-12)
    assert (1 - min(1.0, 2 * r)) ** n < 0.05
    if n >= 200:
        assert r == pytest.approx(-np.log(0.05) / n, rel=0.01)


def test_unseen_mass_is_never_zero_and_not_below_the_missing_mass_on_average():
    """Hypothesis: the reported unseen mass (max of Good–Turing and the resolution) is
    > 0 even when every start is on one attractor, never below the Good–Turing
    estimate, and over simulated censuses of the mixture with N = 200 (whose ten 0.2 %
    basins are what 200 starts miss) its mean is not below the mean true missing mass
    (to 4 standard errors): an estimate that errs high, not a bound of each census."""
    assert unseen_mass([200], 200)[0] == resolution(200) > 0
    p = MIXTURE / MIXTURE.sum()
    counts = _draws(p, 200, 2000, seed=7)
    unseen = np.array([unseen_mass(c, 200)[0] for c in counts])
    missing = np.array([p[c == 0].sum() for c in counts])
    assert np.all(unseen >= [good_turing(c, 200) for c in counts])
    se = np.sqrt(unseen.var(ddof=1) + missing.var(ddof=1)) / np.sqrt(unseen.size)
    assert unseen.mean() >= missing.mean() - 4 * se


@pytest.fixture(scope="module")
def full():
    """A census of the unforced double well from 256 random starts."""
    return vi.attractors(vi.System(DOUBLE_WELL), starts=256, box=BOX, seed=5)


def test_census_stores_the_unseen_mass_of_its_labels(full):
    """Hypothesis: the census' unseen, unseen_good_turing and singletons are the
    estimator applied to its own labels (starts per attractor), at every eta."""
    for i in range(full.sizes["eta"]):
        lab = full.label.values[i]
        want = unseen_mass(np.bincount(lab[lab >= 0]), full.sizes["start"])
        assert float(full.unseen[i]) == want[0]
        assert float(full.unseen_good_turing[i]) == want[1]
        assert int(full.singletons[i]) == want[2]
    assert np.all(full.unseen.values > 0)


@pytest.mark.parametrize("level", [0.2, 0.05, 0.012])
def test_until_unseen_stops_at_the_first_round_that_meets_the_level(full, level):
    """Hypothesis: with until_unseen the census runs the rounds of its most starts (16,
    64, 256) and stops after the first whose starts leave at most ``level`` unseen; its
    labels are the first n labels of the full census (the same states and the same
    library before each round) and n is that round's end."""
    cut = vi.attractors(vi.System(DOUBLE_WELL), starts=256, box=BOX, seed=5,
                        until_unseen=level)
    n = cut.sizes["start"]
    ends = [b for _, b in C.rounds(256)]
    lab = full.label.values[0]
    meets = [b for b in ends if unseen_mass(np.bincount(lab[:b][lab[:b] >= 0]), b)[0]
             <= level]
    assert n == (meets[0] if meets else 256)
    np.testing.assert_array_equal(cut.label.values, full.label.values[:, :n])
    np.testing.assert_array_equal(cut.start_state.values, full.start_state.values[:n])
    assert float(cut.attrs["until_unseen"]) == level and cut.attrs["n_starts"] == n


@pytest.mark.parametrize("kwargs, name", [
    (dict(until_unseen=0.0), "until_unseen"), (dict(until_unseen=1.0), "until_unseen"),
    (dict(until_unseen="0.1"), "until_unseen"),
    (dict(until_unseen=0.1, starts=np.zeros((4, 2))), "until_unseen")])
def test_bad_until_unseen_is_refused_naming_it(kwargs, name):
    """Hypothesis: a level outside (0, 1), not a number, or with explicit states (no
    count of starts to add rounds from) is a ValueError naming until_unseen."""
    kw = dict(starts=16) | kwargs
    with pytest.raises(ValueError, match=name):
        vi.attractors(vi.System(DOUBLE_WELL), box=BOX, **kw)


@pytest.mark.parametrize("value", ["0", "1", "-0.1", "nan", "x"])
def test_cli_bad_until_unseen_is_one_line_and_exit_2(value, tmp_path, capsys):
    """Hypothesis: --until-unseen outside (0, 1) or not a number exits 2 with one line
    naming the option, writing nothing."""
    out = tmp_path / "c.nc"
    try:
        status = main(["attractors", "--preset", "soft-impact", "--starts", "16",
                       "--until-unseen", value, "-o", str(out)])
    except SystemExit as exc:  # argparse's own refusal of a typed option
        status = exc.code
    assert status == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--until-unseen" in err[0]
    assert not out.exists()


def test_cli_prints_the_unseen_mass_and_the_hint(tmp_path, capsys):
    """Hypothesis: the printed table has one 'unseen' line per eta with the stored value,
    and a census of 16 starts (resolution 0.17 > 0.01) prints the hint that names more
    starts, --until-unseen and 'vibimpact orbits'; with --until-unseen met, no hint."""
    out = tmp_path / "c.nc"
    assert main(["attractors", "--preset", "soft-impact", "--starts", "16", "--eta",
                 "0.8,0.9", "--no-progress", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    lines = [ln for ln in text.splitlines() if "unseen (Good-Turing" in ln]
    ds = vi.io.read_netcdf(out)
    assert len(lines) == 2
    for ln, u in zip(lines, ds.unseen.values):
        assert f"<= {float(u):.3f}" in ln
    hint = [ln for ln in text.splitlines() if ln.startswith("hint:")]
    assert len(hint) == 1 and "--until-unseen" in hint[0] and "vibimpact orbits" in hint[0]
    out2 = tmp_path / "c2.nc"
    assert main(["attractors", "--preset", "soft-impact", "--starts", "256", "--eta", "0.8",
                 "--until-unseen", "0.2", "--no-progress", "-o", str(out2)]) == 0
    text = capsys.readouterr().out
    assert "hint:" not in text
    assert vi.io.read_netcdf(out2).sizes["start"] == 16


def test_an_orbit_hunt_names_the_stable_orbit_no_census_start_reached():
    """Hypothesis: in the unforced double well, a census whose starts all lie in the
    right well reaches only x = +1; a hunt of period-1 orbits finds both stable wells
    (and the saddle at 0, unstable), and unreached_orbits names exactly the orbit at
    x = -1, never the unstable one; a census with starts in both wells reaches both."""
    from vibimpact.census.locate import unreached_orbits
    from vibimpact.orbits import hunt_to_dataset

    system = vi.System(DOUBLE_WELL)
    right = vi.attractors(system, starts=16, box=Box([0.6, -0.2], [1.4, 0.2]))
    both = vi.attractors(system, starts=32, box=BOX, seed=1)
    seeds = np.array([[1.1, 0.0], [-1.1, 0.0], [0.01, 0.0]])
    hunt = hunt_to_dataset(vi.hunt_orbits(system, (1,), seeds=seeds, random=0,
                                          continuation=False), system)
    x = hunt.orbit_point.values[:, 0, 0]
    stable = hunt.stable.values == 1
    assert sorted(np.round(x[stable], 6)) == [-1.0, 1.0]
    missed = unreached_orbits(hunt, right)
    assert [o for o, _ in missed] == [int(np.flatnonzero(stable & (x < 0))[0])]
    assert unreached_orbits(hunt, both) == []


@pytest.mark.slow  # two fig11 censuses (about half a minute on 2 cores)
def test_readme_census_settings_find_the_four_fig11_attractors(tmp_path, capsys):
    """Hypothesis: at fig11, eta = 1.06, the README's census (2000 starts, seed 0) lists
    four attractors, among them the two P1 orbits with small basins (impactless and
    with one impact); 200 starts list fewer, with an unseen mass above 0 and the hint."""
    big, small = tmp_path / "c.nc", tmp_path / "s.nc"
    argv = ["attractors", "--preset", "fig11", "--eta", "1.06", "--no-progress"]
    assert main([*argv, "--starts", "2000", "--workers", "2", "-o", str(big)]) == 0
    assert main([*argv, "--starts", "200", "-o", str(small)]) == 0
    text = capsys.readouterr().out
    c, s = vi.io.read_netcdf(big), vi.io.read_netcdf(small)
    names = [str(n) for n in c.name.values[0] if str(n)]
    assert len(names) == 4
    periods = [re.match(r"P(\d+)\b", n) for n in names]
    assert sum(m is not None and m.group(1) == "1" for m in periods) == 2, names
    assert np.isfinite(s.fraction.values[0]).sum() < 4
    assert float(s.unseen[0]) > 0 and "hint:" in text


def test_orbits_take_the_census_names_of_the_attractors_they_are(tmp_path):
    """Hypothesis: named after a census of both wells, each stable orbit of the double
    well's hunt gets the census' global id of the well it is (the attractor whose
    samples hold its point), the unstable saddle gets -1; named after a census that saw
    only the right well, the left orbit gets a new id after the census' largest; the ids
    survive the file, and the orbits figure labels and colours a named orbit as the
    census figure does its attractor."""
    from vibimpact.census.locate import orbits_named_after
    from vibimpact.orbits import hunt_to_dataset, write_orbits
    from vibimpact.plotting.orbits import plot_orbits
    from vibimpact.plotting.style import attractor_colour

    system = vi.System(DOUBLE_WELL)
    both = vi.attractors(system, starts=32, box=BOX, seed=1)
    right = vi.attractors(system, starts=16, box=Box([0.6, -0.2], [1.4, 0.2]))
    seeds = np.array([[1.1, 0.0], [-1.1, 0.0], [0.01, 0.0]])
    hunt = hunt_to_dataset(vi.hunt_orbits(system, (1,), seeds=seeds, random=0,
                                          continuation=False), system)
    x = hunt.orbit_point.values[:, 0, 0]
    stable = hunt.stable.values == 1
    named = orbits_named_after(hunt, both)
    cx = both.representative.values[0, :, 0]  # each census attractor's x
    for o in range(hunt.sizes["orbit"]):
        g = int(named.global_id.values[o])
        if not stable[o]:
            assert g == -1
            continue
        a = int(np.flatnonzero(both.global_id.values[0] == g)[0])
        assert np.sign(cx[a]) == np.sign(x[o])
    assert sorted(int(g) for g in named.global_id.values[stable]) == sorted(
        int(g) for g in both.global_id.values[0] if g >= 0)
    alone = orbits_named_after(hunt, right)
    left = int(np.flatnonzero(stable & (x < 0))[0])
    assert int(alone.global_id.values[left]) == int(right.global_id.values.max()) + 1
    path = tmp_path / "o.nc"
    write_orbits(named, path)
    back = vi.io.read_netcdf(path)
    np.testing.assert_array_equal(back.global_id.values, named.global_id.values)
    ax = plot_orbits(back).axes[0]
    labels = [t.get_text() for t in ax.get_yticklabels()]
    o = int(np.flatnonzero(stable)[0])
    g = int(named.global_id.values[o])
    assert labels[o].startswith(f"A{g}: ")
    import matplotlib.colors as mc

    drawn = [ln for ln in ax.get_lines() if np.allclose(ln.get_ydata(), o)]
    assert drawn and all(mc.same_color(ln.get_color(), attractor_colour(g)) for ln in drawn)


def test_the_orbits_command_names_each_stable_orbit_after_its_seeds_census(tmp_path,
                                                                         capsys):
    """Hypothesis: 'vibimpact orbits --seeds CENSUS' prints, for each stable orbit on an
    attractor of the census, the census' name of it (A<id>, the id the census file
    holds for that attractor), and stores that id in the orbits file."""
    census, orbits = tmp_path / "c.nc", tmp_path / "o.nc"
    assert main(["attractors", "--preset", "soft-impact", "--eta", "0.8", "--starts", "16",
                 "--no-progress", "-o", str(census)]) == 0
    assert main(["orbits", "--preset", "soft-impact", "--eta", "0.8", "--seeds",
                 str(census), "--period", "1", "--random", "0", "--no-progress", "-o",
                 str(orbits)]) == 0
    text = capsys.readouterr().out
    c, o = vi.io.read_netcdf(census), vi.io.read_netcdf(orbits)
    ids = {int(g) for g in c.global_id.values[0] if g >= 0}
    stable = np.flatnonzero(o.stable.values == 1)
    assert stable.size >= 1
    for k in stable:
        g = int(o.global_id.values[k])
        assert g in ids
        assert f"orbit {k} ({o.label.values[k]}) is A{g} of the census" in text
