"""Tests of kinetic_fem.gas: the gas model, the problems and parameter validation.

Every bad parameter must raise ValueError (bad value) or TypeError (bad type) with a
message naming the given value and what is allowed.
"""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from kinetic_fem.gas import (
    CoolingProblem,
    HeatedProblem,
    InelasticGas,
    check_alpha,
    check_finite_array,
    check_positive,
)


@given(st.floats(0.0, 1.0, exclude_max=True))
def test_valid_alpha_is_kept(alpha):
    gas = InelasticGas(alpha)
    assert gas.alpha == alpha
    assert gas.epsilon == pytest.approx(1.0 - alpha)


@pytest.mark.parametrize("alpha", [-0.1, -1e-300, 1.0 + 1e-12, 1.5, 2, math.inf, -math.inf])
def test_alpha_outside_range(alpha):
    with pytest.raises(ValueError, match=r"alpha=.*outside \[0, 1\]"):
        InelasticGas(alpha)


def test_alpha_one_heated_says_no_steady_state():
    """Elastic rods are a valid gas; under white noise alone they have no steady state,
    under a Fokker-Planck bath they do."""
    with pytest.raises(ValueError, match="alpha = 1.*no steady state") as err:
        HeatedProblem.from_parameters(1.0)
    assert "friction" in str(err.value)
    assert HeatedProblem.from_parameters(1.0, friction=1.0).friction == 1.0


def test_alpha_one_allowed_only_when_elastic_is_asked_for():
    assert check_alpha(1.0, allow_elastic=True) == 1.0
    with pytest.raises(ValueError, match=r"outside \[0, 1\]"):
        check_alpha(1.01, allow_elastic=True)


def test_alpha_nan():
    with pytest.raises(ValueError, match="alpha is NaN"):
        InelasticGas(float("nan"))


@pytest.mark.parametrize("bad", ["0.5", None, True, False, [0.5], 1j, np.array([0.5])])
def test_alpha_wrong_type(bad):
    with pytest.raises(TypeError, match="alpha must be a real number") as err:
        InelasticGas(bad)
    assert type(bad).__name__ in str(err.value)


def test_numpy_scalars_are_accepted():
    gas = InelasticGas(np.float32(0.5), density=np.int64(3))
    assert isinstance(gas.alpha, float) and gas.alpha == 0.5
    assert isinstance(gas.density, float) and gas.density == 3.0


@pytest.mark.parametrize("name", ["density", "diffusion"])
@pytest.mark.parametrize("value", [0.0, -1.0, -0.0, math.inf, -math.inf])
def test_density_and_diffusion_must_be_positive_finite(name, value):
    with pytest.raises(ValueError, match=rf"{name}=.* must be finite and > 0") as err:
        HeatedProblem.from_parameters(0.5, **{name: value})
    assert repr(float(value)) in str(err.value)


@pytest.mark.parametrize("name", ["density", "diffusion"])
def test_density_and_diffusion_nan(name):
    with pytest.raises(ValueError, match=rf"{name} is NaN"):
        HeatedProblem.from_parameters(0.5, **{name: float("nan")})


@pytest.mark.parametrize("name", ["density", "diffusion"])
@pytest.mark.parametrize("bad", ["1", None, True, object()])
def test_density_and_diffusion_wrong_type(name, bad):
    with pytest.raises(TypeError, match=rf"{name} must be a real number"):
        HeatedProblem.from_parameters(0.5, **{name: bad})


def test_cooling_problem_validates_too():
    with pytest.raises(ValueError, match="density"):
        CoolingProblem.from_parameters(0.5, density=-2)
    with pytest.raises(ValueError, match="alpha"):
        CoolingProblem.from_parameters(1.0)
    assert CoolingProblem.from_parameters(0.8).as_dict() == {
        "problem": "cooling", "alpha": 0.8, "density": 1.0, "gamma": 1.0}


def test_problems_need_a_gas():
    with pytest.raises(TypeError, match="gas must be an InelasticGas"):
        HeatedProblem(0.5)
    with pytest.raises(TypeError, match="gas must be an InelasticGas"):
        CoolingProblem({"alpha": 0.5})


@given(st.floats(1e-3, 1e3), st.floats(1e-3, 1e3))
def test_velocity_scale(density, diffusion):
    """u = (D/n)^(1/3) is the only velocity built from n and D."""
    problem = HeatedProblem(InelasticGas(0.5, density), diffusion)
    assert problem.velocity_scale**3 == pytest.approx(diffusion / density, rel=1e-12)
    assert problem.as_dict()["problem"] == "heated"


@given(st.floats(0.0, 1.0, exclude_max=True),
       st.floats(-10, 10), st.floats(-10, 10))
def test_collision_rule(alpha, v1, v2):
    """v1' + v2' = v1 + v2 and v1' - v2' = -alpha (v1 - v2)."""
    a, b = InelasticGas(alpha).collide(np.array([v1]), np.array([v2]))
    assert a[0] + b[0] == pytest.approx(v1 + v2, abs=1e-12)
    assert a[0] - b[0] == pytest.approx(-alpha * (v1 - v2), abs=1e-12)


def test_check_positive_and_finite_array_messages():
    assert check_positive("x", 3) == 3.0
    with pytest.raises(ValueError, match=r"x contains 2 non-finite value\(s\).*index 1"):
        check_finite_array("x", [1.0, np.nan, np.inf])
    with pytest.raises(ValueError, match="x must be a 1-d array, got shape"):
        check_finite_array("x", [[1.0]], ndim=1)
