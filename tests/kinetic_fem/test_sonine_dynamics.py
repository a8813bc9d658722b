"""First-Sonine ODEs of :mod:`kinetic_fem.analysis.sonine_dynamics`.

Theory: for the Maxwell model (gamma = 0) the first-Sonine closure is exact (the pair
averages involve moments up to the fourth only), so T(t) and a2(t) equal the closed
moment equations of :mod:`kinetic_fem.solvers.maxwell` along any protocol; for hard
rods under white noise the steady a2 is the paper's 16(1 - 2 alpha^2)/(129 + 30 alpha^2).
"""

import math

import numpy as np
import pytest

from kinetic_fem.analysis.sonine_dynamics import (
    evolve_sonine,
    pair_average,
    sonine_rates,
    steady_sonine,
)
from kinetic_fem.model.protocol import Protocol, ramp, steps
from kinetic_fem.solvers.maxwell import evolve_moments, steady_state
from kinetic_fem.sonine import a2_first_order


def test_pair_averages_of_the_gaussian_and_first_order():
    """<|g|^p> of two unit Gaussians is E|N(0, 2)|^p; <|g|^3> = 8/sqrt(pi)(1 + 3 a2/16)."""
    for p in (0.0, 1.0, 2.5, 3.0, 5.0):
        exact = 2.0**p * math.gamma((p + 1) / 2) / math.sqrt(math.pi)
        assert pair_average(p, 0)[0] == pytest.approx(exact, rel=1e-14)
    a0, a1, _ = pair_average(3.0, 0)
    assert a1 / a0 == pytest.approx(3 / 16, rel=1e-13)
    # <g^4> = 2<v^4> + 6<v^2>^2 = 12 + 6 a2 exactly; <G^2 g^2> = <(v1^2 - v2^2)^2>/4
    assert pair_average(4.0, 0) == pytest.approx((12.0, 6.0, 0.0), abs=1e-13)
    assert pair_average(2.0, 2) == pytest.approx((1.0, 1.5, 0.0), abs=1e-13)


@pytest.mark.parametrize("alpha", [0.0, 0.3, 0.7, 0.95])
def test_hard_rod_steady_a2_is_the_papers_first_order(alpha):
    t, a2 = steady_sonine(alpha)
    assert a2 == pytest.approx(float(a2_first_order(alpha)), abs=1e-12)
    # energy balance: 2D = (1 - alpha^2)/4 <|g|^3>
    assert 2.0 == pytest.approx(0.25 * (1 - alpha**2) * 8 / math.sqrt(math.pi)
                                * (1 + 3 * a2 / 16) * t**1.5, rel=1e-10)


@pytest.mark.parametrize("alpha", [0.2, 0.8])
def test_maxwell_steady_state_is_exact(alpha):
    exact = steady_state(alpha, order=2, diffusion=1.0)
    for linear in (True, False):
        t, a2 = steady_sonine(alpha, gamma=0.0, linear=linear)
        assert t == pytest.approx(exact.temperature, rel=1e-12)
        assert a2 == pytest.approx(exact.a2, abs=1e-12)


def test_maxwell_transient_is_exact_along_a_protocol():
    """Steps of D and xi, a ramp, a restitution change: equal to the moment equations."""
    protocol = Protocol(diffusion=steps([1.0], [1.0, 0.2]), friction=ramp([0.5, 2.0], [0.0, 0.8]),
                        restitution=[(1.5, 0.9)])
    times = np.array([0.0, 0.4, 1.0, 1.7, 2.5, 4.0])
    sonine = evolve_sonine(0.3, kernel=0.0, times=times, protocol=protocol,
                           initial_temperature=2.0, initial_a2=-0.1, rtol=1e-12)
    m4 = 3 * 4.0 * (1 - 0.1)
    exact = evolve_moments(lambda t: 0.3 if t < 1.5 else 0.9, times,
                           diffusion=lambda t: protocol.diffusion_at(t, 1.0),
                           friction=lambda t: protocol.friction_at(t, 0.0),
                           initial_moments=[1.0, 0.0, 2.0, 0.0, m4],
                           breakpoints=protocol.breakpoints(10.0), rtol=1e-12)
    np.testing.assert_allclose(sonine.temperature, exact.temperature, rtol=1e-9)
    np.testing.assert_allclose(sonine.a2, exact.a2, atol=1e-9)


def test_friction_leaves_da2_alone_and_rates_scale():
    """da2/dt does not depend on xi; dT/dt gains -2 xi T."""
    base = sonine_rates(1.3, 0.05, 0.6)
    bath = sonine_rates(1.3, 0.05, 0.6, friction=0.7)
    assert bath[1] == pytest.approx(base[1], rel=1e-14)
    assert bath[0] - base[0] == pytest.approx(-2 * 0.7 * 1.3, rel=1e-13)


def test_bad_input():
    with pytest.raises(ValueError, match="increasing"):
        evolve_sonine(0.5, times=[1.0, 0.5])
    with pytest.raises(ValueError, match="initial_temperature"):
        evolve_sonine(0.5, times=[1.0], initial_temperature=-1.0)
