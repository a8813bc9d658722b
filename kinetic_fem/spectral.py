"""Sonine (Laguerre/Hermite) spectral solver of the heated steady state and the HCS.

The scaled distribution is expanded in Sonine polynomials,

.. math::

    f(c) = \\Phi(c)\\Big(1 + \\sum_{p=2}^{P} a_p S_p(c^2)\\Big), \\qquad
    S_p(c^2) = L_p^{(-1/2)}(c^2/2), \\qquad P(v) = f(v/\\sqrt T)/\\sqrt T,

and the steady Boltzmann equation is projected on the even monomials
:math:`\\varphi_k = v^{2k}`, ``k = 1 .. P`` (moment method).  With the weak form of
the collision operator,

.. math::

    2k(2k-1)\\, D\\, T^{k-1}\\mu_{2k-2}
    + \\frac n2 T^{k+1/2} J_k(a) = 0,\\qquad
    J_k(a) = \\iint |c_1 - c_2| f(c_1) f(c_2)
        \\left[c_1'^{2k} + c_2'^{2k} - c_1^{2k} - c_2^{2k}\\right],

where :math:`\\mu_{2m} = \\langle c^{2m}\\rangle_f` is linear and :math:`J_k`
quadratic in :math:`(1, a_2, \\dots, a_P)`.  The ``k = 1`` equation is the energy
balance C1 and fixes :math:`T^{3/2} = -4D/(n J_1)`; the others,
:math:`2k(2k-1)\\mu_{2k-2} = 2 J_k/J_1`, fix the :math:`a_p` independently of ``n`` and
``D``.  Linearising in the :math:`a_p` at ``P = 2`` reproduces the first-order
result :func:`kinetic_fem.sonine.a2_first_order` exactly.

The double integrals are evaluated exactly: in centre-of-mass and relative
velocities :math:`C = (c_1+c_2)/2`, :math:`g = c_1 - c_2` the weight is
:math:`e^{-C^2} e^{-g^2/4}/(2\\pi)`; Gauss-Hermite in ``C`` and, after
:math:`s = g^2/4` on the even part in ``g``, Gauss-Laguerre in ``s`` integrate the
polynomial remainder exactly.

The truncated series is accurate for the heated gas (claim C15) but is not
positive in the far tails; use ``"fem"`` or ``"fd"`` for the tails.
"""

from __future__ import annotations

import math
import time
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import fsolve
from scipy.special import genlaguerre, roots_genlaguerre, roots_hermite

from .distribution import RunInfo, VelocityDistribution
from .gas import CoolingProblem, HeatedProblem, check_alpha
from .grid import simpson_weights
from .model import WhiteNoise
from .solve import register_solver

__all__ = ["SonineSolution", "solve_sonine", "sonine_heated", "solve_sonine_cooling",
           "sonine_cooling"]


def _sonine_polys(order: int) -> list[np.polynomial.Polynomial]:
    """:math:`S_p(c^2)` as polynomials in ``c``, ``p = 0 .. order``."""
    out = []
    for p in range(order + 1):
        coeffs_x = genlaguerre(p, -0.5).coeffs[::-1]  # in x = c^2/2, lowest first
        c_coeffs = np.zeros(2 * p + 1)
        c_coeffs[::2] = coeffs_x / 2.0 ** np.arange(p + 1)
        out.append(np.polynomial.Polynomial(c_coeffs))
    return out


@lru_cache(maxsize=32)
def _tensors(order: int, alpha: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Moment matrix ``M[m, p]`` and collision tensor ``A[k, p, q]``.

    ``M[m, p] = ∫Φ S_p c^{2m}`` (``m = 0 .. order``) and
    ``A[k, p, q] = ∬ |g| Φ Φ S_p(c1²) S_q(c2²) Δφ_k`` (``k = 1 .. order``).
    """
    polys = _sonine_polys(order)
    n_nodes = 3 * order + 4
    xc, wc = roots_hermite(n_nodes)               # weight exp(-C^2)
    xs, ws = roots_genlaguerre(n_nodes, 0.0)      # weight exp(-s), s = g^2/4
    big_c = xc[:, None]
    m = np.zeros((order + 1, order + 1))
    # single integrals with weight Φ(c): c = sqrt(2) t, Gauss-Hermite in t
    t, wt = roots_hermite(n_nodes)
    c1d = math.sqrt(2.0) * t
    w1d = wt / math.sqrt(math.pi)
    for p, sp in enumerate(polys):
        for mm in range(order + 1):
            m[mm, p] = np.sum(w1d * sp(c1d) * c1d ** (2 * mm))
    a = np.zeros((order + 1, order + 1, order + 1))
    half = 0.5 * (1.0 + alpha)
    for sign in (1.0, -1.0):                       # even part in g
        g = sign * 2.0 * np.sqrt(xs)[None, :]
        c1 = big_c + 0.5 * g
        c2 = big_c - 0.5 * g
        c1p, c2p = c1 - half * g, c2 + half * g
        # ∫∫|g| e^{-C^2 - g^2/4}/(2π) h dC dg = (4/(2π)) Σ wc ws h_even
        weight = (4.0 / (2.0 * math.pi)) * 0.5 * wc[:, None] * ws[None, :]
        s1 = np.array([sp(c1) for sp in polys])
        s2 = np.array([sp(c2) for sp in polys])
        for k in range(1, order + 1):
            dphi = c1p ** (2 * k) + c2p ** (2 * k) - c1 ** (2 * k) - c2 ** (2 * k)
            a[k] += np.einsum("ij,pij,qij->pq", weight * dphi, s1, s2)
    return m, a


class SonineSolution:
    """Sonine coefficients and temperature of the heated steady state.

    Attributes
    ----------
    order : int
        Truncation order ``P``.
    coefficients : ndarray, shape (order + 1,)
        ``a_0 = 1, a_1 = 0, a_2 .. a_P``.
    temperature : float
        Steady temperature.
    """

    def __init__(self, order: int, coefficients: NDArray[np.float64], temperature: float):
        self.order = order
        self.coefficients = coefficients
        self.temperature = temperature

    def f(self, c: NDArray[np.float64]) -> NDArray[np.float64]:
        """The truncated series :math:`f(c)` (may be negative in the far tails)."""
        c = np.asarray(c, dtype=float)
        polys = _sonine_polys(self.order)
        series = sum(a * sp(c) for a, sp in zip(self.coefficients, polys, strict=True))
        return np.exp(-0.5 * c**2) / math.sqrt(2.0 * math.pi) * series


def solve_sonine(alpha: float, order: int = 6, *, density: float = 1.0, diffusion: float = 1.0,
                 linearized: bool = False) -> SonineSolution:
    """Solve the moment equations for :math:`a_2 .. a_P` and :math:`T`.

    Parameters
    ----------
    alpha : float
        Restitution coefficient in ``[0, 1)``.
    order : int
        Truncation order ``P >= 2``.
    linearized : bool
        Drop products :math:`a_p a_q` (``p, q >= 2``): the first-order Sonine theory.

    Examples
    --------
    >>> from kinetic_fem.sonine import a2_first_order
    >>> sol = solve_sonine(0.5, order=2, linearized=True)
    >>> bool(abs(sol.coefficients[2] - a2_first_order(0.5)) < 1e-12)
    True
    """
    problem = HeatedProblem.from_parameters(alpha, density=density, diffusion=diffusion)
    order = _check_order(order)
    coef, j1 = _solve_moments(problem.gas.alpha, order, linearized, cooling=False)
    temperature = (-4.0 * problem.diffusion / (problem.gas.density * j1)) ** (2.0 / 3.0)
    return SonineSolution(order, coef, temperature)


def _check_order(order: object) -> int:
    if isinstance(order, bool) or not isinstance(order, int) or order < 2:
        raise ValueError(f"Sonine order must be an integer >= 2, got {order!r}")
    if order > 12:
        raise ValueError(f"order={order} is not supported (<= 12); the moment method "
                         "becomes ill-conditioned at high order")
    return order


def _solve_moments(alpha: float, order: int, linearized: bool, *, cooling: bool
                   ) -> tuple[NDArray[np.float64], float]:
    """Sonine coefficients ``a_0 .. a_P`` and :math:`J_1` of the moment equations.

    Heated: :math:`2k(2k-1)\\mu_{2k-2} J_1 = 2 J_k`; cooling (scaled, :math:`\\langle
    c^2\\rangle = 1`): :math:`k\\mu_{2k} J_1 = J_k`, ``k = 2 .. P``.
    """
    m, a = _tensors(order, alpha)

    def full(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.concatenate([[1.0, 0.0], x])

    def j(k: int, coef: NDArray[np.float64]) -> float:
        if linearized:
            return float(a[k, 0, 0] + a[k, 0, 2:] @ coef[2:] + a[k, 2:, 0] @ coef[2:])
        return float(coef @ a[k] @ coef)

    def residual(x: NDArray[np.float64]) -> NDArray[np.float64]:
        coef = full(x)
        j1 = j(1, coef)
        # each row scaled by its Gaussian size |J_1| times the Gaussian moment
        if cooling:
            mu = np.array([m[k] @ coef for k in range(order + 1)])
            if linearized:  # mu_2k J_1 without the products a_p a_q
                mu0, j10 = m[:, 0], a[1, 0, 0]
                prod = mu0 * j1 + (mu - mu0) * j10
            else:
                prod = mu * j1
            return np.array([(k * prod[k] - j(k, coef)) / (k * m[k, 0] * abs(a[1, 0, 0]))
                             for k in range(2, order + 1)])
        return np.array([(2 * k * (2 * k - 1) * (m[k - 1] @ coef) * j1 - 2.0 * j(k, coef))
                         / (2 * k * (2 * k - 1) * m[k - 1, 0] * abs(a[1, 0, 0]))
                         for k in range(2, order + 1)])

    x, _, _, msg = fsolve(residual, np.zeros(order - 1), xtol=1e-13, full_output=True)
    if not np.max(np.abs(residual(x))) < 1e-12:
        raise RuntimeError(f"the Sonine moment equations ({'cooling' if cooling else 'heated'}, "
                           f"alpha={alpha}, order {order}) have no solution the solver could "
                           f"find ({msg.strip()}); the truncated series fails where f is far "
                           "from a Gaussian: try another order or method='fd'")
    coef = full(x)
    return coef, j(1, coef)


def solve_sonine_cooling(alpha: float, order: int = 6, *, linearized: bool = False
                         ) -> tuple[SonineSolution, float]:
    """Sonine coefficients of the homogeneous cooling state and its cooling rate.

    The scaled state :math:`\\zeta (cf)' = \\tilde Q[f]` (see
    :mod:`kinetic_fem.cooling`) projected on :math:`c^{2k}`:
    :math:`-2k\\zeta\\mu_{2k} = J_k/2`; ``k = 1`` gives :math:`\\zeta = -J_1/4`, the
    others :math:`k\\mu_{2k}J_1 = J_k`.

    Returns
    -------
    solution : SonineSolution
        Coefficients at unit temperature.
    zeta : float
        Dimensionless cooling rate, :math:`dT/dt = -2\\zeta n T^{3/2}`.

    Examples
    --------
    First order (linearised, ``P = 2``): :math:`a_2 = 16(1-2\\alpha^2)/(33+30\\alpha^2)`,
    the 1D case of van Noije and Ernst's result.

    >>> sol, zeta = solve_sonine_cooling(0.5, order=2, linearized=True)
    >>> round(float(sol.coefficients[2]), 12), round(16 * 0.5 / (33 + 7.5), 12)
    (0.197530864198, 0.197530864198)
    """
    alpha = check_alpha(alpha)
    order = _check_order(order)
    coef, j1 = _solve_moments(alpha, order, linearized, cooling=True)
    return SonineSolution(order, coef, 1.0), -j1 / 4.0


@register_solver("spectral", problem="heated")
def sonine_heated(problem: HeatedProblem, *, order: int = 6, cutoff: float = 12.0,
                  n_v: int = 2401, linearized: bool = False) -> VelocityDistribution:
    """Heated steady state by the Sonine moment method (registry key ``"spectral"``).

    Parameters
    ----------
    problem : HeatedProblem
    order : int
        Truncation order ``P``.
    cutoff : float
        Output grid half-width in units of the thermal velocity.
    n_v : int
        Number of output nodes on ``[-cutoff, cutoff]`` (odd, for Simpson weights).
    linearized : bool
        First-order (linearised) Sonine theory.

    Returns
    -------
    VelocityDistribution
        Values of the truncated series on the grid; ``info.extra['sonine']`` holds
        :math:`a_0 .. a_P`.
    """
    problem.require("spectral", gammas=(1.0,), constant_restitution=True, thermostats=(WhiteNoise,))
    start = time.perf_counter()
    sol = solve_sonine(problem.gas.alpha, order, density=problem.gas.density,
                       diffusion=problem.diffusion, linearized=linearized)
    c = np.linspace(-cutoff, cutoff, n_v)
    s = math.sqrt(sol.temperature)
    info = RunInfo(converged=True, iterations=0, residual=0.0,
                   wall_time=time.perf_counter() - start,
                   message=f"Sonine moment method, order {order}",
                   extra={"order": order, "sonine": [float(x) for x in sol.coefficients],
                          "linearized": linearized})
    return VelocityDistribution.from_values(
        s * c, sol.f(c) / s, weights=s * simpson_weights(c), method="spectral",
        params=problem.as_dict(), info=info)


@register_solver("spectral", problem="cooling")
def sonine_cooling(problem: CoolingProblem, *, order: int = 6, cutoff: float = 12.0,
                   n_v: int = 2401, linearized: bool = False) -> VelocityDistribution:
    """Homogeneous cooling state by the Sonine moment method (key ``"spectral"``).

    Accurate only while the state is close to a Gaussian (moderate inelasticity): the
    two humps of the near-elastic state (claims C10, C15) are beyond a truncated
    series.  Parameters as :func:`sonine_heated`; the result is at unit temperature
    and ``info.extra`` holds ``zeta`` and the coefficients.
    """
    problem.require("spectral", gammas=(1.0,), constant_restitution=True)
    start = time.perf_counter()
    sol, zeta = solve_sonine_cooling(problem.gas.alpha, order, linearized=linearized)
    c = np.linspace(-cutoff, cutoff, n_v)
    info = RunInfo(converged=True, iterations=0, residual=0.0,
                   wall_time=time.perf_counter() - start,
                   message=f"Sonine moment method (cooling), order {order}",
                   extra={"order": order, "sonine": [float(x) for x in sol.coefficients],
                          "linearized": linearized, "zeta": zeta})
    return VelocityDistribution.from_values(c, sol.f(c), weights=simpson_weights(c),
                                            method="spectral", params=problem.as_dict(),
                                            info=info)
