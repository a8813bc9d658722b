"""Adaptive refinement of the FEM homogeneous cooling state by its two-level estimate.

:meth:`kinetic_fem.solvers.fem.cooling_newton.CoolingState.error_estimate` solves one
Newton step of the cooling equations on the mesh with every element bisected; the step
estimates the error of :math:`\\ln f_h` per element and of :math:`\\zeta`, including the
error that the cooling drift carries outward along the outer edge of the near-elastic
humps, which a local (recovery) indicator cannot see.  Measured at
:math:`\\varepsilon = 10^{-4}` (``benchmarks/results/fem_cooling.md``), the largest true
error of :math:`\\ln f` where :math:`f > 10^{-30}` over the largest estimate is 1.02,
1.00 and 0.86 at 0.1, 0.07 and 0.05 hump widths, and the estimate of :math:`\\zeta`
is within 12 % of its true error; the recovery indicator is 1300 to 4000 times too small.

:func:`adapted_state` refines the elements whose estimate exceeds the target, where
:math:`f_h > 10^{-30}` (the accuracy asked of a state; the deep tails feed nothing back),
into :math:`\\lceil(\\eta_K/\\mathrm{target})^{1/3}\\rceil` pieces
(:func:`kinetic_fem.operators.adaptive.refined_vertices`), and solves again from the
interpolated state.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from ...operators.adaptive import refined_vertices
from ...operators.fem_discretisation import FEMDiscretisation
from .cooling_newton import CoolingState, newton_cooling

__all__ = ["adapted_state", "WATCHED_LOG_F", "ADAPT_ROUNDS"]

logger = logging.getLogger(__name__)

WATCHED_LOG_F = math.log(1e-30)
"""The error of :math:`\\ln f` is controlled where :math:`f_h` exceeds this on an element."""
ADAPT_ROUNDS = 3
"""Largest number of refine-and-solve rounds."""


def adapted_state(state: CoolingState, target: float, *, tol: float = 1e-11,
                  max_iter: int = 60, rounds: int = ADAPT_ROUNDS) -> CoolingState:
    """Refine ``state`` until its two-level estimate of :math:`\\ln f` is below ``target``.

    Parameters
    ----------
    state : CoolingState
        A converged cooling state (symmetric mesh).
    target : float
        Largest estimated error of :math:`\\ln f_h` on an element where
        :math:`f_h > 10^{-30}`.
    tol, max_iter : float, int
        Newton tolerance and iteration limit of each re-solve.
    rounds : int
        Largest number of refinements.

    Returns
    -------
    CoolingState
        The last state; ``info.extra`` is not set here: the estimate reached is logged
        and returned by :meth:`~CoolingState.error_estimate` of the result.

    Raises
    ------
    ValueError
        For a target that is not positive.
    """
    if not (math.isfinite(target) and target > 0.0):
        raise ValueError(f"target must be a positive finite number, got {target!r}")
    for k in range(rounds + 1):
        eta, dzeta = state.error_estimate()
        verts = state.disc.vertices
        f_max = np.maximum(state.disc.evaluate(state.u, verts[:-1]),
                           state.disc.evaluate(state.u, verts[1:]))
        eta = np.where(np.log(f_max) > WATCHED_LOG_F, eta, 0.0)
        logger.info("HCS adaptivity round %d: %d elements, estimated ln f error %.2e, "
                    "zeta %.2e", k, eta.size, eta.max(), dzeta)
        if eta.max() <= target or k == rounds:
            return state
        right = verts[:-1] >= 0.0  # refine the right half and mirror it (exact symmetry)
        half = refined_vertices(verts[verts >= 0.0], eta[right], target)
        new = np.concatenate([-half[:0:-1], half])
        disc = FEMDiscretisation(state.disc.alpha, new, state.disc.order,
                                 state.disc.intorder, gamma=state.disc.gamma)
        refined = newton_cooling(disc, state.log_f(disc.dof_locations), state.zeta, tol=tol,
                                 max_iter=max_iter, pseudo_time=np.inf)
        if not refined.info.converged:
            logger.warning("HCS adaptivity: Newton failed on the refined mesh (%s); "
                           "keeping the previous state", refined.info.message)
            return state
        state = refined
    return state
