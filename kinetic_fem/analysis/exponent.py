"""The effective exponent of the tail and the position of its maximum (claims C6, C7).

The effective exponent :math:`n(c) = d\\ln(-\\ln(f/f_0))/d\\ln c` of a distribution
(:meth:`~kinetic_fem.distribution.VelocityDistribution.effective_exponent`) rises from
2 at small c; its maximum :math:`(c^*, n^*)`, the quasi-elastic variable
:math:`x^* = v^* \\varepsilon^{1/3}` of claim C5, and power-law fits of how they move
with the inelasticity are computed here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..distribution import VelocityDistribution

__all__ = ["F_ANALYSIS_FLOOR", "ExponentPeak", "exponent_peak", "power_law_exponent",
           "local_exponents"]

F_ANALYSIS_FLOOR = 1e-60
"""Smallest f(c) used in fits; with the cut-off moved out (f below 1e-89 there) the
Dirichlet condition changes ln f by less than (1e-89/1e-60)^2 over the fitted range."""


def power_law_exponent(x: NDArray[np.float64], y: NDArray[np.float64]) -> float:
    """Slope of the least-squares line of ``log y`` against ``log x``.

    Parameters
    ----------
    x, y : ndarray, shape (m,)
        Positive values, ``m >= 2``.

    Returns
    -------
    float
    """
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])



@dataclass(frozen=True)
class ExponentPeak:
    """Maximum of the effective exponent: position in c, v and x, height ``n``.

    ``interior`` is False when the largest n(c) sits at the end of the searched range
    (no maximum resolved).

    Parameters
    ----------
    eps : float
        Inelasticity ``1 - alpha``.
    c : float
        Position of the peak in thermal velocities.
    v : float
        Position in physical velocity.
    x : float
        Position in the quasi-elastic variable :math:`x = (n\\varepsilon/D)^{1/3} v`.
    n : float
        Height of the peak, the effective exponent there.
    interior : bool
        A maximum inside the searched range.
    """

    eps: float
    c: float
    v: float
    x: float
    n: float
    interior: bool = True


def _resolved_c_max(dist: VelocityDistribution, floor: float) -> float:
    keep = (dist.c > 0) & (dist.f_values > floor)
    return float(dist.c[keep].max())


def exponent_peak(dist: VelocityDistribution, *, floor: float = F_ANALYSIS_FLOOR,
                  c_min: float = 0.3, n_points: int = 4000,
                  c_max: float | None = None, drop: float | None = None) -> ExponentPeak:
    """Largest :math:`n(c)` for ``c_min <= c <= c_max`` and ``f(c) > floor`` (parabolic
    refinement); ``c_max`` keeps the search away from the cut-off's boundary layer.

    With ``drop``, the search ends where n(c) first falls ``drop`` below its running
    maximum: the first maximum, not a later wiggle of an under-resolved deep tail.

    Parameters
    ----------
    dist : VelocityDistribution
        A heated steady state.
    floor : float
        Search only where ``f(c) > floor``.
    c_min : float
        Start of the search (thermal velocities).
    n_points : int
        Points of the search grid.
    c_max : float, optional
        End of the search (default: the end of the distribution).
    drop : float, optional
        Stop at the first maximum: where n(c) falls this much below its running maximum.

    Returns
    -------
    ExponentPeak
    """
    top = _resolved_c_max(dist, floor)
    c = np.linspace(c_min, top if c_max is None else min(top, c_max), n_points)
    n = dist.effective_exponent(c)
    if drop is not None:
        running = np.fmax.accumulate(np.nan_to_num(n, nan=-np.inf))
        below = np.flatnonzero(n < running - drop)
        if below.size:
            c, n = c[:below[0] + 1], n[:below[0] + 1]
    i = int(np.nanargmax(n))
    interior = 0 < i < c.size - 1
    if interior:
        y0, y1, y2 = n[i - 1], n[i], n[i + 1]
        shift = 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)
        c_star = c[i] + shift * (c[1] - c[0])
        n_star = y1 - 0.25 * (y0 - y2) * shift
    else:
        c_star, n_star = c[i], n[i]
    eps = 1.0 - float(dist.params["alpha"])
    v = c_star * math.sqrt(dist.temperature)
    return ExponentPeak(eps, float(c_star), float(v), float(v * eps ** (1 / 3)), float(n_star),
                        interior)


def local_exponents(peaks) -> list[tuple[float, float, float, float]]:
    """Two-point exponents of v* and 3 - n* between successive peaks.

    Parameters
    ----------
    peaks : sequence of ExponentPeak
        Peaks in order of decreasing eps.

    Returns
    -------
    list of tuple
        ``(eps_1, eps_2, exponent of v*, exponent of 3 - n*)`` for each successive pair.
    """
    out = []
    for a, b in zip(peaks[:-1], peaks[1:], strict=True):
        le = math.log(b.eps / a.eps)
        out.append((a.eps, b.eps, math.log(b.v / a.v) / le,
                    math.log((3.0 - b.n) / (3.0 - a.n)) / le))
    return out
