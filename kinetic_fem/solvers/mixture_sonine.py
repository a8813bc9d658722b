"""First-order Sonine theory of a granular mixture: temperatures and every :math:`a_{2,s}`.

Each species is taken as a Gaussian of variance :math:`\\sigma_s^2 = T_s/m_s` corrected by
its first non-trivial Sonine polynomial,

.. math::

    f_s(v) = \\phi_s(v)\\,[1 + a_{2,s} S_2(x)], \\qquad x = \\frac{v^2}{2\\sigma_s^2},
    \\qquad S_2(x) = \\tfrac12\\big(x^2 - 3x + \\tfrac34\\big),

so that :math:`\\langle v^2\\rangle_s = \\sigma_s^2` and
:math:`\\langle v^4\\rangle_s = 3\\sigma_s^4(1 + a_{2,s})`.  The balances of
:math:`\\langle v^2\\rangle_s` and :math:`\\langle v^4\\rangle_s`,

.. math::

    \\frac{d\\langle\\psi\\rangle_s}{dt} = n\\sum_r x_r
    \\big\\langle B(|g|)\\,[\\psi(v_s - a_{sr} g) - \\psi(v_s)]\\big\\rangle_{f_s f_r}
    + \\text{forcing}, \\qquad a_{sr} = \\mu_{sr}(1 + \\alpha_{sr}),

are evaluated to first order in the :math:`a_{2,s}` (the products
:math:`a_{2,s}a_{2,r}` dropped: van Noije and Ernst's truncation, which for one species
gives :func:`kinetic_fem.sonine.a2_first_order`).  Each average is exact: with
:math:`g = v_s - v_r` and :math:`w = (\\sigma_r^2 v_s + \\sigma_s^2 v_r)/\\Sigma`,
:math:`\\Sigma = \\sigma_s^2 + \\sigma_r^2`, the Gaussians factor into independent
:math:`g \\sim N(0, \\Sigma)` and :math:`w \\sim N(0, \\sigma_s^2\\sigma_r^2/\\Sigma)`,
every integrand is :math:`B(|g|)` times a polynomial in :math:`(g, w)`, and
:math:`\\langle B(|g|)\\,g^k\\rangle` is the kernel's Gaussian mean
(:meth:`~kinetic_fem.model.CollisionKernel.gaussian_mean`).

Heated steady state: every balance zero (white noise adds :math:`2D_s` and
:math:`12 D_s\\sigma_s^2`, a bath :math:`-2\\xi_s\\sigma_s^2` and
:math:`-4\\xi_s\\langle v^4\\rangle_s`).  Free cooling: every :math:`\\sigma_s^2` decays at one
rate :math:`\\lambda` and every scaled fourth moment is stationary, at :math:`T = 1`
(:math:`\\lambda(1 + a_{2,s})` linearised to :math:`\\lambda + \\lambda_0 a_{2,s}`,
:math:`\\lambda_0 = \\dot T/T` of Gaussian species: for one species this is van Noije and Ernst's
:math:`a_2 = 16(1-2\\alpha^2)/(33 + 30\\alpha^2)`).

A velocity-dependent restitution law :math:`\\alpha_{sr}(|g|)` (heated states): the change
:math:`\\psi(v_s - a(g)g) - \\psi(v_s)` expanded in powers of :math:`a(g) = \\mu_{sr}(1 +
\\alpha_{sr}(|g|))`, whose averages :math:`\\langle B g^k a(g)^j\\rangle` replace the
kernel's Gaussian means (the rule of
:func:`~kinetic_fem.solvers.mixture_gaussian.law_rule`); the cooling state needs constant
coefficients.

For the Maxwell kernel the truncation is exact (the :math:`a_{2,s}a_{2,r}` terms multiply
moments of order 8 that the fourth-moment balance does not contain): the tests check this
module against :mod:`kinetic_fem.solvers.maxwell_mixture`.

References
----------
T. P. C. van Noije and M. H. Ernst, Granular Matter 1, 57 (1998); V. Garzo and J. W.
Dufty, Phys. Rev. E 60, 5706 (1999).
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable
from math import comb, prod

import numpy as np
from numpy.typing import NDArray

from ..mixture_state import MixtureMoments
from ..model.kernel_base import CollisionKernel
from ..model.mixture import Mixture
from ..model.validation import UnsupportedModelError, check_positive
from .mixture_gaussian import solve_root

__all__ = ["collision_rates", "steady_state", "cooling_state"]

Poly = dict[tuple[int, int], float]
"""A polynomial in two variables: ``{(i, j): c}`` is :math:`\\sum c\\,x^i y^j`."""


def _mul(p: Poly, q: Poly) -> Poly:
    out: Poly = defaultdict(float)
    for (i, j), a in p.items():
        for (k, m), b in q.items():
            out[(i + k, j + m)] += a * b
    return dict(out)


def _substitute(p: Poly, a: float, c: float) -> Poly:
    """:math:`p(v_1, v_2)` with :math:`v_1 = w + a g`, :math:`v_2 = w - c g`, in ``(g, w)``."""
    degree = max(max(i, j) for i, j in p)
    powers1, powers2 = [{(0, 0): 1.0}], [{(0, 0): 1.0}]
    for _ in range(degree):
        powers1.append(_mul(powers1[-1], {(1, 0): a, (0, 1): 1.0}))
        powers2.append(_mul(powers2[-1], {(1, 0): -c, (0, 1): 1.0}))
    out: Poly = defaultdict(float)
    for (i, j), coef in p.items():
        for key, value in _mul(powers1[i], powers2[j]).items():
            out[key] += coef * value
    return dict(out)


def _gauss_moment(var: float, k: int) -> float:
    """:math:`\\langle w^k\\rangle` of :math:`N(0, var)`."""
    return 0.0 if k % 2 else var ** (k // 2) * prod(range(k - 1, 0, -2))


def _sonine(var: float, v_index: int) -> Poly:
    """:math:`S_2(v^2/2\\sigma^2)` as a polynomial in :math:`(v_1, v_2)` (``v_index`` 0/1)."""
    def mono(k: int) -> tuple[int, int]:
        return (k, 0) if v_index == 0 else (0, k)
    return {mono(4): 0.125 / var**2, mono(2): -0.75 / var, mono(0): 0.375}


def _expect(kernel: CollisionKernel, var_s: float, var_r: float, p: Poly,
            moment: Callable[[int], float] | None = None) -> float:
    """:math:`\\langle B(|v_1 - v_2|)\\,p(v_1, v_2)\\rangle` over independent Gaussians
    (``moment(k)``: :math:`\\langle B(|g|) g^k h(|g|)\\rangle` in place of the kernel's
    Gaussian mean, for a weight :math:`h` of the relative speed)."""
    total = var_s + var_r
    gw = _substitute(p, var_s / total, var_r / total)
    var_w = var_s * var_r / total
    out = 0.0
    for (k, m), coef in gw.items():
        if k % 2 or m % 2 or coef == 0.0:
            continue
        g_k = kernel.gaussian_mean(0.5 * total, float(k)) if moment is None else moment(k)
        out += coef * g_k * _gauss_moment(var_w, m)
    return out


def _law_rates(mixture: Mixture, s: int, r: int, var: NDArray[np.float64],
               a2: NDArray[np.float64]) -> tuple[float, float]:
    """The pair's terms of :func:`collision_rates` for a velocity-dependent law:
    :math:`\\psi(v_1 - a(g)g) - \\psi(v_1) = \\sum_{j \\ge 1}\\binom pj v_1^{p-j}
    (v_2 - v_1)^j a(g)^j`, each power of :math:`a(g) = \\mu_{sr}(1 + \\alpha(|g|))` inside
    the average over the relative velocity
    (:func:`~kinetic_fem.solvers.mixture_gaussian.law_rule`)."""
    from .mixture_gaussian import law_rule

    mu = mixture.masses[r] / (mixture.masses[s] + mixture.masses[r])
    kernel = mixture.collision_kernel
    g, weights, one_plus = law_rule(mixture.laws[s][r], kernel, var[s] + var[r])
    out = []
    for power in (2, 4):
        value = 0.0
        for j in range(1, power + 1):
            weight_j = weights * (mu * one_plus) ** j
            term = {(power - j, 0): float(comb(power, j))}
            for _ in range(j):
                term = _mul(term, {(0, 1): 1.0, (1, 0): -1.0})

            def moment(k: int, w: NDArray[np.float64] = weight_j) -> float:
                return float(np.sum(w * g**k))

            value += _expect(kernel, var[s], var[r], term, moment)
            value += a2[s] * _expect(kernel, var[s], var[r], _mul(term, _sonine(var[s], 0)),
                                     moment)
            value += a2[r] * _expect(kernel, var[s], var[r], _mul(term, _sonine(var[r], 1)),
                                     moment)
        out.append(value)
    return out[0], out[1]


def _change(power: int, a: float) -> Poly:
    """:math:`\\psi(v_1 - a(v_1 - v_2)) - \\psi(v_1)` for :math:`\\psi = v^{power}`."""
    # (1 - a) v1 + a v2
    out: Poly = {(i, power - i): comb(power, i) * (1.0 - a)**i * a**(power - i)
                 for i in range(power + 1)}
    out[(power, 0)] = out.get((power, 0), 0.0) - 1.0
    return out


def collision_rates(mixture: Mixture, variances: np.ndarray, a2: np.ndarray,
                    density: float = 1.0) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Collisional rates of :math:`\\langle v^2\\rangle_s` and :math:`\\langle v^4\\rangle_s`.

    To first order in the :math:`a_{2,s}` (module notes).

    Parameters
    ----------
    mixture : Mixture
        Any kernel with Gaussian means, any restitution law per pair.
    variances : array_like, shape (k,)
        :math:`\\sigma_s^2 > 0`.
    a2 : array_like, shape (k,)
        :math:`a_{2,s}`.
    density : float
        Total number density.

    Returns
    -------
    rate2, rate4 : ndarray, shape (k,)
    """
    density = check_positive("density", density)
    var = np.asarray(variances, dtype=float)
    a2 = np.asarray(a2, dtype=float)
    masses = np.asarray(mixture.masses)
    kernel = mixture.collision_kernel
    rates = np.zeros((2, mixture.n_species))
    for s in range(mixture.n_species):
        for r in range(mixture.n_species):
            alpha = mixture.laws[s][r].constant
            if alpha is None:
                pair = _law_rates(mixture, s, r, var, a2)
                rates[:, s] += density * mixture.fractions[r] * np.array(pair)
                continue
            a = masses[r] / (masses[s] + masses[r]) * (1.0 + alpha)
            for row, power in enumerate((2, 4)):
                change = _change(power, a)
                value = _expect(kernel, var[s], var[r], change)
                value += a2[s] * _expect(kernel, var[s], var[r], _mul(change, _sonine(var[s], 0)))
                value += a2[r] * _expect(kernel, var[s], var[r], _mul(change, _sonine(var[r], 1)))
                rates[row, s] += density * mixture.fractions[r] * value
    return rates[0], rates[1]


def _forcing(mixture: Mixture, var: NDArray[np.float64], a2: NDArray[np.float64]
             ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    d, xi = mixture.diffusions(), mixture.frictions()
    m4 = 3.0 * var**2 * (1.0 + a2)
    return 2.0 * d - 2.0 * xi * var, 12.0 * d * var - 4.0 * xi * m4


def _result(mixture: Mixture, density: float, var: NDArray[np.float64],
            a2: NDArray[np.float64], zeta: float | None) -> MixtureMoments:
    moments = np.zeros((mixture.n_species, 5))
    moments[:, 0] = 1.0
    moments[:, 2] = var
    moments[:, 4] = 3.0 * var**2 * (1.0 + a2)
    info: dict[str, object] = {"approximation": "first-order Sonine, linear in a2"}
    if np.any(1.0 + a2 <= 0.0):
        # <v^4> < 0: the truncated balance has no physical solution (for the Maxwell kernel
        # exactly where the scaled fourth moment grows without bound)
        info["unphysical"] = "1 + a2 <= 0: no finite fourth moment at this order"
    return MixtureMoments(mixture, density, moments, "sonine-first-order", zeta=zeta,
                          info=info)


def steady_state(mixture: Mixture, *, density: float = 1.0) -> MixtureMoments:
    """Temperatures and :math:`a_{2,s}` of the heated steady state, first-order Sonine.

    Parameters
    ----------
    mixture : Mixture
        Every species forced; any restitution law per pair.
    density : float
        Total number density :math:`n > 0`.

    Returns
    -------
    MixtureMoments

    Examples
    --------
    >>> from kinetic_fem import sonine
    >>> from kinetic_fem.model.mixture import Mixture
    >>> state = steady_state(Mixture.white_noise((1.0, 1.0), (0.5, 0.5), alpha=0.6))
    >>> bool(abs(state.a2[0] - sonine.a2_first_order(0.6)) < 1e-12)
    True
    """
    from . import mixture_gaussian

    if not mixture.heated:
        raise ValueError("a steady state needs forced species; for free cooling use "
                         "cooling_state")
    start = mixture_gaussian.steady_state(mixture, density=density)
    k = mixture.n_species

    def fun(x: NDArray[np.float64]) -> NDArray[np.float64]:
        var, a2 = np.exp(x[:k]), x[k:]
        rate2, rate4 = collision_rates(mixture, var, a2, density)
        force2, force4 = _forcing(mixture, var, a2)
        return np.concatenate([(rate2 + force2) / var, (rate4 + force4) / var**2])

    x = solve_root(fun, np.concatenate([np.log(start.moments[:, 2]), np.zeros(k)]),
                   "first-order Sonine theory of the mixture's steady state")
    return _result(mixture, density, np.exp(x[:k]), x[k:], None)


def cooling_state(mixture: Mixture, *, density: float = 1.0) -> MixtureMoments:
    """Temperature ratios, :math:`a_{2,s}` and cooling rate of the HCS, first-order Sonine.

    Parameters
    ----------
    mixture : Mixture
        No forcing; a homogeneous kernel; constant restitution per pair.
    density : float
        Total number density :math:`n > 0`.

    Returns
    -------
    MixtureMoments
        At :math:`T = 1`; ``zeta`` from :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`.
    """
    from . import mixture_gaussian

    if mixture.heated:
        raise ValueError("the homogeneous cooling state is for free cooling; this mixture is "
                         "forced (use steady_state)")
    if mixture.collision_kernel.homogeneity_degree is None:
        raise UnsupportedModelError(
            f"a homogeneous cooling state needs a homogeneous kernel (a power law), got "
            f"{mixture.collision_kernel!r}")
    start = mixture_gaussian.cooling_state(mixture, density=density)
    k = mixture.n_species
    weights = np.asarray(mixture.fractions) * np.asarray(mixture.masses)

    def fun(x: NDArray[np.float64]) -> NDArray[np.float64]:
        var, a2 = np.exp(x[:k]), x[k:]
        rate2, rate4 = collision_rates(mixture, var, a2, density)
        rel2 = rate2 / var  # d ln sigma_s^2 / dt, one common value lambda
        common = rel2[0]
        # d<v^4>_s/dt = 2 lambda <v^4>_s = 6 sigma_s^4 lambda (1 + a2_s), linear in a2:
        # lambda (1 + a2_s) -> lambda + lambda_0 a2_s, lambda_0 = (dT/dt)/T of Gaussians
        # (the same for every species, so the result does not depend on their order)
        gauss = collision_rates(mixture, var, np.zeros(k), density)[0]
        common0 = float(np.dot(weights, gauss) / np.dot(weights, var))
        rel4 = (rate4 - 6.0 * var**2 * (common + common0 * a2)) / var**2
        return np.concatenate([rel2[1:] - common, rel4, [np.log(np.dot(weights, var))]])

    x = solve_root(fun, np.concatenate([np.log(start.moments[:, 2]), np.zeros(k)]),
                   "first-order Sonine theory of the mixture's cooling state")
    var, a2 = np.exp(x[:k]), x[k:]
    rate2, _ = collision_rates(mixture, var, a2, density)
    return _result(mixture, density, var, a2, -float(np.dot(weights, rate2)) / (2.0 * density))
