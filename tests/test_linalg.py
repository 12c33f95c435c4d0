"""The package's own small linear algebra: right, and the same on every processor.

numpy's and numba's ``@`` and ``np.linalg`` go through OpenBLAS, whose kernels are chosen
at run time from the processor; the analyses feed such results back into trajectories, so
the package uses :mod:`vibimpact._kernel.linalg` instead.  These tests check its values
against LAPACK (to rounding) and that a sweep gives the same bits whichever BLAS kernels
and numpy SIMD paths the process is given.
"""
import json
import os
import platform
import subprocess
import sys

import numpy as np
import pytest

from vibimpact._kernel.boundary import dot, eigvals, lstsq, matmul, solve
from vibimpact._kernel.linalg import qr, svd


def _sorted(z):
    return np.sort_complex(np.asarray(z, dtype=complex))


@pytest.mark.parametrize("n", [1, 2, 3, 4, 6, 9])
def test_eigvals_agree_with_lapack_on_badly_scaled_random_matrices(n):
    """Hypothesis: the balanced Hessenberg-QR eigenvalues equal LAPACK's to 1e-12 relative
    to the spectral radius, complex pairs included, rows scaled over 1e-4 .. 1e4."""
    rng = np.random.default_rng(n)
    for _ in range(100):
        a = rng.standard_normal((n, n)) * np.exp(rng.uniform(-9.0, 9.0, (n, 1)))
        ref = _sorted(np.linalg.eigvals(a))
        got = _sorted(eigvals(a))
        assert np.abs(got - ref).max() <= 1e-12 * np.abs(ref).max()


def test_eigvals_of_a_rotation_and_a_jordan_block_are_exact():
    """Hypothesis: a rotation by 90 degrees has eigenvalues +-i and a 2x2 Jordan block
    with diagonal 1 has the double eigenvalue 1, without rounding error."""
    assert _sorted(eigvals(np.array([[0.0, -1.0], [1.0, 0.0]]))).tolist() == [-1j, 1j]
    assert eigvals(np.array([[1.0, 1.0], [0.0, 1.0]])).tolist() == [1.0, 1.0]


@pytest.mark.parametrize("shape", [(7, 3), (3, 7), (5, 5)])
def test_lstsq_is_the_minimum_norm_solution_of_numpy(shape):
    """Hypothesis: lstsq returns numpy's minimum-norm least-squares solution and rank, also
    for a rank-deficient matrix (a column repeated)."""
    rng = np.random.default_rng(1)
    a = rng.standard_normal(shape)
    a[:, -1] = 2.0 * a[:, 0]
    b = rng.standard_normal((shape[0], 2))
    x, rank = lstsq(a, b, 1e-10)
    ref, _, rank_ref, _ = np.linalg.lstsq(a, b, rcond=1e-10)
    assert rank == rank_ref
    np.testing.assert_allclose(x, ref, rtol=0, atol=1e-12 * np.abs(ref).max())


def test_qr_and_svd_reconstruct_their_matrix_with_orthonormal_factors():
    """Hypothesis: q r = a with q's columns orthonormal and r upper triangular; u s v.T = a
    with orthonormal u and v; |r_kk| equals LAPACK's."""
    a = np.random.default_rng(2).standard_normal((6, 4))
    q, r = qr(a)
    np.testing.assert_allclose(q @ r, a, atol=1e-14)
    np.testing.assert_allclose(q.T @ q, np.eye(4), atol=1e-14)
    assert np.all(np.tril(r, -1) == 0.0)
    np.testing.assert_allclose(np.abs(np.diag(r)), np.abs(np.diag(np.linalg.qr(a)[1])),
                               rtol=1e-13)
    u, s, v = svd(a)
    np.testing.assert_allclose(u @ np.diag(s) @ v.T, a, atol=1e-14)
    np.testing.assert_allclose(np.sort(s), np.sort(np.linalg.svd(a)[1]), rtol=1e-13)


def test_solve_dot_and_matmul_agree_with_numpy_and_report_a_singular_matrix():
    """Hypothesis: solve, dot and matmul equal numpy's to rounding; an exactly singular
    matrix gives ok = False and NaN (where numpy raises LinAlgError)."""
    rng = np.random.default_rng(3)
    a, b = rng.standard_normal((5, 5)), rng.standard_normal(5)
    x, ok = solve(a, b)
    assert ok
    np.testing.assert_allclose(x, np.linalg.solve(a, b), rtol=1e-12)
    assert dot(b, b) == pytest.approx(float(b @ b), rel=1e-15)
    np.testing.assert_allclose(matmul(a, a), a @ a, rtol=1e-13)
    x, ok = solve(np.zeros((2, 2)), np.ones(2))
    assert not ok and np.all(np.isnan(x))


_SWEEP = """
import json, sys
import numpy as np
import vibimpact as vi
ds = vi.sweep(vi.presets.get("fig11"), np.round(np.arange(1.10, 1.16 + 1e-9, 0.005), 6),
              analyses=("period", "impacts", "response", "lyapunov"), continuation=vi.Continuation(blocks=1))
print(json.dumps({k: np.asarray(ds[k].values, dtype=float).tobytes().hex()
                  for k in ("R_m", "final_state", "lyapunov", "contraction")}))
"""

#: the processor-dependent paths pinned to two different choices
#: two settings of the BLAS (and numpy's SIMD paths) per processor family: OpenBLAS
#: core names are those of the machine; elsewhere, two thread counts change its blocking
_ENVIRONMENTS = {
    "x86_64": [
        {"OPENBLAS_CORETYPE": "Haswell"},
        {"OPENBLAS_CORETYPE": "Prescott",
         "NPY_DISABLE_CPU_FEATURES": "AVX512F AVX512CD AVX512_SKX AVX512_CLX AVX512_CNL "
                                     "AVX512_ICL AVX512_SPR AVX2 FMA3"}],
    "aarch64": [{"OPENBLAS_CORETYPE": "NEOVERSEN1"}, {"OPENBLAS_CORETYPE": "ARMV8"}],
}.get(platform.machine(), [{"OPENBLAS_NUM_THREADS": "1"}, {"OPENBLAS_NUM_THREADS": "2"}])


@pytest.mark.slow  # a sweep in a subprocess per BLAS setting
def test_a_sweep_gives_the_same_bits_whichever_blas_kernels_run():
    """Hypothesis: a fig11 sweep through the settling extrapolation, shooting and the
    Lyapunov QR gives bit-identical results with OpenBLAS forced to its Haswell and to its
    Prescott kernels (and numpy's AVX paths off; on other processors, two kernels or
    thread counts of theirs): nothing the results depend on goes through
    processor-selected BLAS code."""
    outs = []
    for extra in _ENVIRONMENTS:
        env = dict(os.environ, **extra)
        proc = subprocess.run([sys.executable, "-c", _SWEEP], env=env, capture_output=True,
                              text=True, check=True)
        outs.append(json.loads(proc.stdout.strip().splitlines()[-1]))
    assert outs[0] == outs[1]
