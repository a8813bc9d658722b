"""Continuation in the restitution coefficient for the cooling state of hard kernels.

For kernels :math:`|g|^\\gamma` with :math:`\\gamma >` :data:`HARD_GAMMA` the cooling
state turns bimodal at moderate inelasticity (:math:`\\gamma = 2`: :math:`\\ln f` at
:math:`c = 0` is -1.19 against -1.21 at :math:`c = 1` at alpha = 0.7, -1.55 against -1.01
at 0.8), and its tail :math:`\\ln f \\simeq -c^\\gamma/(\\gamma\\zeta)` is far steeper
than the Gaussian start's.  The pseudo-transient iteration from the Gaussian start of
:func:`kinetic_fem.solvers.fem.cooling.cooling_state` then diverges for every alpha >= 0.6
(measured at :math:`\\gamma = 2` on bulk spacings 0.05 to 0.2, cut-offs 6 to 13.5, and
with a start whose tail follows :math:`-c^2/(2\\zeta)`), while Newton's method with
backtracking from the state at a nearby alpha converges in 8 to 10 steps per step
of 0.1 in alpha.  :func:`alpha_chain` walks from :data:`~.cooling_order.STRONG_ALPHA` (where
the Gaussian start converges) to the target in equal steps of the inelasticity on a log
scale, each of ratio at most :data:`ALPHA_CHAIN_RATIO`, on the target's mesh; a failed
step is retried through the geometric mean.  Below :data:`~.cooling_quasi.QUASI_EPS`
the chain stops there and :func:`~.cooling_quasi.quasi_elastic_chain` continues on
meshes that follow the humps; that state is on its own mesh, and it is remembered in
the ``memo`` of the call (:class:`~.regimes.Run`) for the globalised retry of the
same call of :func:`~.cooling.cooling_state`, whose Newton step on the default fine
mesh turns singular there (its far tail underflows).  For gamma = 2 on the default mesh the chain
only runs if the one Newton solve from the stored anchors of :mod:`.cooling_gamma2`
fails (and to generate those anchors: :mod:`.cooling_generate`).
"""

from __future__ import annotations

import logging
import math

import numpy as np
from numpy.typing import NDArray

from ...model import CoolingProblem
from ..continuation import StepRule, continuation, geometric_path
from .cooling_mesh import hcs_bulk, hcs_cutoff, hcs_spacing, hcs_vertices
from .cooling_newton import CoolingState, newton_cooling
from .cooling_order import STRONG_ALPHA, order_spacing
from .cooling_quasi import QUASI_EPS, check_frontier, quasi_elastic_chain
from .heated import FEMDiscretisation

__all__ = ["HARD_GAMMA", "ALPHA_CHAIN_RATIO", "ALPHA_CHAIN_COARSE", "ALPHA_CHAIN_TOL",
           "QUASI_TOL", "DIRECT_EPS", "uses_alpha_chain", "alpha_chain",
           "quasi_seed_vertices"]

logger = logging.getLogger(__name__)

HARD_GAMMA = 1.0
"""Kernels harder than this (and alpha above
:data:`~.cooling_order.STRONG_ALPHA`) use :func:`alpha_chain`."""
ALPHA_CHAIN_RATIO = 1.6
"""Largest ratio of successive inelasticities of the chain (0.5 -> 0.4 -> ... -> 0.1:
ratios 1.25 to 1.5 converged at gamma = 2; 2 failed on the coarse mesh)."""
ALPHA_CHAIN_TOL = 1e-7
"""Newton tolerance of the intermediate states (they only start the next step)."""
ALPHA_CHAIN_COARSE = 2.0
"""Mesh sequencing factor of the chain's coarse mesh (instead of
:data:`~.cooling_order.COARSE_FACTOR`): at gamma = 2, alpha = 0.95 the chain stalled
(residual 8e-6) on 4 times the bulk spacing (0.147) and converged on 2 times (0.07, 1.5 s)."""
MIN_RATIO = 1.02
"""Steps are not halved below this ratio of inelasticities."""
DIRECT_EPS = 3e-3
"""Below this inelasticity :func:`~.cooling.cooling_state` (default mesh) goes
straight to the near-elastic chain on its own meshes: the Newton step on the default
fine mesh turned singular at alpha 0.998, 0.999 and 0.9995 (converged at 0.995, to 4.6e-11
in zeta against 1e-8 for the chain's state), and the detour through the target's meshes
cost 1.2-1.3x (alpha 0.998 4.59 -> 3.48 CPU s, 0.999 5.58 -> 4.32 s, 0.9995 10.95 ->
9.03 s; the same states to 1e-15)."""
QUASI_TOL = 1e-11
"""Newton tolerance (at most) of the near-elastic chain."""


def uses_alpha_chain(problem: CoolingProblem) -> bool:
    """A kernel harder than :data:`HARD_GAMMA` at alpha above
    :data:`~.cooling_order.STRONG_ALPHA`.

    Parameters
    ----------
    problem : CoolingProblem
        The cooling problem.

    Returns
    -------
    bool
    """
    return problem.gas.gamma > HARD_GAMMA and problem.gas.alpha > STRONG_ALPHA


def quasi_seed_vertices(gamma: float, order: int) -> NDArray[np.float64]:
    """The mesh of the state at :data:`~.cooling_quasi.QUASI_EPS` that seeds
    :func:`~.cooling_quasi.quasi_elastic_chain`: that alpha's default mesh at
    :data:`ALPHA_CHAIN_COARSE` times its spacing.

    Parameters
    ----------
    gamma : float
        Kernel exponent.
    order : int
        Lagrange degree.

    Returns
    -------
    ndarray
        Symmetric vertices (thermal velocities).
    """
    problem = CoolingProblem.from_parameters(1.0 - QUASI_EPS, kernel=gamma)
    return hcs_vertices(hcs_cutoff(problem), ALPHA_CHAIN_COARSE * order_spacing(
        hcs_spacing(problem), order), gamma=gamma, bulk=hcs_bulk(QUASI_EPS))


def alpha_chain(disc: FEMDiscretisation, start: CoolingState, alpha_start: float, *,
                tol: float, max_iter: int,
                memo: dict[tuple, CoolingState] | None = None) -> CoolingState:
    """Continuation in :math:`\\varepsilon = 1 - \\alpha` from ``start`` to ``disc.alpha``.

    Parameters
    ----------
    disc : FEMDiscretisation
        The discretisation at the target alpha (the chain runs on its mesh).
    start : CoolingState
        The state at ``alpha_start`` on the same mesh.
    alpha_start : float
        Restitution coefficient of ``start``, below ``disc.alpha``.
    tol : float
        Newton tolerance of the state at the target.
    max_iter : int
        Newton steps allowed per step of the chain.
    memo : dict, optional
        The near-elastic states of one call of the solver (below
        :data:`~.cooling_quasi.QUASI_EPS`), keyed on alpha, kernel, degrees, tolerance
        and iteration limit, not on ``start``: a second chain of the same call toward the
        same state (the globalised retry after mesh sequencing) reuses the first's.  None:
        nothing is remembered.

    Returns
    -------
    CoolingState
        The state at the target (below :data:`~.cooling_quasi.QUASI_EPS` on the mesh
        of :func:`~.cooling_quasi.quasi_elastic_chain`, not ``disc``'s);
        ``info.converged`` False if a step failed at the smallest ratio :data:`MIN_RATIO`
        (that step's state).

    Raises
    ------
    UnsupportedModelError
        Below :data:`~.cooling_quasi.QUASI_FRONTIER`.
    """
    eps, eps_prev = 1.0 - disc.alpha, 1.0 - alpha_start
    if eps < QUASI_EPS and eps_prev > QUASI_EPS:
        check_frontier(disc.alpha, disc.kernel.gamma)
        # one key for the coarse solve and the globalised retry of a call (tol 1e-11 for
        # both: the links' Newton ends quadratically, a looser tol saved nothing)
        quasi_tol = min(tol, QUASI_TOL)
        key = (disc.alpha, disc.gamma, disc.order, disc.intorder, quasi_tol, max_iter)
        if memo is not None and key in memo:
            return memo[key]
        # the state at QUASI_EPS only seeds the links: on its own coarse mesh (alpha 0.999:
        # 3.6 CPU s on the target's coarse mesh, 1.5 s on this one)
        mid_verts = quasi_seed_vertices(disc.kernel.gamma, disc.order)
        mid = FEMDiscretisation(1.0 - QUASI_EPS, mid_verts, disc.order, disc.intorder,
                                gamma=disc.gamma)
        start = CoolingState(FEMDiscretisation(alpha_start, mid_verts, disc.order,
                                               disc.intorder, gamma=disc.gamma),
                             start.log_f(mid.dof_locations), start.zeta, start.info)
        state = alpha_chain(mid, start, alpha_start, tol=ALPHA_CHAIN_TOL, max_iter=max_iter,
                            memo=memo)
        if not state.info.converged:
            return state
        state = quasi_elastic_chain(state, QUASI_EPS, disc.alpha, tol=quasi_tol,
                                    max_iter=max_iter)
        if state.info.converged and memo is not None:
            memo[key] = state
        return state

    def solve(prev: CoolingState, eps_prev: float, step: float) -> CoolingState:
        final = step == eps
        step_disc = disc if final else FEMDiscretisation(
            1.0 - step, disc.vertices, disc.order, disc.intorder, gamma=disc.gamma)
        zeta0 = prev.zeta * (1.0 - (1.0 - step) ** 2) / (1.0 - (1.0 - eps_prev) ** 2)
        return newton_cooling(step_disc, prev.u, zeta0, tol=tol if final else ALPHA_CHAIN_TOL,
                              max_iter=max_iter, pseudo_time=math.inf)

    return continuation(start, eps_prev, geometric_path(eps_prev, eps, ALPHA_CHAIN_RATIO),
                        solve, rule=StepRule(min_ratio=MIN_RATIO)).last
