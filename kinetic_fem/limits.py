"""What the deterministic solvers can answer, checked where a request enters.

* Scales: the temperature of a heated problem must lie in
  :data:`TEMPERATURE_RANGE`, so that the moments up to order
  :data:`~kinetic_fem.distribution.MAX_MOMENT` (``T^6``) stay inside double precision
  (``n = 1e300`` gave ``T = 2e-200`` and ``a2 = nan``).  The estimate is the Gaussian
  closure :meth:`~kinetic_fem.model.HeatedProblem.temperature_estimate`.
* The near-elastic frontier (:data:`FRONTIER`): the smallest ``1 - alpha`` each
  method resolves with its default discretisation; closer to elastic collisions the
  request is refused at once, naming the quasi-elastic solutions
  (:func:`kinetic_fem.scaling.solve_phi`, :func:`~kinetic_fem.scaling.solve_psi`).
* A converged result is a physical state (:func:`check_result`): finite positive
  temperature, finite values and moments, positive mass, and a mesh long enough that
  the part of :math:`\\langle c^4\\rangle` beyond its ends is negligible; otherwise
  :class:`~kinetic_fem.exceptions.ConvergenceError` says which check failed.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Iterable

import numpy as np

from .distribution import VelocityDistribution
from .exceptions import ConvergenceError
from .model import CoolingProblem, HeatedProblem, InelasticGas

logger = logging.getLogger(__name__)

__all__ = ["TEMPERATURE_RANGE", "FRONTIER", "SLOW_EPS", "MESH_OPTIONS", "check_scale",
           "check_frontier", "check_result", "check_cooling_span"]

TEMPERATURE_RANGE = (1e-24, 1e24)
"""Temperatures a heated problem may have: ``T^6`` stays far inside double precision."""

FRONTIER: dict[tuple[str, str], float] = {
    ("heated", "fem"): 1e-7, ("cooling", "fem"): 1e-6,
}
"""Smallest ``eps = 1 - alpha`` per (problem, method) with the default discretisation.

The measured capability of the defaults: the FEM cooling state's continuation reaches
1 - alpha = 1e-6 (``solvers.fem.cooling_links.HUMP_FRONTIER``; the slow test
``test_near_elastic_frontier_alpha_0999999`` checks zeta and a2 there to 2e-10, 38 CPU s
idle, 107 at load 13), the heated state 1e-7 (a2 within 1e-8 of the quasi-elastic
expansion, ``benchmarks/results/heated_near_elastic.md``; at 1e-8 round-off in the O(eps)
cancellation of gain and loss spoils a2).  Below :data:`SLOW_EPS` both take from tens of
seconds to minutes: :func:`check_frontier` logs a warning that says so.  Measured (issue 28, on a
loaded 2-core machine, default options): the cooling state at alpha = 0.9999 takes
7.4 s of CPU, at 0.99999 more than 60 s and at 0.999999 more than 400 s of wall time
(1 - 1e-9: minutes, then a failure); the heated state at 0.999 / 0.9995 1.4 / 1.7 s
of CPU, at 0.9999 more than 150 s and at 0.99999 more than 60 s of wall time.  The
frontier applies to the default discretisation only: a mesh given as an option
(:data:`MESH_OPTIONS`) is the caller's choice.  Methods not listed state no frontier."""

SLOW_EPS = 1e-4
"""Below this ``1 - alpha`` the default FEM solves take tens of seconds or more."""

MESH_OPTIONS = frozenset({"spacing", "vertices", "cutoff", "resolution", "n_v", "c_max"})
"""Options that replace the default discretisation (the frontier is then not applied)."""

_TAIL_SHARE = 1e-3
"""Largest share of :math:`\\langle c^4\\rangle` the ends of the mesh may leave out."""


def check_scale(problem: HeatedProblem) -> float:
    """The estimated temperature, refusing one outside :data:`TEMPERATURE_RANGE`.

    Parameters
    ----------
    problem : HeatedProblem
        The request.

    Returns
    -------
    float
        The Gaussian-closure temperature.

    Raises
    ------
    ValueError
        With the parameters, the estimate and the allowed range.
    """
    lo, hi = TEMPERATURE_RANGE
    what = (f"density={problem.gas.density:g}, diffusion={problem.diffusion:g}, "
            f"friction={problem.friction:g}, alpha={problem.gas.restitution!r}")
    try:
        t = float(problem.temperature_estimate())
    except (ArithmeticError, ValueError) as err:
        raise ValueError(f"{what}: the temperature scale cannot be estimated ({err}); "
                         f"temperatures must lie in [{lo:g}, {hi:g}]") from None
    if not lo <= t <= hi:
        raise ValueError(f"{what} put the temperature near {t:.3g}, outside [{lo:g}, {hi:g}] "
                         "where the moments up to order 12 stay within double precision; "
                         "the equation scales exactly (v -> s v): solve with parameters of "
                         "order one and rescale (VelocityDistribution.rescaled)")
    return t


def check_frontier(problem: HeatedProblem | CoolingProblem, method: str,
                   options: Iterable[str] = ()) -> None:
    """Refuse at once a constant ``alpha`` closer to 1 than the method resolves.

    Parameters
    ----------
    problem : HeatedProblem or CoolingProblem
        The request.
    method : str
        The registry key.
    options : iterable of str
        The option names given; with one of :data:`MESH_OPTIONS` nothing is refused.

    Raises
    ------
    ValueError
        Naming the frontier and the quasi-elastic solutions.
    """
    alpha = problem.gas.restitution.constant
    kind = "cooling" if isinstance(problem, CoolingProblem) else "heated"
    eps_min = FRONTIER.get((kind, method))
    if (alpha is None or eps_min is None or alpha == 1.0
            or MESH_OPTIONS.intersection(options)):
        return
    if isinstance(problem, HeatedProblem) and problem.friction > 0.0:
        return  # a bath keeps the state at its temperature: no near-elastic limit
    if 1.0 - alpha >= eps_min:
        if 1.0 - alpha < SLOW_EPS:
            logger.warning("alpha=%r is close to elastic collisions (1 - alpha = %.3g < %g): "
                           "the %s FEM state takes tens of seconds to minutes; the "
                           "quasi-elastic solution kinetic_fem.scaling.%s is instant",
                           alpha, 1.0 - alpha, SLOW_EPS, kind,
                           "solve_psi" if kind == "cooling" else "solve_phi")
        return
    scaled = "solve_psi (cooling, scaled by eps)" if kind == "cooling" else \
        "solve_phi (heated, scaled by eps^(1/3))"
    raise ValueError(f"alpha={alpha!r} (1 - alpha = {1.0 - alpha:.3g}) is beyond the "
                     f"near-elastic frontier of the {kind} method {method!r}: 1 - alpha >= "
                     f"{eps_min:g} (the state's width shrinks with 1 - alpha until the "
                     "mesh or expansion cannot resolve it in reasonable time); closer to "
                     f"elastic collisions use the quasi-elastic solution kinetic_fem.scaling."
                     f"{scaled}, or give the mesh yourself (one of {sorted(MESH_OPTIONS)}) "
                     "to run the method anyway (minutes or more)")


def _tail_c4(c: np.ndarray, f: np.ndarray) -> float:
    """:math:`\\int_L^\\infty c^4 f` beyond the last node ``L``, for ``f ~ e^{-k c}`` there.

    ``k`` is the local decay rate from the last two nodes; without decay the estimate is
    ``L^5 f(L)`` (what a :math:`c^{-4}` tail would leave, up to a factor 4).
    """
    big_l, f1, f0 = abs(float(c[-1])), abs(float(f[-1])), abs(float(f[-2]))
    if f1 == 0.0:
        return 0.0
    k = math.log(f0 / f1) / abs(float(c[-1] - c[-2])) if f0 > f1 else 0.0
    return big_l**4 * f1 / k if k > 1.0 / big_l else big_l**5 * f1


def check_result(dist: VelocityDistribution, *, check_tail: bool = True) -> VelocityDistribution:
    """Raise if a result that says ``converged`` is not a physical state.

    Parameters
    ----------
    dist : VelocityDistribution
        A solver's result.
    check_tail : bool
        Check that the mesh holds :math:`\\langle c^4\\rangle` (False for a state
        without a finite fourth moment: the Maxwell model's cooling state).

    Returns
    -------
    VelocityDistribution
        ``dist`` itself.

    Raises
    ------
    ConvergenceError
        Saying which check failed: non-finite values, mass, mean or temperature, a
        temperature that is not positive, ``a2 = nan`` (``+inf`` is the Maxwell model's
        cooling state), a non-positive mass, or a mesh whose ends leave out
        more than 0.1 % of :math:`\\langle c^4\\rangle` (the state is not resolved;
        estimated from the decay over the last element).
    """
    if not dist.info.converged:
        return dist
    problem = f"the {dist.method!r} result ({dist.info.message!r})"
    if not (np.all(np.isfinite(dist.values)) and np.all(np.isfinite(dist.raw_moments[:3]))):
        raise ConvergenceError(f"{problem} holds non-finite values or moments")
    if not dist.raw_moments[0] > 0:
        raise ConvergenceError(f"{problem} has mass {dist.raw_moments[0]!r}, not positive")
    t, a2 = dist.temperature, dist.a2
    # (a2 = +inf is physical: the Maxwell model's cooling state has a c^-4 tail)
    if not (math.isfinite(t) and t > 0 and not math.isnan(a2)):
        raise ConvergenceError(f"{problem} has T = {t!r}, a2 = {a2!r}: not a physical state")
    if check_tail and dist.errors is None and dist.v.size > 1 and math.isfinite(a2):
        tail = max(_tail_c4(dist.c, dist.f_values), _tail_c4(-dist.c[::-1],
                                                              dist.f_values[::-1]))
        if not tail <= _TAIL_SHARE * 3.0 * (1.0 + a2):
            raise ConvergenceError(
                f"{problem} is not resolved: beyond the ends of the mesh (|c| = "
                f"{np.abs(dist.c[[0, -1]]).max():.3g}) int c^4 f ~ {tail:.3g}, more than "
                f"{_TAIL_SHARE:g} of <c^4> = {3.0 * (1.0 + a2):.3g}; the tail reaches beyond "
                "the mesh (a kernel close to the Maxwell model?): lengthen the cut-off")
    return dist


def check_cooling_span(gas: InelasticGas, t_end: float, temperature0: float) -> None:
    """Refuse a free-cooling run whose temperature leaves :data:`TEMPERATURE_RANGE`.

    Haff's law of the Gaussian closure, :math:`dT/dt = -L(1) T^{1+\\gamma/2}` with
    :math:`L` the loss rate (:meth:`~kinetic_fem.model.InelasticGas.loss_rate`),
    gives :math:`T(t_{end})`; for a law or a saturating kernel the power law is an
    estimate.

    Parameters
    ----------
    gas : InelasticGas
        The gas.
    t_end : float
        The last output time.
    temperature0 : float
        The initial temperature.

    Raises
    ------
    ValueError
        With the estimated final temperature and the latest allowed time.
    """
    lo = TEMPERATURE_RANGE[0]
    if not t_end > 0 or gas.restitution.constant == 1.0:
        return
    rate = gas.loss_rate(temperature0) / temperature0  # 1/time at the start
    gamma = float(getattr(gas.kernel, "scale_degree", 1.0))
    if gamma > 0:  # T^(-gamma/2) grows linearly: T0^(-g/2) (1 + g/2 rate t)
        log_t = math.log(temperature0) - (2.0 / gamma) * math.log1p(0.5 * gamma * rate * t_end)
        t_max = (math.exp(-0.5 * gamma * math.log(lo / temperature0)) - 1.0) / (0.5 * gamma * rate)
    else:
        log_t = math.log(temperature0) - rate * t_end
        t_max = math.log(temperature0 / lo) / rate
    if log_t < math.log(lo):
        raise ValueError(f"times up to {t_end:.3g}: the gas cools to T ~ exp({log_t:.4g}) "
                         f"(Haff's law), below {lo:g}, where the moments underflow; the "
                         f"latest time allowed is about {t_max:.3g} (the homogeneous cooling "
                         "state, kinetic_fem.solve_cooling, is the late-time limit)")
