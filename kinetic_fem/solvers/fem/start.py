"""The tail of the heated FEM start for soft kernels: the gain-delayed (tangent) tail.

Far from the bulk a heated state decays as :math:`e^{-S(v)}`, :math:`S' = \\sqrt{B}`
(white noise, ``n = D = 1``), but for kernels that grow slower than linearly the gain
keeps the bulk Gaussian (at the temperature :math:`T`) well beyond the point where the
bare :math:`e^{-S}` would take over (:func:`kinetic_fem.solvers.fem.defaults.gain_margin`):
the tail is the Gaussian up to :math:`v_t`, where its slope :math:`v/T` meets
:math:`S'(v)`, and the tangent :math:`e^{-(G(v_t) + S(v) - S(v_t))}` beyond.  The start
:func:`kinetic_fem.solvers.fem.defaults.initial_log_density` takes this tail in place of
:math:`\\min(G, S)` (the bare tail, many decades below the state): the first coarse
Newton update of the saturating kernel at alpha = 0.81 and 0.9 falls from 3e3 and 5e6 to
17 and 270, and the coarse solve needs 2 Jacobians instead of 3 (issue 16; the state is
the same to round-off).
"""

from __future__ import annotations

from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from ...model import CollisionKernel

__all__ = ["TailModel", "start_exponent"]


class TailModel(Protocol):
    """What :func:`start_exponent` reads of a heated model
    (:class:`~kinetic_fem.solvers.fem.defaults.ScaledModel` is one).

    Parameters
    ----------
    friction : float
        Friction of the bath (0: white noise), a property.
    kernel : CollisionKernel
        The collision kernel, a property.
    """

    @property
    def friction(self) -> float:
        """Friction of the bath (0: white noise)."""

    @property
    def kernel(self) -> CollisionKernel:
        """The collision kernel."""


def start_exponent(gauss: NDArray[np.float64], action: NDArray[np.float64],
                   model: TailModel) -> NDArray[np.float64]:
    """:math:`-\\ln P` (unnormalised) of the start on an increasing grid from 0.

    :math:`\\min(G, S)` (the Gaussian exponent ``gauss`` in the bulk, the tail action
    ``action`` where that grows more slowly); for soft kernels (the kernel's
    ``tail_growth`` below 1) under white noise the Gaussian up to the first grid interval
    where it grows faster than :math:`S`, and :math:`S` continued from there (the tangent
    tail of the module docstring).

    Parameters
    ----------
    gauss : ndarray
        :math:`G(v) = v^2/2T` on the grid.
    action : ndarray
        :math:`S(v)` on the grid (:math:`S(0) = 0`).
    model : TailModel
        The heated model (its ``friction`` and ``kernel``, e.g. a
        :class:`~kinetic_fem.solvers.fem.defaults.ScaledModel`).

    Returns
    -------
    ndarray

    Examples
    --------
    >>> from kinetic_fem.model import ConstantRestitution
    >>> from kinetic_fem.solvers.fem.defaults import ScaledModel
    >>> v = np.linspace(0.0, 4.0, 5)
    >>> m = ScaledModel(ConstantRestitution(0.5), 0.0, 0.0, 1.0, 2.0)   # Maxwell, T = 2
    >>> start_exponent(v**2 / 4.0, v, m)     # tangent at v = T = 2: G(2) + v - 2
    array([0.  , 0.25, 1.  , 2.  , 3.  ])
    """
    exponent = np.minimum(gauss, action)
    if model.friction > 0.0 or model.kernel.tail_growth[1] >= 1.0:
        return exponent
    cross = np.flatnonzero(np.diff(gauss) > np.diff(action))
    if cross.size:
        t = int(cross[0])
        exponent[t:] = gauss[t] + action[t:] - action[t]
    return exponent
