"""Variational (tangent) equations of a piecewise-smooth model, with saltation matrices.

The augmented state is ``y = (x, v_1, ..., v_m)``: the model state ``x`` (``n`` entries)
followed by ``m`` tangent vectors of ``n`` entries each (column ``c`` at
``y[n + c n : n + (c + 1) n]``).  Inside a mode the tangent vectors obey
``v' = J(s, x) v`` with the model's analytic Jacobian.  At a switching event the vector
field jumps from ``f-`` to ``f+`` and the tangent vectors are mapped by the *saltation
matrix* (Aizerman & Gantmacher 1958; Müller 1995, "Calculation of Lyapunov exponents for
dynamic systems with discontinuities", Chaos Solitons Fractals 5, 1671-1681;
Leine & Nijmeijer 2004, *Dynamics and Bifurcations of Non-Smooth Mechanical Systems*,
sec. 3.5)::

    S = I + (f+ - f-) grad(g)^T / (grad(g) . f- + dg/ds)

where ``g`` is the switching function that vanished.  Without it the tangent vectors
would be those of a smooth flow and the exponents wrong wherever the field jumps (the
tangential damping ``BT`` at contact entry and exit; slip to stick).  Entering a Filippov
stick phase ``S`` projects the vectors onto the sliding surface.

The gradient of ``g`` is taken by central differences of the model's own switching
functions (in the mode before the event), so the same code serves every model.
Everything here is ``@njit`` over plain arrays.
"""
import numpy as np
from numba import njit

from . import duffing, rotor
from .jitopts import INNER, INNER_ALLOC


@njit(**INNER)
def tangent_product(J, y, n, out):
    """``out[n + c n + i] = sum_j J[i, j] y[n + c n + j]`` for every tangent column ``c``."""
    m = (y.size - n) // n
    for c in range(m):
        base = n + c * n
        for i in range(n):
            acc = 0.0
            for j in range(n):
                acc += J[i, j] * y[base + j]
            out[base + i] = acc


@njit(**INNER)
def apply_saltation(y, n, fm, fp, grad, g_s):
    """Map every tangent column by ``S = I + (fp - fm) grad^T / (grad . fm + g_s)``.

    A grazing event (denominator zero to rounding) leaves the vectors unchanged: the
    saltation matrix is unbounded there and the exponent of a grazing orbit is not defined.
    """
    den = g_s
    jump = 0.0
    for i in range(n):
        den += grad[i] * fm[i]
        jump += abs(fp[i] - fm[i])
    if jump == 0.0 or den == 0.0 or not np.isfinite(den):
        return
    m = (y.size - n) // n
    for c in range(m):
        base = n + c * n
        dot = 0.0
        for j in range(n):
            dot += grad[j] * y[base + j]
        coef = dot / den
        for i in range(n):
            y[base + i] += (fp[i] - fm[i]) * coef


@njit(**INNER)
def fd_step(v):
    """Central-difference step for a variable of size ``v``."""
    return 1e-6 * max(1.0, abs(v))


# --- the rotor -------------------------------------------------------------------------

@njit(**INNER)
def rotor_rhs(s, y, p, mode, out):
    """Rotor state and tangent vectors (``y.size = 4 (1 + m)``)."""
    rotor.rhs(s, y, p, mode, out)
    # the Jacobian as scalars (no array allocated per evaluation: this runs at every
    # stage of the Lyapunov and Floquet integrations)
    j20, j21, j22, j23, j30, j31, j32, j33 = rotor.jac_rows(s, y, p, mode)
    m = (y.size - 4) // 4
    for c in range(m):
        b = 4 + 4 * c
        v0 = y[b]
        v1 = y[b + 1]
        v2 = y[b + 2]
        v3 = y[b + 3]
        out[b] = v2
        out[b + 1] = v3
        out[b + 2] = j20 * v0 + j21 * v1 + j22 * v2 + j23 * v3
        out[b + 3] = j30 * v0 + j31 * v1 + j32 * v2 + j33 * v3


@njit(**INNER_ALLOC)
def rotor_transition(s, y, p, mode, which):
    """Mode change of the rotor plus the saltation map of the tangent vectors."""
    n = np.int64(4)  # not a literal: apply_saltation would be compiled for it alone
    x = y[:n].copy()
    fm = np.empty(n)
    rotor.rhs(s, x, p, mode, fm)
    grad = np.empty(n)
    g = np.empty(rotor.N_SWITCH)
    xp = x.copy()
    for j in range(n):
        d = fd_step(x[j])
        xp[j] = x[j] + d
        rotor.switches(s, xp, p, mode, g)
        gp = g[which]
        xp[j] = x[j] - d
        rotor.switches(s, xp, p, mode, g)
        grad[j] = (gp - g[which]) / (2.0 * d)
        xp[j] = x[j]
    d = fd_step(s)
    rotor.switches(s + d, x, p, mode, g)
    gp = g[which]
    rotor.switches(s - d, x, p, mode, g)
    g_s = (gp - g[which]) / (2.0 * d)
    old0 = mode[0]
    old1 = mode[1]
    rotor.transition(s, y, p, mode, which)
    if mode[0] == old0 and mode[1] == old1:
        return
    fp = np.empty(n)
    rotor.rhs(s, x, p, mode, fp)
    apply_saltation(y, n, fm, fp, grad, g_s)


# --- the Duffing oscillator (smooth: no terminal switches) ------------------------------

@njit(**INNER)
def duffing_rhs(s, y, p, mode, out):
    """Duffing state and tangent vectors (``y.size = 2 (1 + m)``)."""
    duffing.rhs(s, y, p, mode, out)
    j10, j11 = duffing.jac_row(s, y, p)
    m = (y.size - 2) // 2
    for c in range(m):
        b = 2 + 2 * c
        v0 = y[b]
        v1 = y[b + 1]
        out[b] = v1
        out[b + 1] = j10 * v0 + j11 * v1


# --- user models (functions passed in; compiled per process) ----------------------------

@njit(error_model="numpy", _nrt=True)
def user_rhs(rhs, jac, n, s, y, p, mode, out):
    """A user model's state and tangent vectors."""
    rhs(s, y, p, mode, out)
    J = np.empty((n, n))
    jac(s, y, p, mode, J)
    tangent_product(J, y, n, out)


@njit(error_model="numpy", _nrt=True)
def user_transition(rhs, switches, transition, n, n_switch, s, y, p, mode, which):
    """A user model's mode change plus the saltation map of the tangent vectors."""
    x = y[:n].copy()
    fm = np.empty(n)
    rhs(s, x, p, mode, fm)
    grad = np.empty(n)
    g = np.empty(n_switch)
    xp = x.copy()
    for j in range(n):
        d = fd_step(x[j])
        xp[j] = x[j] + d
        switches(s, xp, p, mode, g)
        gp = g[which]
        xp[j] = x[j] - d
        switches(s, xp, p, mode, g)
        grad[j] = (gp - g[which]) / (2.0 * d)
        xp[j] = x[j]
    d = fd_step(s)
    switches(s + d, x, p, mode, g)
    gp = g[which]
    switches(s - d, x, p, mode, g)
    g_s = (gp - g[which]) / (2.0 * d)
    old = mode.copy()
    transition(s, y, p, mode, which)
    same = True
    for i in range(mode.size):
        if mode[i] != old[i]:
            same = False
    if same:
        return
    fp = np.empty(n)
    rhs(s, x, p, mode, fp)
    apply_saltation(y, n, fm, fp, grad, g_s)

