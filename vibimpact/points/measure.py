"""The second half of a point's pipeline: measure what the request asks on the record.

:func:`measure` takes the record :func:`vibimpact.points.transient.settle` left and fills a
:class:`~vibimpact.points.point.PointResult`: period, impacts and contact arcs, response
maxima and Poincaré samples (:func:`describe`), Floquet multipliers of a periodic point,
the settling evidence, and only where no period was found the chaos tests (0-1 test,
largest Lyapunov exponent), the torus test and a longer recurrence search; then the
label (:func:`vibimpact.analysis.classify.decide`).
"""
from __future__ import annotations

import math

import numpy as np

from ..analysis.chaos01 import test01
from ..analysis.classify import Label, decide
from ..analysis.exponents import Averaging
from ..analysis.extrapolation import extrapolate_limit
from ..analysis.impacts import contact_arcs, impact_count
from ..analysis.lyapunov import lyapunov_spectrum
from ..analysis.period import detect_period
from ..analysis.settling import contraction_rate, settling_periods, torus_evidence
from ..core.run import Status
from .codes import CONTACT_IMPACTING, CONTACT_NONE, CONTACT_PERMANENT, REGIME_CODES

#: longest period the recurrence search looks for when the exponent is negative but no
#: period up to the rule's ``max_period`` was found (as a multiple of ``max_period``)
LONG_SEARCH = 4
#: a record whose points neither contract nor recur is looked at this many times as long
TORUS_EXTEND = 4


def orbit_point(strobe):
    """The fixed point of a converged period-1 record: minimal polynomial extrapolation
    of its last 6 stroboscopic points, or the last point where the extrapolation leaves
    their neighbourhood.  The record's points approach the orbit geometrically (after a
    transient ended at the period test's tolerance, about 1e-7 of the orbit's size
    remains); the limit removes that residue, which the continuation's predictor would
    amplify (:mod:`vibimpact.points.predict`)."""
    z = strobe[-6:]
    last = z[-1]
    xs = extrapolate_limit(z) if z.shape[0] >= 3 else last
    spread = float(np.abs(np.diff(z, axis=0)).max()) if z.shape[0] > 1 else 0.0
    if not np.all(np.isfinite(xs)) or float(np.abs(xs - last).max()) > 10.0 * spread:
        return last.copy()
    return xs


def maxima(dense, positions=(0, 1)):
    """Largest ``|x_i|``, ``|x_j|`` and ``R = hypot(x_i, x_j)`` of densely sampled
    motion, ``(i, j)`` the contact's two ``positions``, refined by a parabola through the
    sample at the maximum and its neighbours (error O(h^3) instead of O(h^2))."""
    out = []
    i0, i1 = positions
    R = np.hypot(dense[:, i0], dense[:, i1])
    for v in (np.abs(dense[:, i0]), np.abs(dense[:, i1]), R):
        i = int(np.argmax(v))
        best = v[i]
        if 0 < i < v.size - 1:
            a, b, c = v[i - 1], v[i], v[i + 1]
            den = a - 2.0 * b + c
            if den < 0.0:
                best = b - 0.125 * (a - c) ** 2 / den
        out.append(float(best))
    return out


def floquet(system, x, n, settings):
    """Multipliers of the period-``n`` orbit through ``x``: one or two Newton steps of
    :func:`vibimpact.analysis.shoot_periodic_orbit` from the converged point (the
    monodromy matrix from the variational equations with saltation matrices), at the
    point's integrator tolerances.  ``{}`` when Newton does not confirm the period."""
    from ..analysis.shooting import shoot_periodic_orbit

    orb = shoot_periodic_orbit(system, x, n, tol=100.0 * settings.rtol, max_iter=4,
                               damping=False)
    if not orb.converged or orb.minimal_period != n:
        return {}
    return dict(multipliers=orb.multipliers, floquet_abs_max=orb.abs_max,
                stable=int(orb.abs_max < 1.0))


def _impacts(res, run, n, rec, start_inside, contact):
    """Impacts per period, contact, arcs and impact statistics of the record."""
    imp = run.impacts
    cnt = impact_count(imp["period"], rec, period=max(n, 1))
    res.impacts_per_period = cnt.per_period
    res.impacts_constant = int(cnt.constant)
    switched = np.any(run.events["which"] == contact.switch)
    res.contact = (CONTACT_IMPACTING if imp.size else
                   CONTACT_PERMANENT if (start_inside and not switched) else CONTACT_NONE)
    arcs = contact_arcs(run)   # the contact intervals: entry to exit, sliding included
    res.arcs = arcs.summary
    res.n_arcs = arcs.n_arcs
    res.arc_table = arcs.table()   # start, end, width (degrees), loaded (time fraction)
    if imp.size:
        res.v_impact_max = float(imp["v_impact"].max())
        res.v_impact_mean = float(imp["v_impact"].mean())
        res.penetration_max = float(imp["penetration"].max())
    else:
        res.v_impact_max = res.v_impact_mean = res.penetration_max = 0.0


def _circle(model):
    """The radius of the model's circular obstacle centred at the origin
    (:attr:`vibimpact.models.PlotSpec.circle`), or None."""
    spec = getattr(model, "plot", None)
    return getattr(spec, "circle", None)


def run_params(run):
    """The parameter vector a run was integrated with."""
    p = run.params
    return p.as_array() if hasattr(p, "as_array") else np.asarray(p, dtype=np.float64)


def describe(res, run, n, rec, start_inside, settings, contact=None, circle=None):
    """Fill the record's results: impacts and arcs (a model with a contact), response
    maxima (a model with a planar contact: the largest displacements and radius in the
    plane of its positions, and the smallest gap: ``circle`` minus that radius where the
    model's obstacle is a circle of radius ``circle``, else minus the contact's largest
    penetration), Poincaré samples.  ``start_inside``: whether the record started in
    contact."""
    st = settings
    want = st.analyses
    pts = run.strobe[1:]
    if contact is not None and ("impacts" in want or "response" in want):
        _impacts(res, run, n, rec, start_inside, contact)
    if contact is not None and len(contact.positions) == 2 and "response" in want and \
            run.dense is not None and run.dense.size:
        cols = tuple(contact.positions)
        Xm, Ym, Rm = maxima(run.dense, cols)
        ext = run.events["which"] == contact.extremum  # exact extrema of R from the log
        if np.any(ext):
            Rm = max(Rm, float(np.hypot(*run.events["state"][ext][:, cols].T).max()))
        res.X_m, res.Y_m, res.R_m = Xm, Ym, Rm
        if circle is not None:  # the obstacle is the circle of this radius
            res.min_gap = float(circle) - Rm
        else:  # the contact's own measure, at the samples and the logged extrema
            states = np.concatenate([run.dense, run.events["state"][ext]])
            res.min_gap = -float(np.max(contact.penetration(states, run_params(run))))
    if "poincare" in want:
        res.samples = np.full((st.n_samples, pts.shape[1]), np.nan)
        if n:  # the cycle, repeated
            cyc = pts[-n:]
            res.samples = np.tile(cyc, (-(-st.n_samples // n), 1))[:st.n_samples]
        else:
            k = min(st.n_samples, pts.shape[0])
            res.samples[:k] = pts[-k:]


def long_recurrence(system, x, settings):
    """``(n, run, status, reason)``: the period of the motion from ``x`` up to
    ``LONG_SEARCH * max_period`` (0 if none), searched on stroboscopic points only, and
    when one is found the record integrated on from the search's end (4 motion periods,
    with events and dense samples as the request needs; None otherwise)."""
    st = settings
    m = LONG_SEARCH * st.rule.max_period
    status, why, pts = system.strobe(3 * m + 1, x)
    if status is not Status.OK:
        return 0, None, status, why
    n = detect_period(pts, tol=st.rule.period_tol, max_period=m)
    if not n:
        return 0, None, status, why
    run = system.simulate(periods=4 * n, state0=pts[-1],
                          dense=st.dense if "response" in st.analyses else 0)
    return n, run, run.status, run.reason


def _settling(res, system, settled, x, n, settings):
    """Evidence of settling and Floquet multipliers of a periodic point."""
    ev, con = settled.evidence, settled.con
    if ev is not None:
        res.update(multipliers=ev.multipliers, floquet_abs_max=ev.abs_max, stable=1,
                   shoot_residual=ev.residual, orbit_distance=ev.distance,
                   contraction=ev.rate)
    elif n and "floquet" in settings.analyses:
        res.update(**floquet(system, x, n, settings))
    if n and np.isfinite(res.floquet_abs_max):
        res.floquet_exponent = math.log(res.floquet_abs_max) / (n * system.period)
    if con is not None and ev is None:
        res.contraction = con.rate
        res.settle_periods = settling_periods(con, settings.rule.period_tol)


def _chaos_tests(res, system, pts, x, n, settings):
    """``(lam, err, k)``: the 0-1 test's K and the largest exponent with its error, only
    where no period was found (the exponent always with ``lyapunov="always"``); None
    when the exponent's run stopped (the point is then marked diverged)."""
    st, rule, T = settings, settings.rule, system.period
    lam = err = k = math.nan
    if not n and "test01" in st.analyses:
        k = test01(pts[:, int(np.argmax(np.ptp(pts, axis=0)))])
    if "lyapunov" in st.analyses and (not n or st.lyapunov == "always"):
        ly = lyapunov_spectrum(system, state0=x, n_exponents=1, averaging=Averaging(
            transient=0, min_periods=st.lyap_min, max_periods=st.lyap_max,
            target_stderr=st.lyap_target, align=20, decisive=(rule.zero / T, rule.z)))
        if ly.status is not Status.OK:
            res.regime = REGIME_CODES[Label.DIVERGED]
            res.reason = f"lyapunov: {ly.status.value}, {ly.reason}"
            return None
        lam, err = float(ly.exponents[0]), float(ly.stderr[0])
    return lam, err, k


def _torus(res, system, settled, pts, x, lam, err, k, settings):
    """The torus test where it can decide (an exponent in the zero band, or K regular);
    ``(torus, ok)``, ``ok`` False when the longer record's run stopped."""
    rule, T, con = settings.rule, system.period, settled.con
    torus = tor = None
    zero_band = math.isfinite(lam) and abs(lam * T) - rule.z * err * T <= rule.zero
    regular_k = not math.isfinite(lam) and math.isfinite(k) and k < rule.k_chaos
    if not settled.n and (zero_band or regular_k) and pts.shape[0] >= 16:
        tor = torus_evidence(pts)
        if con is None and tor.non_contracting and not tor.recurrent:
            # a torus whose rotation number lies near a rational covers its curve slowly:
            # look at a record TORUS_EXTEND times as long before deciding
            status, why, more = system.strobe((TORUS_EXTEND - 1) * settled.rec, x)
            if status is not Status.OK:
                res.diverged(status, why, "torus record")
                return None, False
            res.final_state = more[-1].copy()
            tor = torus_evidence(np.concatenate([pts, more[1:]]))
        torus = tor.torus and con is None
    if not settled.n and con is None and pts.shape[0] > 8:
        c1 = tor.contraction if tor is not None else contraction_rate(pts, 1)
        res.contraction = np.nan if c1 is None else c1.rate
    return torus, True


def measure(system, settled, settings, res):
    """Fill ``res`` (a :class:`~vibimpact.points.point.PointResult`) from the record.

    Parameters
    ----------
    system : System
    settled : Settled
        From :func:`vibimpact.points.transient.settle` (without failure).
    settings : SweepSettings
    res : PointResult

    Returns
    -------
    PointResult
        ``res``, filled.
    """
    st, rule, T = settings, settings.rule, system.period
    run, n, rec, ev = settled.run, settled.n, settled.rec, settled.evidence
    contact = system.model.contact
    res.transient = settled.transient
    start_inside = contact is not None and bool(
        contact.penetration(settled.x_start[None, :], system.p)[0] > 0.0)
    res.recorded = rec
    x = run.final_state
    res.final_state = x.copy()
    pts = run.strobe[1:]
    if n:
        n = detect_period(run.strobe, tol=rule.period_tol,
                          max_period=min(rule.max_period, rec // 3)) or n
    res.period = n
    if n == 1:
        res.orbit_point = orbit_point(run.strobe)
    describe(res, run, n, rec, start_inside, st, contact, _circle(system.model))
    _settling(res, system, settled, x, n, st)
    tests = _chaos_tests(res, system, pts, x, n, st)
    if tests is None:
        return res
    lam, err, k = tests
    torus, ok = _torus(res, system, settled, pts, x, lam, err, k, st)
    if not ok:
        return res
    label, n_out, conf, reason = decide(n, lam * T, err * T, k, rule, torus=torus)
    if label is Label.UNSETTLED and math.isfinite(lam) and \
            lam * T + rule.z * err * T < -rule.zero:
        # an attracting motion without a period <= max_period: search a longer record
        long_n, long_run, status, why = long_recurrence(system, x, st)
        if status is not Status.OK:
            return res.diverged(status, why, "recurrence search")
        if long_n:  # the search's periods were transient; the record follows them
            res.transient += 3 * LONG_SEARCH * rule.max_period + 1
            res.recorded = rec = long_run.strobe.shape[0] - 1
            res.final_state = long_run.final_state.copy()
            describe(res, long_run, long_n, rec, start_inside, st, contact,
                     _circle(system.model))
            label, n_out, conf = Label.PERIODIC, long_n, 1.0
            reason = f"recurrence found by a search up to {LONG_SEARCH * rule.max_period}"
    if ev is not None:
        reason = (f"shooting: orbit of period {n} converged (residual "
                  f"{ev.residual:.1e}), |mu|max {ev.abs_max:.4f}, approached "
                  f"at {ev.rate:.2e}/period; confirmed by integration")
    elif label is Label.UNSETTLED and np.isfinite(res.settle_periods):
        reason += (f"; contracting at {res.contraction:.2e}/period, would need "
                   f"{res.settle_periods:.0f} more periods")
    res.update(regime=REGIME_CODES[label], period=n_out, confidence=conf, lyapunov=lam,
               lyapunov_err=err, k01=k, reason=reason)
    return res
