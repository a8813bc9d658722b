"""DSMC time series of a mixture against the exact Maxwell-mixture relaxation.

particles.dsmc_mixture.evolve_mixture (16 independent runs of 500 rods) against
kf.evolve_heated / kf.evolve_cooling with method="maxwell" (the exact moment equations):
|z| < 4 for both species temperatures and their ratio at every output time, from unequal
initial temperatures (measured at 6 seeds: max |z| over the 8 checks 1.0 ... 3.2).
"""

import numpy as np
import pytest

import kinetic_fem as kf
from particles.dsmc_mixture import evolve_mixture

Z_MAX = 4.0


@pytest.mark.parametrize("heated", [True, False])
def test_dsmc_relaxation_follows_the_exact_maxwell_mixture(heated):
    times = [1.0, 2.0, 3.0, 4.0]
    init = (0.5, 2.0)
    if heated:
        mix = kf.Mixture.white_noise((1.0, 4.0), (0.5, 0.5), alpha=0.6, kernel=0.0,
                                     convention="same_power")
        exact = kf.evolve_heated(mix, times=times, method="maxwell", initial_temperature=init)
    else:
        mix = kf.Mixture((1.0, 4.0), (0.3, 0.7), alpha=0.6, kernel=0.0)
        exact = kf.evolve_cooling(mix, times=times, method="maxwell", initial_temperature=init)
    run = evolve_mixture(mix, 500, times=times, seed=7, n_runs=16, initial_temperature=init)
    z = (run.temperatures - exact.temperatures) / run.temperature_errors
    assert np.all(np.abs(z) < Z_MAX)
    zr = (run.temperature_ratio() - exact.temperature_ratio()) / run.temperature_ratio_error()
    assert np.all(np.abs(zr) < Z_MAX)
    # the relaxation is resolved: the ratio moves by many standard errors
    assert abs(run.temperature_ratio()[-1] - 0.25) / run.temperature_ratio_error()[-1] > 10


def test_dsmc_evolution_bad_input():
    mix = kf.Mixture((1.0, 4.0), (0.5, 0.5), alpha=0.6)
    with pytest.raises(ValueError, match="n_runs"):
        evolve_mixture(mix, 100, times=[1.0], n_runs=1)
    with pytest.raises(ValueError, match="times"):
        evolve_mixture(mix, 100, times=[2.0, 1.0])
