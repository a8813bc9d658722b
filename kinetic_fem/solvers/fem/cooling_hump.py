"""One continuation step of the near-elastic hard-rod HCS and the hump-mesh options.

Split from :mod:`kinetic_fem.solvers.fem.cooling` (which re-exports these names; its
module docstring describes the continuation): :func:`continued_state` solves the state
at one inelasticity on a mesh that follows the humps
(:func:`kinetic_fem.operators.adaptive.hump_vertices`) from a state at another, rescaled
on the hump variable; the constants set the element sizes, degrees and ratios of the
default path (``benchmarks/results/fem_cooling.md``, ``fem_cooling_speed.md``).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ...operators.adaptive import EDGE_EFOLDS, HUMP_DECADES, hump_vertices
from ...options import option_group
from .cooling_mesh import HUMP_INTORDER
from .cooling_newton import CLOSE_DAMPING, MONITOR_LOG_F, CoolingState, newton_cooling
from .heated import FEMDiscretisation

__all__ = ["continued_state", "HumpStepOptions", "HUMP_RESOLUTION", "HUMP_STEP_RESOLUTION",
           "HUMP_LINK_RESOLUTION", "HUMP_COARSE_LINK", "HUMP_COARSE_EPS", "HUMP_LINK_RATIO",
           "HUMP_P3_EPS", "HUMP_P3_RESOLUTION", "HUMP_FAST_LINK",
           "HUMP_LINK_DECADES", "FULL_STEP_ITER", "FAR_DECADES", "P3_FAR_EFOLDS",
           "P3_MONITOR_LOG_F"]

logger = logging.getLogger(__name__)

HUMP_RESOLUTION = 0.07
"""Default P2 element size in the humps below HUMP_P3_EPS, in hump widths eps^(1/3)
(``benchmarks/convergence_fem_cooling.py``: with the Gauss degree HUMP_INTORDER, zeta to
3e-13, a2 to 3e-11, ln f where f > 1e-30 to 1.3e-5 at eps = 1e-4)."""
HUMP_STEP_RESOLUTION, HUMP_LINK_RESOLUTION = 0.07, 0.14
"""Element sizes (hump widths): the step mesh and the intermediate states' below
HUMP_COARSE_EPS (2-4 times faster; at eps = 1e-6 ln f moves by 7e-6, zeta by 1e-12:
benchmarks/results/fem_cooling.md)."""
HUMP_COARSE_LINK, HUMP_COARSE_EPS, HUMP_LINK_RATIO = 0.2, 1e-3, 16.0
"""Element size (hump widths) of the intermediate states at eps >= HUMP_COARSE_EPS (1.3 to
1.5 times faster than 0.14; the state asked for is reached on this mesh first and then
solved on the finer one at the same eps), and their largest eps ratio toward a state asked
for there (8: 1.2-1.3 times faster than 2; 16 on the HUMP_FAST_LINK meshes:
benchmarks/archive/results/fem_cooling_speed.md)."""
FULL_STEP_ITER = 8
"""Newton from the same eps on a coarser mesh takes full steps (no backtracking: every
step was accepted at damping 1, and the trial residual came without the Jacobian, one
residual call more per step: 10-15 % of a call at eps = 1e-3 ... 0.03, same states to the
last digit); if it has not converged in this many steps, it is redone with backtracking."""
FAR_DECADES, P3_FAR_EFOLDS = 30.0, 2.0
"""The default P3 state's elements beyond f = 1e-30 (of its start) fall 2 e-folds, not 1:
the accuracy is asked where f > 1e-30, and the 45-decade cut-off (HUMP_DECADES) put a
quarter of the mesh beyond it (36 of 154 vertices per side at eps = 1e-3).  925 -> 823
dofs at eps = 1e-3, 811 -> 709 at 1e-2; against P3 at 0.1 hump widths unchanged errors
(zeta 1.7e-14 / 4.1e-14, a2 4.7e-13 / 6.6e-13, ln f 3.0e-7 / 4.6e-7) and no growing
mode of the linearised operator (largest rate 0 zeta, the scale mode:
benchmarks/archive/results/fem_cooling_speed.md)."""
HUMP_FAST_LINK, HUMP_LINK_DECADES = 0.3, 30.0
"""Links toward a state asked for at eps >= HUMP_COARSE_EPS (issue 16): element size in
hump widths, and the decades the start falls to the cut-off (not HUMP_DECADES).  Eighth
round: 20 decades (the y-rescaled start from eps = 0.1 or 0.01 overestimated the outer
edge by up to 36 e-folds, so the 45-decade cut-off put half of a link mesh where the state
is below 1e-60).  Ninth round: 30, for the links from the stored starts
(:mod:`~kinetic_fem.solvers.fem.cooling_seeds`) and warm starts, whose edge is close: at
20 decades the link state ended at f ~ 1e-20 and the state asked for, started beyond by
the link's ln f continued linearly, took a Jacobian more on the finest mesh (eps = 1e-3 ...
0.01: 3 -> 2 Jacobians; at 35 and 40 decades no faster)."""
P3_MONITOR_LOG_F = math.log(1e-30)
"""The default P3 state's Newton steps and residuals are measured where f > 1e-30 (not
1e-40, :data:`~kinetic_fem.solvers.fem.cooling_newton.MONITOR_LOG_F`), where its
accuracy is asked: beyond, the start is the link's ln f continued linearly past the
link's cut-off, 1.5 e-folds off at f ~ 1e-38 (eps = 1e-3), and the step there took a
Jacobian more on the finest mesh after the rest had converged (issue 16, ninth round:
3 -> 2 Jacobians at eps = 1e-3 ... 5e-3; the states move by <= 3e-15 in zeta, 1.2e-14 in
a2, 1.2e-10 in ln f where f > 1e-30)."""
HUMP_P3_EPS, HUMP_P3_RESOLUTION = 1e-4, 0.2
"""Default state at eps >= HUMP_P3_EPS: P3 at this many hump widths (Gauss degree 9), on
fewer dofs than P2 at HUMP_RESOLUTION and 4 to 50 times more accurate (eps = 1e-4 ... 3e-2
against P2 at 0.035: zeta 3e-14 ... 8e-13, a2 2e-12 ... 3e-11, ln f 6e-7 ... 4e-6;
benchmarks/archive/results/fem_cooling_speed.md); below, and with ``resolution``, P2."""


@option_group
@dataclass(frozen=True)
class HumpStepOptions:
    """The options of :func:`continued_state` that travel together.

    Parameters
    ----------
    resolution, order, intorder, tol, max_iter, decades, far_efolds, monitor, predict_iter
        As in :func:`continued_state`.

    Examples
    --------
    >>> HumpStepOptions(order=3).resolution == HUMP_RESOLUTION
    True
    """

    resolution: float = HUMP_RESOLUTION
    order: int = 2
    intorder: int | None = None
    tol: float = 1e-11
    max_iter: int = 100
    decades: float = HUMP_DECADES
    far_efolds: float = 1.0
    monitor: float = MONITOR_LOG_F
    predict_iter: int = 0


def continued_state(prev: CoolingState, eps_prev: float, eps: float,
                    options: HumpStepOptions | None = None, **overrides: Any) -> CoolingState:
    """One continuation step: the hard-rod HCS at ``eps`` from ``prev`` at ``eps_prev``.

    Parameters
    ----------
    prev : CoolingState
        A converged state at ``eps_prev``.
    eps_prev, eps : float
        Inelasticities :math:`1 - \\alpha` of ``prev`` and of the new state.
    options : HumpStepOptions, optional
        The options below as one object.
    **overrides
        Any option below by keyword, over ``options`` (an unknown name raises
        :class:`TypeError`).
    resolution : float
        Element size in the humps, in hump widths :math:`\\varepsilon^{1/3}`.
    order : int
        Lagrange degree.
    intorder : int, optional
        Gauss degree; default :data:`~kinetic_fem.solvers.fem.cooling_mesh.HUMP_INTORDER`
        (the exponential outer edge of the humps needs it).
    tol : float
        Newton tolerance (step of :math:`\\ln f` and relative step of :math:`\\zeta`).
    max_iter : int
        Newton iteration limit.
    decades : float
        The mesh ends where the rescaled start has fallen this many decades.
    far_efolds : float
        Beyond :data:`FAR_DECADES` decades of the start, the outer edge's elements fall
        ``far_efolds`` times :data:`~kinetic_fem.operators.adaptive.EDGE_EFOLDS`
        e-folds (:data:`P3_FAR_EFOLDS` for the default P3 states).
    monitor : float
        Newton's steps and residuals are measured where :math:`\\ln f_h` is above this
        (:data:`P3_MONITOR_LOG_F` for the default P3 states).
    predict_iter : int
        Newton steps that stop on the step first
        (:func:`~kinetic_fem.solvers.fem.cooling_newton.newton_cooling`;
        :data:`~kinetic_fem.solvers.fem.cooling_newton.PREDICT_ITER` for the default P3
        states).

    Returns
    -------
    CoolingState
        Converged or not (``info.converged``); the caller decides.
    """
    o = HumpStepOptions(**overrides) if options is None else replace(options, **overrides)
    resolution, order, intorder, tol = o.resolution, o.order, o.intorder, o.tol
    max_iter, decades, far_efolds = o.max_iter, o.decades, o.far_efolds
    monitor, predict_iter = o.monitor, o.predict_iter
    alpha = 1.0 - eps
    zeta0 = prev.zeta * (1.0 - alpha**2) / (1.0 - (1.0 - eps_prev) ** 2)
    # the cut-off where the rescaled start has fallen HUMP_DECADES decades (at eps ~ 1e-2
    # the outer edge is still slower than psi's e^(y^3/3), so the psi-based estimate
    # alone puts the outflow boundary at f ~ 1e-15 and spoils ln f near it)
    w = eps ** (1.0 / 3.0)
    probe = 1.0 + w * np.linspace(0.0, 60.0, 6001)
    start = prev.rescaled_log_f(eps_prev, eps, probe)
    low = start < -decades * math.log(10.0)
    cutoff = float(probe[np.argmax(low)]) if low.any() else float(probe[-1])
    # the outer edge's elements follow the start's slope (EDGE_EFOLDS e-folds each)
    slope = np.maximum(-np.gradient(start, probe), 0.0)
    if far_efolds != 1.0:  # elements of far_efolds e-folds where the start is < 1e-30
        slope = np.where(start < -FAR_DECADES * math.log(10.0), slope / far_efolds, slope)
    # (and refine with the resolution below that of the continuation steps)
    verts = hump_vertices(eps, zeta0, resolution=resolution, cutoff=cutoff,
                          edge_slope=lambda c: float(np.interp(c, probe, slope)),
                          efolds=EDGE_EFOLDS * min(1.0, resolution / HUMP_STEP_RESOLUTION))
    disc = FEMDiscretisation(alpha, verts, order, intorder or max(HUMP_INTORDER, 2 * order + 1),
                             gamma=1.0)  # the humps are those of hard rods
    same = eps == eps_prev
    # at the same eps the state itself (the rescaled form continues the inner tail beyond
    # y = 1/(2w) by psi's, 1.2 in ln f off at c = 0 for eps = 1e-3: a Newton step more)
    u0 = (prev.log_f(disc.dof_locations) if same
          else prev.rescaled_log_f(eps_prev, eps, disc.dof_locations))
    # a finer mesh at the same eps: full steps first (FULL_STEP_ITER, no line search)
    tries = [(False, min(max_iter, FULL_STEP_ITER))] if same else []
    for line_search, iters in [*tries, (True, max_iter)]:
        state = newton_cooling(disc, u0, zeta0, tol=tol, max_iter=iters,
                               pseudo_time=np.inf,
                               settle_steps=eps >= 1e-4,  # LOG_STEP_ZETA: measured there
                               min_damping=CLOSE_DAMPING if same else 1e-3,
                               line_search=line_search, monitor=monitor,
                               predict_iter=predict_iter,
                               speculative=True)  # the trials' Jacobians: same iterates
        if state.info.converged:
            break
    logger.info("HCS continuation eps = %.3g: %d dofs, %d Newton steps, zeta/eps = %.12g",
                eps, state.u.size, state.info.iterations, state.zeta / eps)
    return state
