"""Tests of particles.rng: xoshiro256**, the 128-bit multiply and the normal ziggurat."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from particles import _dsmc_segments as seg
from particles import rng

TABLES = rng.ziggurat_tables()
_MASK = (1 << 64) - 1


def _state(seed=0):
    return np.random.SeedSequence(seed).generate_state(4, dtype=np.uint64)


def _heated(seed=0):
    """The 5-word state of the heated kernels (xoshiro256** and the wyrand word)."""
    return rng.heated_state(np.random.SeedSequence(seed))


@pytest.fixture
def wrapping():
    """The kernels' uint64 arithmetic wraps on purpose; as plain Python numpy warns."""
    with np.errstate(over="ignore"):
        yield


def _rotl(x, k):
    return ((x << k) | (x >> (64 - k))) & _MASK


def _xoshiro_reference(s):
    """One xoshiro256** output from a list of 4 Python ints (the reference C code)."""
    out = _rotl((s[1] * 5) & _MASK, 7) * 9 & _MASK
    t = (s[1] << 17) & _MASK
    s[2] ^= s[0]
    s[3] ^= s[1]
    s[1] ^= s[2]
    s[0] ^= s[3]
    s[2] ^= t
    s[3] = _rotl(s[3], 45)
    return out


def test_xoshiro_matches_reference_recurrence(wrapping):
    """xoshiro256** against a Python big-int transcription of the reference C code."""
    s = [int(x) for x in _state(5)]
    expected = [_xoshiro_reference(s) for _ in range(20)]
    state = _state(5)
    got = [int(rng.next_u64(state)) for _ in range(20)]
    assert got == expected
    assert [int(x) for x in state] == s


def test_mul128_is_the_full_product():
    gen = np.random.default_rng(1)
    for r in gen.integers(0, 2**64, size=200, dtype=np.uint64):
        for n in (2, 3, 25_000, 10**7, 2**32 - 1, 2**64 - 1):
            hi, lo = rng.mul128_pair(r, np.uint64(n))
            assert (int(hi) << 64) + int(lo) == int(r) * n
            assert int(rng.mulhi(r, np.uint64(n))) == (int(r) * n) >> 64


def test_ziggurat_normals_are_standard_normal():
    out = np.empty(1_000_000)
    rng.fill_normal(out, _state(2), *TABLES)
    assert stats.kstest(out, "norm").pvalue > 1e-3
    se = 1 / math.sqrt(out.size)
    assert abs(out.mean()) < 4 * se
    assert abs(out.var() - 1) < 4 * math.sqrt(2) * se
    assert abs(np.mean(out**4) - 3) < 4 * math.sqrt(96) * se
    tail = np.mean(np.abs(out) > rng.ZIGGURAT_R)  # the tail sampler's share
    p = math.erfc(rng.ZIGGURAT_R / math.sqrt(2))
    assert abs(tail - p) < 4 * math.sqrt(p / out.size)


def test_fill_normal_gives_the_numbers_a_white_kick_adds(wrapping):
    out = np.empty(10_000)
    rng.fill_normal(out, _heated(3), *TABLES)
    v = np.zeros(10_000)
    lo, hi = seg.kick(v, 1.0, 1.0, _heated(3), *TABLES)
    np.testing.assert_array_equal(v, out)
    assert (lo, hi) == (out.min(), out.max())
