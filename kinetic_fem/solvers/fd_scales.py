"""The heated problem as the finite-difference solver sees it: the unit problem and its scales.

Every heated steady state maps onto one at :math:`n = D = 1`: with
:math:`u = (D/n)^{1/(2+\\gamma)}` and :math:`v = u w`, :math:`t = s/(n u^\\gamma)`,

.. math::

    \\partial_s P = Q_1[P] + \\xi'\\,\\partial_w(w P) + \\partial_w^2 P, \\qquad
    \\xi' = \\frac{\\xi}{n u^\\gamma},

so the solver works with ``(alpha, gamma, xi')`` only.  Its numerical defaults derive
from the model's scales: the grid spacing and the cut-off are given in units of the
estimated thermal speed :math:`\\sqrt{T}`, and the cut-off is where the tail of the
steady state falls below :data:`TAIL_TARGET`:

* hard rods, white noise: the far tail :math:`e^{-\\frac23 v^{3/2}}` (claim C4) or,
  if reached first, the core (the Gaussian or the quasi-elastic :math:`e^{-x^3/6}`,
  claim C5);
* Maxwell kernel, white noise: the loss frequency is :math:`n`, so
  :math:`D P'' \\approx n P` gives the exponential tail :math:`e^{-v}`; the core is
  Gaussian;
* Fokker-Planck bath: the friction adds the Gaussian :math:`e^{-\\xi' v^2/2}` of the
  bath temperature, which bounds the cut-off from above.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..model import HeatedProblem
from ..operators.collision import kernel_power
from ..sonine import relaxation_time, steady_temperature

__all__ = ["TAIL_TARGET", "UnitModel", "default_cutoff"]

TAIL_TARGET = 1e-60
"""Value of f(c) at the default cut-off."""


@dataclass(frozen=True)
class UnitModel:
    """The unit problem ``n = D = 1`` of a heated problem and its scales.

    Attributes
    ----------
    alpha : float
        Constant restitution coefficient.
    gamma : float
        Kernel exponent, 1 (hard rods) or 0 (Maxwell).
    friction : float
        :math:`\\xi' = \\xi/(n u^\\gamma)` (0 for white noise).
    temperature : float
        Estimate of the steady temperature (unit problem): first-order Sonine for hard
        rods under white noise (the paper's scale, unchanged), otherwise the Gaussian
        closure of the energy balance (:meth:`HeatedProblem.temperature_estimate`;
        exact for the Maxwell kernel).
    relaxation_time : float
        Time scale of the stopping criterion of the time marching:
        :func:`kinetic_fem.sonine.relaxation_time` for hard rods under white noise,
        otherwise the estimated temperature over :math:`D = 1`.
    """

    alpha: float
    gamma: float
    friction: float
    temperature: float
    relaxation_time: float

    @classmethod
    def from_problem(cls, problem: HeatedProblem) -> UnitModel:
        """The unit problem of ``problem`` (constant restitution, gamma 0 or 1)."""
        alpha = problem.gas.alpha
        gamma = problem.gas.gamma
        kernel_power(gamma)
        u = problem.velocity_scale
        xi = problem.friction / (problem.gas.density * u**gamma)
        if gamma == 1.0 and xi == 0.0:
            return cls(alpha, gamma, 0.0, steady_temperature(alpha), relaxation_time(alpha))
        unit = HeatedProblem.from_parameters(alpha, density=1.0, diffusion=1.0, friction=xi,
                                             kernel=gamma)
        temperature = unit.temperature_estimate()
        return cls(alpha, gamma, xi, temperature, temperature)

    def spacing(self) -> float:
        """Default coarsest spacing (units of :math:`\\sqrt{T}`) of the extrapolated solve.

        0.08; for hard rods under white noise near elastic collisions the core
        :math:`e^{-x^3/6}`, :math:`x = \\varepsilon^{1/3} v`, steepens the tail, so
        :math:`0.2\\,\\varepsilon^{1/3}` (0.043 at alpha = 0.99), never below 0.02
        (the grid of spacing/4 has ~2400 nodes there).

        Examples
        --------
        >>> [round(UnitModel(a, 1.0, 0.0, 1.0, 1.0).spacing(), 3) for a in (0.5, 0.99, 0.999)]
        [0.08, 0.043, 0.02]
        """
        if self.gamma == 1.0 and self.friction == 0.0 and self.alpha < 1.0:
            return min(0.08, max(0.02, 0.2 * (1.0 - self.alpha) ** (1.0 / 3.0)))
        return 0.08

    def cutoff(self) -> float:
        """Default cut-off in units of :math:`\\sqrt{T}` (module docstring).

        Examples
        --------
        >>> round(UnitModel(0.5, 0.0, 0.0, 16 / 3, 16 / 3).cutoff(), 1)  # Maxwell
        59.8
        """
        s = math.sqrt(self.temperature)
        log_target = -math.log(TAIL_TARGET)
        gauss = math.sqrt(2.0 * log_target)
        if self.gamma == 1.0:
            tail = (log_target / (2.0 / 3.0 * self.temperature**0.75)) ** (2.0 / 3.0)
            if self.friction == 0.0 and self.alpha < 1.0:
                x_core = (6.0 * log_target) ** (1.0 / 3.0)
                quasi_elastic = 1.25 * x_core / ((1.0 - self.alpha) ** (1.0 / 3.0) * s)
                core = min(gauss, quasi_elastic)
            else:
                core = gauss
        else:
            tail, core = log_target / s, gauss
        white = max(tail, core)
        if self.friction > 0.0:
            bath = math.sqrt(2.0 * log_target / (self.friction * self.temperature))
            return max(min(white, bath), gauss)
        return white


def default_cutoff(alpha: float) -> float:
    """Cut-off in units of :math:`\\sqrt{T}` where f(c) is below about 1e-60 (hard rods,
    white noise).

    The far tail :math:`e^{-A_c c^{3/2}}` (claim C4, :math:`A_c = \\tfrac23 T^{3/4}` at
    ``n = D = 1``) or, if that is reached first, the core: the smaller of the Gaussian
    :math:`e^{-c^2/2}` and the quasi-elastic :math:`e^{-x^3/6}` (claim C5,
    :math:`x = \\varepsilon^{1/3} v`, with a margin of 1.25 for the crossover).  The
    quasi-elastic estimate keeps the cut-off short of double-precision underflow as
    :math:`\\alpha \\to 1`.

    Examples
    --------
    >>> [round(default_cutoff(a), 1) for a in (0.0, 0.9, 0.99, 0.9999)]
    [29.2, 16.6, 12.1, 12.1]
    """
    return UnitModel(alpha, 1.0, 0.0, steady_temperature(alpha),
                     relaxation_time(alpha)).cutoff()
