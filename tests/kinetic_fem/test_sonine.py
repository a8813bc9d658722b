"""Tests of kinetic_fem.sonine: the analytic first-order Sonine and scaling results.

Theory (1D, heated): a2 = 16 (1 - 2 alpha^2) / (129 + 30 alpha^2), a2 -> -16/159;
energy balance 2D = (n/4)(1 - alpha^2) <|v - v'|^3> with
<|v - v'|^3> = (8/sqrt(pi)) T^(3/2) (1 + 3 a2/16); Haff's law
dT/dt = -(n/4)(1 - alpha^2) <|v - v'|^3>.
"""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from kinetic_fem import VelocityDistribution
from kinetic_fem.operators.collision import pair_moment
from kinetic_fem.operators.grid import simpson_weights
from kinetic_fem.sonine import (
    A2_ELASTIC_LIMIT,
    a2_first_order,
    crossover_velocities,
    haff_temperature,
    relative_speed_cubed,
    relaxation_time,
    steady_temperature,
    tail_exponent_amplitude,
)

alphas = st.floats(0.0, 1.0, exclude_max=True)


def test_a2_first_order_values():
    assert a2_first_order(0.0) == pytest.approx(16 / 129, rel=1e-15)
    assert a2_first_order(1 / math.sqrt(2)) == pytest.approx(0.0, abs=1e-15)
    assert a2_first_order(1.0) == pytest.approx(-16 / 159, rel=1e-15)
    assert A2_ELASTIC_LIMIT == -16 / 159
    out = a2_first_order([0.0, 0.5, 1.0])
    assert isinstance(out, np.ndarray) and out.shape == (3,)
    assert isinstance(a2_first_order(0.3), float)


@given(alphas)
def test_a2_first_order_decreases_between_its_limits(alpha):
    a2 = a2_first_order(alpha)
    assert A2_ELASTIC_LIMIT <= a2 <= 16 / 129
    assert a2_first_order(min(alpha + 1e-3, 1.0)) < a2


@pytest.mark.parametrize("bad", [-0.1, 1.1, float("nan"), [0.5, 2.0]])
def test_a2_first_order_rejects_bad_alpha(bad):
    with pytest.raises(ValueError, match=r"alpha must lie in \[0, 1\]"):
        a2_first_order(bad)


def test_relative_speed_cubed_of_a_gaussian():
    """<|v - v'|^3> of two independent Gaussians of temperature T, by O(N) quadrature."""
    t = 1.7
    v = np.linspace(-15, 15, 3001) * math.sqrt(t)
    p = np.exp(-v**2 / (2 * t)) / math.sqrt(2 * math.pi * t)
    assert pair_moment(v, p, simpson_weights(v), 3) == pytest.approx(
        relative_speed_cubed(t), rel=1e-9)


@given(alphas, st.floats(0.1, 10), st.floats(0.1, 10))
def test_steady_temperature_balances_energy(alpha, density, diffusion):
    t = steady_temperature(alpha, density, diffusion)
    loss = density / 4 * (1 - alpha**2) * relative_speed_cubed(t, a2_first_order(alpha))
    assert loss == pytest.approx(2 * diffusion, rel=1e-10)
    t0 = steady_temperature(alpha, density, diffusion, a2=0.0)
    assert t0 == pytest.approx((math.sqrt(math.pi) * diffusion
                                / (density * (1 - alpha**2))) ** (2 / 3), rel=1e-12)


def test_relaxation_time_scales_as_eps_to_minus_two_thirds():
    """tau(eps) / tau(eps/8) -> 1/4 as eps -> 0 (C2)."""
    ratios = [relaxation_time(1 - e) / relaxation_time(1 - e / 8) for e in (1e-2, 1e-4, 1e-6)]
    assert abs(ratios[-1] - 0.25) < 1e-6
    assert abs(ratios[0] - 0.25) > abs(ratios[-1] - 0.25)


def test_tail_amplitude_and_crossovers():
    assert tail_exponent_amplitude() == pytest.approx(2 / 3)
    assert tail_exponent_amplitude(4.0, 1.0) == pytest.approx(4 / 3)
    assert tail_exponent_amplitude(1.0, 1.0, temperature=16.0) == pytest.approx(2 / 3 * 8)
    v1, v2 = crossover_velocities(0.9)
    assert v1 == pytest.approx(10 ** (1 / 3))
    assert v2 == pytest.approx(100 ** (1 / 3))
    # v_cr2 / v_cr1 = eps^(-1/3) grows as eps -> 0
    v1, v2 = crossover_velocities(1 - 1e-6, density=2.0, diffusion=3.0)
    assert v2 / v1 == pytest.approx(100.0, rel=1e-6)
    with pytest.raises(ValueError, match="temperature"):
        tail_exponent_amplitude(temperature=-1.0)


@given(st.floats(0.0, 0.99), st.floats(0.1, 10), st.floats(0.1, 10))
def test_haff_law_solves_the_cooling_equation(alpha, density, t0):
    """T(t) from haff_temperature satisfies dT/dt = -(n/4)(1-alpha^2)<|v-v'|^3>."""
    assert haff_temperature(0.0, alpha, density, t0) == pytest.approx(t0)
    t = np.array([0.3, 2.0, 50.0])
    temp = haff_temperature(t, alpha, density, t0)
    h = 1e-5 * t
    deriv = (haff_temperature(t + h, alpha, density, t0)
             - haff_temperature(t - h, alpha, density, t0)) / (2 * h)
    rate = np.array([density / 4 * (1 - alpha**2) * relative_speed_cubed(x) for x in temp])
    np.testing.assert_allclose(deriv, -rate, rtol=1e-6)


def test_haff_late_times_decay_as_t_minus_two():
    t = np.array([1e6, 1e7])
    temp = haff_temperature(t, 0.9)
    assert temp[0] / temp[1] == pytest.approx(100.0, rel=1e-4)


def test_sonine_coefficient_of_first_order_distribution():
    """Phi(c)(1 + a2 S2) has exactly this a2 (consistency of the two modules)."""
    a2 = a2_first_order(0.2)
    c = np.linspace(-12, 12, 2401)
    s2 = c**4 / 8 - 3 * c**2 / 4 + 3 / 8
    d = VelocityDistribution.from_values(c, np.exp(-c**2 / 2) * (1 + a2 * s2))
    assert d.a2 == pytest.approx(a2, rel=1e-10)
    assert abs(d.sonine_coefficient(3)) < 1e-10


@pytest.mark.parametrize("func", [steady_temperature, relaxation_time, crossover_velocities])
def test_bad_parameters(func):
    with pytest.raises(ValueError, match="alpha"):
        func(1.0)
    with pytest.raises(ValueError, match="density"):
        func(0.5, density=0.0)
    with pytest.raises(TypeError, match="diffusion"):
        func(0.5, diffusion="1")
