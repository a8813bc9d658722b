"""DSMC free cooling (particles.dsmc.simulate_cooling) against kf.evolve_cooling.

An ensemble of independent DSMC runs from a Gaussian; the physical T(t) and a2(t) of
each replica are interpolated (linearly in t, ln T and a2 sampled every 0.05
collisions per particle) to the FEM output times and averaged; every output time
must lie within ``Z_MAX = 4.5`` standard errors of the FEM curve: for 10 z-scores from
32 replicas (Student t, 31 degrees of freedom) a false alarm has probability about
1e-3 per test, so the bound holds for any root seed, not only the fixed one (0: max |z|
2.04 for hard rods, 1.51 for the Maxwell model; the issue's criterion, 3 standard errors
at every output time, is met there).  Over 64 root seeds
(benchmarks/results/cooling_transient.md) 6 of 640 hard-rod and 2 of 640 Maxwell
z-scores lie beyond 3 (Student t, 31 degrees of freedom: 0.53 %), the mean z per output
time is within -0.34..+0.11 (standard error 0.13).  The DSMC runs go well past the last
output time: a run ending just after it biased the last T high (mean z +1.2).
"""

from __future__ import annotations

import numpy as np
import pytest

import kinetic_fem as kf
from particles.dsmc import simulate_cooling

TIMES = np.array([0.25, 1.0, 2.0, 4.0, 8.0])
Z_MAX = 4.5
"""Bound on every |z|: P(|t_31| > 4.5) = 9.0e-5, about 1e-3 over the 10 z-scores of a
test; the largest of 1280 measured (64 seeds, both models) was 4.07."""


def dsmc_ensemble(alpha: float, gamma: float, n_particles: int, replicas: int, seed: int,
                  collisions: float) -> tuple[np.ndarray, np.ndarray]:
    """T and a2 of each replica at TIMES, shape (replicas, n_t) each."""
    temps, a2s = [], []
    for r in range(replicas):
        s = simulate_cooling(alpha, n_particles, kernel=gamma, seed=seed * 1000 + r,
                             collisions_per_particle=collisions, relax=0.0,
                             sample_every=0.05, n_batches=2).series
        t = np.asarray(s["t"])
        assert t[-1] > TIMES[-1]
        temps.append(np.exp(np.interp(TIMES, t, s["log_temperature"])))
        a2s.append(np.interp(TIMES, t, s["a2"]))
    return np.array(temps), np.array(a2s)


def z_scores(samples: np.ndarray, reference: np.ndarray) -> np.ndarray:
    err = samples.std(axis=0, ddof=1) / np.sqrt(samples.shape[0])
    return (samples.mean(axis=0) - reference) / err


@pytest.mark.parametrize(("alpha", "gamma", "collisions"), [(0.5, 1.0, 8.0),
                                                              (0.7, 0.0, 9.0)])
def test_dsmc_cooling_follows_evolve_cooling(alpha, gamma, collisions):
    ev = kf.evolve_cooling(alpha, kernel=gamma, times=TIMES, spacing=0.5, rtol=1e-6)
    temps, a2s = dsmc_ensemble(alpha, gamma, 20_000, 32, seed=0, collisions=collisions)
    z_t, z_a = z_scores(temps, ev.temperature), z_scores(a2s, ev.a2)
    assert np.abs(z_t).max() < Z_MAX, z_t
    assert np.abs(z_a).max() < Z_MAX, z_a
