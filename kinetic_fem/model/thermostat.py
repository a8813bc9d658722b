"""Thermostats: how energy is fed to the gas.

Three forcings of the homogeneous Boltzmann equation
:math:`\\partial_t P = Q[P] + \\mathcal{F}[P]`:

* :class:`WhiteNoise`: random kicks of strength :math:`D`,
  :math:`\\mathcal F = D\\,\\partial_v^2 P` (the paper);
* :class:`FokkerPlanckBath`: a Langevin bath with friction :math:`\\xi` and
  diffusion :math:`D`, :math:`\\mathcal F = \\partial_v(\\xi v P) + D\\,\\partial_v^2 P`;
  without collisions it relaxes to the Gaussian at the bath temperature
  :math:`T_b = D/\\xi` (the elastic limit);
* :class:`NoThermostat`: free cooling, studied in scaled variables.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .validation import check_nonnegative, check_positive

__all__ = ["Thermostat", "WhiteNoise", "FokkerPlanckBath", "NoThermostat", "as_thermostat"]


class Thermostat:
    """Base class of the forcings."""

    @property
    def diffusion(self) -> float:
        """:math:`D` (0 for free cooling)."""
        return 0.0

    @property
    def friction(self) -> float:
        """:math:`\\xi` (0 without a bath)."""
        return 0.0

    @property
    def drives(self) -> bool:
        """True if the forcing injects energy (a steady state can exist)."""
        return self.diffusion > 0.0

    @property
    def bath_temperature(self) -> float:
        """:math:`D/\\xi` (``inf`` without friction)."""
        return self.diffusion / self.friction if self.friction > 0 else math.inf

    def energy_input(self, temperature: float) -> float:
        """:math:`d\\langle v^2\\rangle/dt` due to the forcing: :math:`2D - 2\\xi T`."""
        return 2.0 * self.diffusion - 2.0 * self.friction * temperature


@dataclass(frozen=True)
class WhiteNoise(Thermostat):
    """White-noise heating :math:`D\\,\\partial_v^2 P` (the paper).

    Parameters
    ----------
    strength : float
        The diffusion coefficient :math:`D > 0` of :math:`D\\,\\partial_v^2 P`
        (velocity\\ :sup:`2` per unit time).

    Examples
    --------
    >>> WhiteNoise(2.0).energy_input(1.0)
    4.0
    """

    strength: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "strength", check_positive("diffusion", self.strength))

    @property
    def diffusion(self) -> float:
        return self.strength


@dataclass(frozen=True)
class FokkerPlanckBath(Thermostat):
    """Langevin bath :math:`\\partial_v(\\xi v P) + D\\,\\partial_v^2 P`.

    Parameters
    ----------
    friction : float
        :math:`\\xi > 0` (inverse time).
    strength : float
        :math:`D > 0`; the bath temperature is :math:`D/\\xi`.

    Examples
    --------
    >>> FokkerPlanckBath(0.5, 1.0).bath_temperature
    2.0
    """

    friction_rate: float = 1.0
    strength: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "friction_rate", check_positive("friction", self.friction_rate))
        object.__setattr__(self, "strength", check_positive("diffusion", self.strength))

    @property
    def diffusion(self) -> float:
        return self.strength

    @property
    def friction(self) -> float:
        return self.friction_rate


@dataclass(frozen=True)
class NoThermostat(Thermostat):
    """No forcing: free cooling (the homogeneous cooling state in scaled variables)."""


def as_thermostat(diffusion: float, friction: float = 0.0) -> Thermostat:
    """The thermostat of plain parameters: white noise if ``friction == 0``, else a bath.

    Parameters
    ----------
    diffusion : float
        Diffusion coefficient :math:`D > 0`.
    friction : float
        Friction rate :math:`\\xi \\ge 0` of the bath (0: white noise).

    Returns
    -------
    Thermostat
        :class:`WhiteNoise` or :class:`FokkerPlanckBath`.

    Raises
    ------
    ValueError
        If ``diffusion <= 0`` or ``friction < 0``.

    Examples
    --------
    >>> as_thermostat(1.0)
    WhiteNoise(strength=1.0)
    >>> as_thermostat(1.0, friction=2.0)
    FokkerPlanckBath(friction_rate=2.0, strength=1.0)
    """
    xi = check_nonnegative("friction", friction)
    d = check_positive("diffusion", diffusion)
    return FokkerPlanckBath(xi, d) if xi > 0.0 else WhiteNoise(d)
