"""Tests of the model's scales, :mod:`kinetic_fem.model.scales`."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from kinetic_fem.model import HeatedProblem
from kinetic_fem.model.scales import (
    TAIL_TARGET,
    ModelScales,
    cooling_cutoff,
    cooling_rate_estimate,
    heated_cutoff,
)
from kinetic_fem.solvers import fd_cooling, fd_scales
from kinetic_fem.sonine import steady_temperature


@pytest.mark.parametrize("gamma", [0.0, 0.5, 1.0, 2.0])
@pytest.mark.parametrize("temperature", [0.3, 1.0, 20.0])
def test_mean_free_time_is_the_gaussian_average_rate(gamma, temperature):
    """``1/<|g|^gamma>`` with ``g ~ N(0, 2T)``, against numerical quadrature."""
    s = ModelScales(0.5, gamma, 0.0, temperature)
    var = 2.0 * temperature
    rate, _ = quad(lambda g: abs(g) ** gamma * math.exp(-g * g / (2 * var))
                   / math.sqrt(2 * math.pi * var), -np.inf, np.inf)
    assert s.mean_free_time == pytest.approx(1.0 / rate, rel=1e-10)
    assert s.thermal_speed == pytest.approx(math.sqrt(temperature), rel=1e-15)


def test_maxwell_mean_free_time_is_one_over_density():
    assert ModelScales(0.3, 0.0, 0.0, 7.0).mean_free_time == pytest.approx(1.0, rel=1e-15)


@pytest.mark.parametrize("gamma", [0.0, 0.5, 1.0, 2.0])
def test_cutoff_is_where_the_tail_model_reaches_the_target(gamma):
    """White noise, alpha = 0: the tail ``exp(-v^(1+g/2)/(1+g/2))`` (WKB of ``P'' = v^g P``)
    or the Gaussian core, whichever is further out, equals the target at the cut-off."""
    temperature = 2.0
    s = ModelScales(0.0, gamma, 0.0, temperature)
    c = s.cutoff(1e-40)
    v = c * math.sqrt(temperature)
    power = 1.0 + 0.5 * gamma
    tail = math.exp(-v**power / power)
    gauss = math.exp(-0.5 * c**2)
    assert max(tail, gauss) == pytest.approx(1e-40, rel=1e-9)


def test_cutoff_grows_with_decades_and_bath_bounds_it():
    s = ModelScales(0.5, 0.0, 0.0, 16 / 3)
    assert s.cutoff(1e-30) < s.cutoff(1e-60) < s.cutoff(1e-120)
    bathed = ModelScales(0.5, 0.0, 5.0, 16 / 3)
    assert bathed.cutoff() < s.cutoff()
    # never inside the Gaussian of the target
    assert bathed.cutoff() >= math.sqrt(2.0 * -math.log(TAIL_TARGET)) - 1e-12


def test_elastic_in_a_bath_is_valid():
    assert ModelScales(1.0, 1.0, 1.0, 1.0).cutoff() == pytest.approx(
        math.sqrt(2.0 * -math.log(TAIL_TARGET)))


def test_hard_rod_cutoff_near_elastic_stays_finite():
    """The quasi-elastic core keeps the cut-off at about 12 thermal speeds as alpha -> 1."""
    values = [heated_cutoff(a) for a in (0.99, 0.999, 0.99999)]
    assert all(11.0 < v < 13.0 for v in values)


def test_solvers_use_the_model_rule():
    """fd_scales and fd_cooling defer to the one rule (bit-identical values)."""
    for a in np.linspace(0.0, 0.9999, 13):
        assert fd_scales.default_cutoff(a) == heated_cutoff(a)
        assert fd_cooling.default_cutoff(a) == cooling_cutoff(a)
        assert fd_cooling.sonine_zeta_estimate(a) == cooling_rate_estimate(a)
    p = HeatedProblem.from_parameters(0.7, density=0.5, diffusion=3.0, friction=0.4, kernel=0.0)
    unit = fd_scales.UnitModel.from_problem(p)
    assert unit.cutoff() == ModelScales.from_problem(p).cutoff()


def test_from_problem_hard_rods_white_noise_uses_the_sonine_temperature():
    s = ModelScales.from_problem(HeatedProblem.from_parameters(0.6, density=2.0, diffusion=5.0))
    assert s.temperature == steady_temperature(0.6)
    assert (s.gamma, s.friction) == (1.0, 0.0)


def test_cooling_cutoff_values():
    """Tail ``1.5 + 80 zeta`` far from elastic, hump edge ``1 + 12 eps^(1/3)`` near it."""
    assert cooling_cutoff(0.3) == pytest.approx(1.5 + 80 * 0.91 / math.sqrt(math.pi))
    assert cooling_cutoff(0.999) == pytest.approx(1.0 + 12.0 * 0.1)


@pytest.mark.parametrize("kw, match", [
    ({"alpha": 1.5}, "alpha"), ({"kernel": 2.5}, "gamma"), ({"kernel": -0.1}, "gamma"),
    ({"friction": -1.0}, "friction"), ({"temperature": 0.0}, "temperature"),
])
def test_bad_scales_raise(kw, match):
    args = {"alpha": 0.5, "kernel": 1.0, "friction": 0.0, "temperature": 1.0} | kw
    with pytest.raises(ValueError, match=match):
        ModelScales(**args)


@pytest.mark.parametrize("target", [0.0, 1.0, -1e-3])
def test_bad_target_raises(target):
    with pytest.raises(ValueError, match="target"):
        ModelScales(0.5, 1.0, 0.0, 1.0).cutoff(target)


def test_fem_rule_is_the_model_rule_at_its_target():
    """The FEM default (1e-33, no crossover margin, one thermal speed added) is the
    model's rule: ``heated_cutoff(alpha, 1e-33, core_margin=1) + 1`` to round-off."""
    from kinetic_fem.solvers.fem.defaults import default_cutoff as fem_cutoff

    for a in np.linspace(0.0, 0.99999, 60):
        model = heated_cutoff(a, 1e-33, core_margin=1.0) + 1.0
        assert model == pytest.approx(fem_cutoff(a), rel=1e-14, abs=0)


def test_core_margin_widens_only_near_elastic():
    assert heated_cutoff(0.5, core_margin=1.0) == heated_cutoff(0.5)
    assert heated_cutoff(0.999, core_margin=1.0) < heated_cutoff(0.999)
    with pytest.raises(ValueError, match="core_margin"):
        heated_cutoff(0.9, core_margin=0.5)
