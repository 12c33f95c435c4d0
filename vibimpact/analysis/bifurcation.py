"""Where and how a periodic orbit ends as a parameter moves: :func:`locate_bifurcation`.

Natural-parameter stepping with bisection on top of
:func:`~vibimpact.analysis.shooting.shoot_periodic_orbit`: the first parameter value
between ``start`` and ``stop`` where a stable period-``n`` orbit stops *persisting* (it
loses stability, vanishes, collapses onto a lower period, or changes its sequence of
switching events), bracketed to ``tol``, and the kind of that event from the Floquet
multipliers (Kuznetsov 2004, ch. 4; Leine & Nijmeijer 2004, ch. 7): a multiplier through
``-1``: period doubling; through ``+1``: fold (the orbit vanishes at a turning point); a
complex pair: Neimark--Sacker; a new or lost switching event (contact entry, lift-off,
stick): grazing / a switching (discontinuity-induced) bifurcation (di Bernardo et al.
2008, ch. 8).  The whole branch, unstable parts included, is
:func:`~vibimpact.analysis.continuation.continue_orbit`'s.

References
----------
.. [1] Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., Springer
   (2004), ch. 4.
.. [2] R. I. Leine, H. Nijmeijer, *Dynamics and Bifurcations of Non-Smooth Mechanical
   Systems*, Springer (2004), ch. 7.
.. [3] M. di Bernardo, C. J. Budd, A. R. Champneys, P. Kowalczyk, *Piecewise-smooth
   Dynamical Systems*, Springer (2008), ch. 8 (grazing of periodic orbits).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import math
from dataclasses import dataclass

import numpy as np

from ..base.bifurcation_kinds import BifurcationKind
from ..core.run import Status
from ..base import _validate as _v
from ..core.system import as_system
from .shooting import PeriodicOrbit, critical_multiplier, shoot_periodic_orbit

if TYPE_CHECKING:  # names of the annotations only
    from collections.abc import Mapping
    from typing import Any

    from numpy.typing import ArrayLike

    from ..core.system import System

__all__ = ["Bifurcation", "locate_bifurcation", "orbit_signature", "grazing_gap",
           "CONTINUATION_SOLVER"]

#: solver defaults of every integration here (shooting, monodromy, signatures, amplitudes;
#: the rest as :func:`vibimpact.simulate`)
CONTINUATION_SOLVER = dict(rtol=1e-10)


def orbit_signature(system, state, n):
    """The switching events of a period-``n`` orbit, as a hashable tuple.

    ``(counts, modes)``: the number of mode-changing events of each terminal switch over
    ``n`` periods, and the sorted distinct modes the orbit visits.  Both are independent
    of where on the orbit ``state`` lies (an event crossing the strobe instant changes
    nothing).  For the built-in rotor, ``counts = (contact entries + exits, slip/stick
    switches)`` and ``modes`` tells free flight, contact and the friction state apart, so
    permanent contact and impactless motion differ.  Two orbits of one branch have the same
    signature until a grazing (a contact appears or disappears, or a permanent contact
    lifts off) or a stick-slip change.

    ``system``'s solver settings default to DOP853, ``rtol = 1e-10``, ``atol = 1e-12``
    (:data:`CONTINUATION_SOLVER`).
    """
    system = as_system(system)
    mdl = system.model
    x = _v.state("state0", state, system.n_state)
    mode = np.zeros(mdl.n_mode, dtype=np.int64)
    mdl.init_mode(0.0, x.copy(), system.p, mode)
    run = system.simulate(periods=n, state0=x, solver=system.settings(**CONTINUATION_SOLVER))
    if run.status is not Status.OK:
        return ("diverged",)
    w = np.asarray(run.events["which"])
    before = np.asarray(run.events["mode_before"]).reshape(w.size, -1)
    after = np.asarray(run.events["mode_after"]).reshape(w.size, -1)
    changed = np.any(before != after, axis=1)
    counts = tuple(int(np.sum((w == i) & changed)) for i in range(mdl.terminal.size)
                   if mdl.terminal[i] == 1)
    modes = {tuple(int(m) for m in mode)}
    modes.update(tuple(int(m) for m in row) for row in after[changed])
    return counts, tuple(sorted(modes))


def grazing_gap(system, state, n):
    """Smallest distance to the contact surface, ``|penetration|`` of the model's contact
    (``|R - 1|`` for the built-in rotor), over the extrema of the penetration along an
    orbit (0 at grazing).

    The extrema are the located events of the model's contact extremum observer
    (:attr:`vibimpact.Contact.extremum`; ``dR/dtau`` for the built-in rotor): the closest
    approaches in free flight and the deepest points of contacts.  NaN for a model
    without a contact (or without an extremum observer) or an orbit without extrema.
    Solver defaults as :func:`orbit_signature`'s.
    """
    system = as_system(system)
    contact = system.model.contact
    if contact is None or contact.extremum is None:
        return math.nan
    run = system.simulate(periods=n, state0=state, solver=system.settings(**CONTINUATION_SOLVER))
    if run.status is not Status.OK:
        return math.nan
    ext = np.asarray(run.events["which"]) == contact.extremum
    if not np.any(ext):
        return math.nan
    depth = contact.penetration(np.asarray(run.events["state"])[ext], system.p)
    return float(np.min(np.abs(depth)))


@dataclass(frozen=True)
class Bifurcation:
    """Where, and how, a stable periodic orbit stops persisting.

    Attributes
    ----------
    param : str or int
    value : float
        Midpoint of ``bracket``; NaN when the orbit persists over the whole range
        (``kind == "none"``).
    bracket : (float, float)
        Last value where the orbit persists, first where it does not.
    kind : BifurcationKind
        :attr:`~BifurcationKind.PERIOD_DOUBLING`, :attr:`~BifurcationKind.FOLD`,
        :attr:`~BifurcationKind.NEIMARK_SACKER`, :attr:`~BifurcationKind.GRAZING` (the
        contact events of the orbit change), :attr:`~BifurcationKind.STICK_SLIP` (its
        friction events change) or :attr:`~BifurcationKind.NONE` (a ``str``: equal to
        its short name, ``"period doubling"``).
    detail : str
        The evidence in words.
    orbit : PeriodicOrbit
        At the persisting end of the bracket.
    beyond : PeriodicOrbit or None
        The Newton result at the other end (``converged`` False past a fold).
    signature, signature_beyond : tuple
        :func:`orbit_signature` at both ends.
    gap : float
        :func:`grazing_gap` of ``orbit`` (NaN for a model without a contact or without
        an extremum observer).
    at_grazing : bool
        The event is a grazing, or a fold within ``10 tol`` of grazing in gap (a
        grazing-induced fold: with a stiff Hertz contact, such as the built-in rotor's,
        the multipliers move fast just past grazing and the orbit vanishes a few 1e-5 in
        the parameter later).
    """

    param: object
    value: float
    bracket: tuple
    kind: BifurcationKind
    detail: str
    orbit: PeriodicOrbit
    beyond: PeriodicOrbit | None = None
    signature: tuple = ()
    signature_beyond: tuple = ()
    gap: float = math.nan
    at_grazing: bool = False

    @property
    def multipliers(self):
        """Floquet multipliers at the persisting end."""
        return self.orbit.multipliers


def _persistence(system, param, value, guess, n, ref_sig, shoot_kw, settle=100):
    """Shoot at ``value``; returns (ok, why, orbit, signature).

    When Newton fails from ``guess`` the motion is first integrated ``settle`` periods
    and Newton tried again from there: next to a grazing with a discontinuous vector
    field (tangential damping B_T) the map is non-smooth and Newton from the other side
    of the grazing can fail although the orbit exists.  An orbit found that way counts
    only when it lies within 2 % of the orbit's size of ``guess`` (past a true fold the
    motion leaves for a distant attractor, or lingers near the ghost and Newton fails
    again).
    """
    q = system.with_param(param, value)
    scale = max(1.0, float(np.abs(guess).max()))
    orb = shoot_periodic_orbit(q, guess, n, **shoot_kw)
    if not orb.converged and settle:
        run = q.simulate(periods=settle, state0=guess)
        if run.status is Status.OK:
            o2 = shoot_periodic_orbit(q, run.final_state, n, **shoot_kw)
            if o2.converged and \
                    float(np.abs(o2.cycle - guess).max(axis=1).min()) <= 0.02 * scale:
                orb = o2
    if not orb.converged:
        return False, "fold", orb, ()
    jump = float(np.abs(orb.cycle - guess).max(axis=1).min())
    if jump > 0.25 * scale:
        return False, "fold", orb, ()  # Newton left for another orbit: this one is gone
    if orb.minimal_period < n:  # the orbit of lower period it collapsed onto
        low = shoot_periodic_orbit(q, orb.state, orb.minimal_period, **shoot_kw)
        return False, "collapse", (low if low.converged else orb), ()
    k = int(np.argmin(np.abs(orb.cycle - guess).max(axis=1)))
    if k:  # the same cycle from another of its points (after settling): re-anchor it
        orb = shoot_periodic_orbit(q, orb.cycle[k], n, **shoot_kw)
    sig = orbit_signature(q, orb.state, n)
    if orb.abs_max >= 1.0:
        return False, "unstable", orb, sig
    if ref_sig is not None and sig != ref_sig:
        return False, "signature", orb, sig
    return True, "", orb, sig


def _kind(why, orb_lo, orb_hi, sig_lo, sig_hi, gap, tol):
    """Bifurcation kind, evidence, and whether it happens at grazing."""
    mu = orb_lo.multipliers
    top = mu[0] if mu.size else complex(math.nan)
    at = f"|mu|max = {abs(top):.4f} (mu = {top.real:+.4f}{top.imag:+.4f}j)"
    if why == "collapse":
        ratio = orb_lo.n // max(1, orb_hi.minimal_period)
        ml = orb_hi.multipliers[0]
        text = (f"the period-{orb_lo.n} orbit collapses onto period "
                f"{orb_hi.minimal_period}; {at}; the period-{orb_hi.minimal_period} "
                f"orbit there: mu = {ml.real:+.4f}{ml.imag:+.4f}j (|mu| {abs(ml):.4f}, "
                f"arg {math.degrees(math.atan2(ml.imag, ml.real)):.1f} deg)")
        if ratio == 2:
            return BifurcationKind.PERIOD_DOUBLING, text, False
        # a period-k orbit, k > 2, born from a period-1 orbit: a resonance of a complex
        # pair of multipliers (Kuznetsov 2004, sec. 9.5), or a fold of the k-cycle
        crit = critical_multiplier(orb_hi.multipliers)
        kind = (BifurcationKind.by_multiplier(crit) if crit in ("+1", "-1", "complex")
                else BifurcationKind.FOLD)
        return kind, text + f" (resonance 1:{ratio})", False
    if why == "unstable":
        crit = critical_multiplier(orb_hi.multipliers)
        mh = orb_hi.multipliers[0]
        return (BifurcationKind.by_multiplier(crit),
                f"multiplier leaves the unit circle through {crit}: {at} before, "
                f"mu = {mh.real:+.4f}{mh.imag:+.4f}j after", False)
    if why == "fold":
        crit = critical_multiplier(mu)
        text = (f"no orbit beyond (Newton fails); {at}, largest multiplier "
                f"{'real positive' if crit == '+1' else crit}")
        at_grazing = bool(np.isfinite(gap) and gap <= 10.0 * tol)
        if at_grazing:
            text += f"; at grazing (gap {gap:.1e} at the bracket)"
        elif crit != "+1":
            text += " (non-smooth: no multiplier approaches +1)"
        return BifurcationKind.FOLD, text, at_grazing
    # the switching events changed
    (cl, ml), (ch, mh) = sig_lo, (sig_hi if len(sig_hi) == 2 else ((), ()))
    first = [m[0] for m in ml], [m[0] for m in mh]
    if (cl[:1] != ch[:1]) or sorted(set(first[0])) != sorted(set(first[1])):
        return (BifurcationKind.GRAZING,
                f"contact events per orbit {cl[0] if cl else '?'} -> "
                f"{ch[0] if ch else '?'}, modes {ml} -> {mh}; {at}", True)
    return (BifurcationKind.STICK_SLIP,
            f"friction events per orbit {cl[1:]} -> {ch[1:]}, modes {ml} -> {mh}; {at}",
            False)


def locate_bifurcation(system: System, state0: ArrayLike, n: int = 1, *, param: str,
                       start: float, stop: float, tol: float = 1e-6,
                       step: float | None = None,
                       shoot_kw: Mapping[str, Any] | None = None) -> Bifurcation:
    """The first value between ``start`` and ``stop`` where a stable period-``n`` orbit
    stops persisting, bracketed to ``tol``, and the kind of bifurcation.

    The orbit is shot at ``start`` from ``state0``, then followed towards ``stop`` in
    steps of at most ``step`` (Newton from a secant prediction of the previous orbits);
    a failing step is halved and retried from the last good orbit until it is below
    ``tol``, so every verdict comes from a guess at most ``tol`` away (plain bisection,
    which keeps an old failure, would take a Newton iteration that jumped to a
    neighbouring orbit for the end of the branch).  It *persists* while Newton
    converges near the previous orbit (after settling the motion for 100 periods when
    Newton alone fails, see :func:`_persistence`), the orbit keeps its minimal period
    ``n``, every Floquet multiplier stays inside the unit circle, and its switching
    events (:func:`orbit_signature`) stay the same.  A fold within ``10 tol`` of a
    grazing (in the smallest gap) is flagged ``at_grazing``.

    Parameters
    ----------
    system : System
        Model, parameters (the value of ``param`` is replaced) and solver settings
        (defaults DOP853, ``rtol = 1e-10``, ``atol = 1e-12``: :data:`CONTINUATION_SOLVER`)
        of every shooting and integration.
    state0 : array_like, shape (d,)
        A guess of the orbit at ``start``.
    n : int
        Period in forcing periods.
    param : str or int
        The parameter varied (``"eta"``, ``"gamma"``, ``"omega"``, ... or an index).
    start, stop : float
        The range; ``stop`` may be below ``start``.
    tol : float
        Width of the final bracket.
    step : float, optional
        Largest continuation step (``|stop - start|`` by default: bisection at once).
    shoot_kw : dict, optional
        Newton's settings passed to :func:`shoot_periodic_orbit` (``tol``, ``max_iter``,
        ``damping``).

    Returns
    -------
    Bifurcation
        ``kind`` :attr:`BifurcationKind.NONE` (value NaN) when the orbit persists up
        to ``stop``.

    Raises
    ------
    ValueError
        Naming the argument; ``state0`` when no stable period-``n`` orbit is found at
        ``start``.

    Examples
    --------
    The period doubling of the Duffing oscillator's period-1 orbit
    (``delta = 0.3, alpha = -1, beta = 1, omega = 1.2``) near ``gamma = 0.2656``:

    >>> import vibimpact as vi
    >>> from vibimpact.analysis import locate_bifurcation
    >>> b = locate_bifurcation(vi.System(vi.DuffingParams(gamma=0.25)), [1.0, 0.0],
    ...                        param="gamma", start=0.25, stop=0.28, tol=1e-5)
    >>> str(b.kind)
    'period doubling'
    """
    start = float(_v.finite("start", start))
    stop = float(_v.finite("stop", stop))
    if start == stop:
        raise ValueError("stop must differ from start")
    tol = _v.positive("tol", tol)
    n = _v.count("n", n, 1)
    system = as_system(system).resolved(**CONTINUATION_SOLVER)
    system.param(param)  # validates param
    step = abs(stop - start) if step is None else _v.positive("step", step)
    shoot_kw = dict(shoot_kw or {})
    q0 = system.with_param(param, start)
    orb = shoot_periodic_orbit(q0, state0, n, **shoot_kw)
    if not orb.converged or orb.minimal_period < n or orb.abs_max >= 1.0:
        raise ValueError(f"state0: no stable period-{n} orbit found at {param} = {start} "
                         f"(converged {orb.converged}, |mu|max {orb.abs_max:.4g}, "
                         f"minimal period {orb.minimal_period})")
    sig = orbit_signature(q0, orb.state, n)
    lo, lo_orb = start, orb
    prev = None  # (value, state) before lo: secant predictor
    sgn = 1.0 if stop > start else -1.0
    h = min(step, abs(stop - start))
    while True:
        h = min(h, abs(stop - lo))
        nxt = stop if h == abs(stop - lo) else lo + sgn * h
        guess = lo_orb.state
        if prev is not None:
            guess = guess + (lo_orb.state - prev[1]) * ((nxt - lo) / (lo - prev[0]))
        ok, why, o, s = _persistence(system, param, nxt, guess, n, sig, shoot_kw)
        if not ok and prev is not None:  # the secant may overshoot near a fold
            ok, why, o, s = _persistence(system, param, nxt, lo_orb.state, n, sig, shoot_kw)
        if ok:
            prev = (lo, lo_orb.state)
            lo, lo_orb = nxt, o
            if nxt == stop:
                gap = grazing_gap(system.with_param(param, lo), lo_orb.state, n)
                return Bifurcation(param, math.nan, (lo, lo), BifurcationKind.NONE,
                                   f"the orbit persists up to {param} = {stop}", lo_orb,
                                   None, sig, sig, gap)
            h = min(2.0 * h, step)
        elif h <= tol:
            hi, hi_why, hi_orb, hi_sig = nxt, why, o, s
            break
        else:
            h = 0.5 * h if 0.5 * h > tol else tol
    gap = grazing_gap(system.with_param(param, lo), lo_orb.state, n)
    kind, detail, at_grazing = _kind(hi_why, lo_orb, hi_orb, sig, hi_sig, gap, tol)
    return Bifurcation(param, 0.5 * (lo + hi), (lo, hi), kind, detail, lo_orb, hi_orb, sig,
                       hi_sig, gap, at_grazing)
