"""The mixture model: validation and the reduced masses (kinetic_fem.model.mixture)."""

import math

import pytest

from kinetic_fem.model import FokkerPlanckBath, ViscoelasticRestitution, WhiteNoise
from kinetic_fem.model.mixture import Mixture


def test_reduced_masses_and_defaults():
    mix = Mixture(masses=(1.0, 3.0), fractions=(0.25, 0.75), alpha=0.8)
    assert mix.reduced_mass(0, 1) == 0.75 and mix.reduced_mass(1, 0) == 0.25
    assert mix.reduced_mass(0, 0) == 0.5
    assert not mix.heated and mix.constant_alpha().tolist() == [[0.8, 0.8], [0.8, 0.8]]


def test_forcing_conventions():
    same_d = Mixture.white_noise((1.0, 4.0), (0.5, 0.5), diffusion=2.0)
    same_p = Mixture.white_noise((1.0, 4.0), (0.5, 0.5), diffusion=2.0, convention="same_power")
    assert same_d.diffusions().tolist() == [2.0, 2.0]
    assert same_p.diffusions().tolist() == [2.0, 0.5]  # m_s D_s equal
    assert same_d.heated and same_p.heated


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"masses": (1.0,), "fractions": (1.0,)}, "at least 2 species"),
    ({"masses": (1.0, -2.0), "fractions": (0.5, 0.5)}, r"masses\[1\]"),
    ({"masses": (1.0, math.nan), "fractions": (0.5, 0.5)}, r"masses\[1\]"),
    ({"masses": (1.0, 2.0), "fractions": (0.5, 0.6)}, "sum to 1"),
    ({"masses": (1.0, 2.0), "fractions": (0.5,)}, "one number fraction per species"),
    ({"masses": (1.0, 2.0), "fractions": (1.0, 0.0)}, r"fractions\[1\]"),
    ({"masses": (1.0, 2.0), "fractions": (0.5, 0.5), "alpha": 1.5}, "outside"),
    ({"masses": (1.0, 2.0), "fractions": (0.5, 0.5), "alpha": [[0.5, 0.6], [0.7, 0.5]]},
     "symmetric"),
    ({"masses": (1.0, 2.0), "fractions": (0.5, 0.5), "alpha": [[0.5, 0.6]]}, "2 x 2"),
    ({"masses": (1.0, 2.0), "fractions": (0.5, 0.5),
      "thermostats": (WhiteNoise(1.0), FokkerPlanckBath(1.0, 1.0), WhiteNoise(1.0))},
     "one Thermostat per species"),
])
def test_bad_mixtures_are_refused_with_the_parameter_named(kwargs, match):
    with pytest.raises((TypeError, ValueError), match=match):
        Mixture(**kwargs)


def test_wrong_types_and_conventions():
    with pytest.raises(TypeError, match="masses"):
        Mixture(masses="12", fractions=(0.5, 0.5))
    with pytest.raises(ValueError, match="convention"):
        Mixture.white_noise((1.0, 2.0), (0.5, 0.5), convention="same_force")


def test_velocity_dependent_law_is_kept_and_refused_where_a_constant_is_needed():
    from kinetic_fem.model import UnsupportedModelError

    mix = Mixture((1.0, 2.0), (0.5, 0.5), alpha=ViscoelasticRestitution(0.2))
    with pytest.raises(UnsupportedModelError, match="constant restitution"):
        mix.constant_alpha()
