"""The soft-impact oscillator: a harmonically forced linear oscillator that hits a spring
stop (a one-sided elastic constraint) at distance ``d``.

    x'' + 2 zeta x' + x + H(x - d) k (x - d) (1 + c x') = A cos(eta s)

State ``y = (x, x')``; ``p`` laid out as :data:`PARAM_NAMES`.  In contact (``mode[0] =
1``) the stop adds a linear spring of stiffness ``k`` (relative to the oscillator's) with
material damping ``c`` in the form of the rotor's Hertz law (``c = 0``: an undamped stop,
whose force is continuous in the state: a piecewise-smooth *continuous* flow).

The classic model of grazing bifurcations: Nordmark (1991); Ing, Pavlovskaia, Wiercigroch
& Banerjee (2008), "Experimental study of impact oscillator with one-sided elastic
constraint", Phil. Trans. R. Soc. A 366, 679-705; di Bernardo, Budd, Champneys &
Kowalczyk (2008), *Piecewise-smooth Dynamical Systems*, Springer, ch. 7.

=====  ==========================================  ==========
index  switching function                          kind
=====  ==========================================  ==========
0      free: ``d - x``; contact: ``x - d``          terminal
1      ``x'`` (extrema of ``x``: peak penetration)  observer
=====  ==========================================  ==========
"""
import math

import numpy as np
from numba import njit

from .jitopts import LEAF
from .registry import kernel_model

PARAM_NAMES = ("zeta", "k", "c", "d", "A", "eta")
I_ZETA, I_K, I_C, I_D, I_A, I_ETA = range(6)
N_STATE = 2
N_MODE = 1
TERMINAL = np.array([1, 0], dtype=np.int64)


@njit(**LEAF)
def rhs(s, y, p, mode, out):
    """Right-hand side in the given mode; writes ``out`` (shape (2,))."""
    x, v = y[0], y[1]
    a = p[I_A] * math.cos(p[I_ETA] * s) - 2.0 * p[I_ZETA] * v - x
    if mode[0] == 1:
        a -= p[I_K] * (x - p[I_D]) * (1.0 + p[I_C] * v)
    out[0] = v
    out[1] = a


@njit(**LEAF)
def jac(s, y, p, mode, J):
    """Analytic Jacobian in the given mode; writes ``J`` (shape (2, 2))."""
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0] = -1.0
    J[1, 1] = -2.0 * p[I_ZETA]
    if mode[0] == 1:
        J[1, 0] -= p[I_K] * (1.0 + p[I_C] * y[1])
        J[1, 1] -= p[I_K] * (y[0] - p[I_D]) * p[I_C]


@njit(**LEAF)
def switches(s, y, p, mode, g):
    """Contact (positive while the mode is consistent) and the velocity observer."""
    g[0] = y[0] - p[I_D] if mode[0] == 1 else p[I_D] - y[0]
    g[1] = y[1]


@njit(**LEAF)
def init_mode(s, y, p, mode):
    """In contact where ``x > d`` (at ``x = d``: in contact when moving into the stop)."""
    mode[0] = 1 if (y[0] > p[I_D] or (y[0] == p[I_D] and y[1] > 0.0)) else 0


@njit(**LEAF)
def transition(s, y, p, mode, which):
    """Contact entry or exit at switch 0."""
    if which == 0:
        mode[0] = 1 - mode[0]


KERNEL_MODEL = kernel_model(rhs, jac, switches, transition, init_mode, N_STATE, N_MODE,
                            TERMINAL, PARAM_NAMES)
