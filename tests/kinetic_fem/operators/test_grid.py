"""Tests of kinetic_fem.operators.grid: meshes, quadrature exactness, O(N) convolutions, moments."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from kinetic_fem.operators.grid import (
    abs_power_convolution,
    moments,
    simpson_kink_correction,
    simpson_weights,
    symmetric_grid,
    trapezoid_weights,
    uniform_grid,
)

coeffs = arrays(float, 4, elements=st.floats(-10, 10))


def _poly_integral(c, a, b):
    """Exact integral of sum_k c_k v^k over [a, b]."""
    return sum(ck * (b ** (k + 1) - a ** (k + 1)) / (k + 1) for k, ck in enumerate(c))


@given(coeffs, st.integers(3, 40), st.floats(-5, 0), st.floats(0.1, 5))
def test_simpson_exact_for_cubics(c, n, a, length):
    """Simpson (1/3, closed by 3/8 for even n) integrates cubics exactly."""
    v = np.linspace(a, a + length, n)
    approx = np.sum(simpson_weights(v) * np.polyval(c[::-1], v))
    exact = _poly_integral(c, a, a + length)
    assert approx == pytest.approx(exact, rel=1e-10, abs=1e-9 * (1 + np.abs(c).sum()) * 5**4)


@given(arrays(float, 2, elements=st.floats(-10, 10)),
       arrays(float, st.integers(2, 30), elements=st.floats(0.01, 2.0)))
def test_trapezoid_exact_for_linear_on_any_nodes(c, steps):
    v = np.concatenate([[0.0], np.cumsum(steps)])
    approx = np.sum(trapezoid_weights(v) * (c[0] + c[1] * v))
    assert approx == pytest.approx(_poly_integral(c, 0.0, v[-1]), rel=1e-10, abs=1e-10)


@pytest.mark.parametrize("odd", [1, 0])
def test_simpson_is_fourth_order(odd):
    """Error of Simpson on exp(v) over [0, 1] falls as h^4 (odd and even node counts)."""
    exact = np.e - 1.0
    errs, h = [], []
    for n in (10 + odd, 20 + odd, 40 + odd, 80 + odd):
        v = np.linspace(0, 1, n)
        h.append(v[1])
        errs.append(abs(np.sum(simpson_weights(v) * np.exp(v)) - exact))
    orders = np.diff(np.log(errs)) / np.diff(np.log(h))
    assert np.all((orders > 3.9) & (orders < 4.3)), orders


def test_grids():
    half = uniform_grid(2.0, 5)
    assert half[0] == 0 and half[-1] == 2.0
    full = symmetric_grid(half)
    assert np.array_equal(full, -full[::-1]) and full.size == 9
    with pytest.raises(ValueError, match="at least 2 nodes"):
        uniform_grid(1.0, 1)
    with pytest.raises(ValueError, match="cutoff must be > 0"):
        uniform_grid(0.0, 5)
    with pytest.raises(ValueError, match="start at v = 0"):
        symmetric_grid(np.array([1.0, 2.0]))
    with pytest.raises(ValueError, match="strictly increasing"):
        trapezoid_weights(np.array([0.0, 1.0, 1.0]))
    with pytest.raises(ValueError, match="equally spaced"):
        simpson_weights(np.array([0.0, 1.0, 3.0]))


@given(arrays(float, st.integers(1, 40), elements=st.floats(-5, 5), unique=True),
       st.sampled_from([1, 3, 5]), st.integers(0, 2**32 - 1))
def test_abs_power_convolution_equals_double_sum(x, power, seed):
    """The O(N) cumulative-moment sum equals the O(N^2) double loop to round-off."""
    x = np.sort(x)
    wf = np.random.default_rng(seed).uniform(0.0, 1.0, x.size)
    at = np.sort(np.random.default_rng(seed + 1).uniform(-6, 6, 7))
    for points in (x, at):
        direct = np.sum(np.abs(points[:, None] - x[None, :]) ** power * wf[None, :], axis=1)
        fast = abs_power_convolution(x, wf, power, at=points if points is at else None)
        scale = np.sum(wf) * (np.abs(points).max() + np.abs(x).max()) ** power
        np.testing.assert_allclose(fast, direct, rtol=0, atol=1e-12 * scale)


@pytest.mark.parametrize("power", [0, 2, -1])
def test_abs_power_convolution_rejects_even_power(power):
    with pytest.raises(ValueError, match="positive odd integer"):
        abs_power_convolution(np.arange(3.0), np.ones(3), power)


def test_moments_of_uniform():
    """<v^k> of the uniform density 1/2 on [-1, 1] is 1/(k+1) for even k, 0 for odd k.

    Exact to round-off up to k = 3 (Simpson is exact for cubics); k = 4 has the
    Simpson error h^4/180 * 24 * 1/2 * 2 / ... = 2.13e-8 at h = 0.02.
    """
    v = np.linspace(-1, 1, 101)
    m = moments(v, np.full(v.size, 0.5), simpson_weights(v), 4)
    np.testing.assert_allclose(m[:4], [1, 0, 1 / 3, 0], atol=1e-14)
    assert m[4] - 0.2 == pytest.approx(0.02**4 / 180 * 24 * 0.5 * 2, rel=1e-6)


def test_kink_correction_makes_kernel_fourth_order():
    """sum_j w_j |v_i - v_j| F_j + c_i F_i converges at fourth order for a Gaussian F.

    Exact: int |a - v| e^{-v^2} dv = a sqrt(pi) erf(a) + e^{-a^2}; at a = 0.5.
    """
    from math import erf, exp, pi, sqrt

    a = 0.5
    exact = a * sqrt(pi) * erf(a) + exp(-a * a)
    errs = []
    for n in (41, 81, 161):  # a = 0.5 is a node of all three meshes on [-10, 10]
        v = np.linspace(-10, 10, n)
        i = int(np.argmin(np.abs(v - a)))
        f = np.exp(-v**2)
        approx = (abs_power_convolution(v, simpson_weights(v) * f, 1)[i]
                  + simpson_kink_correction(v)[i] * f[i])
        errs.append(abs(approx - exact))
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(orders > 3.5), orders
    with pytest.raises(ValueError, match="odd number"):
        simpson_kink_correction(np.linspace(0, 1, 4))
