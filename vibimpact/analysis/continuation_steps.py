"""The step controls of :func:`vibimpact.analysis.continue_orbit` (:class:`Steps`) and the
smallest step it can resolve from a start (:func:`smallest_step`)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base import _validate as _v

__all__ = ["STEP_ULPS", "Steps", "check_steps", "smallest_step"]


@dataclass(frozen=True)
class Steps:
    """Step controls of :func:`continue_orbit`.

    Parameters
    ----------
    ds, ds_min, ds_max : float
        Initial, smallest and largest arclength step (in the units of ``(x, lambda)``),
        ``newton_tol <= ds_min <= ds <= ds_max`` (a step below the corrector's
        tolerance cannot be told from its error); :func:`continue_orbit` also refuses
        steps below :func:`smallest_step` at its start.
    max_points : int
        Orbits on the branch at most (``>= 2``).
    fd_step : float
        Relative step ``h`` of the finite difference of the map in the parameter:
        central, or, where ``lambda - h`` or ``lambda + h`` lies outside the parameter's
        domain (at or next to a bound such as ``BT = 0``), one-sided of the same second
        order into the domain.
    newton_tol : float
        Corrector tolerance on ``max |G|`` (relative to ``max(1, max |x|)``), and Newton's
        tolerance of the shooting at the start.
    max_newton : int
        Corrector iterations per step.

    Raises
    ------
    ValueError
        Naming the offending field.
    """

    ds: float = 0.005
    ds_min: float = 1e-5
    ds_max: float = 0.02
    max_points: int = 400
    fd_step: float = 1e-6
    newton_tol: float = 1e-9
    max_newton: int = 8

    def __post_init__(self):
        for name in ("ds", "ds_min", "ds_max", "fd_step", "newton_tol"):
            object.__setattr__(self, name, _v.positive(name, getattr(self, name)))
        object.__setattr__(self, "max_points", _v.count("max_points", self.max_points, 2))
        object.__setattr__(self, "max_newton", _v.count("max_newton", self.max_newton, 1))
        if not self.ds_min <= self.ds <= self.ds_max:
            raise ValueError(f"ds must lie between ds_min and ds_max, got ds_min = "
                             f"{self.ds_min:g}, ds = {self.ds:g}, ds_max = {self.ds_max:g}")
        if self.ds_min < self.newton_tol:
            raise ValueError(f"ds_min must be >= newton_tol = {self.newton_tol:g} (a step "
                             f"below the corrector's tolerance cannot be told from its "
                             f"error), got {self.ds_min:g}")


#: a step must exceed this many units in the last place of the largest coordinate of the
#: start ``(x, lambda)``: below it ``start + ds`` is ``start``, or nearly, in floats
STEP_ULPS = 64


def smallest_step(steps, *values):
    """The smallest arclength step resolvable from a start whose coordinates are
    ``values``: the corrector's tolerance ``steps.newton_tol`` relative to
    ``max(1, max |x|)``, and :data:`STEP_ULPS` units in the last place of the largest
    ``|value|``."""
    big = max((abs(float(v)) for v in values), default=0.0)
    return max(steps.newton_tol * max(1.0, big), STEP_ULPS * float(np.spacing(big)))


def check_steps(steps, *values, names=("ds", "ds_min", "ds_max")):
    """ValueError naming the step (``names``: how to call ``ds``, ``ds_min``,
    ``ds_max``) that is below :func:`smallest_step` at a start whose coordinates are
    ``values``."""
    floor = smallest_step(steps, *values)
    named = dict(zip(("ds", "ds_min", "ds_max"), names))
    for field in ("ds_min", "ds", "ds_max"):  # the smallest first
        value, name = getattr(steps, field), named[field]
        if name and value < floor:
            big = max(abs(float(v)) for v in values)
            raise ValueError(f"{name} must be >= {floor:.3g}, the smallest step resolvable "
                             f"at a start of magnitude {big:.6g} (the corrector's tolerance "
                             f"{steps.newton_tol:g} and the float resolution there), got "
                             f"{value:.3g}")
