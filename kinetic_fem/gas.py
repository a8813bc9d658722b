"""The one-dimensional inelastic gas and the two problems posed on it.

The gas is a set of equal-mass rods with restitution coefficient
:math:`0 \\le \\alpha < 1` at number density :math:`n`.  A binary collision maps

.. math::

    v_1' + v_2' = v_1 + v_2, \\qquad v_1' - v_2' = -\\alpha (v_1 - v_2),

so that :math:`v_1' = v_1 - \\tfrac{1+\\alpha}{2}(v_1 - v_2)`.  The homogeneous
Boltzmann equation for the velocity distribution :math:`P(v, t)` is

.. math::

    \\partial_t P - D \\partial_v^2 P = Q[P, P],

with :math:`D > 0` for the randomly heated gas (:class:`HeatedProblem`) and
:math:`D = 0` for free cooling (:class:`CoolingProblem`).

Parameters are validated here, where they enter the package; solvers and kernels
below trust them.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

__all__ = [
    "InelasticGas",
    "HeatedProblem",
    "CoolingProblem",
    "check_alpha",
    "check_positive",
    "check_finite_array",
]


def _check_real(name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__} {value!r}")
    value = float(value)
    if math.isnan(value):
        raise ValueError(f"{name} is NaN; a finite real number is required")
    return value


def check_alpha(alpha: object, *, allow_elastic: bool = False) -> float:
    """Validate a restitution coefficient.

    Parameters
    ----------
    alpha : float
        Restitution coefficient.
    allow_elastic : bool
        Accept ``alpha = 1`` (elastic rods: collisions only exchange velocities and
        :math:`P(v, t)` is frozen, claim C17).

    Returns
    -------
    float

    Raises
    ------
    TypeError
        If ``alpha`` is not a real number.
    ValueError
        If ``alpha`` is NaN or outside ``[0, 1)`` (``[0, 1]`` with ``allow_elastic``).

    Examples
    --------
    >>> check_alpha(0.9)
    0.9
    """
    alpha = _check_real("alpha", alpha)
    upper_ok = alpha <= 1.0 if allow_elastic else alpha < 1.0
    if not (alpha >= 0.0 and upper_ok):
        allowed = "[0, 1]" if allow_elastic else "[0, 1)"
        raise ValueError(
            f"restitution coefficient alpha={alpha!r} is outside {allowed}"
            + ("" if allow_elastic or alpha != 1.0 else
               "; alpha = 1 (elastic) has no heated steady state: the energy injected "
               "by the noise is never dissipated")
        )
    return alpha


def check_positive(name: str, value: object) -> float:
    """Validate a strictly positive, finite real parameter.

    Raises
    ------
    TypeError
        If ``value`` is not a real number.
    ValueError
        If ``value`` is NaN, infinite, zero or negative.

    Examples
    --------
    >>> check_positive("density", 2)
    2.0
    """
    value = _check_real(name, value)
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name}={value!r} is not allowed; {name} must be finite and > 0")
    return value


def check_finite_array(name: str, values: object, *, ndim: int | None = None) -> np.ndarray:
    """Return ``values`` as a float array, refusing NaN and infinities.

    Raises
    ------
    ValueError
        If an entry is not finite or the number of dimensions is wrong.
    """
    array = np.asarray(values, dtype=float)
    if ndim is not None and array.ndim != ndim:
        raise ValueError(f"{name} must be a {ndim}-d array, got shape {array.shape}")
    bad = ~np.isfinite(array)
    if bad.any():
        first = int(np.flatnonzero(bad.ravel())[0])
        raise ValueError(
            f"{name} contains {int(bad.sum())} non-finite value(s) (first at flat index "
            f"{first}: {array.ravel()[first]!r}); all entries must be finite"
        )
    return array


@dataclass(frozen=True)
class InelasticGas:
    """A homogeneous one-dimensional gas of inelastic rods.

    Parameters
    ----------
    alpha : float
        Restitution coefficient, ``0 <= alpha < 1``.
    density : float
        Number density :math:`n > 0` (rods per unit length).

    Examples
    --------
    >>> gas = InelasticGas(0.9, density=2.0)
    >>> round(gas.epsilon, 12)
    0.1
    """

    alpha: float
    density: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "alpha", check_alpha(self.alpha))
        object.__setattr__(self, "density", check_positive("density", self.density))

    @property
    def epsilon(self) -> float:
        """Inelasticity :math:`\\varepsilon = 1 - \\alpha`."""
        return 1.0 - self.alpha

    def collide(self, v1: np.ndarray, v2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Post-collision velocities :math:`(v_1', v_2')` of the pairs ``(v1, v2)``.

        Examples
        --------
        >>> InelasticGas(0.5).collide(np.array([1.0]), np.array([-1.0]))
        (array([-0.5]), array([0.5]))
        """
        dv = 0.5 * (1.0 + self.alpha) * (np.asarray(v1) - np.asarray(v2))
        return v1 - dv, v2 + dv


@dataclass(frozen=True)
class HeatedProblem:
    """Steady state of the gas heated by white noise of strength ``diffusion``.

    The noise :math:`\\langle\\eta(t)\\eta(t')\\rangle = 2D\\delta(t-t')` adds
    :math:`D\\partial_v^2 P` to the Boltzmann equation.  Dimensional analysis
    gives every steady state from the one at :math:`n = D = 1`:
    :math:`P_{n,D}(v) = P_{1,1}(v/u)/u` with :math:`u = (D/n)^{1/3}`
    (see :meth:`velocity_scale`).
    """

    gas: InelasticGas
    diffusion: float = 1.0

    def __post_init__(self) -> None:
        if not isinstance(self.gas, InelasticGas):
            raise TypeError(f"gas must be an InelasticGas, got {type(self.gas).__name__}")
        object.__setattr__(self, "diffusion", check_positive("diffusion", self.diffusion))

    @classmethod
    def from_parameters(
        cls, alpha: float, *, density: float = 1.0, diffusion: float = 1.0
    ) -> HeatedProblem:
        """Build the problem from plain numbers, validating each."""
        return cls(InelasticGas(alpha, density), diffusion)

    @property
    def velocity_scale(self) -> float:
        """:math:`u = (D/n)^{1/3}`, the only velocity built from ``D`` and ``n``."""
        return (self.diffusion / self.gas.density) ** (1.0 / 3.0)

    def as_dict(self) -> dict[str, float | str]:
        """Plain parameters, as stored with results."""
        return {"problem": "heated", "alpha": self.gas.alpha, "density": self.gas.density,
                "diffusion": self.diffusion}


@dataclass(frozen=True)
class CoolingProblem:
    """Free cooling: no forcing; the homogeneous cooling state in scaled variables.

    The temperature decays by Haff's law and :math:`f(c) = \\sqrt{T} P(v)` tends to a
    time-independent scaling form.
    """

    gas: InelasticGas

    def __post_init__(self) -> None:
        if not isinstance(self.gas, InelasticGas):
            raise TypeError(f"gas must be an InelasticGas, got {type(self.gas).__name__}")

    @classmethod
    def from_parameters(cls, alpha: float, *, density: float = 1.0) -> CoolingProblem:
        """Build the problem from plain numbers, validating each."""
        return cls(InelasticGas(alpha, density))

    def as_dict(self) -> dict[str, float | str]:
        """Plain parameters, as stored with results."""
        return {"problem": "cooling", "alpha": self.gas.alpha, "density": self.gas.density}
