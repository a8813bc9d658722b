"""Homogeneous cooling state (HCS) of the free gas: cooling ``method="fd"``.

Without forcing, the homogeneous Boltzmann equation
:math:`\\partial_t P = Q[P]` has scaling solutions
:math:`P(v, t) = f(v/s(t))/s(t)` with :math:`s = \\sqrt{T}`.  Since
:math:`Q[P](v) = n\\,\\tilde Q[f](c)` (the collision operator is homogeneous), the scaled
distribution satisfies

.. math::

    \\zeta\\,\\frac{d}{dc}\\big(c f(c)\\big) = \\tilde Q[f](c), \\qquad
    \\int f = 1,\\quad \\int c^2 f = 1,

where :math:`\\zeta = -\\dot s/(n s^2)` is the dimensionless cooling rate: Haff's law
:math:`T(t) = T_0/(1 + \\zeta n \\sqrt{T_0}\\, t)^2` (claim C9).  Multiplying by
:math:`c^2` and integrating gives the energy identity (claim C1 without forcing)

.. math::

    \\zeta = \\frac{1-\\alpha^2}{8}\\,\\langle |c - c'|^3 \\rangle_f ,

which the solver does not impose: it is a check of the discretisation.  The scaled
HCS does not depend on the density ``n``.

Discretisation (shares the collision operator of :mod:`kinetic_fem.finite_difference`):
the unknown is :math:`u = \\ln f` on the half grid :math:`c_i = i h` (``f`` even);
:math:`\\tilde Q` is the strong collision term (Simpson with the kink correction,
:math:`\\nu` by cumulative moments, the gain with interpolation of :math:`\\ln f`);
the drift is written :math:`(cf)' = f\\,(1 + c\\,u')` with :math:`u'` by central
differences; at the cut-off, where the gain term misses its partners beyond the
grid, the equation is replaced by the closure :math:`u'' = 0` (exact for an
exponential tail).  Working with :math:`u` keeps ``f`` positive
and its exponential tail :math:`f \\sim e^{-c/\\zeta}/c` exact on any grid, where a
difference of :math:`cf` itself would oscillate.  Newton's method solves

.. math::

    R_i = \\tilde Q_i - \\lambda f_i - \\zeta f_i (1 + c_i u'_i) = 0,\\qquad
    \\sum_i w_i f_i = 1,\\qquad \\sum_i w_i c_i^2 f_i = 1

for :math:`(u, \\zeta, \\lambda)`; :math:`\\lambda` absorbs the small mass defect of the
discrete operators (as in the heated solver).  Near elastic collisions
(``alpha > 0.8``) the solution is reached by continuation in
:math:`\\varepsilon = 1 - \\alpha`, each step on its own grid.

References
----------
Barrat, Biben, Racz, Trizac, van Wijland, J. Phys. A 35 (2002) 463, section 3.
"""

from __future__ import annotations

import logging
import math
import time
import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import lu_factor, lu_solve

from ._fd_newton import collision_jacobian, update_factor
from .collision import HalfGrid, gain_term, half_grid, loss_frequency, pair_moment
from .distribution import RunInfo, VelocityDistribution
from .gas import CoolingProblem, check_alpha, check_positive
from .solve import register_solver

__all__ = ["HCSSolution", "ResolutionWarning", "default_cutoff", "default_spacing",
           "drift_term", "hcs_residual", "initial_guess", "newton_hcs", "solve_hcs", "hcs_fd",
           "sonine_zeta_estimate"]

logger = logging.getLogger(__name__)

_MONITOR_FLOOR = 1e-50
_CONTINUATION_START = 0.2  # eps at which continuation starts from a Gaussian
_CONTINUATION_RATIO = 3.0  # eps ratio of one continuation step (halved on failure)


class ResolutionWarning(UserWarning):
    """The grid or cut-off does not resolve the cooling state to the requested level."""


def sonine_zeta_estimate(alpha: float) -> float:
    """Gaussian estimate :math:`\\zeta \\approx (1-\\alpha^2)\\,\\langle|g|^3\\rangle_G/8`,
    :math:`\\langle|g|^3\\rangle_G = 8/\\sqrt\\pi` for unit temperature."""
    return (1.0 - alpha**2) / math.sqrt(math.pi)


def default_cutoff(alpha: float) -> float:
    """Cut-off :math:`c_{max}` (thermal velocities) below :math:`f \\approx 10^{-35}`.

    The larger of the exponential tail :math:`e^{-c/\\zeta}` (80 decay lengths past
    :math:`c = 1.5`) and, near elastic collisions, the outer edge of the humps
    :math:`c = 1 + 12\\varepsilon^{1/3}` (where :math:`\\psi \\sim e^{y^3/3}` has fallen
    below 1e-35, claim C12).
    """
    eps = 1.0 - alpha
    return max(1.0 + 12.0 * eps ** (1.0 / 3.0), 1.5 + 80.0 * sonine_zeta_estimate(alpha))


def default_spacing(alpha: float) -> float:
    """Grid spacing (thermal velocities): :math:`\\min(0.04, \\varepsilon^{1/3}/25)`.

    The humps of the near-elastic state have width :math:`\\propto \\varepsilon^{1/3}`
    (claim C11); see ``benchmarks/convergence_cooling.py`` for the errors it gives.
    """
    return min(0.04, (1.0 - alpha) ** (1.0 / 3.0) / 25.0)


def _log_derivative(grid: HalfGrid, u: NDArray[np.float64]) -> NDArray[np.float64]:
    """:math:`u'_i`: central differences, ``u' = 0`` at ``c = 0``, one-sided at the end."""
    du = np.empty_like(u)
    du[0] = 0.0
    du[1:-1] = (u[2:] - u[:-2]) / (2.0 * grid.h)
    du[-1] = (u[-1] - u[-2]) / grid.h
    return du


def drift_term(grid: HalfGrid, u: NDArray[np.float64]) -> NDArray[np.float64]:
    """:math:`(cf)'_i = f_i (1 + c_i u'_i)` with :math:`f = e^u` on the half grid.

    Examples
    --------
    >>> g = half_grid(12.0, 1201)
    >>> u = -g.v**2 / 2
    >>> exact = np.exp(u) * (1 - g.v**2)
    >>> bool(np.max(np.abs(drift_term(g, u)[:-1] - exact[:-1])) < 1e-4)
    True
    """
    return np.exp(u) * (1.0 + grid.v * _log_derivative(grid, u))


def _drift_jacobian(grid: HalfGrid, u: NDArray[np.float64]) -> NDArray[np.float64]:
    """Dense :math:`\\partial (cf)'_i / \\partial u_l`."""
    n, h, c = grid.n, grid.h, grid.v
    f = np.exp(u)
    du = _log_derivative(grid, u)
    jac = np.zeros((n, n))
    idx = np.arange(n)
    jac[idx, idx] = f * (1.0 + c * du)
    inner = idx[1:-1]
    jac[inner, inner + 1] += f[inner] * c[inner] / (2.0 * h)
    jac[inner, inner - 1] -= f[inner] * c[inner] / (2.0 * h)
    jac[n - 1, n - 1] += f[n - 1] * c[n - 1] / h
    jac[n - 1, n - 2] -= f[n - 1] * c[n - 1] / h
    return jac


def hcs_residual(grid: HalfGrid, u: NDArray[np.float64], zeta: float, multiplier: float, *,
                 alpha: float, order: int = 3) -> NDArray[np.float64]:
    """:math:`R_i(u, \\zeta, \\lambda)` of the module docstring; the last row is the
    closure :math:`u_{n-1} - 2u_{n-2} + u_{n-3} = 0` at the cut-off."""
    f = np.exp(u)
    q = (gain_term(grid, f, alpha=alpha, density=1.0, order=order)
         - loss_frequency(grid, f, density=1.0) * f)
    res = q - multiplier * f - zeta * drift_term(grid, u)
    # closure at the cut-off: the gain there misses its partners beyond the grid, so
    # the last row extrapolates ln f linearly instead (exact for an exponential tail)
    res[-1] = u[-1] - 2.0 * u[-2] + u[-3]
    return res


@dataclass(frozen=True)
class HCSSolution:
    """A homogeneous cooling state on one half grid.

    Attributes
    ----------
    grid : HalfGrid
    f : ndarray, shape (n,)
        Scaled distribution on ``grid.v`` (unit temperature).
    zeta : float
        Dimensionless cooling rate: :math:`dT/dt = -2\\zeta n T^{3/2}`.
    multiplier : float
        Mass-defect rate :math:`\\lambda` of the discrete operator (a discretisation
        error, zero in the continuum).
    iterations : int
    residual : float
        Largest scaled residual on the monitored nodes.
    converged : bool
    message : str
    """

    grid: HalfGrid
    f: NDArray[np.float64]
    zeta: float
    multiplier: float
    iterations: int
    residual: float
    converged: bool
    message: str

    def energy_identity(self, alpha: float) -> float:
        """:math:`(1-\\alpha^2)\\langle|c-c'|^3\\rangle/8`, to compare with :attr:`zeta`."""
        w = self.grid.weights
        g3 = pair_moment(self.grid.v_full, self.grid.full(self.f), w, 3)
        return (1.0 - alpha**2) * g3 / 8.0


def newton_hcs(grid: HalfGrid, u0: NDArray[np.float64], zeta0: float, *, alpha: float,
               order: int = 3, tol: float = 1e-10, max_iter: int = 60) -> HCSSolution:
    """Solve the discrete HCS equations by damped Newton from ``(u0, zeta0)``.

    Rows are scaled by :math:`f_i(\\nu_i + \\zeta(1 + c_i/h))`, so that tail equations
    weigh as much as bulk ones; converged when the largest change of ``u`` on the
    nodes with :math:`f > 10^{-50}` is below ``tol``.
    """
    w = grid.half_weights
    c2w = w * grid.v**2
    u = np.asarray(u0, dtype=float).copy()
    zeta, lam = float(zeta0), 0.0

    def evaluate(u_: NDArray[np.float64], zeta_: float, lam_: float,
                 scale: NDArray[np.float64] | None = None):
        """Residuals and their max norm, rows scaled by ``scale`` (default: own scale).

        The line search compares norms with the scaling of the current iterate: a
        scaling that moves with the trial point (through f and zeta) can grow while the
        residual itself falls."""
        f_ = np.exp(u_)
        nu_ = loss_frequency(grid, f_, density=1.0)
        res_ = hcs_residual(grid, u_, zeta_, lam_, alpha=alpha, order=order)
        d_ = np.maximum(f_ * (nu_ + abs(zeta_) * (1.0 + grid.v / grid.h)), 1e-300)
        d_[-1] = 1.0  # the closure row is already O(1)
        mon_ = f_ > _MONITOR_FLOOR
        constraint = np.array([np.dot(w, f_) - 1.0, np.dot(c2w, f_) - 1.0])
        s_ = d_ if scale is None else scale
        norm_ = max(float(np.max(np.abs(res_[mon_] / s_[mon_]))),
                    float(np.max(np.abs(constraint))))
        return f_, nu_, res_, d_, mon_, constraint, norm_

    f, nu, res, d, mon, cons, norm = evaluate(u, zeta, lam)
    converged = False
    message = "maximum iterations reached"
    it = 0
    n = grid.n
    while it < max_iter:
        it += 1
        jac = collision_jacobian(grid, f, nu, alpha, True, order) * f[None, :]
        jac[np.arange(n), np.arange(n)] -= lam * f
        jac -= zeta * _drift_jacobian(grid, u)
        big = np.zeros((n + 2, n + 2))
        jac[-1, :] = 0.0
        jac[-1, -3:] = [1.0, -2.0, 1.0]
        drift = drift_term(grid, u)
        drift[-1] = 0.0
        big[:n, :n] = jac / d[:, None]
        big[:n, n] = -drift / d
        big[:n, n + 1] = -np.where(np.arange(n) < n - 1, f, 0.0) / d
        big[n, :n] = w * f
        big[n + 1, :n] = c2w * f
        rhs = np.concatenate([-res / d, -cons])
        step = lu_solve(lu_factor(big, check_finite=False), rhs, check_finite=False)
        if not np.all(np.isfinite(step)):
            message = "singular Newton system"
            break
        du, dzeta, dlam = step[:n], step[n], step[n + 1]
        # the step du is applied as a relative change of f, f -> f * update_factor(du)
        # (sublinear in ln f for large rises, exponential damping of large falls, as in
        # the heated solver), then backtracking on the residual norm
        theta = 1.0
        for _ in range(12):
            u_try = u + np.log(update_factor(theta * du))
            trial = evaluate(u_try, zeta + theta * dzeta, lam + theta * dlam, d)
            if trial[-1] < norm or theta < 1e-3:
                break
            theta *= 0.5
        change = float(np.max(np.abs(u_try - u)[mon]))
        u, zeta, lam = u_try, zeta + theta * dzeta, lam + theta * dlam
        f, nu, res, d, mon, cons, norm = evaluate(u, zeta, lam)
        if change < tol:
            converged = True
            message = f"Newton converged: max |d ln f| < {tol:g}"
            break
    if not math.isfinite(norm):
        converged = False
    return HCSSolution(grid, f, float(zeta), float(lam), it, norm, converged, message)


def _grid(alpha: float, spacing: float | None, cutoff: float | None) -> HalfGrid:
    h = default_spacing(alpha) if spacing is None else spacing
    cut = default_cutoff(alpha) if cutoff is None else cutoff
    n_v = int(math.ceil(cut / h - 1e-9)) + 1
    return half_grid((n_v - 1) * h, n_v)


def initial_guess(c: NDArray[np.float64], zeta: float) -> NDArray[np.float64]:
    """``ln f`` of a Gaussian continued by the exponential tail :math:`e^{-c/\\zeta}`
    (matched in value and slope at :math:`c = 1/\\zeta`)."""
    c0 = 1.0 / zeta
    u = -0.5 * c**2
    far = c > c0
    u[far] = 0.5 * c0**2 - c0 * c[far]
    return u - 0.5 * math.log(2.0 * math.pi)


def _transfer(sol: HCSSolution, grid: HalfGrid) -> NDArray[np.float64]:
    """``ln f`` of ``sol`` on ``grid``: linear interpolation, linear extrapolation beyond."""
    c_old = sol.grid.v
    u_old = np.log(np.maximum(sol.f, 1e-300))
    u = np.interp(grid.v, c_old, u_old)
    slope = (u_old[-1] - u_old[-2]) / (c_old[-1] - c_old[-2])
    far = grid.v > c_old[-1]
    u[far] = u_old[-1] + slope * (grid.v[far] - c_old[-1])
    return u


def solve_hcs(alpha: float, *, spacing: float | None = None, cutoff: float | None = None,
              interpolation_order: int = 3, tol: float = 1e-10, max_iter: int = 60
              ) -> HCSSolution:
    """Homogeneous cooling state on a uniform half grid (unit temperature).

    Parameters
    ----------
    alpha : float
        Restitution coefficient, ``0 <= alpha < 1``.
    spacing, cutoff : float, optional
        Grid spacing and cut-off in thermal velocities (defaults
        :func:`default_spacing`, :func:`default_cutoff`).
    interpolation_order : {2, 3}
        Interpolation of ``ln f`` at the gain term's off-grid argument.
    tol, max_iter : float, int
        Newton stopping criterion (largest change of ``ln f``) and iteration limit.

    Returns
    -------
    HCSSolution

    Raises
    ------
    ValueError
        For alpha outside [0, 1), non-positive spacing or cut-off, or a grid with
        fewer than 8 nodes per hump width near elastic collisions.

    Examples
    --------
    >>> sol = solve_hcs(0.5)
    >>> sol.converged, round(sol.zeta, 4), round(sol.energy_identity(0.5), 4)
    (True, 0.4356, 0.4356)
    """
    alpha = check_alpha(alpha)
    if spacing is not None:
        spacing = check_positive("spacing", spacing)
        width = (1.0 - alpha) ** (1.0 / 3.0)
        if spacing > width / 8.0:
            raise ValueError(f"spacing={spacing:g} does not resolve the humps of the cooling "
                             f"state at alpha={alpha} (width ~ eps^(1/3) = {width:.3g}); use "
                             f"spacing <= {width / 8.0:.3g} (default {default_spacing(alpha):.3g})")
    if cutoff is not None:
        cutoff = check_positive("cutoff", cutoff)
        if cutoff < 1.5:
            raise ValueError(f"cutoff={cutoff:g} thermal velocities cuts into the bulk; "
                             f"use cutoff >= 1.5 (default {default_cutoff(alpha):.3g})")
    if interpolation_order not in (2, 3):
        raise ValueError(f"interpolation_order must be 2 or 3, got {interpolation_order!r}")
    eps = 1.0 - alpha
    # continuation in eps from 0.2 (a Gaussian start suffices there) down to eps; a
    # step that fails is halved (in log eps)
    sol = None
    a_prev = None
    a_next = alpha if eps >= _CONTINUATION_START else 1.0 - _CONTINUATION_START
    while True:
        last = a_next == alpha
        grid = _grid(a_next, spacing if last else None, cutoff if last else None)
        if sol is None:
            zeta0 = sonine_zeta_estimate(a_next)
            u0 = initial_guess(grid.v, zeta0)
        else:
            u0 = _transfer(sol, grid)
            zeta0 = sol.zeta * (1.0 - a_next**2) / (1.0 - a_prev**2)
        trial = newton_hcs(grid, u0, zeta0, alpha=a_next, order=interpolation_order,
                           tol=tol if last else 1e-6, max_iter=max_iter if last else 30)
        logger.debug("HCS alpha=%.6g: %s after %d iterations (zeta=%.6g)", a_next,
                     trial.message, trial.iterations, trial.zeta)
        if trial.converged or (last and sol is None):
            sol, a_prev = trial, a_next
            if last:
                break
            a_next = 1.0 - max(eps, (1.0 - a_next) / _CONTINUATION_RATIO)
        elif sol is None:
            raise RuntimeError(f"HCS Newton failed at the start of the continuation, "
                               f"alpha={a_next:.6g}: {trial.message}")
        else:
            eps_prev, eps_next = 1.0 - a_prev, 1.0 - a_next
            if eps_prev / eps_next < 1.05:
                if last:
                    sol = trial
                    break
                raise RuntimeError(f"HCS continuation stalled at alpha={a_prev:.6g} on the "
                                   f"way to alpha={alpha}: {trial.message}")
            a_next = 1.0 - math.sqrt(eps_prev * eps_next)
    assert sol is not None
    return sol


def _check(sol: HCSSolution, alpha: float) -> None:
    if not sol.converged:
        warnings.warn(f"HCS Newton did not converge at alpha={alpha}: {sol.message} "
                      f"(residual {sol.residual:.2e}); try a finer spacing",
                      ResolutionWarning, stacklevel=3)
    if sol.f[-1] > 1e-30:
        warnings.warn(f"f at the cut-off is {sol.f[-1]:.2e} > 1e-30: increase cutoff "
                      f"(now {sol.grid.v[-1]:.3g})", ResolutionWarning, stacklevel=3)
    steps = np.abs(np.diff(np.log(sol.f[sol.f > 1e-30])))
    if steps.size and steps.max() > 1.0:
        warnings.warn(f"ln f changes by {steps.max():.2f} between neighbouring nodes where "
                      "f > 1e-30: reduce spacing", ResolutionWarning, stacklevel=3)


@register_solver("fd", problem="cooling")
def hcs_fd(problem: CoolingProblem, *, spacing: float | None = None,
           cutoff: float | None = None, interpolation_order: int = 3, tol: float = 1e-10,
           max_iter: int = 60) -> VelocityDistribution:
    """Homogeneous cooling state by Newton on the finite-difference grid (key ``"fd"``).

    Parameters
    ----------
    problem : CoolingProblem
    spacing, cutoff, interpolation_order, tol, max_iter
        See :func:`solve_hcs`.

    Returns
    -------
    VelocityDistribution
        The scaled state at unit temperature (``v = c``);
        ``info.extra`` holds ``zeta`` (:math:`dT/dt = -2\\zeta n T^{3/2}`), the energy
        identity ``zeta_energy`` (equal to ``zeta`` up to the discretisation error),
        the mass-defect rate, the spacing and the cut-off.
    """
    problem.require("fd", gammas=(1.0,), constant_restitution=True)
    start = time.perf_counter()
    alpha = problem.gas.alpha
    sol = solve_hcs(alpha, spacing=spacing, cutoff=cutoff,
                    interpolation_order=interpolation_order, tol=tol, max_iter=max_iter)
    _check(sol, alpha)
    info = RunInfo(converged=sol.converged, iterations=sol.iterations, residual=sol.residual,
                   wall_time=time.perf_counter() - start, message=sol.message,
                   extra={"zeta": sol.zeta, "zeta_energy": sol.energy_identity(alpha),
                          "mass_defect_rate": sol.multiplier, "spacing": sol.grid.h,
                          "cutoff": float(sol.grid.v[-1]), "n_v_half": sol.grid.n})
    return VelocityDistribution.from_values(sol.grid.v_full, sol.grid.full(sol.f),
                                            weights=sol.grid.weights, method="fd",
                                            params=problem.as_dict(), info=info)
