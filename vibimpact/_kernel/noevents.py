"""The era's integrator: classical RK4 at a fixed step, the contact switch evaluated
inside the right-hand side, no event location (``@njit``).

A method to *measure* with, not to use: it integrates as a simple code of the paper's
time would have (a fixed-step Runge--Kutta scheme with a Heaviside switch in the force law),
so that the labels and intervals of an accurate integration can be compared with what
such a code finds.  Its global error is of order 1 at best through a contact switch
(a step that straddles the switch integrates a field that is not smooth inside it) and
of order 4 between switches.

How it treats the model's switches (the model's own functions, so every model runs on
it, user models included):

* every Runge--Kutta stage evaluates the right-hand side in the mode *its own state*
  implies: starting from the mode of the step's start, the transition of each terminal
  switching function that is negative at the stage's state is applied, in index order,
  to a scratch copy of the mode (the state itself is not changed there).  For a force
  law (the rotor's Hertz contact and Coulomb friction) this is the Heaviside switch
  inside the force;
* after each step the transitions of the terminal switches negative at its end are
  applied there, unlocated: the mode that the next step starts from, and the state
  jump of an impulsive contact (a restitution law reverses the velocity at the end of
  the step that penetrated the stop); each is logged at the step's end with the state
  before it, as a located event would be;
* an observer (a switching function that changes no mode) that went from positive to
  non-positive over a step is logged at the step's end.

Steps are ``T / N`` (``N`` steps per forcing period, from the option ``h_fixed``) on
a grid that lands on every period's end, where the stroboscopic sample is taken; dense
samples come from the cubic Hermite interpolant of the step.  The arguments and results
of :func:`integrate_noevents` are those of :func:`.driver.integrate`; :mod:`.boundary`
calls it for this method (a loop of its own, compiled on its first use: the main job's
kernel does not carry it).
"""
import math

from numba import njit

from .dispatch import model_rhs, model_switches, model_transition
from .integrator import (C_EVENTS, C_OBSERVED, C_RHS, C_STEPS, LOG_FULL, MAX_STEPS,
                         O_BOUND, O_HFIX, O_MAXSTEPS, O_NBOUND, OK, check_state, hermite)
from .integrator import log_event as _log
from .jitopts import LEAF, PIECE
from .renormalise import renormalise
from .sampling import suspend

#: transitions applied to one state at most (a contact entry, then its friction state)
CHAIN = 4


@njit(**PIECE)
def _first_negative(terminal, g):
    """The first terminal switch negative in ``g``, or -1."""
    for i in range(g.size):
        if terminal[i] == 1 and g[i] < 0.0:
            return i
    return -1


@njit(**PIECE)
def _state_mode(model, terminal, p, s, y, mode, out, g, scratch):
    """The mode the state ``y`` implies, into ``out``: ``mode`` with the transitions of
    the terminal switches negative at ``y`` applied in turn (on ``scratch``, a copy of
    ``y``: a jump of the state is not applied inside a step)."""
    for m in range(mode.size):
        out[m] = mode[m]
    for _ in range(CHAIN):
        model_switches(model, s, y, p, out, g)
        which = _first_negative(terminal, g)
        if which < 0:
            return
        for m in range(y.size):
            scratch[m] = y[m]
        model_transition(model, s, scratch, p, out, which)


@njit(**PIECE)
def _stage(model, terminal, p, s, y, mode, ws, out, counters):
    """The right-hand side at ``(s, y)`` in the mode ``y`` implies, into ``out``."""
    _state_mode(model, terminal, p, s, y, mode, ws.mode_stage, ws.gbuf, ws.yint)
    model_rhs(model, s, y, p, ws.mode_stage, out)
    counters[C_RHS] += 1


@njit(**PIECE)
def _rk4(model, terminal, p, A, B, C, s, y, h, mode, ws, counters):
    """One classical RK4 step of size ``h`` from ``(s, y)``, every stage in the mode its
    state implies; the new state into ``ws.y1``, the derivative at the start in
    ``ws.K[0]``."""
    K, ytmp, y1 = ws.K, ws.ytmp, ws.y1
    n = y.size
    _stage(model, terminal, p, s, y, mode, ws, K[0], counters)
    for i in range(1, 4):
        for m in range(n):
            acc = 0.0
            for j in range(i):
                acc += A[i, j] * K[j, m]
            ytmp[m] = y[m] + h * acc
        _stage(model, terminal, p, s + C[i] * h, ytmp, mode, ws, K[i], counters)
    for m in range(n):
        acc = 0.0
        for j in range(4):
            acc += B[j] * K[j, m]
        y1[m] = y[m] + h * acc


@njit(**PIECE)
def _first_sample(s, dt, dense_m, T):
    """Index of the first dense sample after the local time ``s``."""
    j = max(int(math.floor(s / dt)), 0)
    while j > 0 and (T if j - 1 == dense_m else (j - 1) * dt) > s:
        j -= 1
    while (T if j == dense_m else j * dt) <= s:
        j += 1
    return j


@njit(**PIECE)
def _samples(model, terminal, p, ws, mode, k, k_record, s, y, h, s_end, dense_m, dense,
             j, strobe, T, counters):
    """Dense samples inside the step ``[s, s_end]`` of period ``k`` (from index ``j``
    on, Hermite interpolation; at the step's end its state) and the stroboscopic sample
    when the step ends the period; returns the next dense index."""
    n = y.size
    y1, f1 = ws.y1, ws.f1r
    if dense_m > 0 and k + 1 >= k_record:
        dt = T / dense_m
        have_f1 = False
        while j <= dense_m:
            tj = T if j == dense_m else j * dt
            if tj > s_end:
                break
            idx = (k - k_record) * dense_m + j
            if idx >= 0 and idx < dense.shape[0]:
                if tj == s_end:
                    for m in range(n):
                        dense[idx, m] = y1[m]
                else:
                    if not have_f1:
                        _stage(model, terminal, p, s_end, y1, mode, ws, f1, counters)
                        have_f1 = True
                    hermite((tj - s) / h, h, y, ws.K[0], y1, f1, ws.yev)
                    for m in range(n):
                        dense[idx, m] = ws.yev[m]
            j += 1
    row = k + 1 - k_record
    if s_end == T and row >= 0 and row < strobe.shape[0]:
        for m in range(n):
            strobe[row, m] = y1[m]
    return j


@njit(**PIECE)
def _end_of_step(model, terminal, p, ws, log, n_ev, mode, t_abs, record, s_end, y1,
                 counters):
    """The switches at the step's end: observers that turned non-positive logged, then
    the transitions of the terminal switches negative there applied to ``mode`` and
    ``y1`` (each logged with the state before it).  ``ws.G[0]`` holds the switching
    functions at the step's start.  Returns the log's count."""
    G0, G1, before, y_old = ws.G[0], ws.G[1], ws.mode_old, ws.yint
    model_switches(model, s_end, y1, p, mode, G1)
    for i in range(terminal.size):
        if terminal[i] == 0 and G0[i] > 0.0 and G1[i] <= 0.0:
            counters[C_OBSERVED] += 1
            if record:
                n_ev = _log(log, n_ev, t_abs, i, mode, mode, y1)
    for _ in range(CHAIN):
        which = _first_negative(terminal, G1)
        if which < 0:
            break
        for m in range(mode.size):
            before[m] = mode[m]
        for m in range(y1.size):
            y_old[m] = y1[m]
        model_transition(model, s_end, y1, p, mode, which)
        counters[C_EVENTS] += 1
        if record:
            n_ev = _log(log, n_ev, t_abs, which, before, mode, y_old)
        model_switches(model, s_end, y1, p, mode, G1)
    return n_ev


@njit(**LEAF)
def integrate_noevents(problem, method, opts, ws, y, mode, ks, k_end, k_record, strobe,
                       log, n_ev, dense_m, dense, counters, renorm):
    """:func:`.driver.integrate` for the fixed-step, no-event RK4 (module docstring):
    the same arguments and results (``status, n_ev, done``)."""
    model, terminal, p, omega = problem
    A, B, C = method[1], method[2], method[3]
    T = 2.0 * math.pi / omega
    N = max(int(round(T / opts[O_HFIX])), 1)
    h = T / N
    n = y.size
    n_bound = n if opts[O_NBOUND] <= 0.0 else min(n, int(opts[O_NBOUND]))
    bound = opts[O_BOUND]
    cap = log[0].size
    nsw = terminal.size
    n_periods = renorm[2].shape[0]
    done = n_periods - n_periods  # 0, not a literal (numba would compile twice)
    status = OK
    while True:  # one pass for a plain run, one per period for a Benettin run
        if n_periods > 0:
            k_end = int(ks[0]) + 1
            k_record = k_end
            n_ev = done - done
        k, s = int(ks[0]), ks[1]
        i = int(math.floor(s / h + 1e-9))  # the grid step the local time is in
        dt = T / dense_m if dense_m > 0 else T
        j = _first_sample(s, dt, dense_m, T) if dense_m > 0 else 1
        status = OK
        if N > opts[O_MAXSTEPS]:
            status = MAX_STEPS
        while k < k_end and status == OK:
            if n_ev + nsw + CHAIN + 1 > cap:
                status = LOG_FULL
                break
            lands = i + 1 >= N
            s_end = T if lands else (i + 1) * h
            hh = s_end - s
            model_switches(model, s, y, p, mode, ws.G[0])
            _rk4(model, terminal, p, A, B, C, s, y, hh, mode, ws, counters)
            status = check_state(ws.y1, n_bound, bound)
            if status != OK:
                break
            counters[C_STEPS] += 1
            j = _samples(model, terminal, p, ws, mode, k, k_record, s, y, hh, s_end,
                         dense_m, dense, j, strobe, T, counters)
            t_abs = k * T + s_end
            n_ev = _end_of_step(model, terminal, p, ws, log, n_ev, mode, t_abs,
                                t_abs >= k_record * T, 0.0 if lands else s_end, ws.y1,
                                counters)
            for m in range(n):
                y[m] = ws.y1[m]
            if lands:
                k += 1
                s, i, j = 0.0, 0, 1
            else:
                i += 1
                s = s_end
        suspend(ks, k, s, h, i, j, dense_m)
        if n_periods == 0 or status != OK:
            break
        status = renormalise(y, renorm[0], renorm[1], renorm[2], renorm[3], done)
        done += 1
        if status != OK or done == n_periods:
            break
    return status, n_ev, done
