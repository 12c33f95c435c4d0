"""Period of a stroboscopic (Poincare) sequence, and the two sections of a run.

:func:`detect_period` works on plain arrays of Poincare points from any system: it
returns the smallest ``n`` with ``x[k + n] = x[k]`` for *every* ``k`` of the
window, to a tolerance relative to the size of the data, or 0 when there is none.  Requiring
the recurrence over the whole window, and several repeats of it, is what keeps a slowly
converging transient, a quasi-periodic orbit (whose near-returns are never exact) and a
chaotic orbit from being called periodic.

:func:`poincare_section` and :func:`impact_map` extract the two usual sections of a
:class:`vibimpact.Run`: the stroboscopic map at ``tau_k = 2 pi k / omega`` (``omega`` the
forcing frequency) and the impact map (the state at each contact entry; for the built-in
rotor, at ``R = 1``), cf. Nordmark (1991) and di Bernardo et al. (2008).

References
----------
.. [1] A. B. Nordmark, "Non-periodic motion caused by grazing incidence in an impact
   oscillator", J. Sound Vib. 145 (1991) 279-297.
.. [2] M. di Bernardo, C. J. Budd, A. R. Champneys, P. Kowalczyk, *Piecewise-smooth
   Dynamical Systems: Theory and Applications*, Springer (2008), ch. 2 (Poincare and
   impact maps).
.. [3] T. S. Parker, L. O. Chua, *Practical Numerical Algorithms for Chaotic Systems*,
   Springer (1989) (recognising periodic steady states from Poincare samples).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..base import _validate as _v

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

    from ..core.run import Run
    from ..models.contact import Contact

__all__ = ["detect_period", "detect_period_windows", "poincare_section", "impact_map",
           "SCALE_FLOOR"]

#: floor of the reference length, relative to the data's largest magnitude, so that an
#: exactly constant sequence at the origin still has a positive scale (and is recognised
#: as period 1)
SCALE_FLOOR = 1e-12
#: a period n is refused (0 returned) when a proper divisor d of n repeats within this
#: many times the tolerance: the data are then a transient spiralling into the d-cycle
DIVISOR_MARGIN = 1e3


def detect_period(points: ArrayLike, tol: float = 1e-6, max_period: int = 64,
                  min_repeats: int = 3, *, scale: float | None = None) -> int:
    """Smallest period of a sequence of Poincare points, or 0 if it has none.

    ``n`` is accepted when ``max_j |points[k + n, j] - points[k, j]| <= tol * scale`` for
    **all** ``k = 0 .. m - n - 1`` (the whole window, not only its end), and the window holds
    at least ``min_repeats`` full repetitions, ``m >= min_repeats * n + 1``.  The smallest
    accepted ``n`` in ``1 .. max_period`` is returned.

    Parameters
    ----------
    points : array_like, shape (m, d) or (m,)
        Successive Poincare (e.g. stroboscopic) samples; a 1-D array is one component.
    tol : float
        Relative tolerance, > 0.  It must exceed the relative accuracy of the data (the
        integrator's ``rtol`` and the residual decay of the transient).
    max_period : int
        Largest period tried, >= 1.
    min_repeats : int
        Repetitions of the period the window must hold, >= 1.
    scale : float, optional
        Reference length of the tolerance.  Default: the larger of the attractor's size
        (largest component range ``max_j (max_k x_kj - min_k x_kj)``) and its magnitude
        ``max |x_kj|``, floored at :data:`SCALE_FLOOR` times the data's largest magnitude.
        The rule is the same at every magnitude (the data are normalised by a power of
        two first): values near ``1e308`` or subnormal ones get the period their shape
        has.  The magnitude matters for a fixed
        point, whose size is only the integration noise (about ``rtol * |x|``), so that a
        size-only scale would never accept it; a size-only scale can be had by passing
        ``scale=np.ptp(points, axis=0).max()``.

    Returns
    -------
    int
        The period ``n`` (``T = n * 2 pi / eta`` for stroboscopic samples), or 0 when no
        ``n <= max_period`` repeats over the whole window (transient, quasi-periodic or
        chaotic data, a period above ``max_period``, or too few points).

    Raises
    ------
    ValueError
        Naming the argument: non-finite or badly shaped ``points``, ``tol <= 0``,
        ``max_period`` or ``min_repeats`` not an integer >= 1, ``scale <= 0``.

    Notes
    -----
    Cost O(max_period * m * d).  A transient that spirals into a fixed point (or an
    ``d``-cycle) turning by nearly ``1/n`` of a turn per sample returns close to itself
    every ``n`` samples long before it has converged; ``n`` is therefore refused (0 is
    returned) when a proper divisor ``d`` of ``n`` repeats to within
    :data:`DIVISOR_MARGIN` times the tolerance.  A true period-``n`` orbit whose points lie
    closer than that to a ``d``-cycle (just after a period doubling) is reported as 0 too.
    A geometric transient ``x_k = x* + a q^k`` is rejected as
    long as its first step ``|a| (1 - q)`` exceeds ``tol * scale``; a quasi-periodic orbit
    is rejected because its closest return in ``n <= max_period`` steps is of order
    ``1 / n`` of its size (three-distance theorem), far above ``tol``.

    Examples
    --------
    >>> import numpy as np
    >>> orbit = np.array([[0.0, 1.0], [1.0, 0.5], [0.2, -1.0]])
    >>> detect_period(np.tile(orbit, (5, 1)))
    3
    >>> detect_period(np.random.default_rng(0).random((200, 2)))
    0
    """
    x = _v.points(points)
    tol = _v.real_positive("tol", tol)
    max_period = _v.count("max_period", max_period)
    min_repeats = _v.count("min_repeats", min_repeats)
    m = x.shape[0]
    if m == 0:
        return 0
    return detect_period_windows(x, (m,), tol, max_period, min_repeats, scale=scale)


def _normalised(x, scale):
    """``x`` and ``scale`` divided by a power of two, so that ``1 <= max |x| < 2``.

    Exact (a power of two only moves the exponent) for all but values below about
    ``2**-1022`` times the largest, which are negligible against it: the decisions are
    those on ``x`` itself, without the overflow of differences and ranges of data near
    ``1e308`` (which made every lag's residual ``inf`` and accepted lag 1) and without
    subnormal data falling under an absolute floor.  The rule is thereby the same at every
    magnitude: ``detect_period(c * x) == detect_period(x)`` for ``c > 0``.
    """
    factor = _v.power_of_two(x)
    if factor == 1.0:
        return x, scale
    if scale is not None:
        scale = max(scale / factor, np.finfo(float).smallest_subnormal)
    return x / factor, scale


def detect_period_windows(points, windows, tol=1e-6, max_period=64, min_repeats=3, *,
                          scale=None):
    """:func:`detect_period` on the trailing windows of a sequence, in one pass.

    Returns the period that ``detect_period(points[-w:], tol, min(max_period, (w - 1) //
    min_repeats), min_repeats)`` finds for the first window ``w`` of ``windows`` (in the
    order given, stopping at the first ``w`` longer than the sequence) that has one, or
    0; the same decisions, bit for bit.  The residuals ``max_j |x[k + n, j] - x[k, j]|``
    of every lag are computed once for the longest window (compiled, ``O(w n d)``) and
    reduced to each shorter window by a suffix maximum, instead of once per window and
    lag: the checks of a sweep's transient (:func:`vibimpact.sweeps.analyse_point`) cost
    about 4x less.

    Parameters
    ----------
    points : array_like, shape (m, d) or (m,)
    windows : sequence of int
        Window lengths, each >= 1.
    tol, max_period, min_repeats, scale
        As for :func:`detect_period` (``scale``, when given, for every window; by
        default each window's own size and magnitude).

    Returns
    -------
    int

    Raises
    ------
    ValueError
        As :func:`detect_period`, or naming ``windows``.

    Notes
    -----
    :func:`detect_period` is this function with the one window ``m``: the decision rule
    (smallest accepted lag, refused when a proper divisor repeats within
    :data:`DIVISOR_MARGIN` times the tolerance) is written once, here.
    """
    x = _v.points(points)
    tol = _v.real_positive("tol", tol)
    max_period = _v.count("max_period", max_period)
    min_repeats = _v.count("min_repeats", min_repeats)
    if scale is not None:
        scale = _v.real_positive("scale", scale)
    x, scale = _normalised(x, scale)
    ws = []
    for w in windows:
        w = _v.count("windows", w)
        if w > x.shape[0]:
            break
        ws.append(w)
    if not ws:
        return 0
    from .._kernel.boundary import suffix_lag_residuals

    W = max(ws)
    xs = np.ascontiguousarray(x[-W:])
    N = max(1, min(max_period, (W - 1) // min_repeats))
    suffix = np.empty((W, N))
    hi = np.empty_like(xs)
    lo = np.empty_like(xs)
    mag = np.empty(W)
    suffix_lag_residuals(xs, N, suffix, hi, lo, mag)
    for w in ws:
        k0 = W - w
        ref = scale if scale is not None else max(float(np.max(hi[k0] - lo[k0])),
                                                  float(mag[k0]), SCALE_FLOOR)
        threshold = tol * ref
        n_max = min(max_period, (w - 1) // min_repeats)
        if n_max < 1:
            continue
        res = suffix[k0, :n_max]
        hit = np.flatnonzero(res <= threshold)
        if hit.size == 0:
            continue
        n = int(hit[0]) + 1
        # a cycle whose points nearly coincide with a shorter one is a transient spiralling
        # into that shorter cycle (its rotation per sample close to 1/n of a turn), not a
        # period-n orbit
        if any(res[d - 1] <= DIVISOR_MARGIN * threshold for d in range(1, n) if n % d == 0):
            continue
        return n
    return 0


def poincare_section(run: Run) -> np.ndarray:
    """Stroboscopic Poincare samples of a run, ``x(tau_k)`` at ``tau_k = 2 pi k / omega``.

    Parameters
    ----------
    run : vibimpact.Run
        Any object with a ``strobe`` array.

    Returns
    -------
    ndarray, shape (periods + 1, n)
        A copy of ``run.strobe`` (``(0, 4)`` when the run has no samples).
    """
    strobe = np.array(run.strobe, dtype=np.float64, copy=True)
    if strobe.size == 0:
        width = strobe.shape[1] if strobe.ndim == 2 else 4
        return np.zeros((0, width))
    return strobe


def impact_map(run: Run, contact: Contact | None = None) -> np.ndarray:
    """States at every contact entry: the impact (Poincare) map of a run.

    Rows are the events of ``run.events`` of the contact's switching function
    (``which == contact.switch``) that go from free flight into contact (its mode entry
    ``contact.mode`` from 0 to 1); contact exits and other switches are dropped.  The
    contact is ``contact``, else the one the run's registered model declares
    (:attr:`vibimpact.Contact.switch`, :attr:`vibimpact.Contact.mode`; a model without
    one: no rows); a run that names no registered model (a user's, unregistered: pass
    ``contact``) is read with switch 0 and mode entry 0, the kernel's first.

    Parameters
    ----------
    run : vibimpact.Run
        A run; ``run.events`` is a dict with ``t`` (k,), ``which`` (k,), ``mode_before``
        (k, n_mode), ``mode_after`` (k, n_mode) and ``state`` (k, n_state) (the built-in
        rotor's n_mode is 2, its n_state 4).  A run without events (or a model without
        contacts) gives no rows.
    contact : vibimpact.models.contact.Contact, optional
        The model's contact (default: the run's registered model's).

    Returns
    -------
    ndarray, shape (n_impacts, n_state)
        The state at each entry in time order (the built-in rotor's ``(X, Y, X', Y')``);
        the contact's angle of these rows (:attr:`vibimpact.Contact.angle`; for the
        built-in rotor ``theta = atan2(Y, X)``) is :attr:`vibimpact.Run.impacts`
        ``["theta"]``.
    """
    events = getattr(run, "events", None) or {}
    width = 4
    strobe = getattr(run, "strobe", None)
    if strobe is not None and np.ndim(strobe) == 2 and np.shape(strobe)[1] > 0:
        width = np.shape(strobe)[1]
    needed = ("which", "mode_before", "mode_after", "state")
    if any(key not in events for key in needed) or np.size(events["which"]) == 0:
        return np.zeros((0, width))
    which = np.asarray(events["which"]).ravel()
    before = np.asarray(events["mode_before"]).reshape(which.size, -1)
    after = np.asarray(events["mode_after"]).reshape(which.size, -1)
    state = np.asarray(events["state"], dtype=np.float64).reshape(which.size, -1)
    switch, mode = _contact_indices(run, contact)
    if switch is None:
        return np.zeros((0, width))
    entry = (which == switch) & (before[:, mode] == 0) & (after[:, mode] == 1)
    return state[entry].copy()


def _contact_indices(run, contact):
    """``(switch, mode)`` of ``contact``, else of the run's registered model's contact
    (``(None, None)``: the model has none), else ``(0, 0)``."""
    if contact is None:
        from .. import models

        name = getattr(run, "model", None)
        if not (isinstance(name, str) and name in models.names()):
            return 0, 0
        contact = models.get(name).contact
        if contact is None:
            return None, None
    return int(contact.switch), int(contact.mode)
