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
from collections.abc import Sequence
from fractions import Fraction
from functools import lru_cache

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
    "sonine_norm",
    "sonine_polynomial_coefficients",
    "sonine_coefficients_from_moments",
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

    Parameters
    ----------
    temperature : float
        Temperature ``T``.
    a2 : float
        First Sonine coefficient.

    Returns
    -------
    float
    """
    return 8.0 / math.sqrt(math.pi) * temperature**1.5 * (1.0 + 3.0 * a2 / 16.0)


def steady_temperature(alpha: float, density: float = 1.0, diffusion: float = 1.0,
                       a2: float | None = None) -> float:
    """Heated steady temperature from the energy balance C1 (first-order Sonine).

    :math:`T^{3/2} = \\sqrt\\pi D / (n (1-\\alpha^2)(1 + 3a_2/16))` with ``a2``
    defaulting to :func:`a2_first_order`.

    Parameters
    ----------
    alpha : float
        Coefficient of restitution, ``0 <= alpha < 1``.
    density : float
        Number density ``n``.
    diffusion : float
        White-noise strength ``D``.
    a2 : float, optional
        First Sonine coefficient (default: :func:`a2_first_order`).

    Returns
    -------
    float
    """
    alpha = check_alpha(alpha)
    n = check_positive("density", density)
    d = check_positive("diffusion", diffusion)
    a2_value = float(a2_first_order(alpha)) if a2 is None else a2
    return (math.sqrt(math.pi) * d / (n * (1 - alpha**2) * (1 + 3 * a2_value / 16))) ** (2.0 / 3.0)


def relaxation_time(alpha: float, density: float = 1.0, diffusion: float = 1.0) -> float:
    """Relaxation-time scale of the heated gas (claim C2).

    :math:`\\tau = [D/(n(1-\\alpha^2))]^{2/3} / D`, the time the noise takes to
    inject the steady temperature.  The paper writes :math:`[D/(n(1-\\alpha^2))]^{2/3}`,
    which is a temperature, not a time; the two agree at ``D = 1`` and both scale as
    :math:`\\varepsilon^{-2/3}`.

    Parameters
    ----------
    alpha : float
        Coefficient of restitution, ``0 <= alpha < 1``.
    density : float
        Number density ``n``.
    diffusion : float
        White-noise strength ``D``.

    Returns
    -------
    float
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

    Parameters
    ----------
    density : float
        Number density ``n``.
    diffusion : float
        White-noise strength ``D``.
    temperature : float, optional
        Steady temperature; given, the amplitude in the scaled velocity is returned.

    Returns
    -------
    float
    """
    n = check_positive("density", density)
    d = check_positive("diffusion", diffusion)
    a = 2.0 / 3.0 * math.sqrt(n / d)
    return a if temperature is None else a * check_positive("temperature", temperature) ** 0.75


def crossover_velocities(alpha: float, density: float = 1.0,
                         diffusion: float = 1.0) -> tuple[float, float]:
    """Crossovers :math:`v_{cr}^{(1)} = (D/n\\varepsilon)^{1/3}`, :math:`v_{cr}^{(2)} =
    (D/n\\varepsilon^2)^{1/3}` (claim C6), as order-of-magnitude scales.

    Parameters
    ----------
    alpha : float
        Coefficient of restitution, ``0 <= alpha < 1``.
    density : float
        Number density ``n``.
    diffusion : float
        White-noise strength ``D``.

    Returns
    -------
    tuple of float
        The two crossover velocities (physical units).
    """
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

    Parameters
    ----------
    t : array_like
        Times (physical units).
    alpha : float
        Coefficient of restitution, ``0 <= alpha < 1``.
    density : float
        Number density ``n``.
    temperature0 : float
        Temperature at ``t = 0``.
    a2 : float
        Sonine coefficient of the cooling state (0: Gaussian).

    Returns
    -------
    ndarray
        ``T(t)``, the shape of ``t``.
    """
    alpha = check_alpha(alpha)
    n = check_positive("density", density)
    t0 = check_positive("temperature0", temperature0)
    rate = n / math.sqrt(math.pi) * (1 - alpha**2) * math.sqrt(t0) * (1 + 3 * a2 / 16)
    return t0 / (1.0 + rate * np.asarray(t, dtype=float)) ** 2


@lru_cache(maxsize=None)
def sonine_norm(p: int) -> Fraction:
    """:math:`N_p = \\int \\Phi(c) S_p(c^2/2)^2 dc = \\Gamma(p+1/2)/(\\sqrt\\pi\\, p!)`, exactly.

    :math:`\\Phi` is the unit Gaussian and :math:`S_p = L_p^{(-1/2)}` the Sonine
    (generalised Laguerre) polynomial in :math:`x = c^2/2`.

    Examples
    --------
    >>> sonine_norm(0), sonine_norm(1), sonine_norm(2)
    (Fraction(1, 1), Fraction(1, 2), Fraction(3, 8))
    """
    out = Fraction(1)
    for i in range(p):
        out *= Fraction(2 * i + 1, 2 * (i + 1))
    return out


@lru_cache(maxsize=None)
def sonine_polynomial_coefficients(p: int) -> tuple[Fraction, ...]:
    """Exact coefficients of :math:`S_p(x) = L_p^{(-1/2)}(x) = \\sum_m s_{p,m} x^m`.

    :math:`s_{p,m} = (-1)^m \\Gamma(p+1/2) / (\\Gamma(m+1/2)\\,(p-m)!\\,m!)`, lowest
    power first (the distribution's :math:`x = c^2/2`).

    Examples
    --------
    >>> [str(s) for s in sonine_polynomial_coefficients(2)]  # 3/8 - 3x/2 + x^2/2
    ['3/8', '-3/2', '1/2']
    """
    if isinstance(p, bool) or not isinstance(p, int) or p < 0:
        raise ValueError(f"Sonine order p must be an integer >= 0, got {p!r}")
    out = []
    for m in range(p + 1):
        ratio = Fraction(1)  # Gamma(p + 1/2) / Gamma(m + 1/2)
        for i in range(m, p):
            ratio *= Fraction(2 * i + 1, 2)
        out.append((-1) ** m * ratio / (math.factorial(p - m) * math.factorial(m)))
    return tuple(out)


def sonine_coefficients_from_moments(moments: Sequence[Fraction | float | int],
                                     order: int) -> list[Fraction] | NDArray[np.float64]:
    """Sonine coefficients :math:`a_0 .. a_P` of a distribution from its scaled moments.

    :math:`a_p = N_p^{-1}\\sum_m s_{p,m}\\,\\mu_{2m}/2^m` with
    :math:`\\mu_k = \\langle c^k\\rangle` the moments in units of the thermal speed
    (:math:`\\mu_0 = \\mu_2 = 1`).  The alternating sum cancels heavily at high order
    (terms grow like :math:`p!` while :math:`a_p` stays moderate), so pass
    :class:`~fractions.Fraction` moments to get exact coefficients; float moments are
    accepted and give float coefficients (accurate only at low order).

    Parameters
    ----------
    moments : sequence, length >= 2 * order + 1
        :math:`\\mu_0, \\mu_1, \\dots` (odd entries are ignored).
    order : int
        Highest Sonine order :math:`P`.

    Returns
    -------
    list of Fraction (exact input) or ndarray, shape (order + 1,)

    Examples
    --------
    >>> gauss = [1, 0, 1, 0, 3, 0, 15]          # a unit Gaussian: a_p = 0, p >= 1
    >>> [int(a) for a in sonine_coefficients_from_moments(gauss, 3)]
    [1, 0, 0, 0]
    """
    if len(moments) < 2 * order + 1:
        raise ValueError(f"order {order} needs the moments up to {2 * order}, got "
                         f"{len(moments)} moments")
    exact = all(isinstance(m, (Fraction, int)) for m in moments[: 2 * order + 1])
    out = []
    for p in range(order + 1):
        s = sonine_polynomial_coefficients(p)
        if exact:
            total = sum((s[m] * Fraction(moments[2 * m]) / 2**m for m in range(p + 1)),
                        Fraction(0))
            out.append(total / sonine_norm(p))
        else:
            total = math.fsum(float(s[m]) * float(moments[2 * m]) / 2.0**m
                              for m in range(p + 1))
            out.append(total / float(sonine_norm(p)))
    return out if exact else np.array(out)
