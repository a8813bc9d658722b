"""Analytic results of kinetic theory for the 1D inelastic gas.

First-order Sonine theory (van Noije and Ernst 1998) in one dimension gives the
kurtosis coefficient of the heated steady state

.. math::

    a_2 = \\frac{16 (1 - 2\\alpha^2)}{129 + 30\\alpha^2}, \\qquad
    a_2 \\to -\\frac{16}{159} \\ (\\alpha \\to 1).

The exact energy balance (claim C1)

.. math::

    \\frac{dT}{dt} = 2D - \\frac{n}{4}(1-\\alpha^2)\\langle |v - v'|^3 \\rangle

with :math:`\\langle|v-v'|^3\\rangle = (8/\\sqrt{\\pi})\\, T^{3/2} (1 + 3a_2/16)` to first
order in :math:`a_2` gives the steady temperature, the relaxation time and, for
:math:`D = 0`, Haff's law.  At large velocity the heated distribution decays as
:math:`\\exp(-\\tfrac23\\sqrt{n/D}\\,|v|^{3/2})` for any :math:`\\varepsilon > 0` (C4).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .gas import check_alpha, check_positive

__all__ = [
    "a2_first_order",
    "A2_ELASTIC_LIMIT",
    "relative_speed_cubed",
    "steady_temperature",
    "relaxation_time",
    "tail_exponent_amplitude",
    "crossover_velocities",
    "haff_temperature",
]

A2_ELASTIC_LIMIT = -16.0 / 159.0
"""Limit of :func:`a2_first_order` as alpha -> 1."""


def a2_first_order(alpha: ArrayLike) -> NDArray[np.float64] | float:
    """First-order Sonine kurtosis coefficient of the heated 1D gas.

    Parameters
    ----------
    alpha : float or array_like
        Restitution coefficient(s) in ``[0, 1]``.

    Examples
    --------
    >>> round(a2_first_order(0.0), 6)
    0.124031
    >>> bool(abs(a2_first_order(1.0) - A2_ELASTIC_LIMIT) < 1e-15)
    True
    """
    a = np.asarray(alpha, dtype=float)
    if np.any(~np.isfinite(a)) or np.any((a < 0) | (a > 1)):
        raise ValueError(f"alpha must lie in [0, 1], got {alpha!r}")
    out = 16.0 * (1.0 - 2.0 * a**2) / (129.0 + 30.0 * a**2)
    return float(out) if out.ndim == 0 else out


def relative_speed_cubed(temperature: float, a2: float = 0.0) -> float:
    """:math:`\\langle |v - v'|^3\\rangle = (8/\\sqrt\\pi) T^{3/2}(1 + 3a_2/16)`.

    Exact for a Gaussian (``a2 = 0``); first order in ``a2`` otherwise.
    """
    return 8.0 / math.sqrt(math.pi) * temperature**1.5 * (1.0 + 3.0 * a2 / 16.0)


def steady_temperature(alpha: float, density: float = 1.0, diffusion: float = 1.0,
                       a2: float | None = None) -> float:
    """Heated steady temperature from the energy balance C1 (first-order Sonine).

    :math:`T^{3/2} = \\sqrt\\pi D / (n (1-\\alpha^2)(1 + 3a_2/16))` with ``a2``
    defaulting to :func:`a2_first_order`.
    """
    alpha = check_alpha(alpha)
    n = check_positive("density", density)
    d = check_positive("diffusion", diffusion)
    a2 = a2_first_order(alpha) if a2 is None else a2
    return (math.sqrt(math.pi) * d / (n * (1 - alpha**2) * (1 + 3 * a2 / 16))) ** (2.0 / 3.0)


def relaxation_time(alpha: float, density: float = 1.0, diffusion: float = 1.0) -> float:
    """Relaxation-time scale of the heated gas (claim C2).

    :math:`\\tau = [D/(n(1-\\alpha^2))]^{2/3} / D`, the time the noise takes to
    inject the steady temperature.  The paper writes :math:`[D/(n(1-\\alpha^2))]^{2/3}`,
    which is a temperature, not a time; the two agree at ``D = 1`` and both scale as
    :math:`\\varepsilon^{-2/3}`.
    """
    alpha = check_alpha(alpha)
    n = check_positive("density", density)
    d = check_positive("diffusion", diffusion)
    return (d / (n * (1 - alpha**2))) ** (2.0 / 3.0) / d


def tail_exponent_amplitude(density: float = 1.0, diffusion: float = 1.0,
                            temperature: float | None = None) -> float:
    """Amplitude ``A`` of the far tail :math:`\\ln P \\sim -A |v|^{3/2}` (claim C4).

    :math:`A = \\tfrac23\\sqrt{n/D}` in ``v``; with ``temperature`` given, the amplitude
    in the scaled velocity ``c``, :math:`A_c = A\\,T^{3/4}`.
    """
    n = check_positive("density", density)
    d = check_positive("diffusion", diffusion)
    a = 2.0 / 3.0 * math.sqrt(n / d)
    return a if temperature is None else a * check_positive("temperature", temperature) ** 0.75


def crossover_velocities(alpha: float, density: float = 1.0,
                         diffusion: float = 1.0) -> tuple[float, float]:
    """Crossovers :math:`v_{cr}^{(1)} = (D/n\\varepsilon)^{1/3}`, :math:`v_{cr}^{(2)} =
    (D/n\\varepsilon^2)^{1/3}` (claim C6), as order-of-magnitude scales."""
    alpha = check_alpha(alpha)
    n = check_positive("density", density)
    d = check_positive("diffusion", diffusion)
    eps = 1.0 - alpha
    return (d / (n * eps)) ** (1 / 3), (d / (n * eps**2)) ** (1 / 3)


def haff_temperature(t: ArrayLike, alpha: float, density: float = 1.0,
                     temperature0: float = 1.0, a2: float = 0.0) -> NDArray[np.float64]:
    """Haff's law for the homogeneous cooling gas.

    :math:`T(t) = T_0 / (1 + t/t_0)^2`, :math:`t_0^{-1} = \\tfrac{n}{\\sqrt\\pi}
    (1-\\alpha^2)\\sqrt{T_0}(1 + 3a_2/16)`, from
    :math:`dT/dt = -\\tfrac n4 (1-\\alpha^2)\\langle|v-v'|^3\\rangle` at fixed shape.
    """
    alpha = check_alpha(alpha)
    n = check_positive("density", density)
    t0 = check_positive("temperature0", temperature0)
    rate = n / math.sqrt(math.pi) * (1 - alpha**2) * math.sqrt(t0) * (1 + 3 * a2 / 16)
    return t0 / (1.0 + rate * np.asarray(t, dtype=float)) ** 2
