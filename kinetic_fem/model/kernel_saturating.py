"""The saturating kernel :math:`B(g) = |g|/(1 + |g|/g_0)`: hard rods that turn Maxwellian.

A pair meets at the rate of its relative speed while that is small (hard rods,
:math:`B \\approx |g|`) and at a rate that saturates at :math:`g_0` when it is large
(the inelastic Maxwell model, :math:`B \\to g_0`): a collision frequency with a ceiling,
as for particles whose encounters are limited by a finite time per collision (a dead
time :math:`1/g_0` per unit density).  It bridges the paper's hard rods
(:math:`g_0 \\to \\infty`) and the Maxwell model (:math:`g_0 \\to 0`, time rescaled),
and it is *not* homogeneous: there is no scaled homogeneous cooling state (as the gas
cools it tends to hard rods), and the heated state's tail is exponential,
:math:`\\ln P \\sim -\\sqrt{n g_0/D}\\,|v|`, while its core is that of hard rods.

This module is the whole model side of the family: the methods evaluate :math:`B` in
the FEM pair rule and the DSMC acceptance through :attr:`SaturatingKernel.numeric`
(family code :data:`~kinetic_fem.model.kernel_base.FAMILY_SATURATING`), and everything
else (temperature estimates, cut-offs, mesh grading, time steps, the reduction to
:math:`n = D = 1`) asks the kernel the questions of
:class:`~kinetic_fem.model.kernel_base.CollisionKernel`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import dawsn, expi

from .kernel_base import FAMILY_SATURATING, CollisionKernel
from .validation import check_real

__all__ = ["SaturatingKernel", "pole_moment"]

POLE_SPLIT = 1.0
""":func:`pole_moment` by its closed form for ``c <= POLE_SPLIT``, by the fixed Gauss
rule beyond (the pole at ``-c`` is then at least this far from the interval)."""
POLE_TOP = 7.0
"""Upper end of the Gauss rule of :func:`pole_moment` (:math:`e^{-49}\\,7^5` is 8e-18 of
the integral)."""
MAX_CLOSED_POWER = 4
"""Integer powers ``p`` in ``[0, MAX_CLOSED_POWER]`` of :meth:`SaturatingKernel.gaussian_mean`
in closed form; other powers by the base class' adaptive quadrature."""
SERIES_TOP = 0.5
"""``s = sqrt(|v|/g0)`` below which :meth:`SaturatingKernel.wkb_action` sums the series
(above, the closed form loses at most a factor 7 to cancellation)."""


@lru_cache(maxsize=1)
def _pole_rule() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Composite Gauss-Legendre rule on ``[0, POLE_TOP]``: 4 panels of 24 points."""
    nodes, weights = np.polynomial.legendre.leggauss(24)
    edges = np.linspace(0.0, POLE_TOP, 5)
    half = 0.5 * np.diff(edges)
    mid = 0.5 * (edges[1:] + edges[:-1])
    x = (mid[:, None] + half[:, None] * nodes[None, :]).ravel()
    w = (half[:, None] * weights[None, :]).ravel()
    return x, w * np.exp(-x * x)


@lru_cache(maxsize=1)
def _series_coefficients() -> NDArray[np.float64]:
    """:math:`2\\binom{-1/2}{k}/(2k+3)`, the series of :math:`s\\sqrt{1+s^2} -
    \\operatorname{asinh} s = \\sum_k a_k s^{2k+3}` (to 1e-18 at ``s = SERIES_TOP``)."""
    binom = np.cumprod(np.concatenate([[1.0], -(np.arange(1, 32) - 0.5) / np.arange(1, 32)]))
    return 2.0 * binom / (2.0 * np.arange(32) + 3.0)


def pole_moment(n: int, c: float) -> float:
    """:math:`R_n(c) = \\int_0^\\infty x^n e^{-x^2}/(x + c)\\,dx` for ``n >= 1``, ``c > 0``.

    For ``c <= POLE_SPLIT`` the division :math:`x^n/(x+c) = \\sum_{k<n}(-c)^{n-1-k}x^k +
    (-c)^n/(x+c)` leaves the moments :math:`\\int_0^\\infty x^k e^{-x^2} =
    \\Gamma(\\tfrac{k+1}2)/2` and :math:`J(c) = \\int_0^\\infty e^{-x^2}/(x+c)\\,dx =
    \\sqrt\\pi F(c) - \\tfrac12 e^{-c^2}\\operatorname{Ei}(c^2)` (:math:`F` Dawson's
    integral); the terms are at most 4.1 times the sum there (``n <= 5``).  Beyond, where
    the pole at :math:`-c` is at least ``POLE_SPLIT`` from the interval, a fixed
    composite Gauss-Legendre rule on ``[0, POLE_TOP]`` (96 points).  Relative accuracy
    <= 2e-15 against 30-digit quadrature for ``n`` in 1..5 and ``c`` in [1e-8, 1e7]
    (``tests/kinetic_fem/model/test_kernel_saturating.py``).

    Parameters
    ----------
    n : int
        Power of :math:`x`, >= 1.
    c : float
        Distance of the pole from 0, > 0.

    Returns
    -------
    float

    Examples
    --------
    >>> round(pole_moment(1, 1e-15), 12)   # c -> 0: sqrt(pi)/2, less c ln(1/c)
    0.886226925453
    """
    if c > POLE_SPLIT:
        x, w = _pole_rule()
        return float(np.dot(w, x**n / (x + c)))
    c2 = c * c
    total = (-c) ** n * (math.sqrt(math.pi) * float(dawsn(c))
                         - 0.5 * math.exp(-c2) * float(expi(c2)))
    for k in range(n):
        total += (-c) ** (n - 1 - k) * 0.5 * math.gamma(0.5 * (k + 1))
    return total


@dataclass(frozen=True)
class SaturatingKernel(CollisionKernel):
    """The kernel :math:`B(g) = |g|/(1 + |g|/g_0)`, :math:`0 < g_0 < \\infty`.

    Parameters
    ----------
    g0 : float
        Saturation speed: :math:`B(g) \\approx |g|` for :math:`|g| \\ll g_0`,
        :math:`B \\to g_0` for :math:`|g| \\gg g_0`.

    Raises
    ------
    ValueError
        If ``g0`` is not finite and > 0.

    Examples
    --------
    >>> k = SaturatingKernel(2.0)
    >>> k.rate([-2.0, 6.0])
    array([1. , 1.5])
    >>> k.rescaled(2.0)                  # B(2g)/2 in units of u = 2: g0 -> g0/u
    SaturatingKernel(g0=1.0)
    >>> k.homogeneity_degree is None, k.tail_growth
    (True, (2.0, 0.0))
    """

    g0: float = 1.0

    def __post_init__(self) -> None:
        g0 = check_real("saturation speed g0", self.g0)
        if not (math.isfinite(g0) and g0 > 0.0):
            raise ValueError(f"saturation speed g0={g0!r} must be finite and > 0 "
                             "(g0 -> infinity is hard rods: PowerLawKernel(1.0))")
        object.__setattr__(self, "g0", g0)

    @property
    def name(self) -> str:
        """``"saturating"`` with :math:`g_0`."""
        return f"saturating g0={self.g0:g}"

    def rate(self, g: ArrayLike) -> NDArray[np.float64]:
        """:math:`B(g) = |g|/(1 + |g|/g_0)`.

        Parameters
        ----------
        g : array_like
            Relative speeds.

        Returns
        -------
        ndarray
        """
        a = np.abs(np.asarray(g, dtype=float))
        return a / (1.0 + a / self.g0)

    @property
    def numeric(self) -> tuple[int, float]:
        """``(FAMILY_SATURATING, g0)``."""
        return FAMILY_SATURATING, self.g0

    @property
    def tail_growth(self) -> tuple[float, float]:
        """``(g0, 0)``: the rate saturates at :math:`g_0`."""
        return self.g0, 0.0

    @property
    def scale_degree(self) -> float:
        """1: :math:`B(ug) = u\\,B_{g_0/u}(g)`, hard rods at small speeds."""
        return 1.0

    def gaussian_mean(self, temperature: float, power: float = 0.0) -> float:
        """:math:`\\langle B(g)|g|^p\\rangle` over two Gaussians of variance :math:`T`.

        With :math:`x = |g|/(2\\sqrt T)` and :math:`c = g_0/(2\\sqrt T)`,
        :math:`B(g)|g|^p = g_0 (2\\sqrt T)^p x^{p+1}/(x + c)`, so the mean is
        :math:`\\tfrac{2}{\\sqrt\\pi} g_0 (2\\sqrt T)^p R_{p+1}(c)`
        (:func:`pole_moment`) for integer ``p`` in ``[0, MAX_CLOSED_POWER]``: about 100
        times faster than the adaptive quadrature of the base class (used for other
        powers), and more accurate.

        Parameters
        ----------
        temperature : float
            Variance :math:`T` of each velocity, > 0.
        power : float
            :math:`p \\ge 0`.

        Returns
        -------
        float

        Examples
        --------
        >>> k = SaturatingKernel(1e9)            # hard rods: <|g|^3> = 8 / sqrt(pi)
        >>> round(k.gaussian_mean(1.0, 2.0) * math.sqrt(math.pi), 6)
        8.0
        """
        if not (float(power).is_integer() and 0 <= power <= MAX_CLOSED_POWER):
            return super().gaussian_average(temperature, None, power)
        scale = 2.0 * math.sqrt(temperature)
        moment = pole_moment(int(power) + 1, self.g0 / scale)
        return 2.0 / math.sqrt(math.pi) * self.g0 * scale**power * moment

    def gaussian_average(self, temperature: float, weight: Callable[[float], float] | None,
                         power: float = 0.0, breaks: Sequence[float] = ()) -> float:
        """:math:`\\langle w(g) B(g) |g|^p\\rangle` (:meth:`CollisionKernel.gaussian_average`;
        without a weight :meth:`gaussian_mean`).

        Parameters
        ----------
        temperature : float
            Variance :math:`T` of each velocity, > 0.
        weight : callable or None
            :math:`w(g)`; ``None``: 1.
        power : float
            :math:`p \\ge 0`.
        breaks : sequence of float
            Relative speeds where :math:`w` has a kink or jump.

        Returns
        -------
        float
        """
        if weight is None:
            return self.gaussian_mean(temperature, power)
        return super().gaussian_average(temperature, weight, power, breaks)

    def wkb_action(self, v: ArrayLike) -> NDArray[np.float64]:
        """:math:`S(v) = \\int_0^{|v|}\\sqrt{B} = g_0^{3/2}\\,(s\\sqrt{1+s^2} -
        \\operatorname{asinh} s)`, :math:`s = \\sqrt{|v|/g_0}`
        (:meth:`CollisionKernel.wkb_action`, in closed form; by its series
        :math:`\\tfrac23 s^3 - \\tfrac15 s^5 + \\dots` below ``s = SERIES_TOP``).

        Parameters
        ----------
        v : array_like
            Velocities.

        Returns
        -------
        ndarray
            :math:`S(|v|)`, the shape of ``v``.

        Examples
        --------
        >>> k = SaturatingKernel(1.0)
        >>> float(np.round(k.wkb_action(3.0), 12))   # sqrt(12) - asinh(sqrt(3))
        2.147143718213
        """
        s = np.sqrt(np.abs(np.asarray(v, dtype=float)) / self.g0)
        s2 = s * s
        closed = s * np.sqrt(1.0 + s2) - np.arcsinh(s)
        series = np.zeros_like(s)
        for a in _series_coefficients()[::-1]:
            series = series * s2 + a
        series *= s2 * s
        return self.g0 ** 1.5 * np.where(s < SERIES_TOP, series, closed)

    def rescaled(self, u: float) -> SaturatingKernel:
        """:math:`B(ug)/u`, the saturating kernel with :math:`g_0/u`.

        Parameters
        ----------
        u : float
            Velocity unit, > 0.

        Returns
        -------
        SaturatingKernel
        """
        return self if u == 1.0 else SaturatingKernel(self.g0 / u)
