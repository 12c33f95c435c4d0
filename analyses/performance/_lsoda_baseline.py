"""numbalsoda (LSODA called from numba) as a work-precision baseline (issue 6, part 1).

numbalsoda (Wogan, https://github.com/Nicholaswogan/numbalsoda) wraps a C++ port of
LSODA (Petzold 1983, "Automatic selection of methods for solving stiff and nonstiff
systems of ordinary differential equations", SIAM J. Sci. Stat. Comput. 4, 136-148) so
that it can be called from ``@njit`` code with a ``@cfunc`` right-hand side: no Python in
the loop, which is what a numba user would reach for.

It has no event location.  To be fair *to it* it gets the switches for free: it
integrates each smooth segment between the switch times of the reference solution, in
that segment's mode, and is restarted at every switch and stopped at every strobe time
(the right-hand side is the kernel's :func:`vibimpact._kernel.rotor.rhs_mode`).  Its
time therefore excludes any event location, which our integrators pay for.

numbalsoda is optional (``pip install numbalsoda`` builds C++ and Fortran and needs
``gfortran``); :func:`available` says whether it is importable here.
"""
import numpy as np
from numba import carray, cfunc, njit

from vibimpact._kernel.rotor import N_MODE, PARAM_NAMES, init_mode, rhs_mode

#: user data layout: the parameters, the two mode entries, the RHS evaluation counter
N_PAR = len(PARAM_NAMES)
D_MODE0, D_MODE1, D_COUNT = N_PAR, N_PAR + 1, N_PAR + 2


def available():
    """numbalsoda's version string, or None when it cannot be imported."""
    try:
        import numbalsoda
    except ImportError:
        return None
    try:
        from importlib.metadata import version
        return version("numbalsoda")
    except Exception:  # pragma: no cover - metadata missing
        return getattr(numbalsoda, "__version__", "unknown version")


_RUNNER = None


def _build():
    """Compile the callback and the driver once per process (numbalsoda imported here)."""
    global _RUNNER
    if _RUNNER is not None:
        return _RUNNER
    import numbalsoda
    lsoda = numbalsoda.lsoda

    @cfunc(numbalsoda.lsoda_sig)
    def f(t, u_, du_, d_):
        u = carray(u_, (4,))
        du = carray(du_, (4,))
        d = carray(d_, (N_PAR + 3,))
        rhs_mode(t, u, d[:N_PAR], int(d[D_MODE0]), int(d[D_MODE1]), du)
        d[D_COUNT] += 1.0

    @njit
    def drive(funcptr, u0, sw_t, sw_mode, mode0, t_strobe, data, rtol, atol):
        """States at ``t_strobe`` (row 0 = ``u0``); status 0 or 1 (LSODA failed)."""
        ns = t_strobe.size
        out = np.empty((ns, 4))
        out[0] = u0
        u = u0.copy()
        t = t_strobe[0]
        data[D_MODE0] = mode0[0]
        data[D_MODE1] = mode0[1]
        j = 1
        k = 0
        while j < ns:
            tb = sw_t[k] if k < sw_t.size else np.inf
            if tb <= t:  # switches at one instant: only the mode changes
                data[D_MODE0] = sw_mode[k, 0]
                data[D_MODE1] = sw_mode[k, 1]
                k += 1
                continue
            m = 0
            while j + m < ns and t_strobe[j + m] < tb:
                m += 1
            switch = tb < t_strobe[ns - 1]
            te = np.empty(1 + m + (1 if switch else 0))
            te[0] = t
            for i in range(m):
                te[1 + i] = t_strobe[j + i]
            if switch:
                te[1 + m] = tb
            usol, ok = lsoda(funcptr, u, te, data, rtol, atol, 100000)
            if not ok:
                return out, 1
            for i in range(m):
                out[j + i] = usol[1 + i]
            u = usol[te.size - 1].copy()
            t = te[te.size - 1]
            j += m
            if switch:
                data[D_MODE0] = sw_mode[k, 0]
                data[D_MODE1] = sw_mode[k, 1]
                k += 1
        return out, 0

    _RUNNER = (f.address, drive)
    return _RUNNER


def make_runner(p, s0, ref, t_strobe, tol):
    """A callable running numbalsoda LSODA at ``rtol = atol = tol`` over ``t_strobe``.

    Parameters
    ----------
    p : vibimpact.Params
    s0 : array_like, shape (4,)
        State at ``t_strobe[0] = 0``.
    ref : vibimpact.Run
        The reference run over the same interval: its terminal events (contact, friction)
        give the switch times and the mode of every segment.
    t_strobe : ndarray, shape (m,)
    tol : float

    Returns
    -------
    callable
        ``fn() -> (strobe states (m, 4), RHS evaluations)``; raises RuntimeError when LSODA
        reports a failure.
    """
    address, drive = _build()
    ev = ref.events
    term = (ev["which"] <= 1) & np.any(ev["mode_before"] != ev["mode_after"], axis=1)
    sw_t = np.ascontiguousarray(ev["t"][term], dtype=np.float64)
    sw_mode = np.ascontiguousarray(ev["mode_after"][term], dtype=np.float64)
    m0 = np.zeros(N_MODE, dtype=np.int64)
    init_mode(0.0, np.asarray(s0, dtype=np.float64), p.as_array(), m0)
    mode0 = m0.astype(np.float64)
    u0 = np.ascontiguousarray(s0, dtype=np.float64)
    ts = np.ascontiguousarray(t_strobe, dtype=np.float64)

    def fn():
        data = np.zeros(N_PAR + 3)
        data[:N_PAR] = p.as_array()
        out, status = drive(address, u0, sw_t, sw_mode, mode0, ts, data, tol, tol)
        if status:
            raise RuntimeError(f"numbalsoda LSODA failed at tol {tol:.0e}")
        return out, int(data[D_COUNT])
    return fn
