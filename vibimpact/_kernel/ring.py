"""The rotor of eq. (5) with a turning retainer ring, as a kernel model (all ``@njit``).

State ``y = (X, Y, X', Y', Vr)``: the rotor of :mod:`.rotor` plus ``Vr``, the speed of the
ring's inner surface (``r_i Omega_r`` in the units of ``X'``; positive along
``e_t = (-Y, X)/R``).  Parameter vector ``p`` laid out as :data:`PARAM_NAMES`: the rotor's
eleven entries in its order (so the rotor's force functions read this vector as theirs),
then the ring's inertia ``Jr`` (``J / (m r_i^2)``), the viscous drag ``cr`` and the Coulomb
drag ``Mr`` of the ring's bearing (both as tangential forces at the inner surface).

The contact's friction and tangential damping act on the *slip* velocity
``v_s = L/R + Rr eta - Vr`` (shaft surface minus ring surface), and their reaction drives
the ring::

    T   = -BT v_s - f F_r sgn(v_s)                  (tangential force on the rotor)
    Jr Vr' = -T - cr Vr - Mr sgn(Vr)

The discrete mode has three entries:

``mode[0]``
    0 = free flight, 1 = contact (``R > 1``).
``mode[1]``
    contact friction: +1 / -1 slipping with ``v_s`` of that sign, 0 sticking (rolling
    without slip, the Filippov sliding mode on ``v_s = 0``).
``mode[2]``
    the ring's bearing: +1 / -1 turning with ``Vr`` of that sign, 0 stuck (``Vr = 0``);
    always +1 when ``Mr = 0`` (no Coulomb torque, nothing to stick).

Stick forces (Filippov 1988; Leine & Nijmeijer 2004, ch. 2): with ``T0`` the force that
holds the rotor's own ``v_t`` (:func:`.rotor.stick_force`) and ``D = cr Vr + Mr s_r`` the
ring's drag, ``dv_s/dtau = T - T0 - Vr' = 0`` gives ``T = (T0 - D/Jr) / (1 + 1/Jr)`` for a
turning ring and ``T = T0`` for a stuck one.  Contact stick holds while
``|T + BT v_s| <= f F_r``; the ring's bearing holds while ``|T| <= Mr``.

=====  ====================================================  ==========
index  switching function                                    kind
=====  ====================================================  ==========
0      free: ``1 - R``; contact: ``R - 1``                     terminal
1      slip: ``s_c v_s``; stick: ``f F_r - |T + BT v_s|``;     terminal
       inactive (1) out of contact, for ``f = 0`` or ``eps > 0``
2      turning: ``s_r Vr``; stuck: ``Mr - |T|``; inactive     terminal
       (1) for ``Mr = 0``
3      ``dR/dtau`` (extrema of ``R``)                          observer
=====  ====================================================  ==========

The Jacobian is analytic (:func:`jac_rows`, scalars only); the saltation matrices at
every switch are the generic ones of :mod:`.variational`.
"""
import math

import numpy as np
from numba import njit

from .jitopts import INNER, LEAF
from .registry import KernelModel
from .rotor import (I_B, I_BT, I_EC, I_EPS, I_ETA, I_F, I_G, I_K3, I_RR, external_force,
                    geometry, normal_force, slip_friction, stick_force)
from .rotor import step_cap as _rotor_step_cap
from .variational import saltation_transition

PARAM_NAMES = ("B", "k3", "kh", "Bh", "BT", "f", "Rr", "Ec", "G", "eta", "eps",
               "Jr", "cr", "Mr")
I_JR, I_CR, I_MR = 11, 12, 13

N_STATE = 5
N_MODE = 3
TERMINAL = np.array([1, 1, 1, 0], dtype=np.int64)

SW_CONTACT = 0
SW_FRICTION = 1
SW_RING = 2
SW_EXTREMUM = 3


@njit(**INNER)
def _sticks(p):
    """Whether contact friction is exact Coulomb friction (Filippov stick possible)."""
    return p[I_F] > 0.0 and p[I_EPS] == 0.0


@njit(**INNER)
def _forces(s, y, p, contact, sc, sr):
    """Tangential force on the rotor, the ring's acceleration and what the switches read.

    Returns ``(T, Vr', F_r, v_s, lam)`` in the mode ``(contact, sc, sr)``; ``lam = T + BT
    v_s`` is the friction part of ``T``.
    """
    W = y[4]
    Jr = p[I_JR]
    drag = p[I_CR] * W
    ring_stuck = sr == 0 and p[I_MR] > 0.0
    if p[I_MR] > 0.0 and not ring_stuck:
        drag += p[I_MR] * sr
    if contact != 1:
        if ring_stuck:
            return 0.0, 0.0, 0.0, 0.0, 0.0
        return 0.0, -drag / Jr, 0.0, 0.0, 0.0
    R, nx, ny, Rd, vt = geometry(y, p)
    Fr, _, _ = normal_force(R, Rd, p)
    vs = vt - W
    if sc == 0 and _sticks(p):
        T0 = stick_force(s, y, p, R, nx, ny, Rd, vt)
        if ring_stuck:
            T = T0
        else:
            T = (T0 - drag / Jr) / (1.0 + 1.0 / Jr)
    else:
        T, _, _ = slip_friction(vs, Fr, p, sc)
    if ring_stuck:
        Wd = 0.0
    else:
        Wd = (-T - drag) / Jr
    return T, Wd, Fr, vs, T + p[I_BT] * vs


@njit(**LEAF)
def rhs(s, y, p, mode, out):
    """Right-hand side in the given mode; writes ``out`` (shape (5,))."""
    ax, ay = external_force(s, y, p)
    T, Wd, Fr, vs, lam = _forces(s, y, p, mode[0], mode[1], mode[2])
    if mode[0] == 1:
        R, nx, ny, Rd, vt = geometry(y, p)
        ax += -Fr * nx - T * ny
        ay += -Fr * ny + T * nx
    out[0] = y[2]
    out[1] = y[3]
    out[2] = ax
    out[3] = ay
    out[4] = Wd


@njit(**INNER)
def jac_rows(s, y, p, mode):
    """Rows 2, 3 and 4 of the analytic Jacobian ``d rhs / d y`` in the given mode.

    Rows 0 and 1 are ``(0, 0, 1, 0, 0)`` and ``(0, 0, 0, 1, 0)``.  Returned as fifteen
    floats (row 2, row 3, row 4, five entries each), so the variational right-hand side
    allocates nothing.  The rotor's part follows :func:`.rotor.jac_rows` with the slip
    velocity ``v_s = v_t - Vr`` in place of ``v_t``; the ring's speed enters through
    ``v_s`` (slip) or the ring's drag (stick with the ring turning).
    """
    X, Y, U, V, W = y[0], y[1], y[2], y[3], y[4]
    B, k3 = p[I_B], p[I_K3]
    Jr = p[I_JR]
    R2 = X * X + Y * Y
    lin = 1.0 + k3 * R2
    j20 = -lin - 2.0 * k3 * X * X
    j21 = -2.0 * k3 * X * Y
    j22 = -B
    j23 = 0.0
    j24 = 0.0
    j30 = -2.0 * k3 * X * Y
    j31 = -lin - 2.0 * k3 * Y * Y
    j32 = 0.0
    j33 = -B
    j34 = 0.0
    stuck = mode[2] == 0 and p[I_MR] > 0.0
    if mode[0] != 1:
        j44 = 0.0 if stuck else -p[I_CR] / Jr
        return (j20, j21, j22, j23, j24, j30, j31, j32, j33, j34,
                0.0, 0.0, 0.0, 0.0, j44)
    R, nx, ny, Rd, vt = geometry(y, p)
    Fr, dF_dR, dF_dRd = normal_force(R, Rd, p)
    dnx0 = (1.0 - nx * nx) / R
    dnx1 = -nx * ny / R
    dny0 = -nx * ny / R
    dny1 = (1.0 - ny * ny) / R
    dRd0 = (U - Rd * nx) / R
    dRd1 = (V - Rd * ny) / R
    dRd2 = nx
    dRd3 = ny
    dF0 = dF_dR * nx + dF_dRd * dRd0
    dF1 = dF_dR * ny + dF_dRd * dRd1
    dF2 = dF_dRd * dRd2
    dF3 = dF_dRd * dRd3
    if mode[1] == 0 and _sticks(p):
        # T0 = w Rd - (-ny fx + nx fy), w = L / R^2 (rotor.jac_rows)
        eta = p[I_ETA]
        amp = p[I_EC] * eta * eta
        fx = amp * math.cos(eta * s) - B * U
        fy = amp * math.sin(eta * s) + p[I_G] - B * V
        T0 = stick_force(s, y, p, R, nx, ny, Rd, vt)
        L = X * V - Y * U
        w = L / R2
        R3 = R2 * R
        dT0 = (V / R2 - 2.0 * L * nx / R3) * Rd + w * dRd0 - (-dny0 * fx + dnx0 * fy)
        dT1 = (-U / R2 - 2.0 * L * ny / R3) * Rd + w * dRd1 - (-dny1 * fx + dnx1 * fy)
        dT2 = -Y / R2 * Rd + w * dRd2 - ny * B
        dT3 = X / R2 * Rd + w * dRd3 + nx * B
        dT4 = 0.0
        if stuck:
            T = T0
        else:
            drag = p[I_CR] * W + (p[I_MR] * mode[2] if p[I_MR] > 0.0 else 0.0)
            k = 1.0 / (1.0 + 1.0 / Jr)
            T = (T0 - drag / Jr) * k
            dT0 *= k
            dT1 *= k
            dT2 *= k
            dT3 *= k
            dT4 = -p[I_CR] / Jr * k
    else:
        L = X * V - Y * U
        T, c, cf = slip_friction(vt - W, Fr, p, mode[1])
        # dv_s/dy = (dv_t/dX, dv_t/dY, -ny, nx, -1)
        dT0 = c * (V - L * nx / R) / R + cf * dF0
        dT1 = c * (-U - L * ny / R) / R + cf * dF1
        dT2 = c * (-ny) + cf * dF2
        dT3 = c * nx + cf * dF3
        dT4 = -c
    # contact acceleration: a_x += -Fr nx - T ny ; a_y += -Fr ny + T nx
    j20 += -dF0 * nx - Fr * dnx0 - dT0 * ny - T * dny0
    j21 += -dF1 * nx - Fr * dnx1 - dT1 * ny - T * dny1
    j22 += -dF2 * nx - dT2 * ny
    j23 += -dF3 * nx - dT3 * ny
    j24 += -dT4 * ny
    j30 += -dF0 * ny - Fr * dny0 + dT0 * nx + T * dnx0
    j31 += -dF1 * ny - Fr * dny1 + dT1 * nx + T * dnx1
    j32 += -dF2 * ny + dT2 * nx
    j33 += -dF3 * ny + dT3 * nx
    j34 += dT4 * nx
    if stuck:
        return (j20, j21, j22, j23, j24, j30, j31, j32, j33, j34,
                0.0, 0.0, 0.0, 0.0, 0.0)
    # the ring: Vr' = (-T - cr Vr - Mr s_r) / Jr
    return (j20, j21, j22, j23, j24, j30, j31, j32, j33, j34,
            -dT0 / Jr, -dT1 / Jr, -dT2 / Jr, -dT3 / Jr, (-dT4 - p[I_CR]) / Jr)


@njit(**LEAF)
def jac(s, y, p, mode, J):
    """Analytic Jacobian ``d rhs / d y`` in the given mode (:func:`jac_rows`); writes
    ``J`` (shape (5, 5))."""
    r = jac_rows(s, y, p, mode)
    for i in range(N_STATE):
        for j in range(N_STATE):
            J[i, j] = 0.0
    J[0, 2] = 1.0
    J[1, 3] = 1.0
    for j in range(N_STATE):
        J[2, j] = r[j]
        J[3, j] = r[5 + j]
        J[4, j] = r[10 + j]


@njit(**INNER)
def var_rhs(s, y, p, mode, out):
    """Ring model state and tangent vectors (``y.size = 5 (1 + m)``), with the Jacobian
    as scalars (no array per evaluation: this runs at every stage of the Lyapunov and
    Floquet integrations)."""
    rhs(s, y, p, mode, out)
    r = jac_rows(s, y, p, mode)
    m = (y.size - N_STATE) // N_STATE
    for c in range(m):
        b = N_STATE + N_STATE * c
        v0 = y[b]
        v1 = y[b + 1]
        v2 = y[b + 2]
        v3 = y[b + 3]
        v4 = y[b + 4]
        out[b] = v2
        out[b + 1] = v3
        out[b + 2] = r[0] * v0 + r[1] * v1 + r[2] * v2 + r[3] * v3 + r[4] * v4
        out[b + 3] = r[5] * v0 + r[6] * v1 + r[7] * v2 + r[8] * v3 + r[9] * v4
        out[b + 4] = r[10] * v0 + r[11] * v1 + r[12] * v2 + r[13] * v3 + r[14] * v4


@njit(**LEAF)
def switches(s, y, p, mode, g):
    """Switching functions (see module docstring); writes ``g`` (shape (4,))."""
    R, nx, ny, Rd, vt = geometry(y, p)
    T, Wd, Fr, vs, lam = _forces(s, y, p, mode[0], mode[1], mode[2])
    if mode[0] == 1:
        g[0] = R - 1.0
        if _sticks(p):
            g[1] = p[I_F] * Fr - abs(lam) if mode[1] == 0 else mode[1] * vs
        else:
            g[1] = 1.0
    else:
        g[0] = 1.0 - R
        g[1] = 1.0
    if p[I_MR] > 0.0:
        g[2] = p[I_MR] - abs(T) if mode[2] == 0 else mode[2] * y[4]
    else:
        g[2] = 1.0
    g[3] = Rd


@njit(**INNER)
def _zero(v, p):
    """Whether a slip or ring speed counts as zero at an event (the rotor's tolerance)."""
    return abs(v) <= 1e-9 * (1.0 + abs(p[I_RR] * p[I_ETA]))


@njit(**INNER)
def _sign(v):
    return 1 if v > 0.0 else -1


@njit(**INNER)
def _consistent(s, y, p, contact, sc, sr, test_c, test_r, exact_c):
    """Whether mode ``(contact, sc, sr)`` is Filippov-consistent at ``y``.

    A stick holds within its cone (``|T + BT v_s| <= f F_r``; a stuck ring:
    ``|T| <= Mr``).  A slip or turn chosen at (nearly) zero speed (``test_c``,
    ``test_r``) must have its switching function positive: the speed is of its sign
    already, or it is exactly zero (``exact_c``: the slip speed has just crossed zero,
    whatever residue of rounding it shows) and accelerates that way.
    """
    T, Wd, Fr, vs, lam = _forces(s, y, p, contact, sc, sr)
    if contact == 1 and _sticks(p):
        if sc == 0:
            if abs(lam) > p[I_F] * Fr:
                return False
        elif test_c and (exact_c or sc * vs <= 0.0):
            if vs != 0.0 and not exact_c:
                return False
            R, nx, ny, Rd, vt = geometry(y, p)
            T0 = stick_force(s, y, p, R, nx, ny, Rd, vt)
            if sc * (T - T0 - Wd) <= 0.0:
                return False
    if p[I_MR] > 0.0:
        if sr == 0:
            if abs(T) > p[I_MR]:
                return False
        elif test_r and sr * y[4] <= 0.0:
            if y[4] != 0.0 or sr * Wd <= 0.0:
                return False
    return True


@njit(**INNER)
def _choose(s, y, p, mode, no_stick_c, no_stick_r, exact_c):
    """Filippov choice of the friction and ring modes at a state (``mode[0]`` given;
    ``mode[1:]`` the modes before the event).

    A speed beyond the zero tolerance fixes its mode's sign.  Within it, stick is
    preferred where its cone holds; otherwise a slip (turn) of the speed's own sign --
    or, at exactly zero speed, of the sign it accelerates to.  A stick that has just
    broken (``no_stick_c`` / ``no_stick_r``: its cone's switch fired) leaves in the
    direction its force points, as in :func:`.rotor.transition`; a slip whose speed has
    just crossed zero (``exact_c``) counts it as zero, so it may stick or turn back
    but never keeps the sign of its rounding residue.  With both speeds
    free, the combinations are tried stick/stick, stick/turn, slip/stick, slip/turn;
    when none holds strictly (a corner of the cones, equal to rounding) the contact
    slips the way its stick force points and the ring stays stuck if its bearing holds.
    """
    contact = mode[0]
    W = y[4]
    # the ring's candidates
    test_r = False
    if p[I_MR] <= 0.0:
        r_opts = (1, 1, 1)
        n_r = 1
    elif not _zero(W, p):
        r_opts = (_sign(W), 0, 0)
        n_r = 1
    elif no_stick_r:
        T, Wd, Fr, vs, lam = _forces(s, y, p, contact, mode[1], 0)
        r_opts = (-_sign(T), 0, 0)
        n_r = 1
    elif W != 0.0:
        r_opts = (0, _sign(W), 0)
        n_r = 2
        test_r = True
    else:
        r_opts = (0, 1, -1)
        n_r = 3
        test_r = True
    # the contact's candidates
    test_c = False
    if contact != 1 or not _sticks(p):
        c_opts = (0, 0, 0)
        n_c = 1
    else:
        R, nx, ny, Rd, vt = geometry(y, p)
        vs = vt - W
        if not exact_c and not _zero(vs, p):
            c_opts = (_sign(vs), 0, 0)
            n_c = 1
        elif no_stick_c:
            T, Wd, Fr, vs2, lam = _forces(s, y, p, contact, 0, mode[2])
            c_opts = (-_sign(lam), 0, 0)
            n_c = 1
        elif vs != 0.0 and not exact_c:
            c_opts = (0, _sign(vs), 0)
            n_c = 2
            test_c = True
        else:
            c_opts = (0, 1, -1)
            n_c = 3
            test_c = True
    for i in range(n_c):
        for j in range(n_r):
            if _consistent(s, y, p, contact, c_opts[i], r_opts[j], test_c, test_r,
                           exact_c):
                mode[1] = c_opts[i]
                mode[2] = r_opts[j]
                return
    sc = c_opts[0]
    if test_c and sc == 0:
        T, Wd, Fr, vs, lam = _forces(s, y, p, contact, 0, mode[2])
        if abs(lam) > p[I_F] * Fr:
            sc = -_sign(lam)
    sr = r_opts[0]
    if test_r:
        T, Wd, Fr, vs, lam = _forces(s, y, p, contact, sc, 0)
        sr = 0 if abs(T) <= p[I_MR] else -_sign(T)
    mode[1] = sc
    mode[2] = sr


@njit(**INNER)
def _stop_ring(y, p, mode):
    """A stuck ring stands still: its speed, zero to the tolerance at the event that
    stuck it, is set to 0 exactly (so that it stays 0, not a residue of 1e-12)."""
    if mode[2] == 0 and p[I_MR] > 0.0:
        y[4] = 0.0


@njit(**LEAF)
def init_mode(s, y, p, mode):
    """Mode consistent with a state (contact iff ``R > 1``; Filippov choice of the
    friction and ring modes).

    Given a variational state (``y.size = 5 (1 + m)``: tangent vectors after the state),
    a start with the ring stuck also removes the tangents' ``Vr`` component: the stuck
    bearing is a sliding surface that attracts in finite time (a ring nudged to speed
    ``dVr`` stops again within ``Jr |dVr| / Mr``), so the flow's derivative along it is
    zero -- the projection that the saltation matrix applies when the ring sticks
    during a run (without it a stuck ring would add a spurious multiplier 1).
    """
    R = math.sqrt(y[0] * y[0] + y[1] * y[1])
    mode[0] = 1 if R > 1.0 else 0
    mode[1] = 0
    mode[2] = 1
    _choose(s, y, p, mode, False, False, False)
    _stop_ring(y, p, mode)
    if mode[2] == 0 and p[I_MR] > 0.0:
        for b in range(N_STATE, y.size, N_STATE):
            y[b + 4] = 0.0


@njit(**LEAF)
def transition(s, y, p, mode, which):
    """Mode change at a located event of terminal switch ``which``."""
    if which == SW_CONTACT:
        mode[0] = 0 if mode[0] == 1 else 1
        mode[1] = 0
        _choose(s, y, p, mode, False, False, False)
    elif which == SW_FRICTION:
        # from stick: the cone broke; from a slip: the slip speed crossed zero
        _choose(s, y, p, mode, mode[1] == 0, False, mode[1] != 0)
    elif which == SW_RING:
        if mode[2] != 0:
            y[4] = 0.0  # the ring's speed crossed zero: it is zero, not its residue
        _choose(s, y, p, mode, False, mode[2] == 0, False)
    _stop_ring(y, p, mode)


#: shortest step the ring's stopping cap asks for (time units; a ring within it of
#: stopping overshoots zero by at most its deceleration times this, and the event
#: location finds the stop inside the step)
RING_STOP_FLOOR = 1e-8


@njit(**INNER)
def step_cap(y, p, mode, f0, at_event, rtol, atol, n_norm, g_in, g_out):
    """The rotor's Hertz step cap (:func:`.rotor.step_cap`; the contact is the rotor's),
    and a ring that its bearing's Coulomb torque decelerates stops within two steps'
    worth of time: at most twice the time to its stop, ``-Vr / Vr'`` (Runge--Kutta is
    exact for the ring's linear run-down, so its error test would accept a step that
    carries ``Vr`` far past zero -- with a large ``Mr`` past the divergence bound --
    before the event location sees the stop)."""
    cap = _rotor_step_cap(y, p, mode, f0, at_event, rtol, atol, n_norm, g_in, g_out)
    if p[I_MR] > 0.0 and mode[2] != 0 and y[4] * f0[4] < 0.0:
        cap = min(cap, max(2.0 * (-y[4] / f0[4]), RING_STOP_FLOOR))
    return cap


KERNEL_MODEL = KernelModel(rhs=rhs, jac=jac, switches=switches, transition=transition,
                           init_mode=init_mode, var_rhs=var_rhs,
                           var_transition=saltation_transition(rhs, switches, transition,
                                                               N_STATE, TERMINAL.size),
                           step_cap=step_cap, n_state=N_STATE, n_mode=N_MODE,
                           terminal=TERMINAL, param_names=PARAM_NAMES)
