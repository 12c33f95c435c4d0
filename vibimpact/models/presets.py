"""Named parameter sets: every built-in model declares its own
(:attr:`vibimpact.models.Model.presets`, in its module of :mod:`vibimpact.builtin_models`);
this module finds them by name, in the registry's order of the models.

The default preset (:data:`DEFAULT`, what the commands use when none is named) is the first
registered model's :attr:`~vibimpact.models.Model.default_preset` (else its first preset).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from ..base._validate import WrongType

if TYPE_CHECKING:  # names of the annotations only
    from . import Model
    from .params import ParamsMixin

#: what ``get`` is given when no preset is named: :data:`DEFAULT`, looked up then
_DEFAULT = "<the default preset>"


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
