"""Tests of the free-cooling DSMC candidate lanes (issue 31): the eight lock-step
xoshiro256++ streams (particles.rng.xoshiro_lanes), the candidate blocks and the
branch-free thinning loop (particles._dsmc_kernels.collide_lanes), the cooling segment
and the stream version of cooling checkpoints."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from particles import _dsmc_kernels as kern
from particles import _dsmc_segments as seg
from particles import dsmc, rng
from particles.sampling import load_checkpoint, save_checkpoint

MASK = (1 << 64) - 1


def _rotl(x, k):
    return ((x << k) | (x >> (64 - k))) & MASK


def _lanes_reference(state, n_steps):
    """xoshiro256++ of each lane in Python big ints: ``(outputs[t, l], new lane words)``."""
    words = [[int(x) for x in row] for row in state[rng.LANE_WORD:].reshape(4, rng.LANES)]
    out = np.zeros((n_steps, rng.LANES), dtype=object)
    for lane in range(rng.LANES):
        s0, s1, s2, s3 = (words[w][lane] for w in range(4))
        for t in range(n_steps):
            out[t, lane] = (_rotl((s0 + s3) & MASK, 23) + s0) & MASK
            tt = (s1 << 17) & MASK
            s2 ^= s0
            s3 ^= s1
            s1 ^= s2
            s0 ^= s3
            s2 ^= tt
            s3 = _rotl(s3, 45)
        for w, x in enumerate((s0, s1, s2, s3)):
            words[w][lane] = x
    return out, words


def _work(block=64):
    return (np.zeros(2 * block, np.uint64), np.zeros(block + 32, np.uint64),
            np.zeros(block + 32, np.uint64), np.zeros(block + 32))


def _collide_reference(v, m, alpha, g_max, state, block):
    """collide_lanes in plain Python (big ints for the candidates)."""
    v = v.copy()
    n = v.size
    half = 0.5 * (1.0 + alpha)
    accepted, done = 0, 0
    while done < m:
        k = min(block, m - done)
        mp = -(-k // rng.LANES) * rng.LANES
        out, words = _lanes_reference(state, 2 * mp // rng.LANES)
        state[rng.LANE_WORD:] = np.array(words, dtype=np.uint64).ravel()
        raw = out.ravel()
        for c in range(k):
            a, b = int(raw[c]), int(raw[mp + c])
            i = ((a >> 32) * n) >> 32
            j = ((a & 0xFFFFFFFF) * (n - 1)) >> 32
            j += j >= i
            u = ((b >> 12) + (1023 << 52)) & MASK
            thr = (float(np.array(u, np.uint64).view(np.float64)) - 1.0) * g_max
            g = v[i] - v[j]
            if abs(g) > thr:
                dv = half * g
                v[i] -= dv
                v[j] += dv
                accepted += 1
        done += k
    return v, accepted


def test_lanes_match_xoshiro256pp_reference():
    """Compiled lanes (a vector loop) = numpy lanes = xoshiro256++ per lane in big ints."""
    state = rng.cooling_state(np.random.SeedSequence(11))
    ref, words = _lanes_reference(state, 13)
    for fill in (_lanes_jit, rng.xoshiro_lanes):  # compiled; numpy (the no-JIT mode)
        s = state.copy()
        out = np.zeros(13 * rng.LANES, np.uint64)
        fill(s, out, 13)
        assert [int(x) for x in out] == [int(x) for x in ref.ravel()]
        assert [int(x) for x in s[rng.LANE_WORD:]] == [x for row in words for x in row]
        assert np.array_equal(s[:rng.LANE_WORD], state[:rng.LANE_WORD])  # untouched


def _lanes_jit(s, out, n_steps):
    """The compiled lanes, through a kernel that calls them (candidate_block)."""
    m = n_steps * rng.LANES // 2
    raw, ci, cj, cu = np.zeros(2 * m, np.uint64), *(np.zeros(m, np.uint64),) * 2, np.zeros(m)
    kern.candidate_block(s, 10, 1.0, raw, ci, cj, cu, m)
    out[:] = raw


def test_cooling_state_layout_is_fixed():
    """The seed fixes the 36 words, whatever the machine (no SIMD-width dependence)."""
    s = rng.cooling_state(np.random.SeedSequence(1))
    assert s.shape == (36,) and s.dtype == np.uint64
    np.testing.assert_array_equal(s, np.random.SeedSequence(1).generate_state(36, np.uint64))


def test_candidates_are_uniform_distinct_pairs():
    """i != j, both uniform below N (chi-square), thresholds uniform on [0, g_max)."""
    n, m = 7, 70_000
    s = rng.cooling_state(np.random.SeedSequence(2))
    raw, ci, cj, cu = np.zeros(2 * m, np.uint64), np.zeros(m, np.uint64), \
        np.zeros(m, np.uint64), np.zeros(m)
    kern.candidate_block(s, n, 2.5, raw, ci, cj, cu, m)
    assert np.all(ci != cj) and ci.max() < n and cj.max() < n
    pairs = np.bincount(ci.astype(np.int64) * n + cj.astype(np.int64), minlength=n * n)
    observed = pairs.reshape(n, n)[~np.eye(n, dtype=bool)]
    assert stats.chisquare(observed).pvalue > 1e-4
    assert cu.min() >= 0.0 and cu.max() < 2.5
    assert stats.kstest(cu / 2.5, "uniform").pvalue > 1e-4


@pytest.mark.parametrize("g", [0.1, 0.5, 0.9])
def test_acceptance_probability_is_g_over_gmax(g):
    m = 40_000
    acc, g2 = kern.collide_lanes(np.array([0.0, g]), m, -1.0, 1.0,
                                 rng.cooling_state(np.random.SeedSequence(3)), *_work(512))
    assert abs(acc - g * m) < 4.0 * np.sqrt(m * g * (1 - g))
    assert g2 == pytest.approx(acc * g * g, rel=1e-12)  # alpha = -1: v never changes


@pytest.mark.parametrize("m, block", [(0, 64), (5, 64), (300, 64), (1000, 512)])
def test_collide_lanes_matches_python_reference(m, block):
    """Blocks, dropped tail draws and the branch-free update, against plain Python."""
    v0 = np.random.default_rng(4).normal(size=50)
    lo, hi = v0.min(), v0.max()
    state = rng.cooling_state(np.random.SeedSequence(5))
    ref_state = state.copy()
    ref, ref_acc = _collide_reference(v0, m, 0.4, hi - lo, ref_state, block)
    v = v0.copy()
    acc, _ = kern.collide_lanes(v, m, 0.4, hi - lo, state, *_work(block))
    assert acc == ref_acc
    np.testing.assert_array_equal(v, ref)
    np.testing.assert_array_equal(state, ref_state)


def test_collide_lanes_conserves_momentum_and_loses_energy():
    v = np.random.default_rng(6).normal(size=1000)
    p0, e0 = v.sum(), (v**2).sum()
    acc, g2 = kern.collide_lanes(v, 20_000, 0.7, float(np.ptp(v)),
                                 rng.cooling_state(np.random.SeedSequence(6)), *_work(512))
    assert acc > 0
    assert v.sum() == pytest.approx(p0, abs=1e-10)
    assert e0 - (v**2).sum() == pytest.approx(0.5 * (1 - 0.7**2) * g2, rel=1e-10)


def test_cooling_segment_reaches_its_target_and_agrees_without_jit():
    """The segment stops within a sixteenth of a block past the target; as plain Python
    (the kernel's own loop; NUMBA_DISABLE_JIT=1) it gives the same numbers."""
    v0 = np.random.default_rng(7).normal(size=200)
    outs = []
    for func in (seg.cooling_segment, seg.cooling_segment.py_func):
        v = v0.copy()
        s = rng.cooling_state(np.random.SeedSequence(8))
        r = func(v, 3000, 200, 0.2, kern.KERNEL_HARD_RODS, 1.0, 0, 0.9, 0.0, 0.0, s,
                 *_work(64))
        outs.append((v, r))
        acc, cand = r[0], r[1]
        assert 3000 <= acc < 3000 + 200 // 16 + 1 + 200
        assert cand > acc
    np.testing.assert_array_equal(outs[0][0], outs[1][0])
    assert outs[0][1] == outs[1][1]


def test_measure_scaled_rescales_and_sums():
    v = np.random.default_rng(9).normal(0.3, 2.0, size=1001)
    sd0 = v.std()
    ref = (v - v.mean()) / sd0
    counts, sums = np.zeros(40), np.zeros(13)
    sd = seg.measure_scaled(v, -4.0, 4.0, counts, sums)
    assert sd == pytest.approx(sd0, rel=1e-12)
    np.testing.assert_allclose(v, ref, rtol=0, atol=1e-12)
    expected = np.array([np.sum(ref**k) for k in range(13)])
    scale = np.array([np.sum(np.abs(ref) ** k) for k in range(13)])
    assert np.all(np.abs(sums - expected) <= 1e-11 * scale)
    assert np.abs(counts - np.histogram(ref, bins=40, range=(-4.0, 4.0))[0]).sum() <= 2
    assert seg.measure_scaled(np.ones(5), -1.0, 1.0, np.zeros(4), np.zeros(13)) == 0.0


def test_old_cooling_checkpoint_is_refused(tmp_path):
    """A cooling checkpoint of the xoshiro256** stream (no stream field, 4 state words)."""
    path = tmp_path / "run.npz"
    kw = dict(seed=3, collisions_per_particle=12, relax=0.0, n_batches=4, checkpoint=path)
    dsmc.simulate_cooling(0.8, 200, **kw)
    arrays, meta = load_checkpoint(path)
    assert meta["stream"] == 2
    del meta["stream"]
    arrays["state"] = arrays["state"][:4]  # as the earlier version wrote it
    save_checkpoint(path, arrays, meta)
    with pytest.raises(ValueError, match="random stream 1 of the cooling DSMC"):
        dsmc.simulate_cooling(0.8, 200, resume=True, **kw)
