"""The paper's claims as data, and their automated check on sweeps.

Every statement of Půst & Kozánek about a frequency interval ("chaos in η ∈ (1.21, 1.29)",
"period 3 with 8 impacts near η = 1.40", ...) is one :class:`Claim`.  :func:`match_points`
says which grid points of a sweep show the claimed kind of motion, :func:`detect` finds the
detected interval nearest to the claim and :func:`score` measures the agreement (a Jaccard
index of grid points), which is also the objective of the calibration of ``B`` and ``Ec``
(``analyses/paper/calibrate.py``).

Kinds of motion a claim can name (``Claim.motion``):

``"irregular"``
    The paper's "chaos": impacting motion without a period up to the detector's maximum,
    i.e. our *chaotic*, *quasi-periodic*, *periodic (long period)* and *unsettled* labels
    (an impacting motion no test decided within its budget).  The paper
    judged the kind of motion from response curves and X-Y trajectories, on which these
    look alike; the report names which of our labels make up a detected interval.
``"periodic"``
    A periodic orbit, with ``period`` (forcing periods) and ``impacts`` (per motion period)
    when the claim gives them.
``"impactless"``
    Motion without contact.

References
----------
L. Půst, J. Kozánek, "Vibrations of rotor supported in magnetic bearings with impacts",
Institute of Thermomechanics AS CR (the paper of this project).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MOTIONS = ("irregular", "periodic", "impactless")


@dataclass(frozen=True)
class Claim:
    """One statement of the paper about a frequency interval.

    Attributes
    ----------
    key : str
        Short identifier, e.g. ``"fig8-chaos"``.
    preset : str
        The preset (figure) it is about.
    statement : str
        The paper's words (abridged).
    motion : {"irregular", "periodic", "impactless"}
    lo, hi : float
        The paper's interval of eta (``lo == hi`` for a claim "near eta").
    period, impacts : int, optional
        Period (forcing periods) and impacts per motion period, when stated.
    arcs : str, optional
        Where the impacts load the retainer ("bottom half", "whole circle",
        "2 small arcs"), checked on the X-Y trajectory by the paper report.
    impacting : bool
        A periodic claim is about impacting motion (the paper's figures 8-11 are about
        motion with impacts; "simple periodic motion" there hits the retainer).
    near : bool
        The paper's bound is approximate ("near eta = 1.40"): the detected interval may
        start up to :data:`NEAR` away.
    weight : float
        Weight in the calibration objective (0: reported, not fitted).
    multi : bool
        Periodic with any period >= 2 (set by :meth:`relaxed`).
    direction : {"up", "down"}, optional
        Only this sweep direction is compared (a jump off the impacting branch is a claim
        about the branch reached from below, the up sweep); both when None.

    A claim with ``lo == hi`` and not ``near`` is a *one-speed* claim (:attr:`at_speed`):
    the paper shows a motion at one speed and says nothing of the speeds around it, so
    it is scored as that motion at that speed, not as an interval.
    """

    key: str
    preset: str
    statement: str
    motion: str
    lo: float
    hi: float
    period: int | None = None
    impacts: int | None = None
    arcs: str | None = None
    impacting: bool = True
    near: bool = False
    weight: float = 1.0
    multi: bool = False
    direction: str | None = None

    @property
    def at_speed(self):
        """A one-speed claim: the motion at eta = ``lo`` (``lo == hi``, not ``near``)."""
        return self.lo == self.hi and not self.near

    def relaxed(self):
        """The claim without its period and impact count: any periodic impacting window
        of period >= 2 (the "a subharmonic window is there" part of a P-n claim)."""
        from dataclasses import replace

        return replace(self, period=None, impacts=None, multi=True)


#: version of the scoring rule (:func:`detect_one`), stored with every set of stored
#: scores (``reports/calibration.nc``) so that scores of an older rule are not read as
#: today's: 1 the interval rule for every claim; 2 one-speed claims scored as the motion
#: at that speed (:attr:`Claim.at_speed`)
SCORING_VERSION = 2


def scored_alike(claim, version):
    """Whether a score of ``claim`` stored under rule ``version`` (:data:`SCORING_VERSION`)
    is what today's rule gives."""
    return version >= 2 or not claim.at_speed


#: how far "near eta" may be from the detected start
NEAR = 0.02
#: how far outside a claim a matching point still counts (against the claim) in the score
WINDOW = 0.03
#: credit in the objective for a claimed P-n window (n >= 2) found with another period
RELAXED_CREDIT = 0.5

#: the paper's interval claims, figure by figure
CLAIMS = (
    Claim("fig6-chaos", "fig6", "a new chaotic motion near eta = 1.2 (kh = 40)",
          "irregular", 1.2, 1.2, near=True, weight=0.5),
    Claim("fig8-AB", "fig8", "eta = 1.185: two bottom impacts A, B (periodic)",
          "periodic", 1.185, 1.185, period=1, impacts=2, arcs="2 small arcs, bottom half",
          weight=0.5),
    Claim("fig8-chaos", "fig8", "third contact point C: chaos in eta in (1.21, 1.29)",
          "irregular", 1.21, 1.29, arcs="3 or more arcs"),
    Claim("fig10-chaos-whole", "fig10", "at eta = 1.2 jumps again into chaos, impacts on "
          "the whole surface", "irregular", 1.2, 1.40, arcs="whole circle"),
    Claim("fig10-P3", "fig10", "near eta = 1.40 period 3 with 8 impacts per period "
          "stabilises; chaos again at eta = 1.45", "periodic", 1.40, 1.445, period=3,
          impacts=8, near=True),
    Claim("fig10-chaos-1.45", "fig10", "turns back into chaotic oscillations at eta = 1.45",
          "irregular", 1.45, 1.46, near=True, weight=0.5),
    Claim("fig11-chaos-low", "fig11", "chaotic motion eta = 0.97-1.05", "irregular",
          0.97, 1.045),
    Claim("fig11-P6", "fig11", "eta = 1.05-1.07: period 6 with 8 impacts, bottom half only",
          "periodic", 1.05, 1.07, period=6, impacts=8, arcs="bottom half"),
    Claim("fig11-P1", "fig11", "eta = 1.14-1.19: simple periodic motion, two small loaded "
          "segments", "periodic", 1.14, 1.19, period=1, arcs="2 small arcs"),
    Claim("fig11-chaos", "fig11", "changes into chaos at eta = 1.19", "irregular",
          1.195, 1.295),
    Claim("fig11-P10", "fig11", "period 10 in eta = 1.3-1.33, similar (two small segments)",
          "periodic", 1.30, 1.33, period=10, arcs="2 small arcs"),
    Claim("fig11-impactless", "fig11", "after a narrow chaotic interval the impact motion "
          "jumps to impactless oscillations (our reading: from about 1.36 on)",
          "impactless", 1.36, 1.50, near=True, weight=0.5, direction="up"),
)


#: "irregular impacting motion anywhere": for marking the paper's chaos on any sweep
IRREGULAR = Claim("irregular", "", "chaos", "irregular", 0.0, 0.0)


def claims(preset=None):
    """The claims, all or those of one preset."""
    return tuple(c for c in CLAIMS if preset is None or c.preset == preset)


def match_points(sub, claim):
    """Which points of a one-direction sweep show the claim's kind of motion.

    Parameters
    ----------
    sub : xarray.Dataset
        A sweep of one direction (dim ``eta``) with ``regime``, ``period`` and
        ``impacts_per_period``.
    claim : Claim

    Returns
    -------
    ndarray of bool, shape (n_eta,)
    """
    reg = np.asarray(sub["regime"].values, dtype=int)
    per = np.asarray(sub["period"].values, dtype=int)
    ipp = np.asarray(sub["impacts_per_period"].values, dtype=float)
    impacting = np.isfinite(ipp) & (ipp > 0)
    if claim.motion == "irregular":
        return impacting & ((reg == 2) | (reg == 3) | (reg == 5) | ((reg == 1) & (per == 0)))
    if claim.motion == "impactless":
        contact = np.asarray(sub["contact"].values, dtype=int) if "contact" in sub else 0
        return (reg == 1) & (ipp == 0) & (contact == 0)
    if claim.motion == "periodic":
        ok = (reg == 1) & (per > 0)
        if claim.impacting:
            ok &= impacting
        if claim.period is not None:
            ok &= per == claim.period
        if claim.multi:
            ok &= per >= 2
        if claim.impacts is not None:
            ok &= np.isfinite(ipp) & (np.abs(ipp - claim.impacts) < 0.5)
        return ok
    raise ValueError(f"claim.motion must be one of {', '.join(MOTIONS)}, got {claim.motion!r}")


def _claimed(eta, claim, step):
    lo = claim.lo - (NEAR if claim.near else 0.0)
    hi = claim.hi + (NEAR if claim.near and claim.lo == claim.hi else 0.0)
    return (eta >= lo - 1e-9 * step) & (eta <= hi + 1e-9 * step)


@dataclass(frozen=True)
class Detection:
    """What a sweep shows for one claim (one direction).

    Attributes
    ----------
    direction : str
    start, end : float
        Detected interval: the run of matching points overlapping (or nearest to) the
        claim; NaN if no point in the window matches.
    score : float
        Jaccard index in [0, 1] of the claimed and the matching grid points inside the
        claim widened by :data:`WINDOW`; for a one-speed claim (:attr:`Claim.at_speed`)
        1 when the grid point at the claimed eta (within half a step) shows the motion,
        else 0.
    agree : bool
        Both ends within one sweep step of the paper's (``near`` claims: start within
        :data:`NEAR`, and a matching point at the claimed eta; one-speed claims: the
        motion at the grid point of the claimed eta, whatever the run around it).
    labels : tuple of str
        The distinct labels of the detected interval's points.
    """

    direction: str
    start: float
    end: float
    score: float
    agree: bool
    labels: tuple


def runs(ok):
    """``[(first, last), ...]`` index ranges of the True runs of a boolean array."""
    runs, i = [], 0
    while i < ok.size:
        if ok[i]:
            j = i
            while j + 1 < ok.size and ok[j + 1]:
                j += 1
            runs.append((i, j))
            i = j + 1
        else:
            i += 1
    return runs


def _at_speed(eta, ok, claim, step):
    """Index of the grid point at a one-speed claim's eta (None: not on the grid within
    half a step), and whether it shows the motion."""
    if eta.size == 0:
        return None, False
    k = int(np.argmin(np.abs(eta - claim.lo)))
    if abs(eta[k] - claim.lo) > 0.5 * step * (1 + 1e-6):
        return None, False
    return k, bool(ok[k])


def detect_one(sub, claim, direction="up"):
    """Compare one claim with a one-direction sweep; see :class:`Detection`."""
    eta = np.asarray(sub["eta"].values, dtype=float)
    step = float(np.median(np.diff(eta))) if eta.size > 1 else 1.0
    ok = match_points(sub, claim)
    claimed = _claimed(eta, claim, step)
    window = (eta >= claim.lo - WINDOW) & (eta <= claim.hi + WINDOW)
    found = ok & window
    union = claimed | found
    score = float((claimed & found).sum() / union.sum()) if union.any() else 0.0
    if claim.at_speed:
        k, there = _at_speed(eta, ok, claim, step)
        score = 1.0 if there else 0.0
    near_runs = [(a, b) for a, b in runs(ok) if window[a:b + 1].any()]
    if not near_runs:
        return Detection(direction, np.nan, np.nan, score, False, ())
    centre = 0.5 * (claim.lo + claim.hi)

    def distance(r):
        a, b = eta[r[0]], eta[r[1]]
        overlap = min(b, claim.hi) - max(a, claim.lo)
        return (-overlap, abs(0.5 * (a + b) - centre)) if overlap >= 0 else \
            (0.0, min(abs(a - claim.hi), abs(b - claim.lo)))

    a, b = min(near_runs, key=distance)
    start, end = float(eta[a]), float(eta[b])
    tol = step * (1 + 1e-6)
    if claim.at_speed:
        agree = there
    elif claim.near:
        agree = abs(start - claim.lo) <= NEAR + tol and bool(ok[claimed].any())
    else:
        agree = abs(start - claim.lo) <= tol and abs(end - claim.hi) <= tol
    labels = tuple(dict.fromkeys(str(x) for x in sub["label"].values[a:b + 1]))
    return Detection(direction, start, end, score, bool(agree), labels)


def detect(ds, claim):
    """Compare one claim with a sweep, in each of its directions.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`vibimpact.sweep` (any direction).
    claim : Claim

    Returns
    -------
    list of Detection
        One per direction, the best (highest score) first.
    """
    if "direction" in ds.dims:
        subs = [(str(d), ds.sel(direction=d)) for d in ds["direction"].values]
    else:
        subs = [(str(ds.attrs.get("sweep_direction", "up")), ds)]
    if claim.direction is not None:
        subs = [(d, sub) for d, sub in subs if d == claim.direction] or subs
    out = [detect_one(sub, claim, d) for d, sub in subs]
    return sorted(out, key=lambda x: -x.score)


#: a detected interval that does not agree is "partly" there from this score on
PARTLY = 0.5
#: the verdicts of :func:`verdict`
VERDICTS = ("agree", "partly", "disagree")


def verdict(det):
    """The verdict on a claim from its :class:`Detection` (the best direction's).

    ``"agree"`` when the detection agrees; ``"partly"`` when an interval of the claimed
    motion was found whose Jaccard index reaches :data:`PARTLY`; else ``"disagree"``.
    The paper report, the performance report and the tests of the shipped defaults all
    judge by this one rule.
    """
    if det.agree:
        return "agree"
    if np.isfinite(det.start) and det.score >= PARTLY:
        return "partly"
    return "disagree"


def judge(ds, claim):
    """``(verdict, detection)`` of one claim on a sweep: :func:`verdict` of the best
    direction of :func:`detect`."""
    det = detect(ds, claim)[0]
    return verdict(det), det


def claim_score(ds, claim):
    """A claim's score in the calibration objective, in [0, 1].

    The best Jaccard index over the directions; for a claim of a period ``n >= 2``, at
    least :data:`RELAXED_CREDIT` times the Jaccard index of any periodic impacting window
    of period >= 2 (the window is there, with another period).
    """
    s = detect(ds, claim)[0].score
    if claim.motion == "periodic" and (claim.period or 0) >= 2:
        s = max(s, RELAXED_CREDIT * detect(ds, claim.relaxed())[0].score)
    return s


def score(datasets, weights=True):
    """Calibration objective: weighted mean of (1 - :func:`claim_score`) over the claims.

    Parameters
    ----------
    datasets : dict
        Preset name -> sweep dataset; claims of presets not given are skipped.
    weights : bool
        Use :attr:`Claim.weight` (else all claims count once).

    Returns
    -------
    objective : float
        In [0, 1]; 0 means every claimed interval is reproduced point for point.
    per_claim : dict
        Claim key -> :func:`claim_score`.
    """
    per, num, den = {}, 0.0, 0.0
    for c in CLAIMS:
        if c.preset not in datasets:
            continue
        s = claim_score(datasets[c.preset], c)
        per[c.key] = s
        w = c.weight if weights else 1.0
        num += w * (1.0 - s)
        den += w
    return (num / den if den else float("nan")), per
