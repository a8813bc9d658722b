"""The saturating kernel's closed forms (issue 16) and the temperature estimate's secant.

* :func:`~kinetic_fem.model.kernel_saturating.pole_moment` and
  :meth:`SaturatingKernel.gaussian_mean` against 30-digit quadrature (mpmath) over
  :math:`T \\in [10^{-6}, 10^6]`, :math:`g_0 \\in [10^{-3}, 10^3]` (measured worst
  1.1e-15; the tolerance 4e-15 is a few ulps), and against the base class' adaptive
  quadrature (measured worst 1.4e-11, which is that quadrature's own error near the pole
  at :math:`g = -g_0` when :math:`T \\gg g_0^2`);
* the WKB action in closed form against mpmath (measured 1e-15) and across the switch
  from the series;
* :func:`~kinetic_fem.model.problem.bracketed_secant` and the white-noise temperature
  estimate against brentq (measured 2.8e-14 over 105 problems).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from kinetic_fem.model import CollisionKernel, HeatedProblem, SaturatingKernel
from kinetic_fem.model.kernel_saturating import POLE_SPLIT, SERIES_TOP, pole_moment
from kinetic_fem.model.problem import bracketed_secant

mpmath = pytest.importorskip("mpmath")


def _pole_reference(n: int, c: float) -> float:
    with mpmath.workdps(30):
        cc = mpmath.mpf(c)
        points = sorted({mpmath.mpf(0), cc, mpmath.mpf(1), mpmath.mpf(3), mpmath.mpf(6)})
        points = [p for p in points if p <= 6] + [mpmath.inf]
        return float(mpmath.quad(lambda x: x**n * mpmath.exp(-x * x) / (x + cc), points))


@pytest.mark.parametrize("n", [1, 2, 3, 5])
def test_pole_moment_against_mpmath(n):
    cs = np.concatenate([np.logspace(-8, 7, 16), [POLE_SPLIT * (1 - 1e-12), POLE_SPLIT,
                                                  POLE_SPLIT * (1 + 1e-12), 0.5, 3.0]])
    for c in cs:
        assert pole_moment(n, float(c)) == pytest.approx(_pole_reference(n, float(c)),
                                                         rel=4e-15, abs=0.0)


def _mean_reference(g0: float, temp: float, power: int) -> float:
    scale = 2.0 * math.sqrt(temp)
    return 2.0 / math.sqrt(math.pi) * g0 * scale**power * _pole_reference(power + 1,
                                                                          g0 / scale)


@pytest.mark.parametrize("g0", [1e-3, 1.0, 1e3])
def test_gaussian_mean_closed_form(g0):
    k = SaturatingKernel(g0)
    for temp in np.logspace(-6, 6, 7):
        for power in (0, 2):
            ref = _mean_reference(g0, float(temp), power)
            assert k.gaussian_mean(float(temp), float(power)) == pytest.approx(ref, rel=4e-15)
            # the adaptive quadrature of the base class (its own error <= 1.4e-11 measured)
            assert CollisionKernel.gaussian_average(k, float(temp), None, float(power)) == \
                pytest.approx(ref, rel=5e-11)
    # gaussian_average without a weight is the closed form
    assert k.gaussian_average(2.0, None, 2.0) == k.gaussian_mean(2.0, 2.0)


def test_gaussian_mean_other_powers_and_weights_use_quadrature():
    k = SaturatingKernel(1.5)
    # a non-integer power: the base class' quadrature (no recursion through the override)
    assert k.gaussian_mean(0.7, 0.5) == CollisionKernel.gaussian_average(k, 0.7, None, 0.5)
    weight = lambda g: 1.0 - 0.25 * math.exp(-g)  # noqa: E731
    assert k.gaussian_average(0.7, weight, 2.0) == \
        CollisionKernel.gaussian_average(k, 0.7, weight, 2.0)


@pytest.mark.parametrize("g0", [1e-3, 1.0, 1e3])
def test_wkb_action_closed_form(g0):
    k = SaturatingKernel(g0)
    edge = g0 * SERIES_TOP**2
    v = np.concatenate([g0 * np.logspace(-8, 6, 15), [edge * (1 - 1e-12), edge * (1 + 1e-12)]])
    got = k.wkb_action(-v)  # even
    with mpmath.workdps(30):
        ref = [float(mpmath.quad(lambda t: 2 * t * mpmath.sqrt(t * t / (1 + t * t / g0)),
                                 [0, mpmath.sqrt(x)])) for x in v]
    np.testing.assert_allclose(got, ref, rtol=4e-15, atol=0.0)
    np.testing.assert_allclose(got, CollisionKernel.wkb_action(k, v), rtol=1e-10, atol=0.0)
    assert k.wkb_action(np.zeros((2, 3))).shape == (2, 3)


def test_bracketed_secant():
    root = bracketed_secant(lambda x: x**3 - 2.0, 0.0, 10.0, 1.0, 3.0)
    assert root == pytest.approx(2.0 ** (1 / 3), rel=1e-15)
    # a function with -inf/inf outside its domain: bisection until finite
    func = lambda x: math.log(x) if x > 0 else -math.inf  # noqa: E731
    assert bracketed_secant(func, -5.0, 5.0, -1.0, 1.0) == pytest.approx(1.0, rel=1e-14)
    with pytest.raises(ValueError, match="no convergence"):
        bracketed_secant(lambda x: math.copysign(1.0, x - math.pi), 0.0, 10.0, 1.0, 1.0,
                         max_iter=5)


@pytest.mark.parametrize("kernel", [0.0, 0.5, 2.0, SaturatingKernel(1.0),
                                    SaturatingKernel(1e-3), SaturatingKernel(1e3)])
def test_white_noise_temperature_estimate_against_brentq(kernel):
    for alpha in (0.0, 0.9, 0.9999):
        for density, diffusion in ((1.0, 1.0), (1e-3, 1e3), (1e3, 1e-4)):
            problem = HeatedProblem.from_parameters(alpha, kernel=kernel, density=density,
                                                    diffusion=diffusion)

            def balance(log_t: float, p: HeatedProblem = problem) -> float:
                t = math.exp(log_t)
                return p.thermostat.energy_input(t) - p.gas.loss_rate(t)

            ref = math.exp(brentq(balance, -60.0, 60.0, xtol=1e-14, rtol=1e-14))
            assert problem.temperature_estimate() == pytest.approx(ref, rel=1e-13)
