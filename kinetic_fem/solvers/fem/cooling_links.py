"""The continuation in the inelasticity of the near-elastic hard-rod cooling state.

Split from :mod:`kinetic_fem.solvers.fem.cooling` (which re-exports these names; its
module docstring describes the method): :func:`chain_state` walks from a converged state
at one inelasticity to the state asked for, through links on coarse meshes that follow
the humps (:func:`~kinetic_fem.solvers.fem.cooling_hump.continued_state`), and solves
the state asked for once more on the fine mesh; :func:`start_state` turns a warm start
(a state, or the distribution a former FEM cooling solve returned, at a neighbouring
restitution coefficient) into the first link's start.

Warm starts (issue 16, eighth round): a sweep over the inelasticity, each state from
its neighbour, takes one link and the final solve per state instead of the links from
:math:`\\varepsilon = 0.1` (``benchmarks/archive/results/fem_cooling_speed.md``).  Ninth round:
the cold path toward :math:`\\varepsilon \\ge 10^{-3}` starts from a stored state
(:mod:`~kinetic_fem.solvers.fem.cooling_seeds`), the links' trial residuals bring their
Jacobians, and the final P3 solve is measured where :math:`f > 10^{-30}` and stops on
the Newton step (2 Jacobians and 1 residual on the finest mesh instead of 3 and 2).
"""

from __future__ import annotations

import logging

import numpy as np
from numpy.typing import NDArray

from ...distribution import VelocityDistribution
from ...operators.adaptive import HUMP_DECADES
from ..continuation import StepRule, continuation, geometric_path, ratio_path
from .cooling_hump import (
    HUMP_COARSE_EPS,
    HUMP_COARSE_LINK,
    HUMP_FAST_LINK,
    HUMP_LINK_DECADES,
    HUMP_LINK_RATIO,
    HUMP_LINK_RESOLUTION,
    P3_FAR_EFOLDS,
    P3_MONITOR_LOG_F,
    HumpStepOptions,
    continued_state,
)
from .cooling_mesh import step_intorder
from .cooling_newton import MONITOR_LOG_F, CoolingState
from .cooling_steps import PREDICT_ITER
from .heated import ConvergenceError

__all__ = ["HUMP_EPS", "HUMP_FRONTIER", "HUMP_RATIO", "HUMP_STEP_TOL", "HUMP_STEP_ITER",
           "HUMP_MIN_RATIO", "hump_chain", "link_chain", "chain_state", "start_state",
           "DistributionStart"]

logger = logging.getLogger(__name__)

HUMP_EPS = 0.1
"""Below this inelasticity (hard rods) the state is reached by continuation in eps on
meshes that follow the humps (:func:`kinetic_fem.operators.adaptive.hump_vertices`)."""
HUMP_FRONTIER = 1e-6
"""Smallest inelasticity the continuation is measured to reach (with the Gauss degree
HUMP_INTORDER); below it a failure is reported as this limit."""
HUMP_RATIO = 2.0
"""Largest ratio of successive inelasticities of the continuation."""
HUMP_STEP_TOL = 1e-7
"""Newton tolerance of the intermediate states (they only start the next step)."""
HUMP_STEP_ITER = 40
"""Newton steps allowed before a continuation step is halved (on a log scale)."""
HUMP_MIN_RATIO = 1.1
"""Continuation steps are not halved below this ratio of inelasticities."""


def hump_chain(eps: float) -> list[float]:
    """Inelasticities of the continuation from :data:`HUMP_EPS` down to ``eps``: steps of
    at most :data:`HUMP_RATIO`, equal on a log scale, ending exactly at ``eps``.

    Parameters
    ----------
    eps : float
        Target inelasticity :math:`1 - \\alpha`, below :data:`HUMP_EPS`.

    Returns
    -------
    list of float
        The inelasticities of the continuation steps, the last one ``eps``.

    Examples
    --------
    >>> [round(e, 6) for e in hump_chain(1e-3)]
    [0.05, 0.025, 0.0125, 0.00625, 0.003125, 0.001563, 0.001]
    """
    return ratio_path(HUMP_EPS, eps, HUMP_RATIO)


def link_chain(eps: float, start: float, ratio: float) -> list[float]:
    """Inelasticities from ``start`` to ``eps`` (either direction) in equal steps on a log
    scale of ratio at most ``ratio``, ending exactly at ``eps`` (``start`` left out).

    Parameters
    ----------
    eps : float
        The last inelasticity.
    start : float
        The inelasticity of the start.
    ratio : float
        Largest ratio of successive inelasticities (> 1).

    Returns
    -------
    list of float

    Examples
    --------
    >>> [round(e, 6) for e in link_chain(0.04, 0.01, 2.0)]
    [0.02, 0.04]
    """
    return geometric_path(start, eps, ratio)


class DistributionStart(CoolingState):
    """A warm start from the distribution of a former FEM cooling solve.

    Only what a continuation step reads of a state: :meth:`log_f` (the cubic spline
    of :math:`\\ln f` through the quadrature points of the distribution, continued
    linearly beyond the last one) and ``zeta``; :meth:`rescaled_log_f` is inherited.

    Parameters
    ----------
    dist : VelocityDistribution
        ``kf.solve_cooling`` (FEM) result: unit temperature, ``info.extra["zeta"]``.
    """

    def __init__(self, dist: VelocityDistribution) -> None:
        try:
            zeta = float(dist.info.extra["zeta"])
        except KeyError:
            raise ValueError("initial must be a CoolingState or the distribution of a FEM "
                             "cooling solve (info.extra['zeta'] is missing)") from None
        super().__init__(None, np.empty(0), zeta, dist.info)  # type: ignore[arg-type]
        self.dist = dist
        self.edge = 0.999 * float(np.max(np.abs(dist.c)))

    def log_f(self, c: NDArray) -> NDArray:
        """:math:`\\ln f` at ``c`` (even; linear continuation beyond the last node)."""
        c_abs = np.abs(np.asarray(c, dtype=float))
        c_in = np.minimum(c_abs, self.edge)
        ends = np.log(self.dist.f(np.array([0.97, 1.0]) * self.edge))
        slope = min((ends[1] - ends[0]) / (0.03 * self.edge), 0.0)
        return np.log(np.maximum(self.dist.f(c_in), 1e-300)) + slope * (c_abs - c_in)


def start_state(initial: CoolingState | VelocityDistribution) -> tuple[CoolingState, float]:
    """A warm start and its inelasticity.

    Parameters
    ----------
    initial : CoolingState or VelocityDistribution
        A hard-rod cooling state (or the distribution ``kf.solve_cooling`` returned) at a
        neighbouring restitution coefficient.

    Returns
    -------
    state : CoolingState
    eps : float
        Its inelasticity :math:`1 - \\alpha`.

    Raises
    ------
    ValueError
        If ``initial`` is neither, or its restitution coefficient is unknown.
    """
    if isinstance(initial, CoolingState):
        return initial, 1.0 - initial.disc.alpha
    if isinstance(initial, VelocityDistribution):
        alpha = initial.params.get("alpha")
        if not isinstance(alpha, (int, float)):
            raise ValueError("initial: the distribution does not name its restitution "
                             f"coefficient (params['alpha'] = {alpha!r})")
        return DistributionStart(initial), 1.0 - float(alpha)
    raise ValueError(f"initial must be a CoolingState or a VelocityDistribution from "
                     f"kf.solve_cooling, got {type(initial).__name__}")


def chain_state(alpha: float, start: CoolingState, eps_start: float, final: HumpStepOptions,
                *, order: int) -> CoolingState:
    """The hard-rod HCS at ``alpha`` by continuation in eps from ``start``.

    Toward eps >= :data:`~kinetic_fem.solvers.fem.cooling_hump.HUMP_COARSE_EPS` from a
    start at or above it: links of ratio at most ``HUMP_LINK_RATIO`` on the fast link
    meshes; else steps of at most :data:`HUMP_RATIO` (module notes of
    :mod:`~kinetic_fem.solvers.fem.cooling`).  A failed step is retried through the
    geometric mean; the state asked for is the one ``final`` describes.

    Parameters
    ----------
    alpha : float
        Restitution coefficient asked for (hard rods, eps < :data:`HUMP_EPS`).
    start : CoolingState
        A converged state at ``eps_start``.
    eps_start : float
        Its inelasticity.
    final : HumpStepOptions
        The state asked for: its element size in the humps (``resolution``, hump
        widths), Lagrange degree, Newton tolerance and iteration limit; its Gauss degree
        (``intorder``, None: by step) is that of the links too.
    order : int
        Lagrange degree of the links.

    Returns
    -------
    CoolingState

    Raises
    ------
    ConvergenceError
        If a step fails at a ratio below :data:`HUMP_MIN_RATIO`.
    """
    resolution, final_order, intorder = final.resolution, final.order, final.intorder
    tol, max_iter = final.tol, final.max_iter
    eps = 1.0 - alpha
    fast = min(eps, eps_start) >= HUMP_COARSE_EPS * (1 - 1e-9)  # HUMP_FAST_LINK meshes
    if eps_start == HUMP_EPS and not fast:
        chain = hump_chain(eps)
    else:
        chain = link_chain(eps, eps_start, HUMP_LINK_RATIO if fast else HUMP_RATIO)
    # the target is reached on the coarser step mesh first, then refined at the same eps
    # (mesh sequencing: the many Newton steps of a continuation step are taken on the
    # coarse mesh, the fine one needs three or four): eps twice in the path
    if eps_start != eps and not (resolution >= _link(eps, resolution, fast)
                                 and final_order == order):
        chain = [*chain, eps]

    def solve(prev: CoolingState, eps_prev: float, step: float) -> CoolingState:
        link = _link(step, resolution, fast)
        final = step == eps and (eps_prev == eps or resolution >= link
                                 and final_order == order)
        res = resolution if final else link
        ratio = max(eps_prev / step, step / eps_prev)
        p3 = final and final_order == 3
        return continued_state(prev, eps_prev, step, resolution=res,
                               order=final_order if final else order,
                               intorder=intorder or step_intorder(step, order, final),
                               tol=tol if final else HUMP_STEP_TOL,
                               decades=HUMP_LINK_DECADES if fast and not final
                               else HUMP_DECADES,
                               far_efolds=P3_FAR_EFOLDS if p3 else 1.0,
                               monitor=P3_MONITOR_LOG_F if p3 else MONITOR_LOG_F,
                               predict_iter=PREDICT_ITER if p3 else 0,
                               max_iter=min(max_iter, HUMP_STEP_ITER)
                               if ratio > HUMP_MIN_RATIO else max_iter)

    walk = continuation(start, eps_start, chain, solve, rule=StepRule(min_ratio=HUMP_MIN_RATIO))
    if not walk.converged:
        assert walk.failed is not None and walk.failed_value is not None
        step, eps_prev, state = walk.failed_value, walk.value, walk.failed
        link = _link(step, resolution, fast)
        res = resolution if step == eps and (eps_prev == eps or resolution >= link
                                             and final_order == order) else link
        where = (f"FEM cooling Newton did not converge at eps = {step:.3g} on the way "
                 f"to alpha = {alpha} (hump mesh of "
                 f"{state.disc.vertices.size - 1} elements, {res:g} hump widths "
                 f"eps^(1/3) = {step ** (1 / 3):.3g}, step from eps = {eps_prev:.3g}; "
                 f"{state.info.message})")
        if step < HUMP_FRONTIER:
            raise ConvergenceError(
                f"{where}: below eps = {HUMP_FRONTIER:g} the continuation is not "
                "measured (there zeta/eps - 1 ~ 0.18 eps^(4/3) nears the round-off of "
                "the collision balance), a known limit of this solver; for the "
                "leading-order state use kf.scaling.solve_psi().humps(c, eps)")
        raise ConvergenceError(
            f"{where}: the mesh does not resolve the humps; pass a smaller "
            f"resolution (e.g. resolution={res / 2:g})")
    return walk.state


def _link(step: float, resolution: float, fast: bool) -> float:
    """Element size (hump widths) of a link state at ``step`` of a chain."""
    return max(resolution, HUMP_FAST_LINK if fast else HUMP_COARSE_LINK
               if step >= HUMP_COARSE_EPS else HUMP_LINK_RESOLUTION)
