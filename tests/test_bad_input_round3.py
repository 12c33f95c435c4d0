"""Bad input of the third adversarial round (issue 32, part 1): parameters that come in
as plain vectors or mappings, arrays and flags that were coerced, and analysers fed
extreme or too few values.  Each case is refused with a ValueError naming the argument
(or the parameter), before any integration."""
import inspect
import math

import numpy as np
import pytest
from numba import njit

import vibimpact as vi
from vibimpact.models.params import Domain


def _outside(dom):
    """A finite value just outside ``dom`` (its lower bound, or below it)."""
    return dom.lo if not dom.lo_closed else dom.lo - 1.0


def _bounded(model):
    """(name, index, domain) of each parameter of ``model`` that has a lower bound."""
    return [(n, i, model.domain(i)) for i, n in enumerate(model.param_names)
            if math.isfinite(model.domain(i).lo)]


# every way parameters come in: a parameter set, a mapping, a plain vector (System and
# simulate), and a changed parameter of a System built from a vector
_WAYS = {
    "param_set": lambda m, name, v: m.param_set(**{name: v}),
    "mapping": lambda m, name, v: vi.System({name: v}, model=m),
    "System(vector)": lambda m, name, v: vi.System(_vector(m, name, v), model=m),
    "simulate(vector)": lambda m, name, v: vi.simulate(_vector(m, name, v), periods=1,
                                                        model=m),
    "with_param": lambda m, name, v: vi.System(m.param_set().as_array(),
                                               model=m).with_param(name, v),
    "with_params": lambda m, name, v: vi.System(m.param_set().as_array(),
                                                model=m).with_params(**{name: v}),
}


def _vector(model, name, value):
    vec = model.param_set().as_array()
    vec[model.param_names.index(name)] = value
    return vec


@pytest.mark.parametrize("way", sorted(_WAYS))
@pytest.mark.parametrize("model_name", vi.models.names())
def test_every_way_in_refuses_a_parameter_outside_its_domain(model_name, way):
    """Every built-in model's parameters are checked the same way whichever form they
    come in: a value just outside a parameter's domain (f = -1, eta = 0, ...), NaN and
    inf each raise a ValueError that starts with the parameter's name."""
    model = vi.models.get(model_name)
    for name, _, dom in _bounded(model):
        for value in (_outside(dom), math.nan, math.inf):
            with pytest.raises(ValueError, match=rf"^{name} must be"):
                _WAYS[way](model, name, value)


@pytest.mark.parametrize("way", sorted(_WAYS))
def test_every_way_in_refuses_nan_in_an_unbounded_parameter(way):
    """A parameter with no bounds (the rotor's k3 and G) is still refused as NaN, in
    every form, so that no NaN reaches the solver (it ran to Status.OK, or failed deep as
    a step-size underflow)."""
    for name in ("k3", "G"):
        with pytest.raises(ValueError, match=rf"^{name} must be finite"):
            _WAYS[way](vi.ROTOR, name, math.nan)


def test_raw_vector_with_forcing_frequency_nan_returns_at_once():
    """simulate of a raw vector with eta = NaN (which never returned) raises naming eta."""
    with pytest.raises(ValueError, match="^eta must be finite"):
        vi.simulate(_vector(vi.ROTOR, "eta", math.nan), periods=1, model=vi.ROTOR)


@pytest.mark.parametrize("vec, match", [
    (np.ones(3), r"^p must have 11 parameters"),
    (np.ones((1, 11)), r"^p must be 1-D"),
    (np.array(["0.1"] * 11), r"^p must be"),
    (np.full(11, 1 + 1j), r"imaginary part"),
    ({"kh": "abc"}, r"^kh must be a real number"),
    ({"nope": 1.0}, r"^p: unknown parameter nope"),
])
def test_parameter_vector_of_wrong_form_is_refused(vec, match):
    """A vector of the wrong length or shape, strings, complex numbers, a mapping with a
    string value or an unknown name: each is a ValueError naming p or the parameter."""
    with pytest.raises(ValueError, match=match):
        vi.System(vec, model=vi.ROTOR)


@njit
def _rhs(s, y, p, mode, out):
    out[0] = y[1]
    out[1] = p[1] * math.cos(p[2] * s) - p[0] * y[1] - y[0]


@njit
def _jac(s, y, p, mode, J):
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0] = -1.0
    J[1, 1] = -p[0]


@njit
def _switches(s, y, p, mode, g):
    g[0] = y[1]


@njit
def _transition(s, y, p, mode, which):
    return


@njit
def _init_mode(s, y, p, mode):
    mode[0] = 0


def _user(domains=None):
    return vi.Model.from_functions("lin", _rhs, _jac, _switches, _transition, _init_mode,
                                   terminal=[0], state_names=("x", "v"),
                                   param_names=("c", "F", "w"), omega_index=2,
                                   domains=domains)


def test_user_model_declared_ranges_are_checked_like_a_builtin_models():
    """A user model's declared domain (c >= 0) is checked for a vector and a mapping and
    read by param_domain; its forcing frequency is > 0 even when undeclared, and every
    parameter must be finite."""
    model = _user({"c": Domain.at_least(0.0)})
    with pytest.raises(ValueError, match=r"^c must be >= 0, got -0.5"):
        vi.System([-0.5, 1.0, 1.0], model=model)
    with pytest.raises(ValueError, match=r"^c must be >= 0"):
        vi.System({"c": -0.5, "F": 1.0, "w": 1.0}, model=model)
    with pytest.raises(ValueError, match=r"^p: missing parameter F"):
        vi.System({"c": 0.5, "w": 1.0}, model=model)
    with pytest.raises(ValueError, match=r"^w must be > 0"):
        vi.System([0.5, 1.0, 0.0], model=_user())
    with pytest.raises(ValueError, match=r"^F must be finite"):
        vi.System([0.5, math.nan, 1.0], model=_user())
    assert vi.System([0.5, 1.0, 1.0], model=model).param_domain("c") == Domain.at_least(0.0)


@pytest.mark.parametrize("domains, match", [
    ({"nope": Domain()}, r"^domains: 'nope' is not a parameter"),
    ({"c": (0, 1)}, r"^domains\['c'\] must be a vibimpact.models.params.Domain"),
    ([("c", Domain())], r"^domains must be a mapping"),
])
def test_user_model_domains_of_wrong_form_are_refused(domains, match):
    """Model.from_functions refuses declared ranges that name no parameter or are not
    Domains."""
    with pytest.raises(ValueError, match=match):
        _user(domains)


def _public_modules():
    """Every public module of the package (no part of its name starts with ``_``)."""
    import importlib
    import pkgutil

    return [importlib.import_module(m.name)
            for m in pkgutil.walk_packages(vi.__path__, "vibimpact.")
            if not any(part.startswith("_") for part in m.name.split("."))]


def _public_functions():
    """(qualified name, function, flag argument, None allowed) of every public function
    defined in a public module that takes an argument annotated ``bool`` or
    ``bool | None``."""
    from vibimpact.base._validate import flag_annotation

    out, seen = [], set()
    for module in _public_modules():
        for name, fn in vars(module).items():
            if (name.startswith("_") or not inspect.isfunction(fn) or id(fn) in seen
                    or fn.__module__ != module.__name__):
                continue
            seen.add(id(fn))
            for arg, prm in inspect.signature(fn).parameters.items():
                optional = flag_annotation(prm.annotation)
                if optional is not None:
                    out.append((f"{module.__name__}.{name}", fn, arg, optional))
    return out


_FLAGS = _public_functions()


def test_the_enumeration_finds_flags_in_every_layer():
    """The enumeration finds bool and bool | None arguments of functions outside the
    package's ``__all__`` lists (so the rule cannot pass by finding none)."""
    names = {f"{q}:{a}" for q, _, a, _ in _FLAGS}
    assert {"vibimpact.analysis.lyapunov.lyapunov_spectrum:floquet",
            "vibimpact.io.write_netcdf:overwrite",
            "vibimpact.io.check_output_path:store",
            "vibimpact.census.basins.write_basins:overwrite",
            "vibimpact.plotting.map2d.plot_map:categorical"} <= names
    assert any(optional for *_, optional in _FLAGS)


_NOT_BOOLS = ["no", "False", 1, np.array([True])]


@pytest.mark.parametrize("qualname, fn, arg, optional", _FLAGS,
                         ids=[f"{q}:{a}" for q, _, a, _ in _FLAGS])
def test_every_public_flag_refuses_what_is_not_a_bool(qualname, fn, arg, optional):
    """A flag of any public function refuses a string ('no' is true to Python), an int
    or an array with a ValueError naming the argument, before the function looks at its
    other arguments (none are given); None too where the annotation is plain bool."""
    for value in _NOT_BOOLS + ([] if optional else [None]):
        with pytest.raises(ValueError, match=rf"^{arg} must be True or False"):
            fn(**{arg: value})


def test_checks_flags_passes_none_on_for_an_optional_flag():
    """checks_flags lets None through for ``bool | None`` (it means "decide") but not
    for ``bool``, and refuses a string for both."""
    from vibimpact.base._validate import checks_flags

    @checks_flags
    def f(a: bool = False, b: bool | None = None):
        return a, b

    assert f(True, None) == (True, None)
    with pytest.raises(ValueError, match="^a must be True or False"):
        f(None)
    with pytest.raises(ValueError, match="^b must be True or False"):
        f(b="no")


def test_write_netcdf_with_overwrite_no_keeps_the_existing_file(tmp_path):
    """overwrite='no' (a true string) is refused and the existing file is untouched,
    for the NetCDF writer and the basins writer."""
    import xarray as xr

    target = tmp_path / "s.nc"
    target.write_bytes(b"keep")
    ds = xr.Dataset({"x": ("i", np.arange(2.0))})
    for write in (vi.io.write_netcdf, vi.census.basins.write_basins):
        with pytest.raises(ValueError, match="^overwrite must be True or False"):
            write(ds, target, overwrite="no")
        assert target.read_bytes() == b"keep"


# --- arrays that were coerced instead of checked ------------------------------------

_SYS = None


def _system():
    global _SYS
    if _SYS is None:
        _SYS = vi.System(vi.presets.get("fig8"))
    return _SYS


_BAD_STATES = {
    "complex": (np.array([0.1 + 1j, 0, 0, 0]), "imaginary part"),
    "digit strings": (["0.1", "0", "0", "0"], "must be"),
    "object strings": (np.array(["a", "b", "c", "d"], dtype=object), "must be"),
    "booleans": ([True, False, False, False], "must be"),
    "nan": ([math.nan, 0, 0, 0], "finite"),
}

_STATE_TAKERS = {
    "simulate": lambda s, v: vi.simulate(s, 1, state0=v),
    "sweep": lambda s, v: vi.sweep(s, [1.0, 1.01], state0=v, analyses=("period",)),
    "map2d": lambda s, v: vi.map2d(s, [1.0], {"B": [0.01]}, state0=v, analyses=("period",)),
    "lyapunov_spectrum": lambda s, v: vi.analysis.lyapunov_spectrum(s, v),
    "classify_params": lambda s, v: vi.classify_params(s, v),
    "monodromy": lambda s, v: s.monodromy(v),
    "shoot_periodic_orbit": lambda s, v: vi.analysis.shoot_periodic_orbit(s, v),
    "basins(base)": lambda s, v: vi.basins(s, grid=(5, 5), base=v),
    "hunt_orbits(seeds)": lambda s, v: vi.hunt_orbits(s, [1], seeds=[v]),
    "attractors(starts)": lambda s, v: vi.attractors(s, starts=np.array([v])),
}


@pytest.mark.parametrize("taker", sorted(_STATE_TAKERS))
def test_a_state_that_is_not_real_numbers_is_refused_everywhere(taker):
    """Every function that takes a state refuses a complex state (whose imaginary part was
    dropped), digit strings (read as numbers), an object array of strings (read as
    zeros), booleans and NaN with a ValueError naming the state argument."""
    for kind, (value, words) in _BAD_STATES.items():
        with pytest.raises(ValueError, match=rf"^(state0|base|seeds|starts)\b.*{words}"):
            _STATE_TAKERS[taker](_system(), value)


_BAD_GRIDS = {
    "digit strings": ["1.0", "1.01"],
    "object strings": np.array(["1.0", "1.01"], dtype=object),
    "complex": [1.0 + 0j, 1.01 + 0j],
    "booleans": [True, True],
}

_GRID_TAKERS = {
    "sweep(eta)": (lambda s, v: vi.sweep(s, v, analyses=("period",)), "eta"),
    "map2d(eta)": (lambda s, v: vi.map2d(s, v, {"B": [0.01]}, analyses=("period",)),
                   "eta"),
    "map2d(vary)": (lambda s, v: vi.map2d(s, [1.0], {"B": v}, analyses=("period",)),
                    "vary B"),
    "attractors(eta)": (lambda s, v: vi.attractors(s, v, starts=2), "eta"),
    "detect_period": (lambda s, v: vi.analysis.detect_period(v), "points"),
    "extrapolate_limit": (lambda s, v: vi.analysis.extrapolate_limit(v), "seq"),
}


@pytest.mark.parametrize("taker", sorted(_GRID_TAKERS))
def test_a_grid_or_series_that_is_not_real_numbers_is_refused(taker):
    """Grids of eta (and of a varied parameter) and the analysers' series refuse strings
    (sweep(eta=['1.0', '1.01']) ran), complex numbers and booleans, naming the argument."""
    fn, name = _GRID_TAKERS[taker]
    for kind, value in _BAD_GRIDS.items():
        with pytest.raises(ValueError, match=rf"^({name})\b"):
            fn(_system(), value)


def test_solver_setting_adaptive_no_is_refused():
    """SolverSettings(adaptive='no') (true to Python) is refused naming adaptive."""
    with pytest.raises(ValueError, match=r"^adaptive must be True or False"):
        vi.SolverSettings(adaptive="no")


# --- analysers at extreme magnitudes and with too few points ------------------------

_CYCLE = np.tile([[1.0, 2.0], [-1.0, 3.0]], (20, 1))


@pytest.mark.parametrize("factor", [1.0, 1e308 / 3.0, 1e-308, 1e-320, 1e-200, 1e200])
def test_detect_period_is_the_same_at_every_magnitude(factor):
    """A clean 2-cycle is period 2 whatever its magnitude: near 1e308 the differences
    overflowed to inf and lag 1 was accepted; subnormal values fell under an absolute
    floor.  The windowed detector agrees."""
    from vibimpact.analysis.period import detect_period_windows

    assert vi.analysis.detect_period(_CYCLE * factor) == 2
    assert detect_period_windows(_CYCLE * factor, (12, 40)) == 2


def test_detect_period_of_mixed_magnitudes_and_extreme_constants():
    """A 2-cycle near the largest float with a subnormal second component is period 2; a
    constant at the largest float and the zero sequence are period 1; a 2-cycle between
    +-1.7e308 (whose difference overflows) is period 2."""
    mixed = _CYCLE.copy()
    mixed[:, 0] *= 5e307
    mixed[:, 1] = 1e-320
    assert vi.analysis.detect_period(mixed) == 2
    assert vi.analysis.detect_period(np.full((20, 1), 1.7e308)) == 1
    assert vi.analysis.detect_period(np.zeros((20, 2))) == 1
    assert vi.analysis.detect_period(np.tile([[1.7e308], [-1.7e308]], (20, 1))) == 2


@pytest.mark.parametrize("m", [1, 2])
def test_extrapolate_limit_of_too_few_iterates_is_refused(m):
    """extrapolate_limit of fewer than 3 iterates (it returned NaNs without a word) is a
    ValueError naming seq and saying how many it needs."""
    with pytest.raises(ValueError, match=r"^seq must hold at least 3 iterates"):
        vi.analysis.extrapolate_limit(np.ones((m, 2)))


@pytest.mark.parametrize("fn, arg, name", [
    ("test01", [1.0], "series"),
    ("lyapunov_from_series", [1.0, 2.0], "series"),
    ("classify", np.zeros((1, 2)), "points"),
    ("torus_evidence", np.zeros((2, 2)), "points"),
    ("lyapunov_from_jacobians", np.zeros((1, 2, 2)), "jacobians"),
])
def test_analysers_refuse_too_few_points_naming_the_argument(fn, arg, name):
    """Every analyser that cannot answer from too few points says so, naming its data
    argument, instead of returning NaN."""
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        getattr(vi.analysis, fn)(arg)


# --- continued_state ---------------------------------------------------------------

def test_continued_state_takes_a_parameter_set_a_system_or_a_preset_name():
    """continued_state gives the same state from a parameter set, a System (which raised
    AttributeError) and a preset's name (which raised a raw TypeError)."""
    from vibimpact.sweeps.sweep import continued_state

    p = vi.presets.get("fig8")
    kw = dict(eta_start=1.0, step=0.05, transient=2)
    a = continued_state(p, 1.05, **kw)
    np.testing.assert_array_equal(a, continued_state(vi.System(p), 1.05, **kw))
    np.testing.assert_array_equal(a, continued_state("fig8", 1.05, **kw))


@pytest.mark.parametrize("args, kw, match", [
    ((42, 1.1), {}, r"^p must be a parameter set"),
    (("nope", 1.1), {}, r"^p: unknown preset 'nope'"),
    (("fig8", 0.0), {}, r"^eta must be finite and > 0"),
    (("fig8", 1.1), dict(step=-0.1), r"^step must be"),
    (("fig8", 1.1), dict(eta_start=math.nan), r"^eta_start must be"),
    (("fig8", 1.1), dict(transient=-1), r"^transient must be"),
    (("fig8", 1.1), dict(state0=["0", "0", "0", "0"]), r"^state0 must be"),
])
def test_continued_state_refuses_bad_input_naming_the_argument(args, kw, match):
    """continued_state's every argument is checked before any run, naming it."""
    from vibimpact.sweeps.sweep import continued_state

    with pytest.raises(ValueError, match=match):
        continued_state(*args, **kw)


@pytest.mark.parametrize("make, arg", [
    (lambda v: vi.SolverSettings(adaptive=v), "adaptive"),
    (lambda v: vi.Execution(resume=v), "resume"),
    (lambda v: Domain(lo_closed=v), "lo_closed"),
    (lambda v: Domain(hi_closed=v), "hi_closed"),
    (lambda v: vi.Solver(_system(), check=v), "check"),
], ids=["SolverSettings.adaptive", "Execution.resume", "Domain.lo_closed",
        "Domain.hi_closed", "Solver.check"])
def test_settings_classes_refuse_a_flag_that_is_not_a_bool(make, arg):
    """The settings and helper classes' bool arguments refuse 'no', 1 and an array as the
    functions' do (None stays 'the default' where the class says so)."""
    for value in ("no", 1, np.array([True])):
        with pytest.raises(ValueError, match=rf"^{arg} must be True or False"):
            make(value)


@pytest.mark.parametrize("kw, match", [
    (dict(lo="0"), r"^lo must be a real number"), (dict(lo=math.nan), r"^lo must be"),
    (dict(lo=1.0, hi=0.0), r"^lo must be <= hi"),
])
def test_a_domain_of_wrong_bounds_is_refused(kw, match):
    """A Domain's bounds are real numbers or infinities, lo <= hi."""
    with pytest.raises(ValueError, match=match):
        Domain(**kw)


def _affine_iterates(factor):
    A = np.array([[0.5, 0.3], [-0.2, 0.8]])
    b = np.array([1.0, 2.0]) * factor
    xs = [np.zeros(2)]
    for _ in range(6):
        xs.append(A @ xs[-1] + b)
    return np.array(xs)


@pytest.mark.parametrize("factor", [1e308 / 4, 1e-300, 1e-308])
def test_extrapolate_limit_is_the_same_at_every_magnitude(factor):
    """The extrapolated limit of an affine iteration scales with its data: near 1e308
    (overflow) and at 1e-308 (subnormal underflow) it returned NaN."""
    exact = vi.analysis.extrapolate_limit(_affine_iterates(1.0))
    got = vi.analysis.extrapolate_limit(_affine_iterates(factor)) / factor
    np.testing.assert_allclose(got, exact, rtol=1e-9)


_SERIES = np.sin(0.7 * np.arange(500)) + 0.3 * np.sin(1.9 * np.arange(500))


@pytest.mark.parametrize("factor", [1e308 / 4, 1e200])
def test_test01_of_huge_values_equals_that_of_the_scaled_series(factor):
    """test01 of a series near 1e308 (its squares overflowed) gives the K of the same
    series at magnitude 1, without a warning."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert vi.analysis.test01(_SERIES * factor) == pytest.approx(
            vi.analysis.test01(_SERIES), abs=1e-9)
