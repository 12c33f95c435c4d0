"""The 0-1 test for chaos (Gottwald & Melbourne 2009) on series with known character."""
import numpy as np
import pytest

from vibimpact.analysis import chaos01

GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0


def logistic(m, x0=0.3, r=4.0, transient=1000):
    x = x0
    for _ in range(transient):
        x = r * x * (1.0 - x)
    out = np.empty(m)
    for k in range(m):
        x = r * x * (1.0 - x)
        out[k] = x
    return out


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("m", [1000, 2000])
def test_period_three_sequence_with_tiny_noise_is_regular(seed, m):
    """A period-3 sequence plus 1e-9 noise gives K < 0.1 (c = 2 pi / 3 is a resonance,
    discarded by the median over c)."""
    noise = 1e-9 * np.random.default_rng(seed).standard_normal(m)
    x = np.tile([0.2, 0.7, 0.4], m // 3 + 1)[:m] + noise
    assert chaos01.test01(x, seed=seed) < 0.1


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_sampled_sine_is_regular(seed):
    """x_k = sin(0.7 k) + 0.3 cos(1.9 k), periodic in continuous time, gives K < 0.1."""
    k = np.arange(2000)
    assert chaos01.test01(np.sin(0.7 * k) + 0.3 * np.cos(1.9 * k), seed=seed) < 0.1


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("m", [1000, 2000, 4000])
def test_two_frequency_quasiperiodic_series_is_regular(seed, m):
    """x_k = cos(2 pi a k) + 0.5 cos(2 pi b k) with incommensurate a (golden) and
    b = sqrt 2 gives K < 0.1."""
    k = np.arange(m)
    x = np.cos(2.0 * np.pi * GOLDEN * k) + 0.5 * np.cos(2.0 * np.pi * np.sqrt(2.0) * k + seed)
    assert chaos01.test01(x, seed=seed) < 0.1


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("x0", [0.1, 0.3, 0.41])
def test_logistic_map_at_r4_is_chaotic(seed, x0):
    """The logistic map at r = 4 (N = 2000 after a transient) gives K > 0.9."""
    assert chaos01.test01(logistic(2000, x0=x0), seed=seed) > 0.9


def test_constant_series_is_regular_and_constant_tol_absorbs_noise():
    """A constant series returns 0.0; 1e-9 noise on a fixed point reads as chaos (the test
    has no tolerance) unless constant_tol is raised above it."""
    assert chaos01.test01(np.full(500, 2.5)) == 0.0
    x = 0.4 + 1e-9 * np.random.default_rng(0).standard_normal(1000)
    assert chaos01.test01(x) > 0.9
    assert chaos01.test01(x, constant_tol=1e-6) == 0.0


def test_result_is_deterministic_for_a_seed_and_accepts_given_c():
    """The same seed gives the same K; explicit c values are used as given."""
    x = logistic(1000)
    assert chaos01.test01(x, seed=5) == chaos01.test01(x, seed=5)
    assert chaos01.test01(x, c=[1.0, 1.5, 2.0]) > 0.9


def test_mean_square_displacement_matches_the_direct_sum():
    """The FFT evaluation of M_c(n) equals the direct average of |z(j+n) - z(j)|^2."""
    x = np.random.default_rng(2).standard_normal(300)
    c = np.array([0.8, 1.7])
    M = chaos01.mean_square_displacement(x, c, 30)
    j = np.arange(1, 301)
    for i, ci in enumerate(c):
        z = np.cumsum(x * np.exp(1j * ci * j))
        direct = [np.mean(np.abs(z[n:] - z[:-n]) ** 2) for n in range(1, 31)]
        np.testing.assert_allclose(M[i], direct, rtol=1e-10)


@pytest.mark.parametrize("kwargs,name", [
    (dict(series=np.ones(10)), "series"),
    (dict(series=np.ones((30, 2))), "series"),
    (dict(series=np.r_[np.ones(30), np.nan]), "series"),
    (dict(series=np.arange(50.0), n_c=0), "n_c"),
    (dict(series=np.arange(50.0), n_cut=50), "n_cut"),
    (dict(series=np.arange(50.0), n_cut=1), "n_cut"),
    (dict(series=np.arange(50.0), c=[np.nan]), "c"),
    (dict(series=np.arange(50.0), constant_tol=-1.0), "constant_tol"),
])
def test_bad_test01_input_raises_value_error_naming_argument(kwargs, name):
    """Short, non-1-D or non-finite series and bad options raise ValueError naming them."""
    with pytest.raises(ValueError, match=name):
        chaos01.test01(**kwargs)


def test_2000_points_use_one_batched_fft_pair_for_all_frequencies(monkeypatch):
    """Hypothesis (the cost claim O(n_c N log N) of ``mean_square_displacement``, counted
    rather than timed -- speed itself belongs in the benchmarks): on N = 2000 with the
    default 100 frequencies, the test makes exactly one forward and one inverse FFT, each
    over all 100 frequencies at once on the zero-padded length 4096 (the next power of two
    >= 2N), and no per-frequency or per-lag transform."""
    calls = []
    fft, ifft = np.fft.fft, np.fft.ifft

    def counted(name, fn):
        def wrapper(a, n=None, axis=-1, **kw):
            out = fn(a, n=n, axis=axis, **kw)
            calls.append((name, np.shape(a), out.shape))
            return out
        return wrapper

    monkeypatch.setattr(np.fft, "fft", counted("fft", fft))
    monkeypatch.setattr(np.fft, "ifft", counted("ifft", ifft))
    assert chaos01.test01(logistic(2000)) > 0.9
    assert calls == [("fft", (100, 2000), (100, 4096)),
                     ("ifft", (100, 4096), (100, 4096))]
