"""Models as data, and the one registry of them.

A :class:`Model` is its right-hand side, Jacobian, switching surfaces and mode transitions
(all ``@njit``, signatures in :mod:`vibimpact._kernel.integrator`) and what it declares
about itself: its state layout and parameter table (:attr:`Model.param_set`), its contact
(:class:`vibimpact.models.contact.Contact`: geometry and law; every impact analysis follows from
it), what XY plots draw (:class:`PlotSpec`), its presets and its bound.

The built-in models (the rotor of eq. (5), the forced Duffing oscillator, the soft-impact
oscillator, ...) are each one module of :mod:`vibimpact.builtin_models` declaring a
:class:`Model` with :meth:`Model.builtin_model` over the kernel module of the same family,
found and registered by :func:`get`, :func:`names` and :func:`of_params`; user models come
from :meth:`Model.from_functions`.  Nothing in the package branches on which model it
runs: it asks the model.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

import importlib
import math
import threading
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from collections.abc import Callable

import numpy as np
from numba.extending import is_jitted

from .._kernel import boundary as _kb
from .._kernel.boundary import Problem
from ..base import _validate as _v
from .contact import Contact, Restitution
from .model_probe import check_model
from .params import Domain
from .plotspec import PlotSpec

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Sequence

    from numpy.typing import ArrayLike


@dataclass(frozen=True)
class Model:
    """A piecewise-smooth, periodically forced model for :func:`vibimpact.simulate`.

    Attributes
    ----------
    name : str
    state_names : tuple of str
    param_names : tuple of str
        Order of the parameter vector the kernel reads.
    omega_index : int
        Index of the forcing frequency in the parameter vector.
    n_mode : int
        Length of the discrete-mode vector.
    terminal : ndarray of int64, shape (n_switch,)
        1 for a mode-changing switching function, 0 for an observer.
    kernel_model : BuiltinModel or tuple
        What the kernel receives as ``model``: a built-in family or ``(rhs, switches,
        transition)``.
    rhs, jac, switches, transition, init_mode : numba functions
    bound : float
        A state component larger than this in magnitude ends the run as DIVERGED.
    param_set : type, optional
        A built-in model's parameter set (:class:`~vibimpact.models.params.Params`,
        :class:`~vibimpact.models.params.DuffingParams`): where its parameters' domains are
        stated, also for a plain parameter vector of the model.
    contact : Contact, optional
        Where and how the model's body meets its obstacle (impacts, arcs and contact
        statistics follow from it); None: the model has no contact.
    plot : PlotSpec, optional
        What XY plots draw.
    presets : mapping, optional
        ``{name: (parameter values, description)}``: the model's named parameter sets
        (:func:`vibimpact.models.presets.get`).
    default_preset : str, optional
        The preset the commands use when none is named (the first registered model's is
        :data:`vibimpact.models.presets.DEFAULT`); None: the first of ``presets``.
    state_text : mapping, optional
        ``{state name: what it is, in words}``: written into files next to the state
        (their ``state_<name>`` attribute, the ``long_name`` of its Poincaré samples).
    domains : mapping, optional
        ``{parameter name: Domain}``: a user model's declared parameter ranges (a
        built-in model's are its ``param_set``'s).
    references : str, optional
        The literature of the model, written as the CF ``references`` of every file of
        it (empty: the package's own, :data:`vibimpact.base.provenance.REFERENCES`).
    defaults : mapping, optional
        What the commands do with this model when not told
        (:data:`vibimpact.models.presets.DEFAULT_KEYS`): ``"frequencies"``, the range
        ``START:STOP:STEP`` a sweep covers without ``--eta`` (``"map_frequencies"``, a
        two-parameter map's coarser grid); ``"census_preset"`` and
        ``"census_frequency"``, the preset and forcing frequency a census or a basin
        image looks at (where the model's attractors coexist).  Each one left out has
        the fallback :func:`vibimpact.models.presets.command_default` states.
    """

    name: str
    state_names: tuple
    param_names: tuple
    omega_index: int
    n_mode: int
    terminal: np.ndarray = field(repr=False)
    kernel_model: _kb.BuiltinModel | tuple[Callable, Callable, Callable] = field(repr=False)
    rhs: Callable = field(repr=False)
    jac: Callable = field(repr=False)
    switches: Callable = field(repr=False)
    transition: Callable = field(repr=False)
    init_mode: Callable = field(repr=False)
    bound: float = 1e3
    # a built-in model's parameter-set class (a frozen dataclass with domain()); None
    # for a user model
    param_set: type[Any] | None = None
    contact: Contact | None = field(default=None, repr=False)
    plot: PlotSpec | None = field(default=None, repr=False)
    presets: Mapping = field(default_factory=dict, repr=False)
    state_text: Mapping = field(default_factory=dict, repr=False)
    domains: Mapping = field(default_factory=dict, repr=False)
    default_preset: str | None = field(default=None, repr=False)
    defaults: Mapping = field(default_factory=dict, repr=False)
    references: str = field(default="", repr=False)

    @property
    def frequency_name(self) -> str:
        """The name of the model's forcing frequency (its parameter at
        :attr:`omega_index`): what a sweep's frequency coordinate holds, recorded in
        its files as ``frequency_name``."""
        return self.param_names[self.omega_index]

    def frequency_attrs(self) -> dict:
        """The attributes of a file's frequency coordinate: ``units`` and the
        ``long_name`` the model's :class:`PlotSpec` declares (``frequency_text``), else
        ``"forcing frequency NAME"``."""
        text = self.plot.frequency_text if self.plot is not None else ""
        return dict(units="1", long_name=text or f"forcing frequency {self.frequency_name}")

    @property
    def builtin(self):
        """Whether this is a built-in model (kernel functions compiled once and cached)."""
        return isinstance(self.kernel_model, _kb.BuiltinModel)

    @classmethod
    def builtin_model(cls, name: str, family: str, state_names: Sequence[str],
                      omega_index: int, param_set: type, *, bound: float = 1e3,
                      contact: Contact | None = None, plot: PlotSpec | None = None,
                      presets: Mapping | None = None,
                      state_text: Mapping | None = None,
                      default_preset: str | None = None,
                      defaults: Mapping | None = None, references: str = "") -> Model:
        """A built-in model: the kernel module ``family`` (its ``KERNEL_MODEL``) and
        what the model declares about itself.

        Parameters
        ----------
        name : str
        family : str
            The kernel module (:mod:`vibimpact._kernel.registry`).
        state_names : sequence of str
        omega_index : int
            Index of the forcing frequency in the parameter vector.
        param_set : type
            The frozen parameter dataclass (its fields in the kernel's order).
        bound, contact, plot, presets, state_text, default_preset, defaults, references
            As the attributes.  The initial mode is the kernel's ``init_mode`` with its
            argument check (:func:`vibimpact._kernel.boundary.initial_mode`).

        Raises
        ------
        ValueError
            When the declaration does not fit the kernel module's sizes.
        """
        km = _kb.kernel_family(family)
        names = tuple(f.name for f in fields(param_set))
        if names != tuple(km.param_names) or len(state_names) != km.n_state:
            raise ValueError(f"model {name!r}: the parameter set or state layout does not "
                             f"match the kernel module {family!r}")
        declared = getattr(param_set, "_FREQUENCY", names[omega_index])
        if declared != names[omega_index]:
            raise ValueError(f"model {name!r}: the parameter set's forcing frequency "
                             f"{declared!r} is not its parameter at omega_index "
                             f"({names[omega_index]!r})")
        unknown = set(state_text or {}) - set(state_names)
        if unknown:
            raise ValueError(f"model {name!r}: state_text names no state: "
                             f"{', '.join(sorted(unknown))}")
        if contact is not None:
            contact.check(km.n_state, km.terminal.size, km.n_mode, names)
        if default_preset is not None and default_preset not in (presets or {}):
            raise ValueError(f"model {name!r}: default_preset {default_preset!r} is not "
                             f"one of its presets")
        from .presets import check_defaults

        check_defaults(name, dict(defaults or {}), presets or {})
        return cls(name=name, state_names=tuple(state_names), param_names=names,
                   omega_index=omega_index, n_mode=km.n_mode, terminal=km.terminal,
                   kernel_model=_kb.builtin(family), rhs=km.rhs, jac=km.jac,
                   switches=km.switches, transition=km.transition,
                   init_mode=_kb.initial_mode(family), bound=bound, param_set=param_set,
                   contact=contact, plot=plot, presets=dict(presets or {}),
                   state_text=dict(state_text or {}), default_preset=default_preset,
                   defaults=dict(defaults or {}), references=str(references))

    def domain(self, index: int) -> Domain:
        """The :class:`~vibimpact.models.params.Domain` of parameter ``index``: the parameter
        set's (a built-in model), the declared one (a user model's ``domains``), else any
        finite number; the forcing frequency is always ``> 0``."""
        name = self.param_names[index]
        if self.param_set is not None:
            return self.param_set.domain(name)
        dom = self.domains.get(name)
        if index == self.omega_index and (dom is None or dom.lo < 0.0 or
                                          (dom.lo == 0.0 and dom.lo_closed)):
            return Domain(lo=0.0, hi=dom.hi if dom else math.inf,
                          hi_closed=dom.hi_closed if dom else False)
        return dom if dom is not None else Domain()

    def check_params(self, p: ArrayLike | Mapping[str, float],
                     name: str = "p") -> np.ndarray:
        """``p`` as this model's validated parameter vector: the one check of every way
        parameters come in (a parameter set, a ``{name: value}`` mapping, a plain vector).

        Parameters
        ----------
        p : parameter set, mapping or array_like
            A mapping may leave out the parameters that have a default (a built-in
            model's); a user model's needs them all.
        name : str
            The argument's name, for messages about the vector as a whole.

        Returns
        -------
        ndarray of float64, shape (n_params,)
            A new C-contiguous vector.

        Raises
        ------
        ValueError
            Naming the parameter: not a real number (:class:`~vibimpact.base._validate.WrongType`),
            not finite, or outside its domain (:meth:`domain`); or naming ``name`` for a
            vector of the wrong length, or a mapping with unknown or missing names.
        """
        names = self.param_names
        if hasattr(p, "as_array") and self.param_set is not None and \
                type(p) is self.param_set:
            return p.as_array()  # validated when it was made
        if isinstance(p, Mapping):
            unknown = [str(k) for k in p if k not in names]
            if unknown:
                raise ValueError(f"{name}: unknown parameter {', '.join(unknown)}; "
                                 f"{self.name}'s are {', '.join(names)}"[:300])
            if self.param_set is not None:
                defaults = self.param_set().as_dict()
                p = {**defaults, **p}
            missing = [n for n in names if n not in p]
            if missing:
                raise ValueError(f"{name}: missing parameter {', '.join(missing)}")
            vec = np.array([_v.finite(n, p[n]) for n in names], dtype=np.float64)
        else:
            vec = _v.array1d(name, p.as_array() if hasattr(p, "as_array") else p,
                             "the parameter vector")
            if np.ndim(p.as_array() if hasattr(p, "as_array") else p) != 1 or \
                    vec.size != len(names):
                raise ValueError(f"{name} must have {len(names)} parameters {names}, got "
                                 f"shape {np.shape(vec)}")
        for i, pname in enumerate(names):
            value = float(vec[i])
            if not math.isfinite(value):
                raise ValueError(f"{pname} must be finite, got {value!r}")
            self.domain(i).check(pname, value)
        return np.ascontiguousarray(vec)

    @_v.checks_flags
    def problem(self, p: np.ndarray, variational: bool = False) -> Problem:
        """The kernel's :class:`~vibimpact._kernel.boundary.Problem` for parameter vector
        ``p`` (of the variational equations with ``variational``)."""
        if not self.builtin and not self.__dict__.get("_probed"):
            # a user model: its sizes are checked on guarded buffers before the kernel
            # runs its functions (once per model object)
            check_model(self, p)
            object.__setattr__(self, "_probed", True)
        kmodel = self.variational_kernel_model if variational else self.kernel_model
        return Problem(kmodel, self.terminal, self.n_mode, p, float(p[self.omega_index]),
                       self.init_mode, n_state=len(self.state_names))

    @property
    def variational_kernel_model(self):
        """What the kernel receives for the variational equations of this model.

        The state followed by tangent vectors, mapped by saltation matrices at every
        switch (:mod:`vibimpact._kernel.variational`).
        """
        if isinstance(self.kernel_model, _kb.BuiltinModel):  # self.builtin
            return _kb.builtin(self.kernel_model.family, variational=True)
        rhs, switches, transition = self.kernel_model
        return (rhs, switches, transition, self.jac, len(self.state_names),
                int(self.terminal.size))

    @classmethod
    def from_functions(cls, name: str, rhs: Callable, jac: Callable, switches: Callable,
                       transition: Callable, init_mode: Callable, terminal: Callable,
                       state_names: Sequence[str], param_names: Sequence[str],
                       omega_index: int, n_mode: int = 1, bound: float = 1e3,
                       contact: Contact | None = None,
                       domains: Mapping[str, Domain] | None = None,
                       references: str = "") -> Model:
        """A user model from numba functions (compiled on first use, not cached on disk).

        Parameters
        ----------
        rhs, jac, switches, transition, init_mode : numba ``@njit`` functions
            With the signatures of a kernel module's
            (:class:`vibimpact._kernel.registry.KernelModel`; e.g. the built-in rotor's,
            :mod:`vibimpact._kernel.rotor`).
        terminal : sequence of int
            One entry per switching function: 1 terminal, 0 observer.  A smooth model
            gives one observer (e.g. a velocity) so that the array is never empty.
        state_names, param_names : sequence of str
        omega_index : int
            Index of the forcing frequency in the parameter vector.
        n_mode : int
            Length of the mode vector.
        bound : float
            A state component larger than this in magnitude ends a run as DIVERGED.
        contact : Contact, optional
            The model's contact (:class:`vibimpact.models.contact.Contact`): with it the model
            gets impact records, impacts per period, contact arcs and contact statistics
            in runs, sweeps and maps.
        domains : mapping, optional
            ``{parameter name: vibimpact.models.params.Domain}``: the values a parameter may
            take (e.g. ``{"delta": Domain.at_least(0.0)}``); every parameter vector of
            the model is checked against them, and the continuation steps up to a bound
            but never past it.  Undeclared: any finite number (the forcing frequency
            ``> 0``).
        references : str, optional
            The model's literature: the CF ``references`` of its files once the model is
            registered (:func:`register`).
        """
        if not isinstance(references, str):
            raise _v.WrongType(f"references must be a str, got {type(references).__name__}")
        if not isinstance(name, str) or not name:
            raise _v.WrongType(f"name must be a non-empty str, got {name!r}"[:200])
        for arg, fn in (("rhs", rhs), ("jac", jac), ("switches", switches),
                        ("transition", transition), ("init_mode", init_mode)):
            if not is_jitted(fn):
                what = ("a plain Python function" if callable(fn) else
                        f"{type(fn).__name__} {fn!r}"[:80])
                raise _v.WrongType(f"{arg} must be compiled with numba (decorate it with "
                                   f"@numba.njit), got {what}")
        states = _names("state_names", state_names)
        params = _names("param_names", param_names)
        term = _v.array1d("terminal", terminal, "0s and 1s")
        if term.size == 0 or not np.all((term == 0) | (term == 1)):
            raise ValueError(f"terminal must list at least one switching function, each 1 "
                             f"(terminal) or 0 (observer), got {terminal!r}"[:200])
        omega_index = _v.count("omega_index", omega_index, 0)
        if omega_index >= len(params):
            raise ValueError(f"omega_index must index param_names (0 to {len(params) - 1}), "
                             f"got {omega_index}")
        n_mode = _v.count("n_mode", n_mode, 0)
        if contact is not None:
            if not isinstance(contact, Contact):
                raise _v.WrongType(f"contact must be a vibimpact.models.contact.Contact, got "
                                   f"{type(contact).__name__}")
            contact.check(len(states), term.size, n_mode, params)
        domains = _domains(domains, params)
        if contact is not None and isinstance(contact.law, Restitution):  # r in [0, 1]
            domains = {contact.law.coefficient: Domain(0.0, 1.0, True, True), **domains}
        return cls(name=name, state_names=states, param_names=params,
                   omega_index=omega_index, n_mode=n_mode,
                   terminal=term.astype(np.int64), kernel_model=(rhs, switches, transition),
                   rhs=rhs, jac=jac, switches=switches, transition=transition,
                   init_mode=init_mode, bound=_v.positive("bound", bound), contact=contact,
                   domains=domains, references=references)


def _domains(value, params):
    """``{name: Domain}`` of a user model's declared ranges, each name one of
    ``params``."""
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise _v.WrongType(f"domains must be a mapping {{parameter name: Domain}}, got "
                           f"{type(value).__name__}")
    for key, dom in value.items():
        if key not in params:
            raise ValueError(f"domains: {key!r} is not a parameter ({', '.join(params)})"
                             [:200])
        if not isinstance(dom, Domain):
            raise _v.WrongType(f"domains[{key!r}] must be a vibimpact.models.params.Domain, got "
                               f"{type(dom).__name__}")
    return dict(value)


def _names(arg, value):
    """A non-empty tuple of distinct, non-empty names."""
    if isinstance(value, str):
        raise _v.WrongType(f"{arg} must be a sequence of str, got the str {value!r}"[:200])
    try:
        names = tuple(value)
    except TypeError:
        raise _v.WrongType(f"{arg} must be a sequence of str, got "
                           f"{type(value).__name__}") from None
    if not names or not all(isinstance(v, str) and v for v in names):
        raise ValueError(f"{arg} must be one or more non-empty str, got {names!r}"[:200])
    if len(set(names)) != len(names):
        raise ValueError(f"{arg} must be distinct, got {names!r}"[:200])
    return names


def spec_of(name) -> PlotSpec | None:
    """The :class:`PlotSpec` of the built-in model ``name`` (a file's ``model``
    attribute); None for a name this installation does not know (a user model's) or a
    model that declares none."""
    if isinstance(name, str) and name in names():
        return get(name).plot
    return None


# --- the registry ---------------------------------------------------------------------

_REGISTRY: dict[str, Model] = {}


def register(model: Model) -> Model:
    """Add a built-in model to the registry (by :mod:`vibimpact.builtin_models`).

    Raises
    ------
    ValueError
        For a second model of the same name or parameter set.
    """
    if model.name in _REGISTRY and _REGISTRY[model.name] is not model:
        raise ValueError(f"a model named {model.name!r} is registered already")
    if model.param_set is not None and any(m.param_set is model.param_set and m is not model
                                           for m in _REGISTRY.values()):
        raise ValueError(f"the parameter set {model.param_set.__name__} has a model already")
    _REGISTRY[model.name] = model
    return model


_LOADING: list[bool] = []
#: held while the built-in models load: a thread that asks meanwhile waits for all of
#: them (re-entrant: a model's own import that asks gets the registry so far)
_LOAD_LOCK = threading.RLock()


def _loaded():
    if _REGISTRY and not _LOADING:
        return _REGISTRY
    with _LOAD_LOCK:
        if not _REGISTRY and not _LOADING:
            _LOADING.append(True)
            try:  # the models' package is found by name, as the kernel finds its families
                for model in importlib.import_module("..builtin_models", __package__).load():
                    register(model)
            finally:
                _LOADING.clear()
    return _REGISTRY


def names() -> list[str]:
    """Names of the built-in models."""
    return list(_loaded())


def get(name: str) -> Model:
    """The built-in model ``name``.

    Raises
    ------
    ValueError
        Naming ``model`` for an unknown name.
    """
    models = _loaded()
    if not isinstance(name, str) or name not in models:
        raise ValueError(f"model must be one of {', '.join(models)}, got {name!r}"[:200])
    return models[name]


def param_set_names() -> str:
    """The built-in models' parameter sets, named for a message (``"Params,
    DuffingParams, ..."``)."""
    return ", ".join(m.param_set.__name__ for m in _loaded().values() if m.param_set)


def of_params(p) -> Model | None:
    """The built-in model whose parameter set ``p`` is an instance of (None: none)."""
    for model in _loaded().values():
        if model.param_set is not None and type(p) is model.param_set:
            return model
    return None


def resolve(p, model=None):
    """The model and the parameter vector of ``p``.

    Parameters
    ----------
    p : parameter set of a built-in model, mapping or array_like
        Parameters (:class:`~vibimpact.Params`, :class:`~vibimpact.DuffingParams`, ...);
        a plain vector or a ``{name: value}`` mapping needs ``model``.
    model : Model, optional
        The model ``p`` belongs to (a built-in one such as ``vi.ROTOR``, or a user's);
        ``p`` is then checked by :meth:`Model.check_params`, as a parameter set is.

    Returns
    -------
    (Model, ndarray of float64)

    Raises
    ------
    ValueError
        Naming ``model`` or ``p``, or the parameter that is not finite or outside its
        domain.
    """
    if model is not None:
        if not isinstance(model, Model):
            raise _v.WrongType(f"model must be a vibimpact.models.Model, got "
                               f"{type(model).__name__}")
        return model, model.check_params(p)
    model = of_params(p)
    if model is not None:
        return model, model.check_params(p)
    raise _v.WrongType(f"p must be the parameter set of a model ({param_set_names()}), "
                       f"got {type(p).__name__}")


def __getattr__(name):
    # ROTOR, DUFFING, SOFT_IMPACT, ...: the built-in models by their constant names
    if not name.isupper():
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    models = _loaded()
    for model in models.values():
        if model.name.upper() == name:
            return model
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
