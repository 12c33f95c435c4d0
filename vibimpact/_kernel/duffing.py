"""Forced Duffing oscillator ``x'' + delta x' + alpha x + beta x^3 = gamma cos(omega t)``.

A smooth second model of the kernel, built in so that every integrator and analyser can be
checked on a system with published results (Guckenheimer & Holmes 1983, sec. 2.2;
Kovacic & Brennan (eds.), *The Duffing Equation*, Wiley 2011).

State ``y = (x, x')``; ``p = (delta, alpha, beta, gamma, omega)``.  One switching function,
an observer: ``x'`` (its crossings to negative values mark the maxima of ``x``).  The mode
array is unused but kept so the model has the kernel's common signature.
"""
import math

import numpy as np
from numba import njit

from .jitopts import INNER, LEAF
from .registry import KernelModel

PARAM_NAMES = ("delta", "alpha", "beta", "gamma", "omega")
N_STATE = 2
N_MODE = 1
N_SWITCH = 1
TERMINAL = np.array([0], dtype=np.int64)


@njit(**LEAF)
def rhs(s, y, p, mode, out):
    """Right-hand side; writes ``out`` (shape (2,))."""
    x, v = y[0], y[1]
    out[0] = v
    out[1] = p[3] * math.cos(p[4] * s) - p[0] * v - p[1] * x - p[2] * x * x * x


@njit(**LEAF)
def jac(s, y, p, mode, J):
    """Analytic Jacobian; writes ``J`` (shape (2, 2))."""
    J[0, 0] = 0.0
    J[0, 1] = 1.0
    J[1, 0], J[1, 1] = jac_row(s, y, p)


@njit(**LEAF)
def jac_row(s, y, p):
    """Row 1 of the Jacobian, ``(d x''/d x, d x''/d x')`` (row 0 is ``(0, 1)``)."""
    return -p[1] - 3.0 * p[2] * y[0] * y[0], -p[0]


@njit(**LEAF)
def switches(s, y, p, mode, g):
    """Observer: velocity (maxima of ``x`` where it turns negative)."""
    g[0] = y[1]


@njit(**LEAF)
def init_mode(s, y, p, mode):
    """The Duffing oscillator is smooth: a single mode."""
    mode[0] = 0


@njit(**LEAF)
def transition(s, y, p, mode, which):
    """No terminal switches: nothing to do."""
    return


# --- the variational equations (smooth: no saltation) -----------------------------------

@njit(**INNER)
def var_rhs(s, y, p, mode, out):
    """Duffing state and tangent vectors (``y.size = 2 (1 + m)``)."""
    rhs(s, y, p, mode, out)
    j10, j11 = jac_row(s, y, p)
    m = (y.size - 2) // 2
    for c in range(m):
        b = 2 + 2 * c
        v0 = y[b]
        v1 = y[b + 1]
        out[b] = v1
        out[b + 1] = j10 * v0 + j11 * v1


KERNEL_MODEL = KernelModel(rhs=rhs, jac=jac, switches=switches, transition=transition,
                           init_mode=init_mode, var_rhs=var_rhs, var_transition=transition,
                           step_cap=None, n_state=N_STATE, n_mode=N_MODE, terminal=TERMINAL,
                           param_names=PARAM_NAMES)
