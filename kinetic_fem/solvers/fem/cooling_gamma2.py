"""The cooling state of the kernel :math:`|g|^2` from its scaled form: one Newton solve.

Near elastic collisions (:math:`\\varepsilon = 1 - \\alpha \\to 0`) the state of
:math:`\\zeta (c f)' = \\tilde Q[f]` is two humps at :math:`c = \\pm 1`, and a
collision moves a particle at :math:`c` toward its partner :math:`c'` by
:math:`\\tfrac{\\varepsilon}{2}(c - c')` (the post-collision pair is the exchanged one
plus that shift).  With :math:`\\ln f = -\\Phi(c)/\\varepsilon + \\Psi(c) + O(\\varepsilon)`,
:math:`\\zeta = 2\\varepsilon + O(\\varepsilon^2)` and the partners in the humps, the
shift of the pre-collision velocity, :math:`\\tfrac{\\varepsilon}{2}(c - s)`, changes
:math:`\\ln f` by :math:`-\\Phi'(c)(c - s)/2 = O(1)`: the scaled equation at leading order
is the Hamilton-Jacobi equation

.. math::

    H(c, \\Phi') = \\tfrac12 \\sum_{s = \\pm 1} (c - s)^2
    \\big[e^{-\\Phi'(c)(c - s)/2} - 1\\big] + 2 c\\, \\Phi'(c) = 0

for the non-trivial root :math:`\\Phi' \\ne 0` (:func:`wkb_exponent`).  Its small-
:math:`\\Phi'` (Fokker-Planck) limit is
:math:`\\Phi' = -4c(1 - c^2)/(c^4 + 6c^2 + 1)`: humps of variance :math:`\\varepsilon`
(:math:`\\Phi'' (1) = 1`), a valley :math:`\\ln f(0) - \\ln f(1) = -\\Phi(0)/\\varepsilon`
with :math:`\\Phi(0) = 0.3734` (0.4135 in the Fokker-Planck limit; measured 0.36 at
eps = 0.01 with the :math:`\\Psi` term) and the tail :math:`\\Phi \\to c^2/4`, i.e.
:math:`\\ln f \\to -c^2/(2\\zeta)`.  So :math:`\\varepsilon \\ln f` is a smooth
:math:`O(1)` function of :math:`c` whose expansion in :math:`\\varepsilon` is regular: the
states at 36 inelasticities from 1 to 5e-4 (the anchors of
:mod:`.cooling_stored`, the data file ``data/gamma2_anchors.json``, computed once by
the path they replace, ``python -m kinetic_fem.solvers.fem.cooling_generate gamma2``: the
pseudo-transient iteration at alpha <= 0.5, above the continuation of
:mod:`.cooling_alpha` and :mod:`.cooling_quasi`; stored as
:math:`\\varepsilon \\ln f` at 65 points)
interpolate to the state at any :math:`\\varepsilon` between them
(:func:`anchored_log_f`: cubic Lagrange interpolation in :math:`\\ln\\varepsilon` of
:math:`\\varepsilon \\ln f` at fixed :math:`c`, and of :math:`\\zeta/\\varepsilon`;
beyond an anchor's sampled range, :math:`\\ln f` continues linearly; bent with the
tail curvature :math:`-1/\\zeta` the default mesh's far tail at alpha 0.995
underflowed, or over 0.2 beyond, alpha 0.998 failed).  From that start Newton's method
converges in 2 to 4 steps (2 Jacobians at most, then chord steps) on the mesh of the
state asked for (:func:`anchored_state`): the default HCS mesh at
:math:`\\varepsilon \\ge` :data:`ANCHORED_DEFAULT_EPS` (at :math:`\\varepsilon \\ge
3\\cdot 10^{-3}` the same discrete state as the continuation's; near elastic cut where
the start is :data:`ANCHORED_CUTOFF_DEPTH` below its peak, which leaves zeta, a2 and
ln f where f > 1e-40 unchanged to round-off), below it the mesh
:func:`~.cooling_quasi.efold_vertices` builds from the start itself
(:data:`~.cooling_quasi.QUASI_FINAL`), instead of 2 to 20 links
of 5 to 13 Newton steps each (``benchmarks/archive/results/fem_cooling_models_speed.md``).
"""

from __future__ import annotations

import functools
import logging
import math

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline

from ...model import CoolingProblem
from .cooling_mesh import hcs_bulk, hcs_cutoff, hcs_spacing, hcs_vertices
from .cooling_newton import CLOSE_DAMPING, CoolingState, newton_cooling
from .cooling_order import order_spacing
from .cooling_quasi import (
    QUASI_CORE,
    QUASI_FINAL,
    QUASI_MAX_SIZE,
    check_frontier,
    efold_vertices,
)
from .cooling_stored import gamma2_anchors
from .heated import FEMDiscretisation

__all__ = ["ANCHOR_CLIP", "ANCHOR_DEGREE", "ANCHORED_CUTOFF_DEPTH", "ANCHORED_DEFAULT_EPS",
           "ANCHORED_GAMMA", "ANCHORED_ITER",
           "ANCHORED_LINE_SEARCH", "AnchoredStart",
           "anchor_samples", "anchored_log_f", "anchored_state", "anchored_zeta",
           "uses_anchors", "wkb_exponent"]

logger = logging.getLogger(__name__)

ANCHORED_GAMMA = 2.0
"""The kernel exponent of the stored anchors."""
ANCHOR_CLIP = 100.0
"""An anchor is sampled out to where its :math:`\\ln f` has fallen this far below its peak
beyond the hump (the continuation's meshes end 110 to 150 below it, and the last
elements carry the cut-off's front).  140 (one process against 100): alpha 0.998 failed
from the anchors (the continuation took over, 10.5 units against 1.7), elsewhere 0 to
15 % faster; not kept."""
ANCHOR_DEGREE = 3
"""Degree of the Lagrange interpolation in :math:`\\ln\\varepsilon` (anchors in ratio 1.25:
degree 1 took 4 to 11 Newton steps at the target, degree 3 took 3 to 5)."""
ANCHORED_CUTOFF_DEPTH = 150.0
"""The default mesh (eps >= :data:`ANCHORED_DEFAULT_EPS`) ends at its first vertex
beyond c = 1 where the anchored start has fallen this far below its peak (as
:data:`~.cooling_quasi.QUASI_FINAL`): near elastic collisions the default cut-off
(the outer edge 1 + 12 eps^(1/3) of the hard-rod humps) reaches ln f ~ -500.  Against
the full default mesh (one process): alpha 0.95 745 -> 629 dofs, 0.99 929 -> 549, 0.995
1041 -> 549, 0.997 1153 -> 565; zeta and a2 equal to 5.6e-16, ln f to 7e-13 where
f > 1e-40 of the peak (0.7 at the new cut-off); 0.995 2.4 -> 0.47 units, 0.99 1.23 ->
0.43; alpha <= 0.9 unchanged (the mesh ends above that depth)."""
ANCHORED_DEFAULT_EPS = 2e-3
"""From this inelasticity up the anchored state is solved on the default mesh (cut at
:data:`ANCHORED_CUTOFF_DEPTH`), below on the :func:`~.cooling_quasi.efold_vertices`
mesh of the start (the continuation switched at :data:`~.cooling_alpha.DIRECT_EPS`
= 3e-3: the uncut default mesh's far tail underflowed).  Cut default mesh, one process,
zeta against the efold mesh twice finer: alpha 0.998 581 dofs, 4 Newton steps, 2.3e-11
(efold mesh 1041 dofs, 1.1e-9); 0.999 633 dofs, 10 steps, 3.1e-11; 0.9995 no convergence
in 12 steps."""
ANCHORED_ITER = 12
"""Newton steps allowed from the anchored start before the continuation takes over."""
ANCHORED_LINE_SEARCH = False
"""Backtracking of Newton's method from the anchored start: every step measured was full,
and without the search each residual comes with its Jacobian (one collision operator
less per step): alpha 0.7 ... 0.9995 13 to 22 % less CPU, the states bitwise equal (one
process, best of two)."""


@functools.lru_cache(maxsize=2)
def _wkb_table(fokker_planck: bool) -> tuple[NDArray, NDArray]:
    """:math:`\\Phi` on 1201 points of [0, 6] (trapezoidal rule on the root :math:`\\Phi'`)."""
    from scipy.integrate import cumulative_trapezoid
    from scipy.optimize import brentq

    grid = np.linspace(0.0, 6.0, 1201)
    slope = -4.0 * grid * (1.0 - grid**2) / (grid**4 + 6.0 * grid**2 + 1.0)
    if not fokker_planck:
        def ham(x: float, p: float) -> float:
            return 0.5 * sum((x - s) ** 2 * math.expm1(-p * (x - s) / 2.0)
                             for s in (1.0, -1.0)) + 2.0 * x * p

        for i, (x, p_fp) in enumerate(zip(grid, slope, strict=True)):
            if abs(p_fp) < 1e-14:
                continue
            # H is convex in p with H(x, 0) = 0: the other root lies on the side of p_fp
            far = p_fp
            while ham(x, far) < 0.0:
                far *= 2.0
            slope[i] = brentq(lambda p, x=x: ham(x, p), 1e-12 * far, far, xtol=1e-14)
    phi = cumulative_trapezoid(slope, grid, initial=0.0)
    return grid, phi - np.interp(1.0, grid, phi)


def wkb_exponent(c: NDArray, *, fokker_planck: bool = False) -> NDArray:
    """The leading-order exponent :math:`\\Phi(c)` of :math:`\\ln f \\simeq
    -\\Phi/\\varepsilon` near elastic collisions, :math:`\\Phi(\\pm 1) = 0` (module notes).

    Parameters
    ----------
    c : array_like
        Velocities (thermal units), :math:`|c| \\le 6`.
    fokker_planck : bool
        The small-:math:`\\Phi'` limit :math:`\\Phi' = -4c(1-c^2)/(c^4+6c^2+1)` instead of
        the root of the Hamilton-Jacobi equation.

    Returns
    -------
    ndarray
        :math:`\\Phi(|c|)`.
    """
    grid, phi = _wkb_table(fokker_planck)
    return np.interp(np.abs(np.asarray(c, dtype=float)), grid, phi)


def anchor_samples(state: CoolingState, eps: float, points: int
                   ) -> tuple[float, float, NDArray[np.float64]]:
    """What the table stores of one anchor state (:mod:`.cooling_generate`).

    Parameters
    ----------
    state : CoolingState
        A converged gamma = 2 state.
    eps : float
        Its inelasticity.
    points : int
        Samples of :math:`\\varepsilon \\ln f` on :math:`[0, c_{end}]`.

    Returns
    -------
    zeta_ratio : float
        :math:`\\zeta/\\varepsilon`.
    c_end : float
        End of the sampled range: where :math:`\\ln f` has fallen :data:`ANCHOR_CLIP` below
        its peak beyond it (at most 0.98 of the mesh's cut-off).
    values : ndarray, shape (points,)
        :math:`\\varepsilon \\ln f` at ``points`` equally spaced velocities.
    """
    edge = 0.98 * state.disc.vertices[-1]
    grid = np.linspace(0.0, edge, 20001)
    log_f = state.log_f(grid)
    peak = int(np.argmax(log_f))
    deep = np.nonzero(log_f[peak:] < log_f[peak] - ANCHOR_CLIP)[0]
    c_end = float(grid[peak + deep[0]]) if deep.size else float(edge)
    c = np.linspace(0.0, c_end, points)
    return state.zeta / eps, c_end, eps * state.log_f(c)


@functools.lru_cache(maxsize=None)
def _anchor(index: int) -> tuple[float, float, float, CubicSpline]:
    eps, zeta_ratio, c_end, values = gamma2_anchors()[1][index]
    c = np.linspace(0.0, c_end, len(values))
    # eps ln f is even: zero slope at c = 0
    return eps, zeta_ratio, c_end, CubicSpline(c, np.asarray(values), bc_type=((1, 0.0),
                                                                             "not-a-knot"))


def _anchor_log_f(index: int, c: NDArray) -> NDArray:
    """:math:`\\ln f` of an anchor at ``|c|``, continued beyond its range (module notes)."""
    eps, zeta_ratio, c_end, spline = _anchor(index)
    c = np.abs(c)
    inside = np.minimum(c, c_end)
    slope = min(float(spline(c_end, 1)) / eps, 0.0)
    return spline(inside) / eps + slope * (c - inside)


def _weights(eps: float) -> tuple[list[int], NDArray]:
    """The anchors nearest ``eps`` in :math:`\\ln\\varepsilon` and their Lagrange weights."""
    logs = np.log([a[0] for a in gamma2_anchors()[1]])
    near = sorted(np.argsort(np.abs(logs - math.log(eps)))[:ANCHOR_DEGREE + 1].tolist())
    s = math.log(eps)
    weights = np.array([math.prod((s - logs[m]) / (logs[k] - logs[m]) for m in near if m != k)
                        for k in near])
    return near, weights


def anchored_log_f(eps: float, c: NDArray) -> NDArray:
    """The start :math:`\\ln f(c)` at ``eps`` interpolated from the anchors (module notes).

    Parameters
    ----------
    eps : float
        Inelasticity, within the anchors' range.
    c : array_like
        Velocities (thermal units).

    Returns
    -------
    ndarray
    """
    c = np.asarray(c, dtype=float)
    near, weights = _weights(eps)
    return sum(w * _anchor(k)[0] * _anchor_log_f(k, c)
               for k, w in zip(near, weights, strict=True)) / eps


def anchored_zeta(eps: float) -> float:
    """The start :math:`\\zeta` at ``eps`` (interpolation of :math:`\\zeta/\\varepsilon`).

    Parameters
    ----------
    eps : float
        Inelasticity, within the anchors' range.

    Returns
    -------
    float
    """
    near, weights = _weights(eps)
    return eps * float(sum(w * _anchor(k)[1] for k, w in zip(near, weights, strict=True)))


class AnchoredStart:
    """The interpolated start as a state-like predictor (``log_f`` only), for
    :func:`~.cooling_quasi.efold_vertices`.

    Parameters
    ----------
    eps : float
        Inelasticity.
    """

    def __init__(self, eps: float) -> None:
        self.eps = eps

    def log_f(self, c: NDArray) -> NDArray:
        """:func:`anchored_log_f` at ``c``."""
        return anchored_log_f(self.eps, c)


def _range() -> tuple[float, float]:
    eps = [a[0] for a in gamma2_anchors()[1]]
    return min(eps), max(eps)


def uses_anchors(problem: CoolingProblem) -> bool:
    """The kernel :data:`ANCHORED_GAMMA` at an inelasticity the anchors cover.

    Parameters
    ----------
    problem : CoolingProblem
        The cooling problem.

    Returns
    -------
    bool
    """
    lo, hi = _range()
    eps = problem.gas.epsilon
    return problem.gas.gamma == ANCHORED_GAMMA and lo * (1 - 1e-9) <= eps <= hi * (1 + 1e-9)


def anchored_state(problem: CoolingProblem, *, order: int, intorder: int | None, tol: float,
                   max_iter: int, refine: float = 1.0) -> CoolingState | None:
    """Newton's method from the anchored start on the mesh of the state asked for.

    Parameters
    ----------
    problem : CoolingProblem
        gamma = 2, eps within the anchors (:func:`uses_anchors`).
    order : int
        Lagrange degree.
    intorder : int or None
        Gauss degree (None: ``2 * order + 1``).
    tol : float
        Newton tolerance.
    max_iter : int
        Newton iteration limit (at most :data:`ANCHORED_ITER` are used).
    refine : float
        Element sizes divided by this (convergence studies): the default mesh's spacing,
        or the e-folds per element, core element and largest element of the near-elastic
        mesh.

    Returns
    -------
    CoolingState or None
        The converged state; None if Newton did not converge (the caller continues).

    Raises
    ------
    UnsupportedModelError
        Below :data:`~.cooling_quasi.QUASI_FRONTIER`.
    """
    eps = problem.gas.epsilon
    check_frontier(problem.gas.alpha, problem.gas.gamma)
    if eps >= ANCHORED_DEFAULT_EPS:
        verts = hcs_vertices(hcs_cutoff(problem),
                             order_spacing(hcs_spacing(problem), order) / refine,
                             gamma=problem.gas.gamma, bulk=hcs_bulk(eps))
        half = verts[verts >= 0.0]
        log_f = anchored_log_f(eps, half)
        deep = np.nonzero((half > 1.0) & (log_f < log_f.max() - ANCHORED_CUTOFF_DEPTH))[0]
        if deep.size:  # near elastic: the default cut-off 1 + 12 eps^(1/3) is far deeper
            half = half[:deep[0] + 1]
            verts = np.concatenate([-half[:0:-1], half])
    else:
        efolds, depth, cutoff_depth = QUASI_FINAL
        verts = efold_vertices(AnchoredStart(eps), eps, efolds=efolds / refine, depth=depth,
                               cutoff_depth=cutoff_depth, core=QUASI_CORE * refine,
                               max_size=QUASI_MAX_SIZE / refine)
    disc = FEMDiscretisation(problem.gas.alpha, verts, order, intorder or 2 * order + 1,
                             gamma=problem.gas.gamma)
    state = newton_cooling(disc, anchored_log_f(eps, disc.dof_locations), anchored_zeta(eps),
                           tol=tol, max_iter=min(max_iter, ANCHORED_ITER),
                           pseudo_time=math.inf, min_damping=CLOSE_DAMPING,
                           line_search=ANCHORED_LINE_SEARCH)
    logger.info("HCS gamma 2 from the anchors at eps %.4g: %d dofs, %s in %d Newton steps",
                eps, disc.dof_locations.size,
                "converged" if state.info.converged else "failed", state.info.iterations)
    return state if state.info.converged else None
