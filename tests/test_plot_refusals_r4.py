"""The refusals of ``vibimpact plot`` and ``vibimpact continue2`` (issue 44, class 9).

``plot`` named the wrong kind of file a figure needs (``--kind xy`` of a census: "needs
a sweep file"; ``--kind branch`` of a map: "needs a sweep file"; ``--kind lyapunov`` of a
map: "stores no Poincare samples").  Every (figure, kind of file) pair that plot refuses
is tried here on a small file of that kind: the one line names what the figure needs and
what the file is.  ``continue2`` ended in a traceback for a ``--state0`` of the wrong
size and for ``--approach 0`` or ``-1``, and ran three points without a word for a
``--step`` larger than its window.
"""
import numpy as np
import pytest
import xarray as xr

from test_bad_input import run_cli

#: the words that name what each figure needs (written here, not taken from the code)
NEEDS = {"xy": "a 'vibimpact simulate' file",
         "response": "a sweep file", "bifurcation": "a sweep file",
         "intervals": "a sweep file", "poincare": "a sweep file", "lyapunov": "a sweep file",
         "map": "a parameter map ('vibimpact map')",
         "branch": "a continued branch ('vibimpact continue')",
         "census": "an attractor census ('vibimpact attractors')"}
#: the figures each kind of file holds the data of
DRAWN = {"run": {"xy"},
         "sweep": {"response", "bifurcation", "intervals", "poincare", "lyapunov"},
         "map": {"map"}, "branch": {"branch"}, "census": {"census"},
         "basins": set(), "orbits": set(), "curve": set()}
#: the words that say what each kind of file is
IS = {"run": "is a 'vibimpact simulate' file", "sweep": "is a sweep file",
      "map": "is a parameter map", "branch": "is a continued branch",
      "census": "is an attractor census", "basins": "is a basins file",
      "orbits": "is an orbit hunt", "curve": "is a two-parameter curve"}


def _file(kind, path):
    """A small file of ``kind``, as the commands' files are told apart."""
    from vibimpact.continuation.branches import _TITLE as BRANCH
    from vibimpact.continuation.curves import _TITLE as CURVE
    from vibimpact.orbits.dataset import TITLE as ORBITS

    eta = {"eta": [1.0, 1.1]}
    ds = {"run": lambda: xr.Dataset({"strobe": (("sample", "state"), np.zeros((2, 4)))},
                                    coords={"state": ["X", "Y", "dX", "dY"]}),
          "sweep": lambda: xr.Dataset({"regime": ("eta", np.ones(2, "i1"))}, coords=eta),
          "map": lambda: xr.Dataset({"regime": (("kh", "eta"), np.ones((2, 2), "i1"))},
                                    coords={**eta, "kh": [100.0, 120.0]},
                                    attrs={"map_vary": "kh"}),
          "branch": lambda: xr.Dataset({"stable": ("point", np.ones(2, "i1"))},
                                       coords={"eta": ("point", [1.0, 1.1])},
                                       attrs={"title": BRANCH,
                                              "continuation_param": "eta"}),
          "census": lambda: xr.Dataset(coords=eta, attrs={"kind": "census"}),
          "basins": lambda: xr.Dataset({"basin": (("row", "column"), np.zeros((2, 2)))},
                                       attrs={"kind": "basins"}),
          "orbits": lambda: xr.Dataset({"period": ("orbit", [1, 2])},
                                       attrs={"title": ORBITS}),
          "curve": lambda: xr.Dataset({"eta": ("point", [1.0, 1.1])},
                                      attrs={"title": CURVE, "curve_params": "eta,kh"}),
          }[kind]()
    ds.to_netcdf(path)
    return path


def one_line(rc, out, err):
    assert rc == 2, (rc, out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("vibimpact: error: "), err
    assert "Traceback" not in err and "Warning" not in err
    return lines[0]


REFUSED = [(kind, what) for what in DRAWN for kind in NEEDS if kind not in DRAWN[what]]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("kinds")
    return {what: _file(what, d / f"{what}.nc") for what in DRAWN}


@pytest.mark.parametrize("kind,what", REFUSED)
def test_a_refused_figure_names_what_it_needs_and_what_the_file_is(kind, what, files,
                                                                    tmp_path, capfd):
    """Hypothesis: ``plot FILE --kind K`` of a file that does not hold K's data exits 2
    with one line naming the kind of file K needs (xy: a simulate file, branch: a
    continue file, census: an attractors file, map: a map file, the rest: a sweep
    file) and the kind the file is, and writes no image."""
    image = tmp_path / "p.png"
    line = one_line(*run_cli(["plot", files[what], "--kind", kind, "-o", image], capfd))
    assert f"--kind {kind} needs {NEEDS[kind]}" in line, line
    assert IS[what] in line, line
    assert not image.exists()


@pytest.mark.parametrize("what", ["basins", "orbits", "curve"])
def test_a_file_plot_does_not_draw_is_named_without_a_kind(what, files, tmp_path, capfd):
    """Hypothesis: ``plot`` of a basins, orbits or continue2 file without --kind says
    what the file is and that plot does not draw it (it said "neither a simulate nor a
    sweep file")."""
    line = one_line(*run_cli(["plot", files[what], "-o", tmp_path / "p.png"], capfd))
    assert IS[what] in line and "plot does not draw" in line, line


@pytest.mark.parametrize("option,what", [("--state", "census"), ("--state", "map"),
                                         ("--branch", "branch"), ("--branch", "run")])
def test_sweep_options_on_another_file_name_the_file(option, what, files, tmp_path,
                                                     capfd):
    """Hypothesis: --state or --branch (options of a sweep's figures) on a file of
    another kind exit 2 with one line naming the option and what the file is."""
    value = "X" if option == "--state" else files["branch"]
    line = one_line(*run_cli(["plot", files[what], option, value, "-o",
                              tmp_path / "p.png"], capfd))
    assert option in line and IS[what] in line, line


CONTINUE2 = ["continue2", "--preset", "fig8", "--eta", "1.12", "--kind", "grazing",
             "--param2", "kh", "--range2", "110:130"]


@pytest.fixture
def no_seed(monkeypatch):
    """continue2's first piece of work (the seed of the curve) fails the test if run."""
    import vibimpact.cli.continue2 as c2

    def seed(*a, **k):
        raise AssertionError("continue2 started its work")
    monkeypatch.setattr(c2, "_seed", seed)


@pytest.mark.parametrize("extra,needle", [
    (["--state0", "0", "0", "0"], "--state0 expects 4 numbers for the rotor model"),
    (["--state0", "0", "0", "0", "0", "0"], "--state0 expects 4 numbers"),
    (["--preset", "soft-impact", "--param2", "A", "--range2", "0.2:0.4", "--eta", "0.83",
      "--state0", "0", "0", "0", "0"], "--state0 expects 2 numbers for the soft_impact"),
    (["--preset", "fig8-ring", "--state0", "0", "0", "0", "0"],
     "--state0 expects 5 numbers for the ring model"),
    (["--approach", "0"], "--approach must be a value of eta > 0"),
    (["--approach", "-1"], "--approach must be a value of eta > 0"),
    (["--step", "21"], "--step 21 is larger than the window --range2 110:130"),
    (["--step", "1e300"], "is larger than the window"),
    (["--stop1", "1.12"], "--stop1 must differ from the start value eta = 1.12"),
    (["--stop1", "-3"], "--stop1: eta must be > 0"),
    (["--range2=-1e308:1e308"], "--range2: kh must be >= 0"),
])
def test_continue2_refuses_bad_input_in_one_line_before_any_work(extra, needle, no_seed,
                                                                 tmp_path, capfd):
    """Hypothesis: continue2 with a --state0 of the wrong size for the model (rotor,
    ring, soft-impact), --approach 0 or -1, a --step larger than the window, a --stop1 at the start
    or outside the domain, or a --range2 outside the domain exits 2 with one line naming
    the option, before the curve's seed is computed, and writes nothing."""
    out = tmp_path / "c.nc"
    line = one_line(*run_cli(CONTINUE2 + extra + ["-o", out], capfd))
    assert needle in line, line
    assert list(tmp_path.iterdir()) == []


def test_continue2_over_a_map_of_other_parameters_is_refused_before_work(no_seed,
                                                                         tmp_path, capfd):
    """Hypothesis: continue2 --over a map over (eta, B) for a curve in (eta, kh) exits 2
    with one line naming --over before any work (it computed the curve first)."""
    path = tmp_path / "m.nc"
    xr.Dataset({"regime": (("B", "eta"), np.ones((2, 2), "i1")),
                "label": (("B", "eta"), np.array([["a", "a"], ["a", "a"]], dtype=object))},
               coords={"eta": [1.0, 1.1], "B": [0.1, 0.2]},
               attrs={"map_vary": "B"}).to_netcdf(path)
    line = one_line(*run_cli(CONTINUE2 + ["--over", path, "--plot", tmp_path / "c.png",
                                          "-o", tmp_path / "c.nc"], capfd))
    assert "--over" in line and "(eta, B)" in line, line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.nc"]


@pytest.mark.parametrize("extra,needle", [
    (["--state0", "0", "0", "0"], "--state0 expects 4 numbers"),
    (["--refine", "1e-300"], "the float resolution of eta over the window, got 1e-300"),
])
def test_continue_refuses_a_start_state_or_width_it_cannot_use(extra, needle, monkeypatch,
                                                              tmp_path, capfd):
    """Hypothesis: continue with a --state0 of the wrong size (argparse took exactly 4
    values, so soft-impact's 2 could not be given) or a --refine below the float
    resolution (the bisection looped for ever) exits 2 with one line before any
    work."""
    import vibimpact.continuation.branches as branches

    monkeypatch.setattr(branches, "follow_branch", lambda *a, **k: pytest.fail("work"))
    line = one_line(*run_cli(["continue", "--stop", "1.2", *extra, "-o",
                              tmp_path / "b.nc"], capfd))
    assert needle in line, line
    assert list(tmp_path.iterdir()) == []


def test_a_refinement_below_the_float_resolution_ends(monkeypatch):
    """Hypothesis: refine_stability_change with a tol far below the spacing of floats
    ends (it bisected for ever once the midpoint equalled an end): the interval it
    returns is as narrow as floats allow."""
    import vibimpact as vi
    from vibimpact.analysis import stability_change as sc

    class Orbit:  # stable below eta = 1.1, unstable above; every shooting converges
        def __init__(self, eta):
            self.converged, self.minimal_period = True, 1
            self.abs_max = 0.5 if eta < 1.1 else 1.5
            self.state = np.zeros(4)
            self.multipliers = np.array([-self.abs_max, 0.1, 0.1, 0.1], dtype=complex)

    monkeypatch.setattr(sc, "shoot_periodic_orbit",
                        lambda system, x, n, tol: Orbit(system.param("eta")))
    system = vi.System(vi.presets.get("fig8"))
    ch = sc.refine_stability_change(system, "eta", 1, (1.0, 1.2),
                                    (np.zeros(4), np.zeros(4)), tol=1e-300)
    lo, hi = ch.bracket
    assert lo < 1.1 <= hi and np.nextafter(lo, 2.0) == hi
