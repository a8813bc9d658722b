"""Moments of a normalised velocity distribution: central moments and Sonine coefficients.

With :math:`u = \\langle v \\rangle` the central moments follow from the raw ones by the
binomial sum

.. math::

    \\langle (v-u)^k \\rangle = \\sum_{j=0}^{k} \\binom{k}{j} \\langle v^j \\rangle (-u)^{k-j},

and the Sonine coefficient :math:`a_p = \\langle S_p(c^2) \\rangle / \\mathcal N_p`,
:math:`S_p(c^2) = L_p^{(-1/2)}(c^2/2)`,
:math:`\\mathcal N_p = \\Gamma(p + 1/2)/(\\sqrt{\\pi}\\, p!)`,
is a linear combination of the even central moments (:mod:`kinetic_fem.distribution`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy.special import binom, gammaln, genlaguerre

__all__ = ["central_from_raw", "sonine_from_central"]


def central_from_raw(raw: NDArray[np.float64]) -> NDArray[np.float64]:
    """Central moments of a normalised distribution from its raw moments.

    Parameters
    ----------
    raw : ndarray, shape (k_max + 1,)
        Raw moments :math:`\\langle v^k \\rangle`, ``k = 0 .. k_max``, with ``raw[0] = 1``
        (velocity units to the power k).

    Returns
    -------
    ndarray, shape (k_max + 1,)
        :math:`\\langle (v-u)^k \\rangle` with :math:`u = ` ``raw[1]``.

    Examples
    --------
    >>> central_from_raw(np.array([1.0, 1.0, 3.0]))  # mean 1, <v^2> = 3: variance 2
    array([1., 0., 2.])
    """
    u = raw[1]
    if u == 0.0:  # central = raw (also for infinite moments, where 0 * inf would be NaN)
        return np.array(raw, dtype=float)
    out = np.empty_like(raw)
    for k in range(raw.size):
        j = np.arange(k + 1)
        out[k] = np.sum(binom(k, j) * raw[j] * (-u) ** (k - j))
    return out


def sonine_from_central(central: NDArray[np.float64], p: int) -> float:
    """The Sonine coefficient :math:`a_p` from central moments.

    Parameters
    ----------
    central : ndarray, shape (k_max + 1,)
        Central moments :math:`\\langle (v-u)^k \\rangle` with ``central[0] = 1`` and
        ``k_max >= 2 p``.
    p : int
        Order of the coefficient (``a_2`` is the kurtosis coefficient).

    Returns
    -------
    float
        :math:`a_p` (dimensionless).

    Examples
    --------
    >>> gauss = np.array([1.0, 0.0, 2.0, 0.0, 12.0])  # T = 2, <v^4> = 3 T^2
    >>> round(sonine_from_central(gauss, 2), 12)
    0.0
    """
    temperature = central[2]
    poly = genlaguerre(p, -0.5)  # in x = c^2 / 2, highest power first
    coeffs = poly.coeffs[::-1]
    with np.errstate(invalid="ignore"):  # inf - inf: undefined for heavy tails (NaN)
        mean_s = sum(coeffs[k] * central[2 * k] / temperature**k / 2.0**k
                     for k in range(p + 1))
    norm = math.exp(gammaln(p + 0.5) - gammaln(p + 1.0)) / math.sqrt(math.pi)
    return float(mean_s / norm)
