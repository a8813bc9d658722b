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
from kinetic_fem.model import ThresholdRestitution, ViscoelasticRestitution
from kinetic_fem.model.protocol import Protocol
from particles.dsmc import simulate_cooling
from particles.dsmc_transient import simulate_protocol

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


@pytest.mark.parametrize(("alpha", "gamma", "collisions"), [
    pytest.param(0.5, 1.0, 8.0, marks=pytest.mark.slow),  # 41 s; the Maxwell case stays fast
    (0.7, 0.0, 9.0)])
def test_dsmc_cooling_follows_evolve_cooling(alpha, gamma, collisions):
    ev = kf.evolve_cooling(alpha, kernel=gamma, times=TIMES, spacing=0.5, rtol=1e-6)
    temps, a2s = dsmc_ensemble(alpha, gamma, 20_000, 32, seed=0, collisions=collisions)
    z_t, z_a = z_scores(temps, ev.temperature), z_scores(a2s, ev.a2)
    assert np.abs(z_t).max() < Z_MAX, z_t
    assert np.abs(z_a).max() < Z_MAX, z_a


# ---------------------------------------------------------------------------------------
# Free cooling under restitution protocols and speed-dependent laws: DSMC ensembles of
# particles.dsmc_transient.simulate_protocol with diffusion=0 (T and a2 measured exactly
# at the output times, no interpolation) against kf.evolve_cooling.  Bound: Z_MAX above
# (32 replicas, 10 z-scores per test).  Measured over 64 root seeds
# (benchmarks/results/cooling_protocol.md): alpha step 8 of 640 |z| > 3 (max 3.94),
# mean z per output time -0.19 ... +0.20.

def protocol_z_scores(alpha, times, protocol=None, seed=0, **fem):
    ev = kf.evolve_cooling(alpha, times=times, protocol=protocol, **fem)
    run = simulate_protocol(alpha, 20_000, times=times, diffusion=0.0, protocol=protocol,
                            replicas=32, seed=seed)
    return run.deviation(ev.temperature, ev.a2)


def test_dsmc_alpha_step_follows_evolve_cooling():
    """Hard rods, alpha 0.9 -> 0.5 at t = 1 (FEM at rtol 1e-5: T 5.5e-5 relative and a2
    1.2e-4 from the rtol 1e-7 curve; rtol 1e-4: 6.0e-4 and 1.2e-3; standard errors
    ~2e-3)."""
    z_t, z_a = protocol_z_scores(0.9, [0.5, 1.0, 1.5, 2.0, 4.0],
                                 Protocol(restitution=[(1.0, 0.5)]), spacing=0.5, rtol=1e-5)
    assert np.abs(z_t).max() < Z_MAX, z_t
    assert np.abs(z_a).max() < Z_MAX, z_a


@pytest.mark.parametrize("times", [
    # 65 s in CI: slow; the default run keeps DSMC against evolve_cooling through the
    # Maxwell case and the alpha step above, and the viscoelastic FEM transient through
    # tests/kinetic_fem/test_evolve_cooling_protocol.py
    pytest.param([0.5, 1.0, 2.0, 3.0, 5.0], marks=pytest.mark.slow),
    pytest.param([0.5, 2.0, 5.0, 10.0, 20.0], marks=pytest.mark.slow),
], ids=["to-5", "to-20"])
def test_dsmc_viscoelastic_cooling_follows_evolve_cooling(times):
    """Viscoelastic hard rods, delta 0.2, from T0 = 1 (T falls to 0.23 by t = 5, 0.04
    by t = 20).  The FEM needs rtol 1e-5 here: the nearly elastic shape relaxes slowly,
    so the time error accumulates (measured at t = 20, rtol 1e-4 against 1e-5: a2 4.3e-3,
    T 1.4e-3; 512 DSMC replicas put rtol 1e-4 11 standard errors off in a2, rtol 1e-5
    within 2.7)."""
    z_t, z_a = protocol_z_scores(ViscoelasticRestitution(0.2), times, spacing=0.5,
                                 rtol=1e-5)
    assert np.abs(z_t).max() < Z_MAX, z_t
    assert np.abs(z_a).max() < Z_MAX, z_a


@pytest.mark.slow
def test_dsmc_threshold_cooling_stops_as_evolve_cooling():
    """Threshold law (alpha 0.5 above |g| = 0.5): cooling stops (T -> ~0.0167 by
    t = 100, collisions below the threshold elastic); DSMC and FEM agree on the way.
    The FEM needs spacing 0.25 and rtol 1e-6 here: at spacing 0.5, rtol 1e-5 its a2 at
    t = 30 is -0.2350 against -0.2416 (the state very non-Gaussian once the threshold
    is four thermal speeds out), 5.6 standard errors of the DSMC off (measured; this
    slow test failed so); refined, the largest |z| are 2.1 (T) and 2.7 (a2)."""
    z_t, z_a = protocol_z_scores(ThresholdRestitution(0.5, 0.5), [1.0, 3.0, 10.0, 30.0, 100.0],
                                 spacing=0.25, rtol=1e-6)
    assert np.abs(z_t).max() < Z_MAX, z_t
    assert np.abs(z_a).max() < Z_MAX, z_a


def test_free_cooling_dsmc_refuses_a_thermostat():
    with pytest.raises(ValueError, match="free cooling"):
        simulate_protocol(0.5, 100, times=[1.0], diffusion=0.0, friction=0.5, replicas=2)
    with pytest.raises(ValueError, match="free cooling"):
        simulate_protocol(0.5, 100, times=[1.0], diffusion=0.0, replicas=2,
                          protocol=Protocol(diffusion=1.0))
