"""The paper's implicit finite-difference iteration (Biben's method), ``method="fd"``.

Time marching of the homogeneous Boltzmann equation of the heated gas (Barrat et al.
2002, section 2.1.3)

.. math::

    \\partial_t P - D\\partial_v^2 P = -\\nu[P](v) P(v) + G[P](v), \\qquad
    \\nu[P](v) = n\\int dv' |v-v'| P(v'),

    G[P](v) = \\frac{4n}{(1+\\alpha)^2}\\int dv' |v-v'| P(v')
              P\\Big(\\frac{2v-(1-\\alpha)v'}{1+\\alpha}\\Big),

to its steady state.  Discretisation (all at ``n = D = 1``; other ``n``, ``D``
follow exactly by :math:`v \\to (D/n)^{1/3} v`):

* :math:`P` on the half grid :math:`v_i = i\\,\\delta v`, ``i = 0 .. N - 1``, using
  :math:`P(-v) = P(v)`; spacing and cut-off are given in units of the Sonine
  estimate of :math:`\\sqrt{T}` (:func:`kinetic_fem.sonine.steady_temperature`).
* Collision term by Simpson's rule on the mirrored grid with the kink correction
  (:func:`kinetic_fem.grid.simpson_kink_correction`), :math:`\\nu` in O(N) by
  cumulative moments, the gain term in O(N^2) with quadratic interpolation of the
  off-grid argument (of :math:`\\ln P` by default) and :math:`P = 0` beyond the cut-off
  (:func:`kinetic_fem.collision.gain_term`).
* Implicit diffusion, explicit collisions (the paper's step):

  .. math::

      (1 + 2r) P_i^{t+\\delta t} - r (P_{i+1}^{t+\\delta t} + P_{i-1}^{t+\\delta t})
      = P_i^t + \\delta t\\,(G_i - \\nu_i P_i)^t, \\qquad r = D\\delta t/\\delta v^2,

  with :math:`P_{-1} = P_1` (reflection at ``v = 0``) and :math:`P_N = 0` at the
  cut-off, a tridiagonal M-matrix solved by :func:`scipy.linalg.solve_banded`.  The
  right side is positive while :math:`\\delta t\\,\\nu_{max} \\le 1`, so :math:`P` stays
  positive and tail values keep their relative accuracy.  ``implicit_loss=True``
  moves :math:`\\delta t\\,\\nu_i` to the diagonal (positive for any step).
  Normalisation is enforced after every step, and the O(h^4) mass defect rate
  :math:`\\lambda = \\sum_i w_i (D\\Delta_h P + G - \\nu P)_i` of the discrete operator is
  subtracted from the collision term (:math:`-\\lambda P_i`), so that the fixed point of
  the step does not depend on :math:`\\delta t` and is exactly the discrete steady state
  solved by ``steady="newton"``.

The Dirichlet condition at the cut-off :math:`L` adds a multiple of the growing
solution of :math:`D P'' = n|v| P`; its relative effect at ``v`` is of order
:math:`(P(L)/P(v))^2`, negligible when :math:`P(L)` is far below the resolved range
(the default cut-off puts :math:`f(L)` near :math:`10^{-60}`).

``steady="newton"`` solves the same discrete steady equations (with the
normalisation and its Lagrange multiplier) by Newton's method on the relative change
of :math:`P` (see :mod:`kinetic_fem._fd_newton`): first on the nodes with f > 1e-50,
then, after a few implicit steps that settle the deep tail, on all nodes down to 1e-200;
``richardson=True`` combines the solutions at ``spacing`` and ``spacing/2`` as
:math:`(4\\ln P_{h/2} - \\ln P_h)/3`.
"""

from __future__ import annotations

import logging
import math
import time
import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import solve_banded

from ._fd_newton import laplacian, newton_steady
from .collision import HalfGrid, gain_term, half_grid, loss_frequency
from .distribution import RunInfo, VelocityDistribution
from .gas import HeatedProblem, check_positive
from .grid import moments
from .model import WhiteNoise
from .solve import register_solver
from .sonine import relaxation_time, steady_temperature

__all__ = ["ConvergenceWarning", "default_cutoff", "march", "MarchResult", "solve_fd",
           "F_FLOOR"]

logger = logging.getLogger(__name__)

F_FLOOR = 1e-30
"""Values of f(c) above which the tails are required to be resolved (claim C16)."""
_TAIL_TARGET = 1e-60
_MONITOR_BULK, _MONITOR_TAIL = 1e-50, 1e-200
_POLISH_COURANT, _POLISH_STEPS = 200.0, 100


class ConvergenceWarning(UserWarning):
    """The iteration stopped before its stopping criterion was met."""


def default_cutoff(alpha: float) -> float:
    """Cut-off in units of :math:`\\sqrt{T}` where f(c) is below about 1e-60.

    The far tail :math:`e^{-A_c c^{3/2}}` (claim C4, :math:`A_c = \\tfrac23 T^{3/4}` at
    ``n = D = 1``) or, if that is reached first, the core: the smaller of the Gaussian
    :math:`e^{-c^2/2}` and the quasi-elastic :math:`e^{-x^3/6}` (claim C5,
    :math:`x = \\varepsilon^{1/3} v`, with a margin of 1.25 for the crossover).  The
    quasi-elastic estimate keeps the cut-off short of double-precision underflow as
    :math:`\\alpha \\to 1`.

    Examples
    --------
    >>> [round(default_cutoff(a), 1) for a in (0.0, 0.9, 0.99, 0.9999)]
    [29.2, 16.6, 12.1, 12.1]
    """
    temperature = steady_temperature(alpha)
    log_target = -math.log(_TAIL_TARGET)
    gauss = math.sqrt(2.0 * log_target)
    tail = (log_target / (2.0 / 3.0 * temperature**0.75)) ** (2.0 / 3.0)
    x_core = (6.0 * log_target) ** (1.0 / 3.0)
    quasi_elastic = 1.25 * x_core / ((1.0 - alpha) ** (1.0 / 3.0) * math.sqrt(temperature))
    return max(tail, min(gauss, quasi_elastic))


@dataclass(frozen=True)
class MarchResult:
    """End state of :func:`march` (unit problem ``n = D = 1``)."""

    p: NDArray[np.float64]
    time: float
    steps: int
    rate: float
    converged: bool
    series: dict[str, NDArray[np.float64]]


def _even_moments(grid: HalfGrid, p: NDArray[np.float64]) -> tuple[float, float]:
    """Temperature and a2 of the even distribution ``p`` (normalised)."""
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


def march(grid: HalfGrid, p0: NDArray[np.float64], *, alpha: float, dt: float,
          implicit_loss: bool = False, log_interp: bool = True, order: int = 2,
          tol: float = 1e-10,
          max_time: float = math.inf, max_steps: int = 10**6, stop: bool = True,
          record_dt: float | None = None, progress: bool = False) -> MarchResult:
    """March the unit problem (``n = D = 1``) from ``p0`` with constant step ``dt``.

    Parameters
    ----------
    grid : HalfGrid
    p0 : ndarray, shape (n,)
        Positive initial distribution on the half grid (normalised here).
    alpha : float
        Restitution coefficient.
    dt : float
        Time step (unit problem).
    implicit_loss : bool
        Treat :math:`\\nu_i P_i` implicitly (positive for any ``dt``).
    log_interp, order : bool, int
        See :func:`kinetic_fem.collision.gain_term`.
    tol : float
        Steady when :math:`\\tau \\max|\\partial_t \\ln P| <` ``tol`` over the nodes with
        :math:`f > 10^{-30}`, :math:`\\tau` the relaxation time
        (:func:`kinetic_fem.sonine.relaxation_time`).
    max_time, max_steps : float, int
        Limits of the run.
    stop : bool
        Stop at the steady state (``False``: run to ``max_time``, for transients).
    record_dt : float, optional
        Interval of the recorded series ``t, temperature, a2, rate`` (default
        :math:`\\tau/20`).

    Raises
    ------
    ValueError
        If an explicit step has :math:`\\delta t\\,\\nu_{max} > 1` (it could make
        :math:`P` negative).
    """
    tau = relaxation_time(alpha)
    record_dt = tau / 20.0 if record_dt is None else record_dt
    w = grid.half_weights
    p = np.asarray(p0, dtype=float) / np.dot(w, p0)
    r = dt / grid.h**2
    ab = np.zeros((3, grid.n))
    ab[0, 1] = -2.0 * r
    ab[0, 2:] = -r
    ab[2, :-1] = -r
    temperature, a2 = _even_moments(grid, p)
    series: dict[str, list[float]] = {"t": [0.0], "temperature": [temperature], "a2": [a2],
                                      "rate": [math.nan]}
    t, rate, steps, converged, next_record = 0.0, math.inf, 0, False, record_dt
    bar = None
    if progress:
        from tqdm.auto import tqdm
        bar = tqdm(total=max_steps, desc=f"fd march alpha={alpha}", leave=False)
    while steps < max_steps and t < max_time:
        nu = loss_frequency(grid, p, density=1.0)
        gain = gain_term(grid, p, alpha=alpha, density=1.0, log_interp=log_interp,
                         order=order)
        # mass-defect rate of the discrete operator, removed so that the fixed point
        # is exactly the steady state of the discrete equations (see _fd_newton)
        defect = np.dot(w, laplacian(p, grid.h) + gain - nu * p)
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
        temperature, a2 = _even_moments(grid, p_new)
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


def _check_resolution(grid: HalfGrid, p: NDArray[np.float64], temperature: float) -> None:
    """Warn when the cut-off or the spacing is too coarse for the solution found."""
    s = math.sqrt(temperature)
    if s * p[-1] > 1e-40:
        warnings.warn(f"f at the cut-off is {s * p[-1]:.2e} > 1e-40: the cut-off "
                      f"{grid.v[-1] / s:.3g} sqrt(T) truncates the tail; increase cutoff",
                      ConvergenceWarning, stacklevel=3)
    keep = s * p > F_FLOOR
    steps = np.abs(np.diff(np.log(p[keep])))
    if steps.size and steps.max() > 1.0:
        warnings.warn(f"ln P changes by {steps.max():.2f} between neighbouring nodes where "
                      "f > 1e-30: the grid is too coarse for this alpha; reduce spacing",
                      ConvergenceWarning, stacklevel=3)


@dataclass(frozen=True)
class _UnitSolution:
    grid: HalfGrid
    p: NDArray[np.float64]
    info: RunInfo
    series: dict[str, NDArray[np.float64]]


def _solve_unit(alpha: float, *, spacing: float, cutoff: float, steady: str, dt: float | None,
                courant: float, implicit_loss: bool, log_interp: bool, order: int, tol: float,
                max_time: float | None, max_steps: int, initial_temperature: float,
                progress: bool) -> _UnitSolution:
    """Steady state of the unit problem on one grid."""
    start = time.perf_counter()
    temp_est = steady_temperature(alpha)
    scale = math.sqrt(temp_est)
    n_v = int(math.ceil(cutoff / spacing - 1e-9)) + 1
    grid = half_grid((n_v - 1) * spacing * scale, n_v)
    t0 = initial_temperature * temp_est
    p0 = np.exp(-grid.v**2 / (2.0 * t0))
    tau = relaxation_time(alpha)
    extra: dict[str, float | int | str] = {"n_v_half": n_v, "dv": grid.h, "cutoff_v": grid.v[-1],
                                           "steady": steady}
    nu_bound = grid.v[-1] + math.sqrt(max(t0, 2.0 * temp_est))
    if steady == "newton":
        # start with thinner-than-Gaussian tails: Newton raises a tail by a full
        # linear step but lowers it by about a factor 10 per iteration; nodes where
        # the start underflows stay at zero in the first Newton solve
        c = grid.v / math.sqrt(t0)
        p_start = np.exp(-0.5 * c**2 - (c / 3.0) ** 4)
        bulk = newton_steady(grid, p_start, alpha=alpha, log_interp=log_interp, order=order,
                             monitor_floor=_MONITOR_BULK)
        # the deep tail (below 1e-50) is slaved to the bulk and relaxes at the large
        # local rate nu(v): a few implicit steps settle it, then Newton polishes all
        polish = march(grid, bulk.p, alpha=alpha, dt=_POLISH_COURANT / nu_bound,
                       implicit_loss=True, log_interp=log_interp, order=order, tol=0.0,
                       max_steps=_POLISH_STEPS, stop=False)
        res = newton_steady(grid, polish.p, alpha=alpha, log_interp=log_interp, order=order,
                            monitor_floor=_MONITOR_TAIL)
        p, series = res.p, {}
        extra["mass_defect_rate"] = res.multiplier
        extra["newton_iterations"] = f"{bulk.iterations} (f > 1e-50) + {res.iterations} (all)"
        extra["polish_steps"] = polish.steps
        info = dict(converged=res.converged, iterations=bulk.iterations + res.iterations,
                    residual=res.residual, message=res.message)
    else:
        if dt is None:
            dt = courant / nu_bound
        elif not implicit_loss and dt * nu_bound > 1.0:
            raise ValueError(f"dt={dt:.3g} is too large for an explicit collision step: "
                             f"dt*nu_max can reach {dt * nu_bound:.3g} > 1 and make P negative. "
                             f"Use dt <= {0.5 / nu_bound:.3g} or implicit_loss=True")
        res = march(grid, p0, alpha=alpha, dt=dt, implicit_loss=implicit_loss,
                    log_interp=log_interp, order=order, tol=tol,
                    max_time=200.0 * tau if max_time is None else max_time,
                    max_steps=max_steps, progress=progress)
        p, series = res.p, res.series
        extra["dt"] = dt
        info = dict(converged=res.converged, iterations=res.steps, residual=res.rate,
                    message=("steady: tau*max|d ln P/dt| < tol" if res.converged else
                             f"not converged after {res.steps} steps, t={res.time:.4g}"))
    if not info["converged"]:
        warnings.warn(f"fd solver (steady={steady!r}) did not converge at alpha={alpha}: "
                      f"{info['message']}", ConvergenceWarning, stacklevel=3)
    temperature, _ = _even_moments(grid, p)
    _check_resolution(grid, p, temperature)
    info["wall_time"] = time.perf_counter() - start
    return _UnitSolution(grid, p, RunInfo(**info, extra=extra), series)


def _richardson(coarse: _UnitSolution, fine: _UnitSolution) -> NDArray[np.float64]:
    """:math:`(4\\ln P_{h/2} - \\ln P_h)/3` on the coarse nodes (fine values where zero)."""
    pf = fine.p[::2]
    pc = coarse.p
    out = pf.copy()
    ok = (pf > 0) & (pc > 0)
    out[ok] = np.exp((4.0 * np.log(pf[ok]) - np.log(pc[ok])) / 3.0)
    return out


@register_solver("fd", problem="heated")
def solve_fd(problem: HeatedProblem, *, spacing: float = 0.04, cutoff: float | None = None,
             steady: str = "march", richardson: bool = False, dt: float | None = None,
             courant: float = 0.5, implicit_loss: bool = False, log_interp: bool = True,
             interpolation_order: int = 2, tol: float = 1e-10, max_time: float | None = None,
             max_steps: int = 10**6,
             initial_temperature: float = 1.0, progress: bool = False) -> VelocityDistribution:
    """Heated steady state by the paper's finite-difference iteration.

    Parameters
    ----------
    problem : HeatedProblem
    spacing : float
        Grid spacing :math:`\\delta v` in units of :math:`\\sqrt{T}` (Sonine estimate).
    cutoff : float, optional
        Cut-off in units of :math:`\\sqrt{T}`, rounded up to a multiple of ``spacing``
        (so that halving the spacing nests the grids); default :func:`default_cutoff`.
    steady : {"march", "newton"}
        Time marching (the paper) or Newton on the same discrete steady equations.
    richardson : bool
        Extrapolate over ``spacing`` and ``spacing / 2`` (module docstring).
    dt : float, optional
        Time step of the unit problem; default ``courant / nu_max``.
    courant : float
        :math:`\\delta t\\, \\nu_{max}` when ``dt`` is not given; must be ``<= 1``.
    implicit_loss : bool
        Implicit loss term (positive for any ``dt``).
    log_interp : bool
        Interpolate :math:`\\ln P` (default) or :math:`P` at the gain-term argument.
    interpolation_order : {2, 3}
        Quadratic on the three nearest nodes (the paper) or cubic on four nodes; the
        interpolation error of the gain term is amplified by :math:`1/\\varepsilon` in the
        energy balance, so cubic pays off as :math:`\\alpha \\to 1`.
    tol : float
        Stopping criterion :math:`\\tau\\max|\\partial_t\\ln P| <` ``tol`` (see :func:`march`).
    max_time : float, optional
        Longest marching time of the unit problem (default 200 relaxation times).
    max_steps : int
        Most time steps.
    initial_temperature : float
        Temperature of the Gaussian start in units of the Sonine estimate.
    progress : bool
        Show a progress bar.

    Returns
    -------
    VelocityDistribution
        On the full symmetric grid with its Simpson weights; ``series`` holds the
        transient ``t, temperature, a2, rate`` (physical units) when marching.

    Raises
    ------
    ValueError
        For a spacing above 0.25 or a cut-off below 4 (in units of sqrt(T)), an unknown
        ``steady``, or a time step that breaks positivity.

    Examples
    --------
    >>> import kinetic_fem as kf
    >>> d = kf.solve_heated(0.5, method="fd", spacing=0.1, steady="newton")
    >>> round(d.a2, 3)
    0.058
    """
    problem.require("fd", gammas=(1.0,), constant_restitution=True, thermostats=(WhiteNoise,))
    spacing = check_positive("spacing", spacing)
    if spacing > 0.25:
        raise ValueError(f"spacing={spacing} sqrt(T) is too coarse; use spacing <= 0.25 "
                         "(0.02-0.05 for production accuracy)")
    alpha = problem.gas.alpha
    cutoff = default_cutoff(alpha) if cutoff is None else check_positive("cutoff", cutoff)
    if cutoff < 4.0:
        raise ValueError(f"cutoff={cutoff} sqrt(T) truncates the bulk of P; use cutoff >= 4 "
                         f"(default for alpha={alpha}: {default_cutoff(alpha):.3g})")
    if interpolation_order not in (2, 3):
        raise ValueError(f"interpolation_order must be 2 or 3, got {interpolation_order!r}")
    if steady not in ("march", "newton"):
        raise ValueError(f"steady must be 'march' or 'newton', got {steady!r}")
    courant = check_positive("courant", courant)
    if courant > 1.0 and not implicit_loss:
        raise ValueError(f"courant={courant} > 1 breaks positivity of the explicit collision "
                         "step; use courant <= 1 or implicit_loss=True")
    initial_temperature = check_positive("initial_temperature", initial_temperature)
    check_positive("tol", tol)
    options = dict(spacing=spacing, cutoff=cutoff, steady=steady, dt=dt, courant=courant,
                   implicit_loss=implicit_loss, log_interp=log_interp,
                   order=interpolation_order, tol=tol,
                   max_time=max_time, max_steps=max_steps,
                   initial_temperature=initial_temperature, progress=progress)
    sol = _solve_unit(alpha, **options)
    p, info = sol.p, sol.info
    if richardson:
        fine = _solve_unit(alpha, **{**options, "spacing": spacing / 2.0,
                                     "dt": None if dt is None else dt / 4.0})
        p = _richardson(sol, fine)
        extra = {**info.extra, "richardson": True, "fine": dict(fine.info.extra)}
        info = RunInfo(converged=info.converged and fine.info.converged,
                       iterations=info.iterations + fine.info.iterations,
                       residual=max(info.residual, fine.info.residual),
                       wall_time=info.wall_time + fine.info.wall_time,
                       message=info.message, extra=extra)
    u = problem.velocity_scale
    time_unit = u**2 / problem.diffusion
    series = dict(sol.series)
    if series:
        series["t"] = series["t"] * time_unit
        series["temperature"] = series["temperature"] * u**2
        series["rate"] = series["rate"] / time_unit
    grid = sol.grid
    params = {**problem.as_dict(), "spacing": spacing, "cutoff": cutoff, "steady": steady,
              "richardson": richardson, "log_interp": log_interp,
              "interpolation_order": interpolation_order}
    return VelocityDistribution.from_values(grid.v_full * u, grid.full(p) / u,
                                            weights=grid.weights * u, method="fd",
                                            params=params, info=info, series=series)
