"""Sonine Galerkin solver of a granular mixture, to high order.

Each species is a Gaussian of its own variance :math:`\\sigma_s^2 = T_s/m_s` times a
truncated series in the orthonormal Sonine basis
(:mod:`kinetic_fem.operators.sonine_tensors`),

.. math::

    P_s(v) = \\frac{1}{\\sigma_s}\\Phi(c)\\sum_{p=0}^{P} b_{s,p}\\,e_p(c),\\qquad
    c = v/\\sigma_s,\\qquad b_{s,0} = 1,\\ b_{s,1} = 0,\\qquad a_{s,p} = b_{s,p}/\\sqrt{N_p},

and the mixture's Boltzmann equations (:mod:`kinetic_fem.model.mixture`) are tested
against :math:`e_q(v/\\sigma_s)`, ``q = 1 .. P``, for every species (Galerkin; ``q = 1``
is the species' energy balance):

.. math::

    R_{s,q} = n\\sum_r x_r \\iint |v_1 - v_2|^\\gamma P_s(v_1)P_r(v_2)
        \\big[e_q(v_1'/\\sigma_s) - e_q(v_1/\\sigma_s)\\big]\\,dv_1dv_2
        - \\frac{D_s}{\\sigma_s^2}\\kappa_q b_{s,q-1}
        - \\Big(\\xi_s + \\frac{\\dot\\sigma}{\\sigma}\\Big)
          (2q\\,b_{s,q} - \\kappa_q b_{s,q-1}) = 0,

with :math:`v_1' = v_1 - \\mu_{sr}(1+\\alpha_{sr})(v_1 - v_2)`, :math:`\\mu_{sr} =
m_r/(m_s+m_r)`, :math:`\\kappa_q = \\sqrt{2q(2q-1)}`, and :math:`\\dot\\sigma/\\sigma = 0`
for the heated steady state (unknowns :math:`b_{s,2..P}` and :math:`\\ln T_s`) or
:math:`-\\zeta n` for the homogeneous cooling state at mixture temperature
:math:`T = \\sum_s x_s T_s = 1` (:math:`dT/dt = -2\\zeta nT^{1+\\gamma/2}`; unknowns
:math:`b_{s,2..P}`, :math:`\\ln T_s` and :math:`\\zeta`, with the equation
:math:`\\ln T = 0`: every species cools at the one rate).

The pair integrals are exact to round-off: with :math:`g = v_1 - v_2` and
:math:`w = (\\sigma_r^2v_1 + \\sigma_s^2v_2)/\\Sigma`, :math:`\\Sigma = \\sigma_s^2 +
\\sigma_r^2`, the two Gaussians factor into independent :math:`g \\sim N(0, \\Sigma)` and
:math:`w \\sim N(0, \\sigma_s^2\\sigma_r^2/\\Sigma)` (as in
:mod:`kinetic_fem.solvers.mixture_sonine`); with :math:`g = \\sqrt{\\Sigma/2}\\,u`,
:math:`w = (\\sigma_s\\sigma_r/\\sqrt\\Sigma)\\,x` and :math:`\\cos\\theta =
\\sigma_s/\\sqrt\\Sigma`, :math:`\\sin\\theta = \\sigma_r/\\sqrt\\Sigma`,

.. math::

    c_1 = x\\sin\\theta + \\frac{u}{\\sqrt2}\\cos\\theta,\\qquad
    c_2 = x\\cos\\theta - \\frac{u}{\\sqrt2}\\sin\\theta,\\qquad
    c_1' = c_1 - \\frac{\\mu_{sr}(1+\\alpha_{sr})\\,u}{\\sqrt2\\cos\\theta},

and :math:`|g|^\\gamma = (\\Sigma/2)^{\\gamma/2}|u|^\\gamma`.  The integrand is a
polynomial of degree ``<= 6P`` in ``(x, u)``: Gauss-Hermite in ``x`` (``3P + 1`` nodes)
and the kernel's rule for the weight :math:`|u|^\\gamma e^{-u^2/4}`
(:meth:`~kinetic_fem.model.kernel.PowerLawKernel.relative_speed_rule`,
``ceil((3P+1)/2)`` nodes) integrate it exactly, for every power law
:math:`|g|^\\gamma` (other kernels have no such rule and are refused).  Newton (the
shared driver, rows scaled by the size of their terms) solves the system, continued in
the order from ``P = 2`` as in :mod:`kinetic_fem.solvers.spectral`; the derivatives in
:math:`\\ln T_s` are complex-step derivatives (exact to round-off: the residual is
analytic in them), those in the coefficients are exact.

For identical species the equations are the one-species ones
(:mod:`kinetic_fem.solvers.spectral`); for the Maxwell kernel (``gamma = 0``) the equation
of order ``q`` involves the moments up to ``2q`` only, so every order gives the exact
:math:`T_s` and :math:`a_{2,s}` of :mod:`kinetic_fem.solvers.maxwell_mixture` (heated) and
its temperature ratios and cooling rate (cooling; there the scaled fourth moment may
diverge, and :math:`a_{2,s}` is then a spurious root, flagged in ``info``).  Measured
(mass ratio 3, fractions 0.3/0.7, alpha 0.6/0.7/0.9): heated to 2e-14 up to ``P = 16``;
cooling to 1e-11 up to ``P = 8``, then 1.3e-9 at ``P = 12``, where the pair rules'
round-off meets coefficients :math:`|a_{s,P}| \\sim 10^4` (the one-species solver uses
the closed-form Maxwell tensor for this reason).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from ..distribution import RunInfo, VelocityDistribution
from ..error import geometric_tail
from ..mixture_error import MixtureError, MixtureErrorRecipe, compare_species
from ..mixture_state import MixtureMoments, MixtureState
from ..model.kernel import PowerLawKernel
from ..model.mixture import Mixture
from ..model.thermostat import FokkerPlanckBath, NoThermostat, WhiteNoise
from ..model.validation import UnsupportedModelError, check_positive
from ..operators.grid import simpson_weights
from ..operators.sonine_tensors import (
    dilation_coefficients,
    laplacian_coefficients,
    orthonormal_sonine,
)
from ..solve import register_solver
from .newton import newton
from .spectral import SERIES_AHEAD, SERIES_FLOOR, resolved_core

__all__ = ["steady_state", "cooling_state", "solve_mixture_heated", "solve_mixture_cooling",
           "MAX_ORDER", "DEFAULT_ORDER", "order_recipe", "ORDER_METHOD"]

logger = logging.getLogger(__name__)

MAX_ORDER = 40
"""Highest truncation order of a mixture (the pair rules grow like ``4.5 P**2`` nodes)."""
DEFAULT_ORDER = 8
"""Truncation order used by :data:`kinetic_fem.mixture_solve.MIXTURE_STATE_METHODS`."""
ROUNDOFF_FLOOR = 1e-10
"""Largest relative residual accepted as a solution (Newton's round-off floor)."""
_STEP = 1e-30
"""Complex step of the derivatives in :math:`\\ln T_s`."""


def _check_order(order: object) -> int:
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or not \
            2 <= order <= MAX_ORDER:
        raise ValueError(f"order must be an integer with 2 <= order <= {MAX_ORDER}, got "
                         f"{order!r}")
    return int(order)


def _check_mixture(mixture: Mixture) -> tuple[float, NDArray[np.float64]]:
    """The kernel exponent and the table of restitution coefficients, or a clear error."""
    if not isinstance(mixture, Mixture):
        raise TypeError(f"mixture must be a kinetic_fem.Mixture, got {mixture!r}")
    kernel = mixture.collision_kernel
    if not isinstance(kernel, PowerLawKernel):
        raise UnsupportedModelError(
            f"the mixture's Sonine Galerkin method needs a power-law kernel |g|^gamma (its "
            f"pair integrals use the Gauss rule of |g|^gamma), got {kernel!r}; use 'fem' or "
            "a particle method")
    assert mixture.thermostats is not None
    for s, thermostat in enumerate(mixture.thermostats):
        if not isinstance(thermostat, (WhiteNoise, FokkerPlanckBath, NoThermostat)):
            raise UnsupportedModelError(
                f"the mixture's Sonine Galerkin method takes white noise, a Fokker-Planck "
                f"bath or no forcing, got {thermostat!r} for species {s}")
    return kernel.gamma, mixture.constant_alpha()


class _MixtureSystem:
    """Galerkin residual and Jacobian of a mixture at one order.

    Unknowns ``x = (b_{0,2..P}, .., b_{k-1,2..P}, ln T_0 .. ln T_{k-1}[, zeta])``.
    """

    def __init__(self, mixture: Mixture, order: int, density: float, gamma: float,
                 alpha: NDArray[np.float64]) -> None:
        self.mixture, self.order, self.density, self.gamma = mixture, order, density, gamma
        self.k = mixture.n_species
        self.cooling = not mixture.heated
        masses = np.asarray(mixture.masses)
        self.masses = masses
        self.jump = masses[None, :] / (masses[:, None] + masses[None, :]) * (1.0 + alpha)
        self.pair_weight = density * np.asarray(mixture.fractions)   # n x_r
        self.diffusion, self.friction = mixture.diffusions(), mixture.frictions()
        self.kappa = laplacian_coefficients(order)
        self.dil = dilation_coefficients(order)
        lap = np.zeros((order + 1, order + 1))
        lap[np.arange(1, order + 1), np.arange(order)] = self.kappa[1:]
        self.lap = lap
        x, wx = np.polynomial.hermite_e.hermegauss(3 * order + 1)
        u, wu = mixture.collision_kernel.relative_speed_rule((3 * order + 2) // 2)
        n_x, n_u = len(x), 2 * len(u)
        self.x = np.repeat(x, n_u)
        self.u = np.tile(np.concatenate([u, -u]), n_x)
        self.weight = np.repeat(wx / math.sqrt(2.0 * math.pi), n_u) * np.tile(
            np.concatenate([wu, wu]) / math.sqrt(4.0 * math.pi), n_x)
        self.n_b = order - 1

    @property
    def size(self) -> int:
        return self.k * self.n_b + self.k + int(self.cooling)

    def split(self, x: NDArray) -> tuple[NDArray, NDArray, complex | float]:
        """Coefficients ``b`` (k, P + 1), ``ln T_s`` and ``zeta`` (0 if heated)."""
        b = np.zeros((self.k, self.order + 1), dtype=x.dtype)
        b[:, 0] = 1.0
        b[:, 2:] = x[: self.k * self.n_b].reshape(self.k, self.n_b)
        logt = x[self.k * self.n_b: self.k * self.n_b + self.k]
        zeta = x[-1] if self.cooling else 0.0
        return b, logt, zeta

    def _pair(self, s: int, r: int, var: NDArray) -> tuple[NDArray, NDArray, NDArray, NDArray]:
        """Basis at ``c_1``, ``c_2``, the change ``e_q(c_1') - e_q(c_1)`` and the weights."""
        total = var[s] + var[r]
        cos, sin = np.sqrt(var[s] / total), np.sqrt(var[r] / total)
        half_u = self.u / math.sqrt(2.0)
        c1 = self.x * sin + half_u * cos
        c2 = self.x * cos - half_u * sin
        e1 = orthonormal_sonine(self.order, c1)
        e2 = orthonormal_sonine(self.order, c2)
        change = orthonormal_sonine(self.order, c1 - self.jump[s, r] * half_u / cos) - e1
        weight = self.weight * (self.pair_weight[r] * (0.5 * total) ** (0.5 * self.gamma))
        return e1, e2, change, weight

    def residual(self, x: NDArray, jacobian: bool = False
                 ) -> tuple[NDArray, NDArray | None, NDArray]:
        """``R`` (rows ``(s, q = 1..P)``, then ``ln T = 0`` in free cooling), ``dR/db``
        (k P x k (P + 1), if asked) and the row scales (the size of each row's terms)."""
        k, p = self.k, self.order
        b, logt, zeta = self.split(x)
        var = np.exp(logt) / self.masses
        coll = np.zeros((k, p), dtype=x.dtype)
        scale = np.zeros((k, p))
        jac = np.zeros((k, p, k, p + 1)) if jacobian else None
        for s in range(k):
            for r in range(k):
                e1, e2, change, weight = self._pair(s, r, var)
                # einsum, not BLAS: threaded gemv/gemm cost 3-4x the CPU time here
                f1, f2 = np.einsum("i,in->n", b[s], e1), np.einsum("j,jn->n", b[r], e2)
                coll[s] += np.einsum("qn,n->q", change[1:], weight * f1 * f2)
                scale[s] += np.einsum("qn,n->q", np.abs(change[1:]), np.abs(weight * f1 * f2))
                if jac is not None:
                    jac[s, :, s] += np.einsum("qn,in->qi", change[1:] * (weight * f2), e1)
                    jac[s, :, r] += np.einsum("qn,in->qi", change[1:] * (weight * f1), e2)
        drift = self.friction - self.density * zeta      # xi_s + sigma'/sigma
        noise = self.diffusion / var                     # D_s / sigma_s^2
        res = coll - noise[:, None] * (b[:, :-1] * self.kappa[None, 1:]) \
            - drift[:, None] * (b @ self.dil[1:].T)
        scale += np.abs(noise)[:, None] * np.abs(b[:, :-1] * self.kappa[None, 1:]) \
            + np.abs(drift)[:, None] * (np.abs(b) @ np.abs(self.dil[1:]).T)
        if jac is not None:
            for s in range(k):
                jac[s, :, s] -= noise[s].real * self.lap[1:] + drift[s].real * self.dil[1:]
        rows, scales = res.reshape(-1), scale.reshape(-1)
        if self.cooling:
            weights = np.asarray(self.mixture.fractions) * np.exp(logt)
            rows = np.concatenate([rows, [np.log(np.sum(weights))]])
            scales = np.concatenate([scales, [1.0]])
        flat = None if jac is None else jac.reshape(k * p, k * (p + 1))
        return rows, flat, scales + np.finfo(float).tiny

    def __call__(self, x: NDArray[np.float64], jacobian: bool = True
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        k, p, n_b = self.k, self.order, self.n_b
        res, jac_b, _ = self.residual(x, jacobian)
        if not jacobian:
            return res, np.zeros((0, 0))
        assert jac_b is not None
        jac = np.zeros((len(res), self.size))
        cols = np.concatenate([np.arange(s * (p + 1) + 2, (s + 1) * (p + 1)) for s in range(k)])
        jac[: k * p, : k * n_b] = jac_b[:, cols]
        for j in range(k):   # ln T_s: complex step (the residual is analytic in them)
            xc = x.astype(complex)
            xc[k * n_b + j] += 1j * _STEP
            jac[:, k * n_b + j] = self.residual(xc)[0].imag / _STEP
        if self.cooling:
            b, _, _ = self.split(x)
            jac[: k * p, -1] = (self.density * (b @ self.dil[1:].T)).reshape(-1)
        return res, jac

    def row_scale(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        return self.residual(x)[2]


def _newton(system: _MixtureSystem, x0: NDArray[np.float64]
            ) -> tuple[NDArray[np.float64], float, int]:
    """Newton with backtracking on the row-scaled residual; ``x``, residual, iterations."""
    def cols(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.maximum(np.abs(x), 1.0)

    with np.errstate(over="ignore", invalid="ignore"):
        out = newton(system, x0, tol=1e-14, max_iter=100, row_scale=system.row_scale,
                     column_scale=cols, min_damping=2.0**-10, stall_level=ROUNDOFF_FLOOR,
                     name="mixture Sonine Newton")
        res, _, rows = system.residual(out.x)
    return out.x, float(np.max(np.abs(res) / rows)), out.iterations


def _solve(mixture: Mixture, order: int, density: float) -> MixtureMoments:
    """Continue in the order from ``P = 2`` (doubling) to ``order`` and package."""
    from . import mixture_gaussian

    order = _check_order(order)
    density = check_positive("density", density)
    gamma, alpha = _check_mixture(mixture)
    cooling = not mixture.heated
    start = (mixture_gaussian.cooling_state if cooling else mixture_gaussian.steady_state)(
        mixture, density=density)
    k = mixture.n_species
    tail = np.log(start.temperatures)
    if cooling:
        assert start.zeta is not None
        tail = np.concatenate([tail, [start.zeta]])
    stages = [2]
    while stages[-1] < order:
        stages.append(min(order, 2 * stages[-1]))
    coef = np.zeros((k, 0))
    iterations = 0
    for stage in stages:
        system = _MixtureSystem(mixture, stage, density, gamma, alpha)
        grown = np.zeros((k, stage - 1))
        grown[:, : coef.shape[1]] = coef
        x, resid, its = _newton(system, np.concatenate([grown.reshape(-1), tail]))
        iterations += its
        coef, tail = x[: k * (stage - 1)].reshape(k, stage - 1), x[k * (stage - 1):]
        logger.debug("mixture Sonine order %d: relative residual %.2e after %d Newton "
                     "steps", stage, resid, its)
    if not (np.all(np.isfinite(x)) and resid <= ROUNDOFF_FLOOR):
        kind = "cooling" if cooling else "heated"
        raise RuntimeError(
            f"the mixture's Sonine Galerkin equations ({kind}, order {order}) have no solution "
            f"Newton could find (relative residual {resid:.1e}); the truncated series fails "
            "where a species is far from a Gaussian: try another order or method='fem'")
    b, logt, zeta = system.split(x)
    return _result(mixture, density, order, b, np.exp(logt),
                   float(np.real(zeta)) if cooling else None, resid, iterations)


def _sqrt_norms(order: int) -> NDArray[np.float64]:
    """:math:`\\sqrt{N_p}`, ``p = 0 .. order``: :math:`b_p = a_p\\sqrt{N_p}`."""
    p = np.arange(order + 1)
    return np.exp(0.5 * (np.array([math.lgamma(j + 0.5) - math.lgamma(j + 1.0) for j in p])
                         - 0.5 * math.log(math.pi)))


def _result(mixture: Mixture, density: float, order: int, b: NDArray[np.float64],
            temps: NDArray[np.float64], zeta: float | None, resid: float,
            iterations: int) -> MixtureMoments:
    """Moments :math:`\\langle v^j\\rangle_s`, ``j <= 2P`` (exact from the series).

    :math:`\\langle c^j e_p\\rangle_\\Phi = 0` for :math:`2p > j` (orthogonality) is set
    exactly, so that the large coefficients of high orders add no round-off to the low
    moments (:math:`T_s` is :math:`m_s\\sigma_s^2` to the last bit).
    """
    c, w = np.polynomial.hermite_e.hermegauss(2 * order + 1)
    w = w / math.sqrt(2.0 * math.pi)
    powers = np.arange(2 * order + 1)
    basis_moments = (orthonormal_sonine(order, c) * w) @ (c[:, None] ** powers[None, :])
    basis_moments[2 * np.arange(order + 1)[:, None] > powers[None, :]] = 0.0
    scaled = b @ basis_moments                                  # (k, 2P + 1)
    var = temps / np.asarray(mixture.masses)
    moments = scaled * np.sqrt(var)[:, None] ** np.arange(2 * order + 1)[None, :]
    norms = _sqrt_norms(order)
    info: dict[str, object] = {"order": order, "sonine": (b / norms).tolist(),
                               "residual": resid, "iterations": iterations}
    if np.any(moments[:, 4] <= 0.0):
        info["unphysical"] = "<v^4>_s <= 0: the truncated system has only a spurious root"
    return MixtureMoments(mixture, density, moments, "sonine-galerkin", zeta=zeta, info=info)


def steady_state(mixture: Mixture, *, density: float = 1.0,
                 order: int = DEFAULT_ORDER) -> MixtureMoments:
    """The heated steady state of a mixture by the Sonine Galerkin method.

    Parameters
    ----------
    mixture : Mixture
        Every species forced (white noise or a bath); constant restitution per pair; a
        power-law kernel :math:`|g|^\\gamma`.
    density : float
        Total number density :math:`n > 0`.
    order : int
        Truncation order ``2 <= P <= MAX_ORDER``.

    Returns
    -------
    MixtureMoments
        :math:`\\langle v^j\\rangle_s`, ``j = 0 .. 2P``; ``info['sonine']`` holds
        :math:`a_{s,0} .. a_{s,P}` of every species.

    Raises
    ------
    ValueError
        Bad ``order`` or ``density``, or a mixture in free cooling.
    UnsupportedModelError
        A kernel that is not a power law, a velocity-dependent restitution law.
    RuntimeError
        If Newton finds no solution of the truncated system.

    Examples
    --------
    Identical species are the one-species gas (:math:`T = 4D/(n(1-\\alpha^2))` for
    Maxwell molecules):

    >>> mix = Mixture.white_noise((1.0, 1.0), (0.5, 0.5), alpha=0.6, kernel=0.0)
    >>> round(float(steady_state(mix, order=4).temperatures[0]), 10)
    6.25
    """
    if not isinstance(mixture, Mixture) or not mixture.heated:
        raise ValueError(f"a steady state needs a Mixture with forced species, got {mixture!r}"
                         "; for free cooling use cooling_state")
    return _solve(mixture, order, density)


def cooling_state(mixture: Mixture, *, density: float = 1.0,
                  order: int = DEFAULT_ORDER) -> MixtureMoments:
    """The homogeneous cooling state of a mixture by the Sonine Galerkin method.

    Parameters
    ----------
    mixture : Mixture
        No forcing; constant restitution per pair; a power-law kernel.
    density : float
        Total number density :math:`n > 0`.
    order : int
        Truncation order ``2 <= P <= MAX_ORDER``.

    Returns
    -------
    MixtureMoments
        At mixture temperature :math:`T = 1`, with the common cooling rate ``zeta``
        (:math:`dT/dt = -2\\zeta nT^{1+\\gamma/2}`).

    Raises
    ------
    ValueError, UnsupportedModelError, RuntimeError
        As :func:`steady_state`.
    """
    if not isinstance(mixture, Mixture) or mixture.heated:
        raise ValueError(f"the homogeneous cooling state needs a Mixture without forcing, got "
                         f"{mixture!r}; for forced species use steady_state")
    return _solve(mixture, order, density)


def _state(moments: MixtureMoments, start: float) -> MixtureState:
    """The truncated series of every species on a grid (as the one-species ``"spectral"``:
    half-width :math:`\\max(12, \\sqrt{4P+8} + 8)` thermal speeds, spacing 0.01)."""
    order = int(moments.info["order"])  # type: ignore[call-overload]
    b = np.asarray(moments.info["sonine"]) * _sqrt_norms(order)
    cutoff = max(12.0, math.sqrt(4.0 * order + 8.0) + 8.0)
    c = np.linspace(-cutoff, cutoff, 2 * int(math.ceil(cutoff / 0.01)) + 1)
    shape = b @ orthonormal_sonine(order, c) * np.exp(-0.5 * c**2) / math.sqrt(2.0 * math.pi)
    mixture = moments.mixture
    info = RunInfo(converged=True, iterations=int(moments.info["iterations"]),  # type: ignore[call-overload]
                   residual=float(moments.info["residual"]),  # type: ignore[arg-type]
                   wall_time=time.perf_counter() - start,
                   message=f"mixture Sonine Galerkin, order {order}",
                   extra={"order": order, "sonine": moments.info["sonine"]})
    params = {"density": moments.density, "masses": list(mixture.masses),
              "fractions": list(mixture.fractions)}
    dists = []
    for s, (mass, temp) in enumerate(zip(mixture.masses, moments.temperatures, strict=True)):
        sigma = math.sqrt(temp / mass)
        dists.append(VelocityDistribution.from_values(
            sigma * c, shape[s] / sigma, weights=sigma * simpson_weights(c), method="spectral",
            params=params, info=info))
    return MixtureState(mixture, moments.density, tuple(dists), "spectral", zeta=moments.zeta,
                        info=info)


@register_solver("spectral", problem="mixture-heated")
def solve_mixture_heated(mixture: Mixture, *, density: float = 1.0,
                         order: int = DEFAULT_ORDER) -> MixtureState:
    """:func:`steady_state` with one distribution per species (``kf.solve_heated``).

    Parameters
    ----------
    mixture, density, order
        As in :func:`steady_state`.

    Returns
    -------
    MixtureState
        The truncated series of each species on a grid of its thermal speed (may be
        negative in the far tails).
    """
    start = time.perf_counter()
    state = _state(steady_state(mixture, density=density, order=order), start)
    return order_recipe(state, lambda p: steady_state(mixture, density=density, order=p)
                        ).attach(state)


@register_solver("spectral", problem="mixture-cooling")
def solve_mixture_cooling(mixture: Mixture, *, density: float = 1.0,
                          order: int = DEFAULT_ORDER) -> MixtureState:
    """:func:`cooling_state` with one distribution per species (``kf.solve_cooling``).

    Parameters
    ----------
    mixture, density, order
        As in :func:`cooling_state`.

    Returns
    -------
    MixtureState
        At mixture temperature 1, with ``zeta``.
    """
    start = time.perf_counter()
    state = _state(cooling_state(mixture, density=density, order=order), start)
    return order_recipe(state, lambda p: cooling_state(mixture, density=density, order=p)
                        ).attach(state)


ORDER_METHOD = "Sonine orders P - 2 .. P + 6"


def order_recipe(state: MixtureState, solve_at: Callable[[int], MixtureMoments]
                 ) -> MixtureErrorRecipe:
    """The error estimate of a Sonine state of order ``P`` from the orders around it.

    As for one species (:func:`kinetic_fem.solvers.spectral.order_estimate` and
    :func:`~kinetic_fem.solvers.spectral.series_check`): the orders ``P - 2`` to
    ``P + SERIES_AHEAD`` are solved (up to the first without a solution).  While every
    quantity's successive changes decrease, its error is the geometric tail
    :math:`d_+/(1 - d_+/d_-)` of the change from order :math:`P - 2`, :math:`d_-`, and
    to :math:`P + 2`, :math:`d_+` (:func:`kinetic_fem.error.geometric_tail`).  When a
    change above round-off does not decrease, or order :math:`P + 2` has no solution,
    the series is asymptotic there: the estimate is the largest difference of the result
    from the orders scanned, flagged ``asymptotic`` (the error may be larger), and a
    warning is logged (measured: gamma 0.5, m 1:4, alpha 0.6, the changes 8 -> 10 are a
    tenth of the error of order 8 and grow from order 12 on).  The f error of a species
    is its change to order :math:`P + 2` times the factor of its :math:`a_2` (or T),
    ``inf`` beyond the trusted core (:func:`kinetic_fem.solvers.spectral.resolved_core`).
    Computed when ``state.error`` is first read: up to five more solves.

    Parameters
    ----------
    state : MixtureState
        The state of order ``P`` (``info.extra["order"]``).
    solve_at : callable
        ``order -> MixtureMoments`` of the same problem.

    Returns
    -------
    MixtureErrorRecipe
    """
    order = int(state.info.extra["order"])
    mix = state.mixture
    k = mix.n_species

    def at(p: int) -> MixtureState | None:
        if p < 2 or p > MAX_ORDER:
            return None
        try:
            return _state(solve_at(p), time.perf_counter())
        except (RuntimeError, ValueError) as err:
            logger.info("mixture Sonine order %d for the error estimate failed: %s", p, err)
            return None

    def compare(a: MixtureState, b: MixtureState) -> MixtureError:
        zeta = None if a.zeta is None else (float(a.zeta), float(b.zeta))  # type: ignore[arg-type]
        return compare_species(a.distributions, b.distributions, mix.masses, mix.fractions,
                               method=ORDER_METHOD, zeta=zeta)

    def compute() -> MixtureError:
        lower = at(order - 2)
        higher: list[MixtureState] = []
        for p in range(order + 2, order + SERIES_AHEAD + 1, 2):
            nxt = at(p)
            if nxt is None:
                break
            higher.append(nxt)
        if not higher and lower is None:
            return MixtureError.unavailable(k, f"neither Sonine order {order - 2} nor "
                                            f"{order + 2} has a solution", method=ORDER_METHOD)
        if not higher:
            note = (f"order {order + 2} has no solution: the change from order "
                    f"{order - 2}; the series is asymptotic here")
            return _flagged(compare(state, lower), note, order)  # type: ignore[arg-type]
        last = compare(state, higher[0])
        if lower is None:
            return replace(last, note=f"the change to order {order + 2} (no order "
                                      f"{order - 2} to measure the rate)")
        chain = [lower, state, *higher]
        steps = np.array([_flat(compare(a, b)) for a, b in zip(chain[:-1], chain[1:], strict=True)])
        # the largest difference from the result over the orders up to each order
        spread = np.maximum.accumulate([_flat(compare(state, h)) for h in higher], axis=0)
        return _series_tail(steps, spread, compare(lower, state), last, order)

    return MixtureErrorRecipe(compute, ORDER_METHOD, k)


def _flat(e: MixtureError) -> NDArray[np.float64]:
    """The scalar errors of ``e`` as one vector (NaN for a missing zeta)."""
    def z(v: float | None) -> float:
        return float("nan") if v is None else float(v)

    return np.concatenate([[s.temperature for s in e.species], [s.a2 for s in e.species],
                           [z(s.zeta) for s in e.species], e.ratios.ravel(),
                           [e.temperature, z(e.zeta)]])


def _unflat(v: NDArray[np.float64], like: MixtureError) -> MixtureError:
    """The inverse of :func:`_flat` (f errors scaled by each species' a2 or T factor)."""
    k = len(like.species)

    def z(x: float) -> float | None:
        return None if math.isnan(x) else float(x)

    species = []
    for s, e in enumerate(like.species):
        t, a2 = float(v[s]), float(v[k + s])
        factors = [x / d for x, d in ((t, e.temperature), (a2, e.a2)) if d > 0]
        species.append(replace(e, temperature=t, a2=a2, zeta=z(v[2 * k + s]),
                               f_relative=resolved_core(e.f_relative
                                                        * max(factors, default=1.0))))
    return replace(like, species=tuple(species), ratios=v[3 * k:3 * k + k * k].reshape(k, k),
                   temperature=float(v[-2]), zeta=z(v[-1]))


def _flagged(e: MixtureError, note: str, order: int) -> MixtureError:
    logger.warning("mixture Sonine series at order %d: %s", order, note)
    return replace(e, species=tuple(replace(s, asymptotic=True, note=note) for s in e.species),
                   asymptotic=True, note=note)


def _series_tail(steps: NDArray[np.float64], spread: NDArray[np.float64],
                 prev: MixtureError, last: MixtureError, order: int) -> MixtureError:
    """Combine the successive changes ``steps`` (rows: orders P - 2 -> P -> P + 2 ...) and
    ``spread`` (row h: the largest difference from the result over the orders P + 2 ..
    P + 2 + 2h) (:func:`order_recipe`).  As in
    :func:`~kinetic_fem.solvers.spectral.series_check`, the scan of a quantity stops at
    its first change that does not decrease: its estimate is its spread up to there."""
    d_prev, d_last = _flat(prev), _flat(last)
    est = np.array([geometric_tail([a, b])[0] if np.isfinite(a) else b
                    for a, b in zip(d_prev, d_last, strict=True)])
    # a change above round-off that does not decrease: the series stops converging
    grows = (steps[1:] >= steps[:-1]) & (steps[1:] > SERIES_FLOOR)
    stalled = np.any(grows, axis=0)
    if not np.any(stalled):
        return _unflat(est, last)
    first = np.argmax(grows, axis=0)  # the first growing change of each quantity
    reach = spread[first, np.arange(spread.shape[1])]
    est = np.where(stalled, np.maximum(np.maximum(est, reach), d_prev), est)
    note = (f"successive Sonine orders from {order - 2} to {order - 2 + 2 * len(steps)} "
            "stop converging: the series is asymptotic here and the error may be larger "
            "than estimated; use method='fem'")
    return _flagged(_unflat(est, last), note, order)
