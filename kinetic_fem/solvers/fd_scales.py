"""The heated problem as the finite-difference solver sees it: the unit problem and its scales.

Every heated steady state maps onto one at :math:`n = D = 1`: with
:math:`u = (D/n)^{1/(2+\\gamma)}` and :math:`v = u w`, :math:`t = s/(n u^\\gamma)`,

.. math::

    \\partial_s P = Q_1[P] + \\xi'\\,\\partial_w(w P) + \\partial_w^2 P, \\qquad
    \\xi' = \\frac{\\xi}{n u^\\gamma},

so the solver works with ``(alpha, gamma, xi')`` only.  Its numerical defaults derive
from the model's scales (:mod:`kinetic_fem.model.scales`, which owns the rule): the grid
spacing and the cut-off are given in units of the estimated thermal speed
:math:`\\sqrt{T}`, and the cut-off is where the tail of the steady state falls below
:data:`TAIL_TARGET`:

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

from dataclasses import dataclass

from ..model import HeatedProblem, as_kernel
from ..model.scales import TAIL_TARGET, ModelScales, heated_cutoff
from ..operators.collision import kernel_power
from ..sonine import relaxation_time

__all__ = ["TAIL_TARGET", "UnitModel", "default_cutoff"]


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
        """The unit problem of ``problem`` (constant restitution, gamma 0 or 1).

        Parameters
        ----------
        problem : HeatedProblem
            The heated problem; the scales are those of
            :meth:`kinetic_fem.model.scales.ModelScales.from_problem`.

        Returns
        -------
        UnitModel
        """
        kernel_power(problem.gas.gamma)
        s = ModelScales.from_problem(problem)
        hard_rods_white = s.gamma == 1.0 and s.friction == 0.0
        tau = relaxation_time(s.alpha) if hard_rods_white else s.temperature
        return cls(s.alpha, s.gamma, s.friction, s.temperature, tau)

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

    def scales(self) -> ModelScales:
        """The model's scales of this unit problem (:mod:`kinetic_fem.model.scales`)."""
        return ModelScales(self.alpha, as_kernel(self.gamma), self.friction, self.temperature)

    def cutoff(self) -> float:
        """Default cut-off in units of :math:`\\sqrt{T}`: the model's rule
        (:meth:`kinetic_fem.model.scales.ModelScales.cutoff`) at :data:`TAIL_TARGET`.

        Examples
        --------
        >>> round(UnitModel(0.5, 0.0, 0.0, 16 / 3, 16 / 3).cutoff(), 1)  # Maxwell
        59.8
        """
        return self.scales().cutoff(TAIL_TARGET)


def default_cutoff(alpha: float) -> float:
    """Cut-off in units of :math:`\\sqrt{T}` where f(c) is below about 1e-60 (hard rods,
    white noise): :func:`kinetic_fem.model.scales.heated_cutoff`.

    Parameters
    ----------
    alpha : float
        Constant restitution coefficient.

    Returns
    -------
    float

    Examples
    --------
    >>> [round(default_cutoff(a), 1) for a in (0.0, 0.9, 0.99, 0.9999)]
    [29.2, 16.6, 12.1, 12.1]
    """
    return heated_cutoff(alpha, TAIL_TARGET)
