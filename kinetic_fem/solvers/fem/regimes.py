"""The regimes of the FEM cooling state: one table that reads as the dispatch (issue 26).

:func:`kinetic_fem.solvers.fem.cooling.cooling_state` solves the scaled homogeneous
cooling state (module notes of :mod:`kinetic_fem.solvers.fem.cooling`) by the one regime of
:data:`REGIMES` that applies to the problem and its options: each regime is a small
class with ``applies(problem, options)`` (the regimes are a partition: exactly one
applies to every power-law kernel, restitution coefficient and set of options,
``tests/kinetic_fem/solvers/test_fem_regimes.py``), ``solve(problem, options, run)``, its
thresholds as class data, and a docstring saying when and why it applies.

================== ==================================================================
regime             applies to (default mesh: no ``spacing``, ``cutoff``, ``vertices``)
================== ==================================================================
MaxwellTail        gamma = 0, no ``cutoff``/``vertices``/``resolution``: short mesh and
                   the analytic :math:`c^{-4}` tail
Gamma2Anchored     gamma = 2, default mesh, eps within the stored anchor states
NearElasticHard    gamma > 1, default mesh, eps < 3e-3 (anchors off or out of range)
HumpBand           hard rods, default mesh and degree, 0.035 <= eps < 0.1
HumpChain          hard rods, default mesh, eps < 0.1 (not the band)
MaxwellTruncated   gamma = 0 on an explicit mesh (``cutoff``, ``vertices``)
HardKernelChain    gamma > 1, alpha > 0.5 (none of the above)
StrongInelastic    gamma > 0, alpha < 0.5 (none of the above)
GenericNewton      everything else: 0 < gamma <= 1 at alpha >= 0.5 away from the humps,
                   and gamma > 1 at alpha = 0.5
================== ==================================================================

A regime whose special start fails hands over to the one named in its ``solve`` (the
anchors to the table without them, the band to the hump chain, the truncated Maxwell
model's closed-form start to mesh sequencing and the Gaussian start).  The states one
call remembers (the near-elastic state of the hard-kernel chain, reused by its
globalised retry) live in the :class:`Run` of that call, so no state outlives it.
"""

from __future__ import annotations

import functools
import logging
import math
from dataclasses import dataclass, field, replace
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...distribution import VelocityDistribution
from ...exceptions import ConvergenceError
from ...model import CoolingProblem, check_positive
from ...operators.fem_discretisation import LAGRANGE_ELEMENTS, FEMDiscretisation
from ..continuation import NO_RETRY, continuation
from .cooling_alpha import (
    ALPHA_CHAIN_COARSE,
    DIRECT_EPS,
    alpha_chain,
    quasi_seed_vertices,
    uses_alpha_chain,
)
from .cooling_band import BAND_EPS, band_state, in_band
from .cooling_gamma2 import ANCHORED_GAMMA, anchored_state, uses_anchors
from .cooling_hump import (
    HUMP_COARSE_EPS,
    HUMP_P3_EPS,
    HUMP_P3_RESOLUTION,
    HUMP_RESOLUTION,
    HumpStepOptions,
)
from .cooling_links import HUMP_EPS, HUMP_STEP_TOL, chain_state, start_state
from .cooling_maxwell import maxwell_cooling_state
from .cooling_mesh import hcs_bulk, hcs_cutoff, hcs_spacing, hcs_vertices, initial_log_f
from .cooling_newton import CLOSE_DAMPING, CoolingState, newton_cooling
from .cooling_order import (
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
from .cooling_seeds import seed_start
from .cooling_tail import maxwell_hcs

__all__ = ["CoolingOptions", "Regime", "Run", "REGIMES", "select", "solve_state",
           "uses_hump_mesh", "link_start", "hump_start", "MaxwellTail", "Gamma2Anchored",
           "NearElasticHard", "HumpBand", "HumpChain", "MaxwellTruncated",
           "HardKernelChain", "StrongInelastic", "GenericNewton"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class CoolingOptions:
    """The options of one cooling-state solve (see
    :func:`~kinetic_fem.solvers.fem.cooling.solve_fem_cooling`).

    Parameters
    ----------
    order, spacing, cutoff, vertices, intorder, tol, max_iter, resolution, initial
        As in :func:`~kinetic_fem.solvers.fem.cooling.solve_fem_cooling`.
    sequence : bool
        Mesh sequencing on a mesh built from ``spacing``
        (:func:`~kinetic_fem.solvers.fem.cooling.cooling_state`).
    stored : bool
        Start from the stored states where they cover the problem (the gamma = 2 anchors
        of :mod:`.cooling_gamma2`, the hard-rod seeds of :mod:`.cooling_seeds`);
        False: the continuation they replace (tests of the stored data).
    """

    order: int | None = None
    spacing: float | None = None
    cutoff: float | None = None
    vertices: ArrayLike | None = field(default=None, compare=False)
    intorder: int | None = None
    tol: float = 1e-11
    max_iter: int = 100
    resolution: float | None = None
    sequence: bool = True
    initial: CoolingState | VelocityDistribution | None = field(default=None, compare=False)
    stored: bool = True

    @property
    def default_mesh(self) -> bool:
        """No ``spacing``, ``cutoff`` or ``vertices``: the mesh is the solver's choice."""
        return self.vertices is None and self.spacing is None and self.cutoff is None


def uses_hump_mesh(problem: CoolingProblem) -> bool:
    """Hard rods below :data:`~.cooling_links.HUMP_EPS`: the default mesh follows the humps.

    Parameters
    ----------
    problem : CoolingProblem
        The cooling problem (kernel and restitution of its gas are read).

    Returns
    -------
    bool
        True for hard rods with :math:`\\varepsilon = 1 - \\alpha <` ``HUMP_EPS``.
    """
    return problem.gas.gamma == 1.0 and problem.gas.epsilon < HUMP_EPS * (1.0 - 1e-12)


class Run:
    """One call of the cooling-state solver: the dispatch, and what the call remembers.

    ``memo`` holds the near-elastic states of the hard-kernel chain
    (:func:`~.cooling_alpha.alpha_chain`) keyed on every input of theirs except the
    start, so the globalised retry of the call reuses the state its coarse solve reached;
    it dies with the call.
    """

    def __init__(self) -> None:
        self.memo: dict[tuple, CoolingState] = {}

    def solve(self, problem: CoolingProblem, options: CoolingOptions) -> CoolingState:
        """The state by the regime of :data:`REGIMES` that applies.

        Parameters
        ----------
        problem : CoolingProblem
            Constant restitution, a power-law kernel.
        options : CoolingOptions
            The options.

        Returns
        -------
        CoolingState

        Raises
        ------
        ConvergenceError
            If Newton's method does not converge.
        ValueError
            For options the regime does not take (e.g. ``resolution`` off the humps).
        """
        return select(problem, options).solve(problem, options, self)


class Regime:
    """One path of the cooling-state solver: when it applies and how it solves."""

    name: ClassVar[str] = "regime"

    def applies(self, problem: CoolingProblem, options: CoolingOptions) -> bool:
        """Whether this regime solves ``problem`` with ``options``.

        Parameters
        ----------
        problem : CoolingProblem
            Constant restitution, a power-law kernel.
        options : CoolingOptions
            The options.

        Returns
        -------
        bool
        """
        raise NotImplementedError

    def solve(self, problem: CoolingProblem, options: CoolingOptions, run: Run
              ) -> CoolingState:
        """The state (on a problem this regime applies to).

        Parameters
        ----------
        problem : CoolingProblem
            The problem.
        options : CoolingOptions
            The options.
        run : Run
            The call (recursive solves go through ``run.solve``).

        Returns
        -------
        CoolingState

        Raises
        ------
        ConvergenceError
            If Newton's method does not converge.
        """
        raise NotImplementedError

    def __repr__(self) -> str:
        return f"{type(self).__name__}()"


def _anchored(problem: CoolingProblem, options: CoolingOptions) -> bool:
    return (options.stored and options.default_mesh and options.resolution is None
            and uses_anchors(problem))


def _near_elastic_hard(problem: CoolingProblem, options: CoolingOptions) -> bool:
    return (uses_alpha_chain(problem) and options.default_mesh
            and problem.gas.epsilon < NearElasticHard.below_eps
            and not _anchored(problem, options))


def _hump(problem: CoolingProblem, options: CoolingOptions) -> bool:
    return uses_hump_mesh(problem) and options.default_mesh


def _band(problem: CoolingProblem, options: CoolingOptions) -> bool:
    return (_hump(problem, options) and options.order is None and options.resolution is None
            and in_band(problem.gas.epsilon, HUMP_EPS))


def _maxwell_tail(problem: CoolingProblem, options: CoolingOptions) -> bool:
    return (problem.gas.gamma == 0.0 and options.vertices is None and options.cutoff is None
            and options.resolution is None)


def _check_order(order: int, hump: bool) -> None:
    if order not in LAGRANGE_ELEMENTS or (hump and order == 3):
        raise ValueError(f"order must be one of {sorted(LAGRANGE_ELEMENTS)} (1 or 2 on the "
                         f"near-elastic hump mesh, whose default is P3 at eps >= "
                         f"{HUMP_P3_EPS:g}: omit order), got {order!r}")


class MaxwellTail(Regime):
    """The inelastic Maxwell model (gamma = 0) on its default mesh: P3 to c = 200 and the
    :math:`c^{-4}` tail continued analytically beyond (:mod:`.cooling_maxwell`).

    Applies without ``cutoff``, ``vertices`` and ``resolution`` (``spacing`` and
    ``order`` refine the short mesh); the closed-form state starts Newton's method.
    """

    name = "Maxwell model, analytic tail"

    def applies(self, problem: CoolingProblem, options: CoolingOptions) -> bool:  # noqa: D102
        return _maxwell_tail(problem, options)

    def solve(self, problem: CoolingProblem, options: CoolingOptions, run: Run  # noqa: D102
              ) -> CoolingState:
        return maxwell_cooling_state(problem.gas.alpha, order=options.order,
                                     spacing=options.spacing, intorder=options.intorder,
                                     tol=options.tol, max_iter=options.max_iter)


class Gamma2Anchored(Regime):
    """gamma = 2 on the default mesh: one Newton solve from the stored scaled states.

    The pseudo-transient iteration from a Gaussian diverges there for alpha >= 0.6 and
    the continuation in alpha costs 10 to 40 solves; the anchors of
    :mod:`.cooling_gamma2` (eps in [5e-4, 1]) start one solve on the mesh they
    decide.  If it fails, the regime the table picks without stored states solves.
    """

    name = "gamma = 2 from the stored anchors"
    gamma: ClassVar[float] = ANCHORED_GAMMA

    def applies(self, problem: CoolingProblem, options: CoolingOptions) -> bool:  # noqa: D102
        return _anchored(problem, options)

    def solve(self, problem: CoolingProblem, options: CoolingOptions, run: Run  # noqa: D102
              ) -> CoolingState:
        state = anchored_state(problem, order=cooling_order(problem, options.order,
                                                            default_mesh=True),
                               intorder=options.intorder, tol=options.tol,
                               max_iter=options.max_iter)
        if state is not None:
            return state
        without = replace(options, stored=False)
        return run.solve(problem, without)


class NearElasticHard(Regime):
    """Kernels harder than hard rods near elastic collisions, default mesh: straight to
    the near-elastic chain on its own meshes (:mod:`.cooling_alpha`).

    The Newton step on the default fine mesh turned singular at alpha 0.998 ... 0.9995
    (its far tail underflows), and the detour cost 1.2-1.3 times more; the chain starts
    on the mesh of the state at eps = 0.01 (:func:`~.cooling_alpha.quasi_seed_vertices`).
    """

    name = "hard kernel near elastic"
    below_eps: ClassVar[float] = DIRECT_EPS

    def applies(self, problem: CoolingProblem, options: CoolingOptions) -> bool:  # noqa: D102
        return _near_elastic_hard(problem, options)

    def solve(self, problem: CoolingProblem, options: CoolingOptions, run: Run  # noqa: D102
              ) -> CoolingState:
        verts = quasi_seed_vertices(problem.gas.gamma,
                                    cooling_order(problem, options.order, default_mesh=False))
        return HardKernelChain().solve(problem, replace(options, vertices=verts), run)


def link_start(order: int, intorder: int | None) -> CoolingState:
    """The state at :data:`~.cooling_links.HUMP_EPS` on the coarse mesh that starts
    the fast links (not cached).

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
    return Run().solve(problem, CoolingOptions(
        order=order, intorder=intorder, tol=HUMP_STEP_TOL, spacing=HumpChain.link_spacing,
        cutoff=HumpChain.link_cutoff, sequence=False))


@functools.lru_cache(maxsize=4)
def hump_start(order: int, intorder: int | None) -> CoolingState:
    """The state at :data:`~.cooling_links.HUMP_EPS` from the Gaussian start (spacing
    0.1, cut-off 12, tolerance 1e-9; cached on both arguments, its only inputs: it starts
    the chains of :mod:`.cooling_chain` and the benchmarks).

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
    return Run().solve(problem, CoolingOptions(order=order, intorder=intorder, tol=1e-9,
                                               spacing=0.1, cutoff=12.0))


class HumpChain(Regime):
    """Hard rods near elastic collisions (eps < 0.1), default mesh: continuation in eps
    on meshes that follow the two humps of width :math:`\\varepsilon^{1/3}`.

    From ``initial`` (a warm start), else from the stored start (:mod:`.cooling_seeds`)
    nearest at or above eps (below :data:`~.cooling_hump.HUMP_COARSE_EPS` the
    smallest), else (``stored=False``) from :func:`link_start` at eps = 0.1; the state
    asked for is P3 at :data:`p3_resolution` hump widths for eps >= :data:`p3_eps` with
    the default ``order`` and ``resolution``, else of degree ``order`` at ``resolution``
    (:func:`~.cooling_links.chain_state`).
    """

    name = "hard rods, near-elastic humps"
    below_eps: ClassVar[float] = HUMP_EPS
    p3_eps: ClassVar[float] = HUMP_P3_EPS
    p3_resolution: ClassVar[float] = HUMP_P3_RESOLUTION
    resolution: ClassVar[float] = HUMP_RESOLUTION
    link_spacing: ClassVar[float] = 0.3
    """Mesh of :func:`link_start` (one solve, tolerance HUMP_STEP_TOL, no mesh sequencing;
    ln f = -77 at c = 9): 0.05 to 0.09 CPU s less per state at eps = 1e-3 ... 0.03 than
    :func:`hump_start`'s, the final states equal to 1.3e-14
    (benchmarks/archive/results/fem_cooling_speed.md)."""
    link_cutoff: ClassVar[float] = 9.0

    def applies(self, problem: CoolingProblem, options: CoolingOptions) -> bool:  # noqa: D102
        return _hump(problem, options) and not _band(problem, options)

    def solve(self, problem: CoolingProblem, options: CoolingOptions, run: Run  # noqa: D102
              ) -> CoolingState:
        order = cooling_order(problem, options.order, default_mesh=False)
        _check_order(order, hump=True)
        resolution = options.resolution
        if resolution is not None:
            resolution = check_positive("resolution", resolution)
        default = options.order is None and options.resolution is None
        p3 = default and problem.gas.epsilon >= self.p3_eps * (1.0 - 1e-9)
        if options.initial is not None:
            start, eps_start = start_state(options.initial)
        elif options.stored:  # a stored start (issue 16)
            start, eps_start = seed_start(max(problem.gas.epsilon, HUMP_COARSE_EPS))
        else:
            start, eps_start = link_start(2, None), HUMP_EPS
        final = HumpStepOptions(resolution=self.p3_resolution if p3 else resolution
                                or self.resolution, order=3 if p3 else order,
                                intorder=options.intorder, tol=options.tol,
                                max_iter=options.max_iter)
        return chain_state(problem.gas.alpha, start, eps_start, final, order=order)


class HumpBand(Regime):
    """Hard rods with broad humps, 0.035 <= eps < 0.1, default mesh and degree: P3 on a
    mesh graded along the tail, from one link from eps = 0.1 (:mod:`.cooling_band`).

    If the link or the solve fails, :class:`HumpChain` solves.
    """

    name = "hard rods, broad humps"
    from_eps: ClassVar[float] = BAND_EPS

    def applies(self, problem: CoolingProblem, options: CoolingOptions) -> bool:  # noqa: D102
        return _band(problem, options)

    def solve(self, problem: CoolingProblem, options: CoolingOptions, run: Run  # noqa: D102
              ) -> CoolingState:
        start, eps_start = (start_state(options.initial) if options.initial is not None
                            else (link_start(2, None), HUMP_EPS))
        state = band_state(problem, start, eps_start, tol=options.tol,
                           max_iter=options.max_iter, intorder=options.intorder)
        if state is not None:
            return state
        return HumpChain().solve(problem, options, run)


@dataclass(frozen=True)
class _Mesh:
    """The mesh of the generic path: degree, bulk spacing, cut-off, discretisation."""

    order: int
    spacing: float
    cutoff: float | None
    disc: FEMDiscretisation


class GenericNewton(Regime):
    """Newton's method on the default (or an explicit) mesh of :func:`hcs_vertices`.

    Everything no other regime takes: kernels up to hard rods at alpha >= 0.5 away from
    the humps, harder kernels at alpha = 0.5, any explicit mesh there.  The state is
    started from the state on a mesh :data:`coarse_factor` times coarser (mesh
    sequencing, on a mesh built from ``spacing`` finer than the coarse cap), else by the
    globalised (pseudo-transient) iteration from :meth:`start` (a Gaussian at the
    Gaussian estimate of zeta).  Subclasses change :meth:`first_start`, :meth:`start`
    or :meth:`globalised`.
    """

    name = "Newton, mesh sequencing"
    coarse_factor: ClassVar[float] = COARSE_FACTOR

    def applies(self, problem: CoolingProblem, options: CoolingOptions) -> bool:  # noqa: D102
        return (problem.gas.gamma > 0.0 and problem.gas.alpha >= STRONG_ALPHA
                and not uses_alpha_chain(problem) and not _hump(problem, options)
                and not _anchored(problem, options))

    @staticmethod
    def mesh(problem: CoolingProblem, options: CoolingOptions) -> _Mesh:
        """The degree and mesh of the generic path, options checked.

        Parameters
        ----------
        problem : CoolingProblem
            The problem.
        options : CoolingOptions
            The options.

        Returns
        -------
        _Mesh

        Raises
        ------
        ValueError
            For a degree not in ``LAGRANGE_ELEMENTS``, a ``resolution`` (the hump mesh's
            option), a non-positive ``spacing``/``cutoff`` or unsymmetric ``vertices``.
        """
        order = cooling_order(problem, options.order, default_mesh=options.spacing is None
                              and options.vertices is None)
        _check_order(order, hump=False)
        if options.resolution is not None:
            check_positive("resolution", options.resolution)
            raise ValueError(f"resolution is the element size of the near-elastic hump mesh "
                             f"(hard rods, eps < {HUMP_EPS}, no spacing/cutoff/vertices), "
                             f"not used at eps = {problem.gas.epsilon:g}, gamma = "
                             f"{problem.gas.gamma:g}; pass spacing instead")
        spacing = order_spacing(hcs_spacing(problem), order) if options.spacing is None \
            else check_positive("spacing", options.spacing)
        c_max = None
        if options.vertices is None:
            c_max = hcs_cutoff(problem) if options.cutoff is None else \
                check_positive("cutoff", options.cutoff)
            verts = hcs_vertices(c_max, spacing, gamma=problem.gas.gamma,
                                 bulk=hcs_bulk(problem.gas.epsilon))
        else:
            verts = np.sort(np.asarray(options.vertices, dtype=float))
            if not np.allclose(verts, -verts[::-1], rtol=0,
                               atol=1e-12 * np.abs(verts).max()) or not np.any(verts == 0.0):
                raise ValueError("vertices must be symmetric about 0 and include c = 0")
        disc = FEMDiscretisation(problem.gas.alpha, verts, order,
                                 options.intorder or 2 * order + 1, gamma=problem.gas.gamma)
        return _Mesh(order, spacing, c_max, disc)

    def solve(self, problem: CoolingProblem, options: CoolingOptions, run: Run  # noqa: D102
              ) -> CoolingState:
        mesh = self.mesh(problem, options)
        state = self.first_start(problem, options, mesh)
        if state is None:
            state = self.sequenced(problem, options, mesh, run)
        if state is None:
            state = self.globalised(problem, options, mesh, run)
        return state

    def first_start(self, problem: CoolingProblem, options: CoolingOptions, mesh: _Mesh
                    ) -> CoolingState | None:
        """A start tried before mesh sequencing (None: none)."""
        return None

    def sequenced(self, problem: CoolingProblem, options: CoolingOptions, mesh: _Mesh,
                  run: Run) -> CoolingState | None:
        """Newton from the state on a coarser mesh (None: not sequenced, or it failed)."""
        cap = P3_COARSE_SPACING if mesh.order == 3 else COARSE_SPACING
        if not (options.sequence and options.vertices is None and mesh.spacing < cap):
            return None
        coarse = run.solve(problem, CoolingOptions(
            order=min(mesh.order, COARSE_ORDER),
            spacing=min(self.coarse_factor * mesh.spacing, cap), cutoff=mesh.cutoff,
            intorder=options.intorder, tol=COARSE_TOL, max_iter=options.max_iter,
            sequence=False))
        disc = mesh.disc
        state = newton_cooling(disc, coarse.log_f(disc.dof_locations), coarse.zeta,
                               tol=options.tol, max_iter=options.max_iter,
                               pseudo_time=np.inf, min_damping=CLOSE_DAMPING)
        if state.info.converged:
            return state
        logger.info("HCS mesh sequencing: Newton from the coarse state failed (%s); "
                    "globalised iteration on the fine mesh", state.info.message)
        return None

    def start(self, problem: CoolingProblem, options: CoolingOptions, mesh: _Mesh,
              run: Run) -> tuple[NDArray[np.float64], float]:
        """The start of the globalised iteration: ln f at the dofs and zeta."""
        zeta0 = problem.zeta_estimate()
        return initial_log_f(mesh.disc.dof_locations, problem.gas.gamma, zeta0), zeta0

    def globalised(self, problem: CoolingProblem, options: CoolingOptions, mesh: _Mesh,
                   run: Run) -> CoolingState:
        """The pseudo-transient iteration from :meth:`start`."""
        u0, zeta0 = self.start(problem, options, mesh, run)
        state = newton_cooling(mesh.disc, u0, zeta0, tol=options.tol,
                               max_iter=options.max_iter)
        if not state.info.converged:
            raise ConvergenceError(
                f"FEM cooling Newton did not converge in {options.max_iter} iterations at "
                f"alpha={problem.gas.alpha} ({state.info.message}); refine the mesh "
                "(smaller spacing) or increase max_iter")
        return state


class MaxwellTruncated(GenericNewton):
    """The Maxwell model on an explicit mesh (``cutoff`` or ``vertices``, e.g. out to
    :math:`V = 10^8`): Newton from the closed-form state first.

    It converges in four or five steps; the Gaussian start's globalised iteration failed
    on the coarse mesh at alpha = 0.99 and took 188 s on the fine one.  If it fails,
    mesh sequencing and the Gaussian start follow (:class:`GenericNewton`).
    """

    name = "Maxwell model, truncated mesh"

    def applies(self, problem: CoolingProblem, options: CoolingOptions) -> bool:  # noqa: D102
        return problem.gas.gamma == 0.0 and not _maxwell_tail(problem, options)

    def first_start(self, problem: CoolingProblem, options: CoolingOptions, mesh: _Mesh
                    ) -> CoolingState | None:
        """Newton from the closed form (None if it failed)."""
        disc = mesh.disc
        state = newton_cooling(disc, np.log(maxwell_hcs(disc.dof_locations)),
                               0.25 * (1.0 - problem.gas.alpha**2), tol=options.tol,
                               max_iter=options.max_iter, pseudo_time=np.inf)
        if state.info.converged:
            return state
        logger.info("HCS Maxwell model: Newton from the closed form failed (%s); globalised "
                    "iteration", state.info.message)
        return None


class HardKernelChain(GenericNewton):
    """Kernels harder than hard rods at alpha > 0.5 (bimodal states): mesh sequencing on
    a mesh :data:`coarse_factor` = 2 times coarser, else continuation in alpha from
    alpha = 0.5 on the target's mesh (:func:`~.cooling_alpha.alpha_chain`).

    The pseudo-transient iteration from a Gaussian diverges there for alpha >= 0.6.
    """

    name = "hard kernel, continuation in alpha"
    coarse_factor = ALPHA_CHAIN_COARSE
    chain_iter: ClassVar[int] = 40
    """Newton steps per step of the chain (at most)."""

    def applies(self, problem: CoolingProblem, options: CoolingOptions) -> bool:  # noqa: D102
        return (uses_alpha_chain(problem) and not _anchored(problem, options)
                and not _near_elastic_hard(problem, options))

    def globalised(self, problem: CoolingProblem, options: CoolingOptions, mesh: _Mesh,
                   run: Run) -> CoolingState:
        """The continuation in alpha from :data:`~.cooling_order.STRONG_ALPHA`."""
        base = run.solve(CoolingProblem.from_parameters(STRONG_ALPHA, kernel=problem.gas.kernel),
                         CoolingOptions(order=mesh.order, vertices=mesh.disc.vertices,
                                        intorder=options.intorder, tol=COARSE_TOL,
                                        max_iter=options.max_iter))
        state = alpha_chain(mesh.disc, base, STRONG_ALPHA, tol=options.tol,
                            max_iter=min(options.max_iter, self.chain_iter), memo=run.memo)
        if not state.info.converged:
            raise ConvergenceError(
                f"FEM cooling continuation in alpha from {STRONG_ALPHA} did not converge at "
                f"alpha={state.disc.alpha:.6g} on the way to {problem.gas.alpha} "
                f"({state.info.message}); refine the mesh (smaller spacing)")
        return state


class StrongInelastic(GenericNewton):
    """alpha < 0.5 (long exponential tails, far from the Gaussian start), gamma > 0:
    the globalised iteration starts from the state one step of at most
    :data:`step` in alpha above (on twice the spacing when sequenced).

    The steps are a :func:`~kinetic_fem.solvers.continuation.continuation` in alpha
    (:meth:`path`) from the state at the top of the path, solved by the regime that
    applies there (alpha 0.5: :class:`GenericNewton`), each step the globalised
    iteration on that alpha's own coarse mesh from the state above, the last on the
    target's mesh; a failed step stops it (no retry).
    """

    name = "strong inelasticity, continuation from alpha 0.5"
    below_alpha: ClassVar[float] = STRONG_ALPHA
    step: ClassVar[float] = STRONG_STEP

    def applies(self, problem: CoolingProblem, options: CoolingOptions) -> bool:  # noqa: D102
        return (problem.gas.gamma > 0.0 and problem.gas.alpha < self.below_alpha
                and not _anchored(problem, options))

    def path(self, problem: CoolingProblem, coarse: CoolingOptions) -> list[float]:
        """The alphas above the target, from the top down: each the one step of at most
        :data:`step` towards :data:`below_alpha` from the next one below, up to the first
        that this regime does not solve with the ``coarse`` options.

        Parameters
        ----------
        problem : CoolingProblem
            The target.
        coarse : CoolingOptions
            The options of the states above it.

        Returns
        -------
        list of float
        """
        ups = []
        alpha = problem.gas.alpha
        while True:
            n_steps = math.ceil((self.below_alpha - alpha) / self.step - 1e-9)
            alpha = alpha + (self.below_alpha - alpha) / n_steps
            ups.append(alpha)
            above = CoolingProblem.from_parameters(alpha, kernel=problem.gas.kernel)
            if not isinstance(select(above, coarse), StrongInelastic):
                return ups[::-1]

    def globalised(self, problem: CoolingProblem, options: CoolingOptions, mesh: _Mesh,
                   run: Run) -> CoolingState:
        """The continuation in alpha down to the target (see the class)."""
        coarse = CoolingOptions(
            order=mesh.order, tol=1e-7, max_iter=options.max_iter,
            spacing=2.0 * mesh.spacing if options.sequence else mesh.spacing, sequence=False)
        alpha = problem.gas.alpha
        ups = self.path(problem, coarse)
        kernel = problem.gas.kernel

        def solve(prev: CoolingState, alpha_prev: float, alpha_next: float) -> CoolingState:
            if alpha_next == alpha:
                disc, tol = mesh.disc, options.tol
            else:
                disc = self.mesh(CoolingProblem.from_parameters(alpha_next, kernel=kernel),
                                 coarse).disc
                tol = coarse.tol
            zeta0 = prev.zeta * (1.0 - alpha_next**2) / (1.0 - alpha_prev**2)
            return newton_cooling(disc, prev.log_f(disc.dof_locations), zeta0, tol=tol,
                                  max_iter=options.max_iter)

        top = run.solve(CoolingProblem.from_parameters(ups[0], kernel=kernel), coarse)
        walk = continuation(top, ups[0], [*ups[1:], alpha], solve, rule=NO_RETRY)
        if not walk.converged:
            failed = walk.failed
            assert failed is not None
            raise ConvergenceError(
                f"FEM cooling Newton did not converge in {options.max_iter} iterations at "
                f"alpha={walk.failed_value} ({failed.info.message}); refine the mesh "
                "(smaller spacing) or increase max_iter")
        return walk.state


REGIMES: tuple[Regime, ...] = (
    MaxwellTail(),
    Gamma2Anchored(),
    NearElasticHard(),
    HumpBand(),
    HumpChain(),
    MaxwellTruncated(),
    HardKernelChain(),
    StrongInelastic(),
    GenericNewton(),
)
"""The regimes of the cooling state, a partition of (kernel, alpha, options)."""


def select(problem: CoolingProblem, options: CoolingOptions) -> Regime:
    """The regime of :data:`REGIMES` that applies.

    Parameters
    ----------
    problem : CoolingProblem
        Constant restitution, a power-law kernel.
    options : CoolingOptions
        The options.

    Returns
    -------
    Regime

    Examples
    --------
    >>> select(CoolingProblem.from_parameters(0.99), CoolingOptions())
    HumpChain()
    >>> select(CoolingProblem.from_parameters(0.7, kernel=0.0), CoolingOptions(cutoff=1e4))
    MaxwellTruncated()
    """
    for regime in REGIMES:
        if regime.applies(problem, options):
            return regime
    raise AssertionError(f"no regime applies to {problem!r} with {options!r}")  # pragma: no cover


def solve_state(problem: CoolingProblem, options: CoolingOptions) -> CoolingState:
    """The cooling state by the regime that applies, in a new :class:`Run`.

    Parameters
    ----------
    problem : CoolingProblem
        The problem (constant restitution).
    options : CoolingOptions
        The solver's options.

    Returns
    -------
    CoolingState
        As :meth:`Run.solve` (which also says what it raises).
    """
    return Run().solve(problem, options)
