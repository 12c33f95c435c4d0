"""The end of a period of a Benettin run: QR re-orthonormalisation (``@njit``).

:func:`renormalise` is called by :func:`.driver.integrate` in its Benettin mode after
every forcing period of a variational model (:mod:`.variational`): the state followed by
``m`` tangent columns.
"""
import math

import numpy as np
from numba import njit

from .integrator import DIVERGED_BOUND, OK
from .jitopts import INNER_ALLOC
from .linalg import qr


@njit(**INNER_ALLOC)
def renormalise(y, n, bound, logs, states, j):
    """End of period ``j`` of a Benettin run: check and store the state, re-orthonormalise
    the tangent columns.

    The model state ``y[:n]`` is checked against ``bound`` (DIVERGED_BOUND beyond it)
    and stored as row ``j`` of ``states``; the ``m`` tangent columns ``y[n + c n : n +
    (c + 1) n]`` are replaced by the columns of ``Q`` of their QR factorisation, signed
    so that ``R`` has a positive diagonal, and ``log |R_cc|`` goes to ``logs[j, c]``
    (a column with ``R_cc = 0``, a direction the flow annihilated, stays zero: ``-inf``)
    (Benettin, Galgani, Giorgilli & Strelcyn 1980, Meccanica 15, 9-30).  Returns the
    status.
    """
    m = (y.size - n) // n
    for i in range(n):
        if abs(y[i]) > bound:
            return DIVERGED_BOUND
        states[j, i] = y[i]
    Q = np.empty((n, m))
    for c in range(m):
        for i in range(n):
            Q[i, c] = y[n + c * n + i]
    q, r = qr(Q)
    for c in range(m):
        rc = r[c, c]
        if rc == 0.0:
            # a direction the flow has annihilated (a saltation matrix onto a sliding
            # surface that attracts in finite time): it stays lost -- Q's column would be
            # an arbitrary complement, and integrating it would invent an exponent
            logs[j, c] = -np.inf
            for i in range(n):
                y[n + c * n + i] = 0.0
            continue
        logs[j, c] = math.log(abs(rc))
        sg = 1.0 if rc >= 0.0 else -1.0
        for i in range(n):
            y[n + c * n + i] = sg * q[i, c]
    return OK
