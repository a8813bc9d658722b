"""The cooling state of kernels harder than hard rods near elastic collisions.

For :math:`|g|^\\gamma` with :math:`\\gamma = 2` the state at small
:math:`\\varepsilon = 1 - \\alpha` is two Gaussian humps at :math:`c \\approx \\pm 1` of
variance :math:`\\approx\\varepsilon` (curvature widths 0.101, 0.071 at eps = 0.01,
0.005), :math:`\\zeta/\\varepsilon \\to 2` (2.0102, 2.0050, 2.0010 at eps = 0.01, 0.005,
0.001: the first-order estimate :math:`\\tfrac18 (1-\\alpha^2)\\, 2^{\\gamma+1}`), and
:math:`\\ln f` has the WKB form :math:`-\\Phi(c)/\\varepsilon`: the valley between the humps
is :math:`\\ln f(0) \\approx -0.36/\\varepsilon` (-35, -72 at eps = 0.01, 0.005), the outer
edge :math:`\\approx -(c - 1)^2/(2\\varepsilon)`.  On the default HCS mesh (uniform
spacing :math:`\\varepsilon^{1/3}/10` to :math:`1 + 12\\varepsilon^{1/3}`, cut-off 3.7 at
eps = 0.001) the outer edge falls up to 20 e-folds per element, where the Galerkin drift
admits no positive discrete state: Newton's steps walk a front of -1.0 through it and the
continuation fails at eps = 2e-3 (alpha = 0.998).

:func:`quasi_elastic_chain` continues a state at ``eps <=`` :data:`QUASI_EPS` in equal
log steps of ratio at most :data:`QUASI_RATIO`, each on a mesh built from the previous
state by :func:`efold_vertices`: elements at most :data:`QUASI_EFOLDS` e-folds of the
previous :math:`\\ln f` wherever it is within :data:`QUASI_DEPTH` of its peak,
:data:`QUASI_CORE` elements per :math:`\\sqrt\\varepsilon` over the humps,
:data:`QUASI_MAX_SIZE` elsewhere (the valley, far below any constraint), and the cut-off
where the previous :math:`\\ln f` has fallen :data:`QUASI_CUTOFF_DEPTH` below its peak
(1.79 and 1.74 for the last two links to eps = 0.001, against 3.7); the last link, to
the state asked for, is on a finer such mesh (:data:`QUASI_FINAL`).  Newton starts
from the previous state itself (rescaled and extrapolated predictors, tried, diverged).
The default gamma = 2 state skips these links: :mod:`.cooling_gamma2` interpolates
stored states in :math:`\\varepsilon \\ln f` (the WKB scaling) and solves once on the
:data:`QUASI_FINAL` mesh built from that start.
"""

from __future__ import annotations

import logging
import math
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from ...model import UnsupportedModelError
from ...operators.mesher import march
from ..continuation import StepRule, continuation, geometric_path
from .cooling_newton import CoolingState, newton_cooling
from .heated import FEMDiscretisation

__all__ = ["QUASI_EPS", "QUASI_FRONTIER", "QUASI_RATIO", "QUASI_EFOLDS", "QUASI_DEPTH",
           "QUASI_CUTOFF_DEPTH", "QUASI_CORE", "QUASI_FINAL", "QUASI_LINK", "QUASI_MAX_SIZE",
           "QUASI_MIN_RATIO", "LogDensity", "check_frontier", "efold_vertices",
           "quasi_elastic_chain"]

logger = logging.getLogger(__name__)

QUASI_EPS = 0.01
"""Below this inelasticity (alpha > 0.99) hard kernels continue on :func:`efold_vertices`
meshes (gamma = 2: the default mesh's continuation failed at eps = 2e-3)."""
QUASI_FRONTIER = 5e-4
"""Smallest inelasticity reached (alpha 0.9995, 3.5 CPU s of links from eps 0.01); at
1e-4 the links failed (zeta/eps 6 after 32 s): below, a clear error."""
QUASI_RATIO = 10.0 ** 0.2
"""Largest ratio of successive inelasticities (1.585: 12 Newton steps per link from eps
0.01 to 0.001; ratio 2 failed at 0.0025 -> 0.001)."""
QUASI_MIN_RATIO = 1.05
"""A failed link is retried through the geometric mean down to this ratio."""
QUASI_EFOLDS = 1.5
"""Largest fall of the previous state's ln f over one element (eps 0.01 -> 0.001, one
process: 1.0 5.6 CPU s, 1.5 2.3 s, 2.0 8.1 s with halved links)."""
QUASI_DEPTH = 100.0
"""The e-fold limit holds where ln f is within this of its peak (deeper: the valley;
with QUASI_EFOLDS 1.5: 120 / 150 2.3 CPU s, 100 / 110 1.7 s)."""
QUASI_CUTOFF_DEPTH = 110.0
"""The mesh ends beyond the humps where ln f has fallen this far below its peak (f there
is 1e-48 of the peak: below the monitored level 1e-40 of Newton's method)."""
QUASI_FINAL = (1.0, 120.0, 150.0)
"""``efolds``, ``depth``, ``cutoff_depth`` of the mesh of the state asked for (eps =
0.001: zeta within 6e-9 of the default mesh at half spacing, against 3e-6 on
:data:`QUASI_LINK`)."""
QUASI_LINK = (QUASI_EFOLDS, QUASI_DEPTH, QUASI_CUTOFF_DEPTH)
"""The same for the intermediate links."""
QUASI_CORE = 3.0
"""Elements per :math:`\\sqrt\\varepsilon` (the humps' standard deviation) within three of
them from c = 1."""
QUASI_MAX_SIZE = 0.05
"""Largest element (thermal velocities)."""


class LogDensity(Protocol):
    """Anything with :meth:`log_f` (a :class:`~.cooling_newton.CoolingState`, or a
    predictor of the state such as :class:`~.cooling_gamma2.AnchoredStart`).

    Attributes
    ----------
    log_f : callable
        ``log_f(c)``: :math:`\\ln f` at the velocities ``c`` (thermal units).
    """

    def log_f(self, c: NDArray) -> NDArray:
        """:math:`\\ln f` at ``c``."""


def efold_vertices(prev: LogDensity, eps: float, *, efolds: float = QUASI_EFOLDS,
                   depth: float = QUASI_DEPTH, cutoff_depth: float = QUASI_CUTOFF_DEPTH,
                   core: float = QUASI_CORE, max_size: float = QUASI_MAX_SIZE
                   ) -> NDArray[np.float64]:
    """Symmetric vertices on which ``prev``'s :math:`\\ln f` falls by at most ``efolds``
    per element (module notes).

    Parameters
    ----------
    prev : LogDensity
        The state that predicts the new one (its ``log_f`` continues linearly beyond its
        mesh), or a predictor of it.
    eps : float
        Inelasticity of the new state (sets the core resolution).
    efolds : float
        Largest fall of :math:`\\ln f` per element where it is within ``depth`` of its peak.
    depth : float
        Depth below the peak where the e-fold limit stops.
    cutoff_depth : float
        The mesh ends at the first vertex beyond c = 1 where :math:`\\ln f` has fallen
        this far below its peak.
    core : float
        Elements per :math:`\\sqrt\\varepsilon` within :math:`3\\sqrt\\varepsilon` of c = 1.
    max_size : float
        Largest element.

    Returns
    -------
    ndarray
        Increasing vertices, symmetric about 0, including 0.
    """
    grid = np.linspace(0.0, 4.0, 16001)
    log_f = prev.log_f(grid)
    peak = float(log_f.max())
    slope = np.abs(np.gradient(log_f, grid))
    width = math.sqrt(eps)

    def stop(c: float) -> bool:
        lf = float(np.interp(c, grid, log_f))
        if c > 1.0 and peak - lf > cutoff_depth:
            return True
        if c >= grid[-1]:
            raise ValueError(f"the state has not fallen {cutoff_depth:g} below its peak by "
                             f"c = {grid[-1]:g}: not a near-elastic state")
        return False

    def size(c: float) -> float:
        lf = float(np.interp(c, grid, log_f))
        h = max_size
        if min(peak - lf, peak - float(np.interp(c + h, grid, log_f))) < depth:
            h = min(h, efolds / max(float(np.interp(c, grid, slope)), 1e-12))
        if abs(c - 1.0) < 3.0 * width:
            h = min(h, width / core)
        return h

    return march(size, stop)


def check_frontier(alpha: float, gamma: float) -> None:
    """Raise the clear error below :data:`QUASI_FRONTIER`.

    Parameters
    ----------
    alpha : float
        Restitution coefficient asked for.
    gamma : float
        Kernel exponent.

    Raises
    ------
    UnsupportedModelError
        If :math:`1 - \\alpha <` :data:`QUASI_FRONTIER`.
    """
    if 1.0 - alpha < QUASI_FRONTIER * (1.0 - 1e-9):
        raise UnsupportedModelError(
            f"the FEM cooling state of the kernel |g|^{gamma:g} is available for "
            f"alpha <= {1.0 - QUASI_FRONTIER:g} (eps >= {QUASI_FRONTIER:g}), got alpha = "
            f"{alpha}: below, the valley between the humps (ln f ~ -0.373/eps) underflows "
            "and Newton's method on ln f does not converge; the state is two Gaussian humps "
            "of variance ~eps at c = +-sqrt(1 - eps) with zeta = 2 eps + eps^2 to O(eps^3)")


def quasi_elastic_chain(start: CoolingState, eps_start: float, alpha: float, *,
                        tol: float, max_iter: int) -> CoolingState:
    """Continuation in :math:`\\varepsilon` from ``start`` to ``alpha`` on
    :func:`efold_vertices` meshes (module notes).

    Parameters
    ----------
    start : CoolingState
        A converged state at ``eps_start`` (at most :data:`QUASI_EPS`, the kernel of the
        target).
    eps_start : float
        Its inelasticity.
    alpha : float
        Restitution coefficient of the target, above ``1 - eps_start``.
    tol : float
        Newton tolerance at the target (the links use it too: their states build the
        next mesh).
    max_iter : int
        Newton steps allowed per link.

    Raises
    ------
    UnsupportedModelError
        Below :data:`QUASI_FRONTIER`.

    Returns
    -------
    CoolingState
        The state at ``alpha`` on its own mesh (:data:`QUASI_FINAL`); ``info.converged``
        False if a link failed at the smallest ratio :data:`QUASI_MIN_RATIO` (that link's
        state).
    """
    eps = 1.0 - alpha
    check_frontier(alpha, start.disc.kernel.gamma)
    disc0 = start.disc

    def solve(prev: CoolingState, eps_prev: float, step: float) -> CoolingState:
        efolds, depth, cutoff_depth = QUASI_FINAL if step == eps else QUASI_LINK
        verts = efold_vertices(prev, step, efolds=efolds, depth=depth,
                               cutoff_depth=cutoff_depth)
        disc = FEMDiscretisation(1.0 - step, verts, disc0.order, disc0.intorder,
                                 gamma=disc0.gamma)
        state = newton_cooling(disc, prev.log_f(disc.dof_locations),
                               prev.zeta * step / eps_prev, tol=tol, max_iter=max_iter,
                               pseudo_time=math.inf)
        logger.info("HCS quasi-elastic link eps %.4g -> %.4g: %d dofs, cut-off %.3f, %s "
                    "in %d Newton steps", eps_prev, step, disc.dof_locations.size,
                    verts[-1], "converged" if state.info.converged else "failed",
                    state.info.iterations)
        return state

    return continuation(start, eps_start, geometric_path(eps_start, eps, QUASI_RATIO), solve,
                        rule=StepRule(min_ratio=QUASI_MIN_RATIO)).last
