"""Pure pieces of the calibration of B and Ec: readings, objective, grid refinement.

Nothing here runs a sweep.  A *row* is one up-and-down sweep of the fig8 rotor
(kh = 120, G = 0.3) with a set of contact dampings switched on, at one (B, Ec); its
result is ``{claim key: ClaimResult}`` for every fitted claim (figs 8, 10 and 11).  A
*reading* of the paper's text says which row models each figure; its objective at
(B, Ec) is the weighted mean of 1 - Jaccard over the claims of its figures, and its
count the number of those claims that agree (both ends within one sweep step).

The search over (B, Ec) of one reading is a *landscape*: ``{(B, Ec): (objective,
count)}`` over the pairs evaluated so far.  :func:`propose` refines it around its best
pair (geometric midpoints in B > 0, arithmetic in Ec, B = 0 a candidate of its own) and
extends the grid outward where the best pair lies on its edge; :func:`converged` says
when to stop.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

#: the contact dampings of eq. (5) a figure may switch on
DAMPINGS = ("Bh", "BT", "f")
#: value of a contact damping when on (the paper's figs 9-11)
CONTACT_ON = 0.05
#: the fitted figures and the damping the paper names for each
NAMED = {"fig8": (), "fig10": ("BT",), "fig11": ("f",)}
FIT_PRESETS = tuple(NAMED)
#: the coarse grid: B = 0 and B log-spaced over 0.001-0.1, Ec over 0.02-0.15
COARSE_B = (0.0,) + tuple(float(f"{x:.4g}") for x in np.logspace(-3, -1, 7))
COARSE_EC = tuple(round(x, 5) for x in np.linspace(0.02, 0.15, 6))
#: a refinement stops when the best objective changes by less than this
TOL = 0.01
#: refinements at most
MAX_ITER = 6
#: the grid is not extended below this B (the limit B -> 0+ is then B = 0's business)
B_FLOOR = 1e-5


@dataclass(frozen=True)
class ClaimResult:
    """One claim on one row: Jaccard score in the objective and agreement of its ends."""

    score: float
    agree: bool
    start: float
    end: float


@dataclass(frozen=True)
class Figure:
    """How a reading models one figure.

    Attributes
    ----------
    preset : str
        ``"fig8"``, ``"fig10"`` or ``"fig11"``.
    damp : tuple of str
        The contact dampings switched on (each :data:`CONTACT_ON`), in :data:`DAMPINGS`
        order.
    b_zero : bool
        The figure is computed at B = 0 whatever the reading's B.
    """

    preset: str
    damp: tuple = ()
    b_zero: bool = False


@dataclass(frozen=True)
class Reading:
    """One reading of the paper's text: which row models each fitted figure.

    Attributes
    ----------
    key : str
        Short identifier (``"a"``, ``"b"``, ``"c:BT|f"``, ``"d:fig8"``).
    kind : str
        ``"a"``, ``"b"``, ``"c"`` or ``"d"`` (the issue's lettering).
    text : str
        What the reading says, for the report.
    figures : tuple of Figure
    adoptable : bool
        A candidate for the presets' defaults (covers figs 8, 10 and 11 together).
    """

    key: str
    kind: str
    text: str
    figures: tuple
    adoptable: bool = True


def variant(damp):
    """Name of a set of contact dampings: ``"none"``, ``"BT"``, ``"Bh+BT+f"``, ..."""
    damp = tuple(d for d in DAMPINGS if d in damp)
    return "+".join(damp) if damp else "none"


def damping_values(damp):
    """``{"Bh": ., "BT": ., "f": .}`` of a set of contact dampings."""
    return {d: (CONTACT_ON if d in damp else 0.0) for d in DAMPINGS}


def supersets(named):
    """Every set of :data:`DAMPINGS` that contains ``named``, smallest first.

    Parameters
    ----------
    named : tuple of str

    Returns
    -------
    list of tuple of str
        In :data:`DAMPINGS` order within each set.
    """
    rest = [d for d in DAMPINGS if d not in named]
    out = []
    for k in range(len(rest) + 1):
        for extra in itertools.combinations(rest, k):
            out.append(tuple(d for d in DAMPINGS if d in set(named) | set(extra)))
    return out


def readings():
    """The readings of the paper's text, in report order.

    (a) one contact damping at a time on top of fig8 (the presets today);
    (b) as (a), fig11 at B = 0 ("only dry friction damped the motion");
    (c) every pair (fig10 set, fig11 set) of supersets of the damping each figure names
    ((a) is the pair of the smallest sets, listed under (a) only);
    (d) each figure alone with (a)'s dampings: do the figures want the same (B, Ec)?
    """
    out = [Reading("a", "a", "one contact damping at a time on top of fig8",
                   (Figure("fig8"), Figure("fig10", ("BT",)), Figure("fig11", ("f",)))),
           Reading("b", "b", "as (a), but fig11 at B = 0 ('only dry friction damped "
                   "the motion')", (Figure("fig8"), Figure("fig10", ("BT",)),
                                    Figure("fig11", ("f",), b_zero=True)))]
    for s10 in supersets(NAMED["fig10"]):
        for s11 in supersets(NAMED["fig11"]):
            if s10 == NAMED["fig10"] and s11 == NAMED["fig11"]:
                continue  # that is (a)
            out.append(Reading(f"c:{variant(s10)}|{variant(s11)}", "c",
                               f"fig10 with {{{', '.join(s10)}}}, fig11 with "
                               f"{{{', '.join(s11)}}}",
                               (Figure("fig8"), Figure("fig10", s10),
                                Figure("fig11", s11))))
    for fig in out[0].figures:
        out.append(Reading(f"d:{fig.preset}", "d", f"{fig.preset} alone, dampings of (a)",
                           (fig,), adoptable=False))
    return out


def title(reading):
    """A short title of a reading, for the figure."""
    if reading.kind == "c":
        f10, f11 = reading.figures[1], reading.figures[2]
        return (f"(c) fig10 {{{', '.join(f10.damp)}}}, fig11 {{{', '.join(f11.damp)}}}")
    return {"a": "(a) one contact damping per figure",
            "b": "(b) as (a), fig11 at B = 0"}.get(
        reading.kind, f"(d) {reading.figures[0].preset} alone")


def row_key(fig, B, Ec):
    """The row ``(variant, B, Ec)`` that models ``fig`` at the reading's (B, Ec)."""
    return (variant(fig.damp), 0.0 if fig.b_zero else B, Ec)


def rows_needed(reading, pairs):
    """Rows that evaluating ``reading`` at every (B, Ec) of ``pairs`` needs."""
    return {row_key(f, B, E) for B, E in pairs for f in reading.figures}


def evaluate(reading, B, Ec, rows, claims):
    """Objective and count of agreeing claims of ``reading`` at (B, Ec).

    Parameters
    ----------
    reading : Reading
    B, Ec : float
    rows : dict
        Row key -> ``{claim key: ClaimResult}``.
    claims : sequence of vibimpact.paper.claims.Claim
        The fitted claims (with ``key``, ``preset``, ``weight``).

    Returns
    -------
    (float, int) or None
        None when a row is missing.
    """
    num = den = 0.0
    count = 0
    for fig in reading.figures:
        row = rows.get(row_key(fig, B, Ec))
        if row is None:
            return None
        for c in claims:
            if c.preset != fig.preset:
                continue
            r = row[c.key]
            num += c.weight * (1.0 - r.score)
            den += c.weight
            count += bool(r.agree)
    return (num / den if den else float("nan")), count


def landscape(reading, pairs, rows, claims):
    """``{(B, Ec): (objective, count)}`` of ``reading`` at the pairs whose rows exist."""
    out = {}
    for B, E in pairs:
        v = evaluate(reading, B, E, rows, claims)
        if v is not None:
            out[(B, E)] = v
    return out


def best_pair(land):
    """The pair of least objective; ties: more agreeing claims, then smaller B and Ec."""
    return min(land, key=lambda pr: (land[pr][0], -land[pr][1], pr[0], pr[1]))


def edge_status(land, best=None):
    """Where the best pair lies in each direction of the evaluated grid.

    Only the pairs through the best are looked at: the B values evaluated at its Ec and
    the Ec values evaluated at its B.

    Returns
    -------
    dict
        ``{"B": s, "Ec": s}``, ``s`` one of ``"interior"`` (evaluated neighbours on both
        sides), ``"low"`` or ``"high"`` (on that edge: the grid must be extended there),
        and for B also ``"zero"`` (the best is B = 0, the physical bound: nothing lies
        below it).
    """
    best = best_pair(land) if best is None else best
    B, E = best
    bs = sorted(b for b, e in land if e == E)
    es = sorted(e for b, e in land if b == B)
    if B == 0.0:
        sb = "zero"
    else:
        pos = [b for b in bs if b > 0.0]
        sb = "low" if B == pos[0] else "high" if B == pos[-1] else "interior"
    se = "low" if E == es[0] else "high" if E == es[-1] else "interior"
    return {"B": sb, "Ec": se}


def is_interior(status):
    """The best pair is not on an edge the grid could be extended beyond."""
    return status["B"] in ("interior", "zero") and status["Ec"] == "interior"


def _rb(x):
    return float(f"{x:.4g}")


def _re(x):
    return round(float(x), 5)


def propose(land, b_factor=10 ** (1 / 3), ec_step=0.026, b_floor=B_FLOOR):
    """New pairs that refine ``land`` around its best pair.

    B (> 0) gets the geometric midpoints with its evaluated neighbours at the best's Ec
    and, on an edge, the next value outward (x or / ``b_factor``; not below ``b_floor``);
    B = 0 gets no new B.  Ec gets the arithmetic midpoints with its neighbours at the
    best's B and, on an edge, ``ec_step`` outward (halfway to 0 below).  The new pairs
    are the cross product of the best's B and its new B values with the best's Ec and
    its new Ec values, less the pairs already evaluated.

    Returns
    -------
    list of (float, float)
        Sorted; empty when nothing new is left to try.
    """
    B, E = best_pair(land)
    bs = sorted(b for b, e in land if e == E and b > 0.0)
    es = sorted(e for b, e in land if b == B)
    nb, ne = {B}, {E}
    if B > 0.0:
        i = bs.index(B)
        if i > 0:
            nb.add(_rb(math.sqrt(bs[i - 1] * B)))
        elif B / b_factor >= b_floor:
            nb.add(_rb(B / b_factor))
        if i < len(bs) - 1:
            nb.add(_rb(math.sqrt(bs[i + 1] * B)))
        else:
            nb.add(_rb(B * b_factor))
    j = es.index(E)
    if j > 0:
        ne.add(_re(0.5 * (es[j - 1] + E)))
    else:
        ne.add(_re(E - ec_step if E - ec_step > 0.0 else 0.5 * E))
    if j < len(es) - 1:
        ne.add(_re(0.5 * (es[j + 1] + E)))
    else:
        ne.add(_re(E + ec_step))
    return sorted((b, e) for b in nb for e in ne if (b, e) not in land)


def converged(history, status, tol=TOL):
    """Whether a reading's search has converged.

    Parameters
    ----------
    history : sequence of float
        The best objective after the coarse grid and after each refinement.
    status : dict
        :func:`edge_status` of the best pair now.
    tol : float

    Returns
    -------
    bool
        At least one refinement, the last one changed the best objective by less than
        ``tol``, and the best pair is interior (:func:`is_interior`).
    """
    return (len(history) >= 2 and abs(history[-1] - history[-2]) < tol
            and is_interior(status))


def rank_key(objective, count):
    """Sort key of readings: most agreeing claims first, then least objective."""
    return (-count, objective)
