"""Power-law collision kernels :math:`B(g) = |g|^\\gamma`, and :func:`as_kernel`.

The Boltzmann collision operator of the one-dimensional gas with kernel :math:`B(g)` is

.. math::

    Q[P](v) = n \\int dv' \\, B(|v - v'|) \\,[\\text{gain} - \\text{loss}].

:class:`PowerLawKernel`, :math:`|g|^\\gamma` with :math:`0 \\le \\gamma \\le 2`:
:math:`\\gamma = 1` are hard rods (the paper, and the default), :math:`\\gamma = 0` the
inelastic Maxwell model (a collision rate independent of the relative speed), anything
between "variable hard rods".  It answers the questions of
:class:`~kinetic_fem.model.kernel_base.CollisionKernel` in closed form; the base class
lists them and the other families.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import quad
from scipy.special import roots_genlaguerre

from .kernel_base import FAMILY_POWER_LAW, CollisionKernel
from .validation import check_real

__all__ = ["PowerLawKernel", "HARD_RODS", "MAXWELL", "as_kernel"]


@dataclass(frozen=True)
class PowerLawKernel(CollisionKernel):
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

    @property
    def numeric(self) -> tuple[int, float]:
        """``(FAMILY_POWER_LAW, gamma)`` (:attr:`CollisionKernel.numeric`)."""
        return FAMILY_POWER_LAW, self.gamma

    @property
    def tail_growth(self) -> tuple[float, float]:
        """``(1, gamma)``: :math:`B(g) = g^\\gamma` at every speed."""
        return 1.0, self.gamma

    @property
    def scale_degree(self) -> float:
        """``gamma`` (:meth:`rescaled` returns the kernel itself)."""
        return self.gamma

    @property
    def homogeneity_degree(self) -> float | None:
        """``gamma``: :math:`B(ug) = u^\\gamma B(g)`."""
        return self.gamma

    def rescaled(self, u: float) -> PowerLawKernel:
        """The kernel itself: :math:`B(ug)/u^\\gamma = B(g)`.

        Parameters
        ----------
        u : float
            Velocity unit, > 0.

        Returns
        -------
        PowerLawKernel
        """
        return self

    def weighted_rate(self, g: ArrayLike, power: float) -> NDArray[np.float64]:
        """:math:`|g|^{\\gamma+p}` (:meth:`CollisionKernel.weighted_rate`).

        Parameters
        ----------
        g : array_like
            Relative speeds.
        power : float
            :math:`p \\ge 0`.

        Returns
        -------
        ndarray
        """
        return np.abs(np.asarray(g, dtype=float)) ** (self.gamma + power)

    def majorant(self, g_max: float) -> float:
        """:math:`g_{max}^\\gamma` (:meth:`CollisionKernel.majorant`).

        Parameters
        ----------
        g_max : float
            Largest relative speed, >= 0.

        Returns
        -------
        float
        """
        return float(g_max) ** self.gamma

    def local_exponent(self, temperature: float) -> float:
        """``gamma`` at every temperature (:meth:`CollisionKernel.local_exponent`).

        Parameters
        ----------
        temperature : float
            Temperature (unused).

        Returns
        -------
        float
        """
        return self.gamma

    def gaussian_mean(self, temperature: float, power: float = 0.0) -> float:
        """:math:`\\langle |g|^{\\gamma + p}\\rangle` for two independent Gaussians.

        The relative speed of two velocities of variance :math:`T` is Gaussian with
        variance :math:`2T`, so
        :math:`\\langle|g|^s\\rangle = (4T)^{s/2}\\Gamma((s+1)/2)/\\sqrt\\pi`.

        Parameters
        ----------
        temperature : float
            Variance :math:`T` of each velocity, > 0.
        power : float
            :math:`p \\ge 0`.

        Returns
        -------
        float

        Examples
        --------
        >>> round(PowerLawKernel(1.0).gaussian_mean(1.0), 12)  # <|g|> = 2/sqrt(pi)
        1.128379167096
        """
        s = self.gamma + power
        return (4.0 * temperature) ** (0.5 * s) * math.gamma(0.5 * (s + 1.0)) / math.sqrt(math.pi)

    def gaussian_average(self, temperature: float, weight: Callable[[float], float] | None,
                         power: float = 0.0, breaks: Sequence[float] = ()) -> float:
        """:math:`\\langle w(g)|g|^{\\gamma+p}\\rangle` (:meth:`CollisionKernel.gaussian_average`;
        without a weight the closed form :meth:`gaussian_mean`).

        Parameters
        ----------
        temperature : float
            Variance :math:`T` of each velocity, > 0.
        weight : callable or None
            :math:`w(g)`; ``None``: 1.
        power : float
            :math:`p \\ge 0`.
        breaks : sequence of float
            Relative speeds where :math:`w` has a kink or jump.

        Returns
        -------
        float
        """
        if weight is None:
            return self.gaussian_mean(temperature, power)
        scale = 2.0 * float(np.sqrt(temperature))
        s = self.gamma + power

        def integrand(x: float) -> float:  # x = g / (2 sqrt T)
            return weight(scale * x) * x**s * float(np.exp(-x * x))

        points = [b / scale for b in breaks] or None
        value = quad(integrand, 0.0, 12.0, points=points, epsabs=0.0, epsrel=1e-12,
                     limit=200)[0]
        return 2.0 * scale**s * value / float(np.sqrt(np.pi))

    def wkb_action(self, v: ArrayLike) -> NDArray[np.float64]:
        """:math:`\\tfrac{2}{2+\\gamma}|v|^{1+\\gamma/2}` (:meth:`CollisionKernel.wkb_action`).

        Parameters
        ----------
        v : array_like
            Velocities.

        Returns
        -------
        ndarray
        """
        speed = np.abs(np.asarray(v, dtype=float))
        return 2.0 / (2.0 + self.gamma) * speed ** (1.0 + 0.5 * self.gamma)

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


def as_kernel(kernel: object) -> CollisionKernel:
    """A kernel object from an exponent ``gamma`` or a kernel.

    Parameters
    ----------
    kernel : float or CollisionKernel
        The exponent :math:`\\gamma \\in [0, 2]` of :math:`B(g) = |g|^\\gamma` (1: hard
        rods, 0: the Maxwell model), or a kernel object (returned as it is).

    Returns
    -------
    CollisionKernel

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
    if isinstance(kernel, CollisionKernel):
        return kernel
    if isinstance(kernel, str):
        raise TypeError(f"kernel must be an exponent gamma in [0, 2] or a CollisionKernel, "
                        f"got the string {kernel!r}")
    return PowerLawKernel(check_real("kernel exponent gamma", kernel))
