"""Impulsive contact: a rigid stop with Newton's impact law, chattering and sticking.

A kernel model whose contact is an *instantaneous impact* rather than a force: one
coordinate ``q = y[pos]`` (velocity ``q' = y[vel]``) meets a rigid stop at ``q = d``
(``d = p[stop]``; the free side is ``side (d - q) > 0``), and at impact its velocity is
reversed with the coefficient of restitution ``r = p[restitution]`` in ``[0, 1]``
(Newton's law ``q'+ = -r q'-``; Brogliato 1999, *Nonsmooth Mechanics*, ch. 4).  The
model gives its free motion (:func:`stop_model`'s ``free_rhs``, ``free_jac`` and the
acceleration ``accel`` of the impacting coordinate); this module builds the model's
``rhs``, ``jac``, ``switches``, ``transition`` and ``init_mode`` around them.  The mode
has two entries: ``mode[0]`` is 0 in free flight and 1 while the stop holds the body
(the contact's mode entry), ``mode[1]`` says how it holds it, :data:`STICK` (at rest)
or :data:`CHATTER` (the end of a chattering sequence, below).

=====  ===============================================================  ==========
index  switching function                                               kind
=====  ===============================================================  ==========
0      free: the gap ``side (d - q)`` (an impact where it vanishes);     terminal
       held: the force into the stop, ``side q''`` of the free motion
       on the stop (the body leaves where it changes sign)
1      ``side q'`` in free flight (closest approaches to the stop);      observer
       1 while held
2      chattering: the envelope speed ``V = -side q'``; 1 otherwise      terminal
=====  ===============================================================  ==========

*Chattering* (Budd & Dux 1994, "Chattering and related behaviour in impact oscillators",
Phil. Trans. R. Soc. A 347, 365-389): with the force pressing the body into the stop
(acceleration ``a > 0`` towards it) an impact at speed ``u`` is followed by a flight of
``2 r u / a`` and an impact at speed ``r u`` (to first order in ``u``), so the impacts
accumulate at a finite time, the geometric series

    t_inf = t_n + sum_{k >= 1} 2 r^k u / a = t_n + 2 r u / (a (1 - r)).

At every impact the transition predicts that remainder (:func:`chatter_remainder`); once
it is below ``chatter_time`` the rest of the sequence -- flights too short to be worth
integrating, and at last too short for any event location -- is replaced by its
envelope: the body stays on the stop and its velocity entry carries the speed ``V`` of
the bounces, which loses ``(1 - r) V`` every flight of ``2 V / a``, i.e.
``V' = -a (1 - r) / 2`` from ``V = r u``.  ``V`` reaches 0 at the accumulation point (at
``t_inf`` exactly for a constant force; to second order in the remainder otherwise), a
located event of switch 2, where the body sticks.  A force that turns to pull the body
away first ends the sequence at switch 0 instead, the body leaving at speed ``V``.  While
sticking (``q = d``, ``q' = 0``) the stop holds the body until the force changes sign
(di Bernardo et al. 2008, *Piecewise-smooth Dynamical Systems*, sec. 1.2.3 and 6.4).

The transition at an impact maps the state by a jump (the velocity reversed, the
position put on the stop); the variational equations take the saltation matrix of every
event from :mod:`.variational`, like any switch.
"""
import numpy as np
from numba import njit

from .jitopts import LEAF

#: mode[0]: free flight, held by the stop (the contact's mode entry)
FREE, HELD = 0, 1
#: mode[1] while held: at rest, or the envelope of a chattering sequence
STICK, CHATTER = 0, 1
#: the switching functions (see the module's docstring)
SW_STOP, SW_VELOCITY, SW_CHATTER = 0, 1, 2
N_MODE = 2
TERMINAL = np.array([1, 0, 1], dtype=np.int64)
#: a chattering sequence whose predicted remainder (time units of the model) is below
#: this is replaced by its envelope
CHATTER_TIME = 1e-3


@njit(**LEAF)
def chatter_remainder(u, a, r):
    """Time from an impact at speed ``u > 0`` to the accumulation point of the chattering
    sequence it starts under a constant acceleration ``a > 0`` towards the stop with
    restitution ``r < 1``: ``2 r u / (a (1 - r))`` (Budd & Dux 1994), ``inf`` for no
    accumulation (``a <= 0`` or ``r >= 1``)."""
    if a <= 0.0 or r >= 1.0:
        return np.inf
    if u <= 0.0 or r <= 0.0:
        return 0.0
    return 2.0 * r * u / (a * (1.0 - r))


def stable_uuid(dispatcher):
    """Give the dispatcher ``dispatcher`` a uuid derived from its function's module and
    name, where it has none yet.

    numba keys the disk cache of a closure on the pickled values it closes over; a
    dispatcher pickles with its uuid, which numba draws at random in every process, so
    that a function made by a factory over dispatchers (:func:`stop_model`'s) would miss
    its cache in every new process and compile again (and add an entry to the index).
    With the same uuid in every process the key is the same.  numba gives no public way to
    name the uuid; where its private one is missing or already set, nothing is done (the
    function then compiles once per process, as a user model's does).
    """
    func = getattr(dispatcher, "py_func", None)
    setter = getattr(dispatcher, "_set_uuid", None)
    if func is None or setter is None:
        return
    try:
        if getattr(dispatcher, "_MemoMixin__uuid", None) is None:
            setter(f"vibimpact-kernel:{func.__module__}.{func.__qualname__}")
    except (AssertionError, AttributeError, TypeError):
        pass


def stop_model(free_rhs, free_jac, accel, n, pos, vel, stop, restitution, side=1.0,
               chatter_time=CHATTER_TIME, cache=True):
    """The kernel functions of a model with a rigid stop (see the module's docstring).

    Parameters
    ----------
    free_rhs : numba function ``free_rhs(s, y, p, out)``
        The free motion's right-hand side (every coordinate).
    free_jac : numba function ``free_jac(s, y, p, J)``
        Its Jacobian.
    accel : numba function ``accel(s, y, p) -> float``
        The impacting coordinate's acceleration in the free motion (``free_rhs``'s entry
        ``vel``): the force on the body at rest on the stop.
    n : int
        State entries.
    pos, vel : int
        Indices of the impacting coordinate and of its velocity.
    stop, restitution : int
        Indices of the stop's position ``d`` and of the coefficient of restitution
        ``r`` in the parameter vector.
    side : float
        +1: the stop is above ``q`` (free while ``q < d``); -1: below.
    chatter_time : float
        A chattering sequence whose predicted remainder (:func:`chatter_remainder`) is
        below this is replaced by its envelope, which ends at the accumulation point.
    cache : bool
        Cache the functions on disk (a built-in model; a user model's are compiled per
        process).

    Returns
    -------
    tuple of numba functions
        ``(rhs, jac, switches, transition, init_mode)`` with the kernel's signatures
        (:mod:`.integrator`); the switches' kinds are :data:`TERMINAL`, the mode has
        :data:`N_MODE` entries.  While held, the free motion's ``rhs`` and ``jac`` hold
        the impacting coordinate (and scale its velocity's row to the envelope's while
        chattering); the other coordinates keep their free motion (the stop's force acts
        on ``q`` alone).

    Raises
    ------
    ValueError
        Naming the argument: an index outside the state, ``side`` not +-1, or
        ``chatter_time`` not positive.
    """
    for name, value in (("pos", pos), ("vel", vel)):
        if not 0 <= value < n:
            raise ValueError(f"{name} must index the {n} states, got {value!r}")
    if side not in (1.0, -1.0):
        raise ValueError(f"side must be +1 or -1, got {side!r}")
    if not chatter_time > 0.0:
        raise ValueError(f"chatter_time must be > 0, got {chatter_time!r}")
    leaf = dict(LEAF, cache=bool(cache))
    side = float(side)
    if cache:
        for fn in (free_rhs, free_jac, accel):
            stable_uuid(fn)

    @njit(**leaf)
    def rhs(s, y, p, mode, out):
        """The free motion; held: ``q`` fixed, ``q'`` the chattering envelope or 0."""
        free_rhs(s, y, p, out)
        if mode[0] == HELD:
            out[pos] = 0.0
            out[vel] = 0.5 * (1.0 - p[restitution]) * out[vel] if mode[1] == CHATTER \
                else 0.0

    @njit(**leaf)
    def jac(s, y, p, mode, J):
        """The Jacobian of :func:`rhs` in the given mode."""
        free_jac(s, y, p, J)
        if mode[0] == HELD:
            c = 0.5 * (1.0 - p[restitution]) if mode[1] == CHATTER else 0.0
            for j in range(n):
                J[pos, j] = 0.0
                J[vel, j] *= c

    @njit(**leaf)
    def switches(s, y, p, mode, g):
        """The stop (gap or force), the velocity observer, the envelope's speed."""
        if mode[0] == HELD:
            g[0] = side * accel(s, y, p)
            g[1] = 1.0
            g[2] = -side * y[vel] if mode[1] == CHATTER else 1.0
        else:
            g[0] = side * (p[stop] - y[pos])
            g[1] = side * y[vel]
            g[2] = 1.0

    @njit(**leaf)
    def transition(s, y, p, mode, which):
        """An impact (the jump, and chattering's envelope or sticking when its remainder
        is short), the accumulation point, or the release."""
        if mode[0] == HELD:
            if which == SW_CHATTER:  # the accumulation point: the body comes to rest
                y[vel] = 0.0
                mode[1] = STICK
            elif which == SW_STOP:  # the force pulls the body off the stop
                mode[0] = FREE
                mode[1] = STICK
            return
        if which != SW_STOP:
            return
        u = side * y[vel]  # the impact speed, > 0 towards the stop
        v = y[vel]
        y[pos] = p[stop]
        y[vel] = 0.0
        a = side * accel(s, y, p)  # the force on the body at rest on the stop
        r = p[restitution]
        if u > 0.0:
            y[vel] = -r * v
        rem = chatter_remainder(u, a, r)
        if rem <= chatter_time:
            mode[0] = HELD
            mode[1] = CHATTER if rem > 0.0 else STICK
            if rem == 0.0:
                y[vel] = 0.0

    @njit(**leaf)
    def init_mode(s, y, p, mode):
        """Held (sticking) at rest on the stop with the force pressing; free otherwise."""
        mode[0] = FREE
        mode[1] = STICK
        if side * (y[pos] - p[stop]) >= 0.0 and y[vel] == 0.0 and side * accel(s, y, p) > 0.0:
            mode[0] = HELD

    return rhs, jac, switches, transition, init_mode
