"""Variational (tangent) equations of a piecewise-smooth model, with saltation matrices.

The augmented state is ``y = (x, v_1, ..., v_m)``: the model state ``x`` (``n`` entries)
followed by ``m`` tangent vectors of ``n`` entries each (column ``c`` at
``y[n + c n : n + (c + 1) n]``).  Inside a mode the tangent vectors obey
``v' = J(s, x) v`` with the model's analytic Jacobian.  At a located event of switching
function ``g`` the model's ``transition`` changes the mode and may map the state by a
jump ``x+ = R(x-)`` (an instantaneous impact: a velocity reversed with a coefficient of
restitution); the vector field jumps from ``f- = f(x-)`` in the old mode to
``f+ = f(x+)`` in the new one, and the tangent vectors are mapped by the *saltation
matrix* (Aizerman & Gantmacher 1958; Müller 1995, "Calculation of Lyapunov exponents for
dynamic systems with discontinuities", Chaos Solitons Fractals 5, 1671-1681;
Leine & Nijmeijer 2004, *Dynamics and Bifurcations of Non-Smooth Mechanical Systems*,
sec. 3.5 and 7.2; di Bernardo et al. 2008, *Piecewise-smooth Dynamical Systems*, sec.
2.5)::

    S = DR + (f+ - DR f-) grad(g)^T / (grad(g) . f- + dg/ds)

With no jump (``R`` the identity: a force law switching, the state continuous) it is
``S = I + (f+ - f-) grad(g)^T / (grad(g) . f- + dg/ds)``.  Without it the tangent
vectors would be those of a smooth flow and the exponents wrong wherever the field jumps
(the tangential damping ``BT`` at contact entry and exit; slip to stick; every impact).
Entering a Filippov stick phase ``S`` projects the vectors onto the sliding surface.

The gradient of ``g`` is taken by central differences of the model's own switching
functions (in the mode before the event), the Jacobian ``DR`` of the jump by central
differences of the model's own ``transition`` (in the mode before the event), so the same
code serves every model: it is written once, in :func:`_saltation_body`, and built for a
built-in model (:func:`saltation_transition`) or a user model (:func:`user_transition`).
Everything here that runs is ``@njit`` over plain arrays.
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
def apply_saltation(y, n, fm, fp, grad, g_s, DR, w):
    """Map every tangent column by the saltation matrix.

    ``S = DR + (fp - DR fm) grad^T / (grad . fm + g_s)`` after a jump of the state with
    Jacobian ``DR`` (``w``: scratch of ``n`` entries); ``S = I + (fp - fm) grad^T /
    (grad . fm + g_s)`` when ``DR`` is None (the state continuous: numba compiles that
    case on its own, without the products by ``DR``).  A grazing event (denominator zero
    to rounding) leaves the correction out (only ``DR`` applies): the saltation matrix is
    unbounded there and the exponent of a grazing orbit is not defined.
    """
    den = g_s
    jump = 0.0
    for i in range(n):
        den += grad[i] * fm[i]
        jump += abs(fp[i] - fm[i])
    m = (y.size - n) // n
    if DR is None:
        if jump == 0.0 or den == 0.0 or not np.isfinite(den):
            return
        for c in range(m):
            base = n + c * n
            dot = 0.0
            for j in range(n):
                dot += grad[j] * y[base + j]
            coef = dot / den
            for i in range(n):
                y[base + i] += (fp[i] - fm[i]) * coef
        return
    bounded = den != 0.0 and np.isfinite(den)
    for c in range(m):
        base = n + c * n
        dot = 0.0
        for j in range(n):
            dot += grad[j] * y[base + j]
        coef = dot / den if bounded else 0.0
        for i in range(n):
            acc = 0.0
            for j in range(n):
                acc += DR[i, j] * y[base + j]
            w[i] = acc
        for i in range(n):
            jf = 0.0
            for j in range(n):
                jf += DR[i, j] * fm[j]
            y[base + i] = w[i] + (fp[i] - jf) * coef


@njit(**INNER)
def fd_step(v):
    """Central-difference step for a variable of size ``v``."""
    return 1e-6 * max(1.0, abs(v))


def _saltation_body(rhs, switches, transition, options):
    """The one variational mode change: the model's ``transition`` at an event of switch
    ``which``, then the saltation map of the tangent vectors (:func:`apply_saltation`).

    Returns an ``@njit`` function ``body(n, n_switch, s, y, p, mode, which)`` compiled
    with ``options``, over the model's functions ``rhs``, ``switches``, ``transition``
    (bound here, not passed as arguments: a call that passes numba functions as arguments
    makes numba refuse to cache the whole kernel of the model, "dynamic globals").
    """
    @njit(**options)
    def body(n, n_switch, s, y, p, mode, which):
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
        jumped = False
        for i in range(n):
            if y[i] != x[i]:
                jumped = True
        if same and not jumped:
            return
        fp = np.empty(n)
        if not jumped:
            rhs(s, x, p, mode, fp)
            apply_saltation(y, n, fm, fp, grad, g_s, None, None)
            return
        # the jump's Jacobian, from the transition in the mode before
        DR = np.empty((n, n))
        up = np.empty(n)
        dn = np.empty(n)
        for j in range(n):
            d = fd_step(x[j])
            up[:] = x
            up[j] = x[j] + d
            mode[:] = old
            transition(s, up, p, mode, which)
            dn[:] = x
            dn[j] = x[j] - d
            mode[:] = old
            transition(s, dn, p, mode, which)
            for i in range(n):
                DR[i, j] = (up[i] - dn[i]) / ((x[j] + d) - (x[j] - d))
        mode[:] = old
        transition(s, x, p, mode, which)  # x is now the state after the jump
        rhs(s, x, p, mode, fp)
        apply_saltation(y, n, fm, fp, grad, g_s, DR, up)
    return body


# --- user models (functions passed in; compiled per process) ----------------------------

@njit(**USER_ALLOC)
def user_rhs(rhs, jac, n, s, y, p, mode, out):
    """A user model's state and tangent vectors."""
    rhs(s, y, p, mode, out)
    J = np.empty((n, n))
    jac(s, y, p, mode, J)
    tangent_product(J, y, n, out)


_USER: dict = {}


def user_transition(rhs, switches, transition):
    """A user model's mode change plus the saltation map of the tangent vectors: the
    function ``body(n, n_switch, s, y, p, mode, which)`` of :func:`_saltation_body` over
    the user's numba functions (built once per model, compiled per process with the
    runtime on, so that the user's functions may allocate)."""
    key = (rhs, switches, transition)
    body = _USER.get(key)
    if body is None:
        body = _USER[key] = _saltation_body(rhs, switches, transition,
                                            USER_ALLOC)
    return body


# --- built-in models --------------------------------------------------------------------

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
    saltation map of the tangent vectors, :func:`_saltation_body`): an ``@njit`` function
    for its ``KERNEL_MODEL`` (``n`` state entries, ``n_switch`` switching functions)."""
    body = _saltation_body(rhs, switches, transition, INNER_ALLOC)

    @njit(**INNER_ALLOC)
    def var_transition(s, y, p, mode, which):
        # not literals: the body would be compiled for them alone
        body(np.int64(n), np.int64(n_switch), s, y, p, mode, which)
    return var_transition
