"""FEM transient of a heated mixture (kinetic_fem.solvers.fem.mixture_transient).

Identical species must follow the one-species FEM transient: the meshes are built the
same way, the operators are the one-species ones to round-off (5e-16 measured) and the
integrator's decisions are the same, so the two agree to round-off, not merely to rtol.
"""

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.model import ThresholdRestitution, ViscoelasticRestitution


@pytest.mark.slow   # 17 s
def test_identical_species_follow_the_one_species_transient():
    mix = kf.Mixture.white_noise((1.0, 1.0), (0.5, 0.5), alpha=0.6, kernel=1.0)
    times = [0.0, 0.2, 0.5]
    opts = {"initial_temperature": 0.8, "spacing": 0.5, "cutoff": 8.0, "rtol": 1e-3}
    one = kf.evolve_heated(0.6, times=times, **opts)
    ev = kf.evolve_heated(mix, times=times, **opts)
    assert ev.method == "fem" and ev.temperatures.shape == (3, 2)
    assert ev.info["n_dofs"][0] == one.info.extra["n_dofs"]
    assert ev.info["accepted"] == one.info.extra["accepted"]
    assert np.allclose(ev.temperatures[:, 0], ev.temperatures[:, 1], rtol=1e-13, atol=0)
    assert np.allclose(ev.temperatures[:, 0], one.temperature, rtol=1e-11, atol=0)
    assert np.allclose(ev.a2[:, 0], one.a2, rtol=0, atol=1e-11)


@pytest.mark.parametrize("law", [ViscoelasticRestitution(0.1), ThresholdRestitution(0.6, 0.5)])
def test_identical_species_with_a_law_follow_the_one_species_transient(law):
    """A velocity-dependent law per pair: identical species are the one-species transient
    with that law to round-off (measured: T 1e-15, a2 9e-16, the same 26 steps)."""
    mix = kf.Mixture.white_noise((1.0, 1.0), (0.5, 0.5), alpha=law, kernel=1.0)
    times = [0.0, 0.2, 0.5]
    opts = {"initial_temperature": 0.8, "spacing": 0.5, "cutoff": 8.0, "rtol": 1e-3}
    one = kf.evolve_heated(law, times=times, **opts)
    ev = kf.evolve_heated(mix, times=times, **opts)
    assert ev.info["accepted"] == one.info.extra["accepted"]
    assert np.allclose(ev.temperatures[:, 0], one.temperature, rtol=1e-12, atol=0)
    assert np.allclose(ev.a2[:, 1], one.a2, rtol=0, atol=1e-12)


@pytest.mark.slow   # 37 s
def test_a_mixture_with_a_law_relaxes_to_its_steady_fem_state():
    """Viscoelastic law, masses 1:3: at t = 30 (rtol 1e-3, spacing 0.5) T_s within 1.8e-5
    and a2_s within 2.2e-6 of the steady FEM state (measured)."""
    mix = kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=ViscoelasticRestitution(0.1))
    steady = kf.solve_heated(mix)
    ev = kf.evolve_heated(mix, times=[0.0, 15.0, 30.0], rtol=1e-3, spacing=0.5)
    assert np.allclose(ev.temperatures[-1], steady.temperatures, rtol=1e-4, atol=0)
    assert np.allclose(ev.a2[-1], steady.a2, rtol=0, atol=1e-5)


def test_fem_mixture_bad_options_name_the_argument():
    mix = kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=0.8, kernel=1.0)
    with pytest.raises(TypeError, match="spacng"):
        kf.evolve_heated(mix, times=[1.0], spacng=0.5)
    with pytest.raises(ValueError, match="order must be 1 or 2"):
        kf.evolve_heated(mix, times=[1.0], order=3)


@pytest.mark.slow   # 28 s
def test_hard_rods_relax_to_the_steady_fem_mixture():
    # measured: at t = 15, rtol 1e-3, spacing 0.5: T_s within 2.1e-5 and the ratio within
    # 8.2e-6 of the steady state, a2_s within 1.1e-6 (82 steps); the Gaussian ratio is 0.4 % off
    mix = kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=0.7, kernel=1.0)
    steady = kf.solve_heated(mix)
    ev = kf.evolve_heated(mix, times=[0.0, 5.0, 15.0], rtol=1e-3, spacing=0.5)
    assert np.allclose(ev.temperatures[-1], steady.temperatures, rtol=1e-3, atol=0)
    assert abs(ev.temperature_ratio()[-1] / steady.temperature_ratio() - 1.0) < 1e-3
    assert np.allclose(ev.a2[-1], steady.a2, rtol=0, atol=1e-3)
    gauss = kf.evolve_heated(mix, times=[0.0, 15.0], method="gaussian")
    off = abs(gauss.temperature_ratio()[-1] / steady.temperature_ratio() - 1.0)
    assert 1e-3 < off < 1e-2


def _cheap_mesh(var):
    """The default Maxwell transient mesh inside 12 thermal velocities, coarse beyond."""
    from kinetic_fem.solvers.fem.transient_setup import build_mesh

    half = build_mesh(12.0, 0.5 * np.sqrt(var), np.sqrt(var))
    half = np.concatenate([half[half >= 0], np.arange(20.0, 93.0, 8.0)])
    return np.concatenate([-half[:0:-1], half])


def test_start_from_floored_gaussian_tails_at_rtol_1e6():
    # The Gaussian start is floored (ln P continued linearly to -691 at the mesh's edge),
    # the first step closes the far tail on its line (-1022 and -1310 on the default
    # Maxwell meshes); the quadratic extrapolation through three such levels put the third
    # step's Newton start at ln P = +1628 and its stale matrix overflowed (ValueError from
    # scipy; rtol 1e-6 failed on the default meshes, and so did ev.error at rtol 1e-4).
    # Here the meshes are the default ones inside 12 and coarse beyond (cheap): before the
    # fix the same ValueError in the third step, now 6 steps without failure.
    mix = kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=0.7, kernel=0.0)
    times = [0.0, 3e-5]
    ev = kf.evolve_heated(mix, times=times, initial_temperature=1.0, rtol=1e-6,
                          vertices=[_cheap_mesh(1.0), _cheap_mesh(1.0 / 3.0)])
    exact = kf.evolve_heated(mix, times=times, initial_temperature=1.0, method="maxwell")
    assert ev.info["newton_failures"] == 0
    assert np.allclose(ev.temperatures, exact.temperatures, rtol=1e-6, atol=0)


def test_heated_fem_transient_returns_each_species_distribution():
    # f_s at every output time (the free-cooling FEM transient had them, the heated one
    # did not): normalised, with the run's T_s = m_s <v^2>_s and a2_s (the same quadrature)
    mix = kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=0.7, kernel=0.0)
    times = [0.0, 1e-5, 3e-5]
    ev = kf.evolve_heated(mix, times=times, initial_temperature=1.0, rtol=1e-4,
                          vertices=[_cheap_mesh(1.0), _cheap_mesh(1.0 / 3.0)])
    assert len(ev.distributions) == 3 and all(len(d) == 2 for d in ev.distributions)
    for i in range(3):
        for s, dist in enumerate(ev.distributions[i]):
            var = dist.moment(2, central=False)
            assert dist.moment(0, central=False) == pytest.approx(1.0, rel=1e-12)
            assert mix.masses[s] * var == pytest.approx(ev.temperatures[i, s], rel=1e-12)
            kurt = dist.moment(4, central=False) / (3.0 * var**2) - 1.0
            assert kurt == pytest.approx(ev.a2[i, s], abs=1e-12)
    assert ev.distributions[0][0].moment(2, central=False) == pytest.approx(1.0, rel=1e-3)


def test_start_under_a_heavier_partners_layer_follows_the_exact_moments():
    """Masses 1:3 from T_s = (1, 3) (equal <v^2>): the heavy species throws light rods
    beyond the light Gaussian's far tail, which gains there up to 1e11 times its value per
    unit time.  Before the fix no first step converged (Newton down to 7e-15); now the
    layer is filled (``layer_start``) and the run follows the inelastic Maxwell mixture's
    exact moments: measured at t = 0.5 (spacing 1, cutoff 8, rtol 1e-3) T_s 4.2e-6
    relative, a2_s 7.7e-5 absolute (4 s)."""
    mix = kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=0.8, kernel=0.0)
    times = [0.0, 0.5]
    exact = kf.evolve_heated(mix, times=times, initial_temperature=[1.0, 3.0],
                             method="maxwell")
    ev = kf.evolve_heated(mix, times=times, initial_temperature=[1.0, 3.0], spacing=1.0,
                          cutoff=8.0, rtol=1e-3)
    # the start: the Gaussians on the coarse meshes (measured 2.5e-6 and 2.6e-6 off)
    assert np.allclose(ev.temperatures[0], [1.0, 3.0], rtol=5e-6, atol=0)
    assert np.allclose(ev.temperatures, exact.temperatures, rtol=1e-5, atol=0)
    assert np.allclose(ev.a2, exact.a2, rtol=0, atol=1.5e-4)

