"""The hard-rod cooling state between the moderate and the near-elastic regime (issue 16).

For :math:`\\varepsilon = 1 - \\alpha` in [:data:`BAND_EPS`, 0.1) the two humps of the
state (width :math:`w = \\varepsilon^{1/3} \\ge 0.33`) are still broad.  The state is
reached in two Newton solves from the state at :math:`\\varepsilon = 0.1` (or a warm
start):

1. one link of the near-elastic continuation
   (:func:`~kinetic_fem.solvers.fem.cooling_hump.continued_state`): P2 on the mesh that
   follows the humps at :data:`~kinetic_fem.solvers.fem.cooling_hump.HUMP_FAST_LINK`
   hump widths, cut off where the rescaled start has fallen
   :data:`~kinetic_fem.solvers.fem.cooling_hump.HUMP_LINK_DECADES` decades, Newton
   tolerance :data:`~kinetic_fem.solvers.fem.cooling_links.HUMP_STEP_TOL`;
2. P3 with the Gauss degree :data:`BAND_INTORDER` on :func:`band_vertices`: uniform at
   :data:`BAND_RESOLUTION` hump widths out to :math:`c = 1 + 2w`, then growing along
   the tail of the link state (at most :data:`BAND_EFOLDS` e-folds per element) out to
   where it has fallen :data:`BAND_DECADES` decades; from the link state (mesh
   sequencing: two Jacobians).

Issue 16, ninth round (``benchmarks/archive/results/fem_cooling_band_speed.md``): the former band
path (P2 on the moderate mesh at three times the P2 spacing from the rescaled eps = 0.1
state, then P3 on the moderate mesh
:func:`~kinetic_fem.solvers.fem.cooling_mesh.hcs_vertices` at 1.5 times it, Gauss degree
7) needed 1123 ... 1285 dofs: that mesh ends at :math:`c = 13.5`, where :math:`f` has
fallen to 1e-66 ... 1e-98 (eps = 0.07 ... 0.04), and 36 ... 50 % of its elements lie
where f < 1e-30; uniform out to the humps' outer edge :math:`1 + 12 w`, it does not grow
its elements along the tail, whose :math:`\\ln f` is nearly cubic (P3 exact).
Here 595 ... 625 dofs, against P3 at 0.1 hump widths errors 3 to 4 times smaller in
:math:`\\zeta` and :math:`a_2`, 2 to 9 times in :math:`\\ln f` where f > 1e-30.

If either solve fails the caller falls back to the near-elastic continuation.
"""

from __future__ import annotations

import logging
from typing import Callable

import numpy as np
from numpy.typing import NDArray

from ...model import CoolingProblem
from ...operators.mesher import LogDropRule, log_drop_vertices
from ..continuation import NO_RETRY, continuation, geometric_path
from .cooling_hump import (
    FULL_STEP_ITER,
    HUMP_FAST_LINK,
    HUMP_LINK_DECADES,
    HUMP_LINK_RATIO,
    continued_state,
)
from .cooling_links import HUMP_STEP_ITER, HUMP_STEP_TOL
from .cooling_newton import CLOSE_DAMPING, CoolingState, newton_cooling
from .heated import FEMDiscretisation

__all__ = ["BAND_EPS", "BAND_RESOLUTION", "BAND_EDGE", "BAND_GROWTH", "BAND_EFOLDS",
           "BAND_INTORDER", "BAND_DECADES", "band_vertices", "band_rule", "in_band", "band_state"]

logger = logging.getLogger(__name__)

BAND_EPS = 0.035
"""Smallest inelasticity solved here by default (below it the near-elastic default, P3
at 0.2 hump widths; at eps = 0.035 this path is 1.2 times faster than that and 100
times more accurate in zeta, 3.4e-13 -> 3.1e-15 against P3 at 0.1 hump widths)."""
BAND_RESOLUTION = 0.12
"""Element size of the P3 state over the humps and between them (out to
:data:`BAND_EDGE` hump widths beyond :math:`c = 1`), in hump widths :math:`w`."""
BAND_EDGE, BAND_GROWTH = 2.0, 0.5
"""Beyond :math:`c = 1 +` ``BAND_EDGE`` :math:`w` the elements grow linearly, by
``BAND_GROWTH`` times their size per hump width (the P3 error of :math:`\\ln f` is
:math:`h^4` times its fourth derivative, and the outer edge :math:`\\ln f \\simeq
-|y|^3/3` is a cubic), as long as :math:`f` falls at most :data:`BAND_EFOLDS` e-folds
over one."""
BAND_EFOLDS = 1.75
"""Largest fall of the start over one element of the tail, in e-folds.  With the Gauss
degree :data:`BAND_INTORDER`, ln f where f > 1e-30 is 4.5e-7 ... 7e-7 off at eps = 0.04
... 0.099 (2 e-folds: 1.5e-6 ... 2.5e-6; 1.5: 3.2e-7 ... 3.6e-7 on 7 % more dofs)."""
BAND_INTORDER = 9
"""Gauss degree of the P3 state (5 points per element): with 4 (degree 7) the e^u of the
tail's long elements is integrated with an error that puts ln f 3e-4 off."""
BAND_DECADES = 40.0
"""The P3 mesh ends where the link state has fallen this many decades (not 45: fewer
dofs, the errors where f > 1e-30 unchanged; elements of twice the e-folds beyond
f = 1e-30, as the near-elastic default has, put ln f 2e-5 off)."""


def band_vertices(eps: float, log_f: Callable[[NDArray], NDArray], *,
                  resolution: float = BAND_RESOLUTION, edge: float = BAND_EDGE,
                  growth: float = BAND_GROWTH, efolds: float = BAND_EFOLDS,
                  decades: float = BAND_DECADES) -> NDArray[np.float64]:
    """Symmetric vertices of the P3 band state, graded along the tail of a start.

    Element size :math:`h_0 =` ``resolution`` :math:`w` (:math:`w =
    \\varepsilon^{1/3}`) for :math:`|c| \\le c_1 = 1 +` ``edge`` :math:`w`; beyond,
    :math:`h = \\max\\big(h_0, \\min(h_0 (1 + g (c - c_1)/w),
    e/|(\\ln f)'|)\\big)`; the mesh ends at the first vertex where the start has
    fallen ``decades`` decades below its value at 0 (at most :math:`c = 40`).

    Parameters
    ----------
    eps : float
        Inelasticity :math:`1 - \\alpha`, in (0, 1).
    log_f : callable
        :math:`\\ln f` of the start (even) at an array of velocities.
    resolution : float
        :math:`h_0` in hump widths.
    edge : float
        :math:`(c_1 - 1)/w`.
    growth : float
        :math:`g`, relative growth of the element size per hump width.
    efolds : float
        :math:`e`, largest fall of the start over a tail element, in e-folds.
    decades : float
        Fall of the start at the cut-off, in decades.

    Returns
    -------
    ndarray
        Increasing vertices, symmetric about 0, with a vertex at 0.

    Examples
    --------
    >>> v = band_vertices(0.05, lambda c: -0.5 * c**2)
    >>> bool(v[0] == -v[-1] and 0.0 in v and np.all(np.diff(v) > 0))
    True
    >>> bool(13.5 < v[-1] < 13.7)  # c^2/2 = 40 ln 10 at c = 13.57
    True
    """
    if not 0.0 < eps < 1.0:
        raise ValueError(f"eps must be in (0, 1), got {eps!r}")
    return log_drop_vertices(log_f, band_rule(eps, resolution=resolution, edge=edge,
                                              growth=growth, efolds=efolds, decades=decades))


def band_rule(eps: float, *, resolution: float = BAND_RESOLUTION, edge: float = BAND_EDGE,
              growth: float = BAND_GROWTH, efolds: float = BAND_EFOLDS,
              decades: float = BAND_DECADES) -> LogDropRule:
    """The placement rule of :func:`band_vertices` at ``eps``: elements of ``resolution``
    hump widths out to :math:`c = 1 +` ``edge`` :math:`w`, then at most ``efolds`` e-folds
    each, growing by at most ``growth`` times their size per hump width.

    Parameters
    ----------
    eps : float
        Inelasticity :math:`1 - \\alpha`, in (0, 1); the hump width :math:`w =
        \\varepsilon^{1/3}`.
    resolution, edge, growth, efolds, decades : float
        As for :func:`band_vertices`.

    Returns
    -------
    LogDropRule

    Examples
    --------
    >>> round(band_rule(0.064).bulk, 12)  # 1 + 2 w, w = 0.4
    1.8
    """
    w = eps ** (1.0 / 3.0)
    return LogDropRule(efolds=efolds, smallest=resolution * w, bulk=1.0 + edge * w,
                       growth=growth, scale=w, decades=decades)

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
        A converged state at ``eps_start`` (rescaled on the hump variable as the start of
        one link; from farther than a ratio
        :data:`~kinetic_fem.solvers.fem.cooling_hump.HUMP_LINK_RATIO` in eps, through
        equal steps on a log scale, :func:`~kinetic_fem.solvers.fem.cooling_links.link_chain`).
    eps_start : float
        Its inelasticity.
    tol : float
        Newton tolerance of the final state.
    max_iter : int
        Newton iteration limit of the final state (the link's is at most
        :data:`~kinetic_fem.solvers.fem.cooling_links.HUMP_STEP_ITER`).
    intorder : int, optional
        Gauss degree of the P3 state; default :data:`BAND_INTORDER`.

    Returns
    -------
    CoolingState or None
        The converged P3 state, or None if a solve did not converge (the caller then
        takes the near-elastic continuation).
    """
    eps = problem.gas.epsilon
    # one link from the eps = 0.1 state; from a far warm start (e.g. eps = 1e-3) a link
    # chain of ratio <= HUMP_LINK_RATIO on the same meshes
    def solve(prev: CoolingState, eps_prev: float, step: float) -> CoolingState:
        return continued_state(prev, eps_prev, step, resolution=HUMP_FAST_LINK, order=2,
                               intorder=5, tol=HUMP_STEP_TOL, decades=HUMP_LINK_DECADES,
                               max_iter=min(max_iter, HUMP_STEP_ITER))

    walk = continuation(start, eps_start, geometric_path(eps_start, eps, HUMP_LINK_RATIO),
                        solve, rule=NO_RETRY)
    if not walk.converged:
        assert walk.failed is not None
        logger.info("HCS band eps = %.3g: the link from %.3g to %.3g failed (%s)", eps,
                    eps_start, walk.failed_value, walk.failed.info.message)
        return None
    link = walk.state
    disc = FEMDiscretisation(problem.gas.alpha, band_vertices(eps, link.log_f), 3,
                             intorder or BAND_INTORDER, gamma=problem.gas.gamma)
    u0 = link.log_f(disc.dof_locations)
    # full Newton steps first (a finer mesh at the same eps, as the near-elastic
    # default's last solve), then backtracking if they do not converge
    for line_search, iters in ((False, min(max_iter, FULL_STEP_ITER)), (True, max_iter)):
        state = newton_cooling(disc, u0, link.zeta, tol=tol, max_iter=iters,
                               pseudo_time=np.inf, min_damping=CLOSE_DAMPING,
                               line_search=line_search)
        if state.info.converged:
            break
    logger.info("HCS band eps = %.3g: %d + %d Newton steps on %d + %d dofs, converged %s",
                eps, link.info.iterations, state.info.iterations, link.u.size,
                state.u.size, state.info.converged)
    return state if state.info.converged else None
