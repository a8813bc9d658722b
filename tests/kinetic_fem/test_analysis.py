"""Tests of kinetic_fem.analysis on distributions whose answers are known in closed form."""

import math

import numpy as np
import pytest

from kinetic_fem.analysis import (
    exponent_peak,
    local_exponents,
    power_law_exponent,
    relaxation_fit,
    richardson,
    tail_fit,
)
from kinetic_fem.analysis.exponent import ExponentPeak
from kinetic_fem.distribution import VelocityDistribution


def _dist(v, p, **kwargs):
    return VelocityDistribution.from_values(v, p, params={"alpha": 0.9}, **kwargs)


def test_power_law_exponent_is_exact_on_a_power_law():
    x = np.geomspace(1e-3, 1.0, 7)
    assert power_law_exponent(x, 3.0 * x**-0.5) == pytest.approx(-0.5, abs=1e-12)


def test_tail_fit_recovers_amplitude_and_prefactor():
    """ln f = -A c^(3/2) + beta ln c + const is fitted exactly (three basis functions)."""
    v = np.linspace(-60.0, 60.0, 24001)
    a, beta = 1.3, 0.7
    p = np.exp(-a * np.abs(v) ** 1.5) * (1.0 + np.abs(v)) ** 0  # placeholder shape
    p = np.where(np.abs(v) > 1.0, np.abs(v) ** beta * np.exp(-a * np.abs(v) ** 1.5), p)
    dist = _dist(v, p)
    t = math.sqrt(dist.temperature)
    fit = tail_fit(dist, f_range=(1e-60, 1e-20))
    # in c = v / sqrt(T): ln f = -A T^(3/4) c^(3/2) + beta ln c + const
    assert fit.amplitude == pytest.approx(a * t**1.5, rel=1e-8)
    assert fit.beta == pytest.approx(beta, rel=1e-6)


def test_exponent_peak_of_a_crossover():
    """-ln(f/f0) = g(v) = v^2 + v^3/(1 + v): n = v g'/g rises from 2, peaks and returns to 2
    (g ~ 2 v^2 at large v); n does not depend on the velocity unit, so the peak height
    and position in v are those of v g'(v)/g(v)."""
    v = np.linspace(-20.0, 20.0, 16001)
    a = np.abs(v)
    p = np.exp(-(a**2 + a**3 / (1.0 + a)))
    peak = exponent_peak(_dist(v, p), c_min=0.3, c_max=6.0, floor=1e-300)
    x = np.linspace(0.3, 12.0, 2_000_001)
    n = x * (2 * x + (3 * x**2 + 2 * x**3) / (1 + x) ** 2) / (x**2 + x**3 / (1 + x))
    assert peak.interior
    assert peak.n == pytest.approx(n.max(), abs=1e-6)
    assert peak.v == pytest.approx(x[np.argmax(n)], rel=2e-3)


def test_local_exponents():
    peaks = [ExponentPeak(e, 1.0, 2.0 * e**-0.5, 0.0, 3.0 - e**0.25) for e in (1e-1, 1e-2, 1e-3)]
    for row in local_exponents(peaks):
        assert row[2] == pytest.approx(-0.5, abs=1e-12)
        assert row[3] == pytest.approx(0.25, abs=1e-12)


def test_relaxation_fit_recovers_the_rate():
    t = np.linspace(0.0, 40.0, 401)
    temp = 2.0 - np.exp(-t / 3.0)
    v = np.linspace(-10, 10, 201)
    dist = _dist(v, np.exp(-v**2 / 4.0), series={"t": t, "temperature": temp})
    # the fit uses |T - T_final|, T_final being the distribution's own temperature (2.0)
    assert dist.temperature == pytest.approx(2.0, rel=1e-6)
    assert relaxation_fit(dist) == pytest.approx(3.0, rel=1e-3)


def test_richardson_removes_the_h2_term():
    v_c = np.linspace(-8, 8, 161)
    v_f = np.linspace(-8, 8, 321)
    h_c, h_f = v_c[1] - v_c[0], v_f[1] - v_f[0]
    exact = -0.5 * v_c**2
    coarse = _dist(v_c, np.exp(exact + 0.3 * h_c**2 * np.cos(v_c)), normalize=False)
    fine = _dist(v_f, np.exp(-0.5 * v_f**2 + 0.3 * h_f**2 * np.cos(v_f)), normalize=False)
    out = richardson(coarse, fine)
    np.testing.assert_allclose(np.log(out.values / out.values[80]), exact - exact[80],
                               atol=1e-12)
    with pytest.raises(ValueError, match="nested grids"):
        richardson(coarse, _dist(v_f[:-2], np.exp(-0.5 * v_f[:-2] ** 2)))
