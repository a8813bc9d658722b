"""DSMC with a kernel that is not a power law: the saturating kernel |g|/(1 + |g|/g0).

The DSMC support of a kernel family is its acceptance :math:`B(|g|)/B(g_{max})` and its
majorant :math:`B(g_{max})` (``particles._dsmc_kernels``); the heated driver, the
transient and the engine read the kernel's answers.  Checked here: the acceptance
probability (binomial, 4.5 sigma), conservation, the compiled loop against its Python
version, and the heated steady state against FEM in physical units (``n = 2, D = 3``:
the DSMC has no reduction to ``n = D = 1``, FEM does, through the kernel's rescaling
:math:`g_0 \\to g_0/u`).  Tolerance: 4 standard errors of each run (batch errors),
fixed seeds; measured z-scores in the docstrings.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.model import SaturatingKernel, ViscoelasticRestitution
from kinetic_fem.model.restitution import VISCOELASTIC
from particles import _dsmc_kernels as kern
from particles import _dsmc_model as model
from particles import _dsmc_segments as seg
from particles import dsmc, dsmc_transient, rng

TABLES = rng.ziggurat_tables()


@pytest.fixture
def wrapping():
    with np.errstate(over="ignore"):
        yield


def _state(seed=0):
    return np.random.SeedSequence(seed).generate_state(4, dtype=np.uint64)


@pytest.mark.parametrize("g0", [0.3, 2.0])
def test_saturating_acceptance_is_b_over_b_max(g0, wrapping):
    """Two particles at distance x g_max: the acceptance is Binomial(m, B(x)/B(g_max))."""
    m = 100_000
    for x in (0.2, 0.7):
        v = np.array([x, 0.0])
        acc, _ = kern.collide_power(v, m, model.KERNEL_SATURATING, g0, 0, -1.0, 0.0, 1.0, 1.0,
                                    _state(3))
        p = (x / (1 + x / g0)) / (1 / (1 + 1 / g0))
        assert abs(acc - m * p) < 4.5 * math.sqrt(m * p * (1 - p)), (x, acc / m, p)


def test_saturating_conserves_momentum_and_loses_the_stated_energy(wrapping):
    v = np.random.default_rng(4).normal(size=400)
    p_tot, e0 = v.sum(), np.sum(v**2)
    lo, hi = seg.extent(v)
    acc, loss = kern.collide_model(v, 20_000, model.KERNEL_SATURATING, 0.8, VISCOELASTIC, 0.2,
                                   0.0, hi - lo, 1.0, _state(4))
    assert acc > 1000
    assert abs(v.sum() - p_tot) < 1e-10
    assert np.sum(v**2) == pytest.approx(e0 - 0.5 * loss, rel=1e-10)


def test_saturating_heated_segment_is_its_python_version(wrapping):
    v0 = np.random.default_rng(5).normal(size=60)
    args = (4, 0.1, 1.0, 0.3, 1.0, 0.2, 30.0, model.KERNEL_SATURATING, 0.7, 0, 0.6, 0.0,
            math.inf, 0.0)
    outs = []
    for f in (seg.heated_segment, seg.heated_segment.py_func):
        v = v0.copy()
        outs.append((v, f(v, *args, rng.heated_state(np.random.SeedSequence(6)), *TABLES)))
    np.testing.assert_array_equal(outs[0][0], outs[1][0])
    assert outs[0][1] == pytest.approx(outs[1][1], rel=1e-12)


def _z(run, fem):
    t_err = run.distribution.observable_error(lambda d: d.temperature)
    return (run.temperature - fem.temperature) / t_err, (run.a2 - fem.a2) / run.a2_error


@pytest.mark.parametrize("seed", [1, 2])
def test_heated_state_against_fem_in_physical_units(seed):
    """g0 = 2, n = 2, D = 3, alpha = 0.6 (FEM T = 6.5444, a2 = 0.1218); N = 10000, 500
    collisions per particle: T to 0.2 %, a2 to 2.5e-3 (one standard error).  Measured
    z (T, a2): seed 1 (+0.6, +1.4), 2 (-0.2, -1.5), 3 (+0.8, +0.3) at N = 4000."""
    k = SaturatingKernel(2.0)
    fem = kf.solve_heated(0.6, kernel=k, density=2.0, diffusion=3.0)
    run = dsmc.simulate_heated(0.6, 10_000, kernel=k, density=2.0, diffusion=3.0, seed=seed,
                               collisions_per_particle=500)
    z_t, z_a2 = _z(run, fem)
    assert abs(z_t) < 4 and abs(z_a2) < 4, (z_t, z_a2)


@pytest.mark.parametrize("seed", [2, 3])
def test_transient_against_the_fem_transient(seed):
    """The DSMC transient (8 replicas of N = 4000) from a Gaussian at T = 3 against
    ``evolve_heated`` at t = 5 and the steady state at t = 60 (g0 = 1, alpha = 0.6).
    Measured z (T(5), a2(5), T(60), a2(60)) over seeds 2..7: within [-1.1, +1.8], one
    a2(60) at -2.3."""
    k = SaturatingKernel(1.0)
    ev = kf.evolve_heated(0.6, kernel=k, initial_temperature=3.0, times=[0.0, 5.0],
                          rtol=1e-3)
    steady = kf.solve_heated(0.6, kernel=k)
    run = dsmc_transient.simulate_protocol(0.6, 4000, times=[0.0, 5.0, 60.0], kernel=k,
                                           seed=seed, initial_temperature=3.0, replicas=8)
    for i, ref in ((1, (ev.temperature[-1], ev.a2[-1])), (2, (steady.temperature, steady.a2))):
        assert abs(run.temperature[i] - ref[0]) < 4 * run.temperature_error[i]
        assert abs(run.a2[i] - ref[1]) < 4 * run.a2_error[i]


@pytest.mark.slow
@pytest.mark.parametrize("alpha, kw", [
    (0.6, dict(kernel=SaturatingKernel(1.0))),
    (0.9, dict(kernel=SaturatingKernel(1.0))),
    (0.6, dict(kernel=SaturatingKernel(0.3), friction=1.0)),
    (ViscoelasticRestitution(0.2), dict(kernel=SaturatingKernel(2.0))),
])
@pytest.mark.parametrize("seed", [11, 12, 13])
def test_models_against_fem(alpha, kw, seed):
    """N = 25000, 2000 collisions per particle (the table in docs/user_guide/models.rst)."""
    fem = kf.solve_heated(alpha, **kw)
    run = dsmc.simulate_heated(alpha, 25_000, seed=seed, collisions_per_particle=2000, **kw)
    z_t, z_a2 = _z(run, fem)
    assert abs(z_t) < 4 and abs(z_a2) < 4, (z_t, z_a2)
