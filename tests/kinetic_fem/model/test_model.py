"""Tests of kinetic_fem.model: kernels, restitution laws, thermostats, problems.

Every bad parameter raises ValueError or TypeError with a message naming what is
allowed; the Gaussian-closure scales reproduce the hard-rod formulas of the paper.
"""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from kinetic_fem import sonine
from kinetic_fem.model import (
    ConstantRestitution,
    CoolingProblem,
    FokkerPlanckBath,
    HeatedProblem,
    InelasticGas,
    NoThermostat,
    PowerLawKernel,
    ThresholdRestitution,
    UnsupportedModelError,
    ViscoelasticRestitution,
    WhiteNoise,
    as_kernel,
    as_restitution,
    as_thermostat,
    restitution_value,
)


@pytest.mark.parametrize("gamma", [-0.1, 2.0001, math.inf])
def test_kernel_exponent_outside_range(gamma):
    with pytest.raises(ValueError, match=r"gamma=.* outside \[0, 2\]"):
        PowerLawKernel(gamma)


def test_kernel_type_errors():
    with pytest.raises(TypeError, match="kernel"):
        as_kernel("hard")
    with pytest.raises(ValueError, match="NaN"):
        as_kernel(float("nan"))


@given(st.floats(0.0, 2.0), st.floats(0.1, 10.0))
def test_gaussian_mean_matches_quadrature(gamma, temperature):
    """<|g|^s> for g ~ N(0, 2T), against generalised Gauss-Laguerre quadrature.

    With g = 2 sqrt(T) sqrt(t): <|g|^s> = (2 sqrt T)^s Int t^((s-1)/2) e^-t dt / sqrt(pi),
    exact for the rule with weight t^((s-1)/2) e^-t."""
    from scipy.special import roots_genlaguerre

    kernel = PowerLawKernel(gamma)
    s = gamma + 2.0
    _, w = roots_genlaguerre(8, 0.5 * (s - 1.0))
    numeric = (2.0 * math.sqrt(temperature)) ** s * np.sum(w) / math.sqrt(math.pi)
    assert kernel.gaussian_mean(temperature, 2.0) == pytest.approx(numeric, rel=1e-10)


def test_laws_agree_with_the_numba_evaluator():
    g = np.array([0.0, 1e-3, 0.1, 0.5, 1.0, 3.0, 50.0])
    for law in [ConstantRestitution(0.7), ThresholdRestitution(0.4, 0.5),
                ViscoelasticRestitution(0.05)]:
        p0, p1 = law.parameters
        direct = np.array([restitution_value(law.code, p0, p1, x) for x in g])
        np.testing.assert_allclose(law(g), direct, rtol=0, atol=0)
        np.testing.assert_array_equal(law(-g), law(g))


def test_viscoelastic_law_range():
    law = ViscoelasticRestitution(0.1)
    g = np.linspace(0.0, law.max_speed, 2001)
    values = law(g)
    assert values[0] == 1.0 and np.all(np.diff(values) <= 1e-15)  # monotone to its minimum
    assert values[-1] == pytest.approx(law.min_alpha, abs=1e-12)
    assert np.all((values >= 0.0) & (values <= 1.0))
    law.check_speed(0.5 * law.max_speed)
    with pytest.raises(ValueError, match="use a smaller delta"):
        law.check_speed(2.0 * law.max_speed)


def test_bad_laws():
    with pytest.raises(ValueError, match="alpha"):
        ThresholdRestitution(1.5, 0.1)
    with pytest.raises(ValueError, match="threshold"):
        ThresholdRestitution(0.5, -1.0)
    with pytest.raises(ValueError, match="delta"):
        ViscoelasticRestitution(0.0)
    with pytest.raises(TypeError, match="alpha must be a real number"):
        as_restitution("0.5")


def test_thermostats():
    assert as_thermostat(2.0) == WhiteNoise(2.0)
    bath = as_thermostat(1.0, friction=0.5)
    assert isinstance(bath, FokkerPlanckBath) and bath.bath_temperature == 2.0
    assert bath.energy_input(2.0) == 0.0
    with pytest.raises(ValueError, match=r"friction=-1.0 .* >= 0"):
        as_thermostat(1.0, friction=-1.0)
    assert not NoThermostat().drives


def test_elastic_gas_needs_friction():
    with pytest.raises(ValueError, match="no steady state"):
        HeatedProblem.from_parameters(1.0)
    problem = HeatedProblem.from_parameters(1.0, friction=0.5, diffusion=1.0)
    assert problem.temperature_estimate() == pytest.approx(2.0, rel=1e-12)
    with pytest.raises(ValueError, match="do not cool"):
        CoolingProblem.from_parameters(1.0)
    with pytest.raises(ValueError, match="needs a thermostat"):
        HeatedProblem(InelasticGas(0.5), NoThermostat())


@given(st.floats(0.0, 0.999))
def test_temperature_estimate_is_the_hard_rod_formula(alpha):
    """Gaussian closure with a2 = 0: T^(3/2) = sqrt(pi) D / (n (1 - alpha^2))."""
    t = HeatedProblem.from_parameters(alpha).temperature_estimate()
    assert t == pytest.approx(sonine.steady_temperature(alpha, a2=0.0), rel=1e-10)


@given(st.floats(0.0, 0.99), st.floats(0.1, 10.0), st.floats(0.1, 10.0))
def test_maxwell_temperature_is_exact(alpha, diffusion, friction):
    """Maxwell kernel: (n/4)(1-alpha^2) <g^2> with <g^2> = 2T closes exactly:
    2D - 2 xi T = (n/2)(1-alpha^2) T."""
    problem = HeatedProblem.from_parameters(alpha, diffusion=diffusion, friction=friction,
                                            kernel=0.0)
    exact = 2.0 * diffusion / (2.0 * friction + 0.5 * (1.0 - alpha**2))
    assert problem.temperature_estimate() == pytest.approx(exact, rel=1e-10)


def test_loss_rate_of_a_law_brackets_the_constants():
    """A threshold law dissipates less than the constant alpha above its threshold."""
    gas_c = InelasticGas(0.5)
    gas_t = InelasticGas(ThresholdRestitution(0.5, 1.0))
    assert 0.0 < gas_t.loss_rate(1.0) < gas_c.loss_rate(1.0)
    tiny = InelasticGas(ThresholdRestitution(0.5, 1e-12))
    assert tiny.loss_rate(1.0) == pytest.approx(gas_c.loss_rate(1.0), rel=1e-6)


def test_velocity_scale_general_kernel():
    problem = HeatedProblem.from_parameters(0.5, diffusion=16.0, kernel=2.0)
    assert problem.velocity_scale == pytest.approx(2.0)
    assert problem.time_scale == pytest.approx(0.25)


def test_alpha_of_a_law_is_refused_with_a_message():
    gas = InelasticGas(ThresholdRestitution(0.5, 0.1))
    with pytest.raises(UnsupportedModelError, match="constant restitution"):
        _ = gas.alpha
    assert gas.as_dict()["alpha"] == 0.5 and "ThresholdRestitution" in gas.as_dict()["restitution"]


def test_require_names_the_method_and_what_it_supports():
    problem = HeatedProblem.from_parameters(0.5, kernel=0.5, friction=1.0)
    with pytest.raises(UnsupportedModelError, match=r"'fd' supports the kernels gamma in \[1.0\]"):
        problem.require("fd", gammas=(1.0,))
    with pytest.raises(UnsupportedModelError, match="thermostats WhiteNoise only"):
        problem.require("fd", thermostats=(WhiteNoise,))
    problem.require("fem")


def test_cooling_zeta_estimate():
    for gamma in (0.0, 1.0, 2.0):
        z = CoolingProblem.from_parameters(0.6, kernel=gamma).zeta_estimate()
        # zeta = (1 - alpha^2) <|g|^(gamma+2)>_G / 8 at T = 1
        expected = (1 - 0.36) * PowerLawKernel(gamma).gaussian_mean(1.0, 2.0) / 8.0
        assert z == pytest.approx(expected, rel=1e-12)
