r"""The hard-impact oscillator: a forced linear oscillator hitting a rigid stop.

``x'' + 2 zeta x' + x = A cos(eta t)`` while ``x < d``, and at the stop ``x = d`` the
impact law ``x'+ = -r x'-`` (kernel: :mod:`vibimpact._kernel.hard_impact`, over the
impulsive contact of :mod:`vibimpact._kernel.impulsive`: chattering sequences end at
their accumulation point in a sticking mode, released where the force pulls the mass off
the stop).  Shaw & Holmes (1983), "A periodically forced impact oscillator with large
dissipation", J. Appl. Mech. 50, 849-857; Nordmark (1991), J. Sound Vib. 145, 279-297;
Budd & Dux (1994), Phil. Trans. R. Soc. A 347, 365-389.

The period-1 single-impact orbit in closed form
-----------------------------------------------
Let ``T = 2 pi / eta``, ``w = sqrt(1 - zeta^2)`` (``zeta < 1``), and the free response
``x_p(t) = P cos(eta t - phi)`` with ``P = A / sqrt((1 - eta^2)^2 + (2 zeta eta)^2)``,
``phi = atan2(2 zeta eta, 1 - eta^2)``.  The homogeneous motion over a time ``tau`` is
``(h, h')(tau) = Phi(tau) (h, h')(0)`` with

    Phi(T) = exp(-zeta T) [[c + zeta s / w,  s / w], [-s / w,  c - zeta s / w]]
           =: [[a, b], [c', e]],      c = cos(w T),  s = sin(w T).

A period-1 orbit with one impact per period hits the stop at times ``t0 + k T`` with speed
``v > 0``.  Write ``theta = eta t0 - phi``, ``D = d - P cos(theta)`` (the homogeneous part
at the stop) and ``W = P eta sin(theta)`` (``= -x_p'(t0)``).  Right after an impact the
homogeneous part is ``(D, W - r v)``; one period later it must be ``(D, W + v)``
(``x_p`` is ``T``-periodic):

    D = a D + b (W - r v),          W + v = c' D + e (W - r v).

Eliminating ``v``: ``K D = b (1 + r) W`` with ``K = (1 - a)(1 + e r) + b r c'``, i.e.

    K P cos(theta) + b (1 + r) eta P sin(theta) = K d,
    theta = psi +- arccos(K d / (P sqrt(K^2 + (b (1 + r) eta)^2))),
    psi = atan2(b (1 + r) eta, K),
    v = (c' D + (e - 1) W) / (1 + e r),

of which an orbit is a root with ``v > 0`` whose flight stays below the stop (Shaw &
Holmes 1983, sec. 3, in other variables).  Its stability: over one period from just
after an impact the tangent map is ``M = S Phi(T)``, with the saltation matrix of the
impact (:mod:`vibimpact._kernel.variational`: the jump ``(x, v) -> (x, -r v)``, the
switch ``d - x``, the accelerations ``a-+ = A cos(eta t0) - d -+ 2 zeta v`` and
``+- 2 zeta r v`` before and after)

    S = [[-r, 0], [(1 + r)(A cos(eta t0) - d) / v, -r]],

so the Floquet multipliers are the roots of ``mu^2 - tr(S Phi(T)) mu + r^2 exp(-2 zeta
T) = 0`` (Shaw & Holmes' Jacobian of the impact map; ``det M = r^2 exp(-2 zeta T)``).
``tests/test_hard_impact.py`` checks both against the kernel's shooting and monodromy.
"""
from ..models.contact import Restitution, stop_contact
from ..models import Model, PlotSpec
from ..models.params import Domain, param_set

#: the parameters: (name, default, domain, meaning), in the kernel's order
_TABLE = [
    ("zeta", 0.05, Domain.at_least(0.0), "viscous damping ratio of the free motion"),
    ("d", 0.5, None, "position of the rigid stop (the mass is free while x < d)"),
    ("r", 0.7, Domain(0.0, 1.0, True, True),
     "Newton's coefficient of restitution of the stop (x'+ = -r x'-)"),
    ("A", 1.0, None, "amplitude of the harmonic force"),
    ("eta", 1.3, Domain.above(0.0), "forcing over natural frequency"),
]
HardImpactParams = param_set("HardImpactParams", _TABLE, omega="eta", module=__name__,
                             doc="Dimensionless parameters of the hard-impact oscillator.")


MODEL = Model.builtin_model(
    "hard_impact", "hard_impact", ("x", "dx"), omega_index=4, param_set=HardImpactParams,
    bound=1e6,
    contact=stop_contact(Restitution("r"), 0, 1, 1, extremum=1),
    plot=PlotSpec(xy=("x", "dx"), symbols={"eta": "η"}),
    presets={"hard-impact": (dict(zeta=0.05, d=0.5, r=0.7, A=1.0, eta=1.3),
                             "hard-impact oscillator: a stable period-1 orbit with one "
                             "impact per period (Shaw & Holmes 1983)"),
             "hard-impact-chatter": (dict(zeta=0.05, d=0.0, r=0.5, A=1.0, eta=0.5),
                                     "hard-impact oscillator with the stop at the rest "
                                     "position: chattering and sticking every period")},
    references="S. W. Shaw, P. J. Holmes (1983): A periodically forced impact oscillator "
               "with large dissipation, J. Appl. Mech. 50, 849-857; A. B. Nordmark (1991): "
               "Non-periodic motion caused by grazing incidence in an impact oscillator, "
               "J. Sound Vib. 145, 279-297; C. Budd, F. Dux (1994): Chattering and "
               "related behaviour in impact oscillators, Phil. Trans. R. Soc. A 347, "
               "365-389")
