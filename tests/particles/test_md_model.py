"""Tests of the model in the event-driven MD: restitution laws, the Fokker-Planck bath,
the kernel it refuses (particles.md with kinetic_fem.model)."""

from __future__ import annotations

import math
import runpy
from pathlib import Path

import numpy as np
import pytest

from kinetic_fem.model import (
    FokkerPlanckBath,
    ThresholdRestitution,
    UnsupportedModelError,
    ViscoelasticRestitution,
    WhiteNoise,
)
from particles import md

EXAMPLES = Path(__file__).parents[2] / "docs" / "examples"


def test_bath_kicks_are_the_exact_ornstein_uhlenbeck_transition():
    """d = exp(-xi dt), b^2 = T_b (1 - d^2): the Gaussian at T_b is stationary for every dt."""
    for dt in (1e-6, 0.1, 3.0):
        k = md.Kicks.from_thermostat(FokkerPlanckBath(2.0, 3.0), dt)
        assert k.interval == dt and k.decay == pytest.approx(math.exp(-2.0 * dt), rel=1e-15)
        # 1 - d^2 = -expm1(-2 xi dt), without the cancellation of 1 - d^2 at small dt
        assert k.amplitude**2 == pytest.approx(-1.5 * math.expm1(-4.0 * dt), rel=1e-14)
    white = md.Kicks.from_thermostat(WhiteNoise(2.0), 0.5)
    assert (white.decay, white.amplitude) == (1.0, math.sqrt(2.0))


def test_elastic_rods_in_a_bath_reach_the_bath_gaussian():
    """alpha = 1, Fokker-Planck bath (xi = 2, D = 1): Gaussian at T_b = D/xi = 1/2.

    Elastic collisions permute the velocities and the kicks are the exact OU
    transition, so iid N(0, T_b) is stationary for any kick interval: the central
    variance has mean T_b (1 - 1/N) and a2 = 0.  Started far away (flat, T = 3);
    tolerance 5 batch standard errors (20 batches).  40 seeds of this run: mean T
    0.49902 against 0.49900, a2 +0.0004 +- 0.0007; the spread over seeds is 0.86 (T)
    and 1.21 (a2) times the batch error, largest |z| 2.1 and 3.0.
    """
    n = 500
    v0 = np.random.default_rng(1).uniform(-3.0, 3.0, n)
    run = md.simulate_heated(1.0, n, friction=2.0, diffusion=1.0, seed=3, velocities=v0,
                             collisions_per_particle=400.0, warmup=20.0, n_batches=20)
    d = run.distribution
    t_err = d.observable_error(lambda x: x.temperature)
    assert t_err < 0.01 and d.a2_error < 0.02  # the check resolves percent-level errors
    assert abs(d.temperature - 0.5 * (1 - 1 / n)) < 5 * t_err
    assert abs(d.a2) < 5 * d.a2_error
    assert run.energy_balance_error < 1e-12
    assert np.all(run.series["energy_dissipated"] == 0.0)
    assert run.params["friction"] == 2.0 and run.n_kicks > 1000


def test_two_rods_follow_the_restitution_law():
    """N = 2 at +-g/2: each collision maps g to alpha(g) g; the energy sum v^2/2 is (g/2)^2."""
    law = ViscoelasticRestitution(0.3)
    run = md.simulate_cooling(law, 2, sigma=0.1, positions=[0.0, 1.0], velocities=[1.0, -1.0],
                              collisions_per_particle=4.0, n_samples=1, n_batches=1)
    g = 2.0
    for _ in range(4):
        g *= float(law(g))
    assert run.n_collisions == 4 and run.n_elastic == 0
    assert math.isclose(run.series["energy"][-1], (g / 2) ** 2, rel_tol=1e-14)
    # threshold law: the first collision (g = 2) is inelastic, the slower ones elastic
    run = md.simulate_cooling(ThresholdRestitution(0.25, threshold=1.0), 2, sigma=0.1,
                              positions=[0.0, 1.0], velocities=[1.0, -1.0],
                              collisions_per_particle=3.0, n_samples=1, n_batches=1)
    assert run.n_elastic == 2
    assert math.isclose(run.series["energy"][-1], 0.25**2, rel_tol=1e-14)


@pytest.mark.parametrize("law", [ThresholdRestitution(0.7, threshold=0.05),
                                 ViscoelasticRestitution(0.2)], ids=["threshold", "visco"])
def test_restitution_laws_conserve_momentum_and_balance_energy(law):
    """Free cooling and heating (white noise, bath) with velocity-dependent laws."""
    v0 = np.random.default_rng(0).normal(0.3, 1.0, 300)
    run = md.simulate_cooling(law, 300, seed=5, collisions_per_particle=300.0, velocities=v0,
                              threshold=1e-6)
    p = run.series["momentum"]
    assert np.max(np.abs(p - p[0])) < 1e-11 * 300
    assert run.energy_balance_error < 1e-12
    assert run.series["energy"][-1] < 0.5 * run.series["energy"][0]
    for friction in (0.0, 1.0):
        heated = md.simulate_heated(law, 300, friction=friction, seed=6,
                                    collisions_per_particle=100.0)
        assert heated.energy_balance_error < 1e-12
        assert heated.series["energy_dissipated"][-1] > 0.0
        assert heated.params["restitution"] == repr(law)


def test_threshold_law_is_the_regularised_constant_law():
    """ThresholdRestitution(alpha, s) == constant alpha with the MD threshold s, bit for bit."""
    kw = {"seed": 8, "collisions_per_particle": 200.0}
    a = md.simulate_cooling(ThresholdRestitution(0.8, 1e-3), 200, **kw)
    b = md.simulate_cooling(0.8, 200, threshold=1e-3, **kw)
    c = md.simulate_cooling(ThresholdRestitution(0.8, 1e-4), 200, threshold=1e-3, **kw)
    assert a.n_elastic == b.n_elastic == c.n_elastic > 0
    assert np.array_equal(a.velocities, b.velocities)
    assert np.array_equal(a.velocities, c.velocities)


def test_bad_model_input():
    with pytest.raises(UnsupportedModelError, match="hard rods only.*particles.dsmc"):
        md.simulate_heated(0.9, 10, kernel=0.0)
    with pytest.raises(UnsupportedModelError, match="hard rods only"):
        md.simulate_cooling(0.9, 10, kernel=2.0)
    with pytest.raises(ValueError, match="gamma"):
        md.simulate_cooling(0.9, 10, kernel=3.0)
    with pytest.raises(ValueError, match="friction"):
        md.simulate_heated(0.9, 10, friction=-1.0)
    with pytest.raises(ValueError, match="no steady state"):
        md.simulate_heated(1.0, 10, friction=0.0)
    with pytest.raises(ValueError, match=r"\[0, 1\]"):
        md.simulate_cooling(1.2, 10)
    # a law that leaves its range: refused before running ...
    with pytest.raises(ValueError, match="smaller delta"):
        md.simulate_heated(ViscoelasticRestitution(1.0), 10)
    with pytest.raises(ValueError, match="initial velocities"):
        md.simulate_cooling(ViscoelasticRestitution(0.5), 4, velocities=[-5.0, 0.0, 1.0, 4.0])
    # ... or, if a collision gets there anyway, stopped by the kernel
    law = ViscoelasticRestitution(1.0)  # defined up to g = 0.63
    rng = np.random.default_rng(1)
    y, v = md.initial_state(50, density=1.0, sigma=0.5, temperature=1.0, rng=rng)
    eng = md.MDEngine(y, v, md.EngineOptions(25.0, 0.5, law), rng)
    with pytest.raises(ValueError, match="a collision of the MD run"):
        eng.advance(1000)


def test_thermostats_example_numbers():
    """docs/examples/plot_thermostats.py: both thermostats at one T (exact rescaling).

    The FEM bath state, rescaled by s = sqrt(T_white/T_bath), has the white-noise T to
    round-off; the bath pulls a2 towards 0 and the tail towards a Gaussian (effective
    exponent at c = 4 nearer 2); both MD runs balance energy to round-off.
    """
    ns = runpy.run_path(str(EXAMPLES / "plot_thermostats.py"))
    r = ns["result"]
    assert r.bath.temperature == pytest.approx(r.white.temperature, rel=1e-12)
    assert r.bath_temperature > r.white.temperature
    assert 0 < r.bath.a2 < r.white.a2
    assert r.bath.effective_exponent([4.0])[0] > r.white.effective_exponent([4.0])[0]
    assert r.md_bath.params["friction"] == r.friction > 0
    assert max(r.md_white.energy_balance_error, r.md_bath.energy_balance_error) < 1e-12


@pytest.mark.slow
def test_bath_md_agrees_with_fem_near_elastic():
    """alpha = 0.95, xi = D = 1 (T_b = 1): MD (n sigma = 0.5) against FEM at n/(1 - n sigma).

    Errors: batch errors of 4 runs combined (40 batches).  Measured (6 seeds, 800 cpp,
    N = 2000): T = 0.9046 +- 0.0016 at the default kick interval and 0.9050 +- 0.0008
    at a quarter of it (no resolved kick-interval bias), a2 = -0.0116 +- 0.0009 and
    -0.0117 +- 0.0008; FEM T = 0.9054, a2 = -0.0121.  (At alpha = 0.8 the MD a2 is
    0.0008 +- 0.0009 against FEM -0.0110: velocity correlations of the dense MD gas.)
    Five other groups of 4 seeds: z(T) from -1.75 to -0.2 (MD about 0.1 % low), z(a2)
    within +-0.7.
    """
    import kinetic_fem as kf

    fem = kf.solve_heated(0.95, density=2.0, diffusion=1.0, friction=1.0)
    runs = [md.simulate_heated(0.95, 2000, friction=1.0, seed=200 + s,
                               collisions_per_particle=800.0, n_records=10) for s in range(4)]
    t = np.mean([r.temperature for r in runs])
    t_err = math.sqrt(sum(r.distribution.observable_error(lambda d: d.temperature) ** 2
                          for r in runs)) / len(runs)
    a2 = np.mean([r.a2 for r in runs])
    a2_err = math.sqrt(sum(r.a2_error**2 for r in runs)) / len(runs)
    assert abs(t - fem.temperature * (1 - 1 / 2000)) < 4 * t_err
    assert abs(a2 - fem.a2) < 4 * a2_err
