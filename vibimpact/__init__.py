"""vibimpact: bifurcation and chaos analysis of vibro-impact rotors.

The model is the rigid rotor on passive magnetic bearings hitting its retainer bearing of
Pust & Kozanek, "Vibrations of rotor supported in magnetic bearings with impacts", eq. (5).

>>> import vibimpact as vi
>>> p = vi.presets.get("fig8").replace(eta=1.25)
>>> run = vi.simulate(p, periods=200, transient=500)

The public names are imported on first use (PEP 562), so that ``import vibimpact`` and
``vibimpact --help`` do not load numba.
"""
import importlib
import sys
import types

__version__ = "0.1.0"

#: public name -> (submodule, attribute or None for the submodule itself)
_EXPORTS = {
    "Params": ("params", "Params"),
    "DuffingParams": ("params", "DuffingParams"),
    "presets": ("presets", None),
    "simulate": ("simulate", "simulate"),
    "METHODS": ("simulate", "METHODS"),
    "Run": ("run", "Run"),
    "Status": ("run", "Status"),
    "Model": ("models", "Model"),
    "ROTOR": ("models", "ROTOR"),
    "DUFFING": ("models", "DUFFING"),
    "Regime": ("analysis.classify", "Regime"),
    "analysis": ("analysis", None),
    "sweep": ("sweeps.sweep", "sweep"),
    "intervals": ("sweeps.dataset", "intervals"),
    "SweepSettings": ("sweeps.point", "SweepSettings"),
    "transition_types": ("sweeps.transitions", "transition_types"),
    "map2d": ("maps.map2d", "map2d"),
}

__all__ = ["Params", "DuffingParams", "presets", "simulate", "Run", "Status", "Model",
           "ROTOR", "DUFFING", "METHODS", "Regime", "analysis", "sweep", "intervals", "SweepSettings",
           "transition_types",
           "map2d", "__version__"]


def _load(name):
    module, attr = _EXPORTS[name]
    mod = importlib.import_module(f"{__name__}.{module}")
    return mod if attr is None else getattr(mod, attr)


class _Package(types.ModuleType):
    """The package module: lazy exports, and ``vibimpact.simulate`` is always the function.

    Importing the submodule ``vibimpact.simulate`` makes the import system set the package
    attribute ``simulate`` to the submodule; the property below keeps the function.
    """

    @property
    def simulate(self):
        """:func:`vibimpact.simulate.simulate`."""
        return _load("simulate")

    @simulate.setter
    def simulate(self, value):
        if not isinstance(value, types.ModuleType):
            raise AttributeError("vibimpact.simulate cannot be replaced")

    def __getattr__(self, name):
        if name in _EXPORTS:
            value = _load(name)
            self.__dict__[name] = value
            return value
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(_EXPORTS))


sys.modules[__name__].__class__ = _Package
