"""kf.evolve_cooling with restitution protocols, speed-dependent laws and any kernel.

kinetic_fem/solvers/fem/cooling_transient.py: a restitution change is a stop and a
restart (backward Euler) with a new discretisation; within a segment of velocity unit V
the law is ``law.rescaled(V)`` and the kernel ``kernel.rescaled(V)`` times V^d.
Figures behind the tolerances: benchmarks/cooling_protocol.py and
benchmarks/results/cooling_protocol.md.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.model import (
    InelasticGas,
    SaturatingKernel,
    ThresholdRestitution,
    UnsupportedModelError,
    ViscoelasticRestitution,
)
from kinetic_fem.model.protocol import Protocol, steps
from kinetic_fem.solvers.maxwell import evolve_moments

STEP = Protocol(restitution=[(1.0, 0.5)])


@pytest.mark.slow  # 28 s idle (rtol 1e-8); the step's fast check: the DSMC alpha-step test
def test_maxwell_alpha_step_follows_the_exact_moment_equations():
    """Maxwell model, alpha 0.9 -> 0.5 at t = 1: T and <v^4> of the closed moment
    equations to 1e-6.  Measured (spacing 0.5, newton_tol 1e-11): rtol 1e-6 T 7.2e-6,
    <v^4> 3.7e-5; rtol 1e-8 1.3e-7, 6.3e-7, and below that the step tolerance sits at its
    floor of 10 Newton tolerances (with the step control merged from i11q: 2.1e-7, 9.5e-7
    at any rtol <= 1e-8).  With newton_tol 1e-13: rtol 1e-8 T 6.5e-8, <v^4> 3.7e-7 (1114
    steps), rtol 1e-9 1.1e-8, 1.1e-7 (merged step control)."""
    times = np.array([0.25, 0.5, 1.0, 1.5, 2.0])
    ev = kf.evolve_cooling(0.9, kernel=0.0, times=times, spacing=0.5, rtol=1e-8,
                           newton_tol=1e-13, protocol=STEP)
    exact = evolve_moments(lambda t: 0.9 if t < 1.0 else 0.5, np.r_[0.0, times],
                           diffusion=0.0, friction=0.0, order=4, breakpoints=[1.0])
    assert np.abs(ev.temperature / exact.temperature[1:] - 1).max() < 1e-6
    assert np.abs(ev.moment(4) / exact.moments[1:, 4] - 1).max() < 1e-6
    # zeta = (1 - alpha^2)/4, right-continuous at the change (t = 1 has the new law)
    np.testing.assert_allclose(ev.series["zeta"], [0.0475, 0.0475, 0.1875, 0.1875, 0.1875],
                               rtol=1e-8)
    assert np.abs(ev.series["mass"] - 1).max() < 1e-12
    assert ev.info.extra["restarts"] == 1


@pytest.mark.parametrize("t0", [0.01, 1.0, 30.0])
@pytest.mark.parametrize(("law", "kernel"), [
    (ViscoelasticRestitution(0.1), 1.0),
    (ThresholdRestitution(0.5, threshold=0.6), 1.0),
    (ThresholdRestitution(0.3, threshold=0.3), 0.0),
    (0.6, SaturatingKernel(2.0)),
], ids=["viscoelastic", "threshold", "threshold-maxwell", "saturating"])
def test_initial_cooling_rate_is_the_gaussian_loss(law, kernel, t0):
    """At t = 0 the state is the Gaussian: -dT/dt = (n/4) <(1 - alpha(g)^2) B(g) g^2>
    (InelasticGas.loss_rate, quadrature to 1e-12), in the units V = sqrt(T0) of the
    first segment (the law and the kernel rescaled by V).  Measured at spacing 0.5: <= 1.9e-8
    relative (spacing 0.25: <= 4.2e-10)."""
    ev = kf.evolve_cooling(law, kernel=kernel, initial_temperature=t0,
                           times=[0.0, 1e-3 / math.sqrt(t0)], spacing=0.5, rtol=1e-4)
    loss = InelasticGas(law, 1.0, kernel).loss_rate(t0)
    assert ev.series["cooling_rate"][0] * t0 == pytest.approx(loss, rel=1e-7, abs=0.0)


@pytest.mark.slow  # 54-63 s; the law's fast check: test_initial_cooling_rate_is_the_gaussian_loss
def test_viscoelastic_velocity_scaling():
    """v -> lambda v maps delta to delta lambda^(1/5) and t to t / lambda (hard rods):
    the run from T0 = lambda^2 equals lambda^2 times the run from T0 = 1 with the
    rescaled law, at lambda times the time (same computation in units V: to round-off)."""
    lam, delta = 3.0, 0.1
    times = np.array([0.5, 2.0, 6.0])
    hot = kf.evolve_cooling(ViscoelasticRestitution(delta), initial_temperature=lam**2,
                            times=times / lam, spacing=0.5, rtol=1e-4)
    unit = kf.evolve_cooling(ViscoelasticRestitution(delta * lam**0.2), times=times,
                             spacing=0.5, rtol=1e-4)
    np.testing.assert_allclose(hot.temperature, lam**2 * unit.temperature, rtol=1e-9)
    np.testing.assert_allclose(hot.a2, unit.a2, atol=1e-9)


# 33-37 s of the default run (two transients at rtol 1e-5); the saturating kernel's fast
# checks in evolve_cooling: test_initial_cooling_rate_is_the_gaussian_loss[saturating-*]
@pytest.mark.slow
def test_saturating_kernel_tends_to_hard_rods():
    """B(g) = g/(1 + g/g0) with g0 = 1e6: hard rods to first order in sqrt(T)/g0."""
    times = np.array([0.5, 2.0])
    rods = kf.evolve_cooling(0.5, times=times, spacing=0.5, rtol=1e-5)
    sat = kf.evolve_cooling(0.5, kernel=SaturatingKernel(1e6), times=times, spacing=0.5,
                            rtol=1e-5)
    np.testing.assert_allclose(sat.temperature, rods.temperature, rtol=2e-5)


def test_saturating_kernel_has_no_scaled_cooling_state():
    """The saturating kernel is not homogeneous: allowed in physical variables
    (evolve_cooling), refused by solve_cooling."""
    with pytest.raises(UnsupportedModelError):
        kf.solve_cooling(0.5, kernel=SaturatingKernel(1.0))


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="no thermostat.*evolve_heated"):
        kf.evolve_cooling(0.5, times=[1.0], protocol=Protocol(diffusion=1.0))
    with pytest.raises(ValueError, match="no thermostat"):
        kf.evolve_cooling(0.5, times=[1.0], protocol=Protocol(friction=steps([0.5], [0, 1])))
    with pytest.raises(TypeError, match="Protocol"):
        kf.evolve_cooling(0.5, times=[1.0], protocol=[(0.5, 0.3)])
    with pytest.raises(ValueError, match="elastic"):
        kf.evolve_cooling(1.0, times=[1.0], protocol=Protocol(restitution=[(0.5, 1.0)]))
    # a hot start beyond the viscoelastic law's range (max_speed 81 for delta 0.3)
    with pytest.raises(ValueError, match="max_speed|defined for relative speeds.*colder"):
        kf.evolve_cooling(ViscoelasticRestitution(0.3), initial_temperature=100.0,
                          times=[1.0])
    with pytest.raises(ValueError, match="restitution change"):
        Protocol(restitution=[(1.0, 0.5), (0.5, 0.3)])
