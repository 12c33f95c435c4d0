"""What the Lyapunov and Floquet analysers share: the result type, the averaging controls
and the default error test of the tangent vectors.

:class:`LyapunovResult` is what :func:`~vibimpact.analysis.lyapunov_spectrum`,
:func:`~vibimpact.analysis.largest_lyapunov`,
:func:`~vibimpact.analysis.lyapunov_from_jacobians` and
:func:`~vibimpact.analysis.floquet_lyapunov` return; :class:`Averaging` says how long the
first two average (transient, alignment, blocks, target error, early stop on the sign).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..base import _validate as _v
from ..core.run import Status

__all__ = ["LyapunovResult", "Averaging", "TANGENT_TOL", "KIND_FLOW", "KIND_FLOW_PHASE"]


@dataclass(frozen=True)
class LyapunovResult:
    """Lyapunov exponents with their standard errors.

    Behaves as the array of exponents (``np.asarray(result)``, ``result[0]``).

    Attributes
    ----------
    exponents : ndarray, shape (m,)
        Per unit of dimensionless time ``tau``, descending; NaN when the run diverged.
    stderr : ndarray, shape (m,)
        Standard error of each exponent from the spread of block estimates (batch means).
    period : float
        Forcing period ``T``; the stroboscopic map's exponents are ``exponents * T``.
    periods : int
        Forcing periods averaged (after the transient and the tangent-vector alignment).
    converged : bool
        The largest exponent's standard error reached the requested target.
    method : str
        "variational", "two-trajectory", "map" or "nolds".
    kind : str
        What the numbers are the exponents of (see the module docstring).
    status : Status
    reason : str
    history : ndarray, shape (n_blocks, m)
        Running estimate after each block (convergence plot); of the QR average also when
        the exponents are Floquet exponents.
    floquet_n : int
        ``n > 0``: ``exponents`` are the Floquet exponents of a period-``n`` orbit (minimal
        period) and ``stderr`` their numerical error; 0: QR averages.
    qr_exponents : ndarray, shape (m,)
        The QR average over ``periods`` periods (NaN if none); ``exponents`` if
        ``floquet_n`` is 0.
    """

    exponents: np.ndarray
    stderr: np.ndarray
    period: float
    periods: int
    converged: bool
    method: str
    kind: str
    status: Status = Status.OK
    reason: str = ""
    history: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    floquet_n: int = 0
    qr_exponents: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def map_exponents(self):
        """Exponents of the stroboscopic map, per forcing period (``exponents * T``)."""
        return self.exponents * self.period

    @property
    def largest(self):
        """The largest exponent (per ``tau``)."""
        return float(self.exponents[0])

    def __array__(self, dtype=None, copy=None):
        return np.asarray(self.exponents, dtype=dtype)

    def __len__(self):
        return len(self.exponents)

    def __getitem__(self, i):
        return self.exponents[i]

    def __iter__(self):
        return iter(self.exponents)


#: the tangent vectors' local errors are tested at this many times the tolerances
TANGENT_TOL = 1e3

KIND_FLOW = ("flow of the non-autonomous state equations, per unit time, without the "
             "forcing phase's zero exponent")
KIND_FLOW_PHASE = ("flow of the autonomous extension (state, forcing phase), per unit time, "
                   "with the phase's zero exponent")


@dataclass(frozen=True)
class Averaging:
    """How long a Lyapunov estimate integrates and averages.

    Parameters
    ----------
    transient : int
        Forcing periods integrated (state only) and discarded before the estimate starts.
    min_periods, max_periods : int
        Forcing periods averaged: at least ``min_periods``, then block by block until the
        largest exponent's standard error is ``<= target_stderr``, at most
        ``max_periods``.
    block : int
        Periods per block (``>= 2``); the standard error is that of the block means
        (batch means).
    target_stderr : float
        Target standard error of the largest exponent, per unit ``tau``.
    align : int
        Periods integrated first and discarded, so that the tangent vectors (or the
        separation) align with the Lyapunov directions.
    decisive : (float, float), optional
        ``(band, z)``: also stop once the largest exponent is at least ``z`` standard
        errors outside ``(-band, band)`` (per unit ``tau``; its sign is settled: what
        sweeps need).  ``converged`` then reports whether ``target_stderr`` was met.

    Raises
    ------
    ValueError
        Naming the offending field.

    Examples
    --------
    >>> from vibimpact.analysis import Averaging
    >>> Averaging(transient=0, max_periods=2000).min_periods
    400
    """

    transient: int = 200
    min_periods: int = 400
    max_periods: int = 20000
    block: int = 50
    target_stderr: float = 2e-3
    align: int = 50
    decisive: tuple | None = None

    def __post_init__(self):
        fix = lambda name, value: object.__setattr__(self, name, value)  # noqa: E731
        fix("transient", _v.count("transient", self.transient, 0))
        fix("align", _v.count("align", self.align, 0))
        fix("block", _v.count("block", self.block, 2))
        fix("min_periods", _v.count("min_periods", self.min_periods, 1))
        fix("max_periods", _v.count("max_periods", self.max_periods, 1))
        if self.max_periods < self.min_periods:
            raise ValueError(f"max_periods must be >= min_periods ({self.min_periods}), "
                             f"got {self.max_periods}")
        fix("target_stderr", _v.positive("target_stderr", self.target_stderr))
        if self.decisive is not None:
            try:
                band, z = (float(v) for v in self.decisive)
            except (TypeError, ValueError):
                raise ValueError(f"decisive must be (band, z), got {self.decisive!r}") \
                    from None
            fix("decisive", (band, z))

    def replace(self, **changes) -> Averaging:
        """A copy with some fields changed."""
        from dataclasses import replace
        return replace(self, **changes)
