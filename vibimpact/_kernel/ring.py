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

The Jacobian is taken by central differences of the right-hand side within a mode
(:func:`jac`); the saltation matrices at every switch are the generic ones of
:mod:`.variational`.
"""
import math

import numpy as np
from numba import njit

from .jitopts import ALLOC, INNER, LEAF
from .registry import KernelModel
from .rotor import (I_BT, I_EPS, I_ETA, I_F, I_RR, external_force, geometry, normal_force,
                    stick_force)
from .rotor import step_cap as _rotor_step_cap
from .variational import fd_step, saltation_transition, tangent_rhs

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
        T = -p[I_BT] * vs
        if p[I_F] > 0.0:
            if p[I_EPS] > 0.0:
                T -= p[I_F] * Fr * math.tanh(vs / p[I_EPS])
            else:
                T -= p[I_F] * Fr * sc
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


@njit(**ALLOC)
def jac(s, y, p, mode, J):
    """Jacobian ``d rhs / d y`` in the given mode by central differences (step
    :func:`.variational.fd_step` of each entry); writes ``J`` (shape (5, 5))."""
    yp = y[:N_STATE].copy()
    fp = np.empty(N_STATE)
    fm = np.empty(N_STATE)
    for j in range(N_STATE):
        d = fd_step(y[j])
        yp[j] = y[j] + d
        rhs(s, yp, p, mode, fp)
        yp[j] = y[j] - d
        rhs(s, yp, p, mode, fm)
        yp[j] = y[j]
        for i in range(N_STATE):
            J[i, j] = (fp[i] - fm[i]) / (2.0 * d)


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
                           init_mode=init_mode, var_rhs=tangent_rhs(rhs, jac, N_STATE),
                           var_transition=saltation_transition(rhs, switches, transition,
                                                               N_STATE, TERMINAL.size),
                           step_cap=step_cap, n_state=N_STATE, n_mode=N_MODE,
                           terminal=TERMINAL, param_names=PARAM_NAMES)
