"""Galerkin FEM for the homogeneous cooling state: cooling ``method="fem"``.

Without forcing, :math:`P(v, t) = f(v/s)/s` with :math:`s = \\sqrt T` solves the
homogeneous Boltzmann equation with kernel :math:`|g|^\\gamma` when

.. math::

    \\zeta\\,\\frac{d}{dc}\\big(c f(c)\\big) = \\tilde Q[f](c), \\qquad
    \\int f = 1, \\quad \\int c^2 f = 1 .

Derivation: :math:`\\partial_t P = -(\\dot s/s^2)(cf)'` and, the collision operator being
homogeneous of degree :math:`\\gamma - 1` in :math:`s`,
:math:`Q[P](v) = n s^{\\gamma-1}\\tilde Q[f](c)`; with the convention
:math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`, i.e. :math:`\\dot s = -\\zeta n s^{\\gamma+1}`,
both sides carry :math:`n s^{\\gamma-1}`, so the scaled equation is the same for every
kernel and does not depend on :math:`n`.  Multiplying by :math:`c^2` and integrating,
:math:`-2\\zeta = -\\tfrac14\\langle(1-\\alpha^2)|g|^{\\gamma+2}\\rangle`: the energy identity

.. math::

    \\zeta = \\tfrac18\\,\\langle (1-\\alpha^2)\\,|c - c'|^{\\gamma+2}\\rangle_f ,

which the solver does not impose (it is a check, reported in ``info.extra``).

Discretisation: P2 (P1; P3 for hard rods, :mod:`.cooling_order`) Lagrange elements
on :math:`[-V, V]`, the unknown :math:`u_h = \\ln f_h` (even), the collision weak form
:math:`C_i` of the heated solver (:class:`~kinetic_fem.solvers.fem.FEMDiscretisation`)
and the drift in weak form,

.. math::

    R_i = C_i[f_h] + \\zeta \\int \\varphi_i'\\, c\\, f_h \\,dc
          - \\zeta \\big[\\varphi_i\\, c f_h\\big]_{-V}^{V} = 0 ,

keeping the outflow through :math:`\\pm V` (the characteristics of the drift leave the
interval there, so no boundary condition may be imposed: a zero-flux condition would
force :math:`\\ln f \\to -\\infty` at the cut-off).  The collision weak form conserves
mass exactly, so :math:`\\sum_i R_i = -2\\zeta V f_h(V)`, the outflow (below 1e-30 for
exponential tails, :math:`O(V^{-3})` for the Maxwell power law): the equation at
:math:`c = 0` is replaced by the normalisation, and the unit temperature
:math:`\\int c^2 f_h = 1` closes the system for :math:`(u_h, \\zeta)`.  Newton's method
(:class:`kinetic_fem.solvers.fem.EquilibratedLU`, the log update of the heated solver) starts
from a Gaussian at the Gaussian estimate of :math:`\\zeta` (pseudo-transient
continuation); below :math:`\\alpha = 0.5` (long exponential tails far from the Gaussian
start) by continuation in :math:`\\alpha` from 0.5; :math:`\\gamma = 2` from stored
scaled states (:mod:`kinetic_fem.solvers.fem.cooling_gamma2`).

Near elastic collisions (hard rods, :math:`\\varepsilon = 1 - \\alpha <` :data:`HUMP_EPS`)
the state is two humps of width :math:`w = \\varepsilon^{1/3}` at :math:`c = \\pm 1`.
While they are broad (:math:`\\varepsilon \\ge` 0.035, :mod:`.cooling_band`) the default
is P3 on a mesh graded along the tail, from one link from 0.1; below, and with ``resolution``, it is
reached by continuation in :math:`\\varepsilon` (:mod:`.cooling_links`,
:mod:`.cooling_hump`: toward :math:`\\varepsilon \\ge 10^{-3}` by one link on a coarse
mesh cut off at 30 decades from the nearest stored start at or above it, eps = 0.04,
0.01 or 0.0025, :mod:`.cooling_seeds`; below from 0.0025 in
steps of at most 2, :func:`hump_chain`; the state asked for is solved once more on the
finer mesh, P3 at 0.2 hump widths by default down to :math:`10^{-4}`; ``initial=`` a state
at a neighbouring alpha starts the continuation there), each on a mesh that follows the
humps
(:func:`kinetic_fem.operators.adaptive.hump_vertices`: ``resolution`` hump widths over
the humps and their outer edge, geometric grading along the exponential inner tail), from
the previous state rescaled on :math:`y = (1 - c)/w` (:meth:`CoolingState.rescaled_log_f`),
by Newton's method with backtracking (:func:`kinetic_fem.solvers.newton.newton`) on
:math:`\\ln f` itself; :meth:`CoolingState.error_estimate` (a Newton step on the bisected
mesh) estimates the error of :math:`\\ln f_h`.  In the outer edge of the humps elements fall
at most :data:`~kinetic_fem.operators.adaptive.EDGE_EFOLDS` e-folds, the Gauss rule is of degree
:data:`~kinetic_fem.solvers.fem.cooling_mesh.HUMP_INTORDER` (the 3-point rule's error on
:math:`e^{u_h}` over the exponential edge gave the old ln f error and growing modes at the
cut-off), the normalisation replaces the equation at the peak.  The continuation converges down to
:math:`\\varepsilon = 10^{-6}` (``benchmarks/results/fem_cooling.md``); below
:data:`HUMP_FRONTIER` a failure says so and names the leading-order :math:`\\psi` state.

The inelastic Maxwell model (:math:`\\gamma = 0`) has the closed-form state
:math:`f(c) = 2/(\\pi(1+c^2)^2)` for every alpha (Baldassarri, Marini Bettolo Marconi,
Puglisi, Europhys. Lett. 58, 14 (2002)), :math:`\\zeta = (1-\\alpha^2)/4`; by default the
mesh ends at :math:`c = 200` and its :math:`c^{-4}` tail (infinite fourth moment) is
continued analytically beyond (:mod:`kinetic_fem.solvers.fem.cooling_maxwell`); with
``cutoff`` (or ``vertices``) it is resolved on a geometric mesh out to, e.g.,
:math:`V = 10^8`; the result carries :math:`f` recovered from the superconvergent points
of :math:`\\ln f_h` (:mod:`kinetic_fem.solvers.fem.cooling_tail`).

A velocity-dependent restitution law has no homogeneous cooling state (the law has its
own speed scale, so the state changes as the gas cools); such problems are refused.

Which of these paths solves a problem is one table, :data:`.regimes.REGIMES`: a
regime per class with its thresholds, exactly one of which applies to a kernel,
restitution coefficient and set of options (:class:`.regimes.CoolingOptions`).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...distribution import VelocityDistribution
from ...exceptions import ConvergenceError
from ...gas import check_positive
from ...model import CoolingProblem, UnsupportedModelError
from ...operators.fem_discretisation import FEMDiscretisation
from ...options import gather
from ...solve import register_solver
from .cooling_hump import (
    HUMP_LINK_RESOLUTION,
    HUMP_P3_EPS,
    HUMP_P3_RESOLUTION,
    HUMP_RESOLUTION,
    HUMP_STEP_RESOLUTION,
    continued_state,
)
from .cooling_links import (
    HUMP_EPS,
    HUMP_FRONTIER,
    HUMP_MIN_RATIO,
    HUMP_RATIO,
    HUMP_STEP_ITER,
    HUMP_STEP_TOL,
    hump_chain,
)
from .cooling_maxwell import MaxwellTailState, maxwell_tail_recipe
from .cooling_mesh import (
    HUMP_INTORDER,
    MAXWELL_CUTOFF,
    hcs_cutoff,
    hcs_spacing,
    hcs_vertices,
    initial_log_f,
)
from .cooling_newton import CoolingState, cooling_recipe, newton_cooling
from .cooling_tail import maxwell_hcs, recovered_distribution
from .heated import ACCURACY_REFINEMENTS, refinement_factor
from .options import MeshOptions
from .regimes import CoolingOptions, hump_start, link_start, solve_state, uses_hump_mesh

__all__ = ["solve_fem_cooling", "cooling_state", "CoolingState", "CoolingOptions",
           "ConvergenceError", "FEMDiscretisation", "continued_state", "hump_chain",
           "hump_start", "uses_hump_mesh", "HUMP_EPS", "HUMP_RESOLUTION", "HUMP_FRONTIER",
           "hcs_cutoff", "hcs_spacing", "hcs_vertices", "maxwell_hcs", "initial_log_f",
           "newton_cooling", "MAXWELL_CUTOFF", "HUMP_STEP_RESOLUTION", "HUMP_LINK_RESOLUTION",
           "HUMP_INTORDER", "HUMP_P3_EPS", "HUMP_P3_RESOLUTION", "link_start",
           "cooling_distribution", "HUMP_RATIO", "HUMP_STEP_TOL", "HUMP_STEP_ITER",
           "HUMP_MIN_RATIO"]

logger = logging.getLogger(__name__)


def _cooling_mesh(m: MeshOptions) -> MeshOptions:
    """``m``, refusing the heated solver's ``grading``."""
    if m.grading is not None:
        raise ValueError(f"grading={m.grading!r}: the cooling state's meshes follow its "
                         "regimes (the drop of ln f per element); give spacing, cutoff or "
                         "vertices")
    return m


def cooling_state(problem: CoolingProblem, *, mesh: MeshOptions | None = None,
                  tol: float = 1e-11, max_iter: int = 100,
                  resolution: float | None = None, sequence: bool = True,
                  initial: CoolingState | VelocityDistribution | None = None,
                  **mesh_keywords: Any) -> CoolingState:
    """The HCS by Newton's method (see :func:`solve_fem_cooling` for the options).

    The keywords make one :class:`~kinetic_fem.solvers.fem.regimes.CoolingOptions`; the
    regime of :data:`~kinetic_fem.solvers.fem.regimes.REGIMES` that applies solves.
    ``sequence``: on a mesh built from ``spacing`` (not explicit ``vertices``), start
    from the state on a mesh :data:`~.cooling_order.COARSE_FACTOR` times coarser, at
    most :data:`~.cooling_order.COARSE_SPACING` (mesh sequencing).

    Parameters
    ----------
    problem : CoolingProblem
        Constant restitution, any kernel.
    mesh, tol, max_iter, resolution, **mesh_keywords
        As in :func:`solve_fem_cooling`.
    sequence : bool
        Mesh sequencing (see above).
    initial : CoolingState or VelocityDistribution, optional
        Warm start, as in :func:`solve_fem_cooling`.

    Returns
    -------
    CoolingState

    Raises
    ------
    UnsupportedModelError
        For a velocity-dependent restitution law.
    ConvergenceError
        If Newton's method does not converge.
    """
    if problem.gas.restitution.constant is None:
        raise UnsupportedModelError(
            f"the homogeneous cooling state needs a constant restitution coefficient, got "
            f"{problem.gas.restitution!r}: a velocity-dependent law has its own speed scale, "
            "so no scaling state exists (the gas approaches elastic collisions as it cools); "
            "use particles.dsmc.simulate_cooling for the transient")
    m = _cooling_mesh(gather(MeshOptions, mesh, mesh_keywords, "cooling_state"))
    return solve_state(problem, CoolingOptions(
        order=m.order, spacing=m.spacing, cutoff=m.cutoff, vertices=m.vertices,
        intorder=m.intorder, tol=tol, max_iter=max_iter, resolution=resolution,
        sequence=sequence, initial=initial))


@register_solver("fem", problem="cooling")
def solve_fem_cooling(problem: CoolingProblem, *, mesh: MeshOptions | None = None,
                      tol: float = 1e-11, max_iter: int = 100,
                      resolution: float | None = None,
                      initial: CoolingState | VelocityDistribution | None = None,
                      accuracy: float | None = None,
                      **mesh_keywords: Any) -> VelocityDistribution:
    """Homogeneous cooling state by Galerkin FEM and Newton's method.

    Parameters
    ----------
    problem : CoolingProblem
        Constant restitution, any kernel :math:`|g|^\\gamma`.
    mesh : MeshOptions, optional
        The mesh's options below as one object (each may also be passed by keyword, over
        ``mesh``; an unknown keyword raises :class:`TypeError`).
    order : int, optional
        Lagrange degree, 1, 2 or 3; default 3 for hard rods on the default mesh at
        :math:`\\varepsilon \\ge` :data:`HUMP_EPS` (:mod:`.cooling_order`), else 2.
    spacing : float, optional
        Bulk element size (thermal velocities); default :func:`hcs_spacing`.
    cutoff : float, optional
        Half-width of the interval (thermal velocities); default :func:`hcs_cutoff`.
    vertices : array_like, optional
        Explicit symmetric vertices (thermal velocities); overrides the two above.
    intorder : int, optional
        Gauss degree; default ``2 * order + 1``.
    tol : float
        Stop when the Newton update of :math:`\\ln f` (and the relative update of
        :math:`\\zeta`) is below ``tol``, or when it stalls at round-off.
    max_iter : int
        Newton iteration limit.
    resolution : float, optional
        Near elastic collisions (hard rods, :math:`\\varepsilon <` :data:`HUMP_EPS`, no
        ``spacing``, ``cutoff`` or ``vertices``): element size in the humps, in hump
        widths :math:`\\varepsilon^{1/3}`; default :data:`HUMP_RESOLUTION`.  The state
        is then reached by continuation in :math:`\\varepsilon` from :data:`HUMP_EPS`.
    initial : CoolingState or VelocityDistribution, optional
        Warm start for sweeps: the hard-rod state (or the distribution this function
        returned) at a neighbouring restitution coefficient.  Near elastic collisions
        (hard rods, :math:`\\varepsilon <` :data:`HUMP_EPS`, default mesh) the
        continuation starts from it instead of from :data:`HUMP_EPS` (one link for a
        neighbour within a ratio of 16 in :math:`\\varepsilon`); the state is solved on
        the same mesh as without it.  Ignored elsewhere.
    accuracy : float, optional
        Target accuracy of T (relative, one by construction), a2 (absolute) and
        :math:`\\zeta` (relative), in place of a mesh: the state's bulk element size (on
        the near-elastic hump mesh its ``resolution``) is refined at the same degree, at
        most :data:`ACCURACY_REFINEMENTS` times at the observed rate, until the bisected
        mesh estimate (``dist.error``) meets it; ``ConvergenceError`` says what was
        reached.  Not with ``vertices``, nor for the Maxwell kernel (its recovered
        :math:`c^{-4}` tail has no estimate).

    Returns
    -------
    VelocityDistribution
        :math:`f(c)` at unit temperature on the quadrature points;
        ``info.extra["zeta"]`` the cooling rate (:math:`dT/dt = -2\\zeta n
        T^{1+\\gamma/2}`), ``info.extra["zeta_identity"]`` the energy identity
        :math:`\\langle(1-\\alpha^2)|g|^{\\gamma+2}\\rangle/8` by the pair rule.

    Raises
    ------
    UnsupportedModelError
        For a velocity-dependent restitution law.
    ConvergenceError
        If Newton's method does not converge, or ``accuracy`` cannot be met.
    """
    m = _cooling_mesh(gather(MeshOptions, mesh, mesh_keywords, "solve_fem_cooling"))
    if accuracy is not None:
        check_positive("accuracy", accuracy)
        if m.vertices is not None:
            raise ValueError("accuracy= refines the mesh: it cannot be combined with "
                             "explicit vertices; give spacing (or neither)")
        if problem.gas.gamma == 0.0:
            raise ValueError("accuracy= needs the bisected-mesh estimate, which the Maxwell "
                             "model's cooling state (kernel=0, its recovered c^-4 tail) has "
                             "not: compare with kinetic_fem.solvers.maxwell.hcs_pdf")
    state = cooling_state(problem, mesh=m, tol=tol, max_iter=max_iter,
                          resolution=resolution, initial=initial)
    dist = cooling_distribution(problem, state)
    if accuracy is None:
        return dist
    hump = uses_hump_mesh(problem) and m.spacing is None and m.cutoff is None
    if hump:   # the hump mesh: refine its resolution (the regime's default first)
        size = resolution if resolution is not None else (
            HUMP_P3_RESOLUTION if m.order is None and problem.gas.epsilon >= HUMP_P3_EPS
            else HUMP_RESOLUTION)
    else:      # the bulk element size of the mesh solved
        size = float(np.min(np.diff(state.disc.vertices)))
    order = state.disc.order
    history: list[tuple[float, float]] = []
    for refinement in range(ACCURACY_REFINEMENTS + 1):
        est = dist.error
        err = max(est.temperature, est.a2, est.zeta or 0.0)
        history.append((size, err))
        logger.info("accuracy=%g: %s %.4g, P%d, estimated error %.2e", accuracy,
                    "resolution" if hump else "spacing", size, order, err)
        if err <= accuracy:
            return dist
        stalled = len(history) > 1 and err > 0.5 * history[-2][1]
        if refinement == ACCURACY_REFINEMENTS or stalled or not math.isfinite(err):
            break
        size *= refinement_factor(history, accuracy, order)
        state = cooling_state(problem, mesh=replace(m, order=order,
                                                    spacing=None if hump else size),
                              tol=tol, max_iter=max_iter,
                              resolution=size if hump else None)
        dist = cooling_distribution(problem, state)
    raise ConvergenceError(
        f"FEM did not reach accuracy={accuracy:g} (T, a2 and zeta) for the cooling state: "
        "estimated errors " + ", ".join(
            f"{e:.2g} at {'resolution' if hump else 'spacing'} {h:.3g}" for h, e in history)
        + f" (P{order}); "
        + ("the estimate stopped decreasing (round-off or the cut-off); "
           if len(history) > 1 and history[-1][1] > 0.5 * history[-2][1] else "")
        + "ask for less, or give a smaller spacing")


def cooling_distribution(problem: CoolingProblem, state: CoolingState) -> VelocityDistribution:
    """The result of :func:`solve_fem_cooling` for a converged state.

    Parameters
    ----------
    problem : CoolingProblem
        The problem solved.
    state : CoolingState
        Its state.

    Returns
    -------
    VelocityDistribution
        As returned by :func:`solve_fem_cooling`.
    """
    info = replace(state.info, extra={"zeta": float(state.zeta),
                                      "zeta_identity": float(state.energy_identity()),
                                      "n_dofs": int(state.u.size), "order": state.disc.order,
                                      "cutoff": float(state.disc.vertices[-1])})
    if isinstance(state, MaxwellTailState):
        dist = state.distribution(method="fem", params=problem.as_dict(), info=info)
        return dist.with_error(maxwell_tail_recipe(state))
    # the result of a state and its error estimate (kinetic_fem.solvers.fem.error)
    def plain(disc: FEMDiscretisation, u: NDArray, **kw: object) -> VelocityDistribution:
        return disc.distribution(u, **kw)

    build: Callable[..., VelocityDistribution] = plain
    if problem.gas.gamma == 0.0:
        # --- the Maxwell model's c^-4 tail: kinetic_fem.solvers.fem.cooling_tail ---
        build = recovered_distribution
    dist = build(state.disc, state.u, method="fem", params=problem.as_dict(), info=info)
    return dist.with_error(cooling_recipe(state.disc, state.u, state.zeta, build))
