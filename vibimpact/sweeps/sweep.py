"""`sweep`: the rotor speed swept up and/or down with continuation, into an xarray Dataset.

Continuation and parallelism
----------------------------
Each point starts from the previous point's final state (in sweep order), so hysteresis
and jumps show as in the paper.  To use several cores without breaking that, the sweep
order is cut into ``blocks`` contiguous blocks.  Block ``b`` starts from a *seed*: the
state reached by a cheap serial pass that continues through every grid point before it
(``seed_periods`` forcing periods per point, no analyses).  Blocks then run
independently, so ``workers`` only decides how many run at once: the result depends on
``blocks`` (1 = pure serial continuation), never on ``workers``, and serial and parallel
runs are bit-identical.  With ``direction="both"`` the up and down sweeps are independent
streams as well.
"""
from __future__ import annotations

import math
import multiprocessing as mp
import os
import queue as _queue
import sys

import numpy as np

from .. import _limits
from ..analysis.classify import Label
from ..params import Params
from ..run import Status
from .. import _validate as _v
from ..simulation import simulate
from . import checkpoint as ck
from .point import ANALYSES, REGIME_CODES, SweepSettings, analyse_point
from .predict import extrapolate_branch

PERIODIC = REGIME_CODES[Label.PERIODIC]

DIRECTIONS = ("up", "down", "both")


def _grid(eta):
    size = np.size(eta) if isinstance(eta, np.ndarray) else None
    if size is not None:
        _limits.check_points(size)  # before copying a huge array
    try:
        arr = np.array(eta, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"eta must be numbers, got {eta!r}") from None
    if arr.size == 0:
        raise ValueError("eta must not be empty")
    _limits.check_points(arr.size)
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0.0):
        raise ValueError("eta must be finite and > 0")
    if arr.size > 1 and not (np.all(np.diff(arr) > 0.0)):
        raise ValueError("eta must be strictly increasing (the direction is a separate "
                         "argument)")
    return arr


def _block_starts(n, blocks):
    """First indices of ``blocks`` contiguous, nearly equal blocks of ``n`` points."""
    blocks = max(1, min(blocks, n))
    return [int(round(b * n / blocks)) for b in range(blocks)] + [n]


def _seeds(p, etas, starts, state0, seed_periods):
    """States at the block starts from a cheap continuation pass over the grid."""
    seeds = {0: None if state0 is None else np.array(state0, dtype=np.float64)}
    x = seeds[0]
    last = max(starts[:-1])
    for i in range(1, last + 1):
        run = simulate(p.replace(eta=float(etas[i - 1])), periods=1,
                       transient=seed_periods - 1, state0=x)
        x = run.final_state if run.status is Status.OK else None
        if i in starts[:-1]:
            seeds[i] = None if x is None else x.copy()
    return seeds


def continued_state(p, eta, *, eta_start=1.0, step=0.02, transient=200, state0=None):
    """State on the branch reached by sweeping ``eta`` up from ``eta_start``.

    ``transient`` forcing periods at every grid point ``eta_start, eta_start + step, ...``
    up to ``eta`` (and at ``eta`` itself when it is off that grid), each starting from the
    previous point's final state (rest, or ``state0``, at the first).  With the default
    B = Ec = 0.1 the impacting upper branch of fig8-fig11 above eta ~ 1.18 is reached only
    this way: from rest the rotor stays on the low, impactless branch.

    Returns
    -------
    ndarray, shape (4,)
        The state at the start of a forcing period at ``eta``.
    """
    x = state0
    last = eta_start
    for e in np.arange(eta_start, eta + 1e-9, step):
        x = simulate(p.replace(eta=float(e)), periods=1, transient=transient,
                     state0=x).final_state
        last = e
    if abs(eta - last) > 1e-9:
        x = simulate(p.replace(eta=float(eta)), periods=1, transient=transient,
                     state0=x).final_state
    return x


_PROGRESS = None


def _init_worker(q):
    """Worker set-up: progress queue; Ctrl-C is the parent's to handle; die with it."""
    global _PROGRESS
    _PROGRESS = q
    import signal
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # not a handler inherited by fork
    if sys.platform.startswith("linux"):
        try:  # PR_SET_PDEATHSIG: SIGKILL this worker when the parent process dies
            import ctypes
            ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)
        except (OSError, AttributeError):
            pass
        if os.getppid() == 1:  # the parent died before the line above
            os._exit(1)


def _run_block(task):
    """Compute one block in order; returns [(index, result)].  Runs in a worker."""
    p, etas, direction, idx, seed, settings, fixed, ckdir, done = task
    out = []
    x = seed
    branch = []  # (eta, orbit_point) of the latest consecutive period-1 points
    for i in idx:
        res = done.get(i)
        if res is None:
            s0 = seed if fixed else x
            guess = None if fixed else _predicted(branch, float(etas[i]), settings.predict)
            res = analyse_point(p.replace(eta=float(etas[i])), s0, settings, guess=guess)
            if ckdir is not None:
                ck.save_point(ckdir, direction, i, res)
            if _PROGRESS is not None:
                _PROGRESS.put(1)
        out.append((i, res))
        fs = res["final_state"]
        x = None if not np.all(np.isfinite(fs)) else np.asarray(fs)
        orbit = res.get("orbit_point")
        if res["regime"] == PERIODIC and res["period"] == 1 and orbit is not None \
                and np.all(np.isfinite(orbit)) and settings.predict > 1:
            branch = branch[-(settings.predict - 1):] + [(float(etas[i]), orbit)]
        else:
            branch = []
    return direction, out


#: the predictor is used only when its step is at most this many times the branch's last
#: step (beyond a fold the extrapolated branch has no orbit to land on)
PREDICT_MAX_STEP = 2.0


def _predicted(branch, eta, m):
    """The continuation predictor's guess at ``eta`` from the last ``m`` period-1 points
    of ``branch``, or None (fewer points, or a step out of line with the branch's)."""
    if m < 2 or len(branch) < m:
        return None
    e, xs = zip(*branch[-m:])
    guess = extrapolate_branch(e, xs, eta)
    last = float(np.abs(xs[-1] - xs[-2]).max())
    if not np.all(np.isfinite(guess)) or \
            float(np.abs(guess - xs[-1]).max()) > PREDICT_MAX_STEP * last:
        return None
    return guess


def check_request(direction, analyses, settings, state0):
    """Validated ``(settings, state0)`` of a sweep or map request.

    ``settings`` (default :class:`SweepSettings`) gets ``analyses`` (in canonical order,
    "period" always included); ``state0`` becomes a float64 array of 4 or stays None.

    Raises
    ------
    ValueError
        Naming ``direction``, ``analyses``, ``settings`` or ``state0``.
    """
    if direction not in DIRECTIONS:
        raise ValueError(f"direction must be one of {', '.join(DIRECTIONS)}, "
                         f"got {direction!r}")
    analyses = tuple(analyses)
    bad = [a for a in analyses if a not in ANALYSES]
    if bad:
        raise ValueError(f"analyses: unknown {', '.join(map(str, bad))}; choose from "
                         f"{', '.join(ANALYSES)}")
    analyses = tuple(a for a in ANALYSES if a in analyses or a == "period")
    settings = SweepSettings() if settings is None else settings
    if not isinstance(settings, SweepSettings):
        raise ValueError("settings must be a SweepSettings")
    settings = SweepSettings(**{**settings.__dict__, "analyses": analyses})
    if state0 is not None:
        s = np.array(state0, dtype=np.float64).reshape(-1)
        if s.size != 4 or not np.all(np.isfinite(s)):
            raise ValueError(f"state0 must be 4 finite numbers, got {state0!r}")
        state0 = s
    return settings, state0


def sweep(p, eta, direction="up", analyses=ANALYSES, *, state0=None, continuation=True,
          settings=None, blocks=16, workers=1, seed_periods=10, checkpoint=None,
          resume=False, progress=False, command=None):
    """Sweep the forcing frequency ``eta`` and classify the motion at every point.

    Parameters
    ----------
    p : Params
        All other parameters (its ``eta`` is ignored).
    eta : array_like, shape (n,)
        Strictly increasing grid; ``direction`` decides the order it is swept in.
    direction : {"up", "down", "both"}
    analyses : sequence of str
        Subset of ``("period", "impacts", "response", "poincare", "lyapunov", "test01")``;
        only these are computed ("period" always runs, it ends the transients).
    state0 : array_like, shape (4,), optional
        State at the first point of each direction (rest by default).
    continuation : bool
        True: each point starts from the previous point's final state.  False: every
        point starts from ``state0`` (a fixed initial state).
    settings : SweepSettings, optional
        Transient, record length, Lyapunov and classifier settings.
    blocks : int
        Contiguous blocks per direction (see the module docstring); the result depends on
        it, not on ``workers``.
    workers : int
        Processes that compute blocks at once (1: in this process).
    seed_periods : int
        Forcing periods per grid point of the seeding pass.
    checkpoint : path, optional
        Directory where every finished point is saved at once; with ``resume=True`` the
        points found there are loaded instead of recomputed.
    progress : bool
        A progress bar on stderr.
    command : str, optional
        Command line to record in the attributes.

    Returns
    -------
    xarray.Dataset
        See :func:`vibimpact.sweeps.dataset.to_dataset`.

    Examples
    --------
    >>> import numpy as np, vibimpact as vi
    >>> ds = vi.sweep(vi.presets.get("fig8"), eta=np.arange(1.0, 1.1, 0.02))
    >>> ds.regime.dims
    ('eta',)
    """
    from .dataset import to_dataset

    if not isinstance(p, Params):
        raise ValueError(f"p must be vibimpact.Params, got {type(p).__name__}")
    etas = _grid(eta)
    settings, state0 = check_request(direction, analyses, settings, state0)
    blocks = _v.count("blocks", blocks, 1)
    workers = _v.count("workers", workers, 1)
    seed_periods = _v.count("seed_periods", seed_periods, 1)
    dirs = ("up", "down") if direction == "both" else (direction,)
    request = dict(params=p.replace(eta=1.0).as_dict(), eta=etas.tolist(), directions=dirs,
                   settings=settings.as_attrs(), state0=None if state0 is None else
                   state0.tolist(), continuation=continuation, blocks=blocks,
                   seed_periods=seed_periods)
    ckdir = ck.open_checkpoint(checkpoint, request, resume) if checkpoint else None

    tasks = []
    n = etas.size
    total = 0
    for d in dirs:
        order = etas if d == "up" else etas[::-1]
        done = {}
        if ckdir is not None:
            for i in range(n):
                r = ck.load_point(ckdir, d, i)
                if r is not None:
                    done[i] = r
        total += n - len(done)
        if not continuation:  # every point from state0: blocks need no seeding
            starts = _block_starts(n, blocks)
            seeds = {s: state0 for s in starts}
        else:
            starts = _block_starts(n, blocks)
            need = [s for s in starts[1:-1] if any(i not in done for i in
                                                   range(s, starts[starts.index(s) + 1]))]
            seeds = {0: state0}
            if need:
                seeds.update(_seeds(p, order, starts, state0, seed_periods))
        for b in range(len(starts) - 1):
            idx = list(range(starts[b], starts[b + 1]))
            if all(i in done for i in idx):
                tasks.append((p, order, d, idx, None, settings, None, None,
                              {i: done[i] for i in idx}))
                continue
            tasks.append((p, order, d, idx, seeds.get(starts[b]), settings,
                          not continuation, ckdir,
                          {i: done[i] for i in idx if i in done}))

    results = {d: [None] * n for d in dirs}
    bar = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=total, desc="classify", unit="pt", file=sys.stderr)
    try:
        if workers == 1 or len(tasks) == 1:
            global _PROGRESS
            q = _LocalBar(bar)
            _PROGRESS = q
            try:
                for t in tasks:
                    d, out = _run_block(t)
                    for i, r in out:
                        results[d][i] = r
            finally:
                _PROGRESS = None
        else:
            ctx = mp.get_context("fork" if sys.platform != "win32" else "spawn")
            q = ctx.Queue()
            pool = ctx.Pool(processes=min(workers, len(tasks)), initializer=_init_worker,
                            initargs=(q,))
            try:
                pending = [pool.apply_async(_run_block, (t,)) for t in tasks]
                while pending:
                    for r in [r for r in pending if r.ready()]:
                        d, out = r.get()  # re-raises a worker's exception
                        for i, res in out:
                            results[d][i] = res
                        pending.remove(r)
                    if pending:
                        try:
                            q.get(timeout=0.05)
                            if bar is not None:
                                bar.update(1)
                        except _queue.Empty:
                            pass
                _drain(q, bar)
                pool.close()
            except BaseException:
                # Ctrl-C or an error: kill the workers now (finished points are already in
                # the checkpoint; the points in flight are lost)
                pool.terminate()
                raise
            finally:
                pool.join()
    finally:
        if bar is not None:
            bar.close()
    return to_dataset(p, etas, dirs, results, settings, direction=direction,
                      continuation=continuation, blocks=blocks, command=command)


class _LocalBar:
    def __init__(self, bar):
        self.bar = bar

    def put(self, k):
        if self.bar is not None:
            self.bar.update(k)


def _drain(q, bar):
    while True:
        try:
            q.get_nowait()
        except (_queue.Empty, OSError, ValueError):
            return
        if bar is not None:
            bar.update(1)


def parse_range(text, name="eta", positive=True):
    """``"START:STOP:STEP"`` -> grid including STOP when it lies on the grid.

    Parameters
    ----------
    text : str
    name : str
        The quantity, named in error messages.
    positive : bool
        Refuse ``START <= 0`` (a forcing frequency).

    Raises
    ------
    ValueError
        Naming ``name``, for anything else, and for a grid of more than
        :data:`vibimpact._limits.MAX_POINTS` points (with the estimated time).
    """
    parts = str(text).split(":")
    if len(parts) != 3:
        raise ValueError(f"{name} must be START:STOP:STEP, got {text!r}")
    try:
        a, b, h = (float(x) for x in parts)
    except ValueError:
        raise ValueError(f"{name} must be three numbers START:STOP:STEP, got "
                         f"{text!r}") from None
    if not all(math.isfinite(v) for v in (a, b, h)):
        raise ValueError(f"{name} must be finite, got {text!r}")
    if h <= 0.0:
        raise ValueError(f"{name} STEP must be > 0, got {text!r}")
    if b < a:
        raise ValueError(f"{name} STOP must be >= START, got {text!r}")
    if positive and a <= 0.0:
        raise ValueError(f"{name} START must be > 0, got {text!r}")
    approx = (b - a) / h + 1.0
    if approx > 1e15:  # beyond exact integers (or inf): refuse without converting
        _limits.check_points(approx, name=name)
    count = int(math.floor((b - a) / h + 1e-9)) + 1
    _limits.check_points(count, name=name)
    return np.round(a + h * np.arange(count), 12)
