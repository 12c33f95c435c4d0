"""API arguments of the fourth adversarial round (issue 44, class 14).

Every public function refuses, before any work, an argument it cannot use: indices into
the state out of range (a census box's ``disk``), absurd counts (workers, random seeds,
Newton iterations, periods), forcing frequencies the solver cannot resolve, name
arguments of the wrong type, a model's ``terminal`` longer than its switching functions,
and a file whose basin fractions add up above 1 or whose drawn values are infinite.
Each refusal is a ``ValueError`` (``TypeError`` for a wrong type, also a ``ValueError``)
whose message names the argument exactly as the function's parameter is named.
"""
import re

import numpy as np
import pytest
import xarray as xr

import vibimpact as vi
from vibimpact.continuation.branches import follow_branch
from vibimpact.census import Box

from test_bad_input import run_cli

FIG8 = vi.presets.get("fig8")


def refused(call, name, kind=ValueError):
    """``call()`` raises ``kind`` whose message starts with (or names) ``name``."""
    with pytest.raises(kind) as info:
        call()
    text = str(info.value)
    assert re.search(rf"(^|\W){re.escape(name)}\W", text), text
    return text


@pytest.mark.parametrize("kw, name", [
    (dict(disk=(0, 9)), "disk"), (dict(disk=(0, 0)), "disk"), (dict(disk=(1,)), "disk"),
    (dict(disk=(-1, 1)), "disk"), (dict(disk=(0.5, 1)), "disk"), (dict(disk=5), "disk"),
    (dict(radius=-1.0), "radius"), (dict(radius=float("nan")), "radius"),
    (dict(radius=float("inf")), "radius"), (dict(radius=0.0), "radius"),
    (dict(radius="1"), "radius"), (dict(lo="abcd"), "lo"), (dict(hi=[1, 1]), "lo and hi"),
])
def test_box_refuses_what_it_cannot_draw_from(kw, name):
    """Hypothesis: Box refuses a disk that is not two different state indices of the box,
    a radius that is not finite and > 0, and lo/hi that are not one vector of numbers,
    naming the argument (the disk (0, 9) ended in an IndexError, the others were taken)."""
    args = dict(lo=[-1.0] * 4, hi=[1.0] * 4, disk=(0, 1), radius=1.0)
    args.update(kw)
    refused(lambda: Box(**args), name)


@pytest.mark.parametrize("call, name", [
    (lambda: vi.sweep(FIG8, [1e-300, 1e300], analyses=["period"]), "eta"),
    (lambda: vi.sweep(FIG8, [2e6]), "eta"),
    (lambda: vi.map2d(FIG8, [1e-7, 1.0], {"B": [0.01]}), "eta"),
    (lambda: vi.attractors(vi.System(FIG8), 1e300, starts=2), "eta"),
    (lambda: vi.basins(vi.System(FIG8), 1e-9, grid=(2, 2), eps=1), "eta"),
    (lambda: vi.hunt_orbits(FIG8.replace(eta=1e300), [1], random=1,
                            continuation=False), "system"),
    (lambda: vi.basins(vi.System(FIG8.replace(eta=1e-9)), grid=(2, 2), eps=1), "system"),
    (lambda: follow_branch(FIG8, stop=1e7), "stop"),
    (lambda: follow_branch(FIG8.replace(eta=1e-7), stop=1.0), "system"),
])
def test_forcing_frequencies_outside_the_solvers_range_are_refused(call, name):
    """Hypothesis: a forcing frequency outside [1e-6, 1e6] (a forcing period the solver
    cannot resolve against the model's time scale) is refused before any work by every
    function that takes one."""
    text = refused(call, name)
    assert "1e-06" in text and "1e+06" in text


@pytest.mark.parametrize("call, name, kind", [
    (lambda: vi.grid("1:2:0.1", name=5), "name", TypeError),
    (lambda: vi.grid("1:2:0.1", name=""), "name", TypeError),
    (lambda: vi.grid(1.0), "text", TypeError),
    (lambda: vi.hunt_orbits("fig8", [1], random=1), "system", TypeError),
    (lambda: vi.hunt_orbits(FIG8, [1], random=10**12), "random", ValueError),
    (lambda: vi.hunt_orbits(FIG8, [1], max_iter=10**6), "max_iter", ValueError),
    (lambda: vi.hunt_orbits(FIG8, [1], starts=10**9), "starts", ValueError),
    (lambda: vi.hunt_orbits(FIG8, [1], transient=10**12), "transient", ValueError),
    (lambda: vi.Execution(workers=10**6), "workers", ValueError),
    (lambda: vi.CensusSettings(max_periods=10**12), "max_periods", ValueError),
    (lambda: vi.CensusSettings(cloud=10**9), "cloud", ValueError),
])
def test_names_and_counts_are_checked_under_their_own_names(call, name, kind):
    """Hypothesis: a name argument of the wrong type and a count above its limit are
    refused naming that argument (vi.grid(1.0) named 'eta', hunt_orbits('fig8') 'p',
    random=10**12 'starts'; name=5 and workers=10**6 were taken)."""
    refused(call, name, kind)


def test_the_api_and_the_command_line_share_one_worker_limit():
    """Hypothesis: the largest worker count the command line takes is the API's too."""
    from vibimpact.base import _limits
    from vibimpact.cli.common.args import MAX_WORKERS

    assert MAX_WORKERS == _limits.MAX_WORKERS
    assert vi.Execution(workers=MAX_WORKERS).workers == MAX_WORKERS
    refused(lambda: vi.Execution(workers=MAX_WORKERS + 1), "workers")


def test_a_terminal_longer_than_the_switching_functions_is_refused():
    """Hypothesis: a user model whose terminal lists more switching functions than its
    switches function sets is refused before the kernel runs it, naming terminal (it was
    taken, the kernel then reading an entry nothing sets)."""
    from test_model_sizes import P6, _model
    from vibimpact.models.model_probe import check_model

    text = refused(lambda: check_model(_model(terminal=[0, 1, 1]), P6), "terminal")
    assert "g[1]" in text
    check_model(_model(terminal=[0]), P6)  # the right length passes


def _census_like(fractions, failed=None):
    ds = xr.Dataset({"fraction": (("eta", "attractor"), np.array(fractions, float))},
                    coords={"eta": [1.0]})
    if failed is not None:
        ds["failed_fraction"] = ("eta", np.array([failed], float))
    return ds


@pytest.mark.parametrize("fractions, failed, name", [
    ([[0.7, 0.6]], None, "fraction"), ([[0.7, np.nan]], 0.5, "failed_fraction"),
    ([[1.5, np.nan]], None, "fraction"), ([[0.5, -0.1]], None, "fraction"),
])
def test_basin_fractions_adding_above_one_are_refused(fractions, failed, name):
    """Hypothesis: basin fractions outside [0, 1], or adding up (with the failed
    fraction) above 1 at an eta, are refused naming the variable."""
    from vibimpact.plotting._sweep import check_contents

    refused(lambda: check_contents(_census_like(fractions, failed), codes=()), name)
    check_contents(_census_like([[0.5, np.nan]], 0.5), codes=())  # adding up to 1


@pytest.mark.parametrize("name", ["X_m", "Y_m", "poincare_X"])
def test_an_infinite_drawn_value_is_refused(name):
    """Hypothesis: a response or Poincare sample that is infinite (never written by the
    toolkit) is refused naming the variable, not drawn; NaN (missing) stays allowed."""
    from vibimpact.plotting._sweep import check_contents

    values = np.array([1.0, np.nan, 0.5])
    ds = xr.Dataset({name: ("eta", values)}, coords={"eta": [1.0, 1.1, 1.2]})
    check_contents(ds, codes=())
    ds[name].values[0] = np.inf
    refused(lambda: check_contents(ds, codes=()), name)


def test_plot_of_a_census_whose_fractions_add_above_one_is_one_line(tmp_path, capfd):
    """Hypothesis: 'vibimpact plot' of a census file whose fractions were altered to add
    up above 1 ends with one line naming fraction and exit status 2, no image."""
    system = vi.System(vi.DuffingParams(delta=0.1, alpha=1.0, beta=-1.0, gamma=5.0,
                                        omega=1.0))
    ds = vi.attractors(system, None, starts=2)
    ds["fraction"].values[:] = 1.5
    ds.attrs["command"] = "vibimpact attractors"
    vi.io.write_netcdf(ds, tmp_path / "c.nc")
    rc, _, err = run_cli(["plot", tmp_path / "c.nc", "-o", tmp_path / "c.png"], capfd)
    lines = err.strip().splitlines()
    assert rc == 2 and len(lines) == 1 and "fraction" in lines[0], err
    assert not (tmp_path / "c.png").exists()


@pytest.mark.parametrize("ranges, needle", [
    (((-1e308, 1e308), (-1.0, 1.0)), "finite hi - lo"),
    (((-1.0, 1.0), (-1.7e308, 1.7e308)), "finite hi - lo"),
    (((1.0, 1.0000000000000002), (-1.0, 1.0)), "too narrow for 6 cells"),
])
def test_basins_ranges_that_overflow_or_coincide_are_refused_without_warnings(ranges,
                                                                               needle):
    """Hypothesis: vi.basins refuses a plane range whose width overflows a float (NumPy
    printed overflow warnings, then 'starts must be finite') or whose cell centres would
    coincide (it computed a plane of repeated starts), naming ``ranges``, before any
    integration, and with no warning."""
    import warnings

    system = vi.System(vi.presets.get("fig11").replace(eta=1.06))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=rf"^ranges.*{needle}"):
            vi.basins(system, grid=(6, 6), ranges=ranges)
