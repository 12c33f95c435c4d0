"""What the commands do when not told is each model's declaration (issue 42, item 2): the
frequencies a sweep and a map cover, the preset and frequency a census and a basin image
look at (:attr:`vibimpact.models.Model.defaults`), never a value written into a command."""
import pytest

from vibimpact import models
from vibimpact.cli import build_parser, main
from vibimpact.cli.common.errors import UsageError
from vibimpact.models import presets
from vibimpact.models.presets import DEFAULT_KEYS, check_defaults, command_default


def _first():
    return models.get(models.names()[0])


def _parsed(*argv):
    return build_parser().parse_args(list(argv))


@pytest.mark.parametrize("command", ["classify", "bifurcation"])
def test_a_sweep_without_eta_covers_the_models_declared_frequencies(command):
    """Hypothesis: classify and bifurcation without --eta sweep the range the default
    preset's model declares, and with --preset the range that preset's model declares."""
    args = _parsed(command)
    assert args.eta == _first().defaults["frequencies"]
    for name in models.names():
        model = models.get(name)
        if model.presets and "frequencies" in model.defaults:
            preset = next(iter(model.presets))
            assert _parsed(command, "--preset", preset).eta == model.defaults["frequencies"]


def test_a_map_without_eta_covers_the_models_coarser_grid():
    """Hypothesis: map without --eta covers the model's declared map grid, which differs
    from its sweep range (a map is a sweep per row: coarser by declaration)."""
    args = _parsed("map", "--vary", "G=0.1,0.2")
    assert args.eta == _first().defaults["map_frequencies"] != _first().defaults["frequencies"]


@pytest.mark.parametrize("command", ["attractors", "basins"])
def test_a_census_without_preset_or_eta_looks_where_the_model_declares(command):
    """Hypothesis: attractors and basins with neither --preset nor --eta use the census
    preset and frequency the first model declares; with another model's preset and no
    --eta, that preset's model's (a declared one, else the preset's own frequency)."""
    args = _parsed(command)
    assert args.preset == _first().defaults["census_preset"]
    assert float(args.eta) == _first().defaults["census_frequency"]
    for name in models.names():
        model = models.get(name)
        for preset in model.presets:
            want = model.defaults.get("census_frequency")
            if want is None:
                want = getattr(presets.get(preset), model.param_names[model.omega_index])
            assert float(_parsed(command, "--preset", preset).eta) == want, preset


def test_a_given_option_wins_over_the_declaration():
    """Hypothesis: what the user gives is used as given; only what is left out is looked
    up."""
    args = _parsed("basins", "--preset", "fig8", "--eta", "1.2")
    assert (args.preset, args.eta) == ("fig8", 1.2)
    assert _parsed("classify", "--eta", "1.0:1.1:0.05").eta == "1.0:1.1:0.05"


def test_a_sweep_of_a_model_that_declares_no_frequencies_asks_for_eta(capfd, tmp_path,
                                                                       monkeypatch):
    """Hypothesis: a sweep of a model that declares no frequencies is refused with one
    line that names --eta and the preset, exit 2, nothing written; never swept over
    another model's range."""
    undeclared = [n for n in models.names() if models.get(n).presets
                  and "frequencies" not in models.get(n).defaults]
    assert undeclared, "every built-in model declares frequencies: nothing to test"
    monkeypatch.chdir(tmp_path)
    for name in undeclared:
        preset = next(iter(models.get(name).presets))
        for command in (["classify"], ["bifurcation"], ["map", "--vary", "A=0.1,0.2"]):
            out = "x.png" if command[0] == "bifurcation" else "x.nc"
            rc = main([*command, "--preset", preset, "--no-progress", "-o", out])
            err = capfd.readouterr().err.strip().splitlines()
            assert rc == 2 and len(err) == 1, (command, err)
            assert "--eta" in err[0] and preset in err[0], err
            assert list(tmp_path.iterdir()) == []


def test_help_says_what_the_default_is_without_loading_a_model(capfd):
    """Hypothesis: --help of every command whose default the model declares says in
    words where the default comes from (no object's repr, no value of one model)."""
    for command in ("classify", "bifurcation", "map", "attractors", "basins"):
        with pytest.raises(SystemExit):
            build_parser().parse_args([command, "--help"])
        text = capfd.readouterr().out
        assert "ModelDefault" not in text and "object at" not in text
        assert "the preset's model declares" in " ".join(text.split()) or \
            "the census preset" in " ".join(text.split()), command


def test_the_presets_command_lists_each_models_defaults(capfd):
    """Hypothesis: 'vibimpact presets' ends with one line per model with presets, saying
    the sweep range (or that --eta is needed) and the census preset and frequency, the
    values command_default gives."""
    assert main(["presets"]) == 0
    lines = capfd.readouterr().out.splitlines()
    for name in models.names():
        model = models.get(name)
        if not model.presets:
            continue
        first = next(iter(model.presets))
        line = [ln for ln in lines if ln.strip().startswith(f"{name}: ")]
        assert len(line) == 1, name
        sweep = command_default("frequencies", first)
        assert (sweep in line[0]) if sweep else ("need --eta" in line[0])
        where = command_default("census_preset", first)
        assert f"{where} at {command_default('census_frequency', where):g}" in line[0]


@pytest.mark.parametrize("defaults,needle", [
    ({"sweep": "0:1:0.1"}, "unknown key 'sweep'"),
    ({"census_preset": "nowhere"}, "census_preset 'nowhere'"),
    ({"frequencies": "0.9-1.5"}, "frequencies must be a range"),
    ({"map_frequencies": 1.0}, "frequencies must be a range"),
    ({"census_frequency": -1.0}, "census_frequency must be a positive number"),
    ({"census_frequency": True}, "census_frequency must be a positive number")])
def test_a_declaration_that_cannot_work_is_refused_naming_the_model(defaults, needle):
    """Hypothesis: a model's defaults with an unknown key, a census preset it does not
    declare or a value of the wrong kind is refused when the model is made, with a
    ValueError that names the model and the key."""
    with pytest.raises(ValueError, match="model 'mine'") as info:
        check_defaults("mine", defaults, {"only": ({}, "")})
    assert needle in str(info.value)


def test_command_default_refuses_an_unknown_key():
    """Hypothesis: asking for a default no model can declare is a ValueError naming the
    keys there are."""
    with pytest.raises(ValueError, match="key must be one of"):
        command_default("colour")
    assert set(DEFAULT_KEYS) >= {"frequencies", "census_preset", "census_frequency"}



def test_the_continued_parameter_defaults_to_the_models_frequency():
    """Hypothesis: 'continue' without --param and 'continue2' without --param1 take the
    forcing frequency of the preset's model (what --eta sets), looked up from the model,
    not a name written into the command."""
    from vibimpact.cli import continue_, continue2

    for name in models.names():
        model = models.get(name)
        for preset in list(model.presets)[:1]:
            args = _parsed("continue", "--preset", preset, "--stop", "1.2")
            assert args.param is None
            continue_._inputs(args)
            assert args.param == model.frequency_name
            args = _parsed("continue2", "--preset", preset, "--kind", "fold", "--param2",
                           model.param_names[0], "--range2", "0:1")
            assert args.param1 is None
            try:
                continue2._inputs(args)
            except UsageError:  # a later check may refuse this request; the default is set
                pass
            assert args.param1 == model.frequency_name
