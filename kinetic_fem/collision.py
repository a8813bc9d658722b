"""Exact moment identities of the inelastic collision operator.

For any test function :math:`\\varphi` the collision operator satisfies the weak form

.. math::

    \\int \\varphi\\, Q[P,P]\\, dv = \\frac n2 \\iint dv_1 dv_2\\, |v_1 - v_2| P(v_1) P(v_2)
    \\left[\\varphi(v_1') + \\varphi(v_2') - \\varphi(v_1) - \\varphi(v_2)\\right].

With :math:`\\varphi = 1, v` the right side vanishes (mass and momentum); with
:math:`\\varphi = v^2`, :math:`v_1'^2 + v_2'^2 - v_1^2 - v_2^2 = -\\tfrac12(1-\\alpha^2)
(v_1-v_2)^2` gives the exact energy balance (claim C1)

.. math::

    \\frac{d\\langle v^2\\rangle}{dt} = 2D - \\frac n4 (1-\\alpha^2)\\langle|v - v'|^3\\rangle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .grid import abs_power_convolution

__all__ = ["pair_moment", "energy_loss_rate", "EnergyBalance", "energy_balance"]


def pair_moment(v: NDArray[np.float64], p: NDArray[np.float64], w: NDArray[np.float64],
                power: int) -> float:
    """:math:`\\langle |v - v'|^{p}\\rangle = \\iint |v-v'|^p P(v)P(v')`, O(N), odd ``power``."""
    wp = np.asarray(w) * np.asarray(p)
    return float(np.sum(wp * abs_power_convolution(v, wp, power)))


def energy_loss_rate(v: NDArray[np.float64], p: NDArray[np.float64], w: NDArray[np.float64],
                     alpha: float, density: float) -> float:
    """Collisional loss :math:`\\tfrac n4 (1-\\alpha^2)\\langle|v-v'|^3\\rangle` by quadrature."""
    return 0.25 * density * (1.0 - alpha**2) * pair_moment(v, p, w, 3)


@dataclass(frozen=True)
class EnergyBalance:
    """Terms of :math:`dT/dt = 2D - \\text{loss}` and the relative imbalance."""

    injection: float
    loss: float

    @property
    def relative_residual(self) -> float:
        """:math:`|2D - \\text{loss}| / 2D` (zero in an exact steady state)."""
        return abs(self.injection - self.loss) / self.injection


def energy_balance(v: NDArray[np.float64], p: NDArray[np.float64], w: NDArray[np.float64], *,
                   alpha: float, density: float, diffusion: float) -> EnergyBalance:
    """Both sides of the steady energy balance C1 for nodal values ``p``."""
    return EnergyBalance(2.0 * diffusion, energy_loss_rate(v, p, w, alpha, density))
