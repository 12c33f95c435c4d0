"""What the orbit hunt records of each periodic orbit: :class:`FoundOrbit`, its
existence and stability intervals (:class:`Extent`) and the result of a hunt
(:class:`OrbitHunt`); and how an orbit is described once found (:func:`describe_orbit`):
its cycle at a canonical phase, Floquet multipliers, impacts per period and contact arcs;
and the text table of a hunt's orbits (:func:`orbit_table`, what ``vibimpact orbits``
prints).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import math

import numpy as np

from ..base._text import count
from ..analysis.bifurcation import CONTINUATION_SOLVER
from ..analysis.impacts import contact_arcs
from ..analysis.shooting import shoot_periodic_orbit
from ..core.run import Status

__all__ = ["Extent", "FoundOrbit", "OrbitHunt", "describe_orbit", "canonical_cycle",
           "orbit_label", "orbit_table", "interval_text"]


@dataclass(frozen=True)
class Extent:
    """Where a periodic orbit exists and where it is stable, in the forcing frequency.

    From the pseudo-arclength continuation of the orbit both ways from the hunt's value
    (:func:`vibimpact.orbits.orbit_extent`), followed on each side up to its first
    turning point (a fold: past it the branch is another orbit) or to where the
    continuation stopped.

    Attributes
    ----------
    lo, hi : float
        The interval in which the orbit exists (as far as it was followed).
    lo_reason, hi_reason : str
        Why it ends there: ``"fold (turning point)"``, ``"end of the window"`` or the
        continuation's own reason (a step below its minimum, an integration that
        stopped, ``max_points``).
    stable : tuple of (float, float)
        The sub-intervals in which it is stable (every ``|mu| < 1``), in increasing
        order; their ends inside ``(lo, hi)`` are stability changes (``|mu|max - 1``
        interpolated between two branch points).
    values : ndarray, shape (k,)
        The branch points' parameter, increasing, from ``lo`` to ``hi``.
    stable_points : ndarray of bool, shape (k,)
    impacts : ndarray of int, shape (k,)
        Impacts per period at each branch point (-1: not counted).
    abs_max : ndarray, shape (k,)
        ``|mu|max`` at each branch point.
    same_impacts : (float, float)
        The interval about the hunt's value in which the impacts per period stay as
        there (between the neighbouring grazings, to a branch step).
    """

    lo: float
    hi: float
    lo_reason: str
    hi_reason: str
    stable: tuple
    values: np.ndarray = field(repr=False)
    stable_points: np.ndarray = field(repr=False)
    impacts: np.ndarray = field(repr=False)
    abs_max: np.ndarray = field(repr=False)
    same_impacts: tuple = (math.nan, math.nan)


@dataclass(frozen=True)
class FoundOrbit:
    """A periodic orbit of the stroboscopic map found by the hunt.

    Attributes
    ----------
    period : int
        Minimal period in forcing periods.
    cycle : ndarray, shape (period, d)
        Its stroboscopic points, from the canonical phase (the point with the largest
        first state variable) on.
    multipliers : ndarray of complex, shape (d,)
        Floquet multipliers of ``P^period``, by decreasing modulus.
    stable : bool
        Every ``|mu| < 1``.
    impacts : int
        Impacts (contact entries) per period; 0 for a model without a contact, -1
        where the run over the cycle stopped.
    n_arcs : int
        Contact arcs the impacts fall on (:func:`vibimpact.analysis.contact_arcs`).
    arcs : str
        Their words (``"bottom half"``, ``"2 small arcs"``, ``"none"``; ``""`` for a
        model without a contact).
    residual : float
        ``max |P^period(x) - x|`` at ``cycle[0]``.
    found_as : int
        The period ``n`` of the shooting that converged to it (a multiple of
        ``period``).
    seed : int
        Index of the seed whose trajectory gave the start (user seeds first).
    extent : Extent or None
        Existence and stability intervals (None: not continued).
    contact : bool
        The model has a contact (without one, the label leaves the impacts out).
    permanent : bool
        No impact, and in contact throughout (e.g. the built-in rotor rolling or
        whirling on its retainer): labelled "permanent contact", as a sweep labels it.
    """

    period: int
    cycle: np.ndarray = field(repr=False)
    multipliers: np.ndarray = field(repr=False)
    stable: bool
    impacts: int
    n_arcs: int
    arcs: str
    residual: float
    found_as: int
    seed: int
    extent: Extent | None = None
    contact: bool = True
    permanent: bool = False

    @property
    def state(self):
        """The orbit's point at the canonical phase, shape (d,)."""
        return self.cycle[0]

    @property
    def abs_max(self):
        """``|mu|max``."""
        return float(np.abs(self.multipliers).max())

    @property
    def label(self):
        """E.g. ``"P6, 8 impacts, unstable"``."""
        return orbit_label(self.period, self.impacts if self.contact else -1, self.stable,
                           self.permanent)


@dataclass(frozen=True)
class OrbitHunt:
    """The result of :func:`vibimpact.orbits.hunt_orbits`.

    Attributes
    ----------
    orbits : tuple of FoundOrbit
        By period, then impacts per period, then canonical first state variable.
    param : str
        The forcing frequency's name (``"eta"`` for the built-in rotor).
    value : float
        Its value, where the orbits were hunted.
    periods : tuple of int
        Periods shot for.
    seeds : ndarray, shape (k, d)
        Every seed (the user's first, then the random ones).
    n_user : int
        User seeds among ``seeds``.
    random_seed : int
        Seed of the random generator.
    counts : dict of str -> int
        ``shots`` (Newton runs), ``converged``, ``duplicates`` (converged onto an orbit
        already found), ``known`` (starts skipped next to an orbit already found),
        ``failed`` (Newton did not converge), ``diverged_seeds`` (seeds whose
        trajectory diverged: the state left the solver's bound or became non-finite),
        ``failed_seeds`` and ``failed_shots`` (seed trajectories and Newton runs whose
        integration failed: the solver could not go on; no orbit comes of them).
    settings : dict
        The hunt's settings (transient, record, starts, max_return, max_iter, tol,
        window).
    timings : dict of str -> float
        Seconds spent hunting (``hunt_s``) and continuing (``continuation_s``).
    failure : str
        The solver's reason for the first failed integration ("" when none failed).
    """

    orbits: tuple
    param: str
    value: float
    periods: tuple
    seeds: np.ndarray = field(repr=False)
    n_user: int
    random_seed: int
    counts: dict
    settings: dict
    timings: dict
    failure: str = ""

    def failed_note(self) -> str | None:
        """The warning about the integrations that failed (seeds and Newton runs, with
        the solver's first reason), or None when none did."""
        seeds = int(self.counts.get("failed_seeds", 0))
        shots = int(self.counts.get("failed_shots", 0))
        if not seeds and not shots:
            return None
        parts = [f"{seeds} of {self.seeds.shape[0]} seeds"] if seeds else []
        parts += [f"{shots} of {self.counts.get('shots', 0)} Newton runs"] if shots else []
        return (f"{' and '.join(parts)} failed to integrate ({self.failure}); no orbit "
                "comes of them (counts failed_seeds, failed_shots)")

    def table(self) -> list[str]:
        """Lines of a text table of the orbits found (what ``vibimpact orbits``
        prints)."""
        return orbit_table(self)


def orbit_label(period, impacts, stable, permanent=False):
    """``"P6, 8 impacts, unstable"`` (impacts left out when not counted; ``"permanent
    contact"`` for an orbit without impacts that stays in contact throughout)."""
    parts = [f"P{int(period)}"]
    if permanent and impacts == 0:
        parts.append("permanent contact")
    elif impacts >= 0:
        parts.append(count(int(impacts), "impact"))
    parts.append("stable" if stable else "unstable")
    return ", ".join(parts)


def canonical_cycle(cycle):
    """``cycle`` rotated to start at its point with the largest first state variable
    (ties: the earlier), so that an orbit met at any phase gets the same rows."""
    k = int(np.argmax(cycle[:, 0]))
    return np.roll(cycle, -k, axis=0)


def _impacts_and_arcs(system, x, m):
    """``(impacts, n_arcs, arcs words, permanent)`` of the period-``m`` orbit through
    ``x``; ``permanent``: no impact, in contact throughout (no contact switch, starting
    inside, as a sweep point's contact code says it)."""
    contact = system.model.contact
    if contact is None:
        return 0, 0, "", False
    run = system.simulate(periods=m, state0=x,
                          solver=system.settings(**CONTINUATION_SOLVER))
    if run.status is not Status.OK:
        return -1, 0, "", False
    arcs = contact_arcs(run)
    inside = bool(contact.penetration(np.asarray(x, float)[None, :], system.p)[0] > 0.0)
    permanent = run.impacts.size == 0 and inside and \
        not np.any(run.events["which"] == contact.switch)
    return int(run.impacts.size), int(arcs.n_arcs), arcs.summary, bool(permanent)


def describe_orbit(system, orb, seed, tol):
    """A :class:`FoundOrbit` of a converged shooting ``orb`` (of period ``orb.n``),
    its cycle of minimal period at the canonical phase; None when the orbit cannot be
    confirmed at its minimal period (the shooting over ``m`` periods does not converge
    at once)."""
    m = int(orb.minimal_period)
    cycle = canonical_cycle(orb.cycle[:m])
    if m == orb.n:
        again = orb if np.array_equal(cycle[0], orb.state) else \
            shoot_periodic_orbit(system, cycle[0], m, tol=tol, max_iter=3)
    else:  # the multipliers of P^m, not of P^n
        again = shoot_periodic_orbit(system, cycle[0], m, tol=tol, max_iter=3)
    if not again.converged or again.minimal_period != m:
        return None
    cycle = canonical_cycle(again.cycle[:m])
    impacts, n_arcs, arcs, permanent = _impacts_and_arcs(system, cycle[0], m)
    return FoundOrbit(m, cycle, again.multipliers, again.stable, impacts, n_arcs, arcs,
                      float(again.residual), int(orb.n), int(seed),
                      contact=system.model.contact is not None, permanent=permanent)


def interval_text(pairs):
    """``"1.05-1.062, 1.07-1.08"``; ``"-"`` for none."""
    return ", ".join(f"{a:.5g}-{b:.5g}" for a, b in pairs) or "-"


def orbit_table(hunt: OrbitHunt) -> list[str]:
    """One header and one line per orbit: label, arcs, ``|mu|max``, existence and
    stability intervals (when continued), and a last line with the counts."""
    p = hunt.param
    head = ("#", "orbit", "arcs", "|mu|max", f"exists in {p}", f"stable in {p}",
            "ends (low / high)")
    rows = []
    for i, o in enumerate(hunt.orbits):
        e = o.extent
        rows.append((str(i), o.label, o.arcs or "-", f"{o.abs_max:.4g}",
                     "-" if e is None else interval_text([(e.lo, e.hi)]),
                     "-" if e is None else interval_text(e.stable),
                     "-" if e is None else f"{e.lo_reason} / {e.hi_reason}"))
    widths = [max(len(r[j]) for r in rows + [head]) for j in range(len(head))]
    fmt = "  ".join(f"{{:{w}s}}" for w in widths)
    lines = [fmt.format(*head).rstrip()] + [fmt.format(*r).rstrip() for r in rows]
    c = hunt.counts
    lines.append(f"{len(hunt.orbits)} orbits at {p} = {hunt.value:g} from "
                 f"{hunt.seeds.shape[0]} seeds ({hunt.n_user} given, "
                 f"{hunt.seeds.shape[0] - hunt.n_user} random, seed {hunt.random_seed}); "
                 f"{c['shots']} Newton runs, {c['converged']} converged, "
                 f"{c['known']} starts next to known orbits skipped")
    return lines
