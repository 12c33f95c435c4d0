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
from vibimpact.params import Domain


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
    ({"c": (0, 1)}, r"^domains\['c'\] must be a vibimpact.params.Domain"),
    ([("c", Domain())], r"^domains must be a mapping"),
])
def test_user_model_domains_of_wrong_form_are_refused(domains, match):
    """Model.from_functions refuses declared ranges that name no parameter or are not
    Domains."""
    with pytest.raises(ValueError, match=match):
        _user(domains)
