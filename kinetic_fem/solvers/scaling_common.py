"""Shared machinery of the quasi-elastic solvers in :mod:`kinetic_fem.solvers.scaling`.

Both limit equations are fixed points :math:`u = \\mathcal T[u]` for the logarithm
:math:`u = \\ln f` of a normalised density on a uniform grid.  They are solved by
Newton's method with matrix-free GMRES (each Jacobian product is one O(N)
cumulative-moment sum) and a backtracking line search on the max-norm residual: the
shared driver :func:`kinetic_fem.solvers.newton.newton` through :func:`newton_krylov`.
"""

from __future__ import annotations

import logging
import numbers
from dataclasses import replace
from typing import Callable, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..distribution import VelocityDistribution
from ..error import ErrorEstimate, ErrorRecipe
from ..gas import check_positive
from .newton import NewtonResult, newton

__all__: list[str] = []

logger = logging.getLogger(__name__)

Evaluation = tuple[NDArray[np.float64], Callable[[NDArray[np.float64]], NDArray[np.float64]]]


class LimitSolution:
    """Shared behaviour of the phi and psi results (a mixin for frozen dataclasses)."""

    distribution: VelocityDistribution
    names: ClassVar[tuple[str, ...]] = ()

    @property
    def values(self) -> NDArray[np.float64]:
        """The solution at the grid nodes."""
        return self.distribution.values

    def __call__(self, x: ArrayLike) -> NDArray[np.float64]:
        """The solution at ``x``: cubic interpolation of its logarithm (zero outside)."""
        return self.distribution.pdf(x)

    def constants(self) -> dict[str, float]:
        """The returned constants by name."""
        return {k: float(getattr(self, k)) for k in self.names}


def check_int(name: str, value: object, *, minimum: int) -> int:
    """Validate an integer option ``>= minimum``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__} {value!r}")
    if value < minimum:
        raise ValueError(f"{name}={value} is not allowed; {name} must be >= {minimum}")
    return int(value)


def check_solver_options(tol: object, max_iter: object) -> tuple[float, int]:
    """Validate the Newton tolerance and iteration cap."""
    return check_positive("tol", tol), check_int("max_iter", max_iter, minimum=1)


def newton_krylov(
    z0: NDArray[np.float64],
    evaluate: Callable[[NDArray[np.float64]], Evaluation],
    *,
    tol: float,
    max_iter: int,
    name: str,
) -> NewtonResult:
    """Solve ``r(z) = 0`` by Newton-GMRES with backtracking (the shared driver).

    Parameters
    ----------
    z0 : ndarray, shape (m,)
        Initial iterate.
    evaluate : callable
        ``evaluate(z) -> (r, jvp)``: the residual and the Jacobian-vector product at ``z``.
    tol : float
        Stop when ``max|r| < tol``.
    max_iter : int
        Newton iterations allowed.
    name : str
        Used in log messages.

    Returns
    -------
    NewtonResult
        Of :func:`kinetic_fem.solvers.newton.newton`; the solution is ``x``.

    Notes
    -----
    :func:`kinetic_fem.solvers.newton.newton` with a matrix-free Jacobian: the step
    :math:`\\delta` solves :math:`J\\delta = -r` by GMRES to a relative accuracy of
    :math:`10^{-14}`; the step is halved (down to 1/16384) until ``max|r|`` decreases,
    and the iteration stops when it does not (the round-off floor).
    """
    last: list[tuple[NDArray[np.float64], Evaluation]] = []

    def system(z: NDArray[np.float64], jacobian: bool) -> Evaluation:
        # the accepted trial point is evaluated again for its Jacobian: reuse it
        if last and np.array_equal(last[0][0], z):
            return last[0][1]
        out = evaluate(z)
        last[:] = [(z.copy(), out)]
        return out

    out = newton(system, z0, tol=tol, max_iter=max_iter, criterion="residual", armijo=0.0,
                 min_damping=2.0**-14, on_failure="stop", name=name)
    if not out.converged:
        logger.warning("%s", out.message)
    return out


def log_normalise(e: NDArray[np.float64], w: NDArray[np.float64]) -> NDArray[np.float64]:
    """:math:`e - \\ln\\sum_j w_j e^{e_j}`, evaluated without overflow."""
    top = float(np.max(e))
    return e - (top + float(np.log(np.sum(w * np.exp(e - top)))))


def fourth_derivative(f: NDArray[np.float64], h: float, stride: int) -> NDArray[np.float64]:
    """Central five-point fourth derivative with step ``stride * h`` (NaN at the ends).

    .. math:: f'''' \\approx (f_{i-2s} - 4f_{i-s} + 6f_i - 4f_{i+s} + f_{i+2s})/(sh)^4
    """
    s = stride
    out = np.full_like(f, np.nan)
    out[2 * s:-2 * s] = (f[:-4 * s] - 4 * f[s:-3 * s] + 6 * f[2 * s:-2 * s]
                         - 4 * f[3 * s:-s] + f[4 * s:]) / (s * h) ** 4
    return out


def fourth_derivative_extrapolated(f: NDArray[np.float64], h: float,
                                   stride: int) -> NDArray[np.float64]:
    """Richardson-extrapolated :func:`fourth_derivative`, :math:`(4D_s - D_{2s})/3`: O(h^4)."""
    return (4 * fourth_derivative(f, h, stride) - fourth_derivative(f, h, 2 * stride)) / 3


def first_derivative(f: NDArray[np.float64], h: float) -> NDArray[np.float64]:
    """Fourth-order central first derivative (NaN at the two outer nodes of each end)."""
    out = np.full_like(f, np.nan)
    out[2:-2] = (f[:-4] - 8 * f[1:-3] + 8 * f[3:-1] - f[4:]) / (12 * h)
    return out


def line_fit(x: NDArray[np.float64], y: NDArray[np.float64]) -> tuple[float, float]:
    """Least-squares ``y = intercept + slope * x``; returns ``(slope, intercept)``."""
    slope, intercept = np.polyfit(x, y, 1)
    return float(slope), float(intercept)


def combine_errors(
    base: dict[str, float], refined: dict[str, float], enlarged: dict[str, float]
) -> tuple[dict[str, float], dict[str, dict[str, float]]]:
    """Error estimates: grid part + |change on enlarging the domain|.

    The grid part is the Richardson estimate :math:`|q_h - q_{h/2}|\\, 2^4/(2^4 - 1)`
    of the error of :math:`q_h` for the fourth-order (Simpson) discretisations here.
    """
    h_err = {k: abs(refined[k] - base[k]) * 16.0 / 15.0 for k in base}
    l_err = {k: abs(enlarged[k] - base[k]) for k in base}
    return ({k: h_err[k] + l_err[k] for k in base},
            {"grid_spacing": h_err, "domain_size": l_err})


REFINEMENT_METHOD = "half the spacing (x 16/15, Simpson) + a domain larger by a quarter"


def refinement_estimate(dist: VelocityDistribution, refined: VelocityDistribution,
                        enlarged: VelocityDistribution) -> ErrorEstimate:
    """``dist.error`` of a phi or psi solution, as :func:`combine_errors` for its constants:
    the change on halving the spacing times :math:`2^4/(2^4-1)` plus the change on
    enlarging the domain, for T, a2 and f (:mod:`kinetic_fem.error`).

    Parameters
    ----------
    dist : VelocityDistribution
        The solution.
    refined, enlarged : VelocityDistribution
        The solutions with half the spacing and on the larger domain.

    Returns
    -------
    ErrorEstimate
    """
    grid = ErrorEstimate.from_comparison(dist, refined, method=REFINEMENT_METHOD,
                                         factor=16.0 / 15.0)
    domain = ErrorEstimate.from_comparison(dist, enlarged, method=REFINEMENT_METHOD)
    return replace(grid, temperature=grid.temperature + domain.temperature,
                   a2=grid.a2 + domain.a2, f_relative=grid.f_relative + domain.f_relative)


def with_estimate(dist: VelocityDistribution, estimate: ErrorEstimate) -> VelocityDistribution:
    """``dist`` carrying an estimate computed eagerly (kept through pickling).

    Parameters
    ----------
    dist : VelocityDistribution
        The result.
    estimate : ErrorEstimate
        Its estimate.
    """
    return dist.with_error(ErrorRecipe(lambda d: estimate, REFINEMENT_METHOD), estimate)
