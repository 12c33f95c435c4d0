"""The forced Duffing oscillator ``x'' + delta x' + alpha x + beta x^3 = gamma cos(omega t)``:
a smooth model with published results (Guckenheimer & Holmes 1983, sec. 2.2), on which
every integrator and analyser is checked.

Kernel: :mod:`vibimpact._kernel.duffing`.  Parameters: :class:`DuffingParams`
(``vi.DuffingParams``).  No contact.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..models import Model, PlotSpec
from ..models.params import Domain, ParamsMixin

#: the domain of each Duffing parameter that has one (validated in this order)
_DUFFING_DOMAINS = {"delta": Domain.at_least(0.0), "omega": Domain.above(0.0)}


@dataclass(frozen=True)
class DuffingParams(ParamsMixin):
    """Forced Duffing oscillator ``x'' + delta x' + alpha x + beta x^3 = gamma cos(omega t)``.

    Raises
    ------
    ValueError
        Naming the parameter, for a non-finite value, ``delta < 0`` or ``omega <= 0``.
    """

    delta: float = 0.3
    alpha: float = -1.0
    beta: float = 1.0
    gamma: float = 0.5
    omega: float = 1.2

    _DOMAINS = _DUFFING_DOMAINS
    _FREQUENCY = "omega"


MODEL = Model.builtin_model("duffing", "duffing", ("x", "dx"), omega_index=4,
                            param_set=DuffingParams, bound=1e6,
                            plot=PlotSpec(xy=("x", "dx"), symbols={"omega": "ω"}),
                            references="J. Guckenheimer, P. Holmes (1983): Nonlinear "
                                       "Oscillations, Dynamical Systems, and Bifurcations "
                                       "of Vector Fields, Springer, sec. 2.2")
