"""Sonine spectral solver: Galerkin projection of the heated and cooling states.

The scaled distribution is expanded in the orthonormal Sonine basis
:math:`e_p(c) = S_p(c^2/2)/\\sqrt{N_p}` (:mod:`kinetic_fem.operators.sonine_tensors`),

.. math::

    f(c) = \\Phi(c)\\sum_{p=0}^{P} b_p e_p(c), \\qquad b_0 = 1,\\ b_1 = 0,\\qquad
    a_p = b_p/\\sqrt{N_p},\\qquad P(v) = f(v/\\sqrt T)/\\sqrt T,

and the homogeneous Boltzmann equation with kernel :math:`|g|^\\gamma`, constant
:math:`\\alpha` and a thermostat :math:`\\partial_v(\\xi vP) + D\\partial_v^2P` is tested
against :math:`e_q(v/\\sqrt T)`, ``q = 1 .. P`` (Galerkin); divided by :math:`nT^{\\gamma/2}`:

.. math::

    R_q = \\tfrac12 \\sum_{rs} A_{qrs} b_r b_s - \\delta\\,\\kappa_q b_{q-1}
          - \\chi\\,(2q\\,b_q - \\kappa_q b_{q-1}) = 0,\\qquad
    \\kappa_q = \\sqrt{2q(2q-1)},

with :math:`\\delta = D/(nT^{1+\\gamma/2})`, :math:`\\chi = \\xi/(nT^{\\gamma/2})` (heated:
unknowns :math:`b_2 .. b_P` and :math:`\\ln T`) and, for the homogeneous cooling state
(:math:`dT/dt = -2\\zeta nT^{1+\\gamma/2}`), :math:`\\delta = 0`, :math:`\\chi = -\\zeta`
(unknowns :math:`b_2..b_P` and :math:`\\zeta`).  ``q = 1`` is the energy balance C1.
:math:`A_{qrs}` is exact to round-off (Gauss rules with the weight :math:`|g|^\\gamma`);
Newton with a line search solves the system, continued in the order from ``P = 2``.
Maxwell kernel (``gamma = 0``): the equation of order ``q`` involves the moments up to
``2q`` only, so every truncation gives the exact :math:`a_2 .. a_P`
(:mod:`kinetic_fem.solvers.maxwell`); its cooling state has no fourth moment and is
refused.  The truncated series is not positive in the far tails (use ``"fem"``).
"""

from __future__ import annotations

import logging
import math
import time
import warnings
from dataclasses import dataclass, replace
from typing import Any, Callable, Literal, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..distribution import RunInfo, VelocityDistribution
from ..error import ErrorEstimate, ErrorRecipe, geometric_tail
from ..exceptions import AsymptoticSeriesWarning, ConvergenceError
from ..gas import check_positive
from ..model import (
    CoolingProblem,
    FokkerPlanckBath,
    HeatedProblem,
    UnsupportedModelError,
    WhiteNoise,
)
from ..operators.grid import simpson_weights
from ..operators.sonine_tensors import (
    collision_tensor,
    dilation_coefficients,
    laplacian_coefficients,
    orthonormal_sonine,
)
from ..solve import register_solver
from .newton import newton

__all__ = ["SonineSolution", "solve_sonine", "solve_spectral_heated", "solve_sonine_cooling",
           "solve_spectral_cooling", "MAX_ORDER", "order_estimate", "ORDER_METHOD",
           "SeriesCheck", "series_check", "SERIES_AHEAD", "resolved_core", "SERIES_FLOOR"]

logger = logging.getLogger(__name__)

MAX_ORDER = 80
"""Highest truncation order (the tensor costs ~ ``P**3 * 4.5 P**2`` operations)."""
ROUNDOFF_FLOOR = 1e-10
"""Largest relative residual accepted as a solution (Newton's round-off floor)."""


@dataclass(frozen=True)
class SonineSolution:
    """Sonine coefficients and temperature of a Galerkin solution.

    Attributes
    ----------
    order : int
        Truncation order ``P``.
    coefficients : ndarray, shape (order + 1,)
        :math:`a_0 = 1, a_1 = 0, a_2 .. a_P` (the convention of
        :meth:`VelocityDistribution.sonine_coefficient`).
    temperature : float
        Temperature (1 for the cooling state, which is scaled).
    zeta : float
        Cooling rate (cooling) or NaN.
    residual : float
        Largest Galerkin residual :math:`|R_q|` relative to the size of its terms.
    condition_number : float
        2-norm condition number of the Newton Jacobian at the solution, rows scaled
        by the size of their terms and columns by the unknowns' magnitudes.
    iterations : int
        Newton iterations (all continuation stages).
    """

    order: int
    coefficients: NDArray[np.float64]
    temperature: float
    zeta: float = math.nan
    residual: float = 0.0
    condition_number: float = math.nan
    iterations: int = 0

    @property
    def orthonormal_coefficients(self) -> NDArray[np.float64]:
        """:math:`b_p = a_p\\sqrt{N_p}`."""
        return self.coefficients * _sqrt_norms(self.order)

    def f(self, c: ArrayLike) -> NDArray[np.float64]:
        """The truncated series :math:`f(c)` (may be negative in the far tails)."""
        c = np.asarray(c, dtype=float)
        basis = orthonormal_sonine(self.order, c)
        series = np.tensordot(self.orthonormal_coefficients, basis, axes=1)
        return np.exp(-0.5 * c**2) / math.sqrt(2.0 * math.pi) * series


def _sqrt_norms(order: int) -> NDArray[np.float64]:
    p = np.arange(order + 1)
    return np.exp(0.5 * (np.array([math.lgamma(k + 0.5) - math.lgamma(k + 1.0) for k in p])
                         - 0.5 * math.log(math.pi)))


def _check_order(order: object) -> int:
    if isinstance(order, bool) or not isinstance(order, int) or order < 2:
        raise ValueError(f"Sonine order must be an integer >= 2, got {order!r}")
    if order > MAX_ORDER:
        raise ValueError(f"order={order} is not supported (2 <= order <= {MAX_ORDER})")
    return order


class _System:
    """Galerkin residual and Jacobian in the unknowns ``x = (b_2 .. b_P, y)``.

    Heated: ``y = ln T`` (units of ``n = D = 1``, friction ``chi0 = xi/(n u^gamma)``);
    cooling: ``y = zeta``.
    """

    def __init__(self, order: int, alpha: float, gamma: float, *, cooling: bool,
                 friction: float = 0.0, linearized: bool = False,
                 reference: float = 1.0) -> None:
        self.order, self.gamma, self.cooling = order, gamma, cooling
        self.friction, self.linearized = friction, linearized
        self.tensor = collision_tensor(order, alpha, gamma)
        self.kappa = laplacian_coefficients(order)
        self.dil = dilation_coefficients(order)
        self.reference = reference   # y of the Gaussian state (linearised products)

    def coefficients(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.concatenate([[1.0, 0.0], x[:-1]])

    def _drive(self, y: float) -> tuple[float, float, float, float]:
        """``delta, chi`` and their derivatives in ``y``."""
        if self.cooling:
            return 0.0, -y, 0.0, -1.0
        g = self.gamma
        delta = float(np.exp(min(-(1.0 + 0.5 * g) * y, 700.0)))   # inf-free trial steps
        chi = self.friction * float(np.exp(min(-0.5 * g * y, 700.0)))
        return delta, chi, -(1.0 + 0.5 * g) * delta, -0.5 * g * chi

    def __call__(self, x: NDArray[np.float64]
                 ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        p = self.order
        b = self.coefficients(x)
        a = self.tensor[1:]                                   # rows q = 1 .. P
        delta, chi, d_delta, d_chi = self._drive(x[-1])
        lap = self.kappa[1:] * b[:-1]                         # kappa_q b_{q-1}
        dil = self.dil[1:] @ b                                # 2q b_q - kappa_q b_{q-1}
        jac_b = np.zeros((p, p + 1))
        if self.linearized:   # products of b_p (p >= 2) with b_r or with delta, chi dropped
            b0 = np.zeros(p + 1)
            b0[0] = 1.0
            ab0 = a @ b0                                      # A_{q r 0}
            coll = 0.5 * a[:, 0, 0] + ab0[:, 2:] @ b[2:]
            jac_b[:, 2:] = ab0[:, 2:]
            d0, c0, _, _ = self._drive(self.reference)
            lap0, dil0 = self.kappa[1:] * b0[:-1], self.dil[1:] @ b0
            res = coll - delta * lap0 - chi * dil0 - d0 * (lap - lap0) - c0 * (dil - dil0)
            jac_b -= d0 * _lap_matrix(self.kappa)[1:] + c0 * self.dil[1:]
            dres_dy = -d_delta * lap0 - d_chi * dil0
        else:
            ab = a @ b                                        # (P, P+1): sum_s A_qrs b_s
            coll = 0.5 * ab @ b
            res = coll - delta * lap - chi * dil
            jac_b = ab - delta * _lap_matrix(self.kappa)[1:] - chi * self.dil[1:]
            dres_dy = -d_delta * lap - d_chi * dil
        jac = np.concatenate([jac_b[:, 2:], dres_dy[:, None]], axis=1)
        return res, jac

    def row_scale(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """Size of the terms of each equation (sum of their absolute values)."""
        b = np.abs(self.coefficients(x))
        delta, chi, _, _ = self._drive(x[-1])
        coll = 0.5 * (np.abs(self.tensor[1:]) @ b) @ b
        lap = self.kappa[1:] * b[:-1]
        dil = np.abs(self.dil[1:]) @ b
        return coll + abs(delta) * lap + abs(chi) * dil + np.finfo(float).tiny


def _lap_matrix(kappa: NDArray[np.float64]) -> NDArray[np.float64]:
    n = len(kappa)
    mat = np.zeros((n, n))
    mat[np.arange(1, n), np.arange(n - 1)] = kappa[1:]
    return mat


def _solve_or_lstsq(jac: NDArray[np.float64], rhs: NDArray[np.float64]) -> NDArray[np.float64]:
    """``jac^{-1} rhs``, least squares where ``jac`` is singular."""
    try:
        return np.asarray(np.linalg.solve(jac, rhs), dtype=np.float64)
    except np.linalg.LinAlgError:
        return np.asarray(np.linalg.lstsq(jac, rhs, rcond=None)[0], dtype=np.float64)


def _newton(system: _System, x0: NDArray[np.float64], *, tol: float = 1e-14,
            max_iter: int = 100) -> tuple[NDArray[np.float64], float, int, float]:
    """Newton with backtracking on the row-scaled residual (the shared driver).

    Each equation is divided by the size of its terms (:meth:`_System.row_scale`, frozen
    during one step) and each unknown by its magnitude before the linear solve, so the
    solution may span many decades (the Maxwell coefficients grow like ``p**p``); a
    residual that stops falling below :data:`ROUNDOFF_FLOOR` is the round-off floor.
    Returns ``x``, the largest relative residual, the iterations and the condition
    number of the equilibrated Jacobian.
    """
    def fun(x: NDArray[np.float64], jacobian: bool
            ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return system(x)

    def cols(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.maximum(np.abs(x), 1.0)

    with np.errstate(over="ignore", invalid="ignore"):
        out = newton(fun, x0, tol=tol, max_iter=max_iter, row_scale=system.row_scale,
                     column_scale=cols, linear_solver=_solve_or_lstsq,
                     min_damping=2.0**-10, stall_level=ROUNDOFF_FLOOR, name="Sonine Newton")
        x = out.x
        res, jac = system(x)
        rows = system.row_scale(x)
        cond = float(np.linalg.cond(jac * cols(x)[None, :] / rows[:, None]))
    return x, float(np.max(np.abs(res) / rows)), out.iterations, cond


def _realisable(b: NDArray[np.float64]) -> bool:
    """Stieltjes test: can :math:`\\nu_k = \\langle c^{2k}\\rangle`, ``k <= min(P, 4)``, be moments?

    The moments of :math:`x = c^2 \\ge 0` need positive semidefinite Hankel matrices
    :math:`[\\nu_{i+j}]` and :math:`[\\nu_{i+j+1}]`; e.g. :math:`a_2 \\ge -2/3`.  Only
    the moments fixed by :math:`b_0 .. b_P` (order ``<= 2P``) enter.
    """
    t, w = np.polynomial.hermite_e.hermegauss(12)
    w = w / w.sum()
    m = min(4, len(b) - 1)
    series = np.tensordot(b[: m + 1], orthonormal_sonine(m, t), axes=1)
    nu = np.array([np.sum(w * series * t ** (2 * k)) for k in range(m + 1)])
    n0, n1 = m // 2 + 1, (m - 1) // 2 + 1
    h0 = np.array([[nu[i + j] for j in range(n0)] for i in range(n0)])
    h1 = np.array([[nu[i + j + 1] for j in range(n1)] for i in range(n1)])
    for h in (h0, h1):
        d = np.diag(h)
        if not (np.all(np.isfinite(h)) and np.all(d > 0)):
            return False
        if np.linalg.eigvalsh(h / np.sqrt(np.outer(d, d))).min() < -1e-12:
            return False
    return True


def _solve(order: int, alpha: float, gamma: float, *, cooling: bool, friction: float,
           linearized: bool, guess_y: float) -> SonineSolution:
    stages = [2]
    while stages[-1] < order:
        stages.append(min(order, 2 * stages[-1]))
    x = np.array([guess_y])
    total = 0
    for stage in stages:
        system = _System(stage, alpha, gamma, cooling=cooling, friction=friction,
                         linearized=linearized, reference=guess_y)
        x = np.concatenate([x[:-1], np.zeros(stage - 1 - (len(x) - 1)), x[-1:]])
        x, resid, its, cond = _newton(system, x)
        total += its
        logger.debug("Sonine order %d: relative residual %.2e after %d Newton steps",
                     stage, resid, its)
    if not (np.all(np.isfinite(x)) and resid <= ROUNDOFF_FLOOR):
        kind = "cooling" if cooling else "heated"
        raise RuntimeError(
            f"the Sonine Galerkin equations ({kind}, alpha={alpha}, gamma={gamma:g}, order "
            f"{order}) have no solution Newton could find (relative residual {resid:.1e}); "
            "the truncated series fails where f is far from a Gaussian: try another order "
            "or method='fem'")
    coef = system.coefficients(x) / _sqrt_norms(order)
    if not _realisable(system.coefficients(x)):
        kind = "cooling" if cooling else "heated"
        raise RuntimeError(
            f"the Sonine Galerkin equations ({kind}, alpha={alpha}, gamma={gamma:g}, order "
            f"{order}) gave only a spurious root (a2 = {coef[2]:.3g}): no distribution has "
            "its moments up to <c^8> (their Hankel matrices are not positive); the "
            "truncated system has no physical solution here: try another order or "
            "method='fem'")
    if cooling:
        return SonineSolution(order, coef, 1.0, float(x[-1]), resid, cond, total)
    return SonineSolution(order, coef, math.exp(x[-1]), math.nan, resid, cond, total)


def solve_sonine(alpha: float, order: int = 6, *, density: float = 1.0, diffusion: float = 1.0,
                 friction: float = 0.0, kernel: float = 1.0,
                 linearized: bool = False) -> SonineSolution:
    """Heated steady state by the Sonine Galerkin method: :math:`a_2 .. a_P` and :math:`T`.

    Parameters
    ----------
    alpha : float
        Restitution coefficient in ``[0, 1)`` (``[0, 1]`` with friction).
    order : int
        Truncation order ``2 <= P <= MAX_ORDER``.
    density, diffusion, friction : float
        :math:`n > 0`, :math:`D > 0`, bath friction :math:`\\xi \\ge 0` (0: white noise).
    kernel : float or PowerLawKernel
        Kernel exponent :math:`\\gamma \\in [0, 2]`.
    linearized : bool
        Drop the products of :math:`a_p` (``p >= 2``) with each other and with the
        thermostat terms: the first-order Sonine theory at ``P = 2``.

    Returns
    -------
    SonineSolution

    Raises
    ------
    RuntimeError
        If Newton finds no solution of the truncated system.

    Examples
    --------
    >>> from kinetic_fem.sonine import a2_first_order
    >>> sol = solve_sonine(0.5, order=2, linearized=True)
    >>> bool(abs(sol.coefficients[2] - a2_first_order(0.5)) < 1e-12)
    True
    """
    problem = HeatedProblem.from_parameters(alpha, density=density, diffusion=diffusion,
                                            friction=friction, kernel=kernel)
    return _solve_problem(problem, _check_order(order), linearized)


def _solve_problem(problem: HeatedProblem, order: int, linearized: bool) -> SonineSolution:
    gas = problem.gas
    u = problem.velocity_scale
    chi0 = problem.friction / (gas.density * u**gas.gamma)
    guess = math.log(problem.temperature_estimate() / u**2)
    sol = _solve(order, gas.alpha, gas.gamma, cooling=False, friction=chi0,
                 linearized=linearized, guess_y=guess)
    return SonineSolution(order, sol.coefficients, sol.temperature * u**2, math.nan,
                          sol.residual, sol.condition_number, sol.iterations)


def solve_sonine_cooling(alpha: float, order: int = 6, *, kernel: float = 1.0,
                         linearized: bool = False) -> tuple[SonineSolution, float]:
    """Sonine coefficients of the homogeneous cooling state and its cooling rate.

    Parameters
    ----------
    alpha : float
        Constant coefficient of restitution, ``0 <= alpha < 1``.
    order : int
        Highest Sonine order kept.
    kernel : float
        Kernel exponent :math:`\\gamma \\in (0, 2]`.
    linearized : bool
        Linearise in the coefficients (the classic first-order results).

    Returns
    -------
    solution : SonineSolution
        Coefficients at unit temperature.
    zeta : float
        Cooling rate in :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`.

    Raises
    ------
    UnsupportedModelError
        For the Maxwell kernel (``gamma = 0``): its cooling state
        :math:`2/(\\pi(1+c^2)^2)` has no fourth moment, hence no Sonine expansion (the
        truncated system has only the spurious root :math:`a_2 = -2`).

    Examples
    --------
    First order (linearised, ``P = 2``): :math:`a_2 = 16(1-2\\alpha^2)/(33+30\\alpha^2)`,
    the 1D case of van Noije and Ernst's result.

    >>> sol, zeta = solve_sonine_cooling(0.5, order=2, linearized=True)
    >>> round(float(sol.coefficients[2]), 12), round(16 * 0.5 / (33 + 7.5), 12)
    (0.197530864198, 0.197530864198)
    """
    problem = CoolingProblem.from_parameters(alpha, kernel=kernel)
    return _solve_cooling_problem(problem, _check_order(order), linearized)


def _solve_cooling_problem(problem: CoolingProblem, order: int, linearized: bool
                           ) -> tuple[SonineSolution, float]:
    gas = problem.gas
    if gas.kernel.is_maxwell:
        raise UnsupportedModelError(
            "method 'spectral' cannot represent the cooling state of the Maxwell kernel "
            "(gamma = 0): f(c) = 2/(pi (1 + c^2)^2) has an infinite fourth moment, so its "
            "Sonine coefficients do not exist; use kinetic_fem.solvers.maxwell.hcs_pdf or 'fem'")
    sol = _solve(order, gas.alpha, gas.gamma, cooling=True, friction=0.0,
                 linearized=linearized, guess_y=problem.zeta_estimate())
    return sol, sol.zeta


def _output(sol: SonineSolution, problem: HeatedProblem | CoolingProblem,
            cutoff: float | None, n_v: int | None, start: float, kind: str,
            solve_at: Callable[[int], SonineSolution] | None = None,
            accuracy: float | None = None,
            check: SeriesCheck | None = None, *,
            lazy_check: bool = False) -> VelocityDistribution:
    if cutoff is None:
        cutoff = max(12.0, math.sqrt(4.0 * sol.order + 8.0) + 8.0)
    if n_v is None:
        n_v = 2 * int(math.ceil(cutoff / 0.01)) + 1
    if n_v < 5 or n_v % 2 == 0:
        raise ValueError(f"n_v={n_v} must be odd and >= 5 (Simpson weights)")
    extra = {"order": sol.order, "sonine": [float(x) for x in sol.coefficients],
             "condition_number": sol.condition_number}
    if kind == "cooling":
        extra["zeta"] = sol.zeta
    message = f"Sonine Galerkin ({kind}), order {sol.order}"
    if check is not None:
        extra["asymptotic_series"] = check.asymptotic
        extra["series_orders"] = list(check.orders)
        extra["series_a2"] = list(check.a2)
        if check.asymptotic:
            message += f"; WARNING: {check.message}"
    elif lazy_check:
        message += "; whether the series converges: dist.error (checked when first read)"
    info = RunInfo(converged=True, iterations=sol.iterations, residual=sol.residual,
                   wall_time=time.perf_counter() - start, message=message, extra=extra)
    dist = _grid_distribution(sol, cutoff, n_v, method="spectral", params=problem.as_dict(),
                              info=info)
    if solve_at is None:
        return dist
    grid = (float(cutoff), int(n_v))
    if lazy_check:
        def estimate(d: VelocityDistribution) -> ErrorEstimate:
            # the user's frame, as seen from here: ErrorRecipe.__call__ <- error <-
            # cached_property.__get__ <- user
            lazy = _warn_asymptotic(sol.order, series_check(sol.order, solve_at), stacklevel=5)
            return order_estimate(sol, solve_at, grid, lazy)

        return dist.with_error(ErrorRecipe(estimate, ORDER_METHOD))
    recipe = ErrorRecipe(lambda d: order_estimate(sol, solve_at, grid, check), ORDER_METHOD)
    return dist.with_error(recipe, None if accuracy is None else
                           order_estimate(sol, solve_at, grid, check))


def _grid_distribution(sol: SonineSolution, cutoff: float, n_v: int,
                       **kwargs: Any) -> VelocityDistribution:
    """The truncated series on ``n_v`` nodes of ``[-cutoff, cutoff]`` thermal speeds."""
    c = np.linspace(-cutoff, cutoff, n_v)
    s = math.sqrt(sol.temperature)
    return VelocityDistribution.from_values(s * c, sol.f(c) / s, weights=s * simpson_weights(c),
                                            **kwargs)


ORDER_METHOD = "Sonine order P + 2 (and P - 2 for the rate)"


def order_estimate(sol: SonineSolution, solve_at: Callable[[int], SonineSolution],
                   grid: tuple[float, int], check: SeriesCheck | None = None
                   ) -> ErrorEstimate:
    """Error estimate of a Sonine solution of order ``P`` from the orders ``P -+ 2``.

    The change to order :math:`P + 2`, :math:`d_+`, and from order :math:`P - 2`,
    :math:`d_-`, of each quantity give the error of order ``P`` as the geometric tail
    :math:`d_+/(1 - d_+/d_-)` while the changes decrease
    (:func:`kinetic_fem.error.geometric_tail`); when they stop decreasing, or order
    :math:`P + 2` has no solution, the series is asymptotic there: the estimate is the
    larger change, flagged ``asymptotic`` (the error may be larger), and a warning is
    logged.  The f error is the change to order :math:`P + 2` times the factor of
    :math:`a_2` (or T, the larger), and ``inf`` beyond the core where it stays below
    :data:`SONINE_F_TRUST` (the tail the series does not resolve).

    Parameters
    ----------
    sol : SonineSolution
        The solution of order ``P``.
    solve_at : callable
        ``order -> SonineSolution`` of the same problem (raises ``RuntimeError`` if the
        truncated system has no solution).
    grid : (float, int)
        The result's output grid (cut-off in thermal speeds, nodes).
    check : SeriesCheck, optional
        The scan of the orders beyond ``P`` (:func:`series_check`): if it found
        the series asymptotic there, so is the estimate (with its message).

    Returns
    -------
    ErrorEstimate
    """
    cutoff, n_v = grid

    def at(order: int) -> SonineSolution | None:
        if order < 2 or order > MAX_ORDER:
            return None
        try:
            return solve_at(order)
        except (RuntimeError, ValueError) as err:
            logger.info("Sonine order %d for the error estimate failed: %s", order, err)
            return None

    lower, upper = at(sol.order - 2), at(sol.order + 2)
    dist = _grid_distribution(sol, cutoff, n_v)

    def compare(other: SonineSolution) -> ErrorEstimate:
        zeta = (sol.zeta, other.zeta) if math.isfinite(sol.zeta) else None
        return ErrorEstimate.from_comparison(dist, _grid_distribution(other, cutoff, n_v),
                                             method=ORDER_METHOD, zeta=zeta)

    if upper is None and lower is None:
        return ErrorEstimate.unavailable(f"neither Sonine order {sol.order - 2} nor "
                                         f"{sol.order + 2} has a solution", method=ORDER_METHOD)
    if upper is None:
        est = compare(lower)  # type: ignore[arg-type]
        note = (f"order {sol.order + 2} has no solution: the change from order "
                f"{sol.order - 2}; the series is asymptotic here")
        logger.warning("Sonine series at order %d: %s", sol.order, note)
        return replace(est, asymptotic=True, note=note)
    last = compare(upper)
    if lower is None:
        return replace(last, note=f"the change to order {sol.order + 2} (no order "
                                  f"{sol.order - 2} to measure the rate)")
    prev = compare(lower)
    t, t_asym = geometric_tail([prev.temperature, last.temperature])
    a2, a2_asym = geometric_tail([prev.a2, last.a2])
    zeta, z_asym = None, False
    if last.zeta is not None and prev.zeta is not None:
        zeta, z_asym = geometric_tail([prev.zeta, last.zeta])
    ratios = [e / d for e, d in ((t, last.temperature), (a2, last.a2)) if d > 0]
    # changes at round-off (T of a cooling state is 1 by construction) are no trend
    asymptotic = any(flag and max(d_last, d_prev) > SERIES_FLOOR for flag, d_last, d_prev in
                     ((t_asym, last.temperature, prev.temperature), (a2_asym, last.a2, prev.a2),
                      (z_asym, last.zeta or 0.0, prev.zeta or 0.0)))
    note = ""
    if check is not None and check.asymptotic and not asymptotic:
        asymptotic, note = True, check.message + " (the estimate is the rate of orders " \
            f"{sol.order - 2}..{sol.order + 2}; the error may be larger)"
    elif asymptotic:
        note = (f"successive Sonine orders {sol.order - 2}, {sol.order}, {sol.order + 2} "
                "stop converging: the series is asymptotic here and the error may be "
                "larger than estimated; use method='fem'")
        logger.warning("Sonine series at order %d: %s", sol.order, note)
    return replace(last, temperature=t, a2=a2, zeta=zeta,
                   f_relative=resolved_core(last.f_relative * max(ratios, default=1.0)),
                   asymptotic=asymptotic, note=note)


SONINE_F_TRUST = 0.1
"""Beyond the first speed (from c = 0 outwards) where the estimated relative f error
reaches this, the Sonine f is not resolved: two orders agree there on a tail that is
wrong by many decades (measured: hard rods at alpha = 0.9, estimate < 1, true 2e8 at
c = 11), so the estimate there is ``inf``."""


def resolved_core(f_rel: NDArray[np.float64]) -> NDArray[np.float64]:
    """``f_rel`` (symmetric nodes) with ``inf`` from the first node out of the trusted core.

    Parameters
    ----------
    f_rel : ndarray
        Relative errors of f at nodes symmetric about c = 0.

    Returns
    -------
    ndarray
        A copy, ``inf`` from the first node (outwards on each side) where the relative
        error reaches :data:`SONINE_F_TRUST`.
    """
    out = f_rel.copy()
    mid = out.size // 2
    for side in (slice(mid, None), slice(mid, None, -1)):
        part = out[side]
        bad = np.flatnonzero(~(part < SONINE_F_TRUST) & np.isfinite(part))
        if bad.size:
            idx = np.arange(part.size)
            part[(idx >= bad[0]) & np.isfinite(part)] = np.inf
            out[side] = part
    return out


SERIES_AHEAD = 6
"""How far beyond the order ``P`` (in orders) the check looks for the series to stop
converging (:func:`series_check`)."""
SERIES_FLOOR = 1e-12
"""Changes of a2 (absolute) and T (relative) below this are round-off, not a trend."""


@dataclass(frozen=True)
class SeriesCheck:
    """Whether successive Sonine orders around ``P`` converge (``dist.error``;
    ``info.extra`` with ``check_series=True``).

    Attributes
    ----------
    orders : tuple of int
        The orders solved, from ``P - 2`` up (a failed order ends the list).
    a2, temperature : tuple of float
        Their :math:`a_2` and :math:`T`.
    asymptotic : bool
        The changes between successive orders stop decreasing (above
        :data:`SERIES_FLOOR`), or an order has no solution.
    message : str
        What was found (empty when the series converges).
    """

    orders: tuple[int, ...]
    a2: tuple[float, ...]
    temperature: tuple[float, ...]
    asymptotic: bool
    message: str


def series_check(order: int, solve_at: Callable[[int], SonineSolution]) -> SeriesCheck:
    r"""Solve orders ``P - 2 .. P + SERIES_AHEAD`` and find whether the series converges.

    The series of the Sonine approximations is asymptotic in general: its successive
    changes decrease, then grow (hard rods' heated state at ``alpha = 0.6``,
    ``gamma = 0.5``: :math:`|\Delta a_2|` = 2.1e-5, 5.2e-6, 8.3e-7, then 2.0e-6 from
    order 12 to 14, and order 20 has no solution), and the error of order ``P`` is then
    not bounded by the changes next to it (there 1.4e-5 at order 8, against changes of
    5e-6).  The scan stops at the first change that does not decrease or the first order
    without solution.

    Parameters
    ----------
    order : int
        ``P``.
    solve_at : callable
        ``order -> SonineSolution`` (memoised by the caller: the estimate reuses them).

    Returns
    -------
    SeriesCheck
    """
    orders: list[int] = []
    a2: list[float] = []
    temp: list[float] = []
    message = ""
    d_prev: tuple[float, float] | None = None
    for p in range(max(2, order - 2), min(MAX_ORDER, order + SERIES_AHEAD) + 1, 2):
        try:
            sol = solve_at(p)
        except (RuntimeError, ValueError):
            message = (f"Sonine order {p} has no solution: the series is asymptotic "
                       f"beyond order {orders[-1] if orders else order}")
            break
        orders.append(p)
        a2.append(float(sol.coefficients[2]))
        temp.append(float(sol.temperature))
        if len(orders) < 2:
            continue
        d = (abs(a2[-1] - a2[-2]), abs(temp[-1] / temp[-2] - 1.0))
        if d_prev is not None and any(now > SERIES_FLOOR and now >= before
                                      for now, before in zip(d, d_prev, strict=True)):
            message = (f"successive Sonine orders stop converging: the change of a2 (T) "
                       f"from order {orders[-2]} to {p} is {d[0]:.2g} ({d[1]:.2g}), after "
                       f"{d_prev[0]:.2g} ({d_prev[1]:.2g}); the series is asymptotic here")
            break
        d_prev = d
    return SeriesCheck(tuple(orders), tuple(a2), tuple(temp), bool(message), message)


def _memoised(solve_at: Callable[[int], SonineSolution]) -> Callable[[int], SonineSolution]:
    """``solve_at`` that solves each order once (failures are raised again)."""
    done: dict[int, SonineSolution | Exception] = {}

    def at(p: int) -> SonineSolution:
        if p not in done:
            try:
                done[p] = solve_at(p)
            except (RuntimeError, ValueError) as err:
                done[p] = err
        out = done[p]
        if isinstance(out, Exception):
            raise out
        return out

    return at


SeriesMode = Union[bool, Literal["lazy"]]
"""``check_series``: ``"lazy"`` (on first read of ``dist.error``), True (at solve time)
or False (never)."""


def _series_mode(check_series: object, linearized: bool) -> SeriesMode:
    """``check_series`` validated (False with ``linearized``)."""
    if not (isinstance(check_series, bool) or check_series == "lazy"):
        raise ValueError(f"check_series must be 'lazy', True or False, got {check_series!r}")
    return False if linearized else check_series  # type: ignore[return-value]


def _warn_asymptotic(order: int, check: SeriesCheck, stacklevel: int) -> SeriesCheck:
    """Issue the :class:`AsymptoticSeriesWarning` of ``check`` if it found the series
    asymptotic (``stacklevel`` as if the caller of this function issued it)."""
    if check.asymptotic:
        warnings.warn(f"Sonine order {order}: {check.message}; its error may exceed "
                      "the estimate (dist.error); use method='fem'",
                      AsymptoticSeriesWarning, stacklevel=stacklevel + 1)
    return check


def _checked(sol: SonineSolution, solve_at: Callable[[int], SonineSolution],
             mode: SeriesMode) -> SeriesCheck | None:
    """:func:`series_check` of ``sol`` at solve time if ``mode`` is True, warning when the
    series is asymptotic (None otherwise: ``"lazy"`` checks in :func:`_output`'s recipe)."""
    if mode is not True:
        return None
    # the user's frame, as seen from here: solve_spectral_* <- solve_heated/_cooling <- user
    return _warn_asymptotic(sol.order, series_check(sol.order, solve_at), stacklevel=4)


def _refine_order(solve_at: Callable[[int], SonineSolution], order: int, accuracy: float,
                  cutoff: float | None, n_v: int | None) -> SonineSolution:
    """The lowest order from ``order`` up (in steps of 2) whose estimate meets
    ``accuracy`` (T relative and a2); raises ``ConvergenceError`` with what it reached."""
    reached = None
    p = order
    while p <= MAX_ORDER - 2:
        sol = solve_at(p)
        c = max(12.0, math.sqrt(4.0 * p + 8.0) + 8.0) if cutoff is None else cutoff
        n = 2 * int(math.ceil(c / 0.01)) + 1 if n_v is None else n_v
        est = order_estimate(sol, solve_at, (c, n))
        if est.meets(accuracy):
            return sol
        reached = (p, est)
        if est.asymptotic:
            break
        p += 2
    assert reached is not None
    p, est = reached
    raise ConvergenceError(
        f"the Sonine method did not reach accuracy={accuracy:g}: at order {p} the estimated "
        f"errors are T {est.temperature:.2g} (relative), a2 {est.a2:.2g}"
        + (" and the series is asymptotic there" if est.asymptotic else "")
        + "; use method='fem'")


@register_solver("spectral", problem="heated")
def solve_spectral_heated(problem: HeatedProblem, *, order: int = 8,
                          cutoff: float | None = None, n_v: int | None = None,
                          linearized: bool = False,
                          accuracy: float | None = None,
                          check_series: SeriesMode = "lazy") -> VelocityDistribution:
    """Heated steady state by the Sonine Galerkin method (registry key ``"spectral"``).

    Kernels :math:`|g|^\\gamma`, ``0 <= gamma <= 2``, constant restitution, white noise or
    a Fokker-Planck bath.

    Parameters
    ----------
    problem : HeatedProblem
    order : int
        Truncation order ``P``.
    cutoff : float, optional
        Output grid half-width in thermal speeds (default
        :math:`\\max(12, \\sqrt{4P+8} + 8)`, beyond the last polynomial's Gaussian bulk).
    n_v : int, optional
        Odd number of output nodes (default spacing 0.01 thermal speeds).
    linearized : bool
        First-order (linearised) Sonine theory.
    accuracy : float, optional
        Target accuracy of T (relative) and a2 (absolute): the order is raised from
        ``order`` in steps of 2 until the error estimate (:func:`order_estimate`) meets
        it; ``ConvergenceError`` says what was reached if it cannot be (the series is
        asymptotic).  Default: the given order.
    check_series : {"lazy", True, False}
        Solve orders ``P - 2 .. P + 6`` to find whether the series still converges there
        (:func:`series_check`; its solutions serve ``dist.error``).  ``"lazy"``
        (default): when ``dist.error`` is first read, with the estimate (the solve costs
        nothing extra; the check costs about 3 times the solve); if the series does
        not converge, that read issues an
        :class:`~kinetic_fem.exceptions.AsymptoticSeriesWarning` and
        ``dist.error.asymptotic`` is True (``info`` does not change).  True: at solve
        time; then the solve issues the warning, and ``info.extra['asymptotic_series']``,
        ``'series_orders'``, ``'series_a2'`` and ``info.message`` record the check.
        False: never (the estimate looks at ``P -+ 2`` only).  Ignored with
        ``linearized``.

    Returns
    -------
    VelocityDistribution
        The truncated series on the grid; ``info.extra['sonine']`` holds
        :math:`a_0 .. a_P`, ``info.extra['condition_number']`` the Jacobian's (and, with
        ``check_series=True``, ``'asymptotic_series'``, ``'series_orders'`` and
        ``'series_a2'`` the check of the series); ``dist.error`` the estimate from orders
        ``P -+ 2`` (:func:`order_estimate`, computed when first read).

    Raises
    ------
    ConvergenceError
        If ``accuracy`` cannot be met.
    ValueError
        If ``check_series`` is not ``"lazy"``, True or False.
    """
    mode = _series_mode(check_series, linearized)
    problem.require("spectral", constant_restitution=True,
                    thermostats=(WhiteNoise, FokkerPlanckBath))
    start = time.perf_counter()
    order = _check_order(order)

    def solve(p: int) -> SonineSolution:
        return _solve_problem(problem, p, linearized)

    solve_at = _memoised(solve)
    if accuracy is None:
        sol = solve_at(order)
    else:
        sol = _refine_order(solve_at, order, check_positive("accuracy", accuracy), cutoff, n_v)
    return _output(sol, problem, cutoff, n_v, start, "heated", solve_at, accuracy,
                   _checked(sol, solve_at, mode), lazy_check=mode == "lazy")


@register_solver("spectral", problem="cooling")
def solve_spectral_cooling(problem: CoolingProblem, *, order: int = 8,
                           cutoff: float | None = None, n_v: int | None = None,
                           linearized: bool = False,
                           accuracy: float | None = None,
                          check_series: SeriesMode = "lazy") -> VelocityDistribution:
    """Homogeneous cooling state by the Sonine Galerkin method (key ``"spectral"``).

    Kernels ``0 < gamma <= 2`` with constant restitution (the Maxwell cooling state has
    no Sonine expansion: :func:`solve_sonine_cooling`).  Accurate while the state is
    close to a Gaussian; the two humps of the near-elastic state (claims C10, C15)
    need high orders.

    Parameters
    ----------
    problem : CoolingProblem
        The cooling problem (constant restitution, kernel exponent ``0 < gamma <= 2``).
    order : int
        Truncation order ``P``.
    cutoff : float, optional
        Output grid half-width in thermal speeds (as :func:`solve_spectral_heated`).
    n_v : int, optional
        Odd number of output nodes (default spacing 0.01 thermal speeds).
    linearized : bool
        First-order (linearised) Sonine theory.
    accuracy : float, optional
        Target accuracy of a2 (and T, exact here) as in :func:`solve_spectral_heated`.
    check_series : {"lazy", True, False}
        As in :func:`solve_spectral_heated` (default ``"lazy"``: on first read of
        ``dist.error``).

    Returns
    -------
    VelocityDistribution
        At unit temperature; ``info.extra`` holds ``zeta`` and the coefficients;
        ``dist.error`` the estimate from orders ``P -+ 2`` (with zeta).

    Raises
    ------
    ConvergenceError
        If ``accuracy`` cannot be met.
    ValueError
        If ``check_series`` is not ``"lazy"``, True or False.
    """
    mode = _series_mode(check_series, linearized)
    problem.require("spectral", constant_restitution=True)
    start = time.perf_counter()
    order = _check_order(order)

    def solve(p: int) -> SonineSolution:
        return _solve_cooling_problem(problem, p, linearized)[0]

    solve_at = _memoised(solve)
    if accuracy is None:
        sol = solve_at(order)
    else:
        sol = _refine_order(solve_at, order, check_positive("accuracy", accuracy), cutoff, n_v)
    return _output(sol, problem, cutoff, n_v, start, "cooling", solve_at, accuracy,
                   _checked(sol, solve_at, mode), lazy_check=mode == "lazy")
