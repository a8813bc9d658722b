"""Public entry points and the registry of deterministic solvers.

Each solver registers itself under a key (``"fem"``, ``"fd"``, ``"spectral"``) and a
problem kind (steady ``"heated"``, ``"cooling"``; ``"transient-heated"``,
``"transient-cooling"``) with :func:`register_solver`, in one registry
(:data:`SOLVERS`); :func:`solve_heated` and :func:`solve_cooling`
validate the parameters once and dispatch.  A solver is a function
``solver(problem, **options) -> VelocityDistribution`` whose options are explicit
keyword arguments, so a misspelt option raises ``TypeError``.  Tests parametrise
over :data:`HEATED_SOLVERS`, so a new solver is tested automatically.
"""

from __future__ import annotations

import importlib
from typing import Any, Callable

from . import limits
from .model import CollisionKernel, CoolingProblem, HeatedProblem, RestitutionLaw
from .model.mixture import Mixture
from .progress import resolve_progress, working

__all__ = ["SOLVERS", "PROBLEM_KINDS", "HEATED_SOLVERS", "COOLING_SOLVERS",
           "TRANSIENT_HEATED_SOLVERS", "TRANSIENT_COOLING_SOLVERS", "register_solver",
           "lookup_solver", "solve_heated", "solve_cooling"]

Solver = Callable[..., Any]
PROBLEM_KINDS = ("heated", "cooling", "transient-heated", "transient-cooling",
                 "mixture-heated", "mixture-cooling")
"""The problem kinds of the registry: steady states (``solver(problem, **options) ->
VelocityDistribution``), transients (``solver(problem_or_gas, *, times, ...) ->
Evolution``, see :mod:`kinetic_fem.evolve`) and the states of a mixture
(``solver(mixture, *, density, **options) -> MixtureState``, reached by passing a
:class:`~kinetic_fem.model.Mixture` as ``alpha``)."""
SOLVERS: dict[str, dict[str, Solver]] = {kind: {} for kind in PROBLEM_KINDS}
"""The one registry: solvers by problem kind and method key."""
HEATED_SOLVERS: dict[str, Solver] = SOLVERS["heated"]
COOLING_SOLVERS: dict[str, Solver] = SOLVERS["cooling"]
TRANSIENT_HEATED_SOLVERS: dict[str, Solver] = SOLVERS["transient-heated"]
TRANSIENT_COOLING_SOLVERS: dict[str, Solver] = SOLVERS["transient-cooling"]


def register_solver(key: str, *, problem: str) -> Callable[[Solver], Solver]:
    """Decorator registering ``solver`` under ``key`` for a problem kind.

    Parameters
    ----------
    key : str
        Method name (``method=key`` selects it).
    problem : {"heated", "cooling", "transient-heated", "transient-cooling"}
        The problem kind (:data:`PROBLEM_KINDS`).

    Returns
    -------
    callable
        A decorator returning the solver unchanged.

    Raises
    ------
    ValueError
        For an unknown problem kind.
    """
    if problem not in SOLVERS:
        raise ValueError(f"unknown problem kind {problem!r}; allowed: {list(PROBLEM_KINDS)}")
    table = SOLVERS[problem]

    def decorate(solver: Solver) -> Solver:
        if key in table:
            raise ValueError(f"a {problem} solver is already registered as {key!r}")
        table[key] = solver
        return solver

    return decorate


def lookup_solver(problem: str, method: str) -> Solver:
    """The solver registered as ``method`` for the problem kind ``problem``.

    Parameters
    ----------
    problem : str
        A problem kind of :data:`PROBLEM_KINDS`.
    method : str
        The registry key.

    Returns
    -------
    callable

    Raises
    ------
    ValueError
        For an unknown method (the message lists the available ones).
    """
    return _lookup(SOLVERS[problem], method, problem)


def _lookup(table: dict[str, Solver], method: str, problem: str) -> Solver:
    importlib.import_module(__package__).load_solvers()  # solver modules register on import
    if not isinstance(method, str) or method not in table:
        raise ValueError(f"unknown {problem} method {method!r}; available: {sorted(table)}")
    return table[method]


def _solve_mixture(kind: str, mixture: Mixture, method: str, density: float,
                   defaults: dict[str, tuple[Any, Any]], options: dict[str, Any]) -> Any:
    """Dispatch a mixture to the solver registered for ``mixture-<kind>``; the model's
    parameters other than the density belong to the :class:`Mixture`."""
    for name, (given, default) in defaults.items():
        if given != default:
            raise ValueError(f"{name}={given!r} does not apply to a Mixture: give the "
                             f"{name} of each species in the Mixture (its kernel and "
                             "thermostats, e.g. Mixture.white_noise)")
    solver = _lookup(SOLVERS[f"mixture-{kind}"], method, f"mixture-{kind}")
    return solver(mixture, density=density, **options)


def solve_heated(alpha: float | RestitutionLaw | Mixture, *, density: float = 1.0,
                 diffusion: float = 1.0, friction: float = 0.0,
                 kernel: float | CollisionKernel = 1.0, method: str = "fem",
                 progress: bool | None = None, **options: Any) -> Any:
    """Steady state of the heated inelastic gas.

    Parameters
    ----------
    alpha : float, RestitutionLaw or Mixture
        Restitution coefficient, ``0 <= alpha < 1`` (``alpha = 1`` with ``friction > 0``),
        or a law :math:`\\alpha(g)` (:mod:`kinetic_fem.model`); or a heated
        :class:`~kinetic_fem.model.Mixture` (its species carry the kernel and the
        thermostats; ``method="fem"``; the result is a
        :class:`~kinetic_fem.mixture_state.MixtureState`).
    density, diffusion : float
        Number density :math:`n > 0` and noise strength :math:`D > 0`.
    friction : float
        Friction :math:`\\xi \\ge 0` of a Fokker-Planck bath (0: white noise, the paper).
    kernel : float or CollisionKernel
        Collision kernel: ``gamma`` in ``[0, 2]`` of :math:`|g|^\\gamma` (1: hard rods), or
        a kernel object (:class:`~kinetic_fem.model.CollisionKernel`; ``"fem"`` takes
        every kernel, the other methods power laws).
    method : str
        Registry key: ``"fem"`` (Galerkin, Newton), ``"fd"`` (the paper's iteration), ...
    progress : bool, optional
        A line with the solve's name and a moving clock on stderr if the solve is still
        running after 2 s (near-elastic states, fine meshes); default (None): when the
        session is interactive (:mod:`kinetic_fem.progress`).
    **options
        Passed to the solver; see its documentation.

    Returns
    -------
    VelocityDistribution

    Raises
    ------
    ValueError, TypeError
        For invalid parameters, an unknown method or an unknown option.
    UnsupportedModelError
        (a ValueError) if the method cannot solve this model; the message says which can.
    ValueError
        Also for parameters whose temperature lies outside
        :data:`kinetic_fem.limits.TEMPERATURE_RANGE`, or alpha beyond the method's
        near-elastic frontier (:data:`kinetic_fem.limits.FRONTIER`).
    ConvergenceError
        If a result that says converged is not a physical state
        (:func:`kinetic_fem.limits.check_result`).

    Examples
    --------
    The paper's gas (hard rods, white noise, ``n = D = 1``) at alpha = 0.6, by FEM and
    by the Sonine spectral method, beside the first-order Sonine estimate:

    >>> import kinetic_fem as kf
    >>> dist = kf.solve_heated(0.6)
    >>> dist.info.converged, round(dist.temperature, 6), round(dist.a2, 6)
    (True, 1.964799, 0.030435)
    >>> abs(kf.solve_heated(0.6, method="spectral").a2 - dist.a2) < 1e-5
    True
    >>> round(kf.sonine.a2_first_order(0.6), 4)
    0.032
    """
    resolve_progress(progress)  # a bad value fails before any work
    if isinstance(alpha, Mixture):
        with working(f"solve_heated (mixture, {method})", progress):
            return _solve_mixture("heated", alpha, method, density,
                                  {"diffusion": (diffusion, 1.0), "friction": (friction, 0.0),
                                   "kernel": (kernel, 1.0)}, options)
    problem = HeatedProblem.from_parameters(alpha, density=density, diffusion=diffusion,
                                            friction=friction, kernel=kernel)
    solver = _lookup(HEATED_SOLVERS, method, "heated")
    limits.check_frontier(problem, method, options)
    limits.check_scale(problem)
    with working(f"solve_heated ({method})", progress):
        return limits.check_result(solver(problem, **options))


def solve_cooling(alpha: float | RestitutionLaw | Mixture, *, density: float = 1.0,
                  kernel: float | CollisionKernel = 1.0, method: str = "fem",
                  progress: bool | None = None, **options: Any) -> Any:
    """Homogeneous cooling state in scaled variables (see :func:`solve_heated`).

    The result has unit temperature; its cooling rate :math:`\\zeta`, defined by
    :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`, is ``dist.info.extra["zeta"]``.

    Parameters
    ----------
    alpha : float, RestitutionLaw or Mixture
        Constant coefficient of restitution, ``0 <= alpha < 1``; or a
        :class:`~kinetic_fem.model.Mixture` without forcing (``method="fem"``: the
        scaled state of every species with one cooling rate, a
        :class:`~kinetic_fem.mixture_state.MixtureState` with ``zeta``).
    density : float
        Number density ``n`` (the scaled state does not depend on it).
    kernel : float or CollisionKernel
        Collision kernel :math:`|g|^\\gamma` (homogeneous kernels only).
    method : str
        ``"fem"`` (default), ``"fd"`` or ``"spectral"``.
    progress : bool, optional
        As for :func:`solve_heated`.
    **options
        Passed to the method (see its solver function).

    Returns
    -------
    VelocityDistribution
        The homogeneous cooling state at unit temperature.

    Examples
    --------
    >>> import kinetic_fem as kf
    >>> hcs = kf.solve_cooling(0.5)
    >>> round(hcs.temperature, 10), round(hcs.info.extra["zeta"], 8), round(hcs.a2, 7)
    (1.0, 0.43556748, 0.1610182)
    """
    resolve_progress(progress)  # a bad value fails before any work
    if isinstance(alpha, Mixture):
        with working(f"solve_cooling (mixture, {method})", progress):
            return _solve_mixture("cooling", alpha, method, density,
                                  {"kernel": (kernel, 1.0)}, options)
    problem = CoolingProblem.from_parameters(alpha, density=density, kernel=kernel)
    solver = _lookup(COOLING_SOLVERS, method, "cooling")
    limits.check_frontier(problem, method, options)
    # the Maxwell model's cooling state has a c^-4 tail: no finite <c^4> to resolve
    with working(f"solve_cooling ({method})", progress):
        return limits.check_result(solver(problem, **options),
                                   check_tail=not problem.gas.kernel.is_maxwell)
