"""The hard-rod cooling state between the moderate and the near-elastic regime (issue 16).

For :math:`\\varepsilon = 1 - \\alpha` in [:data:`BAND_EPS`, 0.1) the two humps of the
state (width :math:`\\varepsilon^{1/3} \\ge 0.34`) are still broad, and the default
mesh of moderate inelasticity (:func:`~kinetic_fem.solvers.fem_cooling_mesh.hcs_vertices`:
uniform bulk out to the humps' outer edge, graded tail) resolves them with P3 elements
at :data:`BAND_SPACING` times the P2 bulk spacing.  The near-elastic path (continuation
from :math:`\\varepsilon = 0.1` on meshes that follow the humps, Gauss degree 9) solved
this band 5 to 20 times slower: its first continuation step, from 0.1 to 0.05, took 8
Jacobians on 1600 dofs.

The state is reached in two Newton solves (backtracking, from close starts):

1. on a P2 mesh of the same cut-off and :data:`BAND_COARSE` times the P2 spacing, from
   the state at :math:`\\varepsilon = 0.1` rescaled on the hump variable
   (:meth:`~kinetic_fem.solvers.fem_cooling_newton.CoolingState.rescaled_log_f`);
   the globalised iteration from the Gaussian start of moderate inelasticity does not
   converge below :math:`\\varepsilon \\approx 0.04`;
2. on the P3 mesh, from that state (mesh sequencing).

Errors against the hump mesh at 0.035 hump widths and Gauss degree 9
(``benchmarks/results/fem_cooling_speed.md``) are below those of the near-elastic
default it replaces in the band; if either solve fails the caller falls back to the
continuation.
"""

from __future__ import annotations

import logging

import numpy as np

from ..model import CoolingProblem
from .fem import FEMDiscretisation
from .fem_cooling_hump import FULL_STEP_ITER
from .fem_cooling_mesh import hcs_bulk, hcs_cutoff, hcs_spacing, hcs_vertices
from .fem_cooling_newton import CLOSE_DAMPING, CoolingState, newton_cooling

__all__ = ["BAND_EPS", "BAND_SPACING", "BAND_COARSE", "BAND_COARSE_TOL", "in_band",
           "band_state"]

logger = logging.getLogger(__name__)

BAND_EPS = 0.04
"""Smallest inelasticity solved on the moderate-inelasticity mesh by default (below it
the P3 mesh's outer edge of the humps is too coarse: at 0.02 its ln f error, 5.8e-5 where
f > 1e-30, is three times the hump mesh's)."""
BAND_SPACING = 1.5
"""Bulk spacing of the P3 mesh, in units of the P2 default spacing
:func:`~kinetic_fem.solvers.fem_cooling_mesh.hcs_spacing` (at 2, ln f where
f > 1e-30 is no better than the hump mesh's, and the Newton iteration is less robust)."""
BAND_COARSE = 3.0
"""Bulk spacing of the P2 mesh of the first solve, in units of the P2 default spacing."""
BAND_COARSE_TOL = 1e-7
"""Newton tolerance of the first solve (it only starts the second)."""


def in_band(eps: float, hump_eps: float) -> bool:
    """Whether the default state at ``eps`` is solved here.

    Parameters
    ----------
    eps : float
        Inelasticity :math:`1 - \\alpha`.
    hump_eps : float
        Upper end of the band (the near-elastic threshold of the caller).

    Returns
    -------
    bool

    Examples
    --------
    >>> in_band(0.05, 0.1), in_band(0.01, 0.1)
    (True, False)
    """
    return BAND_EPS <= eps < hump_eps


def _disc(problem: CoolingProblem, spacing: float, order: int,
          intorder: int | None) -> FEMDiscretisation:
    eps = problem.gas.epsilon
    verts = hcs_vertices(hcs_cutoff(problem), spacing, gamma=problem.gas.gamma,
                         bulk=hcs_bulk(eps))
    return FEMDiscretisation(problem.gas.alpha, verts, order, intorder or 2 * order + 1,
                             gamma=problem.gas.gamma)


def band_state(problem: CoolingProblem, start: CoolingState, eps_start: float, *,
               tol: float = 1e-11, max_iter: int = 100,
               intorder: int | None = None) -> CoolingState | None:
    """The hard-rod HCS in the band, from a state at a larger inelasticity.

    Parameters
    ----------
    problem : CoolingProblem
        Hard rods with :func:`in_band` inelasticity.
    start : CoolingState
        A converged state at ``eps_start`` (rescaled on the hump variable as the start).
    eps_start : float
        Its inelasticity.
    tol : float
        Newton tolerance of the final state.
    max_iter : int
        Newton iteration limit of each solve.
    intorder : int, optional
        Gauss degree of the P3 mesh; default 7.

    Returns
    -------
    CoolingState or None
        The converged P3 state, or None if a solve did not converge (the caller then
        takes the near-elastic continuation).
    """
    eps = problem.gas.epsilon
    p2 = hcs_spacing(problem)
    coarse_disc = _disc(problem, BAND_COARSE * p2, 2, None)
    u0 = start.rescaled_log_f(eps_start, eps, coarse_disc.dof_locations)
    zeta0 = start.zeta * (1.0 - problem.gas.alpha**2) / (1.0 - (1.0 - eps_start) ** 2)
    coarse = newton_cooling(coarse_disc, u0, zeta0, tol=BAND_COARSE_TOL, max_iter=max_iter,
                            pseudo_time=np.inf)
    if not coarse.info.converged:
        logger.info("HCS band eps = %.3g: the coarse solve failed (%s)", eps,
                    coarse.info.message)
        return None
    disc = _disc(problem, BAND_SPACING * p2, 3, intorder)
    u0 = coarse.log_f(disc.dof_locations)
    # full Newton steps first (as the same-eps refinement of the hump path), then
    # backtracking if they do not converge
    for line_search, iters in ((False, min(max_iter, FULL_STEP_ITER)), (True, max_iter)):
        state = newton_cooling(disc, u0, coarse.zeta, tol=tol, max_iter=iters,
                               pseudo_time=np.inf, min_damping=CLOSE_DAMPING,
                               line_search=line_search)
        if state.info.converged:
            break
    logger.info("HCS band eps = %.3g: %d + %d Newton steps on %d + %d dofs, converged %s",
                eps, coarse.info.iterations, state.info.iterations, coarse.u.size,
                state.u.size, state.info.converged)
    return state if state.info.converged else None
