"""The near-elastic cooling state's humps rescaled onto the psi equation (claims C11, C12).

Near elastic collisions, :math:`\\epsilon = 1 - \\alpha \\to 0`, the homogeneous cooling
state :math:`f(c)` has two humps at :math:`c = \\pm\\langle|c|\\rangle`; on the scaled
variable

.. math::

    y = \\frac{1 - c/\\langle|c|\\rangle}{\\epsilon^{1/3}}, \\qquad
    \\psi_{HCS}(y) = 2 f(c)\\, \\epsilon^{1/3} \\langle|c|\\rangle,

the right hump tends to the solution of the psi equation
(:func:`kinetic_fem.solvers.scaling.solve_psi`), and its width scales as :math:`\\epsilon^{1/3}`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["HumpProfile", "psi_profile"]


@dataclass(frozen=True)
class HumpProfile:
    """The right hump of a cooling state on the psi variables.

    Attributes
    ----------
    y : ndarray, shape (n_v,)
        Scaled velocity :math:`(1 - c/\\langle|c|\\rangle)/\\epsilon^{1/3}`, increasing.
    psi : ndarray, shape (n_v,)
        :math:`2 f(c)\\, \\epsilon^{1/3} \\langle|c|\\rangle` at ``y``.
    mean_abs : float
        :math:`\\langle|c|\\rangle` in thermal velocities.
    """

    y: NDArray[np.float64]
    psi: NDArray[np.float64]
    mean_abs: float


def psi_profile(c: NDArray[np.float64], f: NDArray[np.float64],
                half_weights: NDArray[np.float64], eps: float) -> HumpProfile:
    """Rescale a symmetric cooling state given on the half line onto the psi variables.

    Parameters
    ----------
    c : ndarray, shape (n_v,)
        Non-negative nodes (thermal velocities, unit temperature).
    f : ndarray, shape (n_v,)
        The scaled distribution :math:`f(c)` at ``c`` (normalised on the whole line).
    half_weights : ndarray, shape (n_v,)
        Weights of even functions over the whole line on these nodes (each node stands
        for :math:`\\pm c`), so that ``sum(half_weights * f) = 1``: the
        ``half_weights`` of :class:`kinetic_fem.operators.collision.HalfGrid`.
    eps : float
        Inelasticity :math:`1 - \\alpha`, positive.

    Returns
    -------
    HumpProfile

    Examples
    --------
    >>> c = np.linspace(0.0, 10.0, 2001)
    >>> w = np.full_like(c, 2 * c[1]); w[0] = w[-1] = c[1]  # trapezoid, doubled
    >>> f = np.exp(-c**2 / 2) / np.sqrt(2 * np.pi)
    >>> round(psi_profile(c, f, w, 1e-3).mean_abs, 4)  # sqrt(2/pi) for a Gaussian
    0.7979
    """
    if not eps > 0:
        raise ValueError(f"eps = 1 - alpha must be positive, got {eps!r}")
    mean_abs = float(np.dot(half_weights, c * f))
    d = eps ** (1.0 / 3.0)
    y = (1.0 - c / mean_abs) / d
    order = np.argsort(y)
    return HumpProfile(y[order], (2.0 * f * d * mean_abs)[order], mean_abs)
