"""The paper's implicit finite-difference iteration (Biben's method), ``method="fd"``.

Time marching of the homogeneous Boltzmann equation of the heated gas (Barrat et al.
2002, section 2.1.3)

.. math::

    \\partial_t P - D\\partial_v^2 P = -\\nu[P](v) P(v) + G[P](v), \\qquad
    \\nu[P](v) = n\\int dv' |v-v'| P(v'),

    G[P](v) = \\frac{4n}{(1+\\alpha)^2}\\int dv' |v-v'| P(v')
              P\\Big(\\frac{2v-(1-\\alpha)v'}{1+\\alpha}\\Big),

to its steady state.  Discretisation (all at ``n = D = 1``; other ``n``, ``D``
follow exactly by :math:`v \\to (D/n)^{1/(2+\\gamma)} v`, see
:mod:`kinetic_fem.solvers.fd_scales`):

* :math:`P` on the half grid :math:`v_i = i\\,\\delta v`, ``i = 0 .. N - 1``, using
  :math:`P(-v) = P(v)`; spacing and cut-off are given in units of the estimate of
  :math:`\\sqrt{T}` (first-order Sonine, :func:`kinetic_fem.sonine.steady_temperature`,
  for hard rods under white noise; the model's Gaussian closure otherwise).
* Collision term by Simpson's rule on the mirrored grid with the kink correction
  (:func:`kinetic_fem.operators.grid.simpson_kink_correction`), :math:`\\nu` in O(N) by
  cumulative moments, the gain term in O(N^2) with quadratic interpolation of the
  off-grid argument (of :math:`\\ln P` by default) and :math:`P = 0` beyond the cut-off
  (:func:`kinetic_fem.operators.collision.gain_term`).
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

``steady="newton"`` (the default) solves the same discrete steady equations (with the
normalisation and its Lagrange multiplier) by Newton's method on the relative change
of :math:`P` (see :mod:`kinetic_fem.solvers.fd_newton`): first on the nodes with f > 1e-50,
then, after a few implicit steps that settle the deep tail, on all nodes down to 1e-200.

Accuracy.  The scheme is second order in :math:`\\delta v`: one grid at
:math:`\\delta v = 0.04\\sqrt T` misses T by about 2e-5 and a2 by about 2e-4
(alpha = 0.6), and the tail at f ~ 1e-30 by several per cent.  The default therefore
extrapolates (``richardson=2``): solutions at ``spacing`` (0.08, finer near elastic
collisions), ``spacing/2`` and
``spacing/4`` (the finer ones started from the coarser), combined on the coarse nodes as
:math:`R_1 = (4\\ln P_{h/2} - \\ln P_h)/3` per pair and
:math:`R_2 = (16 R_1(h/2) - R_1(h))/15`.  With the cubic interpolation of the gain
argument (the default; the paper's quadratic one has an error that is not smooth in
the spacing, which extrapolation does not remove) this reaches T to ~1e-8, a2 to
~1e-8 and f to ~1e-4 relative where f > 1e-30 (``benchmarks/convergence_fd.py``).  Every result
states its order and an error estimate in ``info.extra``: ``order`` (2),
``richardson`` (levels), and ``estimated_error_temperature`` (relative),
``estimated_error_a2`` (absolute), ``estimated_error_f`` (max relative where
f > 1e-30), the difference between the result and the next less extrapolated one (an
upper estimate of the error); NaN without Richardson (a single grid gives no
estimate).  ``energy_balance_residual`` (claim C1) checks them independently.

Models (issue 9): constant restitution only (the gain term's pre-collision velocity
is linear in :math:`v` only then); the kernels :math:`|g|` (hard rods, the paper) and
:math:`|g|^0` (Maxwell: :math:`\\nu = n`, the gain a plain convolution); white noise or
a Fokker-Planck bath, whose drift :math:`\\partial_v(\\xi v P)` joins the Laplacian in
the implicit operator and in the Newton system.
"""

from __future__ import annotations

import logging
import math
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..distribution import RunInfo, VelocityDistribution
from ..error import ErrorRecipe, comparison_recipe
from ..exceptions import ConvergenceError, ConvergenceWarning
from ..gas import HeatedProblem, check_positive
from ..model import FokkerPlanckBath, UnsupportedModelError, WhiteNoise
from ..operators.collision import HalfGrid, half_grid, pair_moment
from ..options import gather_groups, option_group
from ..solve import register_solver
from .fd_march import F_FLOOR, MarchOptions, MarchResult, even_moments, march
from .fd_newton import FDOperator, newton_steady
from .fd_scales import UnitModel, default_cutoff
from .fem.heated import refinement_factor
from .richardson import RICHARDSON_METHOD, richardson_log

__all__ = ["ConvergenceWarning", "default_cutoff", "march", "MarchResult", "solve_fd_heated",
           "FDScheme", "FDOperator", "MarchOptions", "F_FLOOR", "ORDER"]

logger = logging.getLogger(__name__)

ORDER = 2
"""Order of the finite-difference scheme in the spacing."""
_MONITOR_BULK, _MONITOR_TAIL = 1e-50, 1e-200
_POLISH_COURANT, _POLISH_STEPS = 200.0, 100


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


@option_group
@dataclass(frozen=True)
class FDScheme:
    """The discretisation of :func:`solve_fd_heated`: its grids and its gain term.

    Parameters
    ----------
    spacing : float, optional
        Grid spacing :math:`\\delta v` of the coarsest grid, in units of the estimated
        :math:`\\sqrt{T}`; default 0.08, finer near elastic collisions
        (:meth:`kinetic_fem.solvers.fd_scales.UnitModel.spacing`: 0.043 at alpha = 0.99,
        0.02 from alpha = 0.992 on).
    cutoff : float, optional
        Cut-off in units of :math:`\\sqrt{T}`, rounded up to a multiple of ``spacing``
        (so that halving the spacing nests the grids); default from the model
        (:class:`kinetic_fem.solvers.fd_scales.UnitModel`; :func:`default_cutoff` for hard
        rods under white noise).
    richardson : {2, 1, 0} or bool
        Levels of Richardson extrapolation: 2 (default) combines ``spacing``,
        ``spacing/2``, ``spacing/4``; 1 or ``True`` the first two; 0 or ``False`` one
        grid (second order, no error estimate).  The cost of Newton grows as
        :math:`(1/\\delta v)^3`: the grid of ``spacing/4`` dominates.
    log_interp : bool
        Interpolate :math:`\\ln P` (default) or :math:`P` at the gain-term argument.
    interpolation_order : {3, 2}
        Cubic on four nodes (default) or quadratic on the three nearest nodes (the
        paper).  The interpolation error of the gain term is amplified by
        :math:`1/\\varepsilon` in the energy balance, and the quadratic one is not a
        smooth function of the spacing (the stencil jumps with the argument), so
        Richardson does not remove it: at alpha = 0.99 the extrapolated quadratic
        result misses T by 1.7e-5 while its estimate says 1.3e-7 (cubic: 2e-8).

    Examples
    --------
    >>> FDScheme(spacing=0.1, richardson=0)  # doctest: +NORMALIZE_WHITESPACE
    FDScheme(spacing=0.1, cutoff=None, richardson=0, log_interp=True,
             interpolation_order=3)
    """

    spacing: float | None = None
    cutoff: float | None = None
    richardson: bool | int = 2
    log_interp: bool = True
    interpolation_order: int = 3


@dataclass(frozen=True)
class _UnitSolution:
    grid: HalfGrid
    p: NDArray[np.float64]
    info: RunInfo
    series: dict[str, NDArray[np.float64]]


def _solve_unit(model: UnitModel, operator: FDOperator, marching: MarchOptions, *,
                spacing: float, intervals: int, steady: str, initial_temperature: float,
                start: NDArray[np.float64] | None = None) -> _UnitSolution:
    """Steady state of the unit problem on one grid (``start``: a guess on this grid)."""
    t_start = time.perf_counter()
    alpha, gamma, xi = model.alpha, model.gamma, model.friction
    temp_est = model.temperature
    n_v = intervals + 1
    grid = half_grid(intervals * spacing * math.sqrt(temp_est), n_v)
    t0 = initial_temperature * temp_est
    extra: dict[str, float | int | str] = {"n_v_half": n_v, "dv": grid.h,
                                           "cutoff_v": float(grid.v[-1]), "steady": steady}
    nu_bound = grid.v[-1] + math.sqrt(max(t0, 2.0 * temp_est)) if gamma == 1.0 else 1.0
    series: dict[str, NDArray[np.float64]] = {}
    info: dict[str, Any]
    warm = None
    if steady == "newton" and start is not None:
        # a finer grid of a Richardson sequence, started from the coarser solution; if
        # that start is too rough (an under-resolved coarse tail), start afresh
        warm = newton_steady(grid, start, operator, monitor_floor=_MONITOR_TAIL, max_iter=15)
        if not warm.converged:
            logger.debug("fd: Newton from the coarser grid failed (%s); cold start",
                         warm.message)
            warm = None
    if warm is not None:
        p = warm.p
        extra["mass_defect_rate"] = float(warm.multiplier)
        extra["newton_iterations"] = f"{warm.iterations} (all, from the coarser grid)"
        info = dict(converged=warm.converged, iterations=warm.iterations,
                    residual=warm.residual, message=warm.message)
    elif steady == "newton":
        # start with thinner-than-Gaussian tails: Newton raises a tail by a full
        # linear step but lowers it by about a factor 10 per iteration; nodes where
        # the start underflows stay at zero in the first Newton solve
        c = grid.v / math.sqrt(t0)
        p_start = np.exp(-0.5 * c**2 - (c / 3.0) ** 4)
        bulk = newton_steady(grid, p_start, operator, monitor_floor=_MONITOR_BULK)
        # the deep tail (below 1e-50) is slaved to the bulk and relaxes at the large
        # local rate nu(v): a few implicit steps settle it, then Newton polishes all
        # (skipped where the bath drift makes the implicit step lose its M-matrix)
        polish = None
        if 0.5 * xi * grid.v[-1] * grid.h <= 1.0:
            polish = march(grid, bulk.p, operator, dt=_POLISH_COURANT / nu_bound,
                           implicit_loss=True, tol=0.0, max_steps=_POLISH_STEPS, stop=False,
                           tau=model.relaxation_time)
        res = newton_steady(grid, bulk.p if polish is None else polish.p, operator,
                            monitor_floor=_MONITOR_TAIL)
        p = res.p
        extra["mass_defect_rate"] = float(res.multiplier)
        extra["newton_iterations"] = f"{bulk.iterations} (f > 1e-50) + {res.iterations} (all)"
        extra["polish_steps"] = 0 if polish is None else polish.steps
        info = dict(converged=res.converged, iterations=bulk.iterations + res.iterations,
                    residual=res.residual, message=res.message)
    else:
        dt, implicit_loss = marching.dt, marching.implicit_loss
        if dt is None:
            dt = marching.courant / nu_bound
        elif not implicit_loss and dt * nu_bound > 1.0:
            raise ValueError(f"dt={dt:.3g} is too large for an explicit collision step: "
                             f"dt*nu_max can reach {dt * nu_bound:.3g} > 1 and make P negative. "
                             f"Use dt <= {0.5 / nu_bound:.3g} or implicit_loss=True")
        tau = model.relaxation_time
        max_time = 200.0 * tau if marching.max_time is None else marching.max_time
        marched = march(grid, np.exp(-grid.v**2 / (2.0 * t0)), operator,
                        replace(marching, dt=dt, max_time=max_time), tau=tau)
        p, series = marched.p, marched.series
        extra["dt"] = dt
        info = dict(converged=marched.converged, iterations=marched.steps,
                    residual=marched.rate,
                    message=("steady: tau*max|d ln P/dt| < tol" if marched.converged else
                             f"not converged after {marched.steps} steps, "
                             f"t={marched.time:.4g}"))
    if not info["converged"]:
        warnings.warn(f"fd solver (steady={steady!r}) did not converge at alpha={alpha}: "
                      f"{info['message']}", ConvergenceWarning, stacklevel=4)
    info["wall_time"] = time.perf_counter() - t_start
    extra["wall_time"] = info["wall_time"]
    return _UnitSolution(grid, p, RunInfo(**info, extra=extra), series)


def _refine(coarse: _UnitSolution) -> NDArray[np.float64]:
    """Start on the grid of half the spacing: ``ln P`` interpolated linearly."""
    p = coarse.p
    out = np.zeros(2 * p.size - 1)
    out[::2] = p
    mid = np.sqrt(p[:-1] * p[1:])
    out[1::2] = mid
    return out


def _error_estimate(grid: HalfGrid, best: NDArray[np.float64], result: NDArray[np.float64]
                    ) -> dict[str, float]:
    """Differences of T (relative), a2 (absolute) and f (max relative, f > 1e-30) of the
    result from the more extrapolated level ``best``."""
    t_b, a2_b = even_moments(grid, best)
    t_r, a2_r = even_moments(grid, result)
    keep = (math.sqrt(t_r) * result > F_FLOOR) & (best > 0)
    return {"estimated_error_temperature": float(abs(t_b / t_r - 1.0)),
            "estimated_error_a2": float(abs(a2_b - a2_r)),
            "estimated_error_f": float(np.max(np.abs(result[keep] / best[keep] - 1.0)))}


def _energy_residual(model: UnitModel, grid: HalfGrid, p: NDArray[np.float64],
                     temperature: float) -> float:
    """:math:`|2D - 2\\xi T - \\tfrac n4(1-\\alpha^2)\\langle|g|^{\\gamma+2}\\rangle|/(2D)`
    of the result (claim C1, unit problem): zero for the exact steady state, so an
    independent check of the error estimates."""
    if model.gamma == 1.0:
        g_moment = pair_moment(grid.v_full, grid.full(p), grid.weights, 3)
    else:
        g_moment = 2.0 * temperature  # <g^2> = 2 <v^2> for an even P of unit mass
    loss = 0.25 * (1.0 - model.alpha**2) * g_moment
    return float(abs(2.0 - 2.0 * model.friction * temperature - loss) / 2.0)


def _richardson_levels(richardson: bool | int) -> int:
    if isinstance(richardson, bool):
        return int(richardson)
    if not isinstance(richardson, (int, np.integer)) or richardson not in (0, 1, 2):
        raise ValueError(f"richardson must be 0/False (one grid), 1/True (spacing, "
                         f"spacing/2) or 2 (spacing, spacing/2, spacing/4), got {richardson!r}")
    return int(richardson)


@register_solver("fd", problem="heated")
def solve_fd_heated(problem: HeatedProblem, *, scheme: FDScheme | None = None,
                    marching: MarchOptions | None = None, steady: str = "newton",
                    initial_temperature: float = 1.0, accuracy: float | None = None,
                    **keywords: Any) -> VelocityDistribution:
    """Heated steady state by the paper's finite-difference scheme.

    A second-order method; the default extrapolates over three grids (module
    docstring, "Accuracy") and reports its estimated error in ``info.extra``.

    Parameters
    ----------
    problem : HeatedProblem
        Constant restitution, kernel ``gamma`` 1 or 0, white noise or a Fokker-Planck
        bath.
    scheme : FDScheme, optional
        The discretisation: ``spacing``, ``cutoff``, ``richardson``, ``log_interp``,
        ``interpolation_order`` (:class:`FDScheme`).
    marching : MarchOptions, optional
        The time marching of ``steady="march"``: ``dt`` (of the coarsest grid, divided by
        4 per halving; default ``courant / nu_max``), ``courant`` (must be ``<= 1``
        without ``implicit_loss``), ``implicit_loss``, ``tol``, ``max_time`` (default 200
        relaxation times), ``max_steps``, ``progress``
        (:class:`kinetic_fem.solvers.fd_march.MarchOptions`).
    steady : {"newton", "march"}
        Newton on the discrete steady equations, or time marching (the paper); both
        reach the same discrete steady state.
    initial_temperature : float
        Temperature of the Gaussian start in units of the estimate.
    accuracy : float, optional
        Target accuracy of T (relative) and a2 (absolute): the spacing is refined (at
        most :data:`MAX_REFINEMENTS` times, at the observed rate, not below
        :data:`MIN_SPACING`) until ``dist.error`` meets it (needs ``richardson`` 1 or 2).
    **keywords
        Any field of ``scheme`` or ``marching`` by keyword, over those objects
        (``kf.solve_heated(0.5, method="fd", spacing=0.1, richardson=0)``); an unknown
        name raises :class:`TypeError`.

    Returns
    -------
    VelocityDistribution
        On the full symmetric grid of ``spacing`` with its Simpson weights; ``series``
        holds the transient ``t, temperature, a2, rate`` (physical units) of the
        coarsest grid when marching.  ``info.extra`` holds ``order`` (2),
        ``richardson`` (levels), the ``estimated_error_*`` figures (module docstring;
        NaN without Richardson), ``energy_balance_residual`` (C1, relative to
        :math:`2D`; an independent check), ``spacings`` and the per-grid details.

    Raises
    ------
    TypeError
        For a keyword that is neither a scheme nor a marching option.
    ValueError
        For a spacing above 0.25 or a cut-off below 4 (in units of sqrt(T)), an unknown
        ``steady`` or ``richardson``, or a time step that breaks positivity.
    UnsupportedModelError
        For a restitution law or a kernel other than gamma = 0, 1.
    ConvergenceError
        If ``accuracy`` is not met within :data:`MAX_REFINEMENTS` refinements down to
        :data:`MIN_SPACING` (the message says what was reached).

    Examples
    --------
    >>> import kinetic_fem as kf
    >>> d = kf.solve_heated(0.5, method="fd", spacing=0.1, richardson=0)
    >>> round(d.a2, 3), d.info.extra["order"]
    (0.058, 2)
    """
    sch, marching = gather_groups(((FDScheme, scheme), (MarchOptions, marching)), keywords,
                                  "solve_fd_heated")
    if accuracy is not None:
        return _refine_to_accuracy(problem, sch, marching, steady, initial_temperature,
                                   check_positive("accuracy", accuracy))
    if problem.gas.restitution.constant is None:
        raise UnsupportedModelError(
            f"the paper's FD method needs a constant restitution coefficient (its gain term "
            f"interpolates P at the pre-collision velocity, linear in v only for constant "
            f"alpha), got {problem.gas.restitution!r}; use method='fem'")
    problem.require("fd", gammas=(0.0, 1.0), constant_restitution=True,
                    thermostats=(WhiteNoise, FokkerPlanckBath))
    spacing, cutoff, richardson = sch.spacing, sch.cutoff, sch.richardson
    log_interp, interpolation_order = sch.log_interp, sch.interpolation_order
    courant, implicit_loss, tol = marching.courant, marching.implicit_loss, marching.tol
    model = UnitModel.from_problem(problem)
    spacing = model.spacing() if spacing is None else check_positive("spacing", spacing)
    if spacing > 0.25:
        raise ValueError(f"spacing={spacing} sqrt(T) is too coarse; use spacing <= 0.25 "
                         "(0.02-0.08 for production accuracy)")
    default = model.cutoff()
    cutoff = default if cutoff is None else check_positive("cutoff", cutoff)
    if cutoff < 4.0:
        raise ValueError(f"cutoff={cutoff} sqrt(T) truncates the bulk of P; use cutoff >= 4 "
                         f"(default for this model: {default:.3g})")
    if interpolation_order not in (2, 3):
        raise ValueError(f"interpolation_order must be 2 or 3, got {interpolation_order!r}")
    if steady not in ("march", "newton"):
        raise ValueError(f"steady must be 'march' or 'newton', got {steady!r}")
    levels = _richardson_levels(richardson)
    courant = check_positive("courant", courant)
    if courant > 1.0 and not implicit_loss:
        raise ValueError(f"courant={courant} > 1 breaks positivity of the explicit collision "
                         "step; use courant <= 1 or implicit_loss=True")
    initial_temperature = check_positive("initial_temperature", initial_temperature)
    check_positive("tol", tol)
    marching = replace(marching, courant=courant)
    operator = FDOperator(model.alpha, gamma=model.gamma, friction=model.friction,
                          log_interp=log_interp, order=interpolation_order)
    # the cut-off is rounded up to a multiple of the spacing, so that the grids of
    # spacing/2 and spacing/4 (Richardson) have exactly 2 and 4 times as many intervals
    intervals = int(math.ceil(cutoff / spacing - 1e-9))
    sols: list[_UnitSolution] = []
    for k in range(levels + 1):
        start = _refine(sols[-1]) if sols and steady == "newton" else None
        level = marching if marching.dt is None else replace(marching, dt=marching.dt / 4**k)
        sols.append(_solve_unit(model, operator, level, spacing=spacing / 2**k,
                                intervals=intervals * 2**k, steady=steady,
                                initial_temperature=initial_temperature, start=start))
    sol = sols[0]
    grid = sol.grid
    extra: dict[str, object] = {**sol.info.extra, "order": ORDER, "richardson": levels,
                                "spacings": [spacing / 2**k for k in range(levels + 1)]}
    if levels:
        # the result is the next-to-best level, whose error the best level measures
        # (issue 29: the best one's own error has no estimate from these grids)
        best, p = richardson_log([s.p for s in sols])
        extra.update(_error_estimate(grid, best, p))
        extra["grids"] = [dict(s.info.extra) for s in sols[1:]]
    else:
        p = sol.p
        extra.update(estimated_error_temperature=math.nan, estimated_error_a2=math.nan,
                     estimated_error_f=math.nan)
    temperature, _ = even_moments(grid, p)
    _check_resolution(grid, p, temperature)
    extra["energy_balance_residual"] = _energy_residual(model, grid, p, temperature)
    info = RunInfo(converged=all(s.info.converged for s in sols),
                   iterations=sum(s.info.iterations for s in sols),
                   residual=max(s.info.residual for s in sols),
                   wall_time=sum(s.info.wall_time for s in sols),
                   message=sols[-1].info.message, extra=extra)
    u = problem.velocity_scale
    time_unit = problem.time_scale
    series = dict(sol.series)
    if series:
        series["t"] = series["t"] * time_unit
        series["temperature"] = series["temperature"] * u**2
        series["rate"] = series["rate"] / time_unit
    params = {**problem.as_dict(), "spacing": spacing, "cutoff": cutoff, "steady": steady,
              "richardson": levels, "log_interp": log_interp,
              "interpolation_order": interpolation_order}
    dist = VelocityDistribution.from_values(grid.v_full * u, grid.full(p) / u,
                                            weights=grid.weights * u, method="fd",
                                            params=params, info=info, series=series)
    return dist.with_error(_richardson_recipe(grid, p, best) if levels else None)


MAX_REFINEMENTS = 3
"""Most refinements of the spacing with ``accuracy=`` (:func:`solve_fd_heated`)."""
MIN_SPACING = 0.02
"""The finest coarse spacing ``accuracy=`` tries (sqrt(T) units; its finest grid has a
quarter of it): at 0.03 the solve takes about 6 times the default's CPU."""


def _refine_to_accuracy(problem: HeatedProblem, sch: FDScheme, marching: MarchOptions,
                        steady: str, initial_temperature: float, accuracy: float
                        ) -> VelocityDistribution:
    """``accuracy=`` of :func:`solve_fd_heated`."""
    levels = _richardson_levels(sch.richardson)
    spacing = UnitModel.from_problem(problem).spacing() if sch.spacing is None else sch.spacing
    return refine_spacing(
        lambda h: solve_fd_heated(problem, scheme=replace(sch, spacing=h), marching=marching,
                                  steady=steady, initial_temperature=initial_temperature),
        spacing, levels, accuracy, "T and a2")


def refine_spacing(solve_at: Callable[[float], VelocityDistribution], spacing: float,
                   levels: int, accuracy: float, what: str) -> VelocityDistribution:
    """The result at ``spacing``, refined at the observed rate (the result is of order
    ``2 * levels``) until its ``dist.error`` meets ``accuracy`` in T, a2 (and zeta where
    it has one), at most :data:`MAX_REFINEMENTS` times, not below :data:`MIN_SPACING`.

    Parameters
    ----------
    solve_at : callable
        ``spacing -> VelocityDistribution``.
    spacing : float
        The first spacing.
    levels : int
        Richardson levels (1 or 2; 0 raises: no estimate).
    accuracy : float
        The target.
    what : str
        The quantities compared, for the message.

    Returns
    -------
    VelocityDistribution

    Raises
    ------
    ValueError
        For ``levels`` 0.
    ConvergenceError
        If the target is not met (the message says what was reached).
    """
    if levels == 0:
        raise ValueError("accuracy= needs the Richardson estimate: use richardson=1 or 2, "
                         "got richardson=0")
    history: list[tuple[float, float]] = []
    for _ in range(MAX_REFINEMENTS + 1):
        dist = solve_at(spacing)
        est = dist.error
        err = max(est.temperature, est.a2, est.zeta or 0.0)
        logger.info("accuracy=%g: fd spacing %.4g, estimated error %.2e", accuracy, spacing,
                    err)
        if err <= accuracy:
            return dist
        history.append((spacing, err))
        if spacing <= MIN_SPACING:
            break
        spacing = max(MIN_SPACING, spacing * refinement_factor(history, accuracy,
                                                               2 * levels - 1))
    zeta = "" if est.zeta is None else f", zeta {est.zeta:.2g}"
    raise ConvergenceError(
        f"FD did not reach accuracy={accuracy:g} ({what}) after {len(history)} spacings "
        f"(the finest tried {MIN_SPACING:g} thermal velocities): at spacing "
        f"{history[-1][0]:.3g} the estimated errors are T {est.temperature:.2g} "
        f"(relative), a2 {est.a2:.2g}{zeta}; use method='fem'")


def _richardson_recipe(grid: HalfGrid, result: NDArray[np.float64],
                       best: NDArray[np.float64]) -> ErrorRecipe:
    """``dist.error``: the result against the one more extrapolated level (unit problem)."""
    def pair() -> tuple[VelocityDistribution, VelocityDistribution]:
        return tuple(VelocityDistribution.from_values(grid.v_full, grid.full(q),  # type: ignore
                                                      weights=grid.weights)
                     for q in (result, best))

    return comparison_recipe(pair, RICHARDSON_METHOD)
