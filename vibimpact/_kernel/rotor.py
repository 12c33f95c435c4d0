"""The rotor of Pust & Kozanek, eq. (5), as a kernel model (all ``@njit``).

State ``y = (X, Y, X', Y')``; parameter vector ``p`` laid out as :data:`PARAM_NAMES`
(the order of :class:`vibimpact.Params`, then the friction regularisation ``eps``).

The right-hand side is piecewise smooth.  The kernel keeps a *discrete mode* next to the
state, an int64 array of two entries:

``mode[0]``
    0 = free flight, 1 = contact with the retainer (``R > 1``).
``mode[1]``
    friction state in contact: +1 slipping with ``v_t > 0``, -1 slipping with ``v_t < 0``,
    0 sticking (Filippov sliding mode on ``v_t = 0``).

Within one mode the field is smooth; the integrator switches modes only at located events,
so no step ever straddles a discontinuity.  Switching functions are written so that each is
*positive while the current mode is consistent*; an event is its crossing to negative values.

=====  ====================================================  ==========
index  switching function                                    kind
=====  ====================================================  ==========
0      free: ``1 - R``; contact: ``R - 1``                     terminal
1      slip: ``s v_t``; stick: ``f F_r - |lambda|``;           terminal
       otherwise 1 (inactive)
2      ``dR/dtau`` (extrema of ``R``: peak penetration in      observer
       contact, closest approach in free flight)
=====  ====================================================  ==========

Filippov stick (Filippov 1988, *Differential Equations with Discontinuous Righthand Sides*;
Leine & Nijmeijer 2004, *Dynamics and Bifurcations of Non-Smooth Mechanical Systems*, ch. 2):
with ``L = X Y' - Y X'`` one has ``v_t = L/R + Rr eta`` and
``dv_t/dtau = e_t . a - (v_t - Rr eta) R'/R`` where ``e_t = (-Y, X)/R``.  The tangential
force that keeps ``v_t = 0`` is ``T = (v_t - Rr eta) R'/R - e_t . (F_ext - B v)`` (the
radial forces have no tangential part).  Of it, ``lambda = T + B_T v_t`` is friction; the
rotor sticks while ``|lambda| <= f F_r``.
"""
import math

import numpy as np
from numba import njit

from .jitopts import INNER, LEAF
from .registry import KernelModel
from .variational import saltation_transition

PARAM_NAMES = ("B", "k3", "kh", "Bh", "BT", "f", "Rr", "Ec", "G", "eta", "eps")
I_B, I_K3, I_KH, I_BH, I_BT, I_F, I_RR, I_EC, I_G, I_ETA, I_EPS = range(11)

N_STATE = 4
N_MODE = 2
N_SWITCH = 3
#: 1 = terminal switch (mode change, step restarted), 0 = observer (logged only)
TERMINAL = np.array([1, 1, 0], dtype=np.int64)

SW_CONTACT = 0
SW_FRICTION = 1
SW_EXTREMUM = 2


@njit(**INNER)
def geometry(y, p):
    """Radius, unit normal, unit tangent, radial speed, tangential contact speed."""
    X, Y, U, V = y[0], y[1], y[2], y[3]
    R = math.sqrt(X * X + Y * Y)
    if R > 0.0:
        nx = X / R
        ny = Y / R
    else:  # at the centre any direction will do (no contact there)
        nx = 1.0
        ny = 0.0
    Rd = nx * U + ny * V
    vt = nx * V - ny * U + p[I_RR] * p[I_ETA]
    return R, nx, ny, Rd, vt


@njit(**INNER)
def normal_force(R, Rd, p):
    """Hertz force ``F_r = kh (R-1)^{3/2} (1 + Bh R')`` and its partials dF/dR, dF/dR'."""
    d = R - 1.0
    if d <= 0.0:
        return 0.0, 0.0, 0.0
    sq = math.sqrt(d)
    damp = 1.0 + p[I_BH] * Rd
    Fr = p[I_KH] * d * sq * damp
    return Fr, 1.5 * p[I_KH] * sq * damp, p[I_KH] * d * sq * p[I_BH]


@njit(**INNER)
def external_force(s, y, p):
    """Forcing, weight and magnetic-support force (everything outside the contact)."""
    X, Y, U, V = y[0], y[1], y[2], y[3]
    eta = p[I_ETA]
    amp = p[I_EC] * eta * eta
    R2 = X * X + Y * Y
    lin = 1.0 + p[I_K3] * R2
    ax = amp * math.cos(eta * s) - p[I_B] * U - X * lin
    ay = amp * math.sin(eta * s) + p[I_G] - p[I_B] * V - Y * lin
    return ax, ay


@njit(**INNER)
def stick_force(s, y, p, R, nx, ny, Rd, vt):
    """Total tangential force that holds ``dv_t/dtau = 0`` (Filippov sliding)."""
    eta = p[I_ETA]
    amp = p[I_EC] * eta * eta
    fx = amp * math.cos(eta * s) - p[I_B] * y[2]
    fy = amp * math.sin(eta * s) + p[I_G] - p[I_B] * y[3]
    return (vt - p[I_RR] * eta) * Rd / R - (-ny * fx + nx * fy)


@njit(**INNER)
def slip_friction(v, Fr, p, sense):
    """Tangential force ``T = -BT v - f F_r sgn(v)`` of a slipping contact (``sgn`` is
    ``sense``, or ``tanh(v / eps)`` for ``eps > 0``) and its partials ``dT/dv`` and
    ``dT/dF_r``: the rotor's with ``v = v_t``, the ring model's with the slip velocity."""
    T = -p[I_BT] * v
    c = -p[I_BT]
    cf = 0.0
    if p[I_F] > 0.0:
        if p[I_EPS] > 0.0:
            th = math.tanh(v / p[I_EPS])
            T -= p[I_F] * Fr * th
            c -= p[I_F] * Fr * (1.0 - th * th) / p[I_EPS]
            cf = -p[I_F] * th
        else:
            T -= p[I_F] * Fr * sense
            cf = -p[I_F] * sense
    return T, c, cf


@njit(**LEAF)
def rhs(s, y, p, mode, out):
    """Right-hand side of eq. (5) in the given mode; writes ``out`` (shape (4,))."""
    rhs_mode(s, y, p, mode[0], mode[1], out)


@njit(**INNER)
def rhs_mode(s, y, p, contact, friction, out):
    """:func:`rhs` with the two mode entries as scalars (for callers without a mode
    array, such as a C callback of an external integrator)."""
    ax, ay = external_force(s, y, p)
    if contact == 1:
        R, nx, ny, Rd, vt = geometry(y, p)
        Fr, _, _ = normal_force(R, Rd, p)
        if friction == 0 and p[I_F] > 0.0 and p[I_EPS] == 0.0:
            T = stick_force(s, y, p, R, nx, ny, Rd, vt)
        else:
            T = -p[I_BT] * vt
            if p[I_F] > 0.0:
                if p[I_EPS] > 0.0:
                    T -= p[I_F] * Fr * math.tanh(vt / p[I_EPS])
                else:
                    T -= p[I_F] * Fr * friction
        ax += -Fr * nx - T * ny
        ay += -Fr * ny + T * nx
    out[0] = y[2]
    out[1] = y[3]
    out[2] = ax
    out[3] = ay


@njit(**INNER)
def jac_rows(s, y, p, mode):
    """Rows 2 and 3 of the analytic Jacobian ``d rhs / d y`` in the given mode.

    Rows 0 and 1 are ``(0, 0, 1, 0)`` and ``(0, 0, 0, 1)``.  Returned as a tuple of eight
    floats ``(J20, J21, J22, J23, J30, J31, J32, J33)``, so the variational right-hand side
    (called at every stage) needs no array of its own.
    """
    X, Y, U, V = y[0], y[1], y[2], y[3]
    B, k3 = p[I_B], p[I_K3]
    R2 = X * X + Y * Y
    lin = 1.0 + k3 * R2
    j20 = -lin - 2.0 * k3 * X * X
    j21 = -2.0 * k3 * X * Y
    j30 = -2.0 * k3 * X * Y
    j31 = -lin - 2.0 * k3 * Y * Y
    j22 = -B
    j33 = -B
    j23 = 0.0
    j32 = 0.0
    if mode[0] != 1:
        return j20, j21, j22, j23, j30, j31, j32, j33
    R, nx, ny, Rd, vt = geometry(y, p)
    Fr, dF_dR, dF_dRd = normal_force(R, Rd, p)
    # partials of the geometric quantities w.r.t. (X, Y, U, V)
    dR = (nx, ny, 0.0, 0.0)
    # dn/dx = (I - n n^T)/R ; e_t = (-ny, nx)
    dnx = ((1.0 - nx * nx) / R, -nx * ny / R, 0.0, 0.0)
    dny = (-nx * ny / R, (1.0 - ny * ny) / R, 0.0, 0.0)
    dRd = ((U - Rd * nx) / R, (V - Rd * ny) / R, nx, ny)
    L = X * V - Y * U
    dvt = ((V - L * nx / R) / R, (-U - L * ny / R) / R, -ny, nx)
    dF = (dF_dR * dR[0] + dF_dRd * dRd[0], dF_dR * dR[1] + dF_dRd * dRd[1],
          dF_dRd * dRd[2], dF_dRd * dRd[3])
    stick = mode[1] == 0 and p[I_F] > 0.0 and p[I_EPS] == 0.0
    dT0 = 0.0
    dT1 = 0.0
    dT2 = 0.0
    dT3 = 0.0
    if stick:
        eta = p[I_ETA]
        amp = p[I_EC] * eta * eta
        fx = amp * math.cos(eta * s) - B * U
        fy = amp * math.sin(eta * s) + p[I_G] - B * V
        T = stick_force(s, y, p, R, nx, ny, Rd, vt)
        w = (vt - p[I_RR] * eta) / R  # = L / R^2
        # T = w Rd - (-ny fx + nx fy);  w = L/R^2
        dL = (V, -U, -Y, X)
        dfx = (0.0, 0.0, -B, 0.0)
        dfy = (0.0, 0.0, 0.0, -B)
        R3 = R * R * R
        dT0 = (dL[0] / (R * R) - 2.0 * L * dR[0] / R3) * Rd + w * dRd[0] \
            - (-dny[0] * fx + dnx[0] * fy)
        dT1 = (dL[1] / (R * R) - 2.0 * L * dR[1] / R3) * Rd + w * dRd[1] \
            - (-dny[1] * fx + dnx[1] * fy)
        dT2 = dL[2] / (R * R) * Rd + w * dRd[2] - (-ny * dfx[2])
        dT3 = dL[3] / (R * R) * Rd + w * dRd[3] - (nx * dfy[3])
    else:
        T, c, cf = slip_friction(vt, Fr, p, mode[1])
        dT0 = c * dvt[0] + cf * dF[0]
        dT1 = c * dvt[1] + cf * dF[1]
        dT2 = c * dvt[2] + cf * dF[2]
        dT3 = c * dvt[3] + cf * dF[3]
    # contact acceleration: a_x += -Fr nx - T ny ; a_y += -Fr ny + T nx
    j20 += -dF[0] * nx - Fr * dnx[0] - dT0 * ny - T * dny[0]
    j21 += -dF[1] * nx - Fr * dnx[1] - dT1 * ny - T * dny[1]
    j22 += -dF[2] * nx - Fr * dnx[2] - dT2 * ny - T * dny[2]
    j23 += -dF[3] * nx - Fr * dnx[3] - dT3 * ny - T * dny[3]
    j30 += -dF[0] * ny - Fr * dny[0] + dT0 * nx + T * dnx[0]
    j31 += -dF[1] * ny - Fr * dny[1] + dT1 * nx + T * dnx[1]
    j32 += -dF[2] * ny - Fr * dny[2] + dT2 * nx + T * dnx[2]
    j33 += -dF[3] * ny - Fr * dny[3] + dT3 * nx + T * dnx[3]
    return j20, j21, j22, j23, j30, j31, j32, j33


@njit(**LEAF)
def jac(s, y, p, mode, J):
    """Analytic Jacobian ``d rhs / d y`` in the given mode; writes ``J`` (shape (4, 4))."""
    r = jac_rows(s, y, p, mode)
    for i in range(4):
        for j in range(4):
            J[i, j] = 0.0
    J[0, 2] = 1.0
    J[1, 3] = 1.0
    J[2, 0], J[2, 1], J[2, 2], J[2, 3] = r[0], r[1], r[2], r[3]
    J[3, 0], J[3, 1], J[3, 2], J[3, 3] = r[4], r[5], r[6], r[7]


#: target of a step capped at a contact's end: its velocity error, from the method's
#: constant, at this fraction of the error test's tolerance
HERTZ_SAFETY = 0.25
#: a step that ends short of a predicted contact exit stops at this fraction of the time
#: to it (a quadratic prediction: the step then crosses only if it is 25 % early)
EXIT_APPROACH = 0.75


@njit(**INNER)
def _hertz_step(gamma, c, w):
    """Step whose singular velocity error ``gamma c h^{5/2}`` has the scaled norm
    :data:`HERTZ_SAFETY` (``w``: norm of a unit velocity error along the contact's
    normal and friction directions)."""
    e = gamma * c * w
    if e <= 0.0:
        return 1e300
    return (HERTZ_SAFETY / e) ** 0.4


@njit(**INNER)
def step_cap(y, p, mode, f0, at_event, rtol, atol, n_norm, g_in, g_out):
    """Largest step from state ``y`` in contact that the Hertz singularity allows.

    Next to a contact's entry and exit the acceleration has a part ``c |t - t_e|^{3/2}``
    with ``c = kh |R'|^{3/2} |1 + Bh R'|`` (and ``f`` times it along the tangent), so a
    step touching the surface has a velocity error ``gamma c h^{5/2}`` for any order of
    the method, while its embedded error estimate may report a small fraction of it
    (:func:`vibimpact._kernel.tableaux.hertz_error_constants`).  Such steps are sized
    from the constant, so their accuracy does not rest on the estimate, and without the
    cascade of rejections an order-8 controller needs to find them:

    * the first step of a contact (``at_event`` on the surface): ``gamma_in``, ``c`` at
      the entry;
    * a step that may reach the exit, predicted from the quadratic ``R - 1 + R' t +
      R'' t^2 / 2`` (``R''`` from the acceleration ``f0[2:4]``): ``gamma_out``, the worst
      position of the exit inside the step, ``c`` at the predicted exit speed; a step
      that the prediction lets stop short of the exit by more than that stops at
      :data:`EXIT_APPROACH` of the time to it.

    Returns ``1e300`` (no cap) in free flight.  The error test still decides whether a
    step is accepted.

    Parameters
    ----------
    y : float64 array, shape (>= 4,)
        State at the step's start (a variational run's tangent entries are ignored).
    f0 : float64 array, shape (>= 4,)
        Right-hand side at the step's start.
    at_event : bool
        The step starts at a terminal event just located (a contact entry when ``y``
        lies on the surface moving out).
    rtol, atol : float
        Tolerances of the error test.
    n_norm : int
        Entries in the error norm (its root mean square divides by this).
    g_in, g_out : float
        The method's constants (the driver makes no call where they are 0: fixed steps).
    """
    if mode[0] != 1 or p[I_KH] <= 0.0:
        return 1e300
    R, nx, ny, Rd, vt = geometry(y, p)
    f = p[I_F]
    # scaled norm of a unit velocity error along the normal plus f times the tangent
    sx = atol + rtol * abs(y[2])
    sy = atol + rtol * abs(y[3])
    ex = abs(nx) + f * abs(ny)
    ey = abs(ny) + f * abs(nx)
    w = math.sqrt(((ex / sx) ** 2 + (ey / sy) ** 2) / n_norm)
    cap = 1e300
    if at_event and Rd > 0.0 and R - 1.0 < 1e-9:
        cap = _hertz_step(g_in, p[I_KH] * Rd * math.sqrt(Rd) * abs(1.0 + p[I_BH] * Rd), w)
    # time to the exit, R - 1 + Rd t + a t^2 / 2 = 0, smallest positive root
    g = max(R - 1.0, 0.0)
    a = (y[0] * f0[2] + y[1] * f0[3] + y[2] * y[2] + y[3] * y[3] - Rd * Rd) / R
    disc = Rd * Rd - 2.0 * a * g
    if disc < 0.0:
        return cap
    sq = math.sqrt(disc)
    t_exit = 1e300
    if a != 0.0:
        for r in ((-Rd - sq) / a, (-Rd + sq) / a):
            if 0.0 < r < t_exit:
                t_exit = r
    elif Rd < 0.0:
        t_exit = -g / Rd
    if t_exit >= 1e300:
        return cap
    v_exit = abs(Rd + a * t_exit)
    h_exit = _hertz_step(g_out, p[I_KH] * v_exit * math.sqrt(v_exit)
                         * abs(1.0 - p[I_BH] * v_exit), w)
    return min(cap, max(h_exit, EXIT_APPROACH * t_exit))


@njit(**LEAF)
def switches(s, y, p, mode, g):
    """Switching functions (see module docstring); writes ``g`` (shape (3,))."""
    R, nx, ny, Rd, vt = geometry(y, p)
    if mode[0] == 1:
        g[0] = R - 1.0
        if p[I_F] > 0.0 and p[I_EPS] == 0.0:
            if mode[1] == 0:
                Fr, _, _ = normal_force(R, Rd, p)
                lam = stick_force(s, y, p, R, nx, ny, Rd, vt) + p[I_BT] * vt
                g[1] = p[I_F] * Fr - abs(lam)
            else:
                g[1] = mode[1] * vt
        else:
            g[1] = 1.0
    else:
        g[0] = 1.0 - R
        g[1] = 1.0
    g[2] = Rd


@njit(**INNER)
def _friction_state(s, y, p):
    """Filippov choice of the friction state at a point in contact.

    Slip in the direction of ``v_t`` when it is non-zero; at ``v_t = 0`` stick when the
    friction cone can hold the rotor (``|lambda| < f F_r``), otherwise slip in the
    direction the unbalanced tangential force drives it.
    """
    R, nx, ny, Rd, vt = geometry(y, p)
    Fr, _, _ = normal_force(R, Rd, p)
    lam = stick_force(s, y, p, R, nx, ny, Rd, vt) + p[I_BT] * vt
    if abs(vt) > 1e-9 * (1.0 + abs(p[I_RR] * p[I_ETA])):
        return 1 if vt > 0.0 else -1
    if abs(lam) < p[I_F] * Fr:
        return 0
    return -1 if lam > 0.0 else 1


@njit(**LEAF)
def init_mode(s, y, p, mode):
    """Mode consistent with a state (contact iff ``R > 1``)."""
    R = math.sqrt(y[0] * y[0] + y[1] * y[1])
    mode[0] = 1 if R > 1.0 else 0
    mode[1] = 0
    if mode[0] == 1 and p[I_F] > 0.0 and p[I_EPS] == 0.0:
        mode[1] = _friction_state(s, y, p)


@njit(**LEAF)
def transition(s, y, p, mode, which):
    """Mode change at a located event of terminal switch ``which``."""
    if which == SW_CONTACT:
        if mode[0] == 1:
            mode[0] = 0
            mode[1] = 0
        else:
            mode[0] = 1
            mode[1] = 0
            if p[I_F] > 0.0 and p[I_EPS] == 0.0:
                mode[1] = _friction_state(s, y, p)
    elif which == SW_FRICTION:
        R, nx, ny, Rd, vt = geometry(y, p)
        Fr, _, _ = normal_force(R, Rd, p)
        lam = stick_force(s, y, p, R, nx, ny, Rd, vt) + p[I_BT] * vt
        if mode[1] == 0:
            mode[1] = -1 if lam > 0.0 else 1
        elif abs(lam) < p[I_F] * Fr:
            mode[1] = 0
        else:
            mode[1] = -1 if lam > 0.0 else 1


@njit(**LEAF)
def energy(y, p):
    """Mechanical energy ``1/2|v|^2 + 1/2 R^2 + 1/4 k3 R^4 + 2/5 kh (R-1)^{5/2} H(R-1)``."""
    R2 = y[0] * y[0] + y[1] * y[1]
    e = 0.5 * (y[2] * y[2] + y[3] * y[3]) + 0.5 * R2 + 0.25 * p[I_K3] * R2 * R2
    R = math.sqrt(R2)
    if R > 1.0:
        e += 0.4 * p[I_KH] * (R - 1.0) ** 2.5
    return e


# --- the variational equations (tangent vectors; saltation at every switch) ------------

@njit(**INNER)
def var_rhs(s, y, p, mode, out):
    """Rotor state and tangent vectors (``y.size = 4 (1 + m)``)."""
    rhs(s, y, p, mode, out)
    # the Jacobian as scalars (no array allocated per evaluation: this runs at every
    # stage of the Lyapunov and Floquet integrations)
    j20, j21, j22, j23, j30, j31, j32, j33 = jac_rows(s, y, p, mode)
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


KERNEL_MODEL = KernelModel(rhs=rhs, jac=jac, switches=switches, transition=transition,
                           init_mode=init_mode, var_rhs=var_rhs,
                           var_transition=saltation_transition(
                               rhs, switches, transition, N_STATE, N_SWITCH),
                           step_cap=step_cap, n_state=N_STATE,
                           n_mode=N_MODE, terminal=TERMINAL, param_names=PARAM_NAMES)
