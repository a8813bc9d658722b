"""kinetic-fem: velocity distributions of the one-dimensional inelastic gas.

Deterministic solvers of the homogeneous Boltzmann equation

.. math::

    \\partial_t P - D\\partial_v^2 P = -n\\int dv'\\,|v-v'|P(v)P(v')
    + \\frac{4n}{(1+\\alpha)^2}\\int dv'\\,|v-v'|P(v')
      P\\Big(\\frac{2v-(1-\\alpha)v'}{1+\\alpha}\\Big)

(heated steady state, free cooling), its quasi-elastic limits, and the common
result type :class:`VelocityDistribution`.  Particle methods live in the
``particles`` package.
"""

import logging
import sys

from . import gas, model, operators, solvers, sonine  # noqa: F401
from .distribution import RunInfo, VelocityDistribution
from .evolve import evolve_cooling, evolve_heated
from .model import (
    CoolingProblem,
    FokkerPlanckBath,
    HeatedProblem,
    InelasticGas,
    PowerLawKernel,
    SaturatingKernel,
    ThresholdRestitution,
    ViscoelasticRestitution,
    WhiteNoise,
)
from .solve import COOLING_SOLVERS, HEATED_SOLVERS, register_solver, solve_cooling, solve_heated

# Importing a solver module registers it (kinetic_fem.solve): all of them, at import.
from .solvers import (  # noqa: F401
    fd_cooling,
    fem,
    fem_cooling,
    finite_difference,
    scaling,  # noqa: F401 - public as kf.scaling (DESIGN.md)
    spectral,
)
from .solvers.relaxation import relaxation_spectrum
from .sweep import sweep  # noqa: F401 - kf.sweep is the function, kinetic_fem.sweep the package

__version__ = "0.1.0"
__all__ = [
    "InelasticGas", "HeatedProblem", "CoolingProblem", "VelocityDistribution", "RunInfo",
    "solve_heated", "solve_cooling", "register_solver", "HEATED_SOLVERS", "COOLING_SOLVERS",
    "PowerLawKernel", "SaturatingKernel", "ThresholdRestitution", "ViscoelasticRestitution",
    "WhiteNoise", "FokkerPlanckBath", "sonine", "scaling", "grid", "gas", "model",
    "evolve_heated", "evolve_cooling", "relaxation_spectrum",
]

# ``import kinetic_fem.scaling`` keeps working: the quasi-elastic solvers moved to
# kinetic_fem.solvers.scaling with the model-layer layout, their public name did not.
sys.modules[__name__ + ".scaling"] = scaling

logging.getLogger(__name__).addHandler(logging.NullHandler())
