"""Tests of the heated DSMC kernels (particles._dsmc_heated) and of the heated runs'
statistics after the move of the kicks and hard-rod candidates to the wyrand word.

Tolerances: counts are Binomial (4.5 standard deviations); run statistics use 4 batch
standard errors of the run itself; the seed-to-seed check of T and a2 against the FEM
steady state uses the spread of the seeds.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

import kinetic_fem as kf
from particles import _dsmc_heated as heated
from particles import _dsmc_segments as seg
from particles import dsmc, rng
from particles.sampling import load_checkpoint, save_checkpoint

TABLES = rng.ziggurat_tables()
_MASK = (1 << 64) - 1


def _heated(seed=0):
    return rng.heated_state(np.random.SeedSequence(seed))


@pytest.fixture
def wrapping():
    """The kernels' uint64 arithmetic wraps on purpose; as plain Python numpy warns."""
    with np.errstate(over="ignore"):
        yield


def _wyrand_reference(w):
    """wyrand in Python big ints: ``(output, new counter)``."""
    w = (w + 0xA0761D6478BD642F) & _MASK
    p = w * (w ^ 0xE7037ED1A0B428DB)
    return ((p >> 64) ^ p) & _MASK, w


def _collide_reference(v, m, alpha, g_max, w):
    """The one-draw thinning loop of collide_heated in plain Python (big ints)."""
    n = len(v)
    scale = g_max * (1.0 / 9007199254740992.0)
    acc, g2 = 0, 0.0
    for _ in range(m):
        r, w = _wyrand_reference(w)
        i, low = (r * n) >> 64, (r * n) & _MASK
        j, low = (low * (n - 1)) >> 64, (low * (n - 1)) & _MASK
        j += j >= i
        threshold = float(low >> 11) * scale
        g = v[i] - v[j]
        if abs(g) > threshold:
            dv = 0.5 * (1.0 + alpha) * g
            v[i], v[j] = v[i] - dv, v[j] + dv
            acc += 1
            g2 += g * g
    return (acc, g2), w


# ----------------------------------------------------------------------------- generator
def test_wyrand_matches_reference(wrapping):
    s = _heated(5)
    w = int(s[rng.WYRAND_WORD])
    expected = []
    for _ in range(50):
        r, w = _wyrand_reference(w)
        expected.append(r)
    assert [int(rng.wyrand_next(s)) for _ in range(50)] == expected
    assert int(s[rng.WYRAND_WORD]) == w


def test_kick_normals_are_standard_normal():
    """The kick's normals (wyrand fast path, xoshiro256** slow paths): KS, moments to
    the 6th, the tail sampler's share and no lag-one correlation, from 2e6 draws."""
    out = np.empty(2_000_000)
    rng.fill_normal(out, _heated(2), *TABLES)
    assert stats.kstest(out, "norm").pvalue > 1e-3
    se = 1 / math.sqrt(out.size)
    assert abs(out.mean()) < 4 * se
    assert abs(out.var() - 1) < 4 * math.sqrt(2) * se
    assert abs(np.mean(out**4) - 3) < 4 * math.sqrt(96) * se
    assert abs(np.mean(out**6) - 15) < 4 * math.sqrt(10395 - 225) * se
    assert abs(np.mean(out[1:] * out[:-1])) < 4 * se
    assert abs(np.mean(out[1:] ** 2 * out[:-1] ** 2) - 1) < 4 * math.sqrt(8) * se
    tail = np.mean(np.abs(out) > rng.ZIGGURAT_R)
    p = math.erfc(rng.ZIGGURAT_R / math.sqrt(2))
    assert abs(tail - p) < 4 * math.sqrt(p / out.size)


def test_heated_kernels_refuse_a_four_word_state():
    four = np.random.SeedSequence(1).generate_state(4, dtype=np.uint64)
    with pytest.raises(ValueError, match="5-word state"):
        heated.kick(np.zeros(10), 1.0, 0.1, four, *TABLES)


# ----------------------------------------------------------------------------- collisions
def test_heated_pairs_are_uniform_and_distinct():
    """With v one-hot at k and g_max = 1 a candidate is accepted iff k is in the pair:
    Binomial(m, 2/N) for every k (``alpha = -1``: the collision is a no-op)."""
    n, m = 10, 200_000
    s = _heated(3)
    counts = []
    for k in range(n):
        v = np.zeros(n)
        v[k] = 1.0
        counts.append(heated.collide_heated(v, m, -1.0, 1.0, s)[0])
    p = 2 / n
    z = (np.array(counts) - m * p) / math.sqrt(m * p * (1 - p))
    assert np.all(np.abs(z) < 4.5)
    assert stats.chisquare(counts).pvalue > 1e-3


@pytest.mark.parametrize("g", [0.05, 0.3, 0.77, 0.999])
def test_heated_acceptance_probability_is_g_over_gmax(g):
    """N = 2, v = (0, g), g_max = 1: each candidate is accepted with probability g (the
    threshold from the last low word is uniform)."""
    m = 400_000
    acc = heated.collide_heated(np.array([0.0, g]), m, -1.0, 1.0, _heated(4))[0]
    assert abs(acc - m * g) < 4.5 * math.sqrt(m * g * (1 - g))


@pytest.mark.parametrize("alpha", [0.0, 0.6, 0.99])
def test_heated_collisions_conserve_momentum_and_keep_majorant(alpha, wrapping):
    v = np.random.default_rng(4).normal(size=1000)
    p0, e0 = v.sum(), np.sum(v**2)
    lo, hi = seg.extent(v)
    acc, g2 = heated.collide_heated(v, 20_000, alpha, hi - lo, _heated(4))
    assert acc > 1000
    assert abs(v.sum() - p0) < 1e-10
    assert np.sum(v**2) == pytest.approx(e0 - 0.5 * (1 - alpha**2) * g2, rel=1e-10)
    lo2, hi2 = seg.extent(v)
    assert lo2 >= lo and hi2 <= hi


@pytest.mark.parametrize("n", [2, 3, 40])
def test_heated_collide_plain_and_batched_are_the_sequential_algorithm(n, wrapping):
    v0 = np.random.default_rng(n).normal(size=n)
    lo, hi = seg.extent(v0)
    ref_v = list(v0)
    s0 = _heated(8)
    ref, ref_w = _collide_reference(ref_v, 300, 0.4, hi - lo, int(s0[rng.WYRAND_WORD]))
    for batch in (-1, 0, 1, 7, 64, 1000):
        v, s = v0.copy(), _heated(8)
        got = heated.collide_heated(v, 300, 0.4, hi - lo, s, batch)
        assert got == ref, batch
        np.testing.assert_array_equal(v, ref_v)
        assert int(s[rng.WYRAND_WORD]) == ref_w
        np.testing.assert_array_equal(s[:4], s0[:4])  # xoshiro256** words untouched


def test_two_draw_candidates_above_one_draw_limit(wrapping):
    """N > ONE_DRAW_MAX_N: two draws per candidate, plain and batched loops agree."""
    n = heated.ONE_DRAW_MAX_N + 3
    v0 = np.zeros(n)
    v0[::1000] = np.random.default_rng(1).normal(size=v0[::1000].size)
    outs = []
    for batch in (0, 128):
        v, s = v0.copy(), _heated(9)
        outs.append((heated.collide_heated(v, 5000, 0.5, 10.0, s, batch), v, int(s[4])))
    assert outs[0][0] == outs[1][0] and outs[0][2] == outs[1][2]
    np.testing.assert_array_equal(outs[0][1], outs[1][1])
    w = int(_heated(9)[4])
    for _ in range(10_000):  # two draws per candidate
        w = _wyrand_reference(w)[1]
    assert outs[0][2] == w


# ----------------------------------------------------------------------------- measurement
def test_measure_centred_against_numpy():
    v = np.random.default_rng(2).normal(0.3, 1.7, size=10_003)
    v0 = v.copy()
    ref = v - v.mean()
    counts, sums = np.full(50, 7.0), np.full(13, 7.0)
    mean = heated.measure_centred(v, -5.0, 5.0, counts, sums)
    assert mean == pytest.approx(v0.mean(), rel=1e-14)
    np.testing.assert_allclose(v, ref, rtol=0, atol=1e-14)
    expected = np.array([np.sum(ref**k) for k in range(13)])
    scale = np.array([np.sum(np.abs(ref) ** k) for k in range(13)])  # round-off scale
    assert np.all(np.abs(sums - expected) <= 1e-12 * scale)
    hist = np.histogram(ref, bins=50, range=(-5.0, 5.0))[0]
    assert np.abs(counts - hist).sum() <= 2  # an edge may round either way
    assert counts.sum() == np.sum((ref >= -5.0) & (ref < 5.0))


def test_old_heated_checkpoint_is_refused(tmp_path):
    path = tmp_path / "run.npz"
    kw = dict(seed=3, collisions_per_particle=12, relax=0.0, n_batches=4, checkpoint=path)
    dsmc.simulate_heated(0.8, 200, **kw)
    arrays, meta = load_checkpoint(path)
    arrays["state"] = arrays["state"][:4]  # as an earlier version wrote it
    save_checkpoint(path, arrays, meta)
    with pytest.raises(ValueError, match="earlier version"):
        dsmc.simulate_heated(0.8, 200, resume=True, **kw)


def test_heated_run_without_jit_is_bit_identical(jit_and_plain):
    """A tiny heated run under NUMBA_DISABLE_JIT=1 equals the compiled one bit for bit."""
    kw = "collisions_per_particle=3, relax=1.0, n_batches=3, seed=4"
    code = ("import numpy as np; from particles import dsmc;"
            f"r = dsmc.simulate_heated(0.6, 60, {kw});"
            "print(repr(r.n_collisions), repr(r.series['a2'].tolist()),"
            " repr(r.counts.sum()), repr(r.power_sums.tolist()))")
    compiled, plain = jit_and_plain(code)
    assert compiled == plain and compiled.strip()


# ----------------------------------------------------------------------------- statistics
@pytest.fixture(scope="module")
def fem_06():
    return kf.solve_heated(0.6, method="fem")


@pytest.mark.parametrize("seed", [11, 12, 13])
def test_heated_t_and_a2_against_fem(seed, fem_06):
    """N = 10^4, 200 collisions per particle: T within 4 standard errors of FEM's (after
    the finite-N shift -2T/N, see particles.dsmc), a2 within 4 standard errors."""
    run = dsmc.simulate_heated(0.6, 10_000, seed=seed, collisions_per_particle=200)
    t_err = run.distribution.observable_error(lambda d: d.temperature)
    t_fem = fem_06.temperature * (1 - 2 / run.n_particles)
    assert abs(run.temperature - t_fem) < 4 * t_err, (run.temperature, t_err, t_fem)
    assert abs(run.a2 - fem_06.a2) < 4 * run.a2_error, (run.a2, run.a2_error, fem_06.a2)
    assert abs(run.dissipation_rate - run.injection_rate) < 4 * run.dissipation_error


@pytest.mark.slow
@pytest.mark.parametrize("alpha", [0.6, 0.9])
def test_heated_seeds_scatter_around_fem(alpha):
    """Eight seeds at N = 25000: the mean of T and of a2 over the seeds within 4 of
    their standard errors (from the seeds' spread) of the FEM values, and the batch
    errors of a2 within a factor 2 of the seeds' spread."""
    fem = kf.solve_heated(alpha, method="fem")
    cpp = 400.0 if alpha == 0.6 else 1000.0
    runs = [dsmc.simulate_heated(alpha, 25_000, seed=100 + k, collisions_per_particle=cpp)
            for k in range(8)]
    t = np.array([r.temperature for r in runs])
    a2 = np.array([r.a2 for r in runs])
    t_fem = fem.temperature * (1 - 2 / 25_000)
    print(f"alpha={alpha}: T {t.mean():.6f} +- {t.std(ddof=1) / math.sqrt(8):.6f} "
          f"(FEM {t_fem:.6f}); a2 {a2.mean():+.5f} +- {a2.std(ddof=1) / math.sqrt(8):.5f} "
          f"(FEM {fem.a2:+.5f}); batch error {np.mean([r.a2_error for r in runs]):.5f}")
    assert abs(t.mean() - t_fem) < 4 * t.std(ddof=1) / math.sqrt(8)
    assert abs(a2.mean() - fem.a2) < 4 * a2.std(ddof=1) / math.sqrt(8)
    ratio = a2.std(ddof=1) / np.mean([r.a2_error for r in runs])
    assert 0.5 < ratio < 2.0, ratio
