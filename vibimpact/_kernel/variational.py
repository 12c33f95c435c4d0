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

from .jitopts import INNER, INNER_ALLOC, USER_ALLOC


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


# --- user models (functions passed in; compiled per process) ----------------------------

@njit(**USER_ALLOC)
def user_rhs(rhs, jac, n, s, y, p, mode, out):
    """A user model's state and tangent vectors."""
    rhs(s, y, p, mode, out)
    J = np.empty((n, n))
    jac(s, y, p, mode, J)
    tangent_product(J, y, n, out)


@njit(**USER_ALLOC)
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



# --- built-in models without hand-written variational equations -------------------------

def tangent_rhs(rhs, jac, n):
    """The variational right-hand side of a built-in model from its ``rhs`` and analytic
    ``jac`` (``n`` state entries): an ``@njit`` function for its ``KERNEL_MODEL``."""
    @njit(**INNER_ALLOC)
    def var_rhs(s, y, p, mode, out):
        rhs(s, y, p, mode, out)
        J = np.empty((n, n))
        jac(s, y, p, mode, J)
        tangent_product(J, y, n, out)
    return var_rhs


def saltation_transition(rhs, switches, transition, n, n_switch):
    """The variational mode change of a built-in model (its ``transition`` plus the
    saltation map of the tangent vectors): an ``@njit`` function for its
    ``KERNEL_MODEL``.

    Its body is :func:`user_transition`'s, written out over the bound functions rather
    than calling it: a call that passes numba functions as arguments makes numba refuse
    to cache the whole kernel of the model ("dynamic globals"): a soft-impact run then
    compiles its kernel in every process instead of loading it from the cache.
    """
    @njit(**INNER_ALLOC)
    def var_transition(s, y, p, mode, which):
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
    return var_transition
