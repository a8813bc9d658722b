"""Newton's method for the steady equations of the finite-difference scheme.

The fixed point of the normalised time step of :mod:`kinetic_fem.solvers.finite_difference`
solves (unit problem ``n = D = 1``)

.. math::

    R_i(P, \\lambda) = \\frac{P_{i+1} - 2P_i + P_{i-1}}{\\delta v^2}
        + \\xi\\,\\frac{v_{i+1}P_{i+1} - v_{i-1}P_{i-1}}{2\\delta v} + G_i[P]
        - \\nu_i[P] P_i - \\lambda P_i = 0, \\qquad \\sum_i w_i P_i = 1,

where :math:`\\lambda` absorbs the O(h^4) mass defect of the discrete collision term
(the normalisation after every step) and :math:`\\xi` is the friction of a
Fokker-Planck bath in units of the unit problem (0 for white noise; the drift
:math:`\\partial_v(\\xi v P)` by central differences, second order like the Laplacian).
The collision term has the kernel :math:`|g|^\\gamma`, ``gamma`` 1 or 0
(:func:`kinetic_fem.operators.collision.kernel_power`).  Newton's method is applied to the
relative change :math:`y_i = \\delta P_i / P_i` (update :math:`P_i \\to P_i (1 + y_i)`,
continued exponentially below :math:`y_i = -0.9` so that :math:`P` stays positive), with
rows scaled by :math:`P_i(\\nu_i + 2/\\delta v^2)`: the scaled Jacobian has O(1)
entries down the tail, so the dense LU solve keeps tail values accurate relative to
themselves.  Nodes where :math:`P` underflows (below 1e-290) are held at zero.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..operators.collision import HalfGrid, gain_term, kernel_power, loss_frequency
from ..operators.fd_kernels import gain_jacobian
from ..options import gather, option_group
from .newton import NewtonReport, NewtonResult, newton

__all__ = ["FDOperator", "FDSteadyState", "laplacian", "drift", "steady_residual",
           "collision_jacobian", "newton_steady", "update_factor", "UNDERFLOW"]

UNDERFLOW = 1e-290


@option_group
@dataclass(frozen=True)
class FDOperator:
    """The discrete operator of the unit problem (``n = D = 1``): the model and the
    interpolation of the gain term, the options that :func:`newton_steady` and
    :func:`kinetic_fem.solvers.fd_march.march` share.

    Parameters
    ----------
    alpha : float
        Coefficient of restitution.
    gamma : float
        Kernel exponent, 1 or 0.
    friction : float
        Bath friction :math:`\\xi` of the unit problem (0: white noise).
    log_interp : bool
        Interpolate :math:`\\ln P` (not :math:`P`) at the pre-collision velocities.
    order : int
        Order of that interpolation, 2 or 3
        (:func:`kinetic_fem.operators.collision.gain_term`).

    Examples
    --------
    >>> FDOperator(0.5, order=3)
    FDOperator(alpha=0.5, gamma=1.0, friction=0.0, log_interp=True, order=3)
    """

    alpha: float
    gamma: float = 1.0
    friction: float = 0.0
    log_interp: bool = True
    order: int = 2


def update_factor(y: NDArray[np.float64]) -> NDArray[np.float64]:
    """:math:`1 + y` (the Newton step in ``P``), continued by :math:`0.1 e^{y + 0.9}` below
    ``y = -0.9`` so that :math:`P` stays positive.

    Parameters
    ----------
    y : ndarray
        Relative Newton step :math:`\\delta P / P`.

    Returns
    -------
    ndarray
        The factor applied to :math:`P`, positive.
    """
    return np.where(y > -0.9, 1.0 + y, 0.1 * np.exp(np.clip(y, -700.0, -0.9) + 0.9))


def laplacian(p: NDArray[np.float64], h: float) -> NDArray[np.float64]:
    """Three-point Laplacian with :math:`P_{-1} = P_1` and :math:`P_N = 0`.

    Parameters
    ----------
    p : ndarray, shape (n,)
        :math:`P_i` on the half grid.
    h : float
        Grid spacing.

    Returns
    -------
    ndarray, shape (n,)
    """
    ext = np.concatenate([[p[1]], p, [0.0]])
    return (ext[2:] - 2.0 * p + ext[:-2]) / h**2


def drift(p: NDArray[np.float64], v: NDArray[np.float64], h: float) -> NDArray[np.float64]:
    """:math:`\\partial_v (v P)` by central differences, :math:`P(-v) = P(v)`, :math:`P_N = 0`.

    Parameters
    ----------
    p : ndarray, shape (n,)
        :math:`P_i` on the half grid.
    v : ndarray, shape (n,)
        The nodes :math:`v_i = i h`.
    h : float
        Grid spacing.

    Returns
    -------
    ndarray, shape (n,)

    Examples
    --------
    >>> v = np.linspace(0.0, 4.0, 5)
    >>> drift(np.ones(5), v, 1.0)  # d(v)/dv = 1 inside; the cut-off sees P_N = 0
    array([ 1. ,  1. ,  1. ,  1. , -1.5])
    """
    vp = np.concatenate([v * p, [0.0]])
    out = np.empty_like(p)
    out[0] = vp[1] / h  # (v_1 P_1 - v_{-1} P_{-1}) / 2h with v_{-1} = -v_1
    out[1:] = (vp[2:] - vp[:-2]) / (2.0 * h)
    return out


def steady_residual(grid: HalfGrid, p: NDArray[np.float64], multiplier: float, *,
                    alpha: float, log_interp: bool = True, order: int = 2,
                    gamma: float = 1.0, friction: float = 0.0) -> NDArray[np.float64]:
    """:math:`R_i(P, \\lambda)` of the module docstring (unit problem).

    Parameters
    ----------
    grid : HalfGrid
        The half grid :math:`v_i = i h \\ge 0` of the unit problem.
    p : ndarray, shape (n,)
        :math:`P_i`.
    multiplier : float
        The mass-defect rate :math:`\\lambda`.
    alpha : float
        Coefficient of restitution.
    log_interp : bool
        Interpolate :math:`\\ln P` at the pre-collision velocities.
    order : int
        Order of that interpolation.
    gamma, friction : float
        Kernel exponent (1 or 0) and bath friction of the unit problem.

    Returns
    -------
    ndarray, shape (n,)
    """
    nu = loss_frequency(grid, p, density=1.0, gamma=gamma)
    gain = gain_term(grid, p, alpha=alpha, density=1.0, log_interp=log_interp, order=order,
                     gamma=gamma)
    res = laplacian(p, grid.h) + gain - (nu + multiplier) * p
    if friction:
        res += friction * drift(p, grid.v, grid.h)
    return res


def collision_jacobian(grid: HalfGrid, p: NDArray[np.float64], nu: NDArray[np.float64],
                       alpha: float, log_interp: bool, order: int, gamma: float = 1.0
                       ) -> NDArray[np.float64]:
    """Dense :math:`\\partial Q_i / \\partial P_l` of the strong collision term
    :math:`Q_i = G_i[P] - \\nu_i[P] P_i` on the half grid (unit density).

    Parameters
    ----------
    grid : HalfGrid
        The half grid :math:`v_i = i h \\ge 0` of the unit problem.
    p : ndarray, shape (n,)
        :math:`P_i`.
    nu : ndarray, shape (n,)
        The loss frequency :math:`\\nu_i[P]`.
    alpha : float
        Coefficient of restitution.
    log_interp : bool
        Interpolate :math:`\\ln P` at the pre-collision velocities.
    order : int
        Order of that interpolation.
    gamma : float
        Kernel exponent, 1 or 0.

    Returns
    -------
    ndarray, shape (n, n)
    """
    n, h = grid.n, grid.h
    idx = np.arange(n)
    power = kernel_power(gamma)
    with np.errstate(divide="ignore"):
        lnp = np.where(p > 0, np.log(np.where(p > 0, p, 1.0)), -np.inf)
    kink = grid.kink if power == 1 else np.zeros_like(grid.kink)
    jac = (2.0 / (1.0 + alpha)) ** (1 + power) * gain_jacobian(
        p, lnp, grid.weights, kink, float(alpha), h, bool(log_interp), int(order), power)
    if power == 0:  # nu_i = sum_l w_l P_l at every node
        jac -= p[:, None] * grid.half_weights[None, :]
        jac[idx, idx] -= nu
        return jac
    v = grid.v
    w_pos = grid.weights[n - 1:]
    w_neg = grid.weights[n - 1::-1]
    dnu = np.abs(v[:, None] - v[None, :]) * w_pos[None, :]
    dnu[:, 1:] += np.abs(v[:, None] + v[None, 1:]) * w_neg[None, 1:]
    dnu[idx, idx] += grid.kink[n - 1:]
    jac -= p[:, None] * dnu
    jac[idx, idx] -= nu
    return jac


def _jacobian(grid: HalfGrid, p: NDArray[np.float64], nu: NDArray[np.float64],
              multiplier: float, alpha: float, log_interp: bool, order: int, gamma: float,
              friction: float) -> NDArray[np.float64]:
    """Dense :math:`\\partial R_i / \\partial P_l`."""
    n, h = grid.n, grid.h
    jac = collision_jacobian(grid, p, nu, alpha, log_interp, order, gamma)
    idx = np.arange(n)
    jac[idx, idx] += -2.0 / h**2 - multiplier
    jac[idx[:-1], idx[:-1] + 1] += 1.0 / h**2
    jac[idx[1:], idx[1:] - 1] += 1.0 / h**2
    jac[0, 1] += 1.0 / h**2  # P_{-1} = P_1: the first row sees P_1 twice
    if friction:
        v = grid.v
        jac[0, 1] += friction * v[1] / h
        jac[idx[1:-1], idx[1:-1] + 1] += friction * v[2:] / (2.0 * h)
        jac[idx[1:], idx[1:] - 1] -= friction * v[:-1] / (2.0 * h)
    return jac


@dataclass(frozen=True)
class FDSteadyState(NewtonReport):
    """A steady state of the finite-difference equations and how Newton found it.

    Parameters
    ----------
    p : ndarray, shape (n,)
        :math:`P_i` on the half grid of the unit problem, :math:`\\sum_i w_i P_i = 1`.
    multiplier : float
        The mass-defect rate :math:`\\lambda` of the module docstring.
    newton : NewtonResult
        The report of :func:`kinetic_fem.solvers.newton.newton`: ``x`` is
        ``(P, lambda)``, ``residual`` the largest scaled residual
        :math:`|R_i|/(P_i(\\nu_i+2/h^2))` on the monitored nodes.
    """

    p: NDArray[np.float64]
    multiplier: float
    newton: NewtonResult


def newton_steady(grid: HalfGrid, p0: NDArray[np.float64], operator: FDOperator | None = None,
                  *, tol: float = 1e-10, max_iter: int = 60, monitor_floor: float = 1e-50,
                  **operator_keywords: Any) -> FDSteadyState:
    """Solve :math:`R(P,\\lambda) = 0`, :math:`\\sum w P = 1` from ``p0`` (positive).

    The shared driver :func:`kinetic_fem.solvers.newton.newton` runs on
    :math:`x = (P, \\lambda)`: the step is the relative change :math:`y` on the active
    nodes (:data:`UNDERFLOW`) and :math:`\\delta\\lambda`, applied by
    :func:`update_factor`; backtracking accepts any decrease of the scaled residual
    (halving down to :math:`2^{-10}`).

    Parameters
    ----------
    grid : HalfGrid
        The half grid :math:`v_i = i h \\ge 0`.
    p0 : ndarray, shape (n,)
        Positive start (a Gaussian is enough for every alpha tried, 0 to 0.9999).
    operator : FDOperator, optional
        The model and the gain term's interpolation (``alpha`` required, here or by
        keyword).
    tol : float
        Converged when the largest relative Newton update is below ``tol`` on the
        monitored nodes.
    max_iter : int
        Newton iterations allowed.
    monitor_floor : float
        Nodes with :math:`f = \\sqrt{T} P >` ``monitor_floor`` are monitored for
        convergence (20 decades below the resolved 1e-30); deeper, under-resolved
        tail nodes are updated but do not hold up convergence.
    **operator_keywords
        Fields of :class:`FDOperator` (``alpha``, ``gamma``, ``friction``,
        ``log_interp``, ``order``), over ``operator``.

    Returns
    -------
    FDSteadyState

    Raises
    ------
    TypeError
        For a keyword that is not a field of :class:`FDOperator`, or no ``alpha``.
    """
    op = gather(FDOperator, operator, operator_keywords, "newton_steady")
    alpha, gamma, friction = op.alpha, op.gamma, op.friction
    log_interp, order = op.log_interp, op.order
    w = grid.half_weights
    n = grid.n
    cache: dict[str, object] = {}

    def evaluate(x: NDArray[np.float64]) -> tuple[NDArray[Any], ...]:
        """``nu, R, row scale d, active nodes`` at ``x`` (the last one cached)."""
        if cache.get("x") is not None and np.array_equal(cache["x"], x):  # type: ignore[arg-type]
            return cache["out"]  # type: ignore[return-value]
        p_, lam_ = x[:n], float(x[n])
        nu_ = loss_frequency(grid, p_, density=1.0, gamma=gamma)
        res_ = steady_residual(grid, p_, lam_, alpha=alpha, log_interp=log_interp,
                               order=order, gamma=gamma, friction=friction)
        act_ = p_ > UNDERFLOW
        d_ = np.asarray(np.where(act_, p_ * (nu_ + 2.0 / grid.h**2 + friction), 1.0),
                        dtype=np.float64)
        cache["x"], cache["out"] = x.copy(), (nu_, res_, d_, act_)
        return nu_, res_, d_, act_

    def monitored_active(x: NDArray[np.float64]) -> NDArray[np.bool_]:
        """The monitored nodes among the active ones (the rows of the step)."""
        p_ = x[:n]
        temperature = np.dot(w, grid.v**2 * p_) / np.dot(w, p_)
        return (math.sqrt(temperature) * p_ > monitor_floor)[p_ > UNDERFLOW]

    def system(x: NDArray[np.float64], jacobian: bool
               ) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
        p_, lam_ = x[:n], float(x[n])
        nu_, res_, d_, act_ = evaluate(x)
        a = np.flatnonzero(act_)
        r = np.concatenate([res_[a] / d_[a], [np.dot(w, p_) - 1.0]])
        if not jacobian:
            return r, None
        jac = _jacobian(grid, p_, nu_, lam_, alpha, log_interp, order, gamma, friction)
        m = a.size
        big = np.zeros((m + 1, m + 1))
        big[:m, :m] = jac[np.ix_(a, a)] * p_[a][None, :] / d_[a][:, None]
        big[:m, m] = -p_[a] / d_[a]
        big[m, :m] = w[a] * p_[a]
        return r, big

    def norm(r: NDArray[np.float64], x: NDArray[np.float64]) -> float:
        return float(np.max(np.abs(r[:-1][monitored_active(x)])))

    def step_norm(dx: NDArray[np.float64], x: NDArray[np.float64]) -> float:
        return float(np.max(np.abs(dx[:-1][monitored_active(x)])))

    def update(x: NDArray[np.float64], dx: NDArray[np.float64]) -> NDArray[np.float64]:
        p_ = x[:n].copy()
        a = np.flatnonzero(p_ > UNDERFLOW)
        p_[a] = p_[a] * update_factor(dx[:-1])
        p_[p_ < UNDERFLOW] = 0.0
        return np.concatenate([p_, [x[n] + dx[-1]]])

    p = np.asarray(p0, dtype=float) / np.dot(w, p0)
    out = newton(system, np.concatenate([p, [0.0]]), tol=tol, max_iter=max_iter,
                 criterion="step", norm=norm, step_norm=step_norm, update=update,
                 armijo=0.0, min_damping=2.0**-10, name="fd Newton")
    return FDSteadyState(out.x[:n], float(out.x[n]), out)
