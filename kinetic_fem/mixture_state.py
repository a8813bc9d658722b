"""The moment-level result of a mixture solve: species temperatures, ratios, kurtosis.

A :class:`MixtureMoments` holds what every mixture method reports: the kinetic temperature
:math:`T_s = m_s\\langle v^2\\rangle_s` of each species, the mixture temperature
:math:`T = \\sum_s x_s T_s`, the kurtosis coefficient
:math:`a_{2,s} = \\langle v^4\\rangle_s/(3\\langle v^2\\rangle_s^2) - 1` where the method
gives it, and in free cooling the common cooling rate :math:`\\zeta` of the convention
:math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}` (reported at :math:`T = 1`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .distribution import VelocityDistribution
from .mixture_error import MixtureError
from .model.mixture import Mixture

__all__ = ["MixtureMoments", "MixtureState", "SpeciesTemperatures"]


class SpeciesTemperatures:
    """The observables every mixture result derives from its species temperatures.

    Subclasses hold ``mixture`` and define ``temperatures`` (:math:`T_s`, shape (k,)).
    """

    mixture: Mixture

    @property
    def temperatures(self) -> NDArray[np.float64]:
        """:math:`T_s = m_s \\langle v^2\\rangle_s`, shape (k,)."""
        raise NotImplementedError

    @property
    def temperature(self) -> float:
        """The mixture temperature :math:`T = \\sum_s x_s T_s`."""
        return float(np.dot(self.mixture.fractions, self.temperatures))

    def temperature_ratio(self, s: int = 0, r: int = 1) -> float:
        """:math:`T_s / T_r` (default: the first species over the second)."""
        temps = self.temperatures
        return float(temps[s] / temps[r])


@dataclass(frozen=True, eq=False)
class MixtureMoments(SpeciesTemperatures):
    """Species temperatures and moments of a steady or scaling state of a mixture.

    Parameters
    ----------
    mixture : Mixture
        The model solved.
    density : float
        Total number density :math:`n`.
    moments : ndarray, shape (k, K + 1)
        :math:`\\langle v^j\\rangle_s`, ``j = 0 .. K``; ``inf`` where a moment diverges
        (a power-law tail), ``nan`` where the method does not give it.
    method : str
        How the state was computed (``"maxwell-exact"``, ``"gaussian"``, ...).
    zeta : float or None
        The cooling rate in free cooling (the state is scaled to :math:`T = 1`), else None.
    info : dict
        Method details.
    """

    mixture: Mixture
    density: float
    moments: NDArray[np.float64]
    method: str
    zeta: float | None = None
    info: dict[str, Any] = field(default_factory=dict)

    @property
    def temperatures(self) -> NDArray[np.float64]:
        """:math:`T_s = m_s \\langle v^2\\rangle_s`, shape (k,)."""
        return np.asarray(self.mixture.masses) * self.moments[:, 2]


    @property
    def a2(self) -> NDArray[np.float64]:
        """The kurtosis coefficients :math:`a_{2,s}`, shape (k,).

        :math:`a_{2,s} = \\langle v^4\\rangle_s / (3\\langle v^2\\rangle_s^2) - 1`.
        """
        if self.moments.shape[1] <= 4:
            return np.full(self.mixture.n_species, np.nan)
        m2, m4 = self.moments[:, 2], self.moments[:, 4]
        return m4 / (3.0 * m2**2) - 1.0

    def __repr__(self) -> str:
        ratio = ", ".join(f"{t:.6g}" for t in self.temperatures)
        zeta = "" if self.zeta is None else f", zeta={self.zeta:.6g}"
        return (f"MixtureMoments(method={self.method!r}, T_s=[{ratio}], "
                f"a2={np.array2string(self.a2, precision=6)}{zeta})")


@dataclass(frozen=True, eq=False)
class MixtureState(SpeciesTemperatures):
    """A steady or scaling state of a mixture with one velocity distribution per species.

    Parameters
    ----------
    mixture : Mixture
        The model solved.
    density : float
        Total number density :math:`n`.
    distributions : tuple of VelocityDistribution, shape (k,)
        :math:`P_s(v)` of each species (physical velocities; scaled to the mixture
        temperature :math:`T = 1` in free cooling).
    method : str
        How the state was computed (``"fem"``).
    zeta : float or None
        The common cooling rate in free cooling, else None.
    info : RunInfo or None
        Convergence and cost of the solve.
    error_recipe : MixtureErrorRecipe, optional
        How the solver estimates the state's errors when :attr:`error` is first read
        (:mod:`kinetic_fem.mixture_error`).
    """

    mixture: Mixture
    density: float
    distributions: tuple[VelocityDistribution, ...]
    method: str
    zeta: float | None = None
    info: Any = None
    error_recipe: Any = field(default=None, repr=False, compare=False)

    @cached_property
    def error(self) -> MixtureError:
        """Estimated errors: each species' (as ``distributions[s].error``), the
        temperature ratios', the mixture temperature's and the cooling rate's
        (:class:`~kinetic_fem.mixture_error.MixtureError`), computed on first read."""
        if self.error_recipe is not None:
            return self.error_recipe()
        return MixtureError.unavailable(
            self.mixture.n_species, f"no error estimate for this state (method "
            f"{self.method!r}): only solvers' results carry one")

    @property
    def temperatures(self) -> NDArray[np.float64]:
        """:math:`T_s = m_s \\langle v^2\\rangle_s`, shape (k,)."""
        return np.asarray(self.mixture.masses) * np.array(
            [d.moment(2, central=False) for d in self.distributions])

    @property
    def a2(self) -> NDArray[np.float64]:
        """The kurtosis coefficients :math:`a_{2,s}`, shape (k,)."""
        return np.array([d.a2 for d in self.distributions])

    def moments(self, order: int = 4) -> MixtureMoments:
        """The :class:`MixtureMoments` of the state up to ``order``.

        Parameters
        ----------
        order : int
            Highest moment :math:`\\langle v^j\\rangle_s`, ``j = 0 .. order``.
        """
        values = np.array([[d.moment(j, central=False) for j in range(order + 1)]
                           for d in self.distributions])
        return MixtureMoments(self.mixture, self.density, values, self.method, zeta=self.zeta)

    def __repr__(self) -> str:
        temps = ", ".join(f"{t:.6g}" for t in self.temperatures)
        zeta = "" if self.zeta is None else f", zeta={self.zeta:.6g}"
        return (f"MixtureState(method={self.method!r}, T_s=[{temps}], "
                f"a2={np.array2string(self.a2, precision=6)}{zeta})")
