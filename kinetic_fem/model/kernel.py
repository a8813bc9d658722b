"""Collision kernels: the rate of a pair collision as a function of the relative speed.

The Boltzmann collision operator of the one-dimensional gas with kernel
:math:`B(g) = |g|^\\gamma` is

.. math::

    Q[P](v) = n \\int dv' \\, B(|v - v'|) \\,[\\text{gain} - \\text{loss}],

with :math:`0 \\le \\gamma \\le 2`: :math:`\\gamma = 1` are hard rods (the paper,
and the default), :math:`\\gamma = 0` the inelastic Maxwell model (a collision rate
independent of the relative speed), anything between "variable hard rods".
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import roots_genlaguerre

from .validation import check_real

__all__ = ["PowerLawKernel", "HARD_RODS", "MAXWELL", "as_kernel"]


@dataclass(frozen=True)
class PowerLawKernel:
    """The collision kernel :math:`B(g) = |g|^\\gamma`, ``0 <= gamma <= 2``.

    Parameters
    ----------
    gamma : float
        Exponent: 1 for hard rods, 0 for the inelastic Maxwell model.

    Raises
    ------
    ValueError
        If ``gamma`` lies outside ``[0, 2]``.

    Examples
    --------
    >>> PowerLawKernel(1.0).rate([-2.0, 3.0])
    array([2., 3.])
    >>> PowerLawKernel(0.0).is_maxwell
    True
    """

    gamma: float = 1.0

    def __post_init__(self) -> None:
        gamma = check_real("kernel exponent gamma", self.gamma)
        if not 0.0 <= gamma <= 2.0:
            raise ValueError(
                f"kernel exponent gamma={gamma!r} is outside [0, 2]: B(g) = |g|^gamma is "
                "supported for 0 <= gamma <= 2 (0 Maxwell molecules, 1 hard rods)")
        object.__setattr__(self, "gamma", gamma)

    @property
    def is_maxwell(self) -> bool:
        """True for :math:`\\gamma = 0` (collision rate independent of the speed)."""
        return self.gamma == 0.0

    @property
    def is_hard_rods(self) -> bool:
        """True for :math:`\\gamma = 1` (the paper)."""
        return self.gamma == 1.0

    @property
    def name(self) -> str:
        """A short human-readable name."""
        if self.is_hard_rods:
            return "hard rods"
        if self.is_maxwell:
            return "Maxwell"
        return f"|g|^{self.gamma:g}"

    def rate(self, g: ArrayLike) -> NDArray[np.float64]:
        """:math:`B(g) = |g|^\\gamma` (with :math:`0^0 = 1`)."""
        return np.abs(np.asarray(g, dtype=float)) ** self.gamma

    def gaussian_mean(self, temperature: float, power: float = 0.0) -> float:
        """:math:`\\langle |g|^{\\gamma + p}\\rangle` for two independent Gaussians.

        The relative speed of two velocities of variance :math:`T` is Gaussian with
        variance :math:`2T`, so
        :math:`\\langle|g|^s\\rangle = (4T)^{s/2}\\Gamma((s+1)/2)/\\sqrt\\pi`.

        Examples
        --------
        >>> round(PowerLawKernel(1.0).gaussian_mean(1.0), 12)  # <|g|> = 2/sqrt(pi)
        1.128379167096
        """
        s = self.gamma + power
        return (4.0 * temperature) ** (0.5 * s) * math.gamma(0.5 * (s + 1.0)) / math.sqrt(math.pi)

    def relative_speed_rule(self, n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Gauss rule for the relative speed with the weight :math:`B(g)e^{-g^2/4}`.

        :math:`\\int_0^\\infty \\varphi(g)\\,B(g)\\,e^{-g^2/4}\\,dg = \\sum_k w_k
        \\varphi(g_k)`, exact for :math:`\\varphi` a polynomial in :math:`g^2` of degree
        below :math:`2n`: with :math:`s = g^2/4` the weight is
        :math:`2^\\gamma s^{(\\gamma-1)/2}e^{-s}`, generalised Gauss-Laguerre.  The Sonine
        tensors (:mod:`kinetic_fem.operators.sonine_tensors`) ask the kernel for it.

        Parameters
        ----------
        n : int
            Number of nodes.

        Returns
        -------
        g, w : ndarray
            Nodes (relative speeds, > 0) and weights.

        Examples
        --------
        >>> g, w = PowerLawKernel(1.0).relative_speed_rule(4)
        >>> round(float(w.sum()), 12)                 # int_0^inf g e^(-g^2/4) dg = 2
        2.0
        """
        s, w = roots_genlaguerre(n, 0.5 * (self.gamma - 1.0))
        return 2.0 * np.sqrt(s), 2.0**self.gamma * w


HARD_RODS = PowerLawKernel(1.0)
MAXWELL = PowerLawKernel(0.0)


def as_kernel(kernel: object) -> PowerLawKernel:
    """A kernel object from an exponent ``gamma`` or a kernel.

    Parameters
    ----------
    kernel : float or PowerLawKernel
        The exponent :math:`\\gamma \\in [0, 2]` of :math:`B(g) = |g|^\\gamma` (1: hard
        rods, 0: the Maxwell model), or a kernel object (returned as it is).

    Returns
    -------
    PowerLawKernel

    Raises
    ------
    TypeError
        If ``kernel`` is neither a real number nor a kernel object.
    ValueError
        If ``gamma`` lies outside [0, 2] or is not finite.

    Examples
    --------
    >>> as_kernel(0.5)
    PowerLawKernel(gamma=0.5)
    """
    if isinstance(kernel, PowerLawKernel):
        return kernel
    if isinstance(kernel, str):
        raise TypeError(f"kernel must be an exponent gamma in [0, 2] or a PowerLawKernel, "
                        f"got the string {kernel!r}")
    return PowerLawKernel(check_real("kernel exponent gamma", kernel))
