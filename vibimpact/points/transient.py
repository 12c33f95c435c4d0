"""The first half of a point's pipeline: settle the transient and integrate the record.

:func:`settle` integrates from the point's initial state in chunks and ends the transient
as soon as the stroboscopic points repeat (a converged periodic orbit), jumps ahead by
extrapolation where they close in geometrically, tries a continuation's predicted orbit
first, and shoots for the attractor where they contract too slowly to settle within the
budget (:mod:`vibimpact.points.settle`).  It returns a :class:`Settled`: the record (one
run on the attractor, with events and dense samples as the request needs) and the
evidence that decided it.  :mod:`vibimpact.points.measure` turns that into the point's
results.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..analysis.exponents import TANGENT_TOL
from ..analysis.extrapolation import extrapolate_limit
from ..analysis.period import detect_period, detect_period_windows
from ..core.run import Status, join_runs
from .settle import MIN_SHOOT_PERIODS, find_contraction, needs_shooting, shoot, unsettled_repeat

#: the transient's contraction is checked every this many chunks
CHECK_EVERY = 3
#: periods integrated after an extrapolation jump before the next check: the jump's point
#: and 6 more fill the period test's shortest window (7 points, a period-1 orbit repeated
#: 6 times) and are the 6 iterates a further period-1 extrapolation needs
CHUNK_AFTER_JUMP = 6
#: extrapolate only when every n-th point moves by at most this fraction of the orbit's
#: magnitude, and the last of 5 steps is below this fraction of the first
EXTRAPOLATE_NEAR = 1e-2
EXTRAPOLATE_SHRINK = 0.9


@dataclass
class Settled:
    """What the transient leaves for the measurements.

    Attributes
    ----------
    run : Run or None
        The record (None when the integration stopped: see ``failure``).
    n : int
        Period the transient converged to (0: none).
    x_start : ndarray, shape (d,)
        State where the record starts.
    rec : int
        Periods recorded.
    transient : int
        Periods of transient integrated before the record (a discarded trial included).
    evidence : Evidence or None
        A periodic attractor found by shooting and confirmed by integration.
    con : Contraction or None
        The record's contraction where no period was found (and no evidence).
    failure : tuple or None
        ``(status, reason, where)`` when the integration stopped.
    """

    run: object = None
    n: int = 0
    x_start: np.ndarray | None = None
    rec: int = 0
    transient: int = 0
    evidence: object = None
    con: object = None
    failure: tuple | None = None


def windows(rule):
    """Windows of the transient's period check: 7, 13, 25, ... points (periods up to 2, 4,
    8, ... repeated 3 times), up to three repeats of the longest period."""
    return (7, 13, 25, 49, 97, 3 * rule.max_period + 1)


def converged_period(strobe, rule):
    """Period of the tail of the transient's strobe sequence, or 0: the first of the
    trailing :func:`windows` in which :func:`detect_period` finds one."""
    return detect_period_windows(strobe, windows(rule), tol=rule.period_tol,
                                 max_period=rule.max_period)


def extrapolated(strobe):
    """Limit of a transient closing in geometrically on an ``n``-cycle (``n <= 4``), or None.

    Every ``n``-th of the last ``5 n + 1`` stroboscopic points (6 iterates of ``P^n``):
    accepted for the smallest ``n`` whose steps are below :data:`EXTRAPOLATE_NEAR` of the
    points' magnitude and shrink (the last below :data:`EXTRAPOLATE_SHRINK` of the first),
    and whose extrapolated limit lies within the geometric tail of those steps.
    """
    scale = max(float(np.abs(strobe).max()), 1e-300)
    for n in range(1, 5):
        if 5 * n + 1 > strobe.shape[0]:
            break
        z = strobe[-1::-n][:6][::-1]
        dz = np.abs(np.diff(z, axis=0)).max(axis=1)
        if not (dz[-1] <= EXTRAPOLATE_NEAR * scale and dz[-1] < EXTRAPOLATE_SHRINK * dz[0]):
            continue
        xs = extrapolate_limit(z)
        r = (dz[-1] / dz[0]) ** 0.25
        if np.all(np.isfinite(xs)) and np.abs(xs - z[-1]).max() <= 3.0 * dz[-1] / (1.0 - r):
            return xs
    return None


def attracting(system, x, n):
    """Whether the period-``n`` orbit through ``x`` attracts: every multiplier of its
    monodromy matrix (variational equations, tangent vectors' errors tested at the
    Lyapunov default) inside the unit circle."""
    from ..analysis.shooting import floquet_multipliers

    m = system.monodromy(x, n, tangent_tol=TANGENT_TOL)
    return m.status is Status.OK and bool(np.abs(floquet_multipliers(m.matrix)).max() < 1.0)


class _Transient:
    """The transient's state between chunks (see :func:`settle`)."""

    def __init__(self, system, x, settings, guess):
        st = self.st = settings
        self.system = system
        self.rule = st.rule
        self.dense = st.dense if "response" in st.analyses else 0
        self.x = x
        self.tail = [x[None, :]]
        self.done = self.n = self.jumps = self.shots = self.wasted = 0
        self.chunk = st.chunk
        self.x_jump = None  # the integrated state a jump left (None: no jump since reset)
        self.run = None  # the record, when the guess's run is one
        self.evidence = None  # a shooting result confirmed by integration
        self.looked = -st.transient_max  # `done` at the last contraction check
        self.guessed = guess is not None
        self.ready = False  # the trial's points wait for the transient's first check
        # the transient's last chunks with their events: an unconverged transient's
        # record when they cover `record` periods of one trajectory
        self.logged = []
        self.x_start = None
        self.rec = 0
        self.failure = None

    def try_shoot(self, strobe, con):
        """Shoot from a contracting ``strobe`` (one attempt of ``st.shoot``)."""
        self.shots += 1
        return shoot(self.system, strobe, con, self.st, self.dense > 0)

    def trial(self, guess):
        """Integrate the record from a predicted orbit point: the record itself when its
        points repeat on an attracting orbit, else the transient's first chunk."""
        st, rule = self.st, self.rule
        g = np.asarray(guess, dtype=np.float64)
        rec = max(st.record_periodic, 4)
        trial = self.system.simulate(periods=rec, state0=g, dense=self.dense)
        nt = 0 if trial.status is not Status.OK else detect_period(
            trial.strobe, tol=rule.period_tol, max_period=min(rule.max_period, rec // 3))
        if nt and 4 * nt <= rec and attracting(self.system, trial.final_state, nt):
            self.run, self.n, self.x_start, self.rec = trial, nt, g, rec
        elif nt or trial.status is not Status.OK:  # a saddle, or no run: plain transient
            self.guessed = False
            self.wasted = rec
        else:  # the run is the first chunk of a transient that started with a jump
            self.x_jump = self.x
            self.x = trial.final_state.copy()
            self.tail = [trial.strobe]
            self.done = rec
            self.ready = True

    def integrate_chunk(self):
        """One chunk of the transient; False when the integration stopped."""
        st = self.st
        todo = min(self.chunk, st.transient_max - self.done)
        if self.done + todo > st.transient_max - st.record:  # may end up in the record
            c = self.system.simulate(periods=todo, state0=self.x, dense=self.dense)
            status, why, pts = c.status, c.reason, c.strobe
            self.logged.append(c)
        else:
            status, why, pts = self.system.strobe(todo, self.x)
        if status is not Status.OK:
            self.failure = (status, why, "transient")
            return False
        self.done += todo
        self.x = pts[-1].copy()
        self.tail.append(pts[1:])
        return True

    def restart_after_saddle(self):
        """A jump (or a guess) onto a saddle: its points repeat for a long while before
        they leave.  Resume from where the jump left the trajectory, without further
        jumps; after a guess, start the plain transient from the initial state."""
        self.n = 0
        self.x = self.x_jump
        self.x_jump = None
        self.logged = []
        if self.guessed:  # the plain transient gets its whole length
            self.jumps, self.wasted, self.done = 0, self.wasted + self.done, 0
        else:
            self.jumps = self.st.extrapolate
        self.guessed = False
        self.tail = [self.x[None, :]]
        self.chunk = self.st.chunk

    def check(self):
        """Check the points after a chunk: True when the transient ends."""
        st, rule = self.st, self.rule
        strobe = np.concatenate(self.tail)[-(3 * rule.max_period + 1):]
        self.tail = [strobe]
        self.n = converged_period(strobe, rule)
        if self.n and self.x_jump is not None and \
                not attracting(self.system, self.x, self.n):
            self.restart_after_saddle()
            return False
        if self.n:
            if self.shots < st.shoot and strobe.shape[0] > MIN_SHOOT_PERIODS:
                con = unsettled_repeat(strobe, self.n, rule.period_tol)
                if con is not None:  # repeating only because the points move slowly
                    self.evidence = self.try_shoot(strobe, con)
            return True
        if self.jumps < st.extrapolate:
            xs = extrapolated(strobe)
            if xs is not None:  # restart from the limit; only new points count
                self.jumps += 1
                if not self.guessed:  # after a guess, a saddle sends it to state0
                    self.x_jump = self.x.copy()
                self.x = xs
                self.logged = []
                self.tail = [self.x[None, :]]
                self.chunk = min(st.chunk, CHUNK_AFTER_JUMP)
                return False
        self.chunk = st.chunk
        if self.shots < st.shoot and strobe.shape[0] > MIN_SHOOT_PERIODS and \
                self.done - self.looked >= CHECK_EVERY * st.chunk:
            self.looked = self.done
            con = find_contraction(strobe)
            if needs_shooting(con, rule.period_tol, st.transient_max - self.done):
                self.evidence = self.try_shoot(strobe, con)
                if self.evidence is not None:
                    return True
        return False

    def loop(self):
        """Chunks until the points converge, the budget is spent or it stopped."""
        while self.run is None and (self.done < self.st.transient_max or self.ready):
            if not self.ready and not self.integrate_chunk():
                return False
            self.ready = False
            if self.check():
                break
        return True

    def record(self):
        """The record: a confirmed orbit's run, the transient's logged chunks, or a new
        run from where the transient ended; a still moving record is shot from once."""
        st, ev = self.st, self.evidence
        if ev is not None:  # the orbit's confirming run is the record
            self.run, self.n, self.x_start = ev.run, ev.n, ev.state
            self.rec = self.run.strobe.shape[0] - 1
        if self.run is None and not self.n and self.logged and \
                sum(c.strobe.shape[0] - 1 for c in self.logged) >= st.record:
            self.run = join_runs(self.logged, self.system.period)
            self.rec = self.run.strobe.shape[0] - 1
            self.x_start = self.run.strobe[0]
            self.done -= self.rec
        if self.run is None:
            self.rec = max(st.record_periodic, 4 * self.n) if self.n else st.record
            self.x_start = self.x
            self.run = self.system.simulate(periods=self.rec, state0=self.x,
                                            dense=self.dense)
            if self.run.status is not Status.OK:
                self.failure = (self.run.status, self.run.reason, "record")
                return None
        con = None
        if not self.n:  # a record that still moves: does it contract onto an orbit?
            con = find_contraction(self.run.strobe)
            if con is not None and self.shots < st.shoot:
                self.evidence = self.try_shoot(self.run.strobe, con)
                ev = self.evidence
                if ev is not None:
                    self.done += self.rec
                    self.run, self.n, self.x_start = ev.run, ev.n, ev.state
                    self.rec = self.run.strobe.shape[0] - 1
        return con


def settle(system, x, settings, guess=None):
    """Settle the transient from ``x`` and integrate the record.

    Parameters
    ----------
    system : System
        With the point's solver settings.
    x : ndarray, shape (d,)
        Initial state at tau = 0.
    settings : SweepSettings
    guess : ndarray, shape (d,), optional
        A predicted point of a period-1 orbit; see
        :func:`vibimpact.points.point.analyse_point`.

    Returns
    -------
    Settled
    """
    tr = _Transient(system, x, settings, guess)
    if tr.guessed:
        tr.trial(guess)
    con = tr.record() if tr.loop() else None
    if tr.failure is not None:
        return Settled(failure=tr.failure)
    return Settled(run=tr.run, n=tr.n, x_start=tr.x_start, rec=tr.rec,
                   transient=tr.done + tr.wasted, evidence=tr.evidence, con=con)
