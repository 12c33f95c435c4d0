"""The command line refuses what a user would not mean (issue 32, part 1, "accepted
without a word"): numbers written with Python's digit separators or non-ASCII digits,
NaN and infinity, integers beyond 64 bits, an empty --preset, --ds above --ds-max,
figures too large to draw, files whose eta or regime codes are damaged.  Each case runs
``vibimpact.cli.main`` in this process and must end with one ``vibimpact: error:`` line,
exit status 2 and nothing written."""
import os

import numpy as np
import pytest

from test_bad_input import run_cli

#: numbers as a user would not write them (each parses with Python's float or int)
NOT_NUMBERS = ["1_0", "\uff11", "nan", "-infinity", "1e999", "0x10"]

#: a command line per number option, with {} where the value goes
NUMBER_OPTIONS = [
    ["simulate", "--eta", "{}", "-o", "s.nc"],
    ["simulate", "--rtol", "{}", "-o", "s.nc"],
    ["simulate", "--state0", "0", "{}", "0", "0", "-o", "s.nc"],
    ["simulate", "--set", "kh={}", "-o", "s.nc"],
    ["classify", "--eta", "1.0:{}:0.01", "--workers", "1"],
    ["classify", "--eta", "{}:1.1:0.01", "--workers", "1"],
    ["classify", "--eta", "1.0,{}", "--workers", "1"],
    ["map", "--eta", "1.0:1.01:0.01", "--vary", "B=0:{}:0.01"],
    ["continue", "--eta", "1.12", "--stop", "{}"],
    ["continue", "--eta", "1.12", "--stop", "1.2", "--ds", "{}"],
    ["basins", "--range", "-1:{},-1:1", "--grid", "5x5"],
    ["basins", "--base", "0,0,{},0", "--grid", "5x5"],
    ["continue2", "--kind", "grazing", "--param2", "BT", "--range2", "0:{}"],
    ["plot", "s.nc", "--dpi", "{}"],
    ["plot", "s.nc", "--figsize", "{}x3"],
]

#: a command line per integer option
INTEGER_OPTIONS = [
    ["simulate", "--periods", "{}", "-o", "s.nc"],
    ["classify", "--eta", "1.0:1.01:0.01", "--workers", "{}"],
    ["map", "--eta", "1.0:1.01:0.01", "--vary", "B=0:0.01:0.01", "--workers", "{}"],
    ["orbits", "--eta", "1.1", "--period", "{}"],
    ["orbits", "--eta", "1.1", "--seed", "{}"],
    ["basins", "--grid", "{}x5"],
    ["attractors", "--eta", "1.1", "--starts", "{}"],
    ["continue", "--eta", "1.12", "--stop", "1.2", "--max-points", "{}"],
]

NOT_INTEGERS = ["1_0", "\uff11\uff10", "1e3", "12345678901234567890"]


def _option(template):
    """The option whose value holds ``{}`` (``--set`` for NAME={}), as a message names
    it (``--eta``; a grid's quantity, ``eta``; a range's option)."""
    k = next(i for i, a in enumerate(template) if "{}" in a)
    return next(a for a in reversed(template[:k]) if a.startswith("-")).lstrip("-")


def _refused(argv, tmp_path, monkeypatch, capfd):
    monkeypatch.chdir(tmp_path)
    before = sorted(os.listdir(tmp_path))
    rc, out, err = run_cli(argv, capfd)
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert rc == 2, (argv, rc, out, err)
    assert len(lines) == 1 and lines[0].startswith("vibimpact: error: "), (argv, err)
    assert sorted(os.listdir(tmp_path)) == before, argv
    return lines[0]


def _rotated(templates, texts, per=2):
    """Each template with ``per`` of the texts, rotating, so that every text is tried on
    several options and every option with several texts (the whole product would cost
    the test command seconds for no other case)."""
    return [(t, texts[(i * per + k) % len(texts)]) for i, t in enumerate(templates)
            for k in range(per)]


@pytest.mark.parametrize("template, text", _rotated(NUMBER_OPTIONS, NOT_NUMBERS),
                         ids=lambda v: " ".join(v[:2]) if isinstance(v, list) else ascii(v))
def test_every_number_option_refuses_what_a_user_would_not_write(template, text,
                                                                 tmp_path, monkeypatch,
                                                                 capfd):
    """Every option that takes a real number (single values, --set, grids, ranges,
    states, figure sizes) refuses digit separators ('1_0' ran eta = 10), fullwidth and
    other non-ASCII digits, NaN, infinity, overflow and hex, in one line naming the
    option, exit 2, before writing anything."""
    line = _refused([a.replace("{}", text) for a in template], tmp_path, monkeypatch,
                    capfd)
    assert _option(template).split("-")[-1] in line, line


@pytest.mark.parametrize("template, text", _rotated(INTEGER_OPTIONS, NOT_INTEGERS),
                         ids=lambda v: " ".join(v[:2] + v[-2:-1]) if isinstance(v, list)
                         else ascii(v))
def test_every_integer_option_refuses_what_a_user_would_not_write(template, text,
                                                                  tmp_path, monkeypatch,
                                                                  capfd):
    """Every integer option refuses separators, non-ASCII digits, exponents, points and
    a 20-digit value (a 20-digit --workers was accepted), naming the option."""
    line = _refused([a.replace("{}", text) for a in template], tmp_path, monkeypatch,
                    capfd)
    assert _option(template) in line, line


@pytest.mark.parametrize("command", [
    ["simulate", "--periods", "1", "-o", "s.nc"], ["classify", "--eta", "1.0:1.01:0.01"],
    ["map", "--eta", "1.0:1.01:0.01", "--vary", "B=0:0.01:0.01"],
    ["continue", "--eta", "1.12", "--stop", "1.2"], ["orbits", "--eta", "1.1"],
    ["basins", "--grid", "5x5"], ["attractors", "--eta", "1.1"],
    ["continue2", "--kind", "grazing", "--param2", "BT", "--range2", "0:1"],
], ids=lambda c: c[0])
@pytest.mark.parametrize("name", ["", " "])
def test_an_empty_preset_is_refused_by_every_command(command, name, tmp_path,
                                                      monkeypatch, capfd):
    """--preset '' named no preset, and simulate ran the default one; every command that
    takes --preset refuses an empty or blank name, naming the presets."""
    line = _refused(command + ["--preset", name], tmp_path, monkeypatch, capfd)
    assert "preset" in line


def test_continue_refuses_a_first_step_above_the_largest(tmp_path, monkeypatch, capfd):
    """continue --ds 0.1 --ds-max 0.01 was accepted; it is refused naming both options,
    and the API's Steps refuses ds outside [ds_min, ds_max] naming ds."""
    from vibimpact.analysis import Steps

    line = _refused(["continue", "--eta", "1.12", "--stop", "1.2", "--ds", "0.1",
                     "--ds-max", "0.01"], tmp_path, monkeypatch, capfd)
    assert "--ds 0.1" in line and "--ds-max 0.01" in line
    for kw in (dict(ds=0.1, ds_max=0.01), dict(ds=1e-6, ds_min=1e-5)):
        with pytest.raises(ValueError, match=r"^ds must lie between ds_min and ds_max"):
            Steps(**kw)


@pytest.mark.parametrize("command", [
    ["simulate", "--periods", "1", "-o", "s.nc", "--plot", "s.png"],
    ["bifurcation", "--eta", "1.0:1.01:0.01"],
    ["map", "--eta", "1.0:1.01:0.01", "--vary", "B=0:0.01:0.01", "--plot", "m.png"],
    ["basins", "--grid", "5x5", "--plot", "b.png"],
    ["orbits", "--eta", "1.1", "--plot", "o.png"],
    ["attractors", "--eta", "1.1", "--plot", "a.png"],
    ["plot", "s.nc"],
], ids=lambda c: c[0])
@pytest.mark.parametrize("size", [["--figsize", "1e9x1e9"], ["--dpi", "1000000"],
                                  ["--figsize", "100000x1", "--dpi", "100"]],
                         ids=["figsize", "dpi", "one side"])
def test_every_drawing_command_refuses_an_image_too_large_before_any_work(
        command, size, tmp_path, monkeypatch, capfd):
    """A figure too large to draw (it ended in MemoryError from Agg after the whole
    computation) is refused by every command that draws, before it computes or writes
    anything, naming the option and the pixel limit."""
    line = _refused(command + size, tmp_path, monkeypatch, capfd)
    assert size[0] in line and "pixels" in line


def test_the_pixel_limit_lets_ordinary_figures_through():
    """The pixel check refuses only what is too large: a journal figure at 600 dpi and
    the largest default figure at 300 dpi pass; the limit's sides are named."""
    from vibimpact.base import _limits

    _limits.check_pixels(3.5, 2.8, 600)
    _limits.check_pixels(12, 16, 300)
    with pytest.raises(ValueError, match="pixels"):
        _limits.check_pixels(12, 16, 3000)


def _sweep_file(path, eta=(1.0, 1.01), regime=(1, 3)):
    import xarray as xr

    from vibimpact.io import write_netcdf

    ds = xr.Dataset({"regime": ("eta", np.array(regime, dtype="i1"),
                                {"flag_values": np.array([1, 2, 3, 4, 5, 0], dtype="i1"),
                                 "flag_meanings": "periodic quasi_periodic chaotic "
                                                  "diverged unsettled not_computed"}),
                     "X_m": ("eta", [0.5, 0.6]), "Y_m": ("eta", [0.5, 0.6]),
                     "label": ("eta", ["P1", "chaos"]), "period": ("eta", [1, 0]),
                     "impacts_per_period": ("eta", [1.0, 2.0]),
                     "poincare_X": (("eta", "sample"), np.ones((2, 4))),
                     "poincare_Y": (("eta", "sample"), np.ones((2, 4)))},
                    coords={"eta": list(eta)}, attrs={"command": "vibimpact classify"})
    write_netcdf(ds, path)


@pytest.mark.parametrize("eta, regime, words", [
    ((1.0, np.nan), (1, 3), "eta holds 1 non-finite"),
    ((1.0, np.inf), (1, 3), "eta holds 1 non-finite"),
    ((1.01, 1.0), (1, 3), "eta must be strictly increasing"),
    ((1.0, 1.01), (1, 9), "regime holds code(s) 9 not among its flag_values"),
    ((1.0, 1.01), (-1, 3), "regime holds code(s) -1"),
])
@pytest.mark.parametrize("kind", ["response", "bifurcation", "intervals", "poincare"])
def test_plot_refuses_a_file_with_damaged_eta_or_undeclared_codes(eta, regime, words, kind,
                                                                  tmp_path, monkeypatch,
                                                                  capfd):
    """plot drew a file with NaN in eta or regime codes its flag_values do not declare;
    every kind of sweep figure now refuses it in one line naming the variable."""
    _sweep_file(tmp_path / "s.nc", eta, regime)
    line = _refused(["plot", "s.nc", "--kind", kind, "-o", "p.png"], tmp_path,
                    monkeypatch, capfd)
    assert words in line


_TAMPERED = [("param_kh", "abc"), ("param_kh", -5.0), ("params", "{not json"),
             ("solver_rtol", 1e-3), ("preset", "fig11"), ("param_eta", None)]


def test_rerun_reports_a_file_whose_run_attributes_contradict_its_command(
        tmp_path, monkeypatch, capfd):
    """rerun said 'identical' for a file whose parameter attributes had been changed
    (param_kh = 'abc' or -5, params no longer JSON); it now compares the attributes that
    say what was computed with those the recorded command writes again, and reports all
    that differ by name (exit 1), while the untouched file stays identical."""
    import xarray as xr

    monkeypatch.chdir(tmp_path)
    rc, out, err = run_cli(["simulate", "--periods", "2", "--transient", "0", "-o",
                            "s.nc"], capfd)
    assert rc == 0, err
    rc, out, err = run_cli(["rerun", "s.nc"], capfd)
    assert rc == 0 and out.startswith("identical: "), (out, err)
    ds = xr.load_dataset("s.nc")
    for name, value in _TAMPERED:
        if value is None:
            del ds.attrs[name]
        else:
            ds.attrs[name] = value
    ds.to_netcdf("t.nc")
    rc, out, err = run_cli(["rerun", "t.nc"], capfd)
    assert rc == 1, (out, err)
    assert out.startswith(f"different: {len(_TAMPERED) - 1} of "), out  # kh counted once
    for name, _ in _TAMPERED:
        assert f"attribute {name}:" in out, (name, out)


def test_every_help_example_names_an_existing_preset():
    """The examples of every command's --help name only presets that exist (orbits'
    used '--preset duffing', which is not one)."""
    import re

    from vibimpact import presets
    from vibimpact.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if hasattr(a, "choices") and
               isinstance(a.choices, dict))
    named = []
    for command in sub.choices.values():
        examples = [ln for ln in (command.epilog or "").splitlines()
                    if ln.strip().startswith("vibimpact ")]
        named += re.findall(r"--preset[ =]([\w.-]+)", "\n".join(examples))
    assert named, "no --preset example found"
    unknown = sorted(set(named) - set(presets.names()))
    assert not unknown, unknown


def _map(vary=(0.0, 0.01), regime=((1, 3), (1, 1))):
    import xarray as xr

    shape = (2, 2)
    flags = {"flag_values": np.array([1, 2, 3, 4, 5, 0], dtype="i1"),
             "flag_meanings": "periodic quasi_periodic chaotic diverged unsettled "
                              "not_computed"}
    return xr.Dataset({"regime": (("B", "eta"), np.array(regime, dtype="i1"), flags),
                       "period": (("B", "eta"), np.ones(shape, dtype="i4")),
                       "label": (("B", "eta"), np.full(shape, "P1")),
                       "impacts_per_period": (("B", "eta"), np.ones(shape)),
                       "lyapunov": (("B", "eta"), np.full(shape, np.nan))},
                      coords={"B": list(vary), "eta": [1.0, 1.01]},
                      attrs={"map_vary": "B"})


@pytest.mark.parametrize("kw, words", [
    (dict(vary=(0.0, np.nan)), "B holds 1 non-finite"),
    (dict(regime=((1, 7), (1, 1))), "regime holds code(s) 7"),
])
def test_plot_map_refuses_a_damaged_grid_or_undeclared_codes(kw, words):
    """A map whose varied parameter holds NaN or whose regime holds a code outside its
    flag_values is refused by plot_map, naming the variable, before anything is drawn."""
    from vibimpact.plotting.map2d import plot_map

    with pytest.raises(ValueError, match=words.replace("(", r"\(").replace(")", r"\)")):
        plot_map(_map(**kw))
