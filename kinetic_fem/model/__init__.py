"""The model: collision kernel, restitution law, thermostat, and the problems posed.

Every method reads the model from here.  Parameters are validated once, where they
enter (the constructors below); solvers state what they support with
``problem.require(...)``, which raises :class:`UnsupportedModelError` with a message
naming the method that does.

Adding a kernel or a thermostat is one class here plus the support each solver needs
in its own module.  A kernel is a :class:`CollisionKernel`, which answers every question
a method asks of it (Gaussian averages, DSMC majorant, tail growth, the rescaling of the
reduction to ``n = D = 1``, a numeric form for compiled code); no method outside the
power-law derivations (Sonine, FD, cooling) reads an exponent.  A new kernel family is
its class (see :class:`SaturatingKernel` in :mod:`kinetic_fem.model.kernel_saturating`)
plus its rate in the FEM pair rule and its acceptance in the DSMC
(``docs/user_guide/models.rst``, "Adding a kernel").
"""

from .kernel import HARD_RODS, MAXWELL, PowerLawKernel, as_kernel
from .kernel_base import CollisionKernel
from .kernel_saturating import SaturatingKernel
from .mixture import Mixture
from .problem import CoolingProblem, HeatedProblem, InelasticGas
from .restitution import (
    ConstantRestitution,
    RestitutionLaw,
    ThresholdRestitution,
    ViscoelasticRestitution,
    as_restitution,
    restitution_value,
)
from .thermostat import FokkerPlanckBath, NoThermostat, Thermostat, WhiteNoise, as_thermostat
from .validation import (
    UnsupportedModelError,
    check_alpha,
    check_finite_array,
    check_nonnegative,
    check_positive,
    check_real,
)

__all__ = [
    "Mixture",
    "CollisionKernel", "PowerLawKernel", "SaturatingKernel", "HARD_RODS", "MAXWELL", "as_kernel",
    "RestitutionLaw", "ConstantRestitution", "ThresholdRestitution",
    "ViscoelasticRestitution", "as_restitution", "restitution_value",
    "Thermostat", "WhiteNoise", "FokkerPlanckBath", "NoThermostat", "as_thermostat",
    "InelasticGas", "HeatedProblem", "CoolingProblem",
    "UnsupportedModelError", "check_alpha", "check_positive", "check_nonnegative",
    "check_real", "check_finite_array",
]
