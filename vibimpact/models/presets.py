"""Named parameter sets: every built-in model declares its own
(:attr:`vibimpact.models.Model.presets`, in its module of :mod:`vibimpact.builtin_models`);
this module finds them by name, in the registry's order of the models.

The default preset (:data:`DEFAULT`, what the commands use when none is named) is the first
registered model's :attr:`~vibimpact.models.Model.default_preset` (else its first preset).
What else the commands do when not told (the frequencies a sweep covers, where a census
looks) is each model's :attr:`~vibimpact.models.Model.defaults`
(:func:`command_default`).
"""
from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

from ..base._validate import WrongType

if TYPE_CHECKING:  # names of the annotations only
    from . import Model
    from .params import ParamsMixin

#: what ``get`` is given when no preset is named: :data:`DEFAULT`, looked up then
_DEFAULT = "<the default preset>"

#: what a model may declare in :attr:`~vibimpact.models.Model.defaults`, and what each is
DEFAULT_KEYS = {
    "frequencies": "the forcing frequencies START:STOP:STEP a sweep covers without --eta",
    "map_frequencies": "the coarser grid of them a two-parameter map covers without --eta "
                       "(else the frequencies)",
    "census_preset": "the preset a census or a basin image uses without --preset",
    "census_frequency": "the forcing frequency a census or a basin image looks at "
                        "without --eta",
}


def check_defaults(model: str, defaults: dict, presets: Mapping) -> None:
    """Refuse a model's ``defaults`` (:data:`DEFAULT_KEYS`) that name an unknown key, a
    preset the model does not declare, or a value of the wrong kind.

    Raises
    ------
    ValueError
        Naming the model and the key.
    """
    for key, value in defaults.items():
        if key not in DEFAULT_KEYS:
            raise ValueError(f"model {model!r}: defaults: unknown key {key!r}; the keys are "
                             f"{', '.join(DEFAULT_KEYS)}")
        if key == "census_preset" and value not in presets:
            raise ValueError(f"model {model!r}: defaults: census_preset {value!r} is not "
                             "one of its presets")
        ranged = isinstance(value, str) and value.count(":") == 2
        if key in ("frequencies", "map_frequencies") and not ranged:
            raise ValueError(f"model {model!r}: defaults: frequencies must be a range "
                             f"'START:STOP:STEP', got {value!r}")
        if key == "census_frequency" and not (isinstance(value, (int, float)) and
                                              not isinstance(value, bool) and value > 0):
            raise ValueError(f"model {model!r}: defaults: census_frequency must be a "
                             f"positive number, got {value!r}")


def command_default(key: str, preset: str | None = None) -> str | float | None:
    """What a command uses for ``key`` (:data:`DEFAULT_KEYS`) when not told: the value
    the model of ``preset`` declares (a name no model declares, or None: the first
    registered model), else the fallback: ``census_preset``, the model's default preset
    (else its first); ``census_frequency``, the forcing frequency of ``preset`` (or of
    the census preset); ``frequencies``, None (the command asks for ``--eta``).

    Raises
    ------
    ValueError
        For a key not in :data:`DEFAULT_KEYS`.
    """
    from .. import models

    if key not in DEFAULT_KEYS:
        raise ValueError(f"key must be one of {', '.join(DEFAULT_KEYS)}, got {key!r}")
    found = _all()
    model = found.get(preset) if isinstance(preset, str) else None
    if model is None:
        model = models.get(models.names()[0])
    if key in model.defaults:
        return model.defaults[key]
    if key == "map_frequencies":
        return command_default("frequencies", preset)
    if key == "census_preset":
        return model.default_preset or next(iter(model.presets))
    if key == "census_frequency":
        name = (preset if isinstance(preset, str) and preset in model.presets
                else str(command_default("census_preset", preset)))
        return float(getattr(get(name), model.frequency_name))
    return None


def _all():
    """``{preset: model}`` of every built-in model's presets, in the registry's order (a
    name two models declare is the first's)."""
    from .. import models

    out: dict[str, Model] = {}
    for mname in models.names():
        model = models.get(mname)
        for name in model.presets:
            out.setdefault(name, model)
    return out


def names() -> list[str]:
    """Names of all presets, model by model in the registry's order, each model's in the
    order it declares them."""
    return list(_all())


def model_of(name: str) -> Model:
    """The built-in :class:`~vibimpact.models.Model` that declares preset ``name``.

    Raises
    ------
    ValueError
        For an unknown preset name.
    """
    if not isinstance(name, str):
        raise WrongType(f"name must be a preset's name (str), got {type(name).__name__}")
    found = _all()
    if name not in found:
        raise ValueError(f"unknown preset {name!r}; choose from {', '.join(found)}")
    return found[name]


def describe(name: str) -> str:
    """One line on what a preset shows."""
    return model_of(name).presets[name][1]


def get(name: str = _DEFAULT) -> ParamsMixin:
    """The parameter set of a preset: the declaring model's own parameter set
    (:class:`~vibimpact.Params` for the paper's figures) with the preset's values.

    Parameters
    ----------
    name : str, optional
        The preset (default: :data:`DEFAULT`, the first model's declared default).

    Raises
    ------
    TypeError
        For a name that is not a str (:class:`~vibimpact.base._validate.WrongType`).
    ValueError
        For an unknown preset name.
    """
    if name == _DEFAULT:
        name = __getattr__("DEFAULT")
    model = model_of(name)
    assert model.param_set is not None  # a built-in model's presets come with its set
    return model.param_set(**model.presets[name][0])


def __getattr__(name):
    # DEFAULT: the first registered model's default preset, looked up when asked (the
    # registry loads the models on first use)
    if name == "DEFAULT":
        from .. import models

        first = models.get(models.names()[0])
        return first.default_preset or next(iter(first.presets))
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
