"""The soft-impact oscillator: a forced linear oscillator hitting a spring stop.

``x'' + 2 zeta x' + x + H(x - d) k (x - d)(1 + c x') = A cos(eta t)`` (kernel:
:mod:`vibimpact._kernel.soft_impact`).  Below grazing it is the linear oscillator, with the
analytic response ``x(t) = A/|1 - eta^2 + 2 i zeta eta| cos(eta t - phi)``; it grazes the
stop where that amplitude equals ``d``, and past grazing the undamped stop (``c = 0``,
a force continuous in the state) changes the periodic orbit by a term of order 3/2 in the
distance past grazing (di Bernardo, Budd & Champneys 2001, "Normal form maps for grazing
bifurcations in n-dimensional piecewise-smooth dynamical systems", Physica D 160,
222-254; Ing et al. 2008, Phil. Trans. R. Soc. A 366, 679-705).  Both are checked in
``tests/test_soft_impact.py``.
"""

from ..models.contact import ContactLaw, stop_contact
from ..models import Model, PlotSpec
from ..models.params import Domain, param_set

SoftImpactParams = param_set(
    "SoftImpactParams",
    [("zeta", 0.05, Domain.at_least(0.0), "damping ratio of the oscillator"),
     ("k", 29.0, Domain.at_least(0.0), "stiffness of the stop relative to the oscillator's"),
     ("c", 0.0, Domain.at_least(0.0), "material damping of the stop (force k d (1 + c d'))"),
     ("d", 1.0, None, "distance from the oscillator's rest position to the stop"),
     ("A", 0.3, None, "forcing amplitude"),
     ("eta", 0.8, Domain.above(0.0), "forcing frequency relative to the natural one")],
    omega="eta", module=__name__,
    doc="Dimensionless parameters of the soft-impact oscillator.")


MODEL = Model.builtin_model(
    "soft_impact", "soft_impact", ("x", "dx"), omega_index=5, param_set=SoftImpactParams,
    bound=1e6,
    contact=stop_contact(ContactLaw(stiffness="k", exponent=1.0, damping="c"), 0, 1, 3,
                         extremum=1),
    plot=PlotSpec(xy=("x", "dx"), symbols={"eta": "η"}),
    presets={"soft-impact": (dict(zeta=0.05, k=29.0, c=0.0, d=1.0, A=0.3, eta=0.8),
                             "soft-impact oscillator below grazing (linear response)"),
             "soft-impact-grazing": (dict(zeta=0.05, k=29.0, c=0.0, d=1.0, A=0.3, eta=0.86),
                                     "soft-impact oscillator just past grazing")},
    references="M. di Bernardo, C. J. Budd, A. R. Champneys (2001): Normal form maps for "
               "grazing bifurcations in n-dimensional piecewise-smooth dynamical systems, "
               "Physica D 160, 222-254; J. Ing, E. Pavlovskaia, M. Wiercigroch, S. "
               "Banerjee (2008): Experimental study of impact oscillator with one-sided "
               "elastic constraint, Phil. Trans. R. Soc. A 366, 679-705")
