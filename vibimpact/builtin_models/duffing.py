"""The forced Duffing oscillator ``x'' + delta x' + alpha x + beta x^3 = gamma cos(omega t)``:
a smooth model with published results (Guckenheimer & Holmes 1983, sec. 2.2), on which
every integrator and analyser is checked.

Kernel: :mod:`vibimpact._kernel.duffing`.  Parameters: :class:`vibimpact.DuffingParams`.
No contact.
"""
from ..models import Model, PlotSpec
from ..models.params import DuffingParams

MODEL = Model.builtin_model("duffing", "duffing", ("x", "dx"), omega_index=4,
                            param_set=DuffingParams, bound=1e6,
                            plot=PlotSpec(xy=("x", "dx")))
