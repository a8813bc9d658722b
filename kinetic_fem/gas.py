"""The gas and its problems (kept for compatibility: the model lives in :mod:`kinetic_fem.model`).

A binary collision of equal-mass rods maps

.. math::

    v_1' + v_2' = v_1 + v_2, \\qquad v_1' - v_2' = -\\alpha (v_1 - v_2).

See :mod:`kinetic_fem.model` for kernels, restitution laws and thermostats.
"""

from .model import (
    CoolingProblem,
    HeatedProblem,
    InelasticGas,
    check_alpha,
    check_finite_array,
    check_positive,
)

__all__ = ["InelasticGas", "HeatedProblem", "CoolingProblem", "check_alpha",
           "check_positive", "check_finite_array"]
