"""Species temperatures of a mixture in the Gaussian (lowest Sonine) approximation.

Each species is taken Gaussian with variance :math:`\\sigma_s^2 = T_s/m_s` (all
:math:`a_{2,s} = 0`), the approximation in which first-order Sonine theory computes the
temperature ratio of a granular mixture (Garzo and Dufty 1999, Barrat and Trizac 2002, who
then add the small :math:`a_2` corrections).  The relative velocity :math:`g = v_s - v_r`
of two independent Gaussians is Gaussian with variance
:math:`\\Sigma_{sr} = \\sigma_s^2 + \\sigma_r^2`, and the part of :math:`v_s` along
:math:`g` is :math:`(\\sigma_s^2/\\Sigma_{sr})\\,g`, so with :math:`v_s' = v_s - a g`,
:math:`a = \\mu_{sr}(1+\\alpha_{sr})`,

.. math::

    \\frac{d\\sigma_s^2}{dt} = n\\sum_r x_r\\, G(\\Sigma_{sr})
        \\Big(a^2 - 2a\\frac{\\sigma_s^2}{\\Sigma_{sr}}\\Big)
        + 2D_s - 2\\xi_s\\sigma_s^2,
    \\qquad G(\\Sigma) = \\langle B(|g|)\\,g^2\\rangle_{g \\sim N(0, \\Sigma)},

for any kernel (:meth:`~kinetic_fem.model.CollisionKernel.gaussian_mean`).  With a
velocity-dependent restitution law :math:`\\alpha_{sr}(|g|)` the pair's term is
:math:`\\mu_{sr}(\\mu_{sr}\\langle Bg^2(1+\\alpha)^2\\rangle - 2\\langle Bg^2(1+\\alpha)
\\rangle\\sigma_s^2/\\Sigma_{sr})` (a composite Gauss rule, :func:`_law_means`): heated
states and the relaxation; the cooling state needs constant coefficients.  The heated
steady state sets every rate to zero; the cooling state asks every
:math:`\\dot\\sigma_s^2/\\sigma_s^2` to be one common rate :math:`-2\\zeta n` at
:math:`T = \\sum_s x_s m_s\\sigma_s^2 = 1` (free cooling of a power law
:math:`|g|^\\gamma` then keeps the ratios: :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`).

For the Maxwell kernel the second-moment equations close and these temperatures are exact
(:mod:`kinetic_fem.solvers.maxwell_mixture`): a check of the two modules against each other.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import solve_ivp
from scipy.optimize import root

from ..exceptions import ConvergenceError
from ..mixture_state import MixtureMoments
from ..model.kernel_base import CollisionKernel
from ..model.mixture import Mixture
from ..model.restitution import RestitutionLaw, ThresholdRestitution
from ..model.validation import UnsupportedModelError, check_positive

__all__ = ["variance_rates", "steady_state", "cooling_state", "solve_root", "relaxed",
           "integrate", "relaxation", "law_rule"]

#: relative step tolerance of the root finder (it may stop with 'xtol too small' at round-off)
_ROOT_TOL = 1e-14
#: accepted residual of the relative rates (round-off of O(1) sums is ~1e-16)
_RESIDUAL_TOL = 1e-12


def _check(mixture: Mixture, density: float) -> float:
    if not isinstance(mixture, Mixture):
        raise TypeError(f"mixture must be a kinetic_fem.Mixture, got {mixture!r}")
    return check_positive("density", density)


_LEGENDRE = np.polynomial.legendre.leggauss(24)
_PIECES = (0.0, 1e-8, 1e-6, 1e-4, 1e-3, 1e-2, 0.05, 0.2, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0,
           8.0, 12.0)
"""Pieces in :math:`x = |g|/\\sqrt{2\\Sigma}` of :func:`law_rule`: 24 Gauss
points each, graded geometrically towards 0 (the viscoelastic :math:`g^{1/5}`; fractional
kernel powers) out to 12 (:math:`e^{-144}`); equal to the adaptive quadrature of
:meth:`~kinetic_fem.model.CollisionKernel.gaussian_average` to 2e-14 (measured over
four laws, five kernels and variances 1e-4 ... 1e5), 30-50 times faster."""


def law_rule(law: RestitutionLaw, kernel: CollisionKernel, total: float
             ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Nodes :math:`g`, weights (times :math:`B(g)`) and :math:`1 + \\alpha(g)` of the rule
    for averages over :math:`g \\sim N(0, \\Sigma)`, ``total`` :math:`= \\Sigma`, of a
    pair with the law ``law``: :math:`\\langle B(|g|)\\,h(|g|)\\rangle \\approx \\sum_i
    w_i h(g_i)` (composite Gauss rule :data:`_PIECES` in :math:`x = |g|/\\sqrt{2\\Sigma}`,
    split at a threshold and at the end of the law's range; a law continued beyond its
    range by its value there, as the one-species estimate
    :meth:`~kinetic_fem.model.InelasticGas.loss_rate`: a scale estimate).

    Parameters
    ----------
    law : RestitutionLaw
    kernel : CollisionKernel
    total : float
        :math:`\\Sigma > 0`.

    Returns
    -------
    g, weights, one_plus_alpha : ndarray
    """
    scale = math.sqrt(2.0 * total)
    edges = list(_PIECES)
    kinks = [law.max_speed, law.threshold if isinstance(law, ThresholdRestitution) else 0.0]
    edges = sorted({*edges, *(k / scale for k in kinks if 0.0 < k / scale < edges[-1])})
    lo, hi = np.array(edges[:-1]), np.array(edges[1:])
    half = 0.5 * (hi - lo)[:, None]
    x = (lo[:, None] + half * (_LEGENDRE[0][None, :] + 1.0)).ravel()
    w = (half * _LEGENDRE[1][None, :]).ravel()
    g = scale * x
    weights = w * (2.0 / math.sqrt(math.pi)) * np.exp(-x * x) * kernel.rate(g)
    return g, weights, 1.0 + law(np.minimum(g, law.max_speed))


def _law_means(law: RestitutionLaw, kernel: CollisionKernel, total: float
               ) -> tuple[float, float]:
    """:math:`\\langle B g^2 (1+\\alpha(g))^2\\rangle` and
    :math:`\\langle B g^2 (1+\\alpha(g))\\rangle` over :math:`g \\sim N(0, \\Sigma)`
    (:func:`law_rule`)."""
    g, weights, one_plus = law_rule(law, kernel, total)
    base = weights * g * g
    return float(np.sum(base * one_plus**2)), float(np.sum(base * one_plus))


def variance_rates(mixture: Mixture, variances: np.ndarray, density: float = 1.0
                   ) -> NDArray[np.float64]:
    """:math:`d\\sigma_s^2/dt` of Gaussian species (module notes).

    Parameters
    ----------
    mixture : Mixture
        Any kernel, any restitution law per pair.
    variances : array_like, shape (k,)
        :math:`\\sigma_s^2 > 0`.
    density : float
        Total number density.

    Returns
    -------
    ndarray, shape (k,)
    """
    density = _check(mixture, density)
    var = np.asarray(variances, dtype=float)
    kernel = mixture.collision_kernel
    masses = np.asarray(mixture.masses)
    rates = 2.0 * mixture.diffusions() - 2.0 * mixture.frictions() * var
    for s in range(mixture.n_species):
        for r in range(mixture.n_species):
            total = var[s] + var[r]
            mu = masses[r] / (masses[s] + masses[r])
            law = mixture.laws[s][r]
            if law.constant is None:  # a(g) = mu (1 + alpha(g)) inside the averages
                square, mean = _law_means(law, kernel, total)
                rates[s] += density * mixture.fractions[r] * mu * (
                    mu * square - 2.0 * mean * var[s] / total)
                continue
            a = mu * (1.0 + law.constant)
            # <B(g) g^2> over g ~ N(0, total): two Gaussians of variance total/2 each
            g2 = kernel.gaussian_mean(0.5 * total, 2.0)
            rates[s] += density * mixture.fractions[r] * g2 * (a * a - 2.0 * a * var[s] / total)
    return rates


def integrate(rhs: Callable[[float, NDArray[np.float64]], NDArray[np.float64]],
              y0: NDArray[np.float64], times: NDArray[np.float64], rtol: float
              ) -> tuple[NDArray[np.float64], int]:
    """A mixture's moment equations from ``t = 0`` to the output ``times`` (DOP853).

    Parameters
    ----------
    rhs : callable
        ``rhs(t, y)``.
    y0 : ndarray
        The moments at ``t = 0``.
    times : ndarray
        Increasing output times, ``times[0] >= 0``.
    rtol : float
        Relative tolerance (the absolute one ``rtol * 1e-6`` of the largest moment).

    Returns
    -------
    y : ndarray, shape (n_t, y0.size)
    nfev : int
    """
    atol = rtol * 1e-6 * np.maximum(np.abs(y0), float(np.max(np.abs(y0))))
    sol = solve_ivp(rhs, (0.0, float(times[-1])), y0, method="DOP853", t_eval=times,
                    rtol=rtol, atol=atol)
    if not sol.success:
        raise RuntimeError(f"the mixture's moment equations failed to integrate: "
                           f"{sol.message}")
    return sol.y.T, int(sol.nfev)


def relaxation(mixture: Mixture, variances: NDArray[np.float64], times: NDArray[np.float64],
               *, density: float = 1.0, rtol: float = 1e-10) -> NDArray[np.float64]:
    """:math:`\\sigma_s^2(t)` of Gaussian species from ``variances`` at ``t = 0``.

    Parameters
    ----------
    mixture : Mixture
        Any kernel, any restitution law per pair.
    variances : ndarray, shape (k,)
        :math:`\\sigma_s^2(0) > 0`.
    times : ndarray
        Increasing output times.
    density : float
        Total number density.
    rtol : float
        Tolerance of :func:`integrate`.

    Returns
    -------
    ndarray, shape (n_t, k)
    """
    return integrate(lambda _, y: variance_rates(mixture, y, density),
                     np.asarray(variances, dtype=float), times, rtol)[0]


def relaxed(drift: Callable[[NDArray[np.float64]], NDArray[np.float64]],
            x0: NDArray[np.float64], steps: int = 400) -> NDArray[np.float64]:
    """A start for :func:`solve_root`: ``x`` moved along ``dx/dt = drift(x)`` (explicit
    steps of at most 0.2 of the fastest rate) towards the steady state it relaxes to.

    Parameters
    ----------
    drift : callable
        The relaxation rates (zero at the state sought).
    x0 : ndarray
        The start.
    steps : int
        Steps at most (stops early once the rates are below 1e-6 of their start).

    Returns
    -------
    ndarray
    """
    x = np.asarray(x0, dtype=float).copy()
    rate = drift(x)
    first = float(np.max(np.abs(rate)))
    step = np.inf
    for _ in range(steps):
        size = float(np.max(np.abs(rate)))
        if not np.isfinite(size) or size <= 1e-6 * first:
            break
        step = min(step, 0.2 / size)  # never longer: the rates shrink near the state
        x += np.clip(rate * step, -0.5, 0.5)
        rate = drift(x)
    return x


def solve_root(fun: Callable[[NDArray[np.float64]], NDArray[np.float64]],
               x0: NDArray[np.float64], what: str) -> NDArray[np.float64]:
    """The root of ``fun`` from ``x0`` (MINPACK's hybrid method), checked.

    Parameters
    ----------
    fun : callable
        The scaled balances; O(1) values, so the residual is compared with round-off.
    x0 : ndarray
        The start.
    what : str
        The theory and state, for the error message.

    Returns
    -------
    ndarray

    Raises
    ------
    ConvergenceError
        If the root is not finite or its residual exceeds 1e-12 (the finder may stop
        with "xtol too small" at round-off: that is accepted).
    """
    sol = root(fun, x0, method="hybr", tol=_ROOT_TOL)
    residual = float(np.max(np.abs(fun(sol.x))))
    if not np.all(np.isfinite(sol.x)) or not residual <= _RESIDUAL_TOL:
        raise ConvergenceError(f"{what}: the root finder stopped ({sol.message}; residual "
                               f"{residual:.3g})")
    return sol.x


def _result(mixture: Mixture, density: float, var: NDArray[np.float64],
            zeta: float | None) -> MixtureMoments:
    moments = np.zeros((mixture.n_species, 5))
    moments[:, 0] = 1.0
    moments[:, 2] = var
    moments[:, 4] = 3.0 * var**2  # Gaussian: a2 = 0 by construction
    return MixtureMoments(mixture, density, moments, "gaussian", zeta=zeta,
                          info={"approximation": "Gaussian species (a2 = 0)"})


def steady_state(mixture: Mixture, *, density: float = 1.0) -> MixtureMoments:
    """The heated steady state's temperatures in the Gaussian approximation.

    Parameters
    ----------
    mixture : Mixture
        Any kernel, any restitution law per pair, every species forced.
    density : float
        Total number density :math:`n > 0`.

    Returns
    -------
    MixtureMoments
        ``a2`` is zero by construction.

    Raises
    ------
    ConvergenceError
        If the root finder fails.
    """
    density = _check(mixture, density)
    if not mixture.heated:
        raise ValueError("a steady state needs forced species; for free cooling use "
                         "cooling_state")

    def fun(log_var: NDArray[np.float64]) -> NDArray[np.float64]:
        var = np.exp(log_var)
        return variance_rates(mixture, var, density) / var

    # start: equal variances at the scale of the mean forcing; the root finder from
    # there, or after relaxing along the dynamics if it fails (the relaxation took 50-400
    # evaluations of the rates, the root finder alone 10-20)
    scale = float(np.mean(mixture.diffusions()) / density)
    x0 = np.full(mixture.n_species, np.log(max(scale, 1e-300)))
    what = "Gaussian approximation of the mixture's steady state"
    try:
        log_var = solve_root(fun, x0, what)
    except ConvergenceError:
        log_var = solve_root(fun, relaxed(fun, x0), what)
    return _result(mixture, density, np.exp(log_var), None)


def cooling_state(mixture: Mixture, *, density: float = 1.0) -> MixtureMoments:
    """The homogeneous cooling state's temperature ratios and cooling rate, Gaussian species.

    Parameters
    ----------
    mixture : Mixture
        A homogeneous kernel (power law), constant restitution per pair, no forcing.
    density : float
        Total number density :math:`n > 0`.

    Returns
    -------
    MixtureMoments
        At :math:`T = 1`; ``zeta`` from :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`.
    """
    density = _check(mixture, density)
    if mixture.heated:
        raise ValueError("the homogeneous cooling state is for free cooling; this mixture is "
                         "forced (use steady_state)")
    for row in mixture.laws:
        for law in row:
            if law.constant is None:
                raise UnsupportedModelError(
                    f"a homogeneous cooling state needs constant restitution coefficients (a "
                    f"velocity-dependent law has no scaling state), got {law!r}; "
                    "evolve_mixture(method='gaussian') follows free cooling in physical time")
    if mixture.collision_kernel.homogeneity_degree is None:
        raise UnsupportedModelError(
            f"a homogeneous cooling state needs a homogeneous kernel (a power law), got "
            f"{mixture.collision_kernel!r}")
    weights = np.asarray(mixture.fractions) * np.asarray(mixture.masses)

    def fun(log_var: NDArray[np.float64]) -> NDArray[np.float64]:
        var = np.exp(log_var)
        rel = variance_rates(mixture, var, density) / var
        return np.concatenate([rel[1:] - rel[:-1], [np.log(np.dot(weights, var))]])

    def drift(log_var: NDArray[np.float64]) -> NDArray[np.float64]:
        # the scaled dynamics: every ln sigma_s^2 relative to the mixture's mean rate
        var = np.exp(log_var)
        rel = variance_rates(mixture, var, density) / var
        return rel - np.dot(weights * var, rel) / np.dot(weights, var)

    x0 = relaxed(drift, np.log(np.full(mixture.n_species, 1.0) / np.asarray(mixture.masses)))
    x0 -= np.log(np.dot(weights, np.exp(x0)))  # T = 1
    log_var = solve_root(fun, x0, "Gaussian approximation of the mixture's cooling state")
    var = np.exp(log_var)
    rate = float(np.dot(weights, variance_rates(mixture, var, density)))  # dT/dt at T = 1
    return _result(mixture, density, var, -rate / (2.0 * density))
