"""Lyapunov exponents of the forced, piecewise-smooth models, and of maps and time series.

Three independent routes, so each checks the others:

* :func:`lyapunov_spectrum` -- variational equations with the analytic Jacobian, saltation
  matrices at every switch, QR re-orthonormalisation each forcing period (Benettin et al.
  1980; Müller 1995 for the saltation).
* :func:`largest_lyapunov` -- two nearby trajectories, separation renormalised each period
  (Benettin, Galgani & Strelcyn 1976).
* :func:`lyapunov_from_jacobians` -- the QR product of a sequence of map Jacobians (any
  map: the Hénon map, or finite-difference Jacobians of the stroboscopic map), and
  :func:`lyapunov_from_series`, a time-series estimate through nolds (Rosenstein et al.
  1993), a cross-check only.

Which spectrum?  The models are periodically forced, *non-autonomous* (e.g. the built-in
rotor and the Duffing oscillator): as autonomous flows on (state, forcing phase) they have
one more exponent, exactly 0, along the phase.
The exponents returned here are those of the ``n``-dimensional state, per unit of
dimensionless time ``tau``, **without** that trivial zero (ask ``include_phase=True`` to
append it).  The stroboscopic (Poincaré) map's exponents are the same numbers times the
forcing period ``T = 2 pi / omega`` (``omega`` the model's forcing frequency, the built-in
rotor's ``eta``): :attr:`LyapunovResult.map_exponents`.  A periodic orbit therefore has
all returned exponents negative; a quasi-periodic one has a largest exponent 0; a chaotic
one a positive largest exponent.

Periodic orbits.  There the exponents are the Floquet exponents ``ln|mu_i| / (n T)`` of
the monodromy matrix (Parker & Chua 1989, *Practical Numerical Algorithms for Chaotic
Systems*, ch. 4).  The QR average (Eckmann & Ruelle 1985, Rev. Mod. Phys. 57, 617, sec.
III.B) tends to them only like ``1/N`` when multipliers share a modulus: a complex pair
(every underdamped mode, e.g. of the built-in rotor) rotates its tangent plane, so
``R_11`` and ``R_22`` split the pair's growth unevenly, by an amount that oscillates
without decaying (only the plane's area growth is free of it).  For the built-in rotor,
after 400 periods at B = 0.01 (impacting period-1 orbits of fig8, eta = 1.05, and fig10,
eta = 1.075), ``lambda_1`` came out up to 17 % above ``ln|mu|/T``, ``lambda_2`` below,
with batch-means errors up to 8 times smaller than the actual ones.
:func:`lyapunov_spectrum` thus returns the Floquet exponents, exact, once the stroboscopic
points repeat and shooting confirms a stable orbit; :func:`floquet_lyapunov` gives them for
a point of an orbit.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import math
from dataclasses import replace

import numpy as np

from .._kernel import boundary as _kb
from ..core.run import Status, status_of
from ..base import _validate as _v
from ..core.solver import Solver
from ..core.system import as_system
from .exponents import KIND_FLOW, KIND_FLOW_PHASE, TANGENT_TOL, Averaging, LyapunovResult
from .floquet import floquet_lyapunov
from .period import detect_period
from .shooting import shoot_periodic_orbit

if TYPE_CHECKING:  # names of the annotations only
    from numpy.typing import ArrayLike

    from ..core.system import System

__all__ = ["lyapunov_spectrum", "largest_lyapunov", "lyapunov_from_jacobians",
           "lyapunov_from_series", "strobe_map_jacobian", "floquet_lyapunov",
           "LyapunovResult", "Averaging", "TANGENT_TOL"]

#: solver defaults of the variational runs (rtol; the rest as :func:`vibimpact.simulate`)
SPECTRUM_SOLVER = dict(rtol=1e-10)
#: of the two-trajectory runs: tighter, so that ``d0`` stands far above the error
TWO_TRAJECTORY_SOLVER = dict(rtol=1e-11, atol=1e-13)
#: of the finite-difference Jacobian
FD_SOLVER = dict(rtol=1e-12, atol=1e-14)


def _start(system, state0, transient, solver):
    """State at the start of a forcing period after ``transient`` periods (``solver``:
    the settings)."""
    y = _v.state("state0", state0, system.n_state)
    if transient == 0:
        return y, Status.OK, ""
    run = system.simulate(periods=1, transient=transient - 1, state0=y, solver=solver)
    return run.final_state, run.status, run.reason


def _estimate(logs, T, block):
    """Exponents, standard errors and running history from per-period log growths."""
    n = logs.shape[0]
    nb = n // block
    # the last axis named: fewer periods than a block leave no block (and no -1 to infer)
    means = logs[: nb * block].reshape(nb, block, logs.shape[1]).mean(axis=1) / T
    lam = logs.mean(axis=0) / T
    # a tangent direction that a Filippov stick phase annihilates (the sliding surface's
    # saltation matrix projects it out: a stuck ring's speed, a sticking contact) has
    # log |R_cc| = -inf: its exponent is -inf exactly, with no error to estimate
    lost = np.isneginf(lam)
    if nb >= 2:
        with np.errstate(invalid="ignore"):
            err = means.std(axis=0, ddof=1) / math.sqrt(nb)
    else:
        err = np.full(logs.shape[1], np.inf)
    err[lost] = 0.0
    history = np.cumsum(means, axis=0) / np.arange(1, nb + 1)[:, None]
    return lam, err, history


def _run_blocks(step, m, T, avg, watch=None):
    """Call ``step(n, logs)`` block by block (after ``avg.align`` periods discarded) until
    the largest exponent's error is ``avg.target_stderr`` (or, with ``avg.decisive = (band,
    z)``, until its sign is settled: ``|lambda| - z sigma`` beyond ``band``; or until
    ``watch(done)``, called after every block with the number of periods integrated,
    returns True)."""
    skip, block = avg.align, avg.block
    total = avg.max_periods + skip
    logs = np.empty((total, m))
    done = 0
    status = _kb.OK
    while done < total:
        todo = skip if done == 0 and skip else min(block, total - done)
        status, got = step(todo, logs[done:done + todo])
        done += got
        if status != _kb.OK:
            break
        if watch is not None and done > skip and watch(done):
            break  # (not during the alignment: a result always averages one block)
        if done - skip >= avg.min_periods:
            lam, err, _ = _estimate(logs[skip:done], T, block)
            if err[0] <= avg.target_stderr:
                break
            dec = avg.decisive
            if dec is not None and abs(lam.max()) - dec[1] * err[0] > dec[0]:
                break
    return logs[skip:done] if done > skip else logs[:0], status


def _result(logs, status, T, block, target, method, kind, order=True):
    st, reason = status_of(status)
    if st is not Status.OK or logs.shape[0] == 0:
        m = logs.shape[1]
        return LyapunovResult(np.full(m, np.nan), np.full(m, np.nan), T, int(logs.shape[0]),
                              False, method, kind, st if st is not Status.OK else
                              Status.FAILED, reason or "no periods integrated")
    lam, err, history = _estimate(logs, T, block)
    if order:
        idx = np.argsort(-lam, kind="stable")
        lam, err, history = lam[idx], err[idx], history[:, idx]
    return LyapunovResult(lam, err, T, int(logs.shape[0]), bool(err[0] <= target), method,
                          kind, Status.OK, "", history, 0, lam)


def _period_watch(states, shoot, tol, max_period, window, attempts=3):
    """``watch(done)`` for :func:`_run_blocks`: True once the trailing ``window`` rows of
    ``states`` repeat with a period ``n`` (:func:`~vibimpact.analysis.period.detect_period`,
    relative ``tol``) and ``shoot(x, n)`` from the last converges to a *stable* orbit (so
    the trajectory is attracted to it, not passing a saddle cycle) within 1e-2 of it; the
    orbit is left in ``watch.orbit``.  At most ``attempts`` shootings per run."""
    left = [attempts]

    def watch(done):
        pts = states[max(0, done - window):done]
        if left[0] <= 0 or done < 4 or not np.all(np.isfinite(pts)):
            return False
        n = detect_period(pts, tol=tol, max_period=max(1, min(max_period,
                                                              (len(pts) - 1) // 3)))
        if n == 0:
            return False
        left[0] -= 1
        orb = shoot(pts[-1], n)
        orbit = orb if (
            orb.status is Status.OK and orb.converged and orb.abs_max < 1.0
            and np.abs(orb.state - pts[-1]).max() <= 1e-2 * max(1.0, np.abs(pts).max())) \
            else None
        watch.orbit = orbit  # type: ignore[attr-defined]  # an attribute of a function
        return orbit is not None

    watch.orbit = None  # type: ignore[attr-defined]  # an attribute of a function
    return watch


@_v.checks_flags
def lyapunov_spectrum(system: System, state0: ArrayLike | None = None, *,
                      n_exponents: int | None = None, averaging: Averaging = Averaging(),
                      include_phase: bool = False, tangent_tol: float = TANGENT_TOL,
                      floquet: bool = True, floquet_tol: float = 1e-5,
                      floquet_max_period: int = 16) -> LyapunovResult:
    """Lyapunov spectrum by variational equations with saltation matrices (Benettin/QR).

    The tangent vectors follow ``v' = J v`` with the model's analytic Jacobian inside each
    mode; at every switching event (contact entry and exit, slip to stick and back) they
    are mapped by the saltation matrix ``S = I + (f+ - f-) grad g^T / (grad g . f- + g_s)``
    (Müller 1995, Chaos Solitons Fractals 5, 1671; Leine & Nijmeijer 2004, sec. 3.5), so
    the exponents stay right where the vector field jumps.  After each forcing period the
    vectors are re-orthonormalised by QR (Benettin et al. 1980, Meccanica 15, 9).

    Parameters
    ----------
    system : System
        Model, parameters and solver settings (defaults DOP853, ``rtol = 1e-10``,
        ``atol = 1e-12``, ``event_tol = 1e-12``, ``max_step = T / 4``; adaptive methods
        only).
    state0 : array_like, shape (n,), optional
        Initial state (rest by default), integrated ``averaging.transient`` periods first.
    n_exponents : int, optional
        How many exponents (tangent vectors), ``1 <= n_exponents <= n``; all by default.
    averaging : Averaging
        Transient, alignment, periods averaged, blocks, target error, early stop on the
        sign (:class:`~vibimpact.analysis.Averaging`; default ``Averaging()``: 200
        transient periods, 50 aligning, 400 to 20000 averaged in blocks of 50 to a
        standard error of 2e-3).
    include_phase : bool
        Append the forcing phase's exponent 0 (spectrum of the autonomous extension).
    tangent_tol : float
        The tangent vectors' local errors are tested against ``tangent_tol`` times the
        tolerances (``atol + rtol |v|``); 1 tests them as the state, ``inf`` not at all
        (they then ride on the state's steps).  The default :data:`TANGENT_TOL` = 1e3:
        at rtol 1e-8 one-period Jacobians stay accurate to about 1e-4 (1e-8 at 1; 1e-3
        untested: the Jacobian of the Hertz force is singular at the contact surface, the
        force itself is not), the exponents of impacting periodic orbits agree with the
        fully tested ones to 1e-5 per unit tau, chaotic exponents within their statistical
        error, at 1.6-1.8x less cost (``analyses/performance/lyapunov_error_control.py``,
        ``reports/performance.md``).  Some test is needed: a state that comes to rest
        would otherwise take steps far too long for its tangent vectors.  Separate
        tolerances for sensitivities are also an option of CVODES
        (``CVodeSensSStolerances``, ``CVodeSetSensErrCon``; Hindmarsh et al. 2005, ACM
        TOMS 31, 363).
    floquet, floquet_tol, floquet_max_period : bool, float, int
        With ``floquet``, once the last ``max(block, 3 floquet_max_period + 1)`` strobe
        points repeat with a period ``n <= floquet_max_period`` to ``floquet_tol``
        (relative; it only says when to try Newton, so it may be loose: 1e-5 is met ~300
        periods before 1e-7 where ``|mu| = 0.98``) and Newton (tolerance
        ``max(1e-9, 10 rtol)``) from the last converges to a *stable* orbit within 1e-2
        of it, stop and return its Floquet exponents (:func:`floquet_lyapunov`,
        ``floquet_n > 0``), the limit that a complex pair lets the QR average reach only
        like ``1/N``.  Points that never repeat (chaos, quasi-periodicity, transients)
        leave the QR average as with ``floquet=False``.

    Returns
    -------
    LyapunovResult
        ``exponents`` shape (m,) per unit ``tau``, descending (see the module docstring
        for the flow/map distinction); ``status`` DIVERGED with NaN exponents after a
        blow-up; ``floquet_n > 0`` for Floquet exponents.

    Examples
    --------
    >>> import vibimpact as vi
    >>> from vibimpact.analysis import lyapunov_spectrum
    >>> res = lyapunov_spectrum(vi.System(vi.presets.get("fig8").replace(eta=1.185)))
    >>> res.exponents.shape
    (4,)
    """
    system = as_system(system)
    settings = system.settings(**SPECTRUM_SOLVER)
    Solver.check_tangents(settings, tangent_tol)
    n = system.n_state
    m = n if n_exponents is None else _v.count("n_exponents", n_exponents, 1)
    if m > n:
        raise ValueError(f"n_exponents must be <= {n}, got {n_exponents}")
    avg = _averaging(averaging)
    if floquet:
        floquet_max_period = _v.count("floquet_max_period", floquet_max_period, 1)
        floquet_tol = _v.positive("floquet_tol", floquet_tol)
    T = system.period
    kind = KIND_FLOW_PHASE if include_phase else KIND_FLOW
    x0, st, reason = _start(system, state0, avg.transient, settings)
    if st is not Status.OK:
        return LyapunovResult(np.full(m, np.nan), np.full(m, np.nan), T, 0, False,
                              "variational", kind, st, "transient: " + reason)
    states = np.full((avg.max_periods + avg.align, n), np.nan)
    newton = system.resolved(**SPECTRUM_SOLVER)
    assert newton.rtol is not None  # resolved()
    tol = max(1e-9, 10.0 * newton.rtol)
    watch = None
    if floquet:
        watch = _period_watch(states, lambda x, k: shoot_periodic_orbit(newton, x, k, tol=tol),
                              floquet_tol, floquet_max_period,
                              max(avg.block, 3 * floquet_max_period + 1))
    solver = Solver.variational(system, x0, settings, tangents=m, tangent_tol=tangent_tol,
                                first_step=system.period / 50.0)
    logs, status = _benettin_blocks(solver, states, avg, watch)
    res = _result(logs, status, T, avg.block, avg.target_stderr, "variational", kind)
    if include_phase and res.status is Status.OK:
        res = _with_phase(res)
    if watch is not None and watch.orbit is not None and status == _kb.OK:
        orb = watch.orbit
        fl = floquet_lyapunov(newton, orb.state, orb.n, n_exponents=m,
                              include_phase=include_phase, tol=tol)
        if fl.status is Status.OK:
            qr_ok = res.status is Status.OK
            return replace(fl, periods=res.periods,
                           converged=bool(fl.stderr[0] <= avg.target_stderr),
                           method="variational",
                           history=res.history if qr_ok else np.zeros((0, len(fl))),
                           qr_exponents=res.exponents if qr_ok else np.full(len(fl), np.nan))
    return res


def _averaging(averaging):
    if not isinstance(averaging, Averaging):
        raise ValueError(f"averaging must be a vibimpact.analysis.Averaging, got "
                         f"{type(averaging).__name__}")
    return averaging


def _benettin_blocks(solver, states, avg, watch):
    """The tangent vectors' log growths per period (QR after each) of the variational
    ``solver``, and the status; the state at the start of each period goes into
    ``states``."""
    n = solver.system.n_state
    m = solver.y.size // n - 1
    pos = [0]

    def step(count, out):
        st_, got = solver.benettin(count, out, states[pos[0]:pos[0] + count])
        pos[0] += got
        return st_, got

    return _run_blocks(step, m, solver.system.period, avg, watch)


def _with_phase(res):
    """``res`` with the forcing phase's exponent 0 appended (in order)."""
    lam = np.concatenate([res.exponents, [0.0]])
    err = np.concatenate([res.stderr, [0.0]])
    idx = np.argsort(-lam, kind="stable")
    hist = np.concatenate([res.history, np.zeros((res.history.shape[0], 1))], axis=1)
    return LyapunovResult(lam[idx], err[idx], res.period, res.periods, res.converged,
                          res.method, res.kind, res.status, res.reason, hist[:, idx], 0,
                          lam[idx])


def largest_lyapunov(system: System, state0: ArrayLike | None = None, *, d0: float = 1e-7,
                     averaging: Averaging = Averaging(align=20)) -> LyapunovResult:
    """Largest Lyapunov exponent from two nearby trajectories (renormalised separation).

    A perturbed copy starts ``d0`` away from the reference; after each forcing period the
    separation ``d`` (Euclidean norm of the state difference) is logged and the copy put
    back at distance ``d0`` along it (Benettin, Galgani & Strelcyn 1976, Phys. Rev. A 14,
    2338; Parker & Chua 1989, *Practical Numerical Algorithms for Chaotic Systems*, 4.2).
    It needs no Jacobian and no saltation matrix, so it checks
    :func:`lyapunov_spectrum` independently.  ``d0`` must be far above the integration
    error and far below the attractor's size: the default tolerances are tighter than
    :func:`lyapunov_spectrum`'s for that reason.

    Parameters
    ----------
    system : System
        Solver defaults DOP853, ``rtol = 1e-11``, ``atol = 1e-13``, ``event_tol = 1e-12``,
        ``max_step = T / 4`` (adaptive methods only).
    state0 : array_like, shape (n,), optional
        As in :func:`lyapunov_spectrum`.
    d0 : float
        Separation after each renormalisation.
    averaging : Averaging
        As in :func:`lyapunov_spectrum`; by default ``Averaging(align=20)``.

    Returns
    -------
    LyapunovResult
        One exponent, ``method`` "two-trajectory".
    """
    system = as_system(system)
    settings = system.settings(**TWO_TRAJECTORY_SOLVER)
    Solver.check_tangents(settings)
    d0 = _v.positive("d0", d0)
    n = system.n_state
    avg = _averaging(averaging)
    T = system.period
    x0, st, reason = _start(system, state0, avg.transient, settings)
    if st is not Status.OK:
        return LyapunovResult(np.full(1, np.nan), np.full(1, np.nan), T, 0, False,
                              "two-trajectory", KIND_FLOW, st, "transient: " + reason)
    y2 = x0.copy()
    y2 += d0 / math.sqrt(n)
    ref, perturbed = Solver.pair(system, x0, y2, settings, first_step=T / 50.0)
    scale = np.ones(n)

    def step(count, out):
        return ref.two_trajectory(perturbed, d0, scale, count, out)

    logs, status = _run_blocks(step, 1, T, avg)
    return _result(logs, status, T, avg.block, avg.target_stderr, "two-trajectory",
                   KIND_FLOW)


def lyapunov_from_jacobians(jacobians: ArrayLike, dt: float = 1.0, *,
                            block: int | None = None, discard: int = 0) -> LyapunovResult:
    """Lyapunov spectrum of a map from the Jacobians along an orbit (QR method).

    Parameters
    ----------
    jacobians : array_like, shape (N, d, d)
        ``J_k = Df(x_k)`` along the orbit ``x_{k+1} = f(x_k)``.
    dt : float
        Time per iteration: 1 for a map's exponents per iteration, ``T`` to turn a
        stroboscopic map's exponents into the flow's per unit time.
    block : int, optional
        Iterations per block for the standard error (``N // 20`` by default).
    discard : int
        Leading iterations used only to align the vectors.

    Returns
    -------
    LyapunovResult
        ``method = "map"``; exponents per unit of ``dt``, descending.

    Examples
    --------
    The Hénon map (a = 1.4, b = 0.3) has exponents 0.419 and -1.623 (per iteration):
    see tests/test_analysis_lyapunov.py.
    """
    J = _v.numeric("jacobians", jacobians, "an array of shape (N, d, d)")
    if J.ndim != 3 or J.shape[1] != J.shape[2] or J.shape[0] < 2:
        raise ValueError(f"jacobians must have shape (N >= 2, d, d), got {J.shape}")
    if not np.all(np.isfinite(J)):
        raise ValueError("jacobians must be finite")
    dt = _v.positive("dt", dt)
    discard = _v.count("discard", discard, 0)
    N, d, _ = J.shape
    if discard >= N - 1:
        raise ValueError(f"discard must be < {N - 1}, got {discard}")
    block = max(2, (N - discard) // 20) if block is None else _v.count("block", block, 2)
    logs = np.empty((N, d))
    _kb.qr_growth(np.ascontiguousarray(J), logs)
    return _result(logs[discard:], _kb.OK, dt, block, np.inf, "map",
                   "map, per unit dt (dt = 1: per iteration)")


def lyapunov_from_series(series: ArrayLike, period: float = 1.0, **kwargs) -> float:
    """Largest exponent of a scalar time series by Rosenstein's method (nolds), a cross-check.

    Parameters
    ----------
    series : array_like, shape (N,)
        E.g. one coordinate of the stroboscopic samples.
    period : float
        Time between samples (the forcing period ``T`` for Poincaré samples), so the
        result is per unit time.
    **kwargs
        Passed to ``nolds.lyap_r``; defaults ``lag=1, emb_dim=4, min_tsep=10,
        trajectory_len=6, fit="poly"`` (on fig8 at eta = 1.22 this gives 0.055 per unit
        tau against 0.075 from the variational equations).

    Returns
    -------
    float
        Per unit time.  A time-series estimate is biased and noisy: use it to confirm a
        sign, not as the value (Rosenstein, Collins & De Luca 1993, Physica D 65, 117).

    Raises
    ------
    ImportError
        When nolds cannot be imported: it comes with the ``crosscheck`` extra
        (``pip install "vibimpact[crosscheck]"``).
    """
    x = _v.array1d("series", series)
    if x.size < 50 or not np.all(np.isfinite(x)):
        raise ValueError("series must be at least 50 finite numbers")
    x = x / _v.power_of_two(x)  # exact; the exponent is scale-free
    period = _v.positive("period", period)
    try:
        import nolds  # lazy: fragile import, needed only for this cross-check
    except ImportError as exc:
        raise ImportError("lyapunov_from_series needs nolds: pip install "
                          f"'vibimpact[crosscheck]' ({exc})") from exc
    # one sample per forcing period is already a "lag": nolds' autocorrelation rule picks
    # a lag of hundreds of samples on Poincaré data, which destroys the estimate
    kwargs.setdefault("lag", 1)
    kwargs.setdefault("emb_dim", 4)
    kwargs.setdefault("min_tsep", 10)
    kwargs.setdefault("trajectory_len", 6)
    kwargs.setdefault("fit", "poly")
    return float(nolds.lyap_r(x, **kwargs)) / period


def strobe_map_jacobian(system: System, state0: ArrayLike, *, n: int = 1,
                        eps: float = 1e-6) -> np.ndarray:
    """Jacobian of the ``n``-fold stroboscopic map at ``state0`` by central differences.

    At a period-``n`` fixed point this is the monodromy matrix; its eigenvalues are the
    Floquet multipliers ``mu`` and ``ln|mu| / (n T)`` the orbit's Lyapunov exponents.

    Parameters
    ----------
    system : System
        Solver defaults DOP853, ``rtol = 1e-12``, ``atol = 1e-14`` (the differences need
        the map far below ``eps``).
    state0 : array_like, shape (d,)
    n : int
        Forcing periods of the map.
    eps : float
        Step of the central differences in each state entry.

    Returns
    -------
    ndarray, shape (d, d)

    Raises
    ------
    ValueError
        Naming the argument; ``state0`` when the map cannot be evaluated there.
    """
    system = as_system(system)
    x0 = _v.state("state0", state0, system.n_state)
    n = _v.count("n", n, 1)
    eps = _v.positive("eps", eps)
    solver = system.settings(**FD_SOLVER)
    d = x0.size
    M = np.empty((d, d))
    for j in range(d):
        cols = []
        for sgn in (1.0, -1.0):
            x = x0.copy()
            x[j] += sgn * eps
            run = system.simulate(periods=n, state0=x, solver=solver)
            if run.status is not Status.OK:
                raise ValueError(f"state0: the map could not be evaluated ({run.reason})")
            cols.append(run.final_state)
        M[:, j] = (cols[0] - cols[1]) / (2.0 * eps)
    return M
