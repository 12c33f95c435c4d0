"""Small dense linear algebra that gives the same bits on every machine.

numpy's ``@``, ``np.linalg`` and numba's ``np.linalg`` call BLAS and LAPACK (OpenBLAS in
the wheels), which pick their inner kernels at run time from the processor (Haswell,
SkylakeX, Zen, ...): the same product or factorisation differs in its last bits from one
machine to the next.  The analyses feed such results back into the trajectory (a
transient's extrapolated jump, the state a sweep continues from, a Newton step of
shooting), and a vibro-impact orbit amplifies a last-bit difference until a label
changes.  The matrices here are small (at most a few dozen rows), so plain loops cost
little, and every sum below is taken in one fixed order with IEEE operations only (no
fast-math: the compiler may neither reorder nor fuse them): the results depend on the
inputs alone.

Functions
---------
dot, matmul : sums in index order.
qr : Householder QR, reduced (LAPACK's sign convention: ``R[k, k] = -sign(x_0) |x|``).
svd : one-sided Jacobi (Hestenes) SVD [1]_.
lstsq : minimum-norm least squares through :func:`svd` (as ``numpy.linalg.lstsq``).
solve : Gaussian elimination with partial pivoting.
eigvals : balancing, Hessenberg reduction by stabilised elimination and the Francis
    double-shift QR iteration [2]_ (the EISPACK ``balanc``/``elmhes``/``hqr`` sequence).

References
----------
.. [1] J. Demmel, K. Veselic, "Jacobi's method is more accurate than QR", SIAM J. Matrix
   Anal. Appl. 13 (1992) 1204-1245.
.. [2] J. H. Wilkinson, C. Reinsch, *Handbook for Automatic Computation, Vol. II: Linear
   Algebra*, Springer (1971), contributions II/11 and II/14.
"""
import math

import numpy as np
from numba import njit

from .jitopts import ALLOC

#: Jacobi rotations stop when every pair of columns is orthogonal to this relative level
_JACOBI_TOL = 1e-15
#: sweeps of the Jacobi SVD and iterations per eigenvalue of the QR algorithm
_MAX_SWEEPS = 60
_MAX_ITS = 60


@njit(**ALLOC)
def dot(a, b):
    """Sum of ``a[i] * b[i]`` in index order; 1-D float64 arrays of one length."""
    s = 0.0
    for i in range(a.size):
        s += a[i] * b[i]
    return s


@njit(**ALLOC)
def matmul(a, b):
    """``a @ b`` for 2-D float64 arrays, each entry summed in index order."""
    m, k = a.shape
    n = b.shape[1]
    c = np.zeros((m, n))
    for i in range(m):
        for j in range(n):
            s = 0.0
            for p in range(k):
                s += a[i, p] * b[p, j]
            c[i, j] = s
    return c


@njit(**ALLOC)
def _reflect(v, k, bk, a, j0):
    """Apply the Householder reflector ``I - bk v_k v_k^T`` (``v_k = v[k:, k]``) to the
    columns ``j0:`` of ``a`` (rows ``k:``), in place."""
    m = a.shape[0]
    for j in range(j0, a.shape[1]):
        s = 0.0
        for i in range(k, m):
            s += v[i, k] * a[i, j]
        s *= bk
        for i in range(k, m):
            a[i, j] -= s * v[i, k]


@njit(**ALLOC)
def qr(a):
    """Reduced Householder QR of an ``(m, n)`` array, ``m >= n``: ``(q (m, n), r (n, n))``."""
    m, n = a.shape
    r = a.copy()
    v = np.zeros((m, n))
    beta = np.zeros(n)
    for k in range(n):
        norm = 0.0
        for i in range(k, m):
            norm += r[i, k] * r[i, k]
        norm = math.sqrt(norm)
        if norm == 0.0:
            continue
        alpha = -norm if r[k, k] >= 0.0 else norm
        vv = 0.0
        for i in range(k, m):
            v[i, k] = r[i, k]
        v[k, k] -= alpha
        for i in range(k, m):
            vv += v[i, k] * v[i, k]
        if vv == 0.0:
            continue
        beta[k] = 2.0 / vv
        _reflect(v, k, beta[k], r, k)
    q = np.zeros((m, n))
    for i in range(n):
        q[i, i] = 1.0
    for k in range(n - 1, -1, -1):
        if beta[k] != 0.0:
            _reflect(v, k, beta[k], q, 0)
    out = np.zeros((n, n))
    for i in range(n):
        for j in range(i, n):
            out[i, j] = r[i, j]
    return q, out


@njit(**ALLOC)
def _rotate(u, p, q, c, s):
    for i in range(u.shape[0]):
        up = u[i, p]
        uq = u[i, q]
        u[i, p] = c * up - s * uq
        u[i, q] = s * up + c * uq


@njit(**ALLOC)
def svd(a):
    """Thin SVD of an ``(m, n)`` array, ``m >= n``, by one-sided Jacobi rotations.

    Returns ``(u (m, n), s (n,), v (n, n))`` with ``a = u diag(s) v.T``; ``s`` is not
    sorted, and columns of ``u`` whose ``s`` is 0 are 0.
    """
    m, n = a.shape
    u = a.copy()
    v = np.eye(n)
    for _ in range(_MAX_SWEEPS):
        rotated = False
        for p in range(n - 1):
            for q in range(p + 1, n):
                al = 0.0
                be = 0.0
                ga = 0.0
                for i in range(m):
                    al += u[i, p] * u[i, p]
                    be += u[i, q] * u[i, q]
                    ga += u[i, p] * u[i, q]
                if ga == 0.0 or abs(ga) <= _JACOBI_TOL * math.sqrt(al * be):
                    continue
                rotated = True
                zeta = (be - al) / (2.0 * ga)
                t = 1.0 / (abs(zeta) + math.sqrt(1.0 + zeta * zeta))
                if zeta < 0.0:
                    t = -t
                c = 1.0 / math.sqrt(1.0 + t * t)
                _rotate(u, p, q, c, c * t)
                _rotate(v, p, q, c, c * t)
        if not rotated:
            break
    s = np.zeros(n)
    for j in range(n):
        nrm = 0.0
        for i in range(m):
            nrm += u[i, j] * u[i, j]
        s[j] = math.sqrt(nrm)
        for i in range(m):
            u[i, j] = u[i, j] / s[j] if s[j] > 0.0 else 0.0
    return u, s, v


@njit(**ALLOC)
def lstsq(a, b, rcond):
    """Minimum-norm least-squares solution of ``a x = b``.

    ``a`` is ``(m, n)``, ``b`` is ``(m, k)``; singular values at or below ``rcond`` times
    the largest are treated as 0 (``rcond < 0``: machine epsilon times ``max(m, n)``, as
    ``numpy.linalg.lstsq(rcond=None)``).  Returns ``(x (n, k), rank)``.
    """
    m, n = a.shape
    if rcond < 0.0:
        rcond = 2.220446049250313e-16 * max(m, n)
    if m >= n:
        u, s, v = svd(a)
    else:  # a.T = u s v.T, so a = v s u.T: swap the roles of the factors
        v, s, u = svd(a.T.copy())
    smax = 0.0
    for j in range(s.size):
        smax = max(smax, s[j])
    x = np.zeros((n, b.shape[1]))
    rank = 0
    for j in range(s.size):
        if not s[j] > rcond * smax:
            continue
        rank += 1
        for col in range(b.shape[1]):
            w = 0.0
            for i in range(m):
                w += u[i, j] * b[i, col]
            w /= s[j]
            for i in range(n):
                x[i, col] += v[i, j] * w
    return x, rank


@njit(**ALLOC)
def solve(a, b):
    """Solve ``a x = b`` (``a`` (n, n), ``b`` (n,)) by elimination with partial pivoting.

    Returns ``(x, ok)``; ``ok`` is False (and ``x`` NaN) when a pivot is exactly 0, where
    ``numpy.linalg.solve`` raises ``LinAlgError``.
    """
    n = a.shape[0]
    lu = a.copy()
    x = b.copy()
    for k in range(n):
        piv = k
        for i in range(k + 1, n):
            if abs(lu[i, k]) > abs(lu[piv, k]):
                piv = i
        if lu[piv, k] == 0.0:
            return np.full(n, np.nan), False
        if piv != k:
            for j in range(n):
                lu[k, j], lu[piv, j] = lu[piv, j], lu[k, j]
            x[k], x[piv] = x[piv], x[k]
        for i in range(k + 1, n):
            f = lu[i, k] / lu[k, k]
            for j in range(k + 1, n):
                lu[i, j] -= f * lu[k, j]
            x[i] -= f * x[k]
    for i in range(n - 1, -1, -1):
        s = x[i]
        for j in range(i + 1, n):
            s -= lu[i, j] * x[j]
        x[i] = s / lu[i, i]
    return x, True


@njit(**ALLOC)
def _balance(a):
    """Scale rows and columns by powers of 2 (exact) towards equal norms, in place."""
    n = a.shape[0]
    done = False
    while not done:
        done = True
        for i in range(n):
            c = 0.0
            r = 0.0
            for j in range(n):
                if j != i:
                    c += abs(a[j, i])
                    r += abs(a[i, j])
            if c == 0.0 or r == 0.0:
                continue
            g = r / 2.0
            f = 1.0
            s = c + r
            while c < g:
                f *= 2.0
                c *= 4.0
            g = r * 2.0
            while c > g:
                f /= 2.0
                c /= 4.0
            if (c + r) / f < 0.95 * s:
                done = False
                for j in range(n):
                    a[i, j] /= f
                for j in range(n):
                    a[j, i] *= f


@njit(**ALLOC)
def _hessenberg(a):
    """Reduce to upper Hessenberg form by stabilised elimination, in place."""
    n = a.shape[0]
    for m in range(1, n - 1):
        x = 0.0
        piv = m
        for j in range(m, n):
            if abs(a[j, m - 1]) > abs(x):
                x = a[j, m - 1]
                piv = j
        if piv != m:
            for j in range(m - 1, n):
                a[piv, j], a[m, j] = a[m, j], a[piv, j]
            for j in range(n):
                a[j, piv], a[j, m] = a[j, m], a[j, piv]
        if x != 0.0:
            for i in range(m + 1, n):
                y = a[i, m - 1]
                if y != 0.0:
                    y /= x
                    a[i, m - 1] = y
                    for j in range(m, n):
                        a[i, j] -= y * a[m, j]
                    for j in range(n):
                        a[j, m] += y * a[j, i]
    for i in range(2, n):
        for j in range(i - 1):
            a[i, j] = 0.0


@njit(**ALLOC)
def _deflation_point(a, nn, anorm):
    """Largest ``l <= nn`` whose subdiagonal entry is negligible (set to 0), else 0."""
    for l in range(nn, 0, -1):
        s = abs(a[l - 1, l - 1]) + abs(a[l, l])
        if s == 0.0:
            s = anorm
        if abs(a[l, l - 1]) + s == s:
            a[l, l - 1] = 0.0
            return l
    return 0


@njit(**ALLOC)
def _francis_start(a, l, nn, x, y, w):
    """Row ``m`` where the double-shift bulge starts, and its first column ``(p, q, r)``."""
    m = nn - 2
    while True:
        z = a[m, m]
        r = x - z
        s = y - z
        p = (r * s - w) / a[m + 1, m] + a[m, m + 1]
        q = a[m + 1, m + 1] - z - r - s
        r = a[m + 2, m + 1]
        s = abs(p) + abs(q) + abs(r)
        p /= s
        q /= s
        r /= s
        if m == l:
            break
        u = abs(a[m, m - 1]) * (abs(q) + abs(r))
        v = abs(p) * (abs(a[m - 1, m - 1]) + abs(z) + abs(a[m + 1, m + 1]))
        if u + v == v:
            break
        m -= 1
    return m, p, q, r


@njit(**ALLOC)
def _francis_sweep(a, l, m, nn, p, q, r):
    """Chase the double-shift bulge from row ``m`` down to ``nn``, in place."""
    for i in range(m + 2, nn + 1):
        a[i, i - 2] = 0.0
        if i != m + 2:
            a[i, i - 3] = 0.0
    x = 0.0
    for k in range(m, nn):
        if k != m:
            p = a[k, k - 1]
            q = a[k + 1, k - 1]
            r = a[k + 2, k - 1] if k != nn - 1 else 0.0
            x = abs(p) + abs(q) + abs(r)
            if x != 0.0:
                p /= x
                q /= x
                r /= x
        s = math.sqrt(p * p + q * q + r * r)
        if p < 0.0:
            s = -s
        if s == 0.0:
            continue
        if k == m:
            if l != m:
                a[k, k - 1] = -a[k, k - 1]
        else:
            a[k, k - 1] = -s * x
        p += s
        x = p / s
        y = q / s
        z = r / s
        q /= p
        r /= p
        for j in range(k, nn + 1):
            p = a[k, j] + q * a[k + 1, j]
            if k != nn - 1:
                p += r * a[k + 2, j]
                a[k + 2, j] -= p * z
            a[k + 1, j] -= p * y
            a[k, j] -= p * x
        for i in range(l, min(nn, k + 3) + 1):
            p = x * a[i, k] + y * a[i, k + 1]
            if k != nn - 1:
                p += z * a[i, k + 2]
                a[i, k + 2] -= p * r
            a[i, k + 1] -= p * q
            a[i, k] -= p


@njit(**ALLOC)
def _hqr(a, wr, wi):
    """Eigenvalues of an upper Hessenberg array (destroyed) into ``wr + i wi``.

    Returns False when an eigenvalue did not converge in :data:`_MAX_ITS` iterations.
    """
    n = a.shape[0]
    anorm = 0.0
    for i in range(n):
        for j in range(max(i - 1, 0), n):
            anorm += abs(a[i, j])
    nn = n - 1
    t = 0.0
    while nn >= 0:
        its = 0
        while True:
            l = _deflation_point(a, nn, anorm)
            x = a[nn, nn]
            if l == nn:  # one root found
                wr[nn] = x + t
                wi[nn] = 0.0
                nn -= 1
                break
            y = a[nn - 1, nn - 1]
            w = a[nn, nn - 1] * a[nn - 1, nn]
            if l == nn - 1:  # two roots found
                p = 0.5 * (y - x)
                q = p * p + w
                z = math.sqrt(abs(q))
                x += t
                if q >= 0.0:
                    z = p + (z if p >= 0.0 else -z)
                    wr[nn - 1] = x + z
                    wr[nn] = x - w / z if z != 0.0 else x + z
                    wi[nn - 1] = 0.0
                    wi[nn] = 0.0
                else:
                    wr[nn - 1] = x + p
                    wr[nn] = x + p
                    wi[nn - 1] = -z
                    wi[nn] = z
                nn -= 2
                break
            if its == _MAX_ITS:
                return False
            if its == 10 or its == 20:  # exceptional shift
                t += x
                for i in range(nn + 1):
                    a[i, i] -= x
                s = abs(a[nn, nn - 1]) + abs(a[nn - 1, nn - 2])
                x = 0.75 * s
                y = x
                w = -0.4375 * s * s
            its += 1
            m, p, q, r = _francis_start(a, l, nn, x, y, w)
            _francis_sweep(a, l, m, nn, p, q, r)
    return True


@njit(**ALLOC)
def eigvals(a):
    """Eigenvalues of a real square array (complex, unsorted); NaN if they fail to converge."""
    n = a.shape[0]
    h = a.copy()
    _balance(h)
    _hessenberg(h)
    wr = np.zeros(n)
    wi = np.zeros(n)
    out = np.empty(n, dtype=np.complex128)
    if not _hqr(h, wr, wi):
        out[:] = complex(np.nan, np.nan)
        return out
    for i in range(n):
        out[i] = complex(wr[i], wi[i])
    return out
