"""vibimpact: bifurcation and chaos analysis of vibro-impact rotors.

The model is the rigid rotor on passive magnetic bearings hitting its retainer bearing of
Pust & Kozanek, "Vibrations of rotor supported in magnetic bearings with impacts", eq. (5);
every analysis serves any vibro-impact model declared as data (``vi.models``: the rotor,
the Duffing oscillator, the soft-impact oscillator, or a user's own).

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
    "ROTOR": ("models", "ROTOR"),
    "DUFFING": ("models", "DUFFING"),
    "SOFT_IMPACT": ("models", "SOFT_IMPACT"),
    "models": ("models", None),
    "Contact": ("models.contact", "Contact"),
    "ContactLaw": ("models.contact", "ContactLaw"),
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
}

__all__ = ["Params", "DuffingParams", "presets", "simulate", "Run", "Status", "Model",
           "System", "SolverSettings", "Solver",
           "ROTOR", "DUFFING", "SOFT_IMPACT", "models", "Contact", "ContactLaw",
           "BifurcationKind", "METHODS", "Regime", "analysis", "sweep", "grid", "intervals",
           "SweepSettings", "classify_params",
           "transition_types",
           "map2d", "attractors", "CensusSettings", "basins", "census", "maps", "plotting",
           "sweeps", "io", "__version__",
           "Execution", "Continuation", "Independent", "Interrupted", "engine", "hunt_orbits",
           "orbits"]


def _load(name):
    module, attr = _EXPORTS[name]
    mod = importlib.import_module(f"{__name__}.{module}")
    return mod if attr is None else getattr(mod, attr)


def __getattr__(name):
    if name in _EXPORTS:
        value = _load(name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
