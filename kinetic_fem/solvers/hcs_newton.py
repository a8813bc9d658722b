"""Newton's method for the finite-difference homogeneous cooling state.

The unknowns are :math:`u = \\ln f` on the half grid, the cooling rate :math:`\\zeta` and
the mass-defect multiplier :math:`\\lambda`; the equations are those of
:mod:`kinetic_fem.solvers.fd_cooling` (its module docstring derives them):

.. math::

    R_i = \\tilde Q_i - \\lambda f_i - \\zeta f_i (1 + c_i u'_i) = 0,\\qquad
    \\sum_i w_i f_i = 1,\\qquad \\sum_i w_i c_i^2 f_i = 1,

with the closure :math:`u'' = 0` at the cut-off in place of the last row.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..operators.collision import HalfGrid, gain_term, loss_frequency, pair_moment
from .fd_newton import collision_jacobian, update_factor
from .newton import NewtonReport, NewtonResult, newton

__all__ = ["HCSSolution", "drift_term", "hcs_residual", "newton_hcs", "MONITOR_FLOOR"]

MONITOR_FLOOR = 1e-50
"""Nodes with f above this are monitored for the convergence of Newton's method."""


def _log_derivative(grid: HalfGrid, u: NDArray[np.float64]) -> NDArray[np.float64]:
    """:math:`u'_i`: central differences, ``u' = 0`` at ``c = 0``, one-sided at the end."""
    du = np.empty_like(u)
    du[0] = 0.0
    du[1:-1] = (u[2:] - u[:-2]) / (2.0 * grid.h)
    du[-1] = (u[-1] - u[-2]) / grid.h
    return du


def drift_term(grid: HalfGrid, u: NDArray[np.float64]) -> NDArray[np.float64]:
    """:math:`(cf)'_i = f_i (1 + c_i u'_i)` with :math:`f = e^u` on the half grid.

    Parameters
    ----------
    grid : HalfGrid
        The half grid :math:`c_i = i h \\ge 0`.
    u : ndarray, shape (n,)
        :math:`\\ln f` on the grid.

    Returns
    -------
    ndarray, shape (n,)

    Examples
    --------
    >>> from kinetic_fem.operators.collision import half_grid
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
    closure :math:`u_{n-1} - 2u_{n-2} + u_{n-3} = 0` at the cut-off.

    Parameters
    ----------
    grid : HalfGrid
        The half grid :math:`c_i = i h \\ge 0` (unit temperature).
    u : ndarray, shape (n,)
        :math:`\\ln f`.
    zeta : float
        Cooling rate.
    multiplier : float
        Mass-defect rate :math:`\\lambda`.
    alpha : float
        Coefficient of restitution.
    order : int
        Order of the interpolation of :math:`\\ln f` at pre-collision velocities.

    Returns
    -------
    ndarray, shape (n,)
    """
    f = np.exp(u)
    q = (gain_term(grid, f, alpha=alpha, density=1.0, order=order)
         - loss_frequency(grid, f, density=1.0) * f)
    res = q - multiplier * f - zeta * drift_term(grid, u)
    # closure at the cut-off: the gain there misses its partners beyond the grid, so
    # the last row extrapolates ln f linearly instead (exact for an exponential tail)
    res[-1] = u[-1] - 2.0 * u[-2] + u[-3]
    return res


@dataclass(frozen=True)
class HCSSolution(NewtonReport):
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
    newton : NewtonResult
        The report of :func:`kinetic_fem.solvers.newton.newton` (``x = (ln f, zeta,
        lambda)``; ``residual``: the largest scaled residual on the monitored nodes).
    """

    grid: HalfGrid
    f: NDArray[np.float64]
    zeta: float
    multiplier: float
    newton: NewtonResult

    def energy_identity(self, alpha: float) -> float:
        """:math:`(1-\\alpha^2)\\langle|c-c'|^3\\rangle/8`, to compare with :attr:`zeta`."""
        w = self.grid.weights
        g3 = pair_moment(self.grid.v_full, self.grid.full(self.f), w, 3)
        return (1.0 - alpha**2) * g3 / 8.0


def newton_hcs(grid: HalfGrid, u0: NDArray[np.float64], zeta0: float, *, alpha: float,
               order: int = 3, tol: float = 1e-10, max_iter: int = 60) -> HCSSolution:
    """Solve the discrete HCS equations by damped Newton from ``(u0, zeta0)``.

    The shared driver :func:`kinetic_fem.solvers.newton.newton` on
    :math:`x = (u, \\zeta, \\lambda)`. Rows are scaled by
    :math:`f_i(\\nu_i + \\zeta(1 + c_i/h))`, so that tail equations weigh as much as
    bulk ones (the scales of the current iterate are frozen during the line search: a
    scaling that moves with the trial point through f and zeta can grow while the
    residual falls); converged when the largest change of ``u`` on the nodes with
    :math:`f > 10^{-50}` is below ``tol``.

    Parameters
    ----------
    grid : HalfGrid
        The half grid :math:`c_i = i h \\ge 0` (unit temperature).
    u0 : ndarray, shape (n,)
        Start for :math:`\\ln f`.
    zeta0 : float
        Start for the cooling rate.
    alpha : float
        Coefficient of restitution.
    order : int
        Order of the interpolation of :math:`\\ln f` at pre-collision velocities.
    tol : float
        Tolerance on the change of ``u`` on the monitored nodes.
    max_iter : int
        Newton iterations allowed.

    Returns
    -------
    HCSSolution
    """
    w = grid.half_weights
    c2w = w * grid.v**2
    n = grid.n
    last: dict[str, object] = {}

    def evaluate(x: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
        """``f, nu, R, row scale d, constraints`` at ``x = (u, zeta, lambda)`` (cached)."""
        if last.get("x") is not None and np.array_equal(last["x"], x):  # type: ignore[arg-type]
            return last["out"]  # type: ignore[return-value]
        u_, zeta_, lam_ = x[:n], float(x[n]), float(x[n + 1])
        f_ = np.exp(u_)
        nu_ = loss_frequency(grid, f_, density=1.0)
        res_ = hcs_residual(grid, u_, zeta_, lam_, alpha=alpha, order=order)
        d_ = np.maximum(f_ * (nu_ + abs(zeta_) * (1.0 + grid.v / grid.h)), 1e-300)
        d_[-1] = 1.0  # the closure row is already O(1)
        cons_ = np.array([np.dot(w, f_) - 1.0, np.dot(c2w, f_) - 1.0])
        last["x"], last["out"] = x.copy(), (f_, nu_, res_, d_, cons_)
        return f_, nu_, res_, d_, cons_

    def system(x: NDArray[np.float64], jacobian: bool
               ) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
        f_, nu_, res_, _, cons_ = evaluate(x)
        r = np.concatenate([res_, cons_])
        if not jacobian:
            return r, None
        u_, zeta_, lam_ = x[:n], float(x[n]), float(x[n + 1])
        jac = collision_jacobian(grid, f_, nu_, alpha, True, order) * f_[None, :]
        jac[np.arange(n), np.arange(n)] -= lam_ * f_
        jac -= zeta_ * _drift_jacobian(grid, u_)
        jac[-1, :] = 0.0
        jac[-1, -3:] = [1.0, -2.0, 1.0]
        drift = drift_term(grid, u_)
        drift[-1] = 0.0
        big = np.zeros((n + 2, n + 2))
        big[:n, :n] = jac
        big[:n, n] = -drift
        big[:n, n + 1] = -np.where(np.arange(n) < n - 1, f_, 0.0)
        big[n, :n] = w * f_
        big[n + 1, :n] = c2w * f_
        return r, big

    def row_scale(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.concatenate([evaluate(x)[3], [1.0, 1.0]])

    def norm(r: NDArray[np.float64], x: NDArray[np.float64]) -> float:
        mon = x[:n] > math.log(MONITOR_FLOOR)
        return max(float(np.max(np.abs(r[:n][mon]))), float(np.max(np.abs(r[n:]))))

    def step_norm(dx: NDArray[np.float64], x: NDArray[np.float64]) -> float:
        mon = x[:n] > math.log(MONITOR_FLOOR)
        return float(np.max(np.abs(np.log(update_factor(dx[:n]))[mon])))

    def update(x: NDArray[np.float64], dx: NDArray[np.float64]) -> NDArray[np.float64]:
        # the step du is applied as a relative change of f, f -> f * update_factor(du)
        # (sublinear in ln f for large rises, exponential damping of large falls, as in
        # the heated solver)
        return np.concatenate([x[:n] + np.log(update_factor(dx[:n])), x[n:] + dx[n:]])

    x0 = np.concatenate([np.asarray(u0, dtype=float), [float(zeta0), 0.0]])
    out = newton(system, x0, tol=tol, max_iter=max_iter, criterion="step", norm=norm,
                 step_norm=step_norm, update=update, row_scale=row_scale, armijo=0.0,
                 min_damping=2.0**-10, name="HCS Newton")
    u = out.x[:n]
    return HCSSolution(grid, np.exp(u), float(out.x[n]), float(out.x[n + 1]), out)
