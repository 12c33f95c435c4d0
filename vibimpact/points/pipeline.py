"""One parameter point, classified: the sweeps' point pipeline for any :class:`System`.

:func:`classify_params` runs :func:`vibimpact.points.point.analyse_point`, the pipeline
every sweep and map point goes through (transient ended early on a converged orbit,
extrapolation jumps, shooting on slowly settling transients, the record, the Lyapunov
exponent and the 0-1 test only where no period is found, the torus test), and returns
its :class:`~vibimpact.analysis.Regime`.  So a point classified alone gets the label a
sweep gives it from the same state.

It uses :mod:`vibimpact.analysis` and the point pipeline beside it; it is exported as
``vibimpact.classify_params`` and ``vibimpact.points.classify_params``.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import math
from dataclasses import fields, replace

from ..base import _validate as _v
from ..analysis.classify import Label, Regime
from ..core.system import as_system
from .point import ANALYSES, REGIME_CODES, SweepSettings, analyse_point

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

    from ..core.system import System
    from .point import PointResult

__all__ = ["classify_params", "CLASSIFY_ANALYSES", "CLASSIFY_SETTINGS"]

#: what :func:`classify_params` computes by default
CLASSIFY_ANALYSES = ("period", "impacts", "lyapunov", "test01")
#: its settings by default: a sweep point's (:class:`~vibimpact.SweepSettings`)
CLASSIFY_SETTINGS = SweepSettings(analyses=CLASSIFY_ANALYSES)

_LABELS = {code: label for label, code in REGIME_CODES.items()}
_FIELDS = {f.name for f in fields(SweepSettings)}


def _settings(settings, changes):
    """The point settings: ``settings`` (or :data:`CLASSIFY_SETTINGS`) with ``changes``."""
    st = CLASSIFY_SETTINGS if settings is None else settings
    if not isinstance(st, SweepSettings):
        raise ValueError(f"settings must be a vibimpact.SweepSettings, got "
                         f"{type(st).__name__}")
    unknown = sorted(set(changes) - _FIELDS)
    if unknown:
        raise ValueError(f"{unknown[0]} is not a setting of the point pipeline (one of "
                         f"{', '.join(sorted(_FIELDS))})")
    st = replace(st, **changes)
    if st.lyapunov not in ("auto", "always"):
        raise ValueError(f"lyapunov must be 'auto' or 'always', got {st.lyapunov!r}")
    st = replace(st, analyses=_v.names("analyses", st.analyses, ANALYSES))
    _v.count("transient_max", st.transient_max, 0)
    for name in ("record", "lyap_min", "lyap_max"):
        _v.count(name, getattr(st, name), 1)
    return replace(st, analyses=tuple(a for a in ANALYSES
                                      if a in st.analyses or a == "period"))


def classify_params(system: System, state0: ArrayLike | None = None, *,
                    settings: SweepSettings | None = None, guess: ArrayLike | None = None,
                    **changes) -> tuple[Regime, PointResult]:
    """Classify one parameter point by the sweeps' point pipeline.

    Parameters
    ----------
    system : System
        Model, parameters and solver settings; a setting left None takes the point
        pipeline's (``settings.method``, ``rtol``, ``atol``: DOP853, 1e-8, 1e-11).
    state0 : array_like, shape (n,), optional
        Initial state (rest by default); a continuation passes the previous point's
        ``final_state``.
    settings : SweepSettings, optional
        What the point computes and how long it integrates; by default
        :data:`CLASSIFY_SETTINGS`, a sweep point's defaults with the analyses "period",
        "impacts", "lyapunov" and "test01" (a transient of at most 200 periods, ended as
        soon as the stroboscopic points repeat, then 128 periods recorded, or 8 on a
        periodic orbit).
    guess : ndarray, optional
        A predicted point of a period-1 orbit (see
        :func:`vibimpact.points.point.analyse_point`).
    **changes
        Fields of :class:`~vibimpact.SweepSettings` to change (``transient_max=500``,
        ``record=300``, ``lyapunov="always"``, ``lyap_target=1e-3``, ``rule=...``).

    Returns
    -------
    regime : Regime
        ``impacting`` and ``impacts_per_period`` are None and NaN for a model without a
        contact (:attr:`vibimpact.models.Model.contact` None) or where the impacts were not
        counted.
    result : PointResult
        The point's full result, as a sweep stores it
        (:class:`~vibimpact.points.point.PointResult`: ``period``, ``final_state``,
        ``reason``, ...).

    Notes
    -----
    The Lyapunov exponent (the largest, per unit ``tau``) is computed only where no period
    is found (``lyapunov="auto"``; ``"always"`` computes it everywhere), from the end of
    the record, by :func:`~vibimpact.analysis.lyapunov_spectrum` with
    ``Averaging(transient=0, min_periods=lyap_min, max_periods=lyap_max,
    target_stderr=lyap_target, align=20, decisive=(rule.zero / T, rule.z))``: 100 to 600
    periods to a standard error of 3e-3 by default, stopped as soon as its sign is
    settled (``z = 3`` standard errors outside the rule's zero band), the tangent vectors'
    errors tested at :data:`~vibimpact.analysis.exponents.TANGENT_TOL` times the
    tolerances, and the Floquet exponents of a stable orbit returned where the points
    repeat; at the point's solver settings (``rtol = 1e-8`` by default).

    Raises
    ------
    ValueError
        Naming the argument.

    Examples
    --------
    >>> import vibimpact as vi
    >>> from vibimpact.points import classify_params
    >>> lin = vi.System(vi.DuffingParams(delta=0.3, alpha=1.0, beta=0.0, gamma=0.2,
    ...                                  omega=1.3))
    >>> str(classify_params(lin)[0])
    'P1'
    """
    system = as_system(system)
    st = _settings(settings, changes)
    x0 = None if state0 is None else _v.state("state0", state0, system.n_state)
    res = analyse_point(system, x0, st, guess)
    return _regime(res, system), res


def _regime(res, system):
    """The :class:`Regime` of a point's result."""
    label = _LABELS.get(int(res.regime), Label.UNSETTLED)
    ipp = float(res.impacts_per_period)
    impacting = None
    if system.model.contact is None or not math.isfinite(ipp):
        ipp = math.nan
    else:
        impacting = bool(ipp > 0.0)
    conf = float(res.confidence)
    return Regime(label, int(res.period) if label is Label.PERIODIC else 0, impacting,
                  ipp, 1.0 if math.isnan(conf) else conf, float(res.lyapunov),
                  float(res.lyapunov_err), float(res.k01), str(res.reason))
