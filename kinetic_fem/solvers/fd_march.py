"""Time marching of the finite-difference scheme (the paper's iteration), unit problem.

One step of :func:`march` (``n = D = 1``, bath friction :math:`\\xi'`, kernel
:math:`|g|^\\gamma` with ``gamma`` 1 or 0) solves

.. math::

    P_i^{t+\\delta t} - \\delta t\\,\\big[\\Delta_h + \\xi' D_h\\big] P^{t+\\delta t}_i
    = P_i^t + \\delta t\\,(G_i - \\nu_i P_i)^t,

:math:`\\Delta_h` the three-point Laplacian and :math:`D_h` the central difference of
:math:`vP` (:func:`kinetic_fem.solvers.fd_newton.drift`), with :math:`P_{-1} = P_1` and
:math:`P_N = 0`: a tridiagonal system solved by :func:`scipy.linalg.solve_banded`.  It is
an M-matrix (so the step keeps :math:`P` positive) while the cell Peclet number
:math:`\\xi' v_{max}\\,\\delta v/2` is at most 1.  See
:mod:`kinetic_fem.solvers.finite_difference` for the whole scheme.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import solve_banded

from ..operators.collision import HalfGrid, gain_term, loss_frequency
from ..operators.grid import moments
from ..options import gather_groups, option_group
from ..sonine import relaxation_time
from .fd_newton import FDOperator, drift, laplacian

__all__ = ["MarchOptions", "MarchResult", "march", "even_moments", "F_FLOOR"]

F_FLOOR = 1e-30
"""Values of f(c) above which the tails are required to be resolved (claim C16)."""


@option_group
@dataclass(frozen=True)
class MarchOptions:
    """How the finite-difference scheme marches in time (unit problem ``n = D = 1``).

    Parameters
    ----------
    dt : float, optional
        Time step; :func:`march` needs it, the solver
        (:func:`kinetic_fem.solvers.finite_difference.solve_fd_heated`) takes
        ``courant / nu_max`` without it.
    courant : float
        :math:`\\delta t\\,\\nu_{max}` when ``dt`` is not given (the solver's).
    implicit_loss : bool
        Treat :math:`\\nu_i P_i` implicitly (positive for any ``dt``).
    tol : float
        Steady when :math:`\\tau \\max|\\partial_t \\ln P| <` ``tol`` over the nodes with
        :math:`f > 10^{-30}`.
    max_time : float, optional
        Longest marching time (default: none for :func:`march`, 200 relaxation times for
        the solver).
    max_steps : int
        Most time steps.
    progress : bool
        Show a progress bar.

    Examples
    --------
    >>> MarchOptions(dt=0.01, implicit_loss=True)  # doctest: +NORMALIZE_WHITESPACE
    MarchOptions(dt=0.01, courant=0.5, implicit_loss=True, tol=1e-10, max_time=None,
                 max_steps=1000000, progress=False)
    """

    dt: float | None = None
    courant: float = 0.5
    implicit_loss: bool = False
    tol: float = 1e-10
    max_time: float | None = None
    max_steps: int = 10**6
    progress: bool = False


@dataclass(frozen=True)
class MarchResult:
    """End state of :func:`march` (unit problem ``n = D = 1``).

    Parameters
    ----------
    p : ndarray, shape (n,)
        :math:`P_i` on the half grid at the end.
    time : float
        Time marched.
    steps : int
        Time steps taken.
    rate : float
        :math:`\\tau\\max|\\partial_t \\ln P|` at the end (the stopping measure).
    converged : bool
        The rate fell below the tolerance.
    series : dict of str to ndarray
        Time series ``t``, ``temperature``, ``a2``, ``rate`` recorded every ``record_dt``.
    """

    p: NDArray[np.float64]
    time: float
    steps: int
    rate: float
    converged: bool
    series: dict[str, NDArray[np.float64]]


def even_moments(grid: HalfGrid, p: NDArray[np.float64]) -> tuple[float, float]:
    """Temperature and a2 of the even distribution ``p`` (normalised).

    Parameters
    ----------
    grid : HalfGrid
        The half grid.
    p : ndarray, shape (n,)
        :math:`P_i` on it (any normalisation).

    Returns
    -------
    temperature, a2 : float
    """
    m = moments(grid.v, p, grid.half_weights, 4)
    temperature = m[2] / m[0]
    return temperature, m[4] / m[0] / (3.0 * temperature**2) - 1.0


def _log_change_rate(p_new: NDArray[np.float64], p_old: NDArray[np.float64], dt: float,
                     scale: float) -> float:
    """:math:`\\max |\\Delta \\ln P| / \\delta t` over nodes with ``scale * P > F_FLOOR``."""
    mask = (scale * p_new > F_FLOOR) & (p_old > 0)
    if not mask.any():
        return math.inf
    return float(np.max(np.abs(np.log(p_new[mask] / p_old[mask])))) / dt


def march(grid: HalfGrid, p0: NDArray[np.float64], operator: FDOperator | None = None,
          options: MarchOptions | None = None, *, stop: bool = True,
          record_dt: float | None = None, tau: float | None = None,
          **keywords: Any) -> MarchResult:
    """March the unit problem (``n = D = 1``) from ``p0`` with constant step ``dt``.

    Parameters
    ----------
    grid : HalfGrid
    p0 : ndarray, shape (n,)
        Positive initial distribution on the half grid (normalised here).
    operator : FDOperator, optional
        The model (``alpha``, ``gamma`` 1 or 0, bath ``friction``) and the gain term's
        interpolation (``log_interp``, ``order``: see
        :func:`kinetic_fem.operators.collision.gain_term`); ``alpha`` required, here or
        by keyword.
    options : MarchOptions, optional
        ``dt`` (required, here or by keyword), ``implicit_loss``, ``tol`` (steady when
        :math:`\\tau \\max|\\partial_t \\ln P| <` ``tol`` over the nodes with
        :math:`f > 10^{-30}`), ``max_time`` (default: none), ``max_steps``, ``progress``.
    stop : bool
        Stop at the steady state (``False``: run to ``max_time``, for transients).
    record_dt : float, optional
        Interval of the recorded series ``t, temperature, a2, rate`` (default
        :math:`\\tau/20`).
    tau : float, optional
        Relaxation time of the stopping criterion (default
        :func:`kinetic_fem.sonine.relaxation_time`, the hard-rod white-noise scale).
    **keywords
        Fields of :class:`FDOperator` and of :class:`MarchOptions`, over ``operator`` and
        ``options``.

    Raises
    ------
    TypeError
        For a keyword that is neither an operator nor a marching option, or no
        ``alpha`` or ``dt``.
    ValueError
        If an explicit step has :math:`\\delta t\\,\\nu_{max} > 1` or the cell Peclet
        number of the bath drift exceeds 1 (either could make :math:`P` negative).
    """
    op, opts = gather_groups(((FDOperator, operator), (MarchOptions, options)), keywords,
                             "march")
    if opts.dt is None:
        raise TypeError("march() needs the time step dt (by keyword or in MarchOptions)")
    alpha, gamma, friction = op.alpha, op.gamma, op.friction
    log_interp, order = op.log_interp, op.order
    dt, implicit_loss, tol, max_steps, progress = (opts.dt, opts.implicit_loss, opts.tol,
                                                   opts.max_steps, opts.progress)
    max_time = math.inf if opts.max_time is None else opts.max_time
    tau = relaxation_time(alpha) if tau is None else tau
    record_dt = tau / 20.0 if record_dt is None else record_dt
    w = grid.half_weights
    p = np.asarray(p0, dtype=float) / np.dot(w, p0)
    r = dt / grid.h**2
    ab = np.zeros((3, grid.n))
    ab[0, 1] = -2.0 * r
    ab[0, 2:] = -r
    ab[2, :-1] = -r
    if friction:
        peclet = 0.5 * friction * grid.v[-1] * grid.h
        if peclet > 1.0:
            raise ValueError(
                f"the bath drift has cell Peclet number xi*v_max*dv/2 = {peclet:.3g} > 1 on "
                f"this grid: the implicit step would lose positivity. Use a spacing of at "
                f"most {1.0 / peclet:.3g} times the present one, or steady='newton'")
        q = dt * friction / (2.0 * grid.h)
        ab[0, 1] -= 2.0 * q * grid.v[1]
        ab[0, 2:] -= q * grid.v[2:]
        ab[2, :-1] += q * grid.v[:-1]
    temperature, a2 = even_moments(grid, p)
    series: dict[str, list[float]] = {"t": [0.0], "temperature": [temperature], "a2": [a2],
                                      "rate": [math.nan]}
    t, rate, steps, converged, next_record = 0.0, math.inf, 0, False, record_dt
    bar = None
    if progress:
        from tqdm.auto import tqdm
        bar = tqdm(total=max_steps, desc=f"fd march alpha={alpha}", leave=False)
    while steps < max_steps and t < max_time:
        nu = loss_frequency(grid, p, density=1.0, gamma=gamma)
        gain = gain_term(grid, p, alpha=alpha, density=1.0, log_interp=log_interp,
                         order=order, gamma=gamma)
        # mass-defect rate of the discrete operator, removed so that the fixed point
        # is exactly the steady state of the discrete equations (see _fd_newton)
        forcing = laplacian(p, grid.h)
        if friction:
            forcing = forcing + friction * drift(p, grid.v, grid.h)
        defect = np.dot(w, forcing + gain - nu * p)
        gain = gain - defect * p
        if implicit_loss:
            ab[1] = 1.0 + 2.0 * r + dt * nu
            rhs = p + dt * gain
        else:
            courant = dt * float(nu.max())
            if courant > 1.0:
                raise ValueError(
                    f"explicit collision step dt={dt:.3g} has dt*nu_max={courant:.3g} > 1 at "
                    f"t={t:.3g}: P could turn negative. Use dt <= {0.5 / nu.max():.3g}, a "
                    "smaller courant, or implicit_loss=True")
            ab[1] = 1.0 + 2.0 * r
            rhs = p * (1.0 - dt * nu) + dt * gain
        p_new = solve_banded((1, 1), ab, rhs, check_finite=False)
        if np.any(p_new < 0):
            raise ValueError(f"negative P after step {steps} (min {p_new.min():.3g}); "
                             "reduce dt or use implicit_loss=True")
        p_new /= np.dot(w, p_new)
        steps += 1
        t += dt
        temperature, a2 = even_moments(grid, p_new)
        rate = _log_change_rate(p_new, p, dt, math.sqrt(temperature))
        p = p_new
        if bar is not None:
            bar.update(1)
        if t >= next_record - 1e-12 * dt:
            next_record += record_dt
            for key, val in (("t", t), ("temperature", temperature), ("a2", a2),
                             ("rate", rate)):
                series[key].append(val)
        if stop and rate * tau < tol:
            converged = True
            break
    if bar is not None:
        bar.close()
    if series["t"][-1] != t:
        for key, val in (("t", t), ("temperature", temperature), ("a2", a2), ("rate", rate)):
            series[key].append(val)
    return MarchResult(p, t, steps, rate * tau, converged,
                       {k: np.asarray(s) for k, s in series.items()})
