"""Analysers: verbs over arrays (Poincaré points, impact logs, Jacobians, time series).

===============================  ==========================================================
:func:`poincare_section`         stroboscopic samples of a run, shape (m, n)
:func:`impact_map`               the state at each contact entry, shape (k, n)
:func:`detect_period`            smallest ``n`` with ``x[k+n] = x[k]``; 0 if none
:func:`impact_count`             contacts per forcing period and per motion period
:func:`contact_arcs`             contact angles grouped into arcs on the obstacle
:func:`impact_statistics`        impact speeds, penetrations, contact durations
:func:`lyapunov_spectrum`        variational equations + saltation matrices (Benettin/QR)
:class:`Averaging`               how long the Lyapunov estimates integrate and average
:func:`largest_lyapunov`         two-trajectory estimate (independent check)
:func:`lyapunov_from_jacobians`  QR method for any map
:func:`lyapunov_from_series`     nolds (Rosenstein) on a series, a cross-check only
:func:`floquet_lyapunov`         exact exponents ln|mu|/T of a periodic orbit (shooting)
:func:`strobe_map_jacobian`      finite-difference Jacobian of the stroboscopic map
:func:`contraction_rate`         how fast stroboscopic points settle (linear map of the
                                 steps)
:func:`torus_evidence`           non-contracting, recurring Poincaré points
                                 (quasi-periodicity)
:func:`test01`                   Gottwald--Melbourne 0-1 test for chaos
:func:`classify`                 -> :class:`Regime` (PERIODIC n, QUASIPERIODIC, CHAOTIC,
                                 DIVERGED, UNSETTLED)
:func:`extrapolate_limit`        limit of a converging map iteration (minimal polynomial
                                 extrapolation)
:func:`monodromy`                Jacobian of the n-fold stroboscopic map (variational eqs.)
:func:`shoot_periodic_orbit`     period-n orbit by Newton shooting, with Floquet multipliers
:func:`floquet_multipliers`      eigenvalues of a monodromy matrix, by decreasing modulus
:func:`locate_bifurcation`       where and how a stable orbit stops persisting in a
                                 parameter
:func:`continue_orbit`           pseudo-arclength continuation of a periodic orbit
:class:`Steps`                   its step controls
:func:`refine_stability_change`  narrow where a branch changes stability, by bisection
:func:`refine_grazing`           narrow where a branch's impacts per period change
                                 (a grazing), by bisection
===============================  ==========================================================

Every analyser of a model's trajectories (Lyapunov exponents, shooting, monodromy,
continuation, classification of a parameter point) takes a :class:`vibimpact.System`
first: model, parameters and solver settings in one value.
"""
from .chaos01 import test01
from .extrapolation import extrapolate_limit
from .classify import DEFAULT_RULE, DecisionRule, Label, Regime, classify
from .exponents import Averaging
from .impacts import (ContactArcs, ImpactCount, ImpactStatistics, contact_arcs,
                      impact_count, impact_statistics)
from .lyapunov import (LyapunovResult, floquet_lyapunov, largest_lyapunov,
                       lyapunov_from_jacobians, lyapunov_from_series, lyapunov_spectrum,
                       strobe_map_jacobian)
from .settling import Contraction, TorusEvidence, contraction_rate, torus_evidence
from .period import detect_period, impact_map, poincare_section
from .shooting import (Monodromy, PeriodicOrbit, floquet_exponents, floquet_multipliers,
                       monodromy, shoot_periodic_orbit)
from .continuation import (Bifurcation, Branch, Grazing, StabilityChange, StartFailed,
                           Steps, continue_orbit, locate_bifurcation, refine_grazing,
                           refine_stability_change)
from .branch_switch import period_doubling_point, switch_branch
from .two_parameter import BifurcationCurve, continue_bifurcation, signed_gap

__all__ = [
    "ContactArcs", "DEFAULT_RULE", "DecisionRule", "ImpactCount", "ImpactStatistics",
    "Label", "LyapunovResult", "Regime", "classify", "contact_arcs",
    "detect_period", "extrapolate_limit", "impact_count", "impact_map", "impact_statistics",
    "largest_lyapunov", "lyapunov_from_jacobians", "lyapunov_from_series",
    "lyapunov_spectrum", "poincare_section", "strobe_map_jacobian", "test01",
    "Bifurcation", "Branch", "Monodromy", "PeriodicOrbit", "continue_orbit",
    "floquet_exponents", "floquet_multipliers", "locate_bifurcation", "monodromy",
    "shoot_periodic_orbit", "floquet_lyapunov", "Contraction", "TorusEvidence",
    "contraction_rate", "torus_evidence", "Averaging", "Steps", "refine_stability_change",
    "StabilityChange", "StartFailed", "Grazing", "refine_grazing",
    "switch_branch", "period_doubling_point", "BifurcationCurve", "continue_bifurcation",
    "signed_gap",
]

