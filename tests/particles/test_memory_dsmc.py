"""DSMC against the deterministic memory-effect and relaxation results (slow).

* The late decay rate of T after a perturbation (odd part of two starts at
  (1 +- 0.3) T_st, ``benchmarks/relaxation_dsmc.py``) against the slowest even rate
  of :func:`kinetic_fem.relaxation_spectrum`, within 3 standard errors (jackknife).
* The Maxwell-model Kovacs protocol: no hump in DSMC either, T(t) within 3 sigma of
  the exact moment equations at every output time.
"""

from __future__ import annotations

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.analysis.decay_fit import fit_decay
from kinetic_fem.analysis.memory_effects import kovacs
from kinetic_fem.distribution import VelocityDistribution
from particles.dsmc_transient import simulate_protocol

SPECTRUM_RATES = {0.6: 1.5373577, 0.9: 0.65670537}
"""benchmarks/results/relaxation_spectrum.md (mesh error <= 9e-9 relative)."""


def dsmc_rate(alpha: float, n_particles: int, replicas: int, seed: int) -> tuple[float, float]:
    """Fitted decay rate of T_+ - T_- and its jackknife error."""
    rate = SPECTRUM_RATES[alpha]
    steady = kf.solve_heated(alpha)
    times = np.linspace(0.0, 5.5 / rate, 89)
    curves = []
    for k, sign in enumerate((1.0, -1.0)):
        scale = np.sqrt(1.0 + 0.3 * sign)
        start = VelocityDistribution.from_values(steady.v * scale, steady.values / scale)
        curves.append(simulate_protocol(alpha, n_particles, times=times, initial=start,
                                        replicas=replicas, seed=seed + k).temperature_replicas)
    fit = fit_decay(times, (curves[0] - curves[1]) / steady.temperature,
                    (1.5 / rate, 5.0 / rate), rate_guess=rate)
    return fit.rate, fit.rate_error


@pytest.mark.slow
@pytest.mark.parametrize("alpha", [0.6, 0.9])
@pytest.mark.parametrize("seed", [11, 12])
def test_dsmc_relaxation_rate_matches_spectrum(alpha, seed):
    """N = 1e5, 64 replicas: errors 2.8 % (0.6) and 1.4 % (0.9); the fit window's own
    bias (first Sonine) is -3.3e-3 and -8e-6, well inside."""
    rate, err = dsmc_rate(alpha, 100_000, 64, seed)
    assert err < 0.05 * rate
    assert abs(rate - SPECTRUM_RATES[alpha]) < 3.0 * err


@pytest.mark.slow
def test_maxwell_kovacs_dsmc_has_no_hump():
    k = kovacs(0.3, kernel=0.0, n_times=21)
    run = simulate_protocol(0.3, 20_000, kernel=0.0, times=k.exact.times, protocol=k.protocol,
                            diffusion=k.diffusion[1],
                            initial_temperature=float(k.exact.temperature[0]),
                            initial_a2=float(k.exact.a2[0]), replicas=32, seed=7)
    z_t, z_a = run.deviation(k.exact.temperature, k.exact.a2)
    assert np.max(np.abs(z_t)) < 3.0
    assert np.max(np.abs(z_a)) < 3.5


@pytest.mark.slow
def test_hard_rod_kovacs_dsmc_sees_the_hump():
    """alpha = 0.3, FEM at spacing 0.5, rtol 1e-4 (hump -4.0535e-3, 3.5e-5 from the
    converged value).  DSMC N = 1e5, 64 replicas: error 6e-4 at the hump, so the hump
    is 5 to 7 sigma from 0 (seeds 21, 22: -4.27e-3 +- 0.68e-3, -3.25e-3 +- 0.57e-3) and
    T(t) follows the FEM curve at all 52 output times (max |z| 2.2 and 2.8 for those
    seeds; the bound 4 allows for the maximum over 52 correlated times)."""
    k = kovacs(0.3, spacing=0.5, rtol=1e-4)
    run = simulate_protocol(0.3, 100_000, times=k.exact.times, protocol=k.protocol,
                            diffusion=k.diffusion[1], initial=k.initial, replicas=64, seed=21)
    z_t, z_a = run.deviation(k.exact.temperature, k.exact.a2)
    assert np.max(np.abs(z_t)) < 4.0 and np.max(np.abs(z_a)) < 4.0
    i = int(np.argmin(np.abs(k.exact.times - k.waiting_time - k.hump_time)))
    dev = run.temperature[i] / k.steady_temperature - 1.0
    err = run.temperature_error[i] / k.steady_temperature
    assert dev < -4.0 * err
    assert abs(run.temperature[i] - k.exact.temperature[i]) < 3.0 * run.temperature_error[i]


KOVACS_09_HUMP = (4.84e-3, 2e-4)
"""FEM hump at alpha = 0.9 and its mesh error bar (benchmarks/results/memory_effects.md)."""


@pytest.mark.slow
@pytest.mark.parametrize("seed", [31, 32])
def test_hard_rod_kovacs_dsmc_positive_hump_at_alpha_09(seed):
    """alpha = 0.9 (a2_st < 0): DSMC sees a positive hump.  The protocol is made
    consistent in DSMC itself: D2 from the ensemble's own T(t_w) (a second run with the
    same seed repeats the pre-switch path bit for bit).  N = 1e5, 64 replicas: error
    5e-4 at the hump; measured (seed 31) +4.68e-3 at t - t_w = 2.22, 9.3 sigma from 0,
    -0.3 sigma from the FEM curve; first Sonine gives +2.59e-3."""
    from kinetic_fem.analysis.memory_effects import sonine_waiting_time
    from kinetic_fem.model.protocol import Protocol, steps

    steady = kf.solve_heated(0.9)
    tw = sonine_waiting_time(0.9)
    times = np.concatenate([np.linspace(0.0, tw, 11),
                            tw + tw * 4.0 * np.geomspace(1e-3, 1.0, 41)])
    pre = simulate_protocol(0.9, 100_000, times=times[:11], diffusion=1e-3, initial=steady,
                            replicas=64, seed=seed)
    t_tw = float(pre.temperature[-1])
    protocol = Protocol(diffusion=steps([tw], [1e-3, (t_tw / steady.temperature) ** 1.5]))
    run = simulate_protocol(0.9, 100_000, times=times, protocol=protocol, diffusion=1e-3,
                            initial=steady, replicas=64, seed=seed)
    assert run.temperature[10] == t_tw
    dev = run.temperature[11:] / t_tw - 1.0
    err = run.temperature_error[11:] / t_tw
    i = int(np.argmin(np.abs(times[11:] - tw - 2.3)))
    assert dev[i] > 5.0 * err[i]
    value, tol = KOVACS_09_HUMP
    assert abs(dev[i] - value) < 3.0 * err[i] + tol
