"""DSMC of mixtures against exact and deterministic results (particles.dsmc_mixture).

Statistical checks at fixed seeds with |z| < 4 (z = difference over the DSMC's batch
standard error): the exact Maxwell-mixture moments (disparate masses, both forcing
conventions, a bath), and identical species against the one-species FEM solution (heated
and the cooling rate of the homogeneous cooling state).
"""


import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.model import (
    FokkerPlanckBath,
    SaturatingKernel,
    ThresholdRestitution,
    UnsupportedModelError,
    ViscoelasticRestitution,
)
from kinetic_fem.model.mixture import Mixture
from kinetic_fem.solvers import maxwell_mixture as mm
from particles.dsmc_mixture import MixtureDSMCOptions, evolve_mixture, simulate_mixture

Z_MAX = 4.0


def _z(value, error, reference):
    return np.abs((np.asarray(value) - reference) / np.asarray(error))


@pytest.mark.parametrize(("masses", "convention", "seed"), [
    ((1.0, 4.0), "same_power", 1), ((1.0, 10.0), "same_diffusion", 2)])
def test_heated_maxwell_mixture_matches_the_exact_moments(masses, convention, seed):
    mix = Mixture.white_noise(masses, (0.3, 0.7), alpha=[[0.9, 0.6], [0.6, 0.4]],
                              kernel=0.0, convention=convention)
    exact = mm.steady_state(mix)
    run = simulate_mixture(mix, 1000, seed=seed, collisions_per_particle=200, relax=30)
    assert np.all(_z(run.temperatures, run.temperature_errors, exact.temperatures) < Z_MAX)
    assert np.all(_z(run.a2, run.a2_errors, exact.a2) < Z_MAX)
    ratio = exact.temperature_ratio()
    assert _z(run.temperature_ratio(), run.temperature_ratio_error(), ratio) < Z_MAX
    assert run.collision_counts[0, 1] == run.collision_counts[1, 0] > 0


def test_maxwell_mixture_in_a_bath_matches_the_exact_moments():
    baths = (FokkerPlanckBath(1.0, 1.0), FokkerPlanckBath(0.5, 2.0))
    mix = Mixture((1.0, 3.0), (0.5, 0.5), alpha=0.5, kernel=0.0, thermostats=baths)
    exact = mm.steady_state(mix)
    run = simulate_mixture(mix, 1000, seed=5, collisions_per_particle=200, relax=30)
    assert np.all(_z(run.temperatures, run.temperature_errors, exact.temperatures) < Z_MAX)


def test_identical_hard_rod_species_are_the_one_species_gas():
    fem = kf.solve_heated(0.7, diffusion=0.5)
    mix = Mixture.white_noise((2.0, 2.0), (0.5, 0.5), alpha=0.7, kernel=1.0, diffusion=0.25)
    run = simulate_mixture(mix, 1000, seed=3, collisions_per_particle=200, relax=30)
    # mass 2 under D = 0.25: <v^2> of the one-species gas at D = 0.25 ... scaled: T = m <v^2>
    # and D/n sets the scale, so T_s / 2 is the one-species <v^2> at D = 0.25
    one = fem.temperature * 0.5 ** (2.0 / 3.0)
    assert np.all(_z(run.temperatures / 2.0, run.temperature_errors / 2.0, one) < Z_MAX)
    assert np.all(_z(run.a2, run.a2_errors, fem.a2) < Z_MAX)


def test_identical_hard_rod_species_cool_at_the_one_species_rate():
    hcs = kf.solve_cooling(0.7)
    mix = Mixture((1.0, 1.0), (0.5, 0.5), alpha=0.7, kernel=1.0)
    run = simulate_mixture(mix, 1000, seed=4, collisions_per_particle=200, relax=30)
    assert _z(run.zeta, run.zeta_error, hcs.info.extra["zeta"]) < Z_MAX
    assert np.all(_z(run.a2, run.a2_errors, hcs.a2) < Z_MAX)
    assert run.temperature == pytest.approx(1.0, rel=1e-12)


def test_same_seed_same_run():
    mix = Mixture.white_noise((1.0, 2.0), (0.5, 0.5), alpha=0.8)
    a = simulate_mixture(mix, 100, seed=7, collisions_per_particle=20, relax=2)
    b = simulate_mixture(mix, 100, seed=7, collisions_per_particle=20, relax=2)
    np.testing.assert_array_equal(a.batch_temperatures, b.batch_temperatures)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"n_particles": 101}, "whole numbers"),
    ({"n_particles": 2}, "at least 2 rods"),
    ({"n_particles": 100.0}, "integer"),
    ({"n_particles": 100, "density": 0.0}, "density"),
    ({"n_particles": 100, "relax": float("nan")}, "relax"),
    ({"n_particles": 100, "collisions_per_particle": 1e300}, "1e8 steps"),
])
def test_bad_arguments_are_refused(kwargs, match):
    mix = Mixture.white_noise((1.0, 2.0), (0.5, 0.5))
    with pytest.raises((TypeError, ValueError), match=match):
        simulate_mixture(mix, **kwargs)


def test_bad_options_are_refused():
    with pytest.raises(ValueError, match="collisions_per_step"):
        MixtureDSMCOptions(collisions_per_step=2.0)
    with pytest.raises(ValueError, match="n_batches"):
        MixtureDSMCOptions(n_batches=1)


@pytest.mark.parametrize(("alpha", "kernel"), [
    (ViscoelasticRestitution(0.1), 1.0), (ThresholdRestitution(0.6, 0.5), 1.0),
    (0.7, SaturatingKernel(1.0))])
def test_identical_species_with_a_law_or_the_saturating_kernel_are_the_one_species_gas(
        alpha, kernel):
    """Restitution laws (at the pair's |g|) and kernels other than power laws: two
    identical species are the one-species gas, T_s and a2_s against the one-species FEM
    state with |z| < 4 (measured over seeds 1-6: |z| <= 3.1; seed 1 <= 1.6; 0.5 s each)."""
    mix = Mixture.white_noise((1.0, 1.0), (0.5, 0.5), alpha=alpha, kernel=kernel)
    ref = kf.solve_heated(alpha, kernel=kernel)
    run = simulate_mixture(mix, 1000, seed=1, collisions_per_particle=200, relax=30)
    assert np.all(_z(run.temperatures, run.temperature_errors, ref.temperature) < Z_MAX)
    assert np.all(_z(run.a2, run.a2_errors, ref.a2) < Z_MAX)


def test_a_law_path_with_a_constant_value_is_the_constant_run_bit_for_bit():
    """A threshold law whose threshold no relative speed reaches (1e-200) takes the law
    path of the collision kernel with the value of the constant coefficient: unequal
    masses, heated and free cooling in physical time, the same runs bit for bit."""
    tables = (0.7, [[ThresholdRestitution(0.7, 1e-200), 0.7], [0.7, 0.7]])
    heated = [simulate_mixture(Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=a), 100,
                               seed=4, collisions_per_particle=20, relax=5)
              for a in tables]
    assert np.array_equal(heated[0].batch_temperatures, heated[1].batch_temperatures)
    cooling = [evolve_mixture(Mixture((1.0, 3.0), (0.5, 0.5), alpha=a), 100,
                              times=[0.5, 1.0], seed=4, n_runs=2) for a in tables]
    assert np.array_equal(cooling[0].temperatures, cooling[1].temperatures)


def test_scaled_cooling_state_needs_a_power_law_and_constant_coefficients():
    """No scaled cooling state exists for a velocity-dependent law or a kernel that is
    not a power law: the error names evolve_mixture; a law beyond its speed range stops
    with a ValueError that says so; a run too short for its batches (here a denormal
    length, which overflowed the batch index) and a negative seed are refused up front."""
    for mix in (Mixture((1.0, 2.0), (0.5, 0.5), alpha=ViscoelasticRestitution(0.1)),
                Mixture((1.0, 2.0), (0.5, 0.5), alpha=0.8, kernel=SaturatingKernel(1.0))):
        with pytest.raises(UnsupportedModelError, match="evolve_mixture"):
            simulate_mixture(mix, 100, seed=1, collisions_per_particle=10)
    fast = Mixture.white_noise((1.0, 2.0), (0.5, 0.5), alpha=ViscoelasticRestitution(1.0),
                               diffusion=100.0)
    with pytest.raises(ValueError, match="max_speed"):
        simulate_mixture(fast, 100, seed=1, collisions_per_particle=20)
    with pytest.raises(ValueError, match="too short for n_batches=20"):
        simulate_mixture(Mixture.white_noise((1.0, 2.0), (0.5, 0.5)), 100, seed=1,
                         collisions_per_particle=5e-324)
    with pytest.raises(ValueError, match="seed"):
        simulate_mixture(Mixture.white_noise((1.0, 2.0), (0.5, 0.5)), 100, seed=-1)


def test_mixture_runs_without_jit_are_bit_identical(jit_and_plain):
    """The compiled steps (heated, scaled free cooling, free cooling in physical time, a
    restitution law) run as plain Python under NUMBA_DISABLE_JIT=1 give the same numbers
    bit for bit: the random numbers come from the kernels' own integer streams."""
    code = (
        "import kinetic_fem as kf\n"
        "from kinetic_fem.model import ViscoelasticRestitution\n"
        "from particles.dsmc_mixture import simulate_mixture, evolve_mixture\n"
        "h = kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=0.7)\n"
        "c = kf.Mixture((1.0, 3.0), (0.5, 0.5), alpha=0.7)\n"
        "law = kf.Mixture((1.0, 3.0), (0.5, 0.5), alpha=ViscoelasticRestitution(0.1))\n"
        "from particles.dsmc_mixture import MixtureDSMCOptions\n"
        "kw = dict(seed=2, collisions_per_particle=4, relax=1, progress=False,\n"
        "          options=MixtureDSMCOptions(n_batches=2))\n"
        "for mix in (h, c):\n"
        "    r = simulate_mixture(mix, 40, **kw)\n"
        "    print(r.batch_temperatures.tolist(), r.batch_zeta, r.n_collisions)\n"
        "e = evolve_mixture(law, 40, times=[0.2, 0.4], seed=2, n_runs=2)\n"
        "print(e.temperatures.tolist())\n")
    compiled, plain = jit_and_plain(code)
    assert compiled == plain and compiled.count("\n") == 3


def test_vector_range_and_power_sums_are_the_plain_loops():
    """The compiled range from integer keys is (min, max), zeros and infinities included;
    the compiled power sums on vectors equal the plain loop's (lane i % 4) bit for bit,
    whatever the remainder of the rods over the lanes."""
    import numba

    from particles import _dsmc_mixture_kernels as mk

    special = np.array([0.0, -0.0, 5e-324, -5e-324, 1e-300, -2.5, np.inf, -np.inf])
    for v in (special, special[:4], -np.abs(special[2:6]), np.array([3.0])):
        lo, hi = mk.extent_keys(v)
        assert lo == v.min() and hi == v.max()

    @numba.njit
    def compiled(x, acc):
        mk.power_sums(x, acc)

    rng = np.random.default_rng(5)
    for n in (0, 1, 3, 4, 7, 1001):
        x = rng.standard_normal(n)
        plain, fast = np.zeros((13, 4)), np.zeros((13, 4))
        mk.power_sums(x, plain)
        compiled(x, fast)
        assert np.array_equal(plain, fast)
        lanes = [x[lane::4] for lane in range(4)]
        assert np.allclose(plain[1:].T, [[np.sum(y**k) for k in range(1, 13)] for y in lanes])


def test_sample_every_below_one_collision_is_refused():
    """Measurements are at least one collision apart: below 2/N they were silently taken
    every collision."""
    mix = Mixture.white_noise((1.0, 2.0), (0.5, 0.5))
    with pytest.raises(ValueError, match=r"options.sample_every=0.01 .*n_particles=100.*"
                                         r">= 2/N = 0\.02"):
        simulate_mixture(mix, 100, collisions_per_particle=1.0, relax=0.0,
                         options=MixtureDSMCOptions(sample_every=0.01, n_batches=2))
    run = simulate_mixture(mix, 100, seed=1, collisions_per_particle=1.0, relax=0.0,
                           options=MixtureDSMCOptions(sample_every=0.02, n_batches=2))
    assert np.all(run.temperatures > 0)
