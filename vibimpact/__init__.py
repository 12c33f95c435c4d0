"""vibimpact: bifurcation and chaos analysis of vibro-impact rotors.

The model is the rigid rotor on passive magnetic bearings hitting its retainer bearing of
Pust & Kozanek, "Vibrations of rotor supported in magnetic bearings with impacts", eq. (5).

>>> import vibimpact as vi
>>> p = vi.presets.get("fig8").replace(eta=1.25)
>>> run = vi.simulate(p, periods=200, transient=500)
"""
from . import presets
from .models import DUFFING, ROTOR, Model
from .params import DuffingParams, Params
from .run import Run, Status
from .simulate import METHODS, simulate

__version__ = "0.1.0"

__all__ = ["Params", "DuffingParams", "presets", "simulate", "Run", "Status", "Model",
           "ROTOR", "DUFFING", "METHODS", "__version__"]
