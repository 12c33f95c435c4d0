"""What each figure of a sweep needs from its dataset, and the one-line refusal when the
dataset lacks it.

A figure drawn from a sweep that did not run the analysis it shows would be wrong
without an error: a Lyapunov plot of a sweep without the ``lyapunov`` analysis shows
only the few exponents the settling measured, an interval map of a sweep without a
chaos test labels every chaotic band "unsettled".  :func:`missing` says, from the
sweep's recorded settings (its ``analyses``), what a figure kind lacks;
:func:`require` raises it as a ``ValueError``, and the command line
(``vibimpact plot``) turns the same answer into its one line.  The plots draw the labels
the dataset holds (:func:`vibimpact.intervals`); none re-derives one.
"""
from __future__ import annotations

import json

import numpy as np

__all__ = ["NEEDS", "missing", "require", "recorded_analyses"]

#: figure kind -> the needs ``(analyses, what, variables, where)``: one of ``analyses``
#: must have run (or, for a dataset that records no settings, one of ``variables`` be
#: finite somewhere) at the points ``where`` ("any": every sweep; "periodic",
#: "non-periodic": only when the sweep has such points)
NEEDS: dict[str, tuple[tuple[tuple[str, ...], str, tuple[str, ...], str], ...]] = {
    "response": ((("response",), "response data (X_m)", ("X_m", "Y_m"), "any"),),
    "bifurcation": ((("poincare",), "Poincare points", ("poincare_X",), "any"),),
    "poincare": ((("poincare",), "Poincare points", ("poincare_X",), "any"),),
    "lyapunov": ((("lyapunov",), "Lyapunov exponents of its non-periodic points",
                  ("lyapunov",), "non-periodic"),
                 (("floquet",), "Floquet exponents of its periodic points",
                  ("floquet_exponent",), "periodic")),
    "intervals": ((("lyapunov", "test01"), "chaos test of its non-periodic points (they "
                   "would all read 'unsettled')", ("lyapunov", "k01"), "non-periodic"),),
}


def recorded_analyses(ds) -> set[str] | None:
    """The analyses the sweep ``ds`` ran (its ``settings`` attribute), or None when it
    records none (a file of another tool)."""
    try:
        got = json.loads(str(ds.attrs["settings"])).get("analyses")
    except (KeyError, ValueError, AttributeError):
        return None
    return None if not isinstance(got, str) else {a for a in got.split(",") if a}


def _points(ds, where):
    """Whether the sweep has points of kind ``where`` (:data:`NEEDS`)."""
    from ..analysis.classify import Label
    from ..points.point import REGIME_CODES

    if where == "any":
        return True
    reg = np.asarray(ds["regime"].values) if "regime" in ds else np.zeros(0)
    periodic = reg == REGIME_CODES[Label.PERIODIC]
    if where == "periodic":
        return bool(periodic.any())
    other = np.isin(reg, [REGIME_CODES[x] for x in
                          (Label.QUASIPERIODIC, Label.CHAOTIC, Label.UNSETTLED)])
    return bool(other.any())


def _finite(ds, names):
    return any(n in ds and np.isfinite(np.asarray(ds[n].values, dtype=float)).any()
               for n in names)


def missing(ds, kind: str) -> tuple[str, str] | None:
    """``(what, analysis to add)`` that the figure ``kind`` lacks in the sweep ``ds``,
    or None when it has what it draws (kinds outside :data:`NEEDS` need nothing)."""
    asked = recorded_analyses(ds)
    if kind == "intervals" and asked is None:
        return None  # labels of another tool's file: drawn as they are
    for analyses, what, names, where in NEEDS.get(kind, ()):
        if not _points(ds, where):
            continue
        ran = _finite(ds, names) if asked is None else bool(asked & set(analyses))
        if not ran or (where == "any" and _decided(ds) and not _finite(ds, names)):
            return what, analyses[0]
    return None


def _decided(ds):
    """Whether some point of the sweep was decided (neither diverged nor not computed:
    a sweep whose every point diverged has nothing to draw but its labels, and draws
    empty axes, as its file says)."""
    from ..analysis.classify import Label
    from ..points.point import REGIME_CODES

    reg = np.asarray(ds["regime"].values) if "regime" in ds else np.zeros(0)
    return bool(np.any((reg != REGIME_CODES[Label.DIVERGED]) & (reg != 0)))


def require(ds, kind: str) -> None:
    """ValueError, in one line, when the sweep ``ds`` lacks what the figure ``kind``
    draws: what is missing and the analysis to add (``vi.sweep(..., analyses=...)``;
    ``--analyses`` on the command line)."""
    gap = missing(ds, kind)
    if gap is None:
        return
    what, analysis = gap
    asked = recorded_analyses(ds)
    if asked is not None and analysis in asked:
        raise ValueError(f"the sweep has no {what} to draw: none of its points has a "
                         "finite value")
    raise ValueError(f"the sweep has no {what}: sweep with analyses including "
                     f"{analysis!r} (--analyses on the command line)")
