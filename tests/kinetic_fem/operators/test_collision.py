"""Tests of kinetic_fem.operators.collision: moment identities and the strong form on a grid."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.special import erf

from kinetic_fem.operators.collision import (
    collision_term,
    energy_balance,
    gain_term,
    half_grid,
    loss_frequency,
    pair_moment,
)
from kinetic_fem.sonine import relative_speed_cubed


def gaussian(v, temperature=1.0):
    return np.exp(-v**2 / (2 * temperature)) / math.sqrt(2 * math.pi * temperature)


def test_half_grid_quadrature():
    g = half_grid(3.0, 7)
    assert g.v_full.size == 13 and g.h == pytest.approx(0.5)
    # half weights integrate even polynomials over the line exactly (Simpson: degree 3)
    assert np.dot(g.half_weights, g.v**2) == pytest.approx(2 * 27 / 3, rel=1e-14)
    np.testing.assert_array_equal(g.full(np.arange(7.0))[:7], np.arange(7.0)[::-1])
    with pytest.raises(ValueError, match="at least 3"):
        half_grid(1.0, 2)


def test_pair_moment_gaussian():
    """<|v - v'|^3> of a Gaussian at temperature T is (8/sqrt(pi)) T^(3/2)."""
    g = half_grid(14.0, 1401)
    p = gaussian(g.v_full, 2.0)
    assert pair_moment(g.v_full, p, g.weights, 3) == pytest.approx(
        relative_speed_cubed(2.0), rel=1e-10)


def test_loss_frequency_fourth_order():
    """nu(v) = n int |v - v'| Phi(v') dv' = n [v erf(v/sqrt2) + 2 Phi(v)] for a Gaussian.

    The kink-corrected Simpson rule is fourth order (errors measured: 1.1e-5, 7.0e-7 at
    h = 0.1, 0.05): the error ratio on halving h is close to 16.
    """
    errs = []
    for n in (101, 201):
        g = half_grid(10.0, n)
        exact = 2.0 * (g.v * erf(g.v / math.sqrt(2)) + 2 * gaussian(g.v))
        errs.append(np.abs(loss_frequency(g, gaussian(g.v), density=2.0) - exact).max())
    assert errs[1] < 2e-6
    assert 12 < errs[0] / errs[1] < 20


@pytest.mark.parametrize("log_interp", [True, False])
def test_collision_term_conservation_and_energy(log_interp):
    """Mass is conserved and the energy moment equals -(n/4)(1-alpha^2)<|v-v'|^3>.

    Measured on a Gaussian at h = 0.05: mass defect 4e-8 (log) / 3e-8, energy relative
    error 3e-8 (log) / 2e-7 (interpolation of P).
    """
    g = half_grid(10.0, 201)
    alpha, density = 0.5, 1.5
    q = collision_term(g, gaussian(g.v), alpha=alpha, density=density, log_interp=log_interp)
    qf = g.full(q)
    assert abs(np.dot(g.weights, qf)) < 1e-7
    exact = -density / 4 * (1 - alpha**2) * relative_speed_cubed(1.0)
    assert np.dot(g.weights, qf * g.v_full**2) / exact - 1 == pytest.approx(0, abs=5e-7)


@given(st.floats(0.2, 3.0), st.sampled_from([True, False]))
def test_elastic_collisions_only_exchange(temperature, log_interp):
    """alpha = 1: the gain term equals the loss term exactly (claim C17, P frozen)."""
    g = half_grid(8.0 * math.sqrt(temperature), 81)
    p = gaussian(g.v, temperature) * (1 + 0.3 * np.cos(g.v))
    q = collision_term(g, p, alpha=1.0, density=1.0, log_interp=log_interp)
    assert np.abs(q).max() < 1e-13 * np.abs(loss_frequency(g, p, density=1.0) * p).max()


@given(st.floats(0.0, 0.99))
def test_gain_term_positive(alpha):
    g = half_grid(12.0, 121)
    p = gaussian(g.v)
    assert np.all(gain_term(g, p, alpha=alpha, density=1.0) >= 0)


def test_energy_balance_gaussian():
    g = half_grid(14.0, 701)
    eb = energy_balance(g.v_full, gaussian(g.v_full), g.weights, alpha=0.0, density=1.0,
                        diffusion=1.0)
    # Simpson across the kink of |v - v'|^3 (third derivative): measured 4.4e-10 at h = 0.04
    assert eb.loss == pytest.approx(0.25 * relative_speed_cubed(1.0), rel=1e-9)
    assert eb.relative_residual == pytest.approx(abs(2 - eb.loss) / 2)
