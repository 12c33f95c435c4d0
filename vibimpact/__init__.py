"""vibimpact: bifurcation and chaos analysis of vibro-impact models.

Every analysis serves any vibro-impact model declared as data (``vi.models``): a built-in
one or a user's own.  The built-in models are the rigid rotor on passive magnetic bearings
hitting its retainer bearing of Pust & Kozanek, "Vibrations of rotor supported in magnetic
bearings with impacts", eq. (5) (registered first; ``fig8`` below is one of its presets),
the Duffing oscillator, the soft-impact oscillator and others.

>>> import vibimpact as vi
>>> p = vi.presets.get("fig8").replace(eta=1.25)
>>> run = vi.simulate(p, periods=200, transient=500)

The public names are imported on first use (PEP 562), so that ``import vibimpact`` and
``vibimpact --help`` do not load numba.
"""
import importlib

__version__ = "0.1.0"

#: public name -> (submodule, attribute or None for the submodule itself)
_EXPORTS = {
    "Params": ("models.params", "Params"),
    "DuffingParams": ("models.params", "DuffingParams"),
    "presets": ("models.presets", None),
    "simulate": ("core.simulation", "simulate"),
    "METHODS": ("core.simulation", "METHODS"),
    "Run": ("core.run", "Run"),
    "Status": ("core.run", "Status"),
    "Model": ("models", "Model"),
    "System": ("core.system", "System"),
    "SolverSettings": ("core.solver", "SolverSettings"),
    "Solver": ("core.solver", "Solver"),
    "models": ("models", None),
    "Contact": ("models.contact", "Contact"),
    "ContactLaw": ("models.contact", "ContactLaw"),
    "Restitution": ("models.contact", "Restitution"),
    "BifurcationKind": ("base.bifurcation_kinds", "BifurcationKind"),
    "Regime": ("analysis.classify", "Regime"),
    "analysis": ("analysis", None),
    "sweep": ("sweeps.sweep", "sweep"),
    "intervals": ("sweeps.dataset", "intervals"),
    "grid": ("sweeps.sweep", "grid"),
    "SweepSettings": ("points.point", "SweepSettings"),
    "classify_params": ("points.pipeline", "classify_params"),
    "transition_types": ("sweeps.transitions", "transition_types"),
    "map2d": ("maps.map2d", "map2d"),
    "attractors": ("census.census", "attractors"),
    "CensusSettings": ("census.reach", "CensusSettings"),
    "basins": ("census.basins", "basins"),
    "Execution": ("engine.execution", "Execution"),
    "Continuation": ("engine.policy", "Continuation"),
    "Independent": ("engine.policy", "Independent"),
    "Interrupted": ("engine.signals", "Interrupted"),
    "engine": ("engine", None),
    "hunt_orbits": ("orbits.hunt", "hunt_orbits"),
    "orbits": ("orbits", None),
    # subpackages a user reaches as attributes (vi.maps.open_map(...)) without importing
    # them first
    "maps": ("maps", None),
    "census": ("census", None),
    "plotting": ("plotting", None),
    "sweeps": ("sweeps", None),
    "io": ("io", None),
    # the one way to save any dataset of the package (a sweep, a census, a run, a map
    # as NetCDF, ...) and to read it back
    "save": ("io", "write_netcdf"),
    "load": ("io", "read_netcdf"),
}

__all__ = ["Params", "DuffingParams", "presets", "simulate", "Run", "Status", "Model",
           "System", "SolverSettings", "Solver",
           "models", "Contact", "ContactLaw", "Restitution",
           "BifurcationKind", "METHODS", "Regime", "analysis", "sweep", "grid", "intervals",
           "SweepSettings", "classify_params",
           "transition_types",
           "map2d", "attractors", "CensusSettings", "basins", "census", "maps", "plotting",
           "sweeps", "io", "__version__",
           "Execution", "Continuation", "Independent", "Interrupted", "engine", "hunt_orbits",
           "orbits", "save", "load"]


def _load(name):
    module, attr = _EXPORTS[name]
    mod = importlib.import_module(f"{__name__}.{module}")
    return mod if attr is None else getattr(mod, attr)


def _model_constants():
    """``ROTOR``, ``DUFFING``, ...: the constant name of every built-in model, one per
    module of :mod:`vibimpact.builtin_models` (found without importing them)."""
    import pkgutil
    from pathlib import Path

    found = pkgutil.iter_modules([str(Path(__file__).with_name("builtin_models"))])
    return sorted(m.name.upper() for m in found if not m.ispkg)


#: the built-in models by their constant names (vi.ROTOR, vi.SOFT_IMPACT, ...), taken from
#: the registry (:mod:`vibimpact.models`) on first use
__all__ += _model_constants()  # noqa: PLE0605 (a list of str, built from the registry)


def __getattr__(name):
    if name in _EXPORTS:
        value = _load(name)
        globals()[name] = value
        return value
    if name.isupper() and name in __all__:
        value = getattr(importlib.import_module(f"{__name__}.models"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS) | set(__all__))
