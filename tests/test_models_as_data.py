"""Models wholly as data (issue 42, item 2): everything about one built-in model lives in
its two model files, ``vibimpact/builtin_models/<name>.py`` and
``vibimpact/_kernel/<family>.py``; no other module of the package names a built-in model
or one of its distinctive parameters."""
import ast
import pathlib
import re

import numpy as np
import pytest

import vibimpact as vi
from vibimpact import models

PKG = pathlib.Path(vi.__file__).resolve().parent


def _families():
    """The kernel families of the registered built-in models."""
    return {m.kernel_model.family for m in (models.get(n) for n in models.names())}


def _model_files():
    """The two files of every built-in model (relative to the package)."""
    files = {f"builtin_models/{n}.py" for n in models.names()}
    return files | {f"_kernel/{f}.py" for f in _families()} | {"builtin_models/__init__.py"}


def _scanned_params():
    """The built-in models' parameter names that say which model they belong to: two
    characters or more and not a Greek letter's name.  One-letter names (``B``, ``G``,
    ``f``, ``k``, ``c``, ``d``, ``A``) are every model's and every formula's symbols, and
    Greek letters (``eta``, ``eps``, ``delta``, ``alpha``, ...) are the conventional names
    any model, a user's included, gives its parameters (``eta`` is also the package's
    name of the swept frequency's coordinate, ``alpha`` matplotlib's transparency): a
    generic module using them says nothing about one model.  What remains (``kh``,
    ``Ec``, ``Rr``, ``Jr``, ...) is one model's vocabulary."""
    greek = {"alpha", "beta", "gamma", "delta", "eps", "epsilon", "zeta", "eta", "theta",
             "kappa", "lambda", "mu", "nu", "xi", "omega", "phi", "psi", "sigma", "tau"}
    out = set()
    for n in models.names():
        out |= {p for p in models.get(n).param_names if len(p) > 1 and p not in greek}
    return out


def _docstrings(tree):
    """The docstring nodes of ``tree`` (module, classes, functions)."""
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef,
                             ast.AsyncFunctionDef)) and node.body and \
                isinstance(node.body[0], ast.Expr) and \
                isinstance(node.body[0].value, ast.Constant) and \
                isinstance(node.body[0].value.value, str):
            out.add(id(node.body[0].value))
    return out


def _hits(tree, model_names, params):
    """What in ``tree``'s code names a built-in model or a scanned parameter."""
    word = re.compile(r"(?<![A-Za-z0-9_])(%s)(?![A-Za-z0-9_])" % "|".join(
        re.escape(n) for n in sorted(model_names, key=len, reverse=True)))
    ident = re.compile(r"(^|_)(%s)(_|$)" % "|".join(re.escape(n) for n in model_names))
    docs = _docstrings(tree)
    hits = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and \
                id(node) not in docs:
            if node.value in params or word.search(node.value):
                hits.add(repr(node.value) if len(node.value) < 40 else
                         repr(word.search(node.value).group(1)))
        names = []
        if isinstance(node, ast.Name):
            names = [node.id]
        elif isinstance(node, ast.Attribute):
            names = [node.attr]
        elif isinstance(node, (ast.FunctionDef, ast.ClassDef, ast.AsyncFunctionDef)):
            names = [node.name]
        elif isinstance(node, ast.keyword) and node.arg:
            names = [node.arg]
        elif isinstance(node, ast.alias):
            names = [node.asname or node.name.split(".")[-1]]
        elif isinstance(node, ast.arg):
            names = [node.arg]
        for n in names:
            if n in params or ident.search(n.lower()):
                hits.add(n)
    return hits


def _scan():
    own = _model_files()
    model_names = set(models.names())
    params = _scanned_params()
    found = {}
    for path in sorted(PKG.rglob("*.py")):
        rel = path.relative_to(PKG).as_posix()
        if rel in own:
            continue
        hits = _hits(ast.parse(path.read_text(), filename=str(path)), model_names, params)
        if hits:
            found[rel] = hits
    return found


def test_no_generic_module_names_a_builtin_model():
    """Hypothesis: outside the built-in models' own files, no module's code (string
    constants that are not docstrings, names, attributes, keywords, arguments, imports)
    names a built-in model (``"rotor"``, ``ROTOR``, ``_rotor``, ``"the rotor's ..."``) or
    one of the parameter names that belong to one model (:func:`_scanned_params`).

    Prose in docstrings and comments may still use the paper's rotor as an example; what
    is checked is code, which is where a model name becomes a branch or a default.  No
    exception: a model's citation is its own (``Model.references``)."""
    found = _scan()
    assert not found, found


def test_the_scan_finds_model_knowledge():
    """Hypothesis: the scan is not vacuous: it finds a model's name in a message and a
    default, and a distinctive parameter name as a string or keyword, and passes over
    the same words in a docstring."""
    names, params = set(models.names()), _scanned_params()
    assert {"kh", "Ec", "Jr"} <= params and not {"eta", "B", "f", "omega"} & params
    code = ('"""The rotor\'s module: kh and Ec."""\n'
            'def f(ds, p):\n'
            '    """For the rotor."""\n'
            '    name = ds.attrs.get("model", "rotor")\n'
            '    raise ValueError(f"only the rotor has {name}")\n'
            '    return p.replace(kh=1.0), "Ec", ROTOR_VAR\n')
    hits = _hits(ast.parse(code), names, params)
    assert hits == {"'rotor'", "'only the rotor has '", "kh", "'Ec'", "ROTOR_VAR"}, hits


@pytest.mark.parametrize("name", ["rotor", "duffing"])
def test_parameter_sets_live_in_their_model_modules(name):
    """Hypothesis: a built-in model's parameter set is defined in its own module and is
    still importable under its old path and as ``vi.<Name>``."""
    from vibimpact.models import params as old

    pset = models.get(name).param_set
    assert pset.__module__ == f"vibimpact.builtin_models.{name}"
    assert getattr(old, pset.__name__) is pset is getattr(vi, pset.__name__)


def _sweep(model, xm):
    """A hand-made up sweep of three points of ``model`` (None: no ``model`` attribute)
    with response maxima ``xm`` (X_m and Y_m alike)."""
    import numpy as np
    import xarray as xr

    ds = xr.Dataset({"regime": ("eta", np.array([1, 1, 3], dtype="i1")),
                     "X_m": ("eta", np.asarray(xm, float)),
                     "Y_m": ("eta", np.asarray(xm, float))},
                    coords={"eta": [1.0, 1.1, 1.2]}, attrs={"sweep_direction": "up"})
    if model is not None:
        ds.attrs["model"] = model
    return ds


def test_response_plots_use_the_models_own_names():
    """Hypothesis: the rotor's response panels keep its words (X, Y in clearances, the
    retainer clearance at 1, eta as η), taken from its PlotSpec; a user model's sweep
    with maxima is labelled by the variables alone, with no obstacle line."""
    import matplotlib

    matplotlib.use("Agg")
    from vibimpact.plotting import plot_response

    fig = plot_response(_sweep("rotor", [0.5, 0.9, 1.05]), bands=False)
    assert [a.get_ylabel() for a in fig.axes] == ["X_m  (max |X| / clearance)",
                                                 "Y_m  (max |Y| / clearance)"]
    assert fig.axes[-1].get_xlabel() == "η"
    assert "retainer clearance" in [t.get_text() for t in fig.axes[0].get_legend().texts]
    user = plot_response(_sweep("linear", [0.5, 0.9, 1.05]), bands=False)
    assert [a.get_ylabel() for a in user.axes] == ["X_m  (max |X|)", "Y_m  (max |Y|)"]
    assert all(line.get_linestyle() != "--" for line in user.axes[0].lines)


@pytest.mark.parametrize("model", ["linear", "duffing"])
def test_a_response_plot_the_data_cannot_draw_is_refused_in_one_line(model):
    """Hypothesis: a sweep whose points hold no response maxima (a user model's, the
    Duffing oscillator's: no planar contact) is refused with one line naming the model,
    not drawn as empty axes labelled with the rotor's clearance."""
    from vibimpact.plotting import plot_response

    with pytest.raises(ValueError, match=f"^the sweep of the {model} model records no "
                                         "response maxima") as err:
        plot_response(_sweep(model, [float("nan")] * 3))
    assert "\n" not in str(err.value)


def test_a_file_naming_no_model_is_refused_not_read_as_the_rotors():
    """Hypothesis: a sweep dataset without a ``model`` attribute is refused in one line
    by the plots and by the reader of recorded parameters, never taken for the rotor."""
    from vibimpact.io.recorded import recorded_model
    from vibimpact.plotting import plot_response

    with pytest.raises(ValueError, match=r"^ds names no model \(no 'model' attribute\)"):
        plot_response(_sweep(None, [0.5, 0.9, 1.05]), bands=False)
    with pytest.raises(ValueError, match=r"^the file names no model") as err:
        recorded_model({"param_kh": 120.0})
    assert "\n" not in str(err.value)


def test_the_presets_come_from_the_models_declarations():
    """Hypothesis: every preset is one model's declaration, ``vi.presets.get`` gives that
    model's parameter set with the declared values, and the default preset is the first
    model's declared one."""
    for name in vi.presets.names():
        model = vi.presets.model_of(name)
        values, _ = model.presets[name]
        p = vi.presets.get(name)
        assert type(p) is model.param_set and \
            all(getattr(p, k) == v for k, v in values.items())
    first = models.get(models.names()[0])
    assert vi.presets.DEFAULT == first.default_preset and \
        vi.presets.get() == vi.presets.get(first.default_preset)


@pytest.mark.parametrize("model, text, markdown", [("rotor", "eta from", "| η from |"),
                                                   ("duffing", "omega from", "| ω from |"),
                                                   ("linear", "eta from", "| η from |")])
def test_interval_tables_name_the_models_forcing_frequency(model, text, markdown):
    """Hypothesis: the interval tables' columns are named after the swept model's forcing
    frequency (the Duffing oscillator's omega, not eta); a model this installation does
    not know keeps the sweeps' coordinate name."""
    import numpy as np
    import xarray as xr

    from vibimpact.sweeps.dataset import format_intervals, intervals

    ds = xr.Dataset({"label": ("eta", np.array(["P1", "P1", "chaotic"], dtype=object)),
                     "regime": ("eta", np.array([1, 1, 3], dtype="i1")),
                     "period": ("eta", np.array([1, 1, 0], dtype="i4")),
                     "impacts_per_period": ("eta", np.array([0.0, 0.0, 1.5])),
                     "arcs": ("eta", np.array(["", "", ""], dtype=object))},
                    coords={"eta": [1.0, 1.1, 1.2]},
                    attrs={"sweep_direction": "up", "model": model})
    iv = intervals(ds)
    assert format_intervals(iv).splitlines()[0].split()[1:3] == text.split()
    assert markdown in iv.to_markdown().splitlines()[0]


@pytest.mark.parametrize("p", [vi.DuffingParams(delta=0.3, alpha=1.0, beta=0.0, gamma=0.2,
                                                omega=1.3),
                               vi.presets.get("hard-impact"), vi.presets.get("fig8")],
                         ids=["duffing", "hard_impact", "rotor"])
def test_a_sweep_file_records_its_models_frequency_by_name(p, tmp_path):
    """Hypothesis: a sweep's file records the name of its model's forcing frequency
    (``frequency_name``: the parameter at omega_index, ``omega`` for the Duffing
    oscillator) and describes its coordinate in the model's words (the declared
    ``frequency_text``, else "forcing frequency NAME"), through a write and a read."""
    model = models.of_params(p)
    freq = model.param_names[model.omega_index]
    ds = vi.sweep(p, [1.0, 1.05], analyses=("period",), continuation=False)
    vi.io.write_netcdf(ds, tmp_path / "s.nc")
    with vi.io.read_netcdf(tmp_path / "s.nc") as back:
        assert back.attrs["frequency_name"] == freq == model.frequency_name
        want = (model.plot.frequency_text if model.plot is not None else "") or \
            f"forcing frequency {freq}"
        assert back["eta"].attrs["long_name"] == want
        assert freq not in json_params(back)


def json_params(ds):
    """The parameters a sweep file records (its ``params`` attribute)."""
    import json

    return json.loads(ds.attrs["params"])


#: words of the rotor's files: a file of another model that says one of them describes
#: that model in the rotor's terms
ROTOR_WORDS = ("retainer", "clearance", "tau", "dR/dtau", "atan2", "R - 1")


@pytest.mark.parametrize("preset", ["hard-impact", "soft-impact"])
def test_no_file_of_another_model_speaks_of_the_rotor(preset, tmp_path):
    """Hypothesis: the texts of a run's, a sweep's and a census' files of a model that
    is not the rotor (every long_name, every state's words, the interval map's) use that
    model's words (its states, its frequency's name, its obstacle), none of the rotor's:
    nothing falls back to the rotor's descriptions."""
    p = vi.presets.get(preset)
    texts = []

    def collect(ds):
        texts.extend(str(v) for v in ds.attrs.values() if isinstance(v, str)
                     and not str(v).startswith(("vibimpact ", "[")))
        for var in ds.variables.values():
            texts.extend(str(v) for v in var.attrs.values() if isinstance(v, str))

    run = vi.simulate(p, periods=3, transient=2)
    collect(run.to_dataset())
    sweep = vi.sweep(p, [p.eta, p.eta * 1.01], continuation=False)
    collect(sweep)
    collect(vi.sweeps.intervals(sweep).dataset)
    census = vi.attractors(vi.System(p), starts=3, seed=0)
    collect(census)
    said = [t for t in texts if any(w in t for w in ROTOR_WORDS)
            and "params" not in t and "command" not in t]
    assert said == [], said
    assert len(texts) > 50  # the scan read the files' texts


def test_a_branch_continues_the_models_own_frequency_by_default():
    """Hypothesis: follow_branch without ``param`` continues the model's forcing
    frequency (the Duffing oscillator's ``omega``), not a parameter named after the
    rotor's; the branch says so and ends at ``stop``."""
    from vibimpact.continuation.branches import follow_branch

    p = vi.DuffingParams(delta=0.3, alpha=1.0, beta=0.0, gamma=0.2, omega=1.3)
    branch, _ = follow_branch(p, stop=1.35, transient=50)
    assert branch.param == "omega"
    assert np.isclose(branch.values[0], 1.3) and np.isclose(branch.values[-1], 1.35)


def test_a_bare_point_result_assumes_no_models_size():
    """Hypothesis: a PointResult made without a model has arrays of no state (not the
    rotor's four), and ``empty(d, m)`` has the model's ``d``."""
    from vibimpact.points.point import PointResult

    bare = PointResult()
    assert bare.final_state.size == bare.multipliers.size == bare.samples.size == 0
    sized = PointResult.empty(2, 8)
    assert sized.samples.shape == (8, 2) and sized.multipliers.shape == (2,)


def test_a_parameter_sets_period_is_over_the_models_own_frequency():
    """Hypothesis: every built-in parameter set's period is 2 pi over the model's forcing
    frequency (one declaration, ParamsMixin's, for hand-written and table-made sets),
    and a model whose set names another frequency than its omega_index is refused."""
    import dataclasses
    import math

    for name in models.names():
        model = models.get(name)
        p = model.param_set()
        assert p.period == 2.0 * math.pi / getattr(p, model.frequency_name), name
    rotor = models.get("rotor")
    wrong = dataclasses.make_dataclass("Wrong", [], bases=(rotor.param_set,), frozen=True,
                                       namespace={"_FREQUENCY": "G"})
    with pytest.raises(ValueError, match="forcing frequency 'G'"):
        vi.models.Model.builtin_model("wrong", "rotor", rotor.state_names,
                                      rotor.omega_index, wrong)
