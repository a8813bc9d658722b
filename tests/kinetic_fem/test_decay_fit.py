"""Tests of kinetic_fem.analysis.decay_fit (late exponential decay with jackknife errors)."""

from __future__ import annotations

import numpy as np
import pytest

from kinetic_fem.analysis.decay_fit import fit_decay, window_bias


def _replicas(rng, times, rate, replicas, noise):
    """Curves c + A exp(-rate t) with noise correlated along each replica (AR(1))."""
    out = np.empty((replicas, times.size))
    for r in range(replicas):
        e = np.empty(times.size)
        e[0] = rng.normal()
        for i in range(1, times.size):
            e[i] = 0.8 * e[i - 1] + 0.6 * rng.normal()
        out[r] = 1.0 - 0.6 * np.exp(-rate * times) + noise * e
    return out


def test_exact_curve_is_recovered():
    t = np.linspace(0.0, 6.0, 61)
    fit = fit_decay(t, [3.0 + 0.5 * np.exp(-1.3 * t)], (1.0, 6.0), rate_guess=1.0)
    assert fit.rate == pytest.approx(1.3, rel=1e-8)
    assert fit.asymptote == pytest.approx(3.0, rel=1e-10) and fit.rate_error == 0.0


def test_jackknife_error_bars_cover_the_truth():
    """20 fixed seeds: the fitted rate is within 3 sigma every time, and within 1 sigma
    in roughly two thirds of them (jackknife errors are neither too small nor too large)."""
    t = np.linspace(0.0, 5.0, 51)
    z = []
    for seed in range(20):
        rng = np.random.default_rng(1000 + seed)
        fit = fit_decay(t, _replicas(rng, t, 0.9, 32, 2e-3), (1.0, 5.0), rate_guess=1.0)
        z.append((fit.rate - 0.9) / fit.rate_error)
    z = np.abs(np.array(z))
    assert np.all(z < 3.0)
    assert 0.45 <= np.mean(z < 1.0) <= 0.9


def test_window_bias_of_two_modes():
    """A faster mode still present biases the rate; a later window less so."""
    t = np.linspace(0.0, 10.0, 201)
    curve = 1.0 - np.exp(-t) - 0.3 * np.exp(-2.0 * t)
    early = window_bias(t, curve, (0.5, 6.0), 1.0)
    late = window_bias(t, curve, (3.0, 10.0), 1.0)
    assert early > 0.0 and abs(late) < abs(early) / 5


def test_bad_input():
    t = np.linspace(0.0, 1.0, 11)
    with pytest.raises(ValueError, match="need >= 4"):
        fit_decay(t, [t], (0.0, 0.2), rate_guess=1.0)
    with pytest.raises(ValueError, match="rate_guess"):
        fit_decay(t, [t], (0.0, 1.0), rate_guess=-1.0)
    with pytest.raises(ValueError, match="expected 11"):
        fit_decay(t, [t[:5]], (0.0, 1.0), rate_guess=1.0)
