"""Graded meshes of the heated FEM solver: element size growing as a power of :math:`|c|`.

:func:`graded_vertices` (re-exported by :mod:`kinetic_fem.solvers.fem.defaults`, where the
grading exponent is chosen from the model's tail) places the vertices uniformly in the
stretched coordinate :math:`s(c) = \\int_0^c dc/h(c)`, inverted in closed form: the
placement :meth:`~kinetic_fem.operators.mesher.ScaleGrading.stretched` of the mesher.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ...operators.mesher import ScaleGrading

__all__ = ["graded_vertices"]


def graded_vertices(c_max: float, spacing: float, *, grading: float,
                    bulk: float = 3.0) -> NDArray[np.float64]:
    """Symmetric vertices in thermal velocities, element size
    :math:`h(c) = h_0 \\max(1, |c|/c_b)^\\kappa` out to ``c_max``.

    Parameters
    ----------
    c_max : float
        Half-width of the interval.
    spacing : float
        :math:`h_0`, the bulk element size.
    grading : float
        :math:`\\kappa \\ge 0` (0: uniform).
    bulk : float
        :math:`c_b`, the end of the uniform bulk.

    Examples
    --------
    >>> v = graded_vertices(10.0, 0.5, grading=0.0)
    >>> v.size, float(v[0]), float(v[-1])
    (41, -10.0, 10.0)
    """
    return ScaleGrading(spacing, grading, bulk).stretched(c_max)
