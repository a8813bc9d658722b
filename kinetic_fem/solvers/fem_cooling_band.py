"""The hard-rod cooling state between the moderate and the near-elastic regime (issue 16).

For :math:`\\varepsilon = 1 - \\alpha` in [:data:`BAND_EPS`, 0.1) the two humps of the
state (width :math:`w = \\varepsilon^{1/3} \\ge 0.34`) are still broad.  The state is
reached in two Newton solves from the state at :math:`\\varepsilon = 0.1` (or a warm
start), both on meshes that follow the humps
(:func:`~kinetic_fem.solvers.fem_cooling_hump.continued_state`,
:func:`kinetic_fem.operators.adaptive.hump_vertices`):

1. one link of the near-elastic continuation: P2 at
   :data:`~kinetic_fem.solvers.fem_cooling_hump.HUMP_FAST_LINK` hump widths, cut off
   where the rescaled start has fallen
   :data:`~kinetic_fem.solvers.fem_cooling_hump.HUMP_LINK_DECADES` decades, Newton
   tolerance :data:`~kinetic_fem.solvers.fem_cooling_links.HUMP_STEP_TOL`;
2. P3 at :data:`BAND_RESOLUTION` hump widths with the Gauss degree
   :data:`BAND_INTORDER`, cut off at :data:`BAND_DECADES` decades, from the link state
   (mesh sequencing: two Jacobians).

Issue 16, ninth round (``benchmarks/results/fem_cooling_band_speed.md``): the former band
path (P2 on the moderate mesh at three times the P2 spacing, then P3 on the moderate mesh
:func:`~kinetic_fem.solvers.fem_cooling_mesh.hcs_vertices` at 1.5 times it, Gauss degree
7) needed 1123 ... 1285 dofs, because the moderate mesh is uniform out to the humps'
outer edge :math:`1 + 12 w` and graded beyond it to :math:`c = 13.5`, where
:math:`\\ln f` is far below 1e-45; the hump mesh refines only the humps, grows its
elements along the exponential inner tail and ends where the state has fallen
:data:`BAND_DECADES` decades (c = 7.3 at eps = 0.05): 805 dofs there, at equal errors
in :math:`\\zeta` and :math:`a_2` and smaller ones in :math:`\\ln f` (against P3 at 0.05
hump widths), 2.0 to 2.4 times faster.

If either solve fails the caller falls back to the near-elastic continuation.
"""

from __future__ import annotations

import logging

from ..model import CoolingProblem
from .fem_cooling_hump import (
    HUMP_FAST_LINK,
    HUMP_LINK_DECADES,
    P3_FAR_EFOLDS,
    continued_state,
)
from .fem_cooling_links import HUMP_STEP_ITER, HUMP_STEP_TOL
from .fem_cooling_newton import CoolingState

__all__ = ["BAND_EPS", "BAND_RESOLUTION", "BAND_INTORDER", "BAND_DECADES", "in_band",
           "band_state"]

logger = logging.getLogger(__name__)

BAND_EPS = 0.04
"""Smallest inelasticity solved here by default (below it the near-elastic default, P3
at 0.2 hump widths with the Gauss degree 9 of the humps' steep outer edge)."""
BAND_RESOLUTION = 0.15
"""Element size of the P3 state in the humps, in hump widths (at 0.2 the errors in
:math:`\\zeta` and :math:`a_2` are 10 to 30 times those of the former band default,
3.6e-13 and 2.1e-12 at eps = 0.05; at 0.15 equal to them, 1.9e-14 and 6.4e-14)."""
BAND_INTORDER = 7
"""Gauss degree of the P3 state (4 points per element; degree 9 costs 1.4 times more
and is no more accurate in :math:`\\zeta` at eps >= 0.04: the outer edge's quadrature
error is amplified by :math:`\\varepsilon^{-2/3} \\le 8.5` here, 460 at 1e-4)."""
BAND_DECADES = 40.0
"""The P3 mesh ends where the link state has fallen this many decades (not 45: 6 % fewer
dofs, the errors where f > 1e-30 unchanged)."""


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


def band_state(problem: CoolingProblem, start: CoolingState, eps_start: float, *,
               tol: float = 1e-11, max_iter: int = 100,
               intorder: int | None = None) -> CoolingState | None:
    """The hard-rod HCS in the band, from a state at a neighbouring inelasticity.

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
        Newton iteration limit of the final state (the link's is at most
        :data:`~kinetic_fem.solvers.fem_cooling_links.HUMP_STEP_ITER`).
    intorder : int, optional
        Gauss degree of the P3 state; default :data:`BAND_INTORDER`.

    Returns
    -------
    CoolingState or None
        The converged P3 state, or None if a solve did not converge (the caller then
        takes the near-elastic continuation).
    """
    eps = problem.gas.epsilon
    link = continued_state(start, eps_start, eps, resolution=HUMP_FAST_LINK, order=2,
                           intorder=5, tol=HUMP_STEP_TOL, decades=HUMP_LINK_DECADES,
                           max_iter=min(max_iter, HUMP_STEP_ITER))
    if not link.info.converged:
        logger.info("HCS band eps = %.3g: the link from %.3g failed (%s)", eps, eps_start,
                    link.info.message)
        return None
    state = continued_state(link, eps, eps, resolution=BAND_RESOLUTION, order=3,
                            intorder=intorder or BAND_INTORDER, tol=tol, max_iter=max_iter,
                            decades=BAND_DECADES, far_efolds=P3_FAR_EFOLDS)
    logger.info("HCS band eps = %.3g: %d + %d Newton steps on %d + %d dofs, converged %s",
                eps, link.info.iterations, state.info.iterations, link.u.size,
                state.u.size, state.info.converged)
    return state if state.info.converged else None
