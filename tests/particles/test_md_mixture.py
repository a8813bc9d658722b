"""Event-driven MD of mixtures (particles.md_mixture).

* Equal masses: the mixture branch of the kernel follows the one-species trajectory
  bit for bit (heated and cooling), and the driver's temperatures agree with the
  one-species MD (|z| < 4).
* Bookkeeping: momentum sum m_i v_i and the energy (kinetic + dissipated) are conserved
  per collision to round-off in free cooling.
* Equilibrium: elastic rods in baths at one bath temperature reach equipartition.
* MD against DSMC for the temperature ratio where molecular chaos holds: a bath that
  redraws the velocities faster than the rods collide (in 1D a rod only ever meets its two
  neighbours, so light rods caged between heavy ones recollide; without such a bath MD
  and the Boltzmann equation differ for unequal masses: see docs/user_guide/mixtures.rst).
"""

import numpy as np
import pytest

from kinetic_fem.model import FokkerPlanckBath, UnsupportedModelError
from kinetic_fem.model.mixture import Mixture
from kinetic_fem.model.restitution import (
    ConstantRestitution,
    ThresholdRestitution,
    ViscoelasticRestitution,
)
from particles import dsmc_mixture, md
from particles._md_engine import EngineOptions, Kicks, MDEngine, MixtureRods
from particles._md_kernels import F_DISS
from particles.md_mixture import simulate_mixture

Z_MAX = 4.0


def _engines(heated, masses=(1.0, 1.0), n=200):
    rng = np.random.default_rng(0)
    y = np.sort(rng.uniform(0.0, 100.0, n))
    v = rng.standard_normal(n)
    v -= v.mean()
    kicks = Kicks(0.05, 1.0, 0.3) if heated else Kicks()
    law = ConstantRestitution(0.9)
    species = np.arange(n, dtype=np.int64) % 2
    rods = MixtureRods.of(species, np.array(masses), ((law, law), (law, law)),
                          np.ones(n) if heated else np.zeros(0))
    one = MDEngine(y, v, EngineOptions(100.0, 0.5, law, 0.0, kicks), np.random.default_rng(5))
    mix = MDEngine(y, v, EngineOptions(100.0, 0.5, law, 0.0, kicks, species=rods),
                   np.random.default_rng(5))
    return one, mix


@pytest.mark.parametrize("heated", [False, True])
def test_equal_masses_follow_the_one_species_trajectory(heated):
    one, mix = _engines(heated)
    for target in (100, 1000, 3000):
        one.advance(target)
        mix.advance(target)
        assert np.array_equal(one.v, mix.v)
        assert one.fstate[0] == mix.fstate[0]
    assert mix.pair_counts.sum() == 3000


def test_momentum_and_energy_bookkeeping_per_collision():
    _, eng = _engines(False, masses=(1.0, 7.0))
    mass = np.array([1.0, 7.0])[np.arange(200) % 2]
    p0 = float(np.sum(mass * eng.v))
    e0 = 0.5 * float(np.sum(mass * eng.v**2))
    for target in range(1, 400):
        eng.advance(target)
        p = float(np.sum(mass * eng.v))
        e = 0.5 * float(np.sum(mass * eng.v**2)) + eng.fstate[F_DISS]
        scale = float(np.sum(mass * np.abs(eng.v)))
        assert abs(p - p0) < 1e-13 * scale * target**0.5 + 1e-14
        assert abs(e - e0) < 1e-14 * e0 * target + 1e-14
    assert eng.fstate[F_DISS] > 0.0


def test_equal_masses_give_the_one_species_temperature():
    # over 12 seeds of small runs: the batch errors of one heated run underestimate its
    # error (the energy relaxes over ~1/(1 - alpha^2) collisions), the seed spread does not
    mix = Mixture.white_noise((1.0, 1.0), (0.5, 0.5), alpha=0.9)
    pairs = []
    for seed in range(12):
        run = simulate_mixture(mix, 100, seed=seed, collisions_per_particle=300.0)
        one = md.simulate_heated(0.9, 100, seed=seed, collisions_per_particle=300.0)
        pairs.append([run.temperature, one.temperature, run.distributions[0].a2, one.a2])
    values = np.array(pairs)
    mean = values.mean(axis=0)
    err = values.std(axis=0, ddof=1) / np.sqrt(len(values))
    assert abs(mean[0] - mean[1]) / np.hypot(err[0], err[1]) < Z_MAX
    assert abs(mean[2] - mean[3]) / np.hypot(err[2], err[3]) < Z_MAX


def test_elastic_rods_in_baths_reach_equipartition():
    baths = (FokkerPlanckBath(1.0, 0.1), FokkerPlanckBath(1.0, 0.025))  # T_b = 0.1
    mix = Mixture((1.0, 4.0), (0.5, 0.5), alpha=1.0, thermostats=baths)
    run = simulate_mixture(mix, 200, seed=1, collisions_per_particle=300.0, sigma=0.1)
    assert np.all(np.abs(run.temperatures - 0.1) / run.temperature_errors < Z_MAX)
    assert run.collision_counts[0, 1] == run.collision_counts[1, 0] > 0


def test_free_cooling_gives_scaled_temperatures_and_a_cooling_rate():
    mix = Mixture((1.0, 2.0), (0.5, 0.5), alpha=0.95)
    run = simulate_mixture(mix, 100, seed=3, collisions_per_particle=60.0, threshold=1e-3)
    assert abs(float(np.dot(mix.fractions, run.batch_temperatures.mean(axis=0))) - 1.0) < 1e-12
    assert run.zeta is not None and run.zeta > 0.0 and run.zeta_error > 0.0


def test_md_mixture_rejects_what_it_cannot_do():
    with pytest.raises(UnsupportedModelError, match="hard rods"):
        simulate_mixture(Mixture.white_noise((1.0, 2.0), (0.5, 0.5), kernel=0.0), 100)
    baths = (FokkerPlanckBath(1.0, 1.0), FokkerPlanckBath(2.0, 1.0))
    with pytest.raises(UnsupportedModelError, match="friction"):
        simulate_mixture(Mixture((1.0, 2.0), (0.5, 0.5), thermostats=baths), 100)
    with pytest.raises(ValueError, match="n_particles"):
        simulate_mixture(Mixture((1.0, 2.0), (0.3, 0.7)), 101)
    with pytest.raises(ValueError, match="warmup"):
        simulate_mixture(Mixture((1.0, 2.0), (0.5, 0.5)), 100, warmup=300.0)
    # free cooling: every batch needs an interval between samples for its cooling rate
    # (n_samples = n_batches gave a NaN zeta), and time must pass within it
    with pytest.raises(ValueError, match="n_samples"):
        simulate_mixture(Mixture((1.0, 2.0), (0.5, 0.5)), 100, n_samples=2, n_batches=2)
    with pytest.raises(ValueError, match="no time passed"):
        simulate_mixture(Mixture((1.0, 2.0), (0.5, 0.5)), 4, seed=1,
                         collisions_per_particle=1e-3, n_samples=3, n_batches=2,
                         threshold=1e-3)


#: MD at n = 0.2, n sigma = 0.1 collides at the density of the points on the reduced ring,
#: n / (1 - n sigma) (the 1D Enskog factor): DSMC runs there
MD_DENSITY, MD_SIGMA = 0.2, 0.5
DSMC_DENSITY = MD_DENSITY / (1.0 - MD_DENSITY * MD_SIGMA)


def _bath_mixture(alpha):
    baths = (FokkerPlanckBath(1.0, 1.0), FokkerPlanckBath(1.0, 0.25))  # T_b = 1
    return Mixture((1.0, 4.0), (0.5, 0.5), alpha=alpha, thermostats=baths)


def _md_against_dsmc_z(mix, seed=4):
    """z of the MD temperature ratio (200 rods, 600 collisions each) against the DSMC's
    (400 rods, 150 collisions each) at the reduced-ring density."""
    run = simulate_mixture(mix, 200, seed=seed, collisions_per_particle=600.0,
                           density=MD_DENSITY, sigma=MD_SIGMA)
    ref = dsmc_mixture.simulate_mixture(mix, 400, seed=seed, collisions_per_particle=150.0,
                                        relax=20.0, density=DSMC_DENSITY)
    err = np.hypot(run.temperature_ratio_error(), ref.temperature_ratio_error())
    return (run.temperature_ratio() - ref.temperature_ratio()) / err


def test_md_against_dsmc_temperature_ratio_fast():
    assert abs(_md_against_dsmc_z(_bath_mixture(0.5))) < Z_MAX


@pytest.mark.slow
@pytest.mark.parametrize(("alpha", "seed"), [(0.5, 11), (0.65, 13), (0.8, 12)])
def test_md_against_dsmc_temperature_ratio(alpha, seed):
    # measured z: -0.83, -1.74, +0.33; at alpha = 0.2 (seed 13) MD is low by z = -5.6
    # (0.911 against 0.929): recollisions at strong inelasticity, outside this regime
    mix = _bath_mixture(alpha)
    run = simulate_mixture(mix, 500, seed=seed, collisions_per_particle=3000.0,
                           density=MD_DENSITY, sigma=MD_SIGMA)
    ref = dsmc_mixture.simulate_mixture(mix, 2000, seed=seed, collisions_per_particle=600.0,
                                        density=DSMC_DENSITY)
    err = np.hypot(run.temperature_ratio_error(), ref.temperature_ratio_error())
    assert abs(run.temperature_ratio() - ref.temperature_ratio()) / err < Z_MAX
    # and the ratio is resolved away from equipartition
    assert (1.0 - ref.temperature_ratio()) / err > Z_MAX


def test_restitution_laws_per_pair_against_dsmc():
    """A viscoelastic law (delta 0.3: alpha 0.75 - 0.70 at g = 0.5 - 2) for every pair, and
    a table mixing it with a constant and a threshold law, in baths (T_b = 1): the MD
    temperature ratio agrees with the DSMC's at the reduced-ring density (measured z over
    seeds 4-6: -1.5 to +0.6)."""
    law = ViscoelasticRestitution(0.3)
    for alpha in (law, [[law, 0.7], [0.7, ThresholdRestitution(0.6, 0.3)]]):
        assert abs(_md_against_dsmc_z(_bath_mixture(alpha))) < Z_MAX


def test_restitution_laws_md_errors():
    """Free cooling has no scaled state with a law (the error names evolve_mixture); a
    relative speed beyond a law's range stops the run with a ValueError saying so."""
    with pytest.raises(UnsupportedModelError, match="evolve_mixture"):
        simulate_mixture(Mixture((1.0, 2.0), (0.5, 0.5), alpha=ViscoelasticRestitution(0.1)),
                         100, seed=1)
    fast = _bath_mixture(ViscoelasticRestitution(1.0))  # defined up to |g| = 0.197
    with pytest.raises(ValueError, match="max_speed"):
        simulate_mixture(fast, 100, seed=1, collisions_per_particle=50.0,
                         density=MD_DENSITY, sigma=MD_SIGMA)
