"""The kernel base class: the questions every method asks of a collision kernel.

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

* :class:`~kinetic_fem.model.kernel.PowerLawKernel`, :math:`B(g) = |g|^\\gamma` with
  :math:`0 \\le \\gamma \\le 2`: :math:`\\gamma = 1` are hard rods (the paper, and the
  default), :math:`\\gamma = 0` the inelastic Maxwell model (a collision rate independent
  of the relative speed), anything between "variable hard rods";
* :class:`~kinetic_fem.model.kernel_saturating.SaturatingKernel`,
  :math:`B(g) = |g|/(1 + |g|/g_0)`: hard rods at small relative speeds, a Maxwell
  (constant) rate :math:`g_0` at large ones; not homogeneous.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import quad

from .validation import UnsupportedModelError

__all__ = ["CollisionKernel", "FAMILY_POWER_LAW", "FAMILY_SATURATING"]

FAMILY_POWER_LAW = 0
"""Family code of :class:`~kinetic_fem.model.kernel.PowerLawKernel` in
:attr:`CollisionKernel.numeric` (parameter: ``gamma``)."""
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
        acceptance (:func:`particles._dsmc_model.kernel_model`) dispatch on it."""

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
        (:meth:`gaussian_average`), :class:`~kinetic_fem.model.kernel.PowerLawKernel` in
        closed form.

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
        :class:`~kinetic_fem.model.kernel.PowerLawKernel` has the closed form
        :math:`\\tfrac{2}{2+\\gamma}|v|^{1+\\gamma/2}`.

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
