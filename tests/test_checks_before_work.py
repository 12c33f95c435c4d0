"""Every input is checked before any work (issue 44, class 7).

``continue --switch`` computed the branch, wrote OUT and then refused the switch with exit
status 2 (bad input, nothing written, the README says) and OUT left behind;
``attractors --sweep`` of a sweep without ``poincare_Y`` computed the census, wrote it and
then refused; a sweep of another model or other parameters was placed in the census
without a word; a sweep whose ``poincare_X`` is text was a traceback.  Each case here
replaces the command's computation by one that fails the test if called, and checks that
nothing is written.
"""
import json

import numpy as np
import pytest
import xarray as xr

import vibimpact as vi
from vibimpact.cli import main

from test_bad_input import listing, run_cli
from test_plot_refusals_r4 import one_line


def _never(*args, **kwargs):
    raise AssertionError("the command started its work")


def sweep_of(preset="fig11", etas=(1.05, 1.06), samples=4, **sets):
    """A small sweep file's dataset of ``preset`` (with ``sets``), as vibimpact writes
    one: regime and the Poincare samples of every state over (eta, sample), the model and
    parameters in the attributes."""
    p = vi.presets.get(preset).replace(**sets)
    system = vi.System(p)
    model = system.model
    rng = np.random.default_rng(0)
    data = {"regime": ("eta", np.ones(len(etas), "i1"))}
    for name in model.state_names:
        data[f"poincare_{name}"] = (("eta", "sample"),
                                    rng.uniform(-0.5, 0.5, (len(etas), samples)))
    params = {k: v for k, v in p.as_dict().items()
              if k != model.param_names[model.omega_index]}
    attrs = {"model": model.name, "params": json.dumps(params, sort_keys=True),
             "settings": json.dumps({"analyses": "period,poincare"})}
    attrs.update({f"param_{k}": float(v) for k, v in params.items()})
    return xr.Dataset(data, coords={"eta": list(etas)}, attrs=attrs)


def _no_poincare_y(ds):
    return ds.drop_vars("poincare_Y")


def _text_samples(ds):
    return ds.assign(poincare_X=(("eta", "sample"),
                                 np.full(ds.poincare_X.shape, "a", dtype=object)))


def _wrong_shape(ds):
    return ds.assign(poincare_X=(("eta", "other"), ds.poincare_X.values))


def _nan_only(ds):
    return ds.assign(poincare_X=ds.poincare_X * np.nan)


def _text_eta(ds):
    return ds.assign_coords(eta=np.array(["a", "b"], dtype=object))


CRAFTED = {
    "no poincare_Y": (_no_poincare_y, "no Poincare samples of Y (poincare_Y)"),
    "poincare_X as text": (_text_samples, "poincare_X must hold numbers"),
    "poincare_X of another shape": (_wrong_shape, "poincare_X must have the dimensions"),
    "poincare_X all NaN": (_nan_only, "holds no finite Poincare samples"),
    "eta as text": (_text_eta, "eta must hold numbers"),
    "a ring sweep": (lambda ds: sweep_of("fig8-ring"), "is a sweep of the ring model; "
                     "the census is of the rotor model"),
    "other parameters": (lambda ds: sweep_of(kh=100.0), "kh = 100 (the census: 120)"),
    "another preset": (lambda ds: sweep_of("fig8"), "other parameters than the census'"),
    "no eta shared": (lambda ds: sweep_of(etas=(1.2, 1.3)), "shares no eta with --eta"),
    "a map": (lambda ds: ds.assign_attrs(map_vary="kh"), "is not a sweep file"),
}


@pytest.mark.parametrize("case", list(CRAFTED))
def test_attractors_sweep_is_checked_before_the_census(case, tmp_path, monkeypatch,
                                                       capfd):
    """Hypothesis: attractors --sweep of a sweep without poincare_Y, with text, misshapen
    or NaN-only samples, text etas, of another model or other parameters, sharing no eta
    or a map exits 2 with one line naming --sweep, before the census is computed, and
    writes nothing (it computed and wrote the census first, or ran without a word)."""
    import vibimpact.census.census as census

    monkeypatch.setattr(census, "attractors", _never)
    change, needle = CRAFTED[case]
    path = tmp_path / "s.nc"
    change(sweep_of()).to_netcdf(path)
    line = one_line(*run_cli(["attractors", "--eta", "1.05:1.06:0.01", "--starts", "2",
                              "--no-progress", "--sweep", path, "-o", tmp_path / "c.nc"],
                             capfd))
    assert "--sweep" in line and needle in line, line
    assert listing(tmp_path) == ["s.nc"]


def test_a_good_sweep_passes_the_checks(tmp_path, monkeypatch, capfd):
    """Hypothesis: the checks refuse what they should only: the same small sweep
    unchanged reaches the census (which here stops the command)."""
    import vibimpact.census.census as census

    class Reached(Exception):
        pass

    def reached(*a, **k):
        raise Reached
    monkeypatch.setattr(census, "attractors", reached)
    path = tmp_path / "s.nc"
    sweep_of().to_netcdf(path)
    with pytest.raises(Reached):
        main(["attractors", "--eta", "1.05:1.06:0.01", "--starts", "2", "--no-progress",
              "--sweep", str(path), "-o", str(tmp_path / "c.nc")])


@pytest.fixture
def failing_switch(monkeypatch):
    import vibimpact.analysis as analysis

    def switch(*a, **k):
        raise ValueError("h: no period-2 orbit found (a test's failure)")
    monkeypatch.setattr(analysis, "switch_branch", switch)


def test_continue_switch_that_fails_writes_neither_file(failing_switch, tmp_path, capfd):
    """Hypothesis: continue --switch whose switch fails exits 2 with one line naming
    --switch and writes neither OUT nor OUT_P2 (it wrote OUT, then exited 2)."""
    line = one_line(*run_cli(["continue", "--preset", "soft-impact", "--stop", "0.9",
                              "--max-points", "3", "--switch", "-o", tmp_path / "x.nc"],
                             capfd))
    assert line.startswith("vibimpact: error: --switch:") and "nothing written" in line
    assert listing(tmp_path) == []


def test_continue_switch_without_a_period_doubling_writes_nothing(tmp_path, capfd):
    """Hypothesis: continue --switch on a branch with no period doubling (fig8, three
    orbits from eta 1.0) exits 2 with one line and leaves no file."""
    line = one_line(*run_cli(["continue", "--stop", "1.05", "--max-points", "3",
                              "--switch", "-o", tmp_path / "x.nc"], capfd))
    assert "--switch" in line
    assert listing(tmp_path) == []


@pytest.mark.parametrize("ranges,needle", [
    ("-1e308:1e308,-1:1", "a finite HI - LO"),
    ("-1:1,-1.7e308:1.7e308", "a finite HI - LO"),
    ("1:1.0000000000000002,-1:1", "too narrow for 6 cells"),
])
def test_basins_range_is_refused_without_a_warning(ranges, needle, tmp_path,
                                                   monkeypatch, capfd):
    """Hypothesis: basins --range whose width overflows a float (NumPy printed two
    RuntimeWarnings, then 'starts must be finite') or whose cells would coincide exits 2
    with one line naming --range and nothing before it, before any work."""
    import vibimpact.census.basins as basins

    monkeypatch.setattr(basins, "basins", _never)
    line = one_line(*run_cli(["basins", "--grid", "6x6", f"--range={ranges}", "-o",
                              tmp_path / "b.nc"], capfd))
    assert "--range" in line and needle in line, line
    assert listing(tmp_path) == []


@pytest.mark.parametrize("argv,needle", [
    (["simulate", "--preset", "soft-impact", "--state0", "0.1", "0", "0", "0"],
     "--state0 expects 2 numbers for the soft_impact model"),
    (["simulate", "--preset", "fig8-ring", "--state0", "0", "0", "0", "0"],
     "--state0 expects 5 numbers for the ring model"),
])
def test_simulate_state0_fits_the_model(argv, needle, tmp_path, monkeypatch, capfd):
    """Hypothesis: simulate --state0 takes one value per state of the model and refuses
    another count in one line before the run (argparse demanded exactly four)."""
    import vibimpact.core.simulation as simulation

    monkeypatch.setattr(simulation, "simulate", _never)
    line = one_line(*run_cli(argv + ["--periods", "2", "-o", tmp_path / "r.nc"], capfd))
    assert needle in line, line
    assert listing(tmp_path) == []


@pytest.mark.parametrize("stop", ["1e7", "1e-9"])
def test_continue_stop_outside_the_frequency_range_names_the_option(stop, tmp_path,
                                                                    monkeypatch, capfd):
    """Hypothesis: continue --stop beyond the forcing-frequency range is refused before
    the branch is followed, in one line naming --stop (the API's refusal named its
    keyword 'stop', after the start orbit had been reached)."""
    import vibimpact.continuation.branches as branches

    monkeypatch.setattr(branches, "follow_branch", _never)
    line = one_line(*run_cli(["continue", "--eta", "1.12", "--stop", stop, "-o",
                              tmp_path / "x.nc"], capfd))
    assert line.startswith("vibimpact: error: --stop: eta must lie in")
    assert listing(tmp_path) == []


def test_orbits_seeds_without_a_state_names_the_file_not_the_api_argument(tmp_path,
                                                                           monkeypatch,
                                                                           capfd):
    """Hypothesis: orbits --seeds of a file that holds no state of the model is refused
    before the hunt in one line naming --seeds and the file, without the API's argument
    name 'ds'."""
    import vibimpact.orbits as orbits

    monkeypatch.setattr(orbits, "hunt_orbits", _never)
    seeds = tmp_path / "empty.nc"
    xr.Dataset({"a": ("x", [1.0])}).to_netcdf(seeds)
    line = one_line(*run_cli(["orbits", "--preset", "fig11", "--eta", "1.06", "--period",
                              "1", "--seeds", seeds, "-o", tmp_path / "o.nc"], capfd))
    assert line.startswith(f"vibimpact: error: --seeds {str(seeds)!r} holds no state")
    assert " ds " not in line
    assert listing(tmp_path) == ["empty.nc"]
