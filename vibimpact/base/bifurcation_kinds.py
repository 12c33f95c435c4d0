"""The one vocabulary of bifurcations and transitions: :class:`BifurcationKind`.

Every place that names how a periodic orbit or a sweep's motion changes uses it:
:func:`vibimpact.analysis.locate_bifurcation` (:attr:`Bifurcation.kind`),
:func:`vibimpact.analysis.continue_orbit` (:attr:`Branch.bifurcations`), the stability
change of :func:`vibimpact.analysis.refine_stability_change`,
:func:`vibimpact.transition_types` (the ``type`` column, kinds joined by ``" + "``), the
``bifurcation_kind`` flag of a branch file (:mod:`vibimpact.continuation.branches`) and the markers
of :mod:`vibimpact.plotting.branch`.

Each kind has its short name (the enum's value: a ``str``, so ``kind == "fold"`` holds),
its integer ``code`` (stored in branch files; the codes 0 to 4 are those files held before
grazing joined), its ``flag`` (the CF ``flag_meanings`` word), its ``words`` (for reports,
legends and the CLI) and its Floquet ``signature`` where it has one: where the
multiplier of largest modulus leaves the unit circle (``"+1"``, ``"-1"`` or
``"complex"``, as :func:`vibimpact.analysis.shooting.critical_multiplier` says it), None
for the kinds no multiplier names.

Only the standard library is imported here, so that any layer may use it.

References
----------
.. [1] Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., Springer
   (2004), ch. 4.
.. [2] M. di Bernardo, C. J. Budd, A. R. Champneys, P. Kowalczyk, *Piecewise-smooth
   Dynamical Systems*, Springer (2008), ch. 8 (grazing of periodic orbits).
"""
from __future__ import annotations

import enum

__all__ = ["BifurcationKind", "BRANCH_KINDS", "branch_flags", "kinds_in"]


@enum.unique
class BifurcationKind(enum.StrEnum):
    """How a periodic orbit (or a sweep's motion) changes as a parameter moves.

    Attributes (of each member)
    ---------------------------
    value : str
        The short name (``"period doubling"``); the member equals it as a ``str``.
    code : int
        The integer stored in files (``bifurcation_kind`` of a branch file).
    flag : str
        The word of the CF attribute ``flag_meanings`` (no spaces).
    words : str
        The kind in words, for reports, legends and the CLI.
    signature : str or None
        Where the Floquet multiplier of largest modulus leaves the unit circle: ``"+1"``
        (a fold, and a turning point of a branch), ``"-1"`` (period doubling),
        ``"complex"`` (a complex pair: Neimark--Sacker); None where no multiplier crosses
        (grazing: the impacts per period change while every multiplier stays inside the
        unit circle) or the kind is not a local bifurcation of one orbit.

    Examples
    --------
    >>> BifurcationKind.by_multiplier("-1") is BifurcationKind.PERIOD_DOUBLING
    True
    >>> BifurcationKind.from_code(5) is BifurcationKind.GRAZING
    True
    >>> BifurcationKind.FOLD == "fold"
    True
    """

    code: int
    flag: str
    words: str
    signature: str | None

    def __new__(cls, name: str, code: int, flag: str, words: str,
                signature: str | None) -> BifurcationKind:
        member = str.__new__(cls, name)
        member._value_ = name
        member.code = code
        member.flag = flag
        member.words = words
        member.signature = signature
        return member

    #: a stability change whose multipliers fit no kind below
    UNKNOWN = ("?", 0, "unknown", "stability change of unknown kind", None)
    #: the branch's parameter turns (a multiplier passes +1 there)
    TURNING_POINT = ("fold (turning point)", 1, "turning_point", "fold (turning point)",
                     "+1")
    #: a multiplier leaves through +1: the orbit vanishes (with another one)
    FOLD = ("fold", 2, "fold", "fold (μ = +1)", "+1")
    #: a multiplier leaves through -1: a period-2n orbit is born
    PERIOD_DOUBLING = ("period doubling", 3, "period_doubling",
                       "period doubling (μ = −1)", "-1")
    #: a complex pair leaves the unit circle: an invariant torus (quasi-periodic motion)
    NEIMARK_SACKER = ("Neimark-Sacker", 4, "Neimark-Sacker",
                      "Neimark–Sacker (complex pair |μ| = 1)", "complex")
    #: the orbit touches the contact surface with zero normal velocity: its impacts per
    #: period change without any multiplier crossing the unit circle
    GRAZING = ("grazing", 5, "grazing", "grazing (impacts per period change)", None)
    #: the orbit's friction (stick / slip) events change
    STICK_SLIP = ("stick-slip", 6, "stick-slip", "stick-slip (friction events change)",
                  None)
    #: chaos ends where a periodic orbit is born in a fold (type-I intermittency)
    INTERMITTENCY = ("intermittency", 7, "intermittency",
                     "intermittency (periodic orbit born in a fold out of chaos)", None)
    #: a chaotic or quasi-periodic attractor appears, vanishes or changes size with no
    #: local bifurcation of a periodic orbit
    CRISIS = ("crisis", 8, "crisis", "crisis (no local bifurcation)", None)
    #: the motion moved to another, coexisting attractor (no bifurcation)
    COEXISTENCE = ("coexistence", 9, "coexistence",
                   "coexistence (another attractor, no bifurcation)", None)
    #: the same orbit on both sides: nothing happened
    NONE = ("none", 10, "none", "no bifurcation", None)
    #: a transition whose kind was not resolved
    UNRESOLVED = ("unresolved", 11, "unresolved", "transition of unresolved kind", None)

    @classmethod
    def from_code(cls, code: int) -> BifurcationKind:
        """The kind stored as ``code``; ValueError naming ``code`` for an unknown one."""
        for kind in cls:
            if kind.code == int(code):
                return kind
        raise ValueError(f"code: no bifurcation kind has code {code!r}")

    @classmethod
    def by_multiplier(cls, crit: str) -> BifurcationKind:
        """The kind of a stability change whose unstable side's largest multiplier is
        ``crit`` (``"+1"``: :attr:`FOLD`, ``"-1"``: :attr:`PERIOD_DOUBLING`,
        ``"complex"``: :attr:`NEIMARK_SACKER`); :attr:`UNKNOWN` for anything else."""
        return _BY_MULTIPLIER.get(crit, cls.UNKNOWN)


#: the kind a stability change gets from its critical multiplier (the turning point
#: shares +1 with the fold but is found by the parameter turning, not by a multiplier)
_BY_MULTIPLIER = {k.signature: k for k in BifurcationKind
                  if k.signature is not None and k is not BifurcationKind.TURNING_POINT}

#: the kinds a continued branch (and its file's ``bifurcation_kind``) can hold
BRANCH_KINDS = (BifurcationKind.UNKNOWN, BifurcationKind.TURNING_POINT,
                BifurcationKind.FOLD, BifurcationKind.PERIOD_DOUBLING,
                BifurcationKind.NEIMARK_SACKER, BifurcationKind.GRAZING)


def branch_flags() -> tuple[tuple[int, ...], str]:
    """``(flag_values, flag_meanings)`` of a branch file's ``bifurcation_kind``."""
    return (tuple(k.code for k in BRANCH_KINDS), " ".join(k.flag for k in BRANCH_KINDS))


def kinds_in(text: str) -> list[BifurcationKind]:
    """The kinds of a transition type, several joined by ``" + "`` in sweep order
    (``"grazing + period doubling"``); ValueError naming ``text`` for a word that is
    no kind."""
    out = []
    for part in str(text).split(" + "):
        try:
            # a lookup by value (EnumMeta.__call__), not a call of __new__
            out.append(BifurcationKind(part))  # type: ignore[call-arg]
        except ValueError:
            raise ValueError(f"text: {part!r} is no bifurcation kind") from None
    return out
