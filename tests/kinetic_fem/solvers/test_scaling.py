"""Tests of kinetic_fem.solvers.scaling: the quasi-elastic phi (heated) and psi (cooling) equations.

Theory used below (derivation in docs/user_guide/quasi_elastic.rst):

* phi = C exp(-U), U = (1/6) int |x-y|^3 phi.  Beyond the support U is the cubic
  polynomial |x|^3/6 + <x^2>|x|/2, so ln phi = ln C - |x|^3/6 - <x^2>|x|/2 + o(1);
  U'' = int |x-y| phi, so near 0 ln phi = ln phi(0) - lambda x^2/2 - phi(0) x^4/12;
  U'''' = 2 phi, so (ln phi)'''' = -2 phi; and int int |x-y|^3 phi phi = 4 (energy balance).
* ln psi = ln C - <y^2> y - (1/6) int psi(y') (|y-y'|^3 - (y+y')^3): left tail
  C exp(y^3/3), right tail C exp(<y^3>/3) exp(-<y^2> y), (ln psi)'''' = -2 psi.

Tolerances come from benchmarks/convergence_scaling.py (errors at the default grids:
phi constants ~1e-10, psi constants ~1e-11; finite-difference checks ~1e-6).
"""

from __future__ import annotations

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.operators.grid import abs_power_convolution, partial_moments, simpson_weights
from kinetic_fem.solvers.scaling import LAMBDA_PAPER, solve_phi, solve_psi
from kinetic_fem.solvers.scaling_psi import psi_flux_kernel, psi_kernel

LAMBDA_REF = 0.7854747688856  # n_v = 5601, cutoff 7 (benchmarks/convergence_scaling.py)
Y2_REF = 1.20970708700731  # n_v = 8401 on (-6, 36)


@pytest.fixture(scope="module")
def phi():
    return solve_phi()


@pytest.fixture(scope="module")
def psi():
    return solve_psi()


# ---------------------------------------------------------------- O(N) kernels
def test_kernels_equal_brute_force_double_sums():
    rng = np.random.default_rng(4)
    y = np.sort(rng.uniform(-3.0, 5.0, 41))
    wf = rng.uniform(0.0, 1.0, 41)
    d = y[:, None] - y[None, :]
    s = y[:, None] + y[None, :]
    np.testing.assert_allclose(abs_power_convolution(y, wf, 3), np.abs(d) ** 3 @ wf,
                               rtol=1e-12, atol=1e-10)
    np.testing.assert_allclose(psi_kernel(y, wf), (np.abs(d) ** 3 - s**3) @ wf / 6,
                               rtol=1e-12, atol=1e-10)
    np.testing.assert_allclose(psi_flux_kernel(y, wf), (np.abs(d) * d - s**2) @ wf,
                               rtol=1e-12, atol=1e-10)


def test_partial_moments_split_the_total_and_keep_tails_accurate():
    x = np.linspace(0.0, 40.0, 401)
    wf = simpson_weights(x) * np.exp(-x)
    lo, up = partial_moments(x, wf, 3)
    np.testing.assert_allclose(lo + up, lo[:, -1:] * np.ones_like(lo), rtol=1e-14)
    # the backward sum keeps the tail mass relative to itself (a difference would not)
    np.testing.assert_allclose(up[0, 300], np.sum(wf[301:]), rtol=1e-13)


# ---------------------------------------------------------------- phi (C5)
def test_phi_converges_to_tolerance_and_is_normalised(phi):
    assert phi.info.converged and phi.info.residual < 1e-12
    w = simpson_weights(phi.x)
    assert abs(np.sum(w * phi.values) - 1.0) < 1e-14
    assert np.all(phi.values > 0)


def test_phi_lambda_matches_paper_and_reference(phi):
    assert round(phi.lam, 3) == LAMBDA_PAPER
    assert abs(phi.lam - LAMBDA_REF) < 5e-10
    assert phi.x_cr == pytest.approx(3 * phi.lam, rel=1e-15)
    assert round(phi.x_cr, 2) == 2.36


def test_phi_error_estimates_bound_the_true_error(phi):
    coarse = solve_phi(n_v=701)
    for name in phi.names:
        true = abs(coarse.constants()[name] - phi.constants()[name])
        assert 0.5 * coarse.errors[name] <= true * (1 + 1e-3) + 1e-13 <= 1.5 * coarse.errors[name]
    assert all(e < 1e-9 for e in phi.errors.values())


def test_phi_tail_core_ode_and_energy(phi):
    a = phi.asymptotics()
    # exact tail: the paper's C exp(-|x|^3/6) misses exp(-<x^2>|x|/2)
    assert a.tail_deviation < 1e-8
    assert a.tail_linear_term == pytest.approx(-phi.x2 * a.tail_window[1] / 2, abs=1e-8)
    assert 2.8 < a.tail_exponent < 3.0
    # Gaussian core C~ exp(-lambda x^2/2), C~ = C exp(-<|x|^3>/6) = phi(0)
    phi0 = phi.values[phi.x.size // 2]
    assert a.c_tilde_rel < 1e-12
    assert a.core_lambda == pytest.approx(phi.lam, abs=1e-6)
    assert a.core_quartic == pytest.approx(-phi0 / 12, rel=1e-3)
    # crossover: effective exponent reaches 5/2 close to 3 lambda
    assert abs(a.x_cr_observed - phi.x_cr) < 0.05
    assert a.ode_residual < 1e-5
    assert a.energy_identity == pytest.approx(4.0, abs=1e-8)


def test_phi_distribution_is_a_velocity_distribution(phi):
    d = phi.distribution
    assert d.method == "phi"
    assert d.temperature == pytest.approx(phi.x2, rel=1e-13)
    assert d.a2 == pytest.approx(phi.a2, rel=1e-10)
    assert phi(np.array([0.0]))[0] == pytest.approx(phi.values[phi.x.size // 2], rel=1e-12)
    n = d.effective_exponent(np.array([0.3, 3.0]))
    assert 1.99 < n[0] < 2.05 and 2.5 < n[1] < 3.0


def test_phi_and_psi_carry_error_estimates_under_the_common_names(phi, psi):
    for res in (phi, psi):
        e = res.distribution.error
        assert e.kind == "estimate" and e.zeta is None
        assert 0.0 < e.temperature < 1e-9 and 0.0 < e.a2 < 1e-9  # measured 5e-12..2e-11
        assert e.c.size > 2 and 0.0 < e.f_max < 1e-7  # measured 5e-10, 7e-10


# ---------------------------------------------------------------- psi (C12)
def test_psi_converges_with_zero_mean(psi):
    assert psi.info.converged and psi.info.residual < 1e-12
    w = simpson_weights(psi.y)
    assert abs(np.sum(w * psi.values) - 1.0) < 1e-14
    assert abs(psi.distribution.mean) < 1e-12
    assert abs(psi.c - psi.y2) < 1e-12
    assert abs(psi.y2 - Y2_REF) < 1e-10
    assert all(e < 1e-8 for e in psi.errors.values())


def test_psi_tails(psi):
    a = psi.asymptotics()
    ln_c = np.log(psi.C)
    assert a.left_cubic == pytest.approx(1 / 3, abs=1e-8)
    assert a.left_log_prefactor == pytest.approx(ln_c, abs=1e-7)
    assert a.right_slope == pytest.approx(-psi.y2, abs=1e-6)
    assert a.right_log_prefactor == pytest.approx(ln_c + psi.y3 / 3, abs=1e-5)
    # the paper's printed right tail C exp(-<y^3>/3) exp(-2<y^2> y) is a misprint
    assert abs(a.right_slope + 2 * psi.y2) > 1.0
    assert abs(a.right_log_prefactor - (ln_c - psi.y3 / 3)) > 0.5


def test_psi_ode_and_differential_form(psi):
    a = psi.asymptotics()
    assert a.ode_residual < 1e-5  # (ln psi)'''' = -2 psi
    assert a.ode_residual_paper > 1.0  # the printed (ln psi)'''' = psi does not hold
    assert a.differential_residual < 1e-6  # the paper's eq. (psi) holds on the solution


def test_psi_peak_and_humps(psi):
    i = int(np.argmax(psi.values))
    assert abs(psi.y_peak - psi.y[i]) <= psi.y[1] - psi.y[0]
    assert psi.psi_peak >= psi.values[i]
    x = np.linspace(-1.5, 1.5, 30001)
    humps = psi.humps(x, 1e-3)
    assert np.sum(humps) * (x[1] - x[0]) == pytest.approx(1.0, abs=1e-6)
    assert humps[np.argmin(np.abs(x))] < 1e-4 * humps.max()  # two humps, nearly empty centre


# ---------------------------------------------------------------- input checking
@pytest.mark.parametrize("kwargs, error", [
    ({"n_v": 1400}, ValueError), ({"n_v": 1403}, ValueError), ({"cutoff": -1.0}, ValueError),
    ({"tol": 0.0}, ValueError), ({"max_iter": 0}, ValueError), ({"n_v": 10.5}, TypeError),
    ({"estimate_errors": 1}, TypeError), ({"nv": 1401}, TypeError),
])
def test_solve_phi_rejects_bad_options(kwargs, error):
    with pytest.raises(error):
        solve_phi(**kwargs)


@pytest.mark.parametrize("kwargs, error", [
    ({"n_v": 1000}, ValueError), ({"domain": (1.0, 30.0)}, ValueError),
    ({"domain": 5.0}, TypeError), ({"domain": (-6.0, np.inf)}, ValueError),
    ({"grid": 3}, TypeError),
])
def test_solve_psi_rejects_bad_options(kwargs, error):
    with pytest.raises(error):
        solve_psi(**kwargs)


# ---------------------------------------------------------------- slow: convergence
def _observed_orders(values):
    d = np.abs(np.diff(values))
    return np.log2(d[:-1] / d[1:])


@pytest.mark.slow
def test_phi_fourth_order_in_grid_spacing():
    lams = [solve_phi(n_v=n, estimate_errors=False).lam for n in (353, 705, 1409, 2817)]
    orders = _observed_orders(lams)
    assert np.all(np.abs(orders - 4.0) < 0.3), orders


@pytest.mark.slow
def test_psi_fourth_order_in_grid_spacing():
    y2 = [solve_psi(n_v=n, estimate_errors=False).y2 for n in (525, 1049, 2097, 4193)]
    orders = _observed_orders(y2)
    assert np.all(np.abs(orders - 4.0) < 0.3), orders


@pytest.mark.slow
def test_heated_fem_solution_approaches_phi(phi):
    """sup |P_eps - phi| in x = (n eps / D)^(1/3) v falls like eps (measured rate 1.00)."""
    fem = pytest.importorskip("kinetic_fem.solvers.fem")
    assert "fem" in kf.HEATED_SOLVERS, fem
    x = np.linspace(-4.0, 4.0, 801)
    diffs = []
    for alpha in (0.999, 0.9999):
        eps = 1.0 - alpha
        dist = kf.solve_heated(alpha, method="fem").rescaled(eps ** (1.0 / 3.0))
        diffs.append(np.max(np.abs(dist.pdf(x) - phi(x))))
    rate = np.log10(diffs[0] / diffs[1])
    assert 0.8 < rate < 1.2, diffs


# ---------------------------------------------------------------- docs examples
def _load_example(name):
    import importlib.util
    import sys
    from pathlib import Path

    path = Path(__file__).parents[3] / "docs" / "examples" / name
    spec = importlib.util.spec_from_file_location(f"example_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up here
    spec.loader.exec_module(module)
    return module


def test_phi_example_numbers():
    module = _load_example("plot_phi.py")
    result = module.main(**module.TEST_KWARGS)
    assert result.phi.distribution.method == "phi"
    assert abs(result.phi.lam - LAMBDA_REF) < 1e-7  # n_v = 353: error 2.5e-8
    assert result.phi.errors["lam"] < 1e-7


def test_psi_example_numbers():
    module = _load_example("plot_psi.py")
    sol = module.main(**module.TEST_KWARGS)
    assert sol.distribution.method == "psi"
    assert abs(sol.y2 - Y2_REF) < 1e-8  # n_v = 1051: error 2.3e-9
