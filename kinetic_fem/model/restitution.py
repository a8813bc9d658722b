"""Restitution laws: the coefficient of restitution as a function of the impact speed.

A binary collision of rods of equal mass with relative velocity :math:`g = v_1 - v_2`
conserves momentum and maps :math:`g \\to -\\alpha(|g|)\\,g`:

.. math::

    v_1' = v_1 - \\tfrac{1+\\alpha(|g|)}{2}\\,g, \\qquad
    v_2' = v_2 + \\tfrac{1+\\alpha(|g|)}{2}\\,g .

Three laws are provided, each a small frozen object that solvers evaluate:

* :class:`ConstantRestitution`: :math:`\\alpha(g) = \\alpha` (the paper);
* :class:`ViscoelasticRestitution`: the law of Brilliantov and Poeschel for
  viscoelastic spheres, to second order in :math:`\\delta g^{1/5}`,
  :math:`\\alpha(g) = 1 - C_1 \\delta g^{1/5} + C_2 \\delta^2 g^{2/5}`,
  so :math:`\\alpha \\to 1` as :math:`g \\to 0`;
* :class:`ThresholdRestitution`: elastic below a relative speed, :math:`\\alpha`
  above (the regularisation of inelastic collapse used in molecular dynamics).

Numba kernels evaluate every law through :func:`restitution_value` with the integer
:attr:`~RestitutionLaw.code` and the two floats :attr:`~RestitutionLaw.parameters`
of the law, so there is one implementation of each law for all methods.

References
----------
N. V. Brilliantov and T. Poeschel, *Kinetic Theory of Granular Gases*, Oxford
University Press (2004), ch. 6; E. Ben-Naim, S. Y. Chen, G. D. Doolen and S. Redner,
Phys. Rev. Lett. 83, 4069 (1999) (the threshold regularisation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._jit import jit
from .validation import check_alpha, check_positive, check_real

__all__ = ["RestitutionLaw", "ConstantRestitution", "ViscoelasticRestitution",
           "ThresholdRestitution", "as_restitution", "restitution_value",
           "CONSTANT", "THRESHOLD", "VISCOELASTIC"]

CONSTANT = 0
THRESHOLD = 1
VISCOELASTIC = 2

#: Brilliantov-Poeschel coefficients of the viscoelastic expansion.
C1 = 1.15344
C2 = 0.798436


@jit
def restitution_value(code: int, p0: float, p1: float, g: float) -> float:
    """:math:`\\alpha(|g|)` of the law ``code`` with parameters ``(p0, p1)``.

    ``CONSTANT``: ``p0 = alpha``; ``THRESHOLD``: ``p0 = alpha``, ``p1`` the threshold
    speed; ``VISCOELASTIC``: ``p0 = delta``.
    """
    if code == CONSTANT:
        return p0
    g = abs(g)
    if code == THRESHOLD:
        return 1.0 if g < p1 else p0
    x = p0 * g ** 0.2
    return 1.0 - C1 * x + C2 * x * x


class RestitutionLaw:
    """Base class of restitution laws :math:`\\alpha(|g|)` with values in [0, 1]."""

    code: int = CONSTANT

    @property
    def parameters(self) -> tuple[float, float]:
        """The two floats the numba kernels take with :attr:`code`."""
        raise NotImplementedError

    @property
    def constant(self) -> float | None:
        """The coefficient if the law is constant, else None."""
        return None

    @property
    def is_elastic(self) -> bool:
        """True if no collision dissipates energy."""
        return False

    @property
    def max_speed(self) -> float:
        """Largest relative speed at which the law is defined (``inf`` if everywhere)."""
        return math.inf

    @property
    def min_alpha(self) -> float:
        """The smallest value of :math:`\\alpha(g)` over the law's range."""
        raise NotImplementedError

    def rescaled(self, u: float) -> RestitutionLaw:
        """The law in velocity units of ``u``: :math:`g \\mapsto \\alpha(u g)`.

        A solver that measures velocities in a unit :math:`V` (the free-cooling transient
        on segments of fixed unit, :mod:`kinetic_fem.solvers.fem.cooling_transient`)
        evaluates ``law.rescaled(V)`` at the relative speeds in that unit; the kernel's
        counterpart is :meth:`kinetic_fem.model.CollisionKernel.rescaled`.

        Parameters
        ----------
        u : float
            Velocity unit, > 0.

        Returns
        -------
        RestitutionLaw
        """
        raise NotImplementedError

    def __call__(self, g: ArrayLike) -> NDArray[np.float64]:
        """:math:`\\alpha(|g|)`, elementwise."""
        speed = np.abs(np.asarray(g, dtype=float))
        p0, p1 = self.parameters
        if self.code == CONSTANT:
            return np.full_like(speed, p0)
        if self.code == THRESHOLD:
            return np.where(speed < p1, 1.0, p0)
        x = p0 * speed**0.2
        return 1.0 - C1 * x + C2 * x * x

    def check_speed(self, g_max: float, where: str = "") -> None:
        """Raise if relative speeds up to ``g_max`` leave the law's range of validity."""
        if g_max > self.max_speed:
            raise ValueError(
                f"{self!r} is defined for relative speeds up to {self.max_speed:.4g} (where "
                f"alpha(g) has its minimum {self.min_alpha:.4g}; beyond, the two-term series "
                f"rises back towards 1 and leaves the law), but {where or 'the problem'} "
                f"reaches g = {g_max:.4g}: use a smaller delta")


@dataclass(frozen=True, repr=True)
class ConstantRestitution(RestitutionLaw):
    """:math:`\\alpha(g) = \\alpha`, ``0 <= alpha <= 1``.

    Parameters
    ----------
    alpha : float
        The coefficient of restitution, ``0 <= alpha <= 1``.

    Examples
    --------
    >>> ConstantRestitution(0.9)([0.5, 2.0])
    array([0.9, 0.9])
    """

    alpha: float

    code = CONSTANT

    def __post_init__(self) -> None:
        object.__setattr__(self, "alpha", check_alpha(self.alpha, allow_elastic=True))

    @property
    def parameters(self) -> tuple[float, float]:
        return (self.alpha, 0.0)

    @property
    def constant(self) -> float | None:
        return self.alpha

    @property
    def is_elastic(self) -> bool:
        return self.alpha == 1.0

    @property
    def min_alpha(self) -> float:
        return self.alpha

    def rescaled(self, u: float) -> ConstantRestitution:
        """The law itself (it does not depend on the speed).

        Parameters
        ----------
        u : float
            Velocity unit, > 0.

        Returns
        -------
        ConstantRestitution
        """
        return self


@dataclass(frozen=True)
class ThresholdRestitution(RestitutionLaw):
    """Elastic below the relative speed ``threshold``, ``alpha`` above.

    Parameters
    ----------
    alpha : float
        Coefficient above the threshold, ``0 <= alpha <= 1``.
    threshold : float
        Relative speed :math:`|g|` (velocity units of the problem) below which collisions
        are elastic, ``> 0``.

    Examples
    --------
    >>> ThresholdRestitution(0.5, threshold=1.0)([0.5, 2.0])
    array([1. , 0.5])
    """

    alpha: float
    threshold: float

    code = THRESHOLD

    def __post_init__(self) -> None:
        object.__setattr__(self, "alpha", check_alpha(self.alpha, allow_elastic=True))
        object.__setattr__(self, "threshold", check_positive("threshold", self.threshold))

    @property
    def parameters(self) -> tuple[float, float]:
        return (self.alpha, self.threshold)

    @property
    def is_elastic(self) -> bool:
        return self.alpha == 1.0

    @property
    def min_alpha(self) -> float:
        return self.alpha

    def rescaled(self, u: float) -> ThresholdRestitution:
        """The threshold in units of ``u``: ``threshold / u``.

        Parameters
        ----------
        u : float
            Velocity unit, > 0.

        Returns
        -------
        ThresholdRestitution

        Examples
        --------
        >>> ThresholdRestitution(0.5, threshold=1.0).rescaled(0.25).threshold
        4.0
        """
        return self if u == 1.0 else ThresholdRestitution(self.alpha, self.threshold / u)


@dataclass(frozen=True)
class ViscoelasticRestitution(RestitutionLaw):
    """Viscoelastic spheres (Brilliantov and Poeschel), to second order.

    .. math::

        \\alpha(g) = 1 - C_1\\,\\delta\\,|g|^{1/5} + C_2\\,\\delta^2 |g|^{2/5},
        \\qquad C_1 = 1.15344,\\ C_2 = 0.798436,

    with :math:`\\delta` (units of speed\\ :sup:`-1/5`) the material parameter
    :math:`A\\kappa^{2/5}` of the theory.  The two-term series decreases from 1 to its
    minimum :math:`1 - C_1^2/(4C_2) = 0.5834` at :math:`g_{max} = (C_1/(2C_2\\delta))^5`
    and is used only below :math:`g_{max}` (:attr:`max_speed`); a problem that
    reaches faster impacts is refused with a message.

    Parameters
    ----------
    delta : float
        The material parameter :math:`\\delta > 0` (units of speed\\ :sup:`-1/5`).

    Examples
    --------
    >>> law = ViscoelasticRestitution(0.1)
    >>> bool(law(1e-8)[()] > 0.97), round(float(law(1.0)[()]), 5)
    (True, 0.89264)
    """

    delta: float

    code = VISCOELASTIC

    def __post_init__(self) -> None:
        object.__setattr__(self, "delta", check_positive("delta", self.delta))

    @property
    def parameters(self) -> tuple[float, float]:
        return (self.delta, 0.0)

    @property
    def max_speed(self) -> float:
        base = C1 / (2.0 * C2 * self.delta)
        return base**5 if base < 1e60 else math.inf  # (delta < 1e-60: no finite limit)

    @property
    def min_alpha(self) -> float:
        return 1.0 - C1 * C1 / (4.0 * C2)

    def rescaled(self, u: float) -> ViscoelasticRestitution:
        """:math:`\\delta u^{1/5}`: :math:`\\delta (ug)^{1/5} = (\\delta u^{1/5}) g^{1/5}`.

        Parameters
        ----------
        u : float
            Velocity unit, > 0.

        Returns
        -------
        ViscoelasticRestitution

        Examples
        --------
        >>> law = ViscoelasticRestitution(0.1)
        >>> bool(abs(law.rescaled(32.0)(1.0)[()] - law(32.0)[()]) < 1e-15)
        True
        """
        return self if u == 1.0 else ViscoelasticRestitution(self.delta * u**0.2)


def as_restitution(alpha: object) -> RestitutionLaw:
    """A restitution law from a float or a law.

    Parameters
    ----------
    alpha : float or RestitutionLaw
        A constant coefficient in [0, 1] or a law (returned as it is).

    Returns
    -------
    RestitutionLaw

    Raises
    ------
    TypeError
        If ``alpha`` is neither a real number nor a :class:`RestitutionLaw`.

    Examples
    --------
    >>> as_restitution(0.5)
    ConstantRestitution(alpha=0.5)
    """
    if isinstance(alpha, RestitutionLaw):
        return alpha
    if isinstance(alpha, str):
        raise TypeError(f"alpha must be a real number (a restitution coefficient in "
                        f"[0, 1]) or a RestitutionLaw, got str {alpha!r}")
    try:
        value = check_real("alpha", alpha)
    except TypeError:
        raise TypeError(f"alpha must be a real number (a restitution coefficient in [0, 1]) "
                        f"or a RestitutionLaw, got {type(alpha).__name__} {alpha!r}") from None
    return ConstantRestitution(value)
