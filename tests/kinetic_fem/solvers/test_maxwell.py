"""Tests of kinetic_fem.solvers.maxwell: exact moment results of the inelastic Maxwell model.

Theory (module docstring of kinetic_fem.solvers.maxwell, docs/user_guide/exact_solutions.rst):
v1' = a v1 + b v2, v2' = b v1 + a v2, a = (1-alpha)/2, b = (1+alpha)/2;
dM_k/dt = (n/2)[sum_j C(k,j)(a^j b^(k-j) + a^(k-j) b^j) M_j M_(k-j) - 2 M_k]
          + D k(k-1) M_(k-2) - xi k M_k.
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.linalg import expm

from kinetic_fem.solvers import maxwell
from kinetic_fem.solvers.maxwell import (
    collision_moment_rates,
    evolve_moments,
    hcs_characteristic_function,
    hcs_pdf,
    hcs_zeta,
    moment_rates,
    scaled_moment_growth_rates,
    steady_state,
)

# an asymmetric, non-Gaussian density: two Gaussians (weight, mean, std)
MIXTURE = [(0.3, -1.2, 0.5), (0.7, 0.6, 1.3)]


def _mixture_nodes(n_nodes=40):
    """Nodes and weights integrating polynomials of degree < 2 n_nodes exactly against
    the mixture density."""
    x, w = np.polynomial.hermite_e.hermegauss(n_nodes)
    w = w / w.sum()
    nodes = np.concatenate([m + s * x for _, m, s in MIXTURE])
    weights = np.concatenate([p * w for p, _, _ in MIXTURE])
    return nodes, weights


@pytest.mark.parametrize("alpha", [0.0, 0.37, 0.9, 1.0])
def test_collision_rates_against_direct_quadrature(alpha):
    """The moment recursion equals (n/2) double integral of P P [phi(v1')+phi(v2')-phi(v1)
    -phi(v2)] with phi = v^k, evaluated by product Gauss rules (exact for polynomials),
    for a density with odd moments; agreement to round-off of the moment sizes."""
    n, kmax = 1.7, 10
    v, w = _mixture_nodes()
    moments = np.array([np.sum(w * v**k) for k in range(kmax + 1)])
    v1, v2 = v[:, None], v[None, :]
    ww = w[:, None] * w[None, :]
    a, b = 0.5 * (1 - alpha), 0.5 * (1 + alpha)
    p1, p2 = a * v1 + b * v2, b * v1 + a * v2
    direct = np.array([0.5 * n * np.sum(ww * (p1**k + p2**k - v1**k - v2**k))
                       for k in range(kmax + 1)])
    rates = collision_moment_rates(moments, alpha, n)
    scale = np.array([np.sum(w * np.abs(v) ** k) for k in range(kmax + 1)])
    assert np.all(np.abs(rates - direct) < 1e-13 * n * scale)
    assert abs(rates[0]) == 0 and abs(rates[1]) < 1e-15   # mass, momentum


@pytest.mark.parametrize("alpha", [0.0, 0.3, 0.6, 0.9, 0.99])
def test_steady_white_noise_closed_forms(alpha):
    """T = 4D/(n(1-alpha^2)), a2 = 2(1-alpha^2)/(7+alpha^2); the recursion makes every
    moment rate vanish (float round-off)."""
    n, d = 1.3, 0.7
    s = steady_state(alpha, 8, density=n, diffusion=d)
    assert s.temperature == pytest.approx(4 * d / (n * (1 - alpha**2)), rel=1e-15)
    assert s.a2 == pytest.approx(2 * (1 - alpha**2) / (7 + alpha**2), rel=1e-14)
    assert s.sonine[0] == 1 and s.sonine[1] == 0
    rates = moment_rates(s.moments, alpha, n, d)
    k = np.arange(len(s.moments))
    assert np.all(np.abs(rates) < 1e-13 * n * s.moments * s.temperature ** 0 + 1e-300)
    assert np.all(s.moments[1::2] == 0)
    assert np.all(np.abs(s.scaled_moments[k % 2 == 0][:2] - 1) < 1e-15)


@pytest.mark.parametrize("alpha,xi", [(0.5, 0.4), (0.9, 3.0), (0.0, 1.0)])
def test_steady_bath_energy_balance(alpha, xi):
    """Fokker-Planck bath: 2D - 2 xi T = (n/2)(1-alpha^2) T."""
    n, d = 1.0, 2.0
    s = steady_state(alpha, 6, density=n, diffusion=d, friction=xi)
    assert s.temperature == pytest.approx(2 * d / (2 * xi + 0.5 * n * (1 - alpha**2)),
                                          rel=1e-15)
    rates = moment_rates(s.moments, alpha, n, d, xi)
    assert np.all(np.abs(rates) < 1e-13 * (1 + xi) * s.moments + 1e-300)


def test_elastic_bath_is_the_gaussian():
    """alpha = 1 with a bath: the Gaussian at T = D/xi, every a_p = 0 (to the working
    precision of the recursion, 80 digits at order 20: measured |a_p| < 3e-75)."""
    s = steady_state(1.0, 20, diffusion=3.0, friction=2.0)
    assert s.temperature == 1.5
    assert np.max(np.abs(s.sonine[2:])) < 1e-60


def test_sonine_coefficients_exact_at_high_order():
    """The multiprecision a_p at order 40 are finite; the float alternating sum of the
    float moments agrees to 1e-10 relative (measured 4e-14 at p <= 40 for alpha = 0.6:
    the a_p of the heated Maxwell gas grow like p^p, a_40 = 8.5e27, so the sum does not
    cancel much).  The exponential tail makes the Sonine series divergent."""
    from kinetic_fem.sonine import sonine_coefficients_from_moments

    s = steady_state(0.6, 40)
    assert np.all(np.isfinite(s.sonine))
    naive = sonine_coefficients_from_moments(list(s.scaled_moments), 40)
    np.testing.assert_allclose(naive[2:], s.sonine[2:], rtol=1e-10)
    assert s.sonine[40] > 1e27


def _expm_m4(alpha, n, d, xi, t, m2, m4):
    """(1, M2, M2^2, M4) obey a linear constant-coefficient system: exact propagator."""
    a, b = 0.5 * (1 - alpha), 0.5 * (1 + alpha)
    l2 = n * (a**2 + b**2 - 1) - 2 * xi
    l4 = n * (a**4 + b**4 - 1) - 4 * xi
    g4 = 0.5 * n * math.comb(4, 2) * 2 * a**2 * b**2
    mat = np.array([[0, 0, 0, 0],
                    [2 * d, l2, 0, 0],
                    [0, 4 * d, 2 * l2, 0],
                    [0, 12 * d, g4, l4]], dtype=float)
    y = expm(mat * t) @ np.array([1.0, m2, m2**2, m4])
    return y[1], y[3]


def test_transient_piecewise_constant_protocol_against_matrix_exponential():
    """D and xi jump at t = 1 and t = 2.5, alpha at t = 2.5: the integrated T and <v^4>
    match the exact matrix-exponential propagator to 1e-10 relative."""
    times = np.array([0.0, 0.5, 1.0, 1.7, 2.5, 4.0])
    def d_of(t):
        return 1.0 if t < 1.0 else (0.2 if t < 2.5 else 2.0)

    def xi_of(t):
        return 0.0 if t < 1.0 else (0.8 if t < 2.5 else 0.3)

    def alpha_of(t):
        return 0.6 if t < 2.5 else 0.9

    ev = evolve_moments(alpha_of, times, diffusion=d_of, friction=xi_of,
                        initial_temperature=0.3, breakpoints=(1.0, 2.5))
    m2, m4 = 0.3, 3 * 0.3**2
    prev = 0.0
    for i, t in enumerate(times):
        if t > prev:
            mid = 0.5 * (prev + t)
            m2, m4 = _expm_m4(alpha_of(mid), 1.0, d_of(mid), xi_of(mid), t - prev, m2, m4)
            prev = t
        assert ev.temperature[i] == pytest.approx(m2, rel=1e-10)
        assert ev.moments[i, 4] == pytest.approx(m4, rel=1e-10)


def test_transient_smooth_protocol_temperature():
    """D(t) = 1 + 0.5 sin(3t): T' = -lambda T + 2D(t) integrates in closed form."""
    alpha, n = 0.7, 2.0
    lam = 0.5 * n * (1 - alpha**2)
    times = np.linspace(0, 5, 6)
    ev = evolve_moments(alpha, times, density=n, diffusion=lambda t: 1 + 0.5 * np.sin(3 * t),
                        initial_temperature=2.0)
    for t, temp in zip(times, ev.temperature, strict=True):
        forced = quad(lambda s, t=t: 2 * (1 + 0.5 * np.sin(3 * s)) * np.exp(-lam * (t - s)),
                      0, t, epsabs=1e-14, epsrel=1e-13)[0]
        assert temp == pytest.approx(2.0 * np.exp(-lam * t) + forced, rel=1e-10)
    assert np.all(np.abs(ev.moments[:, 1::2]) == 0)


@pytest.mark.parametrize("alpha", [0.0, 0.5, 0.9])
def test_free_cooling_moments_have_no_scaling_limit(alpha):
    """D = xi = 0: T = T0 exp(-2 zeta n t), zeta = (1-alpha^2)/4 exactly;
    mu4 = <c^4> = -3 + (mu4(0) + 3) exp(2 a^2 b^2 n t) grows without bound (the HCS has an
    infinite fourth moment), and the ratio mu6/mu4 grows too."""
    n = 1.5
    times = np.linspace(0, 40, 9)
    ev = evolve_moments(alpha, times, density=n, diffusion=0.0, order=6)
    zeta = hcs_zeta(alpha)
    np.testing.assert_allclose(ev.temperature, np.exp(-2 * zeta * n * times), rtol=1e-10)
    mu4 = ev.moments[:, 4] / ev.temperature**2
    ab = zeta
    np.testing.assert_allclose(mu4, -3 + 6 * np.exp(2 * ab**2 * n * times), rtol=1e-10)
    mu6 = ev.moments[:, 6] / ev.temperature**3
    assert np.all(np.diff(mu6 / mu4) > 0)
    rates = scaled_moment_growth_rates(alpha, 8, n)
    assert abs(rates[2]) < 1e-15 and abs(rates[3]) < 1e-15 and np.all(rates[4:] > 0)


def test_hcs_closed_form():
    """f(c) = 2/(pi (1+c^2)^2): normalised, unit temperature, Fourier transform
    (1+|k|)e^{-|k|}, and the scaled Fourier equation
    Phi(a k) Phi(b k) - Phi(k) = -zeta k Phi'(k) with zeta = ab, for every alpha."""
    assert quad(hcs_pdf, -np.inf, np.inf, epsabs=1e-14)[0] == pytest.approx(1, abs=1e-13)
    assert quad(lambda c: c * c * hcs_pdf(c), -np.inf, np.inf,
                epsabs=1e-13)[0] == pytest.approx(1, abs=1e-11)
    for k in (0.3, 1.0, 4.0):
        ft = 2 * quad(hcs_pdf, 0, 200, weight="cos", wvar=k, epsabs=1e-14, limit=400)[0]
        assert ft == pytest.approx(hcs_characteristic_function(k), abs=1e-7)  # tail > 200: 1e-7
    k = np.linspace(-6, 6, 121)
    for alpha in (0.0, 0.4, 0.95):
        a, b = 0.5 * (1 - alpha), 0.5 * (1 + alpha)
        phi = hcs_characteristic_function
        dphi = -k * np.exp(-np.abs(k))
        np.testing.assert_allclose(phi(a * k) * phi(b * k) - phi(k),
                                   -hcs_zeta(alpha) * k * dphi, atol=1e-15)


def test_bad_input():
    with pytest.raises(ValueError, match="strictly increasing"):
        evolve_moments(0.5, [0.0, 2.0, 1.0])
    with pytest.raises(ValueError, match="diffusion"):
        evolve_moments(0.5, [0.0, 1.0], diffusion=-1.0)
    with pytest.raises(ValueError, match=r"protocol friction\(t\)"):
        evolve_moments(0.5, [0.0, 1.0], friction=lambda t: -1.0)
    with pytest.raises(ValueError, match=r"alpha\(t\)"):
        evolve_moments(lambda t: 1.5, [0.0, 1.0])
    with pytest.raises(ValueError, match="normalised"):
        evolve_moments(0.5, [0.0, 1.0], initial_moments=[2.0, 0.0, 1.0])
    with pytest.raises(ValueError, match="alpha"):
        steady_state(1.0)                       # white noise, elastic: no steady state
    with pytest.raises(ValueError, match="order"):
        steady_state(0.5, 0)
    assert maxwell.steady_state(1.0, 2, friction=1.0).temperature == 1.0
