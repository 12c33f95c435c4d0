"""One point of a sweep: integrate, stop the transient early, analyse only what is asked.

:func:`analyse_point` is a pure function of ``(params, state0, settings)``: the same
input gives the same numbers in any process, which makes parallel sweeps and resumed
sweeps bit-identical to serial, uninterrupted ones.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from ..analysis.chaos01 import test01
from ..analysis.classify import DecisionRule, Label, decide
from ..analysis.extrapolation import extrapolate_limit
from ..analysis.impacts import contact_arcs, impact_count
from ..analysis.exponents import TANGENT_TOL, Averaging
from ..analysis.lyapunov import lyapunov_spectrum
from ..analysis.period import detect_period, detect_period_windows
from ..analysis.settling import contraction_rate, settling_periods, torus_evidence
from ..run import Status, join_runs
from ..system import System
from .settle import (MAX_SHOTS, MIN_SHOOT_PERIODS, find_contraction, needs_shooting, shoot,
                     unsettled_repeat)

#: analyses a sweep can compute ("period" always runs: it ends the transient)
ANALYSES = ("period", "impacts", "response", "poincare", "lyapunov", "test01", "floquet")

#: regime label -> integer code stored in datasets (CF flag_values / flag_meanings)
REGIME_CODES = {Label.PERIODIC: 1, Label.QUASIPERIODIC: 2, Label.CHAOTIC: 3,
                Label.DIVERGED: 4, Label.UNSETTLED: 5}
REGIME_FLAGS = "periodic quasi_periodic chaotic diverged unsettled"


@dataclass(frozen=True)
class SweepSettings:
    """What each sweep point computes, and how long it integrates.

    Attributes
    ----------
    analyses : tuple of str
        Subset of :data:`ANALYSES`.
    transient_max : int
        Longest transient in forcing periods; it ends earlier as soon as the stroboscopic
        points repeat with a period ``n`` (checked every ``chunk`` periods).
    chunk : int
        Periods between convergence checks; after an extrapolation jump the next check
        comes as soon as the period test's shortest window is full
        (:data:`CHUNK_AFTER_JUMP` periods).
    extrapolate : int
        Jumps of the transient at most: when the stroboscopic points of a chunk close in
        geometrically on an ``n``-cycle (every ``n``-th point, ``n <= 4``, moving less than
        1 % of the orbit's magnitude and its steps shrinking), the transient restarts from
        their limit by minimal polynomial extrapolation
        (:func:`vibimpact.analysis.extrapolate_limit`) instead of waiting for the slowest
        Floquet mode to decay.  The period is still only accepted from integrated points
        repeating to the rule's tolerance, and, since extrapolation finds saddles as
        readily as attractors, only if the orbit's Floquet multipliers lie inside the
        unit circle (otherwise the transient resumes from before the jump, without
        further jumps); 0 turns this off.
    shoot : int
        Newton-shooting attempts at most per point (:mod:`vibimpact.sweeps.settle`):
        where the transient's stroboscopic points contract too slowly to settle within
        ``transient_max``, the orbit they approach is sought by shooting and accepted on
        evidence, confirmed by integrating from it; 0 turns this off.
    predict : int
        Continuation's predictor (:mod:`vibimpact.sweeps.predict`): after this many
        consecutive period-1 points, a point is first tried from the polynomial
        extrapolation of their states (``guess`` of :func:`analyse_point`); 0 turns this
        off.  The default, 4 (a cubic), lands close enough for the first record to be
        periodic at about 2 of 3 points of a period-1 branch.
    record : int
        Periods recorded where the transient did not converge to a periodic orbit (0-1
        test, impacts per period, Poincaré samples): the transient's last chunks, logged
        with their events as they are integrated and still checked for a period, at least
        ``record`` periods of one trajectory (130 of the 200 with the defaults; the
        exponent then starts where they end).  Only when an extrapolation jump cut them
        short are they recorded after the transient instead.
    record_periodic : int
        At least this many periods (and at least 4 motion periods) recorded on a
        converged periodic orbit.
    n_samples : int
        Poincaré samples stored per point (a periodic orbit's cycle is repeated to fill).
    dense : int
        Samples per period used, and discarded, to find the response maxima X_m, Y_m.
    lyapunov : {"auto", "always"}
        "auto": the largest exponent only where no period is found.
    lyap_min, lyap_max, lyap_target : int, int, float
        Periods and target standard error (per unit tau) of the largest exponent.
    rule : DecisionRule
    method, rtol, atol : integrator settings
        ``rtol = 1e-8`` by default: the period test's tolerance (1e-6 of the orbit's size)
        is met with margin, and a sweep runs about 15 % faster than at 1e-9.
    """

    analyses: tuple = ANALYSES
    transient_max: int = 200
    chunk: int = 10
    extrapolate: int = 5
    shoot: int = MAX_SHOTS
    predict: int = 4
    record: int = 128
    record_periodic: int = 8
    n_samples: int = 64
    dense: int = 48
    lyapunov: str = "auto"
    lyap_min: int = 100
    lyap_max: int = 600
    lyap_target: float = 3e-3
    rule: DecisionRule = DecisionRule()
    method: str = "dop853"
    rtol: float = 1e-8
    atol: float = 1e-11

    def as_attrs(self):
        """Flat dict for dataset attributes."""
        d = asdict(self)
        rule = d.pop("rule")
        d["analyses"] = ",".join(self.analyses)
        d.update({f"rule_{k}": v for k, v in rule.items()})
        return d


#: contact codes: free flight throughout, impacts (contact entries), or permanent contact
#: (the rotor rolls or whirls on the retainer, R > 1 throughout, with no new impact)
CONTACT_NONE, CONTACT_IMPACTING, CONTACT_PERMANENT = 0, 1, 2
CONTACT_FLAGS = "none impacting permanent_contact"

#: scalar result fields of a point, with their fill value
SCALARS = {
    "regime": 0, "period": 0, "confidence": np.nan, "impacts_per_period": np.nan,
    "impacts_constant": 0, "contact": -1, "lyapunov": np.nan, "lyapunov_err": np.nan, "k01": np.nan,
    "X_m": np.nan, "Y_m": np.nan, "R_m": np.nan, "min_gap": np.nan, "n_arcs": 0,
    "v_impact_max": np.nan, "v_impact_mean": np.nan, "penetration_max": np.nan,
    "transient": 0, "recorded": 0,
    # --- issue 8: Floquet multipliers of periodic points ("floquet") ---
    "floquet_abs_max": np.nan, "stable": -1,
    # --- settling at low damping: contraction rate, shooting evidence ---
    "floquet_exponent": np.nan, "contraction": np.nan, "settle_periods": np.nan,
    "shoot_residual": np.nan, "orbit_distance": np.nan,
}

#: longest period the recurrence search looks for when the exponent is negative but no
#: period up to the rule's ``max_period`` was found (as a multiple of ``max_period``)
LONG_SEARCH = 4
#: a record whose points neither contract nor recur is looked at this many times as long
TORUS_EXTEND = 4
#: the transient's contraction is checked every this many chunks
CHECK_EVERY = 3

#: Floquet multipliers stored per point (one per state variable)
N_MULTIPLIERS = 4


#: periods integrated after an extrapolation jump before the next check: the jump's point
#: and 6 more fill the period test's shortest window (7 points, a period-1 orbit repeated
#: 6 times) and are the 6 iterates a further period-1 extrapolation needs
CHUNK_AFTER_JUMP = 6


def _windows(rule):
    """Windows of the transient's period check: 7, 13, 25, ... points (periods up to 2, 4,
    8, ... repeated 3 times), up to three repeats of the longest period."""
    return (7, 13, 25, 49, 97, 3 * rule.max_period + 1)


def _converged_period(strobe, rule):
    """Period of the tail of the transient's strobe sequence, or 0: the first of the
    trailing windows :func:`_windows` in which :func:`detect_period` finds one."""
    return detect_period_windows(strobe, _windows(rule), tol=rule.period_tol,
                                 max_period=rule.max_period)


#: extrapolate only when every n-th point moves by at most this fraction of the orbit's
#: magnitude, and the last of 5 steps is below this fraction of the first
EXTRAPOLATE_NEAR = 1e-2
EXTRAPOLATE_SHRINK = 0.9


def _extrapolated(strobe):
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


def _attracting(p, x, n, st):
    """Whether the period-``n`` orbit through ``x`` attracts: every multiplier of its
    monodromy matrix (variational equations, tangent vectors' errors tested at the
    Lyapunov default) inside the unit circle."""
    from ..analysis.shooting import floquet_multipliers

    m = point_system(p, st).monodromy(x, n, tangent_tol=TANGENT_TOL)
    return m.status is Status.OK and bool(np.abs(floquet_multipliers(m.matrix)).max() < 1.0)


def _orbit_point(strobe):
    """The fixed point of a converged period-1 record: minimal polynomial extrapolation
    of its last 6 stroboscopic points, or the last point where the extrapolation leaves
    their neighbourhood.  The record's points approach the orbit geometrically (after a
    transient ended at the period test's tolerance, about 1e-7 of the orbit's size
    remains); the limit removes that residue, which the continuation's predictor would
    amplify (:mod:`vibimpact.sweeps.predict`)."""
    z = strobe[-6:]
    last = z[-1]
    xs = extrapolate_limit(z) if z.shape[0] >= 3 else last
    spread = float(np.abs(np.diff(z, axis=0)).max()) if z.shape[0] > 1 else 0.0
    if not np.all(np.isfinite(xs)) or float(np.abs(xs - last).max()) > 10.0 * spread:
        return last.copy()
    return xs


def _maxima(dense):
    """Largest |X|, |Y| and R of densely sampled motion, refined by a parabola through the
    sample at the maximum and its neighbours (error O(h^3) instead of O(h^2))."""
    out = []
    R = np.hypot(dense[:, 0], dense[:, 1])
    for v in (np.abs(dense[:, 0]), np.abs(dense[:, 1]), R):
        i = int(np.argmax(v))
        best = v[i]
        if 0 < i < v.size - 1:
            a, b, c = v[i - 1], v[i], v[i + 1]
            den = a - 2.0 * b + c
            if den < 0.0:
                best = b - 0.125 * (a - c) ** 2 / den
        out.append(float(best))
    return out


def _floquet(p, x, n, st):
    """Multipliers of the period-``n`` orbit through ``x`` (issue 8).

    One or two Newton steps of :func:`vibimpact.analysis.shoot_periodic_orbit` from the
    converged point (the monodromy matrix from the variational equations with saltation
    matrices), at the sweep's integrator tolerances.
    """
    from ..analysis.shooting import shoot_periodic_orbit

    orb = shoot_periodic_orbit(point_system(p, st), x, n, tol=100.0 * st.rtol, max_iter=4,
                               damping=False)
    if not orb.converged or orb.minimal_period != n:
        return {}
    return dict(multipliers=orb.multipliers, floquet_abs_max=orb.abs_max,
                stable=int(orb.abs_max < 1.0))


def _describe(res, run, n, rec, r_start, want, st):
    """Fill the record's results: impacts and arcs, response maxima, Poincaré samples."""
    pts = run.strobe[1:]
    imp = run.impacts
    if "impacts" in want or "response" in want:
        cnt = impact_count(imp["period"], rec, period=max(n, 1))
        res["impacts_per_period"] = cnt.per_period
        res["impacts_constant"] = int(cnt.constant)
        switched = np.any(run.events["which"] == 0)
        res["contact"] = (CONTACT_IMPACTING if imp.size else
                          CONTACT_PERMANENT if (r_start > 1.0 and not switched) else
                          CONTACT_NONE)
        arcs = contact_arcs(imp["theta"])
        res["arcs"] = arcs.summary
        res["n_arcs"] = arcs.n_arcs
        if imp.size:
            res["v_impact_max"] = float(imp["v_impact"].max())
            res["v_impact_mean"] = float(imp["v_impact"].mean())
            res["penetration_max"] = float(imp["penetration"].max())
        else:
            res["v_impact_max"] = res["v_impact_mean"] = res["penetration_max"] = 0.0
    if "response" in want and run.dense is not None and run.dense.size:
        Xm, Ym, Rm = _maxima(run.dense)
        ext = run.events["which"] == 2  # exact extrema of R from the event log
        if np.any(ext):
            Rm = max(Rm, float(np.hypot(*run.events["state"][ext, :2].T).max()))
        res["X_m"], res["Y_m"], res["R_m"] = Xm, Ym, Rm
        res["min_gap"] = 1.0 - Rm
    if "poincare" in want:
        res["samples"] = np.full((st.n_samples, 4), np.nan)
        if n:  # the cycle, repeated
            cyc = pts[-n:]
            res["samples"] = np.tile(cyc, (-(-st.n_samples // n), 1))[:st.n_samples]
        else:
            k = min(st.n_samples, pts.shape[0])
            res["samples"][:k] = pts[-k:]


def point_system(p, settings):
    """``p`` (Params or System) as the System a point is analysed with: the solver
    settings of ``settings`` for those a System leaves None."""
    system = p if isinstance(p, System) else System(p)
    return system.resolved(method=settings.method, rtol=settings.rtol, atol=settings.atol)


def analyse_point(p, state0, settings, guess=None):
    """Analyse one parameter point.

    Parameters
    ----------
    p : Params or System
        A System's own solver settings take precedence over those of ``settings``.
    state0 : ndarray, shape (4,) or None
        Initial state at tau = 0 (rest when None).
    settings : SweepSettings
    guess : ndarray, shape (4,), optional
        A predicted point of a period-1 orbit (a continuation's predictor,
        :func:`vibimpact.sweeps.predict.extrapolate_branch`).  The record is integrated
        from it first; when its stroboscopic points already repeat (period 1 or 2, to the
        rule's tolerance, over the whole record) and the orbit attracts (Floquet
        multipliers inside the unit circle), that run is the record and the transient is
        0.  Otherwise the transient goes on from the run's end like after an extrapolation
        jump: a period found later is accepted only on an attracting orbit, or the
        transient restarts from ``state0`` with neither guess nor jumps.

    Returns
    -------
    result : dict
        :data:`SCALARS` entries, ``arcs`` (str), ``samples`` (n_samples, 4) Poincaré
        points (NaN where not computed), ``final_state`` (4,) for the next point,
        ``multipliers`` (4,) complex Floquet multipliers of a periodic point (NaN where
        not computed; the "floquet" analysis).

    Notes
    -----
    The transient's budget and its "has it settled?" test follow the motion's own
    contraction.  Points that repeat to the period test's tolerance have settled only
    when the geometric tail of their steps (the distance still to go, from the measured
    rate) is within that tolerance too; otherwise the orbit is refined by shooting (the
    period test's ``n`` stands when shooting fails).  At every check where
    the points neither repeat nor allow an extrapolation jump, their contraction rate
    (:func:`vibimpact.analysis.settling.contraction_rate`) says how many periods they
    still need; when that exceeds what is left of ``transient_max``, the attractor is
    sought by Newton shooting instead (:mod:`vibimpact.sweeps.settle`) and accepted only
    on evidence, confirmed by integrating from it.  A motion that no evidence decides is
    labelled UNSETTLED with its contraction rate and the periods it would need.
    """
    st = settings
    p = point_system(p, st)
    rule = st.rule
    want = set(st.analyses)
    res = dict(SCALARS)
    res["arcs"] = ""
    res["reason"] = ""
    res["samples"] = np.full((st.n_samples, 4), np.nan)
    x = np.zeros(p.n_state) if state0 is None else np.asarray(state0, dtype=np.float64).copy()
    res["final_state"] = np.full(4, np.nan)
    res["orbit_point"] = np.full(4, np.nan)
    res["multipliers"] = np.full(N_MULTIPLIERS, np.nan) + np.nan * 1j

    def diverged(status, reason, where):
        res["regime"] = REGIME_CODES[Label.DIVERGED]
        res["confidence"] = 1.0
        res["reason"] = f"{where}: {status.value}, {reason}"
        return res

    def try_shoot(strobe, con):
        """Shoot from a contracting ``strobe`` (one attempt of ``st.shoot``)."""
        nonlocal shots
        shots += 1
        return shoot(p, strobe, con, st, need_dense)

    # --- transient, ended early on a converged periodic orbit -----------------------
    tail = [x[None, :]]
    done = 0
    n = 0
    jumps = 0
    shots = 0
    chunk = st.chunk
    x_jump = None  # the integrated state a jump left (None: no jump since the last reset)
    run = None  # the record, when the guess's run is one
    evidence = None  # a shooting result confirmed by integration
    looked = -st.transient_max  # `done` at the last contraction check of the transient
    need_dense = "response" in want
    guessed = guess is not None
    ready = False  # the trial's points wait for the transient's first check
    wasted = 0  # periods of a trial not continued (reported in "transient", not counted)
    logged = []  # the transient's last chunks with their events: an unconverged transient's
    # record when they cover `record` periods of one trajectory
    if guessed:
        g = np.asarray(guess, dtype=np.float64)
        rec = max(st.record_periodic, 4)
        trial = p.simulate(periods=rec, state0=g, dense=st.dense if need_dense else 0)
        nt = 0 if trial.status is not Status.OK else detect_period(
            trial.strobe, tol=rule.period_tol, max_period=min(rule.max_period, rec // 3))
        if nt and 4 * nt <= rec and _attracting(p, trial.final_state, nt, st):
            run, n, x_start = trial, nt, g
        elif nt or trial.status is not Status.OK:  # a saddle, or no run: plain transient
            guessed = False
            wasted = rec
        else:  # the run is the first chunk of a transient that started with a jump
            x_jump = x
            x = trial.final_state.copy()
            tail = [trial.strobe]
            done = rec
            ready = True
    while run is None and (done < st.transient_max or ready):
        if not ready:  # integrate a chunk (a failed trial's points are checked first)
            todo = min(chunk, st.transient_max - done)
            if done + todo > st.transient_max - st.record:  # may end up in the record
                c = p.simulate(periods=todo, state0=x, dense=st.dense if need_dense else 0)
                status, why, pts = c.status, c.reason, c.strobe
                logged.append(c)
            else:
                status, why, pts = p.strobe(todo, x)
            if status is not Status.OK:
                return diverged(status, why, "transient")
            done += todo
            x = pts[-1].copy()
            tail.append(pts[1:])
        ready = False
        strobe = np.concatenate(tail)[-(3 * rule.max_period + 1):]
        tail = [strobe]
        n = _converged_period(strobe, rule)
        if n and x_jump is not None and not _attracting(p, x, n, st):
            # a jump (or a guess) onto a saddle: its points repeat for a long while
            # before they leave.  Resume from where the jump left the trajectory, without
            # further jumps; after a guess, start the plain transient from state0.
            n = 0
            x = x_jump
            x_jump = None
            logged = []
            if guessed:  # the plain transient gets its whole length
                jumps, wasted, done = 0, wasted + done, 0
            else:
                jumps = st.extrapolate
            guessed = False
            tail = [x[None, :]]
            chunk = st.chunk
            continue
        if n:
            if shots < st.shoot and strobe.shape[0] > MIN_SHOOT_PERIODS:
                con = unsettled_repeat(strobe, n, rule.period_tol)
                if con is not None:  # repeating only because the points move slowly
                    evidence = try_shoot(strobe, con)
            break
        if jumps < st.extrapolate:
            xs = _extrapolated(strobe)
            if xs is not None:  # restart from the limit; only new points count
                jumps += 1
                if not guessed:  # after a guess, a saddle sends the transient to state0
                    x_jump = x.copy()
                x = xs
                logged = []
                tail = [x[None, :]]
                chunk = min(st.chunk, CHUNK_AFTER_JUMP)
                continue
        chunk = st.chunk
        if shots < st.shoot and strobe.shape[0] > MIN_SHOOT_PERIODS and \
                done - looked >= CHECK_EVERY * st.chunk:
            looked = done
            con = find_contraction(strobe)
            if needs_shooting(con, rule.period_tol, st.transient_max - done):
                evidence = try_shoot(strobe, con)
                if evidence is not None:
                    break
    if evidence is not None:  # the orbit's confirming run is the record
        run, n, x_start = evidence.run, evidence.n, evidence.state
        rec = run.strobe.shape[0] - 1
    if run is None and not n and logged and \
            sum(c.strobe.shape[0] - 1 for c in logged) >= st.record:
        run = join_runs(logged, p.period)
        rec = run.strobe.shape[0] - 1
        x_start = run.strobe[0]
        done -= rec

    # --- record -----------------------------------------------------------------------
    if run is None:
        rec = max(st.record_periodic, 4 * n) if n else st.record
        x_start = x
        run = p.simulate(periods=rec, state0=x, dense=st.dense if need_dense else 0)
        if run.status is not Status.OK:
            return diverged(run.status, run.reason, "record")
    con = None
    if not n:  # a record that still moves: does it contract onto an orbit?
        con = find_contraction(run.strobe)
        if con is not None and shots < st.shoot:
            evidence = try_shoot(run.strobe, con)
            if evidence is not None:
                done += rec
                run, n, x_start = evidence.run, evidence.n, evidence.state
                rec = run.strobe.shape[0] - 1
    res["transient"] = done + wasted
    r_start = math.hypot(x_start[0], x_start[1])
    res["recorded"] = rec
    x = run.final_state
    res["final_state"] = x.copy()
    pts = run.strobe[1:]
    if n:
        n = detect_period(run.strobe, tol=rule.period_tol,
                          max_period=min(rule.max_period, rec // 3)) or n
    res["period"] = n
    if n == 1:
        res["orbit_point"] = _orbit_point(run.strobe)
    _describe(res, run, n, rec, r_start, want, st)
    T = p.period

    # --- evidence of settling, Floquet multipliers of a periodic point ----------------
    if evidence is not None:
        res.update(multipliers=evidence.multipliers, floquet_abs_max=evidence.abs_max,
                   stable=1, shoot_residual=evidence.residual,
                   orbit_distance=evidence.distance, contraction=evidence.rate)
    elif n and "floquet" in want:
        res.update(_floquet(p, x, n, st))
    if n and np.isfinite(res["floquet_abs_max"]):
        res["floquet_exponent"] = math.log(res["floquet_abs_max"]) / (n * T)
    if con is not None and evidence is None:
        res["contraction"] = con.rate
        res["settle_periods"] = settling_periods(con, rule.period_tol)
    # --- chaos tests, only where no period was found ----------------------------------
    lam = err = k = math.nan
    if not n and "test01" in want:
        k = test01(pts[:, int(np.argmax(np.ptp(pts, axis=0)))])
    if "lyapunov" in want and (not n or st.lyapunov == "always"):
        ly = lyapunov_spectrum(p, state0=x, n_exponents=1, averaging=Averaging(
            transient=0, min_periods=st.lyap_min, max_periods=st.lyap_max,
            target_stderr=st.lyap_target, align=20, decisive=(rule.zero / T, rule.z)))
        if ly.status is not Status.OK:
            res["regime"] = REGIME_CODES[Label.DIVERGED]
            res["reason"] = f"lyapunov: {ly.status.value}, {ly.reason}"
            return res
        lam, err = float(ly.exponents[0]), float(ly.stderr[0])
    torus = tor = None
    # a torus? (only where it can decide: an exponent in the zero band, or K regular)
    zero_band = math.isfinite(lam) and abs(lam * T) - rule.z * err * T <= rule.zero
    regular_k = not math.isfinite(lam) and math.isfinite(k) and k < rule.k_chaos
    if not n and (zero_band or regular_k) and pts.shape[0] >= 16:
        tor = torus_evidence(pts)
        if con is None and tor.non_contracting and not tor.recurrent:
            # a torus whose rotation number lies near a rational covers its curve slowly:
            # look at a record TORUS_EXTEND times as long before deciding
            status, why, more = p.strobe((TORUS_EXTEND - 1) * rec, x)
            if status is not Status.OK:
                return diverged(status, why, "torus record")
            res["final_state"] = more[-1].copy()
            tor = torus_evidence(np.concatenate([pts, more[1:]]))
        torus = tor.torus and con is None
    if not n and con is None and pts.shape[0] > 8:
        c1 = tor.contraction if tor is not None else contraction_rate(pts, 1)
        res["contraction"] = np.nan if c1 is None else c1.rate
    label, n_out, conf, reason = decide(n, lam * T, err * T, k, rule, torus=torus)
    if label is Label.UNSETTLED and math.isfinite(lam) and \
            lam * T + rule.z * err * T < -rule.zero:
        # an attracting motion without a period <= max_period: search a longer record
        long_n, long_run, status, why = _long_recurrence(p, x, rule, st, need_dense)
        if status is not Status.OK:
            return diverged(status, why, "recurrence search")
        if long_n:  # the search's periods were transient; the record follows them
            res["transient"] += 3 * LONG_SEARCH * rule.max_period + 1
            res["recorded"] = rec = long_run.strobe.shape[0] - 1
            res["final_state"] = long_run.final_state.copy()
            _describe(res, long_run, long_n, rec, r_start, want, st)
            label, n_out, conf = Label.PERIODIC, long_n, 1.0
            reason = f"recurrence found by a search up to {LONG_SEARCH * rule.max_period}"
    if evidence is not None:
        reason = (f"shooting: orbit of period {n} converged (residual "
                  f"{evidence.residual:.1e}), |mu|max {evidence.abs_max:.4f}, approached "
                  f"at {evidence.rate:.2e}/period; confirmed by integration")
    elif label is Label.UNSETTLED and np.isfinite(res["settle_periods"]):
        reason += (f"; contracting at {res['contraction']:.2e}/period, would need "
                   f"{res['settle_periods']:.0f} more periods")
    res.update(regime=REGIME_CODES[label], period=n_out, confidence=conf, lyapunov=lam,
               lyapunov_err=err, k01=k, reason=reason)
    return res


def _long_recurrence(p, x, rule, st, need_dense):
    """``(n, run, status, reason)``: the period of the motion from ``x`` up to
    ``LONG_SEARCH * max_period`` (0 if none), searched on stroboscopic points only, and
    when one is found the record integrated on from the search's end (4 motion periods,
    with events and dense samples as the request needs; None otherwise)."""
    m = LONG_SEARCH * rule.max_period
    status, why, pts = p.strobe(3 * m + 1, x)
    if status is not Status.OK:
        return 0, None, status, why
    n = detect_period(pts, tol=rule.period_tol, max_period=m)
    if not n:
        return 0, None, status, why
    run = p.simulate(periods=4 * n, state0=pts[-1], dense=st.dense if need_dense else 0)
    return n, run, run.status, run.reason
