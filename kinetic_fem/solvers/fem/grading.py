"""Graded meshes of the heated FEM solver: element size growing as a power of :math:`|c|`.

:func:`graded_vertices` (re-exported by :mod:`kinetic_fem.solvers.fem.defaults`, where the
grading exponent is chosen from the model's tail) places the vertices uniformly in the
stretched coordinate :math:`s(c) = \\int_0^c dc/h(c)`, inverted in closed form.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ...operators.grid import symmetric_grid, uniform_grid

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
    if grading == 0.0:
        half = max(2, int(math.ceil(c_max / spacing)))
        return symmetric_grid(uniform_grid(c_max, half + 1))
    # stretched coordinate s(c) = int_0^c dc / h(c), uniform in s
    total = _stretched(c_max, spacing, grading, bulk)
    n_el = max(2, int(math.ceil(total)))
    targets = np.linspace(0.0, total, n_el + 1)
    nodes = np.concatenate([[0.0], _unstretched(targets[1:-1], spacing, grading, bulk),
                            [c_max]])
    return np.concatenate([-nodes[:0:-1], nodes])


def _unstretched(s: NDArray, h0: float, kappa: float, cb: float) -> NDArray:
    """The inverse of :func:`_stretched` in closed form (the former root-finding to 2e-12,
    4 % of a heated state)."""
    t = np.asarray(s, dtype=float) * h0 / cb  # the stretched coordinate in units of c_b
    tail = t > 1.0
    out = cb * t
    if kappa == 1.0:
        out[tail] = cb * np.exp(t[tail] - 1.0)
    else:
        out[tail] = cb * (1.0 + (1.0 - kappa) * (t[tail] - 1.0)) ** (1.0 / (1.0 - kappa))
    return out


def _stretched(c: float, h0: float, kappa: float, cb: float) -> float:
    if c <= cb:
        return c / h0
    if kappa == 1.0:
        return (cb + cb * math.log(c / cb)) / h0
    return (cb + cb / (1.0 - kappa) * ((c / cb) ** (1.0 - kappa) - 1.0)) / h0
