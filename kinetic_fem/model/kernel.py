"""Collision kernels: the rate of a pair collision as a function of the relative speed.

The Boltzmann collision operator of the one-dimensional gas with kernel :math:`B(g)` is

.. math::

    Q[P](v) = n \\int dv' \\, B(|v - v'|) \\,[\\text{gain} - \\text{loss}].

Every kernel is a :class:`CollisionKernel`: an even, non-negative, non-decreasing
function of the relative speed that answers the questions the methods ask of it, so
that no solver reads a formula of one family:

* :meth:`~CollisionKernel.rate`, :math:`B(g)` (the FEM pair rule evaluates it in
  compiled code through :attr:`~CollisionKernel.numeric`);
* :meth:`~CollisionKernel.gaussian_mean`, :math:`\\langle B(g)|g|^p\\rangle` over two
  Gaussians (temperature estimates, energy loss, mean free times);
* :meth:`~CollisionKernel.majorant`, :math:`\\max_{|g| \\le g_{max}} B` (DSMC
  acceptance);
* :attr:`~CollisionKernel.tail_growth`, :math:`B(g) \\sim c\\,g^p` as
  :math:`g \\to \\infty` (tails, cut-offs and mesh grading);
* :attr:`~CollisionKernel.scale_degree` and :meth:`~CollisionKernel.rescaled`, how
  the kernel changes when velocities are measured in a unit :math:`u` (the reduction
  of a heated problem to :math:`n = D = 1`); :attr:`~CollisionKernel.homogeneity_degree`
  (``None`` unless :math:`B(ug) = u^d B(g)`: the scaled cooling state needs it);
* :attr:`~CollisionKernel.numeric`, ``(family code, parameter)`` for the numba loops.

Two families:

* :class:`PowerLawKernel`, :math:`B(g) = |g|^\\gamma` with :math:`0 \\le \\gamma \\le 2`:
  :math:`\\gamma = 1` are hard rods (the paper, and the default), :math:`\\gamma = 0` the
  inelastic Maxwell model (a collision rate independent of the relative speed),
  anything between "variable hard rods";
* :class:`~kinetic_fem.model.kernel_saturating.SaturatingKernel`,
  :math:`B(g) = |g|/(1 + |g|/g_0)`: hard rods at small relative speeds, a Maxwell
  (constant) rate :math:`g_0` at large ones; not homogeneous.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import quad
from scipy.special import roots_genlaguerre

from .validation import UnsupportedModelError, check_real

__all__ = ["CollisionKernel", "PowerLawKernel", "HARD_RODS", "MAXWELL", "as_kernel",
           "FAMILY_POWER_LAW", "FAMILY_SATURATING"]

FAMILY_POWER_LAW = 0
"""Family code of :class:`PowerLawKernel` in :attr:`CollisionKernel.numeric` (parameter:
``gamma``)."""
FAMILY_SATURATING = 1
"""Family code of :class:`~kinetic_fem.model.kernel_saturating.SaturatingKernel`
(parameter: ``g0``)."""


class CollisionKernel(ABC):
    """A collision kernel :math:`B(g)`: even, :math:`\\ge 0`, non-decreasing in :math:`|g|`.

    A new kernel family is a subclass that implements :meth:`rate`, :attr:`name`,
    :attr:`numeric`, :attr:`tail_growth`, :attr:`scale_degree` and :meth:`rescaled`;
    the Gaussian averages, the DSMC majorant and the local exponent have numerical
    defaults here, which a family with closed forms overrides.  Methods whose
    derivation assumes a power law (Sonine, the paper's finite differences, the scaled
    cooling state) read :attr:`gamma`, which refuses other families with
    :class:`UnsupportedModelError`.
    """

    @property
    @abstractmethod
    def name(self) -> str:
        """A short human-readable name."""

    @abstractmethod
    def rate(self, g: ArrayLike) -> NDArray[np.float64]:
        """:math:`B(g)` at the relative speeds ``g``.

        Parameters
        ----------
        g : array_like
            Relative speeds (any sign: :math:`B` is even).

        Returns
        -------
        ndarray
        """

    @property
    @abstractmethod
    def numeric(self) -> tuple[int, float]:
        """``(family, parameter)`` for compiled code: :data:`FAMILY_POWER_LAW` and
        ``gamma``, or :data:`FAMILY_SATURATING` and ``g0``.  The FEM pair rule
        (:func:`kinetic_fem.operators.fem_pair_breaks.kernel_rate`) and the DSMC
        acceptance (:func:`particles._dsmc_kernels.kernel_code`) dispatch on it."""

    @property
    @abstractmethod
    def tail_growth(self) -> tuple[float, float]:
        """``(c, p)`` with :math:`B(g) \\sim c\\,g^p` as :math:`g \\to \\infty`.

        The loss frequency of a fast particle is then :math:`n c |v|^p`, which sets the
        far tail :math:`e^{-S(v)}` of a heated state (:func:`kinetic_fem.model.scales.tail_action`).
        """

    @property
    @abstractmethod
    def scale_degree(self) -> float:
        """:math:`d` of :meth:`rescaled`: :math:`B(ug) = u^d K_u(g)`."""

    @abstractmethod
    def rescaled(self, u: float) -> CollisionKernel:
        """The kernel in velocity units of ``u``: :math:`K_u(g) = B(ug)/u^d`.

        With :math:`d` = :attr:`scale_degree` a heated problem at density :math:`n` and
        noise strength :math:`D` maps onto one at :math:`n = D = 1` with the kernel
        :math:`K_u`, :math:`u = (D/n)^{1/(2+d)}`
        (:attr:`kinetic_fem.model.HeatedProblem.unit_kernel`).  A family that is not
        closed under this rescaling may raise
        :class:`~kinetic_fem.model.UnsupportedModelError` for ``u != 1``: its heated
        problems are then solvable at ``D = n`` only.

        Parameters
        ----------
        u : float
            Velocity unit, > 0.

        Returns
        -------
        CollisionKernel
        """

    @property
    def homogeneity_degree(self) -> float | None:
        """:math:`d` if :math:`B(ug) = u^d B(g)` for every :math:`u`, else ``None``.

        The homogeneous cooling state is a scaling solution only for a homogeneous
        kernel (free cooling, :class:`kinetic_fem.model.CoolingProblem`).
        """
        return None

    @property
    def gamma(self) -> float:
        """The exponent of a power law; other families refuse.

        Raises
        ------
        UnsupportedModelError
            The kernel is not a power law :math:`|g|^\\gamma`.
        """
        raise UnsupportedModelError(
            f"this computation assumes a power-law kernel |g|^gamma (its derivation uses "
            f"the exponent), got the {self.name} kernel {self!r}; the 'fem' method and "
            f"particles.dsmc (heated states) support it")

    @property
    def is_maxwell(self) -> bool:
        """True for a constant rate (:math:`\\gamma = 0`)."""
        return False

    @property
    def is_hard_rods(self) -> bool:
        """True for :math:`B(g) = |g|` (the paper)."""
        return False

    def weighted_rate(self, g: ArrayLike, power: float) -> NDArray[np.float64]:
        """:math:`B(g)|g|^p` (the energy-loss weight for ``p = 2``).

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
        a = np.abs(np.asarray(g, dtype=float))
        return self.rate(a) * a**power

    def majorant(self, g_max: float) -> float:
        """:math:`\\max_{|g| \\le g_{max}} B(g)`, the DSMC majorant (``B`` is
        non-decreasing: :math:`B(g_{max})`).

        Parameters
        ----------
        g_max : float
            Largest relative speed, >= 0.

        Returns
        -------
        float
        """
        return float(self.rate(g_max))

    def gaussian_mean(self, temperature: float, power: float = 0.0) -> float:
        """:math:`\\langle B(g)|g|^p\\rangle` for two independent Gaussians.

        The relative speed of two velocities of variance :math:`T` is Gaussian with
        variance :math:`2T`; this default integrates numerically
        (:meth:`gaussian_average`), :class:`PowerLawKernel` in closed form.

        Parameters
        ----------
        temperature : float
            Variance :math:`T` of each velocity, > 0.
        power : float
            :math:`p \\ge 0`.

        Returns
        -------
        float
        """
        return self.gaussian_average(temperature, None, power)

    def gaussian_average(self, temperature: float, weight: Callable[[float], float] | None,
                         power: float = 0.0, breaks: Sequence[float] = ()) -> float:
        """:math:`\\langle w(g) B(g) |g|^p\\rangle` over two independent Gaussians.

        Adaptive quadrature (relative accuracy 1e-12) over
        :math:`x = |g|/(2\\sqrt T) \\in [0, 12]`, with the density
        :math:`2e^{-x^2}/\\sqrt\\pi` of :math:`x`.

        Parameters
        ----------
        temperature : float
            Variance :math:`T` of each velocity, > 0.
        weight : callable or None
            :math:`w(g)` of a relative speed :math:`g \\ge 0` (e.g. :math:`1 - \\alpha(g)^2`
            for the energy loss); ``None``: 1.
        power : float
            :math:`p \\ge 0`.
        breaks : sequence of float
            Relative speeds where :math:`w` has a kink or jump.

        Returns
        -------
        float
        """
        scale = 2.0 * math.sqrt(temperature)

        def integrand(x: float) -> float:
            g = scale * x
            w = 1.0 if weight is None else weight(g)
            return w * float(self.rate(g)) * g**power * float(np.exp(-x * x))

        points = [b / scale for b in breaks] or None
        value = quad(integrand, 0.0, 12.0, points=points, epsabs=0.0, epsrel=1e-12,
                     limit=200)[0]
        return 2.0 * value / float(np.sqrt(np.pi))

    def local_exponent(self, temperature: float) -> float:
        """:math:`d\\ln\\langle B\\rangle/d\\ln\\sqrt T` over Gaussians at ``temperature``:
        the exponent of the power law that best matches the kernel at thermal speeds
        (:math:`\\gamma` for a power law).  Scale estimates (relaxation times) use it.

        Parameters
        ----------
        temperature : float
            Temperature, > 0.

        Returns
        -------
        float
        """
        h = 1e-4
        up = self.gaussian_mean(temperature * math.exp(2.0 * h))
        down = self.gaussian_mean(temperature * math.exp(-2.0 * h))
        return math.log(up / down) / (2.0 * h)

    def wkb_action(self, v: ArrayLike) -> NDArray[np.float64]:
        """:math:`S(v) = \\int_0^{|v|}\\sqrt{B(w)}\\,dw`, the far-tail action of a heated
        state at :math:`n = D = 1` under white noise (:math:`P'' \\approx B(v) P`,
        :math:`P \\sim e^{-S}`).

        This default integrates numerically (Gauss-Legendre in :math:`t = \\sqrt w` on
        a grid through the requested points, relative accuracy ~1e-10);
        :class:`PowerLawKernel` has the closed form :math:`\\tfrac{2}{2+\\gamma}|v|^{1+\\gamma/2}`.

        Parameters
        ----------
        v : array_like
            Velocities.

        Returns
        -------
        ndarray
            :math:`S(|v|)`, the shape of ``v``.
        """
        speed = np.abs(np.asarray(v, dtype=float))
        flat = np.sqrt(speed.ravel())
        top = float(flat.max()) if flat.size else 0.0
        grid = np.unique(np.concatenate([[0.0], flat, np.linspace(0.0, top, 257)]))
        nodes, weights = np.polynomial.legendre.leggauss(16)
        mid = 0.5 * (grid[1:] + grid[:-1])
        half = 0.5 * (grid[1:] - grid[:-1])
        t = mid[:, None] + half[:, None] * nodes[None, :]
        pieces = (2.0 * t * np.sqrt(self.rate(t * t))) @ weights * half
        cumulative = np.concatenate([[0.0], np.cumsum(pieces)])
        return cumulative[np.searchsorted(grid, flat)].reshape(speed.shape)

    def relative_speed_rule(self, n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Gauss rule for the relative speed with the weight :math:`B(g)e^{-g^2/4}`
        (Sonine tensors); only power laws have one.

        Parameters
        ----------
        n : int
            Number of nodes.

        Returns
        -------
        g, w : ndarray

        Raises
        ------
        UnsupportedModelError
            Unless the kernel is a power law.
        """
        raise UnsupportedModelError(
            f"the Sonine tensors need a power-law kernel |g|^gamma, got {self!r}; use "
            f"method='fem' or particles.dsmc")


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
