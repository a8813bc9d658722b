"""The saturating kernel :math:`B(g) = |g|/(1 + |g|/g_0)`: hard rods that turn Maxwellian.

A pair meets at the rate of its relative speed while that is small (hard rods,
:math:`B \\approx |g|`) and at a rate that saturates at :math:`g_0` when it is large
(the inelastic Maxwell model, :math:`B \\to g_0`): a collision frequency with a ceiling,
as for particles whose encounters are limited by a finite time per collision (a dead
time :math:`1/g_0` per unit density).  It bridges the paper's hard rods
(:math:`g_0 \\to \\infty`) and the Maxwell model (:math:`g_0 \\to 0`, time rescaled),
and it is *not* homogeneous: there is no scaled homogeneous cooling state (as the gas
cools it tends to hard rods), and the heated state's tail is exponential,
:math:`\\ln P \\sim -\\sqrt{n g_0/D}\\,|v|`, while its core is that of hard rods.

This module is the whole model side of the family: the methods evaluate :math:`B` in
the FEM pair rule and the DSMC acceptance through :attr:`SaturatingKernel.numeric`
(family code :data:`~kinetic_fem.model.kernel_base.FAMILY_SATURATING`), and everything
else (temperature estimates, cut-offs, mesh grading, time steps, the reduction to
:math:`n = D = 1`) asks the kernel the questions of
:class:`~kinetic_fem.model.kernel_base.CollisionKernel`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .kernel_base import FAMILY_SATURATING, CollisionKernel
from .validation import check_real

__all__ = ["SaturatingKernel"]


@dataclass(frozen=True)
class SaturatingKernel(CollisionKernel):
    """The kernel :math:`B(g) = |g|/(1 + |g|/g_0)`, :math:`0 < g_0 < \\infty`.

    Parameters
    ----------
    g0 : float
        Saturation speed: :math:`B(g) \\approx |g|` for :math:`|g| \\ll g_0`,
        :math:`B \\to g_0` for :math:`|g| \\gg g_0`.

    Raises
    ------
    ValueError
        If ``g0`` is not finite and > 0.

    Examples
    --------
    >>> k = SaturatingKernel(2.0)
    >>> k.rate([-2.0, 6.0])
    array([1. , 1.5])
    >>> k.rescaled(2.0)                  # B(2g)/2 in units of u = 2: g0 -> g0/u
    SaturatingKernel(g0=1.0)
    >>> k.homogeneity_degree is None, k.tail_growth
    (True, (2.0, 0.0))
    """

    g0: float = 1.0

    def __post_init__(self) -> None:
        g0 = check_real("saturation speed g0", self.g0)
        if not (math.isfinite(g0) and g0 > 0.0):
            raise ValueError(f"saturation speed g0={g0!r} must be finite and > 0 "
                             "(g0 -> infinity is hard rods: PowerLawKernel(1.0))")
        object.__setattr__(self, "g0", g0)

    @property
    def name(self) -> str:
        """``"saturating"`` with :math:`g_0`."""
        return f"saturating g0={self.g0:g}"

    def rate(self, g: ArrayLike) -> NDArray[np.float64]:
        """:math:`B(g) = |g|/(1 + |g|/g_0)`.

        Parameters
        ----------
        g : array_like
            Relative speeds.

        Returns
        -------
        ndarray
        """
        a = np.abs(np.asarray(g, dtype=float))
        return a / (1.0 + a / self.g0)

    @property
    def numeric(self) -> tuple[int, float]:
        """``(FAMILY_SATURATING, g0)``."""
        return FAMILY_SATURATING, self.g0

    @property
    def tail_growth(self) -> tuple[float, float]:
        """``(g0, 0)``: the rate saturates at :math:`g_0`."""
        return self.g0, 0.0

    @property
    def scale_degree(self) -> float:
        """1: :math:`B(ug) = u\\,B_{g_0/u}(g)`, hard rods at small speeds."""
        return 1.0

    def rescaled(self, u: float) -> SaturatingKernel:
        """:math:`B(ug)/u`, the saturating kernel with :math:`g_0/u`.

        Parameters
        ----------
        u : float
            Velocity unit, > 0.

        Returns
        -------
        SaturatingKernel
        """
        return self if u == 1.0 else SaturatingKernel(self.g0 / u)
