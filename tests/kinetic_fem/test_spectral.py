"""Tests of the Sonine spectral solver (kinetic_fem/spectral.py)."""

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.collision import energy_balance
from kinetic_fem.grid import simpson_weights
from kinetic_fem.sonine import a2_first_order, steady_temperature
from kinetic_fem.spectral import solve_sonine


@pytest.mark.parametrize("alpha", [0.0, 0.3, 0.6, 0.9, 0.999])
def test_linearized_order_two_is_first_order_sonine(alpha):
    """Linearised P = 2 moment equations are exactly van Noije-Ernst's first order:
    a2 = 16(1-2alpha^2)/(129+30alpha^2), T from C1 with <g^3> (1 + 3a2/16)."""
    sol = solve_sonine(alpha, 2, linearized=True)
    assert abs(sol.coefficients[2] - a2_first_order(alpha)) < 1e-13
    assert abs(sol.temperature / steady_temperature(alpha) - 1) < 1e-12


@pytest.mark.parametrize("alpha", [0.6, 0.9])
def test_converges_with_order(alpha):
    """Successive orders agree: |a2(12) - a2(10)| measured 6e-8 (0.6) and 2e-8 (0.9)."""
    a10 = solve_sonine(alpha, 10).coefficients[2]
    a12 = solve_sonine(alpha, 12).coefficients[2]
    assert abs(a12 - a10) < 1e-6


def test_registered_and_energy_balance():
    """The output distribution satisfies C1 to the accuracy of the truncated tails."""
    d = kf.solve_heated(0.6, method="spectral", order=8)
    assert d.method == "spectral"
    assert abs(d.a2 - d.info.extra["sonine"][2]) < 1e-9
    c = d.v / np.sqrt(d.temperature)
    bal = energy_balance(d.v, d.values, np.sqrt(d.temperature) * simpson_weights(c),
                         alpha=0.6, density=1.0, diffusion=1.0)
    assert bal.relative_residual < 1e-6


def test_rescaling_in_density_and_diffusion():
    """T scales exactly as (D/n)^(2/3); the a_p do not depend on n, D."""
    s1 = solve_sonine(0.7, 6)
    s2 = solve_sonine(0.7, 6, density=3.0, diffusion=0.5)
    assert np.allclose(s1.coefficients, s2.coefficients, atol=1e-13)
    assert abs(s2.temperature / (s1.temperature * (0.5 / 3.0) ** (2 / 3)) - 1) < 1e-12


@pytest.mark.parametrize("order", [1, 13, 2.5, True])
def test_bad_order(order):
    with pytest.raises(ValueError, match="order"):
        solve_sonine(0.5, order)
