"""The model, parameters and states a file records, validated as if typed on the command line.

A file can be edited after it was written, by hand or by anyone: every value a command or
an API function takes from a file (a sweep's parameters and ``final_state`` that
``simulate --from`` starts from, the start a ``simulate --from`` file records for
``rerun``, the parameters a plot's title shows) goes through this module first.  The
rules are the command line's: a parameter is one real, finite number inside its domain
(:meth:`vibimpact.models.Model.domain`: ``kh = -5`` or ``B = NaN`` are refused as
``--set kh=-5`` is), a state holds numbers, as many as the model has states, all finite,
and the model is one this installation knows.  Where a file records the same parameter
twice (a sweep's ``params`` JSON and its ``param_NAME`` attributes) the two must agree:
a file that says two things is refused, never read one way silently.

The messages name the file (``name``) and the attribute or variable.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Literal, overload

import math

import numpy as np

from ..base import _json, _validate as _v

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Mapping

    from ..models import Model



def _short(value, width=40):
    text = repr(value)
    return text if len(text) <= width else text[:width] + "..."


def recorded_number(value, what: str) -> float:
    """``value`` (an attribute or a JSON entry) as one real, finite number.

    Parameters
    ----------
    value : object
        What the file holds: a number, a 1-element array, text, ...
    what : str
        How the message names it (``"the file's param_kh"``).

    Returns
    -------
    float

    Raises
    ------
    ValueError
        For text, a boolean, a complex number, several numbers, NaN or an infinity.
    """
    if isinstance(value, (str, bytes)):
        raise ValueError(f"{what} is text ({_short(value)}), not a number")
    if isinstance(value, (bool, np.bool_)) or value is None:
        raise ValueError(f"{what} is {_short(value)}, not a number")
    arr = np.asarray(value)
    if arr.dtype.kind not in "iuf" or arr.size != 1:
        kind = f"{arr.size} values" if arr.size != 1 else f"of type {arr.dtype}"
        raise ValueError(f"{what} is not one real number ({kind})")
    number = float(arr.reshape(()))
    if not math.isfinite(number):
        raise ValueError(f"{what} is {number!r}, not a finite number")
    return number


def model_name(attrs: Mapping, name: str = "the file") -> str:
    """The name of the model a file records (its ``model`` attribute), as it is.

    Raises
    ------
    ValueError
        One line naming ``name``, for a file without a ``model`` attribute: no model is
        assumed for it.
    """
    if "model" not in attrs:
        from .. import models

        raise ValueError(f"{name} names no model (no 'model' attribute): it cannot be read "
                         f"as any model's ({', '.join(models.names())})")
    return attrs["model"]


@overload
def recorded_model(attrs: Mapping, name: str = ..., *, required: Literal[True]) -> Model: ...
@overload
def recorded_model(attrs: Mapping, name: str = ..., *, required: bool = ...) -> Model | None: ...
@_v.checks_flags
def recorded_model(attrs: Mapping, name: str = "the file", *,
                   required: bool = False) -> Model | None:
    """The model a file records (its ``model`` attribute; a file without one is refused,
    never read as one model's): the installed :class:`~vibimpact.models.Model`, or None
    for a name this installation does not know (a user model's file) unless
    ``required``.

    Raises
    ------
    ValueError
        For a file without a ``model`` attribute, one that is not a name, or
        (``required``) one that names
        no model of this installation, or one without a parameter set.
    """
    from .. import models

    value = model_name(attrs, name)
    if not isinstance(value, str) or not value.strip():
        raise ValueError(f"{name} records model {_short(value)}, not a model's name")
    if value not in models.names():
        if required:
            raise ValueError(f"{name} records model {_short(value)}, which this "
                             f"installation does not have ({', '.join(models.names())})")
        return None
    model = models.get(value)
    if required and model.param_set is None:
        raise ValueError(f"{name} records the user model {value!r}, whose parameters "
                         "cannot be read back into a parameter set")
    return model


def _json_params(attrs, key, name):
    """``{parameter: number}`` of the JSON attribute ``key``."""
    text = attrs[key]
    if not isinstance(text, str):
        raise ValueError(f"{name}'s {key!r} attribute is not text (JSON)")
    values = _json.loads(text, f"{name}'s {key!r} attribute")  # bounded depth and size
    if not isinstance(values, dict):
        raise ValueError(f"{name}'s {key!r} attribute is not a JSON object of "
                         "parameters")
    return {str(k): recorded_number(v, f"{name}'s {key!r} entry {str(k)[:40]!r}")
            for k, v in values.items()}


def recorded_values(attrs: Mapping, name: str = "the file", *, key: str | None = "params",
                    prefix: str | None = "param_") -> dict[str, float]:
    """Every parameter value a file records, each one real, finite number; where the
    JSON attribute ``key`` and an attribute ``PREFIX + NAME`` both give one, they agree.

    Parameters
    ----------
    attrs : mapping
        The file's global attributes.
    name : str
        How the messages name the file.
    key : str or None
        The JSON attribute of parameters (a sweep's ``params``), None for none.
    prefix : str or None
        The prefix of the attributes of one parameter each (``param_``), None for none.

    Returns
    -------
    dict
        ``{parameter: value}``, both sources together.

    Raises
    ------
    ValueError
        Naming the attribute: text, not one number, NaN, infinite, or two values of the
        same parameter that differ.
    """
    values = _json_params(attrs, key, name) if key and key in attrs else {}
    if prefix:
        for attr in sorted(a for a in attrs if isinstance(a, str) and a.startswith(prefix)):
            pname = attr[len(prefix):]
            v = recorded_number(attrs[attr], f"{name}'s {attr}")
            if pname in values and values[pname] != v:
                raise ValueError(f"{name} records two values of {pname}: {attr} = {v!r} "
                                 f"and {values[pname]!r} in its {key!r} attribute")
            values[pname] = v
    return values


def check_in_domains(model: Model, values: Mapping[str, float], name: str = "the file",
                     prefix: str = "param_") -> None:
    """Each of ``values`` a parameter of ``model`` inside its domain.

    Raises
    ------
    ValueError
        ``the file records param_kh = -5: kh must be >= 0, got -5.0``, or an unknown
        parameter.
    """
    for pname, v in values.items():
        if pname not in model.param_names:
            raise ValueError(f"{name} records the parameter {pname[:40]!r}, which model "
                             f"{model.name!r} does not have ({', '.join(model.param_names)})")
        try:
            model.domain(model.param_names.index(pname)).check(pname, v)
        except ValueError as exc:
            raise ValueError(f"{name} records {prefix}{pname} = {v:g}: {exc}") from None


def check_recorded(attrs: Mapping, name: str = "the file") -> dict[str, float]:
    """The parameters a file records (``params`` JSON and ``param_*``), whatever they
    are: each a real, finite number, the two records agreeing, and, of a model this
    installation knows, each a parameter of it inside its domain.  What a command that
    only shows the values (a plot's title) checks; a command that computes with them
    uses :func:`recorded_params`.

    Returns
    -------
    dict
        ``{parameter: value}``.

    Raises
    ------
    ValueError
        Naming the file and the attribute.
    """
    values = recorded_values(attrs, name)
    model = recorded_model(attrs, name)
    if model is not None:
        check_in_domains(model, values, name)
    return values


def recorded_params(attrs: Mapping, name: str = "the file", *, key: str | None = "params",
                    prefix: str | None = "param_", omega: float | None = None):
    """The parameter set a file records, complete and valid, to compute with.

    Parameters
    ----------
    attrs : mapping
        The file's global attributes.
    name : str
        How the messages name the file.
    key : str or None
        The JSON attribute of the parameters (``params``; ``start_params``), which must
        be there; None for none.
    prefix : str or None
        The prefix of the one-parameter attributes (``param_``), which must be there for
        every parameter (the forcing frequency's only when ``omega`` is None) and agree
        with ``key``'s; None for none.
    omega : float, optional
        The forcing frequency (a sweep's grid value), which the records leave out.

    Returns
    -------
    parameter set
        Of the model the file records (:class:`~vibimpact.Params` for the built-in
        rotor).

    Raises
    ------
    ValueError
        Naming the file and what is missing, text, not finite, outside its domain, or
        recorded twice with two values; or a model this installation does not know.
    """
    model = recorded_model(attrs, name, required=True)
    if key and key not in attrs:
        raise ValueError(f"{name} has no {key!r} attribute (its parameters)")
    values = recorded_values(attrs, name, key=key, prefix=prefix)
    if key and prefix:  # every parameter of the JSON has its attribute as well
        no_attr = sorted(set(_json_params(attrs, key, name)) - {
            a[len(prefix):] for a in attrs if isinstance(a, str) and a.startswith(prefix)})
        if no_attr:
            raise ValueError(f"{name} records {', '.join(no_attr)} in its {key!r} "
                             f"attribute but has no {prefix}{no_attr[0]} attribute")
    freq = model.param_names[model.omega_index]
    if omega is not None:
        values[freq] = recorded_number(omega, f"{name}'s {freq}")
    unknown = [p for p in values if p not in model.param_names]
    if unknown:
        check_in_domains(model, {unknown[0]: values[unknown[0]]}, name)
    missing = [p for p in model.param_names if p not in values]
    if missing:
        where = f"{prefix}{missing[0]} attribute" if prefix else f"{key!r} attribute"
        raise ValueError(f"{name} records no {', '.join(missing)} (no {where})")
    check_in_domains(model, values, name, prefix or f"{key!r} entry ")
    assert model.param_set is not None  # recorded_model(required=True) refuses none
    return model.param_set(**values)


def recorded_state(values, model: Model, what: str) -> np.ndarray:
    """A state a file records (``final_state`` of one point, ``state0``): numbers, one
    per state of ``model``, all finite, as float64.

    Raises
    ------
    ValueError
        Naming ``what``: text or another non-number type, the wrong number of values,
        NaN or an infinity.
    """
    arr = np.asarray(values)
    if arr.dtype.kind not in "iuf":
        raise ValueError(f"{what} holds {arr.dtype} values, not real numbers")
    n = len(model.state_names)
    if arr.shape != (n,):
        raise ValueError(f"{what} has shape {arr.shape}; model {model.name!r} has {n} "
                         f"states ({', '.join(model.state_names)})")
    state = arr.astype(np.float64)
    if not np.all(np.isfinite(state)):
        raise ValueError(f"{what} is not finite ({state.tolist()})")
    return state


__all__ = ["check_recorded", "check_in_domains", "recorded_model", "recorded_number",
           "recorded_params", "recorded_state", "recorded_values"]
