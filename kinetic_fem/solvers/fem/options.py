"""The options of an FEM solve or transient as objects (issue 26).

:class:`MeshOptions` holds the options of the velocity mesh that travel together: the
Lagrange degree, the bulk spacing, the cut-off, explicit vertices and the Gauss degree.
The FEM solvers take it as ``mesh=`` and still take each field by keyword
(``kf.solve_heated(0.5, spacing=0.2)``), through :func:`kinetic_fem.options.gather`.

:class:`EvolveOptions` (heated) and :class:`CoolingEvolveOptions` (free cooling) hold
the numerical options of an FEM transient (tolerance, mesh, steps, Newton); the drivers
take them as ``options=`` and each field by keyword (``kf.evolve_heated(0.5, times=...,
rtol=1e-5)``).  The drivers resolve them into the integrator's
:class:`~kinetic_fem.solvers.fem.transient_setup.TransientOptions` (defaults that depend
on ``rtol`` filled in).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...distribution import VelocityDistribution
from ...operators.mesher import LogDropRule, log_drop_vertices
from ...options import option_group

__all__ = ["MeshOptions", "EvolveOptions", "CoolingEvolveOptions", "STATE_RULE", "mesh_from_state"]


@option_group
@dataclass(frozen=True)
class MeshOptions:
    """The velocity mesh of an FEM solve (None: the solver's default).

    Parameters
    ----------
    order : int, optional
        Lagrange degree, 1, 2 or 3.
    spacing : float, optional
        Bulk element size, thermal velocities.
    cutoff : float, optional
        Half-width of the velocity interval, thermal velocities.
    vertices : array_like, optional
        Explicit symmetric vertices (overrides ``spacing`` and ``cutoff``).
    intorder : int, optional
        Gauss degree (default ``2 * order + 1``).
    grading : float, optional
        Tail grading :math:`\\kappa \\ge 0` of the heated solver's mesh: elements of
        size :math:`h_0 \\max(1, |c|/3)^\\kappa`
        (:func:`~kinetic_fem.solvers.fem.grading.graded_vertices`); 0 a uniform mesh;
        default: from the model's scales, :math:`(3 - \\gamma)/3` for the tail
        :math:`\\ln f \\sim -c^\\gamma` (uniform for the paper's model).  The cooling
        state's meshes follow its regimes and refuse it.

    Examples
    --------
    >>> MeshOptions(order=3, spacing=0.2)
    MeshOptions(order=3, spacing=0.2, cutoff=None, vertices=None, intorder=None, grading=None)
    """

    order: int | None = None
    spacing: float | None = None
    cutoff: float | None = None
    vertices: ArrayLike | None = field(default=None, compare=False)
    intorder: int | None = None
    grading: float | None = None


STATE_RULE = LogDropRule(efolds=1.0, smallest=0.1, largest=0.3, decades=40.0)
"""The default placement of :func:`mesh_from_state`: at most one e-fold of ln f per
element, elements of 0.1 ... 0.3, the mesh ends where f has fallen 40 decades.  Hard
rods, alpha = 0.5, P2, from the state on the mesh of spacing 0.5 (174 vertices, zeta
2.5e-6 off): 225 vertices, zeta 3.0e-7 off (the default P2 mesh: 853 vertices, 2.6e-10;
the default mesh's grading at spacing 0.3: 144 vertices, 3.3e-7)."""


def mesh_from_state(state: Any, options: MeshOptions | None = None, *,
                    rule: LogDropRule = STATE_RULE) -> MeshOptions:
    """Mesh options whose vertices follow a state: each element carries at most
    ``rule.efolds`` e-folds of its :math:`\\ln f`
    (:func:`~kinetic_fem.operators.mesher.log_drop_vertices`).

    For re-solving on a mesh adapted to a previous solution:
    ``kf.solve_cooling(alpha, mesh=mesh_from_state(coarse))``.

    Parameters
    ----------
    state : VelocityDistribution, LogDensity or callable
        A distribution (its :math:`\\ln P(v)` in its own velocities, interpolated; the
        mesh ends where its data end), anything with ``log_f(c)`` (a cooling state, a
        predictor), or a callable giving :math:`\\ln f` at an array of velocities.
    options : MeshOptions, optional
        The other mesh options (order, Gauss degree) to keep; its ``vertices``,
        ``spacing`` and ``cutoff`` are replaced.
    rule : LogDropRule
        The placement (:data:`STATE_RULE`).

    Returns
    -------
    MeshOptions
        ``options`` with the vertices (``spacing`` and ``cutoff`` None).

    Raises
    ------
    TypeError
        If ``state`` is none of these.

    Examples
    --------
    >>> m = mesh_from_state(lambda c: -0.5 * c**2, MeshOptions(order=2))
    >>> m.order, float(m.vertices[-1]) > 13.5
    (2, True)
    """
    log_f = _log_density(state)
    vertices = log_drop_vertices(log_f, rule)
    return replace(options or MeshOptions(), vertices=vertices, spacing=None, cutoff=None)


def _log_density(state: Any) -> Callable[[NDArray[np.float64]], NDArray[np.float64]]:
    if isinstance(state, VelocityDistribution):
        def log_p(v: NDArray[np.float64]) -> NDArray[np.float64]:
            with np.errstate(divide="ignore"):
                return np.log(state.pdf(v))  # -inf beyond the data: the mesh ends there
        return log_p
    if callable(getattr(state, "log_f", None)):
        return state.log_f  # type: ignore[no-any-return]
    if callable(state):
        return state  # type: ignore[no-any-return]
    raise TypeError(f"state must be a VelocityDistribution, an object with log_f, or a "
                    f"callable ln f, got {type(state).__name__}")


NEWTON_NORMS = ("moments", "ln_p")
"""What the step Newton of an FEM transient converges (:class:`EvolveOptions`)."""


@option_group
@dataclass(frozen=True)
class EvolveOptions:
    """Numerical options of an FEM transient of the heated gas (None: the driver's default).

    Parameters
    ----------
    rtol : float
        Tolerance on the local error per collision time (relative on T, absolute on a2).
    order : int
        Lagrange degree, 1 or 2.
    spacing : float, optional
        Element size in thermal velocities of the coldest state (default
        :func:`~kinetic_fem.solvers.fem.evolution.default_transient_spacing`).
    cutoff : float, optional
        Half-width of the velocity interval in thermal velocities of the hottest state
        (default :func:`~kinetic_fem.solvers.fem.evolution.default_transient_cutoff`).
    first_step : float, optional
        First step and step after a discontinuity (default ``rtol`` collision times).
    max_step : float
        Largest step (inf: no limit).
    max_steps : int
        Accepted plus rejected steps before giving up.
    newton_tol : float, optional
        Newton tolerance on the update of ln P (default
        :func:`~kinetic_fem.solvers.fem.transient_setup.default_newton_tol`).
    max_newton : int
        Newton iterations per step before the step counts as failed.
    scheme : str
        Time scheme (:data:`~kinetic_fem.solvers.fem.transient_setup.SCHEMES`):
        ``"bdf4"`` (default: variable-step BDF4, 2-4 times fewer steps than BDF2 at
        default size and equal or smaller global error; a level after which no step
        converges is taken again by BDF2), ``"bdf3"`` or ``"bdf2"``.
    newton_norm : str
        What the step Newton converges: ``"moments"`` (default: the moments
        :math:`\\langle v^k\\rangle`, :math:`k \\le 12`, to ``newton_tol`` and every ln P to
        1e-2; about 2 iterations per step) or ``"ln_p"`` (every ln P to ``newton_tol``,
        2-3 times the iterations).  The memory-effect runs use ``"ln_p"``: on the moments'
        norm the hard-rod Kovacs quench at alpha 0.9 (spacing 0.25, rtol 1e-5, BDF2) reached
        a state from which no step converged (s = 1.288), with ``"ln_p"`` it runs through.

    Examples
    --------
    >>> EvolveOptions(rtol=1e-5).spacing is None
    True
    """

    rtol: float = 1e-4
    order: int = 2
    spacing: float | None = None
    cutoff: float | None = None
    first_step: float | None = None
    max_step: float = math.inf
    max_steps: int = 20000
    newton_tol: float | None = None
    max_newton: int = 12
    scheme: str = "bdf4"
    newton_norm: str = "moments"

    def __post_init__(self) -> None:
        if self.newton_norm not in NEWTON_NORMS:
            raise ValueError(f"newton_norm must be one of {NEWTON_NORMS}, got "
                             f"{self.newton_norm!r}")


@option_group
@dataclass(frozen=True)
class CoolingEvolveOptions(EvolveOptions):
    """Numerical options of an FEM transient of free cooling: those of
    :class:`EvolveOptions` with other defaults, and ``rescale``.

    Parameters
    ----------
    rtol : float
        Local error tolerance per step (relative on T, absolute on a2).
    spacing : float
        Element size in thermal velocities at the end of a segment (the coarsest).
    cutoff : float, optional
        Largest half-width of a mesh in thermal velocities at a segment's start (default
        :func:`~kinetic_fem.solvers.fem.cooling_transient.default_cooling_cutoff`).
    rescale : float
        Temperature ratio after which the state is remapped to the current thermal
        speed (> 1).
    scheme : str
        As in :class:`EvolveOptions`, default ``"bdf2"`` (BDF4 before the backtracking
        of issue 30 made two cooling tests take 86 s and 102 s against 8-16 s and 1.5 s;
        not yet measured over the cooling tests with it).
    newton_norm : str
        As in :class:`EvolveOptions`, default ``"ln_p"`` (free cooling's rescaled segments
        were measured with it).
    order, first_step, max_step, max_steps, newton_tol, max_newton
        As in :class:`EvolveOptions` (``first_step`` default: a tenth of
        :math:`\\sqrt{r_{tol}}` collision times).

    Examples
    --------
    >>> CoolingEvolveOptions().rescale
    4.0
    """

    rtol: float = 1e-6
    spacing: float | None = 0.25
    rescale: float = 4.0
    scheme: str = "bdf2"
    newton_norm: str = "ln_p"
