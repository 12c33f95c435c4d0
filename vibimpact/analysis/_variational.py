"""What the Lyapunov and Floquet analysers share: the result type and the set-up of the
variational equations (model, parameter vector, tableau, kernel options, the tangent
entries' error test).

Private: :mod:`vibimpact.analysis.lyapunov`, :mod:`vibimpact.analysis.shooting` and
:mod:`vibimpact.analysis.floquet` import it, so that none of them imports another's
internals.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._kernel import boundary as _kb
from ..run import Status
from .. import _validate as _v
from ..models import resolve


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

KIND_FLOW = ("flow of the non-autonomous state equations, per unit tau, without the "
              "forcing phase's zero exponent")
KIND_FLOW_PHASE = ("flow of the autonomous extension (state, forcing phase), per unit tau, "
                    "with the phase's zero exponent")


def tangent_tolerance(options, n, tangent_tol):
    """``options`` with the error test of the tangent entries (beyond the ``n`` state
    entries) at ``tangent_tol`` times the tolerances (``inf``: no test)."""
    try:
        f = float(tangent_tol)
    except (TypeError, ValueError):
        raise ValueError(f"tangent_tol must be a number >= 1 or inf, got {tangent_tol!r}") \
            from None
    if not f >= 1.0:
        raise ValueError(f"tangent_tol must be a number >= 1 or inf, got {tangent_tol!r}")
    return options.with_(n_err=n, tangent_factor=0.0 if math.isinf(f) else f)


def setup(p, model, method, rtol, atol, max_step, event_tol):
    """Model, parameter vector, frequency, period, method and kernel options (the bound
    on the model state only) of a variational run."""
    mdl, pvec = resolve(p, model)
    if method not in ("dop853", "dp5"):
        raise ValueError(f"method must be 'dop853' or 'dp5' (adaptive), got {method!r}")
    rtol = _v.positive("rtol", rtol)
    atol = _v.positive("atol", atol)
    event_tol = _v.positive("event_tol", event_tol)
    omega = float(pvec[mdl.omega_index])
    T = 2.0 * math.pi / omega
    max_step = T / 4.0 if max_step is None else _v.positive("max_step", max_step)
    options = _kb.Options(rtol=rtol, atol=atol, h_fixed=T / 400.0, max_step=max_step,
                          bound=mdl.bound, event_tol=event_tol, max_steps_per_period=10**6,
                          adaptive=True, n_bound=len(mdl.state_names))
    return mdl, pvec, omega, T, _kb.Method.named(method), options
