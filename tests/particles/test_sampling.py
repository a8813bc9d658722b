"""Tests of particles.sampling: batch histograms, checkpoints, seeds, replicas."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from kinetic_fem.distribution import MAX_MOMENT, RunInfo
from particles.sampling import (
    Accumulator,
    load_checkpoint,
    run_replicas,
    save_checkpoint,
    spawn_seeds,
)


def test_accumulator_matches_numpy_histogram_and_power_sums():
    rng = np.random.default_rng(3)
    x = rng.normal(size=5000)
    acc = Accumulator(-3.0, 3.0, 30, 2)
    acc.add(0, x[:2500])
    acc.add(1, x[2500:])
    edges = acc.edges
    for b, part in enumerate((x[:2500], x[2500:])):
        inside = part[(part >= -3) & (part < 3)]
        np.testing.assert_array_equal(acc.counts[b], np.histogram(inside, edges)[0])
        k = np.arange(MAX_MOMENT + 1)
        np.testing.assert_allclose(acc.sums[b], (part[:, None] ** k).sum(0), rtol=1e-10)
    # samples outside the range count in the sums only
    assert acc.counts.sum() < x.size
    assert acc.sums[:, 0].sum() == x.size


def test_accumulator_distribution_has_error_bars_and_exact_moments():
    rng = np.random.default_rng(4)
    acc = Accumulator(-6.0, 6.0, 60, 10)
    x = rng.normal(size=100_000)
    for b, part in enumerate(np.array_split(x, 10)):
        acc.add(b, part)
    d = acc.distribution(method="test", params={}, info=RunInfo())
    assert d.errors is not None and np.all(d.errors >= 0)
    assert d.temperature == pytest.approx(np.var(x), rel=1e-12)
    assert abs(d.a2) < 4 * d.a2_error


def test_accumulator_rejects_bad_range_and_empty():
    with pytest.raises(ValueError, match="hi > lo"):
        Accumulator(1.0, 1.0, 10, 2)
    with pytest.raises(ValueError, match="no samples"):
        Accumulator(0.0, 1.0, 10, 2).distribution(method="", params={}, info=RunInfo())


def test_state_restore_roundtrip():
    acc = Accumulator(-1.0, 1.0, 8, 3)
    acc.add(1, np.linspace(-1, 1, 50))
    other = Accumulator(-1.0, 1.0, 8, 3)
    other.restore(acc.state())
    np.testing.assert_array_equal(other.counts, acc.counts)
    np.testing.assert_array_equal(other.sums, acc.sums)


def test_checkpoint_roundtrip_keeps_arrays_and_meta(tmp_path):
    state = np.random.default_rng(1).bit_generator.state
    arrays = {"v": np.arange(5.0), "s": np.array([1, 2**63 + 5], dtype=np.uint64)}
    path = save_checkpoint(tmp_path / "ck", arrays, {"rng": state, "n": 3})
    assert path.suffix == ".npz" and not list(tmp_path.glob("*.tmp.npz"))
    got, meta = load_checkpoint(path)
    np.testing.assert_array_equal(got["v"], arrays["v"])
    np.testing.assert_array_equal(got["s"], arrays["s"])
    assert meta == {"rng": state, "n": 3}


def test_spawn_seeds_deterministic_and_independent():
    a = [s.generate_state(2) for s in spawn_seeds(7, 3)]
    b = [s.generate_state(2) for s in spawn_seeds(7, 3)]
    np.testing.assert_array_equal(a, b)
    assert len({tuple(x) for x in a}) == 3


def _draw(*, seed, size):
    return np.random.default_rng(seed).random(size)


def test_run_replicas_in_seed_order_with_any_executor():
    seeds = spawn_seeds(11, 3)
    expected = [_draw(seed=s, size=4) for s in seeds]
    with ThreadPoolExecutor(2) as ex:
        got = run_replicas(_draw, seeds, executor=ex, size=4)
    for e, g in zip(expected, got, strict=True):
        np.testing.assert_array_equal(e, g)
    got = run_replicas(_draw, seeds, max_workers=2, size=4)  # process pool
    for e, g in zip(expected, got, strict=True):
        np.testing.assert_array_equal(e, g)


def test_integrated_autocorrelation_time_of_known_series():
    """AR(1) with rho = 0.8 has tau = (1 + rho)/(1 - rho) = 9; white noise 1.

    Ten seeds of 2e4 samples gave 8.4-10.3 (AR(1)) and 1.00-1.17 (white, 4000).
    """
    from particles.sampling import integrated_autocorrelation_time as tau

    for seed in range(3):
        rng = np.random.default_rng(seed)
        e = rng.normal(size=20000)
        y = np.zeros(e.size)
        for k in range(1, y.size):
            y[k] = 0.8 * y[k - 1] + e[k]
        assert 7.5 < tau(y) < 11.0
        assert 1.0 <= tau(rng.normal(size=4000)) < 1.3
    assert tau(np.ones(10)) == 1.0
    with pytest.raises(ValueError, match="1D series"):
        tau(np.ones(1))
