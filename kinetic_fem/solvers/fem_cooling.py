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

Discretisation: P2 (P1; P3 for hard rods, :mod:`.fem_cooling_order`) Lagrange elements
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
scaled states (:mod:`kinetic_fem.solvers.fem_cooling_gamma2`).

Near elastic collisions (hard rods, :math:`\\varepsilon = 1 - \\alpha <` :data:`HUMP_EPS`)
the state is two humps of width :math:`w = \\varepsilon^{1/3}` at :math:`c = \\pm 1`.
While they are broad (:math:`\\varepsilon \\ge` 0.035, :mod:`.fem_cooling_band`) the default
is P3 on a mesh graded along the tail, from one link from 0.1; below, and with ``resolution``, it is
reached by continuation in :math:`\\varepsilon` (:mod:`.fem_cooling_links`,
:mod:`.fem_cooling_hump`: toward :math:`\\varepsilon \\ge 10^{-3}` by one link on a coarse
mesh cut off at 30 decades from the nearest stored start at or above it, eps = 0.04,
0.01 or 0.0025, :mod:`.fem_cooling_seeds`; below from 0.0025 in
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
:data:`~kinetic_fem.solvers.fem_cooling_mesh.HUMP_INTORDER` (the 3-point rule's error on
:math:`e^{u_h}` over the exponential edge gave the old ln f error and growing modes at the
cut-off), the normalisation replaces the equation at the peak.  The continuation converges down to
:math:`\\varepsilon = 10^{-6}` (``benchmarks/results/fem_cooling.md``); below
:data:`HUMP_FRONTIER` a failure says so and names the leading-order :math:`\\psi` state.

The inelastic Maxwell model (:math:`\\gamma = 0`) has the closed-form state
:math:`f(c) = 2/(\\pi(1+c^2)^2)` for every alpha (Baldassarri, Marini Bettolo Marconi,
Puglisi, Europhys. Lett. 58, 14 (2002)), :math:`\\zeta = (1-\\alpha^2)/4`; by default the
mesh ends at :math:`c = 200` and its :math:`c^{-4}` tail (infinite fourth moment) is
continued analytically beyond (:mod:`kinetic_fem.solvers.fem_cooling_maxwell`); with
``cutoff`` (or ``vertices``) it is resolved on a geometric mesh out to, e.g.,
:math:`V = 10^8`; the result carries :math:`f` recovered from the superconvergent points
of :math:`\\ln f_h` (:mod:`kinetic_fem.solvers.fem_cooling_tail`).

A velocity-dependent restitution law has no homogeneous cooling state (the law has its
own speed scale, so the state changes as the gas cools); such problems are refused.
"""

from __future__ import annotations

import functools
import logging
import math
from collections.abc import Callable
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from ..distribution import VelocityDistribution
from ..model import CoolingProblem, UnsupportedModelError, check_positive
from ..operators.fem_discretisation import LAGRANGE_ELEMENTS
from ..solve import register_solver
from .fem import ConvergenceError, FEMDiscretisation
from .fem_cooling_alpha import (
    ALPHA_CHAIN_COARSE,
    DIRECT_EPS,
    alpha_chain,
    quasi_seed_vertices,
    uses_alpha_chain,
)
from .fem_cooling_band import band_state, in_band
from .fem_cooling_gamma2 import anchored_state, uses_anchors
from .fem_cooling_hump import (
    HUMP_COARSE_EPS,
    HUMP_LINK_RESOLUTION,
    HUMP_P3_EPS,
    HUMP_P3_RESOLUTION,
    HUMP_RESOLUTION,
    HUMP_STEP_RESOLUTION,
    continued_state,
)
from .fem_cooling_links import (
    HUMP_EPS,
    HUMP_FRONTIER,
    HUMP_MIN_RATIO,
    HUMP_RATIO,
    HUMP_STEP_ITER,
    HUMP_STEP_TOL,
    chain_state,
    hump_chain,
    start_state,
)
from .fem_cooling_maxwell import MaxwellTailState, maxwell_cooling_state
from .fem_cooling_mesh import (
    HUMP_INTORDER,
    MAXWELL_CUTOFF,
    hcs_bulk,
    hcs_cutoff,
    hcs_spacing,
    hcs_vertices,
    initial_log_f,
)
from .fem_cooling_newton import CLOSE_DAMPING, CoolingState, newton_cooling
from .fem_cooling_order import (
    COARSE_FACTOR,
    COARSE_ORDER,
    COARSE_SPACING,
    COARSE_TOL,
    P3_COARSE_SPACING,
    STRONG_ALPHA,
    STRONG_STEP,
    cooling_order,
    order_spacing,
)
from .fem_cooling_seeds import seed_start
from .fem_cooling_tail import maxwell_hcs, recovered_distribution
from .fem_error import cooling_recipe

__all__ = ["solve_fem_cooling", "cooling_state", "CoolingState", "continued_state",
           "hump_chain", "hump_start", "uses_hump_mesh", "HUMP_EPS", "HUMP_RESOLUTION",
           "HUMP_FRONTIER", "hcs_cutoff", "hcs_spacing", "hcs_vertices", "maxwell_hcs",
           "initial_log_f", "newton_cooling", "MAXWELL_CUTOFF", "HUMP_STEP_RESOLUTION",
           "HUMP_LINK_RESOLUTION", "HUMP_INTORDER", "HUMP_P3_EPS", "HUMP_P3_RESOLUTION",
           "link_start", "cooling_distribution", "HUMP_RATIO", "HUMP_STEP_TOL",
           "HUMP_STEP_ITER", "HUMP_MIN_RATIO"]

logger = logging.getLogger(__name__)

def _discretisation(problem: CoolingProblem, vertices: NDArray, order: int,
                    intorder: int | None) -> FEMDiscretisation:
    return FEMDiscretisation(problem.gas.alpha, vertices, order, intorder or 2 * order + 1,
                             gamma=problem.gas.gamma)


def uses_hump_mesh(problem: CoolingProblem) -> bool:
    """Hard rods below :data:`HUMP_EPS`: the default mesh follows the humps.

    Parameters
    ----------
    problem : CoolingProblem
        The cooling problem (kernel and restitution of its gas are read).

    Returns
    -------
    bool
        True for hard rods with :math:`\\varepsilon = 1 - \\alpha <` :data:`HUMP_EPS`.
    """
    return problem.gas.gamma == 1.0 and problem.gas.epsilon < HUMP_EPS * (1.0 - 1e-12)


@functools.lru_cache(maxsize=4)
def hump_start(order: int, intorder: int | None) -> CoolingState:
    """The state at :data:`HUMP_EPS` from the Gaussian start (cached: it starts every chain).

    Parameters
    ----------
    order : int
        Lagrange degree.
    intorder : int or None
        Gauss degree (None: ``2 * order + 1``).

    Returns
    -------
    CoolingState
    """
    problem = CoolingProblem.from_parameters(1.0 - HUMP_EPS)
    return cooling_state(problem, order=order, intorder=intorder, tol=1e-9, spacing=0.1,
                         cutoff=12.0)


LINK_START_SPACING, LINK_START_CUTOFF = 0.3, 9.0
"""Mesh of the state at :data:`HUMP_EPS` that starts the links toward eps >=
:data:`~kinetic_fem.solvers.fem_cooling_hump.HUMP_COARSE_EPS` (one solve, tolerance
:data:`HUMP_STEP_TOL`, no mesh sequencing; ln f = -77 at c = 9): the links' coarse meshes
do not need :func:`hump_start`'s (spacing 0.1 after 0.2, cut-off 12).  0.05 to 0.09 CPU s
less per state at eps = 1e-3 ... 0.03, the final states equal to 1.3e-14
(benchmarks/results/fem_cooling_speed.md)."""


def link_start(order: int, intorder: int | None) -> CoolingState:
    """The state at :data:`HUMP_EPS` on the coarse mesh that starts the fast links (not cached).

    Parameters
    ----------
    order : int
        Lagrange degree.
    intorder : int or None
        Gauss degree (None: ``2 * order + 1``).

    Returns
    -------
    CoolingState
    """
    problem = CoolingProblem.from_parameters(1.0 - HUMP_EPS)
    return cooling_state(problem, order=order, intorder=intorder, tol=HUMP_STEP_TOL,
                         spacing=LINK_START_SPACING, cutoff=LINK_START_CUTOFF, sequence=False)


def _hump_state(problem: CoolingProblem, initial, **options) -> CoolingState:
    """Continuation in eps from ``initial`` (a warm start), else from the stored start
    (:mod:`.fem_cooling_seeds`) nearest at or above eps (below HUMP_COARSE_EPS the
    smallest, then the chain of :func:`hump_chain`: eps 9e-4, 5e-4, 1e-4 in 0.45, 0.59,
    1.48 CPU s instead of 1.28, 1.45, 2.39 from :func:`hump_start` at 0.1, the same states
    to 2e-14 in zeta, 1.2e-13 in a2):
    :func:`~kinetic_fem.solvers.fem_cooling_links.chain_state`."""
    if initial is not None:
        start, eps_start = start_state(initial)
    else:  # a stored start (issue 16)
        start, eps_start = seed_start(max(problem.gas.epsilon, HUMP_COARSE_EPS))
    return chain_state(problem.gas.alpha, start, eps_start, **options)


def cooling_state(problem: CoolingProblem, *, order: int | None = None,
                  spacing: float | None = None, cutoff: float | None = None, vertices=None,
                  intorder: int | None = None,
                  tol: float = 1e-11, max_iter: int = 100,
                  resolution: float | None = None, sequence: bool = True,
                  initial: CoolingState | VelocityDistribution | None = None) -> CoolingState:
    """The HCS by Newton's method (see :func:`solve_fem_cooling` for the options).

    ``sequence``: on a mesh built from ``spacing`` (not explicit ``vertices``), start
    from the state on a mesh :data:`COARSE_FACTOR` times coarser, at most
    :data:`COARSE_SPACING` (mesh sequencing).

    Parameters
    ----------
    problem : CoolingProblem
        Constant restitution, any kernel.
    order, spacing, cutoff, vertices, intorder, tol, max_iter, resolution
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
    if problem.gas.gamma == 0.0 and vertices is None and cutoff is None and resolution is None:
        # the Maxwell model: short mesh, analytic c^-4 tail (.fem_cooling_maxwell)
        return maxwell_cooling_state(problem.gas.alpha, order=order, spacing=spacing,
                                     intorder=intorder, tol=tol, max_iter=max_iter)
    default_mesh = vertices is None and spacing is None and cutoff is None
    if default_mesh and resolution is None and uses_anchors(problem):
        # gamma 2: one Newton solve from the stored scaled states (.fem_cooling_gamma2)
        state = anchored_state(problem, order=cooling_order(problem, order, default_mesh=True),
                               intorder=intorder, tol=tol, max_iter=max_iter)
        if state is not None:
            return state
    if uses_alpha_chain(problem) and default_mesh and problem.gas.epsilon < DIRECT_EPS:
        # hard kernels near elastic: straight to the chain on the meshes that follow the
        # humps (.fem_cooling_alpha; the target's default mesh cannot hold the state)
        vertices = quasi_seed_vertices(problem.gas.gamma,
                                       cooling_order(problem, order, default_mesh=False))
    hump = uses_hump_mesh(problem) and default_mesh
    default = order is None and resolution is None
    band = hump and default and in_band(problem.gas.epsilon, HUMP_EPS)
    order = cooling_order(problem, order, default_mesh=not hump and spacing is None
                          and vertices is None)
    if order not in LAGRANGE_ELEMENTS or (hump and order == 3):
        raise ValueError(f"order must be one of {sorted(LAGRANGE_ELEMENTS)} (1 or 2 on the "
                         f"near-elastic hump mesh, whose default is P3 at eps >= "
                         f"{HUMP_P3_EPS:g}: omit order), got {order!r}")
    if resolution is not None:
        resolution = check_positive("resolution", resolution)
    if band:  # the broad humps of eps in [BAND_EPS, 0.1): P3 on band_vertices
        start, eps_start = (start_state(initial) if initial is not None
                            else (link_start(2, None), HUMP_EPS))
        state = band_state(problem, start, eps_start, tol=tol,
                           max_iter=max_iter, intorder=intorder)
        if state is not None:
            return state
    if hump:
        p3 = default and problem.gas.epsilon >= HUMP_P3_EPS * (1.0 - 1e-9)
        return _hump_state(problem, initial, order=order, intorder=intorder, tol=tol,
                           max_iter=max_iter, final_order=3 if p3 else order,
                           resolution=HUMP_P3_RESOLUTION if p3 else resolution or
                           HUMP_RESOLUTION)
    if resolution is not None:
        raise ValueError(f"resolution is the element size of the near-elastic hump mesh "
                         f"(hard rods, eps < {HUMP_EPS}, no spacing/cutoff/vertices), not "
                         f"used at eps = {problem.gas.epsilon:g}, gamma = {problem.gas.gamma:g};"
                         " pass spacing instead")
    spacing = order_spacing(hcs_spacing(problem), order) if spacing is None else \
        check_positive("spacing", spacing)
    if vertices is None:
        c_max = hcs_cutoff(problem) if cutoff is None else check_positive("cutoff", cutoff)
        verts = hcs_vertices(c_max, spacing, gamma=problem.gas.gamma,
                             bulk=hcs_bulk(problem.gas.epsilon))
    else:
        verts = np.sort(np.asarray(vertices, dtype=float))
        if not np.allclose(verts, -verts[::-1], rtol=0, atol=1e-12 * np.abs(verts).max()) \
                or not np.any(verts == 0.0):
            raise ValueError("vertices must be symmetric about 0 and include c = 0")
    disc = _discretisation(problem, verts, order, intorder)
    if problem.gas.gamma == 0.0:
        # the Maxwell model: Newton from the closed-form state (module notes) converges in
        # four or five steps; the Gaussian start's globalised iteration failed on the
        # coarse mesh at alpha = 0.99 and took 188 s on the fine one
        state = newton_cooling(disc, np.log(maxwell_hcs(disc.dof_locations)),
                               0.25 * (1.0 - problem.gas.alpha**2), tol=tol,
                               max_iter=max_iter, pseudo_time=np.inf)
        if state.info.converged:
            return state
        logger.info("HCS Maxwell model: Newton from the closed form failed (%s); globalised "
                    "iteration", state.info.message)
    cap = P3_COARSE_SPACING if order == 3 else COARSE_SPACING
    if sequence and vertices is None and spacing < cap:
        coarse = cooling_state(problem, order=min(order, COARSE_ORDER),
                               spacing=min((ALPHA_CHAIN_COARSE if uses_alpha_chain(problem)
                                            else COARSE_FACTOR) * spacing, cap),
                               cutoff=c_max, intorder=intorder, tol=COARSE_TOL,
                               max_iter=max_iter, sequence=False)
        state = newton_cooling(disc, coarse.log_f(disc.dof_locations), coarse.zeta, tol=tol,
                               max_iter=max_iter, pseudo_time=np.inf, min_damping=CLOSE_DAMPING)
        if state.info.converged:
            return state
        logger.info("HCS mesh sequencing: Newton from the coarse state failed (%s); "
                    "globalised iteration on the fine mesh", state.info.message)
    if uses_alpha_chain(problem):  # bimodal at moderate eps: continuation from alpha 0.5
        base = cooling_state(CoolingProblem.from_parameters(STRONG_ALPHA,
                                                            kernel=problem.gas.kernel),
                             order=order, vertices=verts, intorder=intorder, tol=COARSE_TOL,
                             max_iter=max_iter)
        state = alpha_chain(disc, base, STRONG_ALPHA, tol=tol, max_iter=min(max_iter, 40))
        if not state.info.converged:
            raise ConvergenceError(
                f"FEM cooling continuation in alpha from {STRONG_ALPHA} did not converge at "
                f"alpha={state.disc.alpha:.6g} on the way to {problem.gas.alpha} "
                f"({state.info.message}); refine the mesh (smaller spacing)")
        return state
    zeta0 = problem.zeta_estimate()
    u0 = initial_log_f(disc.dof_locations, problem.gas.gamma, zeta0)
    if problem.gas.alpha < STRONG_ALPHA and problem.gas.gamma > 0.0:
        n_steps = math.ceil((STRONG_ALPHA - problem.gas.alpha) / STRONG_STEP - 1e-9)
        alpha_prev = problem.gas.alpha + (STRONG_ALPHA - problem.gas.alpha) / n_steps
        coarse_problem = CoolingProblem.from_parameters(alpha_prev, kernel=problem.gas.kernel)
        coarse = cooling_state(coarse_problem, order=order, tol=1e-7, max_iter=max_iter,
                               spacing=2.0 * spacing if sequence else spacing,
                               sequence=False)
        u0 = coarse.log_f(disc.dof_locations)
        zeta0 = coarse.zeta * (1.0 - problem.gas.alpha**2) / (1.0 - alpha_prev**2)
    state = newton_cooling(disc, u0, zeta0, tol=tol, max_iter=max_iter)
    if not state.info.converged:
        raise ConvergenceError(
            f"FEM cooling Newton did not converge in {max_iter} iterations at alpha="
            f"{problem.gas.alpha} ({state.info.message}); refine the mesh (smaller spacing) "
            "or increase max_iter")
    return state


@register_solver("fem", problem="cooling")
def solve_fem_cooling(problem: CoolingProblem, *, order: int | None = None,
                      spacing: float | None = None, cutoff: float | None = None,
                      vertices=None, intorder: int | None = None, tol: float = 1e-11,
                      max_iter: int = 100, resolution: float | None = None,
                      initial: CoolingState | VelocityDistribution | None = None
                      ) -> VelocityDistribution:
    """Homogeneous cooling state by Galerkin FEM and Newton's method.

    Parameters
    ----------
    problem : CoolingProblem
        Constant restitution, any kernel :math:`|g|^\\gamma`.
    order : int, optional
        Lagrange degree, 1, 2 or 3; default 3 for hard rods on the default mesh at
        :math:`\\varepsilon \\ge` :data:`HUMP_EPS` (:mod:`.fem_cooling_order`), else 2.
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
        If Newton's method does not converge.
    """
    state = cooling_state(problem, order=order, spacing=spacing, cutoff=cutoff,
                          vertices=vertices, intorder=intorder, tol=tol, max_iter=max_iter,
                          resolution=resolution, initial=initial)
    return cooling_distribution(problem, state)


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
        return state.distribution(method="fem", params=problem.as_dict(), info=info)
    # the result of a state and its error estimate (kinetic_fem.solvers.fem_error)
    def plain(disc: FEMDiscretisation, u: NDArray, **kw: object) -> VelocityDistribution:
        return disc.distribution(u, **kw)

    build: Callable[..., VelocityDistribution] = plain
    if problem.gas.gamma == 0.0:
        # --- the Maxwell model's c^-4 tail: kinetic_fem.solvers.fem_cooling_tail ---
        build = recovered_distribution
    dist = build(state.disc, state.u, method="fem", params=problem.as_dict(), info=info)
    return dist.with_error(cooling_recipe(state.disc, state.u, state.zeta, build))
