"""Relaxation of a mixture's species temperatures (kinetic_fem.mixture_evolution).

The Maxwell moment equations integrated in time must end on the exact steady state
(heated) and the exact cooling-state temperature ratio (free cooling) of
kinetic_fem.solvers.maxwell_mixture; the Gaussian ODE on the Gaussian-approximation
states of kinetic_fem.solvers.mixture_gaussian, for hard rods too.
"""

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.model import UnsupportedModelError
from kinetic_fem.solvers import maxwell_mixture as mm
from kinetic_fem.solvers import mixture_gaussian as mg


def test_maxwell_relaxation_ends_on_the_exact_steady_state():
    mix = kf.Mixture.white_noise((1.0, 5.0), (0.3, 0.7), alpha=[[0.9, 0.6], [0.6, 0.5]],
                                 kernel=0.0, convention="same_power")
    ev = kf.evolve_heated(mix, times=[0.0, 1.0, 200.0], method="maxwell",
                          initial_temperature=(2.0, 0.5))
    exact = mm.steady_state(mix)
    assert np.allclose(ev.temperatures[0], [2.0, 0.5], rtol=0, atol=1e-15)
    assert np.allclose(ev.temperatures[-1], exact.temperatures, rtol=1e-8, atol=0)
    assert np.allclose(ev.a2[-1], exact.a2, rtol=0, atol=1e-8)
    assert ev.temperature.shape == (3,)


def test_maxwell_cooling_ratio_relaxes_to_the_homogeneous_cooling_state():
    mix = kf.Mixture((1.0, 4.0), (0.5, 0.5), alpha=0.7, kernel=0.0)
    ev = kf.evolve_cooling(mix, times=np.linspace(0.0, 60.0, 4), method="maxwell")
    hcs = mm.cooling_state(mix)
    assert abs(ev.temperature_ratio()[-1] - hcs.temperature_ratio()) < 1e-8
    assert np.all(np.diff(ev.temperature) < 0.0)


@pytest.mark.parametrize("heated", [True, False])
def test_gaussian_relaxation_ends_on_the_gaussian_state(heated):
    if heated:
        mix = kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=0.8)
        ev = kf.evolve_heated(mix, times=[0.0, 100.0], method="gaussian")
        ref = mg.steady_state(mix).temperatures
        assert np.allclose(ev.temperatures[-1], ref, rtol=1e-8, atol=0)
    else:
        mix = kf.Mixture((1.0, 3.0), (0.5, 0.5), alpha=0.8)
        ev = kf.evolve_cooling(mix, times=[0.0, 400.0], method="gaussian")
        ref = mg.cooling_state(mix).temperature_ratio()
        assert abs(ev.temperature_ratio()[-1] - ref) < 1e-7
    assert np.all(ev.a2 == 0.0) and ev.temperature_ratio_error() is None


def test_gaussian_free_cooling_with_a_law_in_physical_time():
    """A law in free cooling (no scaled state): the Gaussian ODE in physical time; a
    threshold below every speed is the constant coefficient (to the ODE's tolerance), and
    with the viscoelastic law the cooling slows as alpha(g) -> 1 (T(t) above Haff's
    decay of the law's coefficient at the start)."""
    from kinetic_fem.mixture_evolution import evolve_mixture
    from kinetic_fem.model import ThresholdRestitution, ViscoelasticRestitution

    times = [0.0, 1.0, 10.0, 100.0]
    law = kf.Mixture((1.0, 3.0), (0.5, 0.5), alpha=ThresholdRestitution(0.7, 1e-200))
    const = kf.Mixture((1.0, 3.0), (0.5, 0.5), alpha=0.7)
    a, b = (evolve_mixture(m, times=times, method="gaussian") for m in (law, const))
    np.testing.assert_allclose(a.temperatures, b.temperatures, rtol=1e-8)
    visco = kf.Mixture((1.0, 3.0), (0.5, 0.5), alpha=ViscoelasticRestitution(0.1))
    ev = evolve_mixture(visco, times=times, method="gaussian")
    assert np.all(np.diff(ev.temperatures, axis=0) < 0)
    start = ViscoelasticRestitution(0.1)(2.0)  # alpha at the initial thermal |g|
    haff = evolve_mixture(kf.Mixture((1.0, 3.0), (0.5, 0.5), alpha=float(start)),
                          times=times, method="gaussian")
    assert np.all(ev.temperatures[-1] > haff.temperatures[-1])


def test_mixture_evolution_bad_input_names_the_argument():
    heated = kf.Mixture.white_noise((1.0, 2.0), (0.5, 0.5), kernel=0.0)
    cooling = kf.Mixture((1.0, 2.0), (0.5, 0.5), kernel=1.0)
    with pytest.raises(ValueError, match="rescale"):
        kf.evolve_cooling(cooling, times=[1.0], rescale=0.5)
    with pytest.raises(ValueError, match="evolve_heated"):
        kf.evolve_cooling(heated, times=[1.0], method="maxwell")
    with pytest.raises(ValueError, match="diffusion"):
        kf.evolve_heated(heated, times=[1.0], method="maxwell", diffusion=2.0)
    with pytest.raises(UnsupportedModelError, match="kernel 0"):
        kf.evolve_cooling(cooling, times=[1.0], method="maxwell")
    with pytest.raises(ValueError, match="initial_temperature"):
        kf.evolve_heated(heated, times=[1.0], method="maxwell", initial_temperature=(1.0,))
    with pytest.raises(ValueError, match=r"initial_temperature\[1\]"):
        kf.evolve_heated(heated, times=[1.0], method="maxwell",
                         initial_temperature=(1.0, -1.0))
    with pytest.raises(TypeError, match="spacing"):
        kf.evolve_heated(heated, times=[1.0], method="maxwell", spacing=0.5)
    with pytest.raises(ValueError, match="method must be one of"):
        kf.mixture_evolution.evolve_mixture(heated, times=[1.0], method="sonine")
