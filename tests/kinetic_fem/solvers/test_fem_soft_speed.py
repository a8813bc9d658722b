"""Issue 16, third round: heated states of soft kernels (the even fold, chord steps on P,
the quasi-elastic cut-off, P3 near elastic collisions)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.model import SaturatingKernel
from kinetic_fem.operators.fem_discretisation import FEMDiscretisation
from kinetic_fem.operators.fem_pair_breaks import kernel_rate
from kinetic_fem.solvers import maxwell
from kinetic_fem.solvers.fem import heated as fem
from kinetic_fem.solvers.fem import newton as fem_newton
from kinetic_fem.solvers.fem.defaults import action_root, model_cutoff, scaled_model, tail_action
from kinetic_fem.solvers.fem.newton import EvenFold, power_of_two_scales
from kinetic_fem.solvers.fem.state import state_temperature


def _disc(order: int = 3) -> FEMDiscretisation:
    half = np.geomspace(0.05, 15.0, 25)
    verts = np.concatenate([-half[::-1], [0.0], half])
    return FEMDiscretisation(0.5, verts, order, 2 * order + 1, gamma=0.0)


def test_even_fold_equals_the_sparse_products_bit_for_bit():
    disc = _disc()
    sym = disc.symmetry
    fold = EvenFold(sym)
    rng = np.random.default_rng(3)
    jac = rng.standard_normal((sym.shape[0], sym.shape[0]))
    r = rng.standard_normal(sym.shape[0])
    x = rng.standard_normal(sym.shape[1])
    assert np.array_equal(fold.matrix(jac), sym.T @ (sym.T @ jac.T).T)
    assert np.array_equal(fold.vector(r), sym.T @ r)
    assert np.array_equal(fold.expand(x), sym @ x)
    assert np.array_equal(fold.counts, np.asarray(sym.sum(axis=0)).ravel())


def test_power_of_two_row_scales():
    jac = np.array([[3.0, -0.1], [0.0, 1e-40], [0.0, 0.0]])
    s = power_of_two_scales(jac)
    top = np.abs(jac).max(axis=1)
    assert np.all(np.log2(s) == np.round(np.log2(s)))
    assert np.all((s[:2] > top[:2]) & (s[:2] <= 2.0 * top[:2])) and s[2] > 0.0


def test_state_temperature_equals_the_distribution():
    disc = _disc(2)
    u = disc.gaussian(1.7) + 0.01 * np.cos(disc.dof_locations)
    assert state_temperature(disc, u) == pytest.approx(disc.distribution(u).temperature,
                                                       rel=1e-13)


def test_gamma_half_rate_is_the_square_root():
    g = np.geomspace(1e-12, 1e6, 50)
    assert all(kernel_rate(0.5, x) == math.sqrt(x) for x in g)
    assert kernel_rate(0.5000001, 4.0) == 4.0**0.5000001


@pytest.mark.parametrize("p_chord", [False, True])
def test_chord_on_p_reaches_the_same_state_with_one_fine_jacobian(monkeypatch, p_chord):
    """Chord steps on P (the factorised Jacobian relative to the iterate's P) and on u
    end at the same state (measured max |du| 2e-13); on P the fine Newton of the Maxwell
    model at alpha = 0.5 needs one Jacobian."""
    monkeypatch.setattr(fem_newton, "CHORD_IN_P", p_chord)
    state = fem.steady_state(kf.HeatedProblem.from_parameters(0.5, kernel=0.0))
    monkeypatch.setattr(fem_newton, "CHORD_IN_P", True)
    ref = fem.steady_state(kf.HeatedProblem.from_parameters(0.5, kernel=0.0))
    assert np.abs(state.u - ref.u).max() < 1e-11
    if p_chord:
        assert state.info.message.endswith("1 Jacobians")


def test_action_root_matches_brentq_for_the_saturating_kernel():
    from scipy.optimize import brentq

    kernel = SaturatingKernel(1.0)
    for friction in (0.0, 0.8):
        def gap(v: float, xi: float = friction) -> float:
            return tail_action(v, kernel, xi) - 76.0

        ref = brentq(gap, 0.0, 400.0, xtol=1e-12)
        assert action_root(kernel, friction, 76.0, 0.0, 400.0) == pytest.approx(ref, rel=1e-9)


def test_quasi_elastic_log_density_of_the_maxwell_model():
    """B = 1: drift -a v and d = a^2 (v^2 + T)/2, so ln P = -(1/a + 1) ln(1 + d) + const
    (near the centre the Gaussian at T = 2/(1 - alpha)); 801 points, linear between them."""
    from kinetic_fem.model.scales import quasi_elastic_log_density

    v = np.array([0.0, 5.0, 10.0, 60.0])
    a, temp = 0.005, 200.0
    lp = quasi_elastic_log_density(v, 0.0, 0.99, temp)
    exact = -(1.0 / a + 1.0) * np.log((1.0 + 0.5 * a * a * (v**2 + temp))
                                      / (1.0 + 0.5 * a * a * temp))
    np.testing.assert_allclose(lp, exact, rtol=1e-6, atol=1e-5)  # interpolation: 3e-6


@pytest.mark.parametrize("alpha", [0.97, 0.99])
def test_quasi_elastic_cutoff_covers_the_gamma_half_state(alpha):
    """gamma = 1/2 near elastic collisions: the cut-off is the quasi-elastic one (11.3
    thermal velocities at alpha = 0.99 instead of 14.3), and f at it is below 1e-33
    (measured 2e-35 at 0.99), with T and a2 as on the wider interval."""
    problem = kf.HeatedProblem.from_parameters(alpha, kernel=0.5)
    scaled = scaled_model(problem)
    c_max = model_cutoff(scaled)
    assert c_max < 14.0
    dist = kf.solve_heated(alpha, kernel=0.5)
    assert dist.f_values[-1] < 1e-33
    wide = fem.steady_state(problem, order=3, spacing=1.7 * 0.08 * (10 * (1 - alpha)) ** 0.2,
                            cutoff=14.33)
    d = wide.disc.distribution(wide.u)
    assert dist.temperature == pytest.approx(d.temperature, rel=1e-9)
    assert dist.a2 == pytest.approx(d.a2, abs=1e-8)


@pytest.mark.parametrize("alpha", [0.99, 0.999])
def test_maxwell_p3_near_elastic_is_exact(alpha):
    """P3 default at alpha = 0.99 and 0.999 (P2 before): T and a2 against the exact
    moments (measured dT/T 1e-14, da2 7e-11 at 0.99)."""
    dist = kf.solve_heated(alpha, kernel=0.0)
    exact = maxwell.steady_state(alpha)
    assert dist.info.extra["order"] == 3
    assert dist.temperature == pytest.approx(exact.temperature, rel=1e-10)
    assert dist.a2 == pytest.approx(exact.a2, abs=1e-8)
