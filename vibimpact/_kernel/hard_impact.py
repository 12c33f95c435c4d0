"""The hard-impact oscillator: a harmonically forced linear oscillator that hits a rigid
stop at distance ``d`` and rebounds with a coefficient of restitution ``r``.

    x'' + 2 zeta x' + x = A cos(eta s)   for x < d;    x'+ = -r x'-   at x = d

State ``y = (x, x')``; ``p`` laid out as :data:`PARAM_NAMES`.  The stop is an impulsive
contact (:mod:`.impulsive`): impacts reverse the velocity, a chattering sequence is ended
at its accumulation point and the stop then holds the mass while the force presses it
into the stop (``mode[0] = 1``).  The model of Shaw & Holmes (1983), "A periodically
forced piecewise linear oscillator", J. Sound Vib. 90, 129-155; Shaw & Holmes (1983),
"A periodically forced impact oscillator with large dissipation", J. Appl. Mech. 50,
849-857; Nordmark (1991), "Non-periodic motion caused by grazing incidence in an impact
oscillator", J. Sound Vib. 145, 279-297; Budd & Dux (1994), Phil. Trans. R. Soc. A 347,
365-389.  Switching functions: those of :mod:`.impulsive` (0: the stop, terminal; 1: the
velocity, observer; 2: the end of a chattering sequence, terminal).
"""
import math

from numba import njit

from .impulsive import N_MODE, TERMINAL, stop_model
from .jitopts import INNER, LEAF
from .registry import kernel_model

PARAM_NAMES = ("zeta", "d", "r", "A", "eta")
I_ZETA, I_D, I_R, I_A, I_ETA = range(5)
N_STATE = 2


@njit(**INNER)
def accel(s, y, p):
    """The free acceleration ``A cos(eta s) - 2 zeta x' - x``."""
    return p[I_A] * math.cos(p[I_ETA] * s) - 2.0 * p[I_ZETA] * y[1] - y[0]


@njit(**LEAF)
def free_rhs(s, y, p, out):
    """The free motion's right-hand side; writes ``out`` (shape (2,))."""
    out[0] = y[1]
    out[1] = accel(s, y, p)


@njit(**LEAF)
def free_jac(s, y, p, J):
    """The free motion's Jacobian; writes ``J`` (shape (2, 2))."""
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0] = -1.0
    J[1, 1] = -2.0 * p[I_ZETA]


rhs, jac, switches, transition, init_mode = stop_model(free_rhs, free_jac, accel, N_STATE,
                                                       0, 1, I_D, I_R)

KERNEL_MODEL = kernel_model(rhs, jac, switches, transition, init_mode, N_STATE, N_MODE,
                            TERMINAL, PARAM_NAMES)
