"""Galerkin finite elements (scikit-fem) for the randomly heated inelastic gas.

Every model of :mod:`kinetic_fem.model`: kernels :math:`|g|^\\gamma`, restitution laws
(evaluated in the pair rule, :mod:`kinetic_fem.operators.fem_kernels`), white noise and the
Fokker-Planck bath, whose drift :math:`\\partial_v(\\xi v P)` enters as the form
:func:`bath_drift`.  Below, the paper's model (hard rods, white noise).

The homogeneous Boltzmann equation with white-noise heating,

.. math::

    \\partial_t P = D\\,\\partial_v^2 P + Q[P, P],

is discretised in weak form on a symmetric velocity interval :math:`[-V, V]` with
P1, P2 or P3 Lagrange elements (P3 on the default mesh of most constant-alpha models, see
:func:`~kinetic_fem.solvers.fem.defaults.default_order`).  The
unknown is the logarithm :math:`u_h = \\ln P_h` in the Lagrange space,
:math:`P_h = e^{u_h} > 0`, and the test functions are the Lagrange basis
:math:`\\varphi_i`, so that for every :math:`i`

.. math::

    \\frac{d}{dt}\\int \\varphi_i P_h = -D\\int \\varphi_i' P_h' + C_i[P_h],

with the collision term :math:`C_i` from the weak form (see
:mod:`kinetic_fem.operators.fem_kernels`) and zero flux at :math:`\\pm V`.  Because
:math:`\\sum_i \\varphi_i \\equiv 1` and :math:`\\sum_i v_i \\varphi_i \\equiv v`, the
discrete operator with the full bracket (``symmetric=True``) conserves mass and
momentum to round-off; with P2 also :math:`\\sum_i v_i^2 \\varphi_i \\equiv v^2`, so
the discrete energy balance (claim C1) holds with the solver's own pair quadrature.
The default reduced bracket keeps mass exact (momentum exact for even
:math:`P_h`, C1 to the quadrature error) and converges cleanly as
:math:`\\alpha \\to 1`.  The logarithmic unknown keeps :math:`P_h` positive and its
tail accurate relative to itself over 30 decades.

The steady state is found by Newton's method on :math:`u_h` restricted to even
functions, with one equation replaced by the normalisation
:math:`\\int P_h = 1`, started from a Gaussian bulk at the first-order Sonine
temperature with the model's WKB tail
(:func:`~kinetic_fem.solvers.fem.defaults.initial_log_density`), first on a nested
3 times coarser mesh (:func:`~kinetic_fem.solvers.fem.state.nested_coarse`: mesh
sequencing; the widening of the interval happens there too), then on the fine mesh
from the coarse state.  For the even state the collision sums visit only the outer
points at :math:`v > 0` and mirror them (half the cost), and near convergence the
factorisation is reused (chord steps, :mod:`kinetic_fem.solvers.fem.newton` on the
shared driver :mod:`kinetic_fem.solvers.newton`); curves over alpha warm start
(:mod:`kinetic_fem.solvers.fem.curve`).  Transients (BDF2):
:func:`kinetic_fem.solvers.fem.transient.evolve_heated`.
Everything is computed at :math:`n = D = 1`; other :math:`n, D` follow from the
exact rescaling :math:`v \\to v (D/n)^{1/3}`.
"""

from __future__ import annotations

import logging
import math
import warnings
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ... import sonine
from ...distribution import VelocityDistribution
from ...exceptions import ConvergenceError, ResolutionWarning
from ...gas import HeatedProblem, check_positive
from ...operators.fem_discretisation import (
    ELEMENTS,
    LAGRANGE_ELEMENTS,
    FEMDiscretisation,
    bath_drift,
    bath_drift_jacobian,
    fokker_planck,
    fokker_planck_jacobian,
    mass,
    weighted_mass,
)
from ...operators.grid import symmetric_grid, uniform_grid
from ...options import gather
from ...solve import register_solver
from .defaults import (
    ScaledModel,
    default_cutoff,
    default_order,
    default_spacing,
    graded_vertices,
    initial_log_density,
    model_cutoff,
    model_spacing,
    scaled_model,
    tail_exponent,
)
from .error import heated_estimate, heated_recipe
from .newton import (
    CHORD_LEVEL,
    CHORD_RATE,
    STALL_LEVEL,
    EquilibratedLU,
    log_update,
    newton_info,
    newton_steady,
    stalled,
)
from .options import MeshOptions
from .state import (
    SEQUENCE_BAND,
    LazyExtra,
    SteadyState,
    check_energy_input,
    nested_coarse,
    state_temperature,
)

__all__ = ["FEMDiscretisation", "SteadyState", "ResolutionWarning", "ConvergenceError",
           "default_cutoff", "default_spacing", "steady_state", "solve_fem_heated", "ELEMENTS",
           "refinement_factor", "ACCURACY_REFINEMENTS",
           "newton_steady", "discretisation", "state_distribution", "STALL_LEVEL",
           "CHORD_LEVEL", "CHORD_RATE", "EquilibratedLU", "log_update",
           "newton_info", "stalled", "bath_drift", "bath_drift_jacobian", "mass", "weighted_mass",
           "fokker_planck", "fokker_planck_jacobian", "nested_coarse", "SEQUENCE_BAND"]

logger = logging.getLogger(__name__)


TAIL_FLOOR = 1e-30
"""f(c) must be resolved down to this value (30 decades)."""
CUTOFF_TARGET = 1e-33
"""With the default cut-off the interval is widened until f(cut-off) is below this."""
MAX_WIDENINGS = 4
ACCURACY_REFINEMENTS = 4
"""Most refinements of the spacing with ``accuracy=`` (:func:`solve_fem_heated`)."""
CONTINUATION_ALPHA = 0.95
"""Above this alpha Newton starts from the solution at ten times the inelasticity."""
SEQUENCE_FACTOR = 3
"""Mesh sequencing: the first solve is on a mesh this much coarser (or 2 where that
would exceed :data:`SEQUENCE_MAX_SPACING`)."""
SEQUENCE_FACTOR_P3 = 2
"""The same for P3: its coarse error is ``factor**4`` times the fine one, ``2**4 = 16``
(``3**3 = 27`` for P2 at :data:`SEQUENCE_FACTOR`), so the fine Newton starts within about
1e-2 in ln P and ends after one Jacobian and one or two chord steps (measured over 12
alphas in [0, 0.99]: the Maxwell model 1.22x, the saturating kernel 1.13x, hard rods in a
bath 1.12x, gamma = 0.5 1.04x against 3; P2 for gamma = 2 at 2: 0.91x).  Not for the
paper's model, whose P3 spacing admits 3 only above alpha = 0.95, where the coarse solve
starts from the continuation guess (5-6 Jacobians; 2 costs 0.6 fine Jacobians more)."""
SEQUENCE_MAX_SPACING = 0.3
"""No sequencing when the coarse spacing would exceed this (thermal velocities) times
half the element degree."""
SEQUENCE_CHORD_LEVEL = 1e-2
"""Chord steps on the fine mesh start below this update (its start is the coarse state;
measured: chord from 2e-3 saves one Jacobian at alpha = 0.9)."""
SEQUENCE_TOL = 1e-2
"""Newton tolerance on the coarse mesh: its state only starts the fine one, which differs
from it by 2e-4 to 0.3 in ln P, and after an update below 1e-2 the coarse error is about
1e-5 or less (quadratic convergence).  Measured (12 alphas in [0, 0.99], gamma 0, 0.5, 1,
2 and the bath): against 1e-6 one coarse Jacobian less at most alphas, 1.06-1.14x per
state, T and a2 equal to 8e-15."""


# ---------------------------------------------------------------- weak forms (n = D = 1)
def _checked_grading(grading: float | None) -> float | None:
    if grading is not None and not (isinstance(grading, (int, float)) and
                                    not isinstance(grading, bool) and
                                    math.isfinite(grading) and grading >= 0.0):
        raise ValueError(f"grading must be a finite number >= 0 (0: a uniform mesh), got "
                         f"{grading!r}")
    return grading


def _mesh(alpha: float, *, cutoff: float | None, spacing: float, vertices,
          model: ScaledModel | None = None, grading: float | None = None) -> NDArray:
    """Mesh vertices at ``n = D = 1``: explicit, or uniform (the paper's model) or graded
    (:func:`kinetic_fem.solvers.fem.defaults.graded_vertices`) in thermal velocities;
    ``grading`` (given) replaces the model's."""
    if vertices is not None:
        verts = np.sort(np.asarray(vertices, dtype=float))
        if not np.allclose(verts, -verts[::-1], rtol=0, atol=1e-12 * np.abs(verts).max()):
            raise ValueError("vertices must be symmetric about 0")
        if not np.any(verts == 0.0):
            raise ValueError("vertices must include v = 0")
        return verts
    check_positive("spacing", spacing)
    if model is None or model.is_paper_model:
        c_max = default_cutoff(alpha) if cutoff is None else check_positive("cutoff", cutoff)
    else:
        c_max = model_cutoff(model) if cutoff is None else check_positive("cutoff", cutoff)
    if spacing > 0.5:
        warnings.warn(f"spacing={spacing} thermal velocities is too coarse to resolve the "
                      "distribution; use spacing <= 0.25", ResolutionWarning, stacklevel=3)
    if model is None or model.is_paper_model:
        scale = math.sqrt(sonine.steady_temperature(alpha))
        if grading is not None:
            return scale * graded_vertices(c_max, spacing, grading=grading)
        half = max(2, int(math.ceil(c_max / spacing)))
        return symmetric_grid(uniform_grid(c_max * scale, half + 1))
    if grading is None:
        grading = (3.0 - tail_exponent(model)) / 3.0
    return math.sqrt(model.temperature) * graded_vertices(c_max, spacing, grading=grading)




def discretisation(model: ScaledModel, vertices: NDArray, order: int = 2,
                   intorder: int | None = None, symmetric: bool = False) -> FEMDiscretisation:
    """The :class:`FEMDiscretisation` of a scaled model on ``vertices``.

    Parameters
    ----------
    model : ScaledModel
        The heated model at ``n = D = 1`` (:func:`kinetic_fem.solvers.fem.defaults.scaled_model`).
    vertices : ndarray
        Increasing mesh vertices (velocities).
    order : int
        Lagrange degree, 1 or 2.
    intorder : int, optional
        Gauss degree (default ``2 * order + 1``).
    symmetric : bool
        Impose even symmetry through the mesh's mirror map.

    Returns
    -------
    FEMDiscretisation
    """
    law = None if model.law.constant is not None else model.law
    return FEMDiscretisation(model.alpha, vertices, order, intorder or 2 * order + 1, symmetric,
                             gamma=model.kernel, law=law, friction=model.friction,
                             speed_scale=model.speed_scale)


def steady_state(model: float | HeatedProblem, *, mesh: MeshOptions | None = None,
                 symmetric: bool = False, tol: float = 1e-11, max_iter: int = 40,
                 initial: SteadyState | Callable[[NDArray], NDArray] | None = None,
                 **mesh_keywords: Any) -> SteadyState:
    """Newton steady state at ``n = D = 1`` (see :func:`solve_fem_heated` for the options).

    ``model`` is a heated problem (solved at ``n = D = 1``, see
    :func:`kinetic_fem.solvers.fem.defaults.scaled_model`) or a restitution coefficient of
    the paper's model (hard rods, white noise).  With the default cut-off, the
    interval is widened (by 15 %, from the current solution) until :math:`f` at the
    cut-off is below :data:`CUTOFF_TARGET`.  ``initial`` (a state of a nearby model,
    e.g. the previous point of a curve, or a prediction ``v -> ln P(v)``) gives the
    starting :math:`f(c)` in place of the Gaussian and of the near-elastic continuation
    (see :mod:`kinetic_fem.solvers.fem.curve`).

    Parameters
    ----------
    model : float or HeatedProblem
        The problem, or a restitution coefficient of the paper's model.
    mesh, symmetric, tol, max_iter, **mesh_keywords
        As in :func:`solve_fem_heated`.
    initial : SteadyState or callable, optional
        A state of a nearby model to start from, or ``v -> ln P(v)`` (``n = D = 1``).

    Returns
    -------
    SteadyState

    Raises
    ------
    ConvergenceError
        If Newton's method does not converge.
    """
    m = gather(MeshOptions, mesh, mesh_keywords, "steady_state")
    problem = model if isinstance(model, HeatedProblem) else \
        HeatedProblem.from_parameters(model)
    return _steady_state(problem, scaled_model(problem), order=m.order, spacing=m.spacing,
                         cutoff=m.cutoff, vertices=m.vertices, intorder=m.intorder,
                         symmetric=symmetric, tol=tol, max_iter=max_iter, initial=initial,
                         grading=_checked_grading(m.grading))


def _steady_state(problem: HeatedProblem, scaled: ScaledModel, *, order: int | None,
                  spacing: float | None, cutoff: float | None, vertices, intorder: int | None,
                  symmetric: bool, tol: float, max_iter: int,
                  initial: SteadyState | Callable[[NDArray], NDArray] | None,
                  grading: float | None = None) -> SteadyState:
    """:func:`steady_state` of ``problem`` with its scaled model (computed once: for other
    kernels than power laws the temperature estimate costs a few ms)."""
    paper = scaled.is_paper_model
    alpha = scaled.alpha
    # with a bath the elastic limit is a Gaussian (no quasi-elastic structure)
    alpha_eff = 1.0 - scaled.effective_epsilon if scaled.friction == 0.0 else 0.0
    if order is None:  # P3 on the default mesh; an explicit mesh keeps its P2 meaning
        order = default_order(scaled) if spacing is None and vertices is None else 2
        if order == 3 and not paper:
            # P3 for the other kernels (default_order); should Newton fail, the P2 default
            try:
                return _steady_state(problem, scaled, order=3, spacing=None,
                                     cutoff=cutoff, vertices=None, intorder=intorder,
                                     symmetric=symmetric, tol=tol, max_iter=max_iter,
                                     initial=initial, grading=grading)
            except ConvergenceError as err:
                logger.info("P3 default failed at alpha=%g (%s); P2", alpha, err)
                order = 2
    if order not in LAGRANGE_ELEMENTS:
        raise ValueError(f"order must be one of {sorted(LAGRANGE_ELEMENTS)}, got {order!r}")
    default = default_spacing(alpha, order) if paper else model_spacing(scaled, order)
    spacing = default if spacing is None else check_positive("spacing", spacing)
    if alpha_eff > CONTINUATION_ALPHA and spacing > 0.3 and vertices is None:
        raise ValueError(f"spacing={spacing} thermal velocities is too coarse for alpha="
                         f"{alpha_eff:.6g} (Newton's method does not converge there); use "
                         f"spacing <= 0.3, production accuracy: default spacing {default:.3g}")
    if cutoff is None:
        c_max = default_cutoff(alpha) if paper else model_cutoff(scaled)
    else:
        c_max = cutoff
    # Gaussian bulk, WKB tail: from the plain Gaussian (far too low in the tail of hard
    # rods) Newton needs one more Jacobian (measured at alpha = 0, 0.3, 0.6)
    def default_start(v: NDArray) -> NDArray:
        return initial_log_density(v, scaled)

    start: Callable[[NDArray], NDArray] = default_start
    if isinstance(initial, SteadyState):
        def start(v: NDArray) -> NDArray:
            return initial.initial_guess(v, scaled.temperature, linear_tail=not paper)
    elif initial is not None:
        start = initial
    elif alpha_eff > CONTINUATION_ALPHA and vertices is None and \
            scaled.law.constant is not None and scaled.continues_near_elastic:
        # start from the solution at eps' = 10 eps, rescaled to f(c) (quasi-elastic
        # limits are approached smoothly in c; Newton from a Gaussian is not robust there)
        coarse_problem = HeatedProblem.from_parameters(
            max(1.0 - 10.0 * (1.0 - alpha), CONTINUATION_ALPHA - 0.05),
            friction=scaled.friction, kernel=scaled.kernel)
        # (P2 at 0.2 also for P3: P3 at 0.3 fails at alpha = 0.99 and for gamma = 2)
        guess = steady_state(coarse_problem, order=min(order, 2), spacing=0.2,
                             symmetric=symmetric, tol=1e-6, max_iter=max_iter)

        def start(v: NDArray) -> NDArray:
            return guess.initial_guess(v, scaled.temperature, linear_tail=not paper)
    first = SEQUENCE_FACTOR_P3 if order == 3 and not paper else SEQUENCE_FACTOR
    coarsen = next((f for f in (first, 2) if f * spacing <= SEQUENCE_MAX_SPACING
                    * order / 2), 0)
    if vertices is None and coarsen:
        # mesh sequencing: the globalised iteration and the widening of the interval on
        # a 3x coarser nested mesh, then Newton from its f on the fine one (one Jacobian
        # and chord steps); any failure falls back to the fine mesh from the default start
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ResolutionWarning)
                coarse, c_seq = _widened_solve(
                    alpha, scaled, paper, order, intorder, symmetric, spacing, c_max, start,
                    fixed=cutoff is not None, tol=SEQUENCE_TOL, max_iter=max_iter,
                    coarsen=coarsen, grading=grading)

            def refined(v: NDArray) -> NDArray:
                return coarse.log_density(v)

            return _widened_solve(alpha, scaled, paper, order, intorder, symmetric, spacing,
                                  c_seq, refined, fixed=cutoff is not None, tol=tol,
                                  max_iter=max_iter, chord_level=SEQUENCE_CHORD_LEVEL,
                                  grading=grading)[0]
        except ConvergenceError as err:
            logger.info("mesh sequencing failed at alpha=%g (%s); default start", alpha, err)
    state, _ = _widened_solve(alpha, scaled, paper, order, intorder, symmetric, spacing,
                              c_max, start, fixed=cutoff is not None or vertices is not None,
                              tol=tol, max_iter=max_iter, vertices=vertices, grading=grading)
    return state


def _widened_solve(alpha: float, scaled: ScaledModel, paper: bool, order: int,
                   intorder: int | None, symmetric: bool, spacing: float, c_max: float,
                   start: Callable[[NDArray], NDArray], *, fixed: bool, tol: float,
                   max_iter: int, vertices=None, coarsen: int = 1,
                   chord_level: float = CHORD_LEVEL,
                   grading: float | None = None) -> tuple[SteadyState, float]:
    """Newton on one mesh from ``ln P = start(v)``; unless ``fixed``, widen the interval
    by 15 % (from the current solution) until :math:`f` at the cut-off is below
    :data:`CUTOFF_TARGET`.  With ``coarsen > 1`` the mesh is :func:`nested_coarse`.
    Returns the state and the final cut-off :math:`c_{max}`."""

    def mesh(c: float):
        verts = _mesh(alpha, cutoff=c, spacing=spacing, vertices=vertices, model=scaled,
                      grading=grading)
        return verts if coarsen == 1 else nested_coarse(verts, coarsen)

    verts = mesh(c_max)
    scaled.law.check_speed(2.0 * verts[-1] * scaled.speed_scale, "the FEM velocity interval")
    disc = discretisation(scaled, verts, order, intorder, symmetric)
    u0 = start(disc.dof_locations)
    verts = disc.vertices
    state: SteadyState | None = None
    edge = math.inf
    for widening in range(MAX_WIDENINGS + 1):
        u, info = newton_steady(disc, u0, tol=tol, max_iter=max_iter, chord_level=chord_level)
        try:
            if not info.converged:
                raise ConvergenceError(f"FEM Newton did not converge in {max_iter} iterations "
                                       f"at alpha={alpha} ({info.message}); increase max_iter "
                                       "or refine the mesh (smaller spacing)")
            temperature = state_temperature(disc, u)
            if not paper and order >= 2:
                check_energy_input(disc, u, temperature, alpha)
        except ConvergenceError as err:
            if state is None or edge > TAIL_FLOOR:
                raise
            # the widening is optional once f(cut-off) < TAIL_FLOOR: keep the state found
            logger.info("widened interval failed (%s); keeping f = %.1e at the cut-off",
                        err, edge)
            disc, u, info, verts = state.disc, state.u, state.info, state.disc.vertices
            c_max /= 1.15
            break
        edge = float(np.exp(u[np.argmax(disc.dof_locations)])) * math.sqrt(temperature)
        if fixed or edge < CUTOFF_TARGET:
            break
        if widening < MAX_WIDENINGS:
            logger.info("f = %.1e at the cut-off; widening the interval", edge)
            state = SteadyState(disc, u, info)
            c_max *= 1.15
            verts = mesh(c_max)
            scaled.law.check_speed(2.0 * verts[-1] * scaled.speed_scale,
                                   "the FEM velocity interval")
            disc = discretisation(scaled, verts, order, intorder, symmetric)
            u0 = state.initial_guess(disc.dof_locations, temperature, linear_tail=not paper)
    if edge > TAIL_FLOOR:
        c_edge = verts[-1] / math.sqrt(temperature)
        warnings.warn(f"f(c) = {edge:.2e} at the cut-off c = {c_edge:.3g} is above "
                      f"{TAIL_FLOOR}: the tail is truncated; increase cutoff "
                      "(default: from the model's tail, widened automatically)",
                      ResolutionWarning, stacklevel=3)
    return SteadyState(disc, u, info), c_max


def refinement_factor(history: list[tuple[float, float]], accuracy: float,
                      order: int) -> float:
    r"""The factor of the element size that should meet ``accuracy`` (``accuracy=``).

    The error is taken as :math:`\propto h^r`: :math:`r = k + 1` at first, then the rate
    observed between the last two meshes (T and a2 often converge faster than
    :math:`\ln P`), within [1, 2(k + 1)]; the factor is kept in [0.25, 0.8].

    Parameters
    ----------
    history : list of (float, float)
        ``(element size, estimated error)`` of the meshes solved, the last one last.
    accuracy : float
        The target.
    order : int
        Lagrange degree :math:`k`.

    Returns
    -------
    float
    """
    h1, err = history[-1]
    rate = order + 1.0
    if len(history) > 1 and err > 0:
        h0, e0 = history[-2]
        rate = min(max(math.log(e0 / err) / math.log(h0 / h1), 1.0), 2.0 * (order + 1))
    return min(0.8, max(0.25, 0.8 * (accuracy / err) ** (1.0 / rate)))


@register_solver("fem", problem="heated")
def solve_fem_heated(problem: HeatedProblem, *, mesh: MeshOptions | None = None,
                     symmetric: bool = False, tol: float = 1e-11, max_iter: int = 40,
                     accuracy: float | None = None,
                     **mesh_keywords: Any) -> VelocityDistribution:
    """Steady state of the heated gas by Galerkin FEM and Newton's method.

    Parameters
    ----------
    problem : HeatedProblem
    mesh : MeshOptions, optional
        The mesh's options below as one object (each may also be passed by keyword, over
        ``mesh``; an unknown keyword raises :class:`TypeError`).
    order : int, optional
        Lagrange degree, 1, 2 or 3; default
        :func:`kinetic_fem.solvers.fem.defaults.default_order` on the default mesh (3 for
        a constant alpha and kernels up to hard rods, else 2; P2 also if Newton fails
        with P3), and 2
        with an explicit ``spacing`` or ``vertices``.
    spacing : float, optional
        Element size in thermal velocities :math:`\\sqrt{T}`; default
        :func:`default_spacing` for hard rods with constant alpha and white noise (T to
        1e-8, a2 to 1e-6, f(c) to 1e-4 down to 1e-30), else
        :func:`kinetic_fem.solvers.fem.defaults.model_spacing` on a mesh graded in the tail.
    cutoff : float, optional
        Half-width :math:`V/\\sqrt{T}` of the velocity interval; default
        :func:`default_cutoff`, or :func:`kinetic_fem.solvers.fem.defaults.model_cutoff` (the
        model's WKB tail reaches 1e-33).
    vertices : array_like, optional
        Explicit (e.g. graded) symmetric mesh vertices at ``n = D = 1``; overrides
        ``spacing`` and ``cutoff``.
    intorder : int, optional
        Gauss degree; default ``2 * order + 1``.
    grading : float, optional
        Tail grading :math:`\\kappa \\ge 0` of the mesh (element size
        :math:`h_0 \\max(1, |c|/3)^\\kappa`, 0: uniform); default from the model's tail,
        :math:`(3 - \\gamma)/3` (uniform for the paper's model).
    symmetric : bool
        Use the full collision bracket :math:`\\varphi(x') + \\varphi(y') -
        \\varphi(x) - \\varphi(y)` on every pair: mass and momentum conserved to
        round-off for any :math:`P_h` and, with P2, the energy identity C1 exact.
        The default replaces :math:`\\varphi(y')` by :math:`\\varphi(x')` (equal
        after integration): mass stays exact, momentum exact for the even steady
        state, C1 holds to the quadrature error (1e-11), and the mesh convergence is
        clean fourth order up to alpha = 0.999 (the full bracket stalls near 1e-6
        at alpha = 0.99).
    tol : float
        Stop when the Newton update of :math:`\\ln P` is below ``tol`` everywhere.
    max_iter : int
        Newton iteration limit.
    accuracy : float, optional
        Target accuracy of T (relative) and a2 (absolute), in place of a mesh: the
        spacing (from ``spacing`` or the default) is refined, at the same element degree,
        until the error estimate ``dist.error`` (one Newton step on the bisected mesh,
        :mod:`kinetic_fem.solvers.fem.error`) meets it; ``ConvergenceError`` says what
        was reached if it cannot be (:data:`ACCURACY_REFINEMENTS` refinements, or the
        estimate stops decreasing at round-off).  Not with ``vertices``.  (``tol`` is
        Newton's tolerance, not an accuracy.)

    Returns
    -------
    VelocityDistribution
        On the quadrature points with the quadrature weights; ``info.extra`` holds
        the mesh size and both sides of the discrete energy balance (C1);
        ``dist.error`` the estimate of the errors of T, a2 and f(c) (computed when
        first read, or during the solve with ``accuracy``).

    Raises
    ------
    ConvergenceError
        If Newton's method does not converge, or ``accuracy`` cannot be met.

    Warns
    -----
    ResolutionWarning
        If the cut-off truncates f(c) above 1e-30 or the spacing is too coarse.
    """
    m = gather(MeshOptions, mesh, mesh_keywords, "solve_fem_heated")
    order, spacing, cutoff, vertices, intorder = (m.order, m.spacing, m.cutoff, m.vertices,
                                                  m.intorder)
    problem.require("fem")
    if accuracy is not None:
        check_positive("accuracy", accuracy)
        if vertices is not None:
            raise ValueError("accuracy= refines the spacing: it cannot be combined with "
                             "explicit vertices; give spacing (or neither)")
    state = steady_state(problem, order=order, spacing=spacing, cutoff=cutoff,
                         vertices=vertices, intorder=intorder, grading=m.grading,
                         symmetric=symmetric, tol=tol, max_iter=max_iter)
    if accuracy is None:
        return state_distribution(problem, state, state.disc.order)
    order = state.disc.order
    scaled = scaled_model(problem)
    if spacing is None:
        spacing = default_spacing(scaled.alpha, order) if scaled.is_paper_model else \
            model_spacing(scaled, order)
    history: list[tuple[float, float]] = []
    for refinement in range(ACCURACY_REFINEMENTS + 1):
        est = heated_estimate(state.disc, state.u, state.disc.distribution(state.u))
        err = max(est.temperature, est.a2)
        history.append((spacing, err))
        logger.info("accuracy=%g: spacing %.4g, P%d, estimated error %.2e", accuracy,
                    spacing, order, err)
        if est.meets(accuracy):
            dist = state_distribution(problem, state, order)
            return dist.with_error(dist.error_recipe, est)
        stalled = len(history) > 1 and err > 0.5 * history[-2][1]
        if refinement == ACCURACY_REFINEMENTS or stalled:
            break
        spacing *= refinement_factor(history, accuracy, order)
        state = steady_state(problem, order=order, spacing=spacing, cutoff=cutoff,
                             intorder=intorder, grading=m.grading, symmetric=symmetric,
                             tol=tol, max_iter=max_iter)
    raise ConvergenceError(
        f"FEM did not reach accuracy={accuracy:g} (T relative and a2): estimated errors "
        + ", ".join(f"{e:.2g} at spacing {h:.3g}" for h, e in history)
        + f" (P{order}); " + ("the estimate stopped decreasing (round-off or the cut-off); "
                              if len(history) > 1 and history[-1][1] > 0.5 * history[-2][1]
                              else "")
        + "ask for less, or give a smaller spacing")


def state_distribution(problem: HeatedProblem, state: SteadyState,
                       order: int = 2) -> VelocityDistribution:
    """The :class:`VelocityDistribution` of a steady state, in the problem's units.

    Parameters
    ----------
    problem : HeatedProblem
        The problem the state solves (at ``n = D = 1``).
    state : SteadyState
        The state from :func:`steady_state`.
    order : int
        Lagrange degree of the state, recorded in ``info.extra``.
    """
    # the two sides of C1 on first read (the loss costs a collision-kernel call)
    def energy_balance() -> dict[str, float]:
        injection, loss = state.energy_terms()
        return {"c1_injection": injection, "c1_loss": loss}

    info = replace(state.info, extra=LazyExtra({"n_dofs": int(state.u.size), "order": order},
                                               lazy=energy_balance))
    dist = state.disc.distribution(state.u, method="fem", params=problem.as_dict(), info=info)
    dist = dist.with_error(heated_recipe(state.disc, state.u))
    return dist.rescaled(problem.velocity_scale) if problem.velocity_scale != 1.0 else dist
