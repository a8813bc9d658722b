"""Tests of the Sonine Galerkin solver (kinetic_fem/spectral.py, kinetic_fem/_sonine_tensors.py).

Theory: f = Phi sum_p b_p e_p, Galerkin rows R_q = (1/2) b A_q b - delta kappa_q b_{q-1}
- chi (2q b_q - kappa_q b_{q-1}); for the Maxwell kernel the row q holds the moments
up to 2q only, so every truncation gives the exact a_2 .. a_P (kinetic_fem.solvers.maxwell).
"""

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.model import UnsupportedModelError, ViscoelasticRestitution
from kinetic_fem.operators.collision import energy_balance
from kinetic_fem.operators.grid import simpson_weights
from kinetic_fem.operators.sonine_tensors import (
    maxwell_tensor,
    orthonormal_sonine,
    quadrature_tensor,
)
from kinetic_fem.solvers import maxwell
from kinetic_fem.solvers.spectral import MAX_ORDER, solve_sonine, solve_sonine_cooling
from kinetic_fem.sonine import a2_first_order, steady_temperature


def test_basis_is_orthonormal():
    """sum_i w_i e_p(c_i) e_q(c_i) = delta_pq with a Gauss-Hermite rule exact to degree 399
    (measured 2e-14 at P = 60)."""
    x, w = np.polynomial.hermite_e.hermegauss(200)
    w = w / w.sum()
    e = orthonormal_sonine(60, x)
    assert np.max(np.abs((e * w) @ e.T - np.eye(61))) < 1e-12


@pytest.mark.parametrize("alpha", [0.0, 0.3, 0.9])
def test_quadrature_tensor_equals_maxwell_closed_form(alpha):
    """The Gauss-rule tensor at gamma = 0 equals the Fourier closed form (measured 1.2e-14
    at P = 12; entries O(1)): an independent check of the quadrature."""
    assert np.max(np.abs(quadrature_tensor(12, alpha, 0.0) - maxwell_tensor(12, alpha))) < 1e-12


@pytest.mark.parametrize("alpha", [0.0, 0.3, 0.6, 0.9, 0.999])
def test_linearized_order_two_is_first_order_sonine(alpha):
    """Linearised P = 2 is van Noije-Ernst's first order: a2 = 16(1-2alpha^2)/(129+30alpha^2),
    T from C1 with <g^3> (1 + 3a2/16)."""
    sol = solve_sonine(alpha, 2, linearized=True)
    assert abs(sol.coefficients[2] - a2_first_order(alpha)) < 1e-13
    assert abs(sol.temperature / steady_temperature(alpha) - 1) < 1e-12


@pytest.mark.parametrize("friction", [0.0, 0.7])
@pytest.mark.parametrize("alpha", [0.3, 0.6, 0.9])
def test_maxwell_exact_at_every_order(alpha, friction):
    """gamma = 0: a_2 .. a_P and T equal the exact moment recursion to round-off at every
    order up to 80 (measured max relative error 4e-14 on a_p, which grow to 1e79 at
    p = 80 with white noise)."""
    exact = maxwell.steady_state(alpha, 80, density=1.3, diffusion=0.8, friction=friction)
    for order in (2, 3, 8, 20, 40, 80):
        sol = solve_sonine(alpha, order, density=1.3, diffusion=0.8, friction=friction,
                           kernel=0.0)
        np.testing.assert_allclose(sol.coefficients[2:], exact.sonine[2:order + 1],
                                   rtol=1e-12)
        assert sol.temperature == pytest.approx(exact.temperature, rel=1e-13)


def test_maxwell_first_order_sonine_is_exact():
    """For Maxwell molecules a_2 enters the <v^4> equation linearly: the linearised P = 2
    theory is exact, a2 = 2(1-alpha^2)/(7+alpha^2)."""
    for alpha in (0.0, 0.5, 0.95):
        sol = solve_sonine(alpha, 2, kernel=0.0, linearized=True)
        assert sol.coefficients[2] == pytest.approx(2 * (1 - alpha**2) / (7 + alpha**2),
                                                    rel=1e-13)


# FEM reference (kf.solve_heated(alpha), default mesh, T to 1e-8, a2 to 1e-6)
FEM = {0.6: (1.9647990226113081, 0.030434774695954122),
       0.9: (4.47291557031213, -0.07124577009638007)}


@pytest.mark.parametrize("alpha", [0.6, 0.9])
def test_hard_rods_converge_to_the_fem_reference(alpha):
    """Orders 24 and 32 agree to 1e-10 in a2 (measured 5e-11 at 0.6, 4e-14 at 0.9) and both
    match the FEM reference within its accuracy (measured a2 5e-9 and 2.4e-8, T 6e-10 and
    3e-9 relative)."""
    s24, s32 = solve_sonine(alpha, 24), solve_sonine(alpha, 32)
    assert abs(s32.coefficients[2] - s24.coefficients[2]) < 1e-9
    t_fem, a2_fem = FEM[alpha]
    assert abs(s32.coefficients[2] - a2_fem) < 1e-6
    assert abs(s32.temperature / t_fem - 1) < 1e-8


@pytest.mark.slow
@pytest.mark.parametrize("alpha", [0.6, 0.9])
def test_hard_rods_against_fem_run(alpha):
    d = kf.solve_heated(alpha)
    s = solve_sonine(alpha, 32)
    assert abs(s.coefficients[2] - d.a2) < 1e-6
    assert abs(s.temperature / d.temperature - 1) < 1e-8


def test_registered_and_energy_balance():
    """The output distribution satisfies C1 to the accuracy of the truncated tails."""
    d = kf.solve_heated(0.6, method="spectral", order=8)
    assert d.method == "spectral"
    assert abs(d.a2 - d.info.extra["sonine"][2]) < 1e-9
    c = d.v / np.sqrt(d.temperature)
    bal = energy_balance(d.v, d.values, np.sqrt(d.temperature) * simpson_weights(c),
                         alpha=0.6, density=1.0, diffusion=1.0)
    assert bal.relative_residual < 1e-6


@pytest.mark.parametrize("gamma", [0.5, 2.0])
def test_bath_and_kernels_through_the_registry(gamma):
    """Any kernel with a bath: the output grid reproduces the coefficients; alpha = 1 with
    a bath is the Gaussian at T = D/xi exactly."""
    d = kf.solve_heated(0.7, method="spectral", kernel=gamma, friction=1.5, order=12)
    assert abs(d.a2 - d.info.extra["sonine"][2]) < 1e-9
    g = kf.solve_heated(1.0, method="spectral", kernel=gamma, friction=2.0, diffusion=3.0)
    assert g.temperature == pytest.approx(1.5, rel=1e-13)
    assert np.max(np.abs(g.info.extra["sonine"][2:])) < 1e-13


def test_rescaling_in_density_and_diffusion():
    """T scales as (D/n)^(2/(2+gamma)) at fixed xi/(n u^gamma); the a_p do not change."""
    gamma = 0.5
    s1 = solve_sonine(0.7, 10, kernel=gamma, friction=0.4)
    n, d = 3.0, 0.5
    u = (d / n) ** (1 / (2 + gamma))
    s2 = solve_sonine(0.7, 10, kernel=gamma, density=n, diffusion=d, friction=0.4 * n * u**gamma)
    np.testing.assert_allclose(s1.coefficients, s2.coefficients, atol=1e-13)
    assert s2.temperature == pytest.approx(s1.temperature * u**2, rel=1e-12)


def test_cooling_against_fd_and_first_order():
    """alpha = 0.85: orders 16 and 32 agree to 2e-4 in a2 (measured 1.3e-4), the zeta to
    1e-4 (measured 2.7e-5); first order (linear P = 2) is 16(1-2alpha^2)/(33+30alpha^2)."""
    s16, z16 = solve_sonine_cooling(0.85, 16)
    s32, z32 = solve_sonine_cooling(0.85, 32)
    assert abs(s32.coefficients[2] - s16.coefficients[2]) < 2e-4
    assert abs(z32 / z16 - 1) < 1e-4
    lin, _ = solve_sonine_cooling(0.85, 2, linearized=True)
    assert lin.coefficients[2] == pytest.approx(16 * (1 - 2 * 0.85**2) / (33 + 30 * 0.85**2),
                                                abs=1e-12)
    d = kf.solve_cooling(0.85, method="spectral", order=16)
    assert d.info.extra["zeta"] == pytest.approx(z16, rel=1e-13)


def test_cooling_without_physical_root_is_refused():
    """alpha = 0.5: the truncated system at order 8 has no root Newton can reach (the same
    algebraic system as the moment method: the test space is the same), alpha = 0.3 at
    order 8 only a root with a2 = -1.04 < -2/3, which no distribution has."""
    with pytest.raises(RuntimeError, match="no solution"):
        solve_sonine_cooling(0.5, 8)
    with pytest.raises(RuntimeError, match="spurious root"):
        solve_sonine_cooling(0.3, 8)


def test_unsupported_models():
    with pytest.raises(UnsupportedModelError, match="infinite fourth moment"):
        kf.solve_cooling(0.5, method="spectral", kernel=0.0)
    with pytest.raises(UnsupportedModelError, match="constant restitution"):
        kf.solve_heated(ViscoelasticRestitution(0.1), method="spectral")


@pytest.mark.parametrize("order", [1, MAX_ORDER + 1, 2.5, True])
def test_bad_order(order):
    with pytest.raises(ValueError, match="order"):
        solve_sonine(0.5, order)
