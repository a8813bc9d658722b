"""Public entry points of time-dependent problems: :func:`evolve_heated`, :func:`evolve_cooling`.

.. math::

    \\partial_t P = Q_{\\alpha(t)}[P] + \\partial_v(\\xi(t) v P) + D(t)\\,\\partial_v^2 P
    \\quad\\text{(heated)}, \\qquad \\partial_t P = Q_\\alpha[P] \\quad\\text{(cooling)},

from an initial distribution (any normalised
:class:`~kinetic_fem.distribution.VelocityDistribution`, or a Gaussian at
``initial_temperature``) to the requested output ``times``; the time dependence of
:math:`D`, :math:`\\xi` and :math:`\\alpha` is a :class:`~kinetic_fem.model.protocol.Protocol`.
Parameters are validated here; methods are registered in the one solver registry
(:data:`kinetic_fem.solve.SOLVERS`, problem kinds ``"transient-heated"`` and
``"transient-cooling"``; ``"fem"``: adaptive BDF2 on the Galerkin system,
:mod:`kinetic_fem.solvers.fem.evolution` and
:mod:`kinetic_fem.solvers.fem.cooling_transient`).
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import Any

from numpy.typing import ArrayLike

from .distribution import VelocityDistribution
from .evolution import Evolution
from .evolution_error import rerun_recipe
from .limits import check_cooling_span
from .mixture_evolution import MixtureEvolution, evolve_mixture
from .model import CollisionKernel, HeatedProblem, InelasticGas, RestitutionLaw, check_positive
from .model.mixture import Mixture
from .model.protocol import Protocol
from .model.validation import check_times
from .options import option_names
from .solve import lookup_solver
from .solvers.fem import cooling_transient, evolution  # noqa: F401  (register "fem")

__all__ = ["evolve_heated", "evolve_cooling", "check_times"]


def _evolve_mixture(mixture: Mixture, *, heated: bool, density: float, times: ArrayLike,
                    initial_temperature: Any, method: str, defaults: dict[str, tuple[Any, Any]],
                    options: dict[str, Any]) -> MixtureEvolution:
    """A :class:`Mixture` given as ``alpha``: :func:`.mixture_evolution.evolve_mixture`."""
    if mixture.heated != heated:
        kind, entry = (("heated", "evolve_heated") if mixture.heated
                       else ("free-cooling", "evolve_cooling"))
        raise ValueError(f"alpha is a {kind} mixture; use kf.{entry}")
    for name, (value, default) in defaults.items():
        if value is not default and value != default:
            raise ValueError(f"{name}={value!r} cannot be given with a Mixture (it carries its "
                             "kernel and a thermostat per species; Gaussian starts only)")
    unknown = set(options) - {"rtol"}
    if unknown and method != "fem":
        raise TypeError(f"unknown option(s) {sorted(unknown)} for a mixture (allowed: rtol)")
    return evolve_mixture(mixture, times=times, density=density,
                          initial_temperature=initial_temperature, method=method, **options)


def _with_progress(solver: Any, progress: bool | None,
                   options: dict[str, Any]) -> dict[str, Any]:
    """``options`` with ``progress`` resolved (None: when interactive), if the method takes it."""
    from .progress import resolve_progress

    show = resolve_progress(progress)
    if "progress" in inspect.signature(solver).parameters:
        return {**options, "progress": show}
    if progress:
        raise TypeError(f"method {getattr(solver, '__name__', solver)!r} has no progress "
                        f"bar; call it with progress=False or None")
    return options


def _initial(initial: Any, initial_temperature: Any) -> tuple[Any, float | None]:
    if initial is not None and initial_temperature is not None:
        raise ValueError("give either initial (a VelocityDistribution) or "
                         "initial_temperature (a Gaussian start), not both")
    if initial is not None and not isinstance(initial, VelocityDistribution):
        raise TypeError(f"initial must be a VelocityDistribution, got {type(initial).__name__}")
    if initial_temperature is not None:
        initial_temperature = check_positive("initial_temperature", initial_temperature)
    return initial, initial_temperature


def evolve_heated(alpha: float | RestitutionLaw, *, density: float = 1.0,
                  diffusion: float = 1.0, friction: float = 0.0,
                  kernel: float | CollisionKernel = 1.0,
                  initial_temperature: float | None = None,
                  initial: VelocityDistribution | None = None, times: ArrayLike,
                  protocol: Protocol | None = None, method: str = "fem",
                  progress: bool | None = None, **options: Any) -> Evolution:
    """Time-dependent heated gas under a protocol.

    Parameters
    ----------
    alpha : float, RestitutionLaw or Mixture
        Restitution at ``t = 0`` (changes are given by ``protocol.restitution``).  A
        heated :class:`~kinetic_fem.Mixture` returns a
        :class:`~kinetic_fem.mixture_evolution.MixtureEvolution` of the species
        temperatures from Gaussians at ``initial_temperature`` (a number or one per
        species; default 1) with ``method="fem"`` (the coupled FEM transient),
        ``"maxwell"`` (exact, kernel 0) or ``"gaussian"``
        (:func:`kinetic_fem.mixture_evolution.evolve_mixture`).
    density, diffusion, friction : float
        :math:`n`, :math:`D` and :math:`\\xi` (values at ``t = 0``, or throughout if the
        protocol leaves them alone).
    kernel : float or CollisionKernel
        ``gamma`` of :math:`|g|^\\gamma` (0 Maxwell, 1 hard rods) or a kernel object.
    initial_temperature : float, optional
        Start from the Gaussian at this temperature (default: the Gaussian-closure
        steady temperature of the parameters at ``t = 0``).
    initial : VelocityDistribution, optional
        Start from this normalised distribution instead (made even).
    times : array_like, shape (n_t,)
        Output times, strictly increasing, >= 0.
    protocol : Protocol, optional
        Time dependence of :math:`D`, :math:`\\xi` and the restitution.
    method : str
        Registry key (``"fem"``).
    progress : bool, optional
        A bar over the simulated time (tqdm, on stderr); default (None): shown when
        the session is interactive (a terminal or a notebook), quiet otherwise
        (:func:`kinetic_fem.progress.resolve_progress`).
    **options
        Passed to the method, e.g. ``rtol`` (tolerance on the local error per collision
        time, relative on T and absolute on a2, so that the global errors of T and a2 are
        about ``rtol`` or below; default 1e-4), ``spacing``, ``cutoff``, ``order``.

    Returns
    -------
    Evolution

    Raises
    ------
    ValueError, TypeError
        For invalid parameters, protocols, times or initial states, unknown methods
        or options.

    Examples
    --------
    >>> ev = evolve_heated(0.5, times=[0.0, 0.5], initial_temperature=0.5, spacing=0.5,
    ...                    rtol=1e-3)
    >>> bool(ev.temperature[1] > ev.temperature[0])
    True
    """
    if isinstance(alpha, Mixture):
        return _evolve_mixture(  # type: ignore[return-value]
            alpha, heated=True, density=density, times=times,
            initial_temperature=initial_temperature, method=method,
            defaults={"diffusion": (diffusion, 1.0), "friction": (friction, 0.0),
                      "kernel": (kernel, 1.0), "initial": (initial, None),
                      "protocol": (protocol, None)}, options=options)
    problem = HeatedProblem.from_parameters(alpha, density=density, diffusion=diffusion,
                                            friction=friction, kernel=kernel)
    if protocol is None:
        protocol = Protocol()
    if not isinstance(protocol, Protocol):
        raise TypeError(f"protocol must be a Protocol, got {type(protocol).__name__}")
    initial, initial_temperature = _initial(initial, initial_temperature)
    solver = lookup_solver("transient-heated", method)
    times = check_times(times)

    def run(**opts: Any) -> Evolution:
        return solver(problem, times=times, protocol=protocol, initial=initial,
                      initial_temperature=initial_temperature, **opts)

    return _with_error(run(**_with_progress(solver, progress, options)), run, solver,
                       options)


def evolve_cooling(alpha: float | RestitutionLaw, *, density: float = 1.0,
                   kernel: float | CollisionKernel = 1.0,
                   initial_temperature: float | None = None,
                   initial: VelocityDistribution | None = None, times: ArrayLike,
                   protocol: Protocol | None = None, method: str = "fem",
                   progress: bool | None = None, **options: Any) -> Evolution:
    """Free cooling from an initial state, :math:`T(t)` in physical units.

    :math:`\\partial_t P = n\\,Q_{\\alpha(t)}[P]` is integrated in physical velocities by
    adaptive BDF2 with local error control (``rtol``: relative on :math:`T`, absolute on
    :math:`a_2`), on segments of fixed velocity scale that are remapped to the current
    thermal speed each time :math:`T` has fallen by ``rescale`` (default 4), so that
    :math:`T(t)` is followed over many decades
    (:mod:`kinetic_fem.solvers.fem.cooling_transient`).  Mass is conserved to round-off
    and :math:`P = e^{u_h} > 0`.  Any restitution law (constant, viscoelastic,
    threshold) and any kernel (also one that is not homogeneous, e.g. the saturating
    kernel) is allowed, and ``protocol`` may change the restitution at given times (the
    integrator stops there and restarts).  ``ev.series["zeta"]`` is the instantaneous
    cooling rate in the convention :math:`dT/dt = -2\\zeta n T^{1+d/2}` (:math:`d` the
    kernel's ``scale_degree``: :math:`\\gamma` for a power law) and
    ``ev.series["cooling_rate"]`` is :math:`-d\\ln T/dt`, both with the law in force at the
    output time (the new one at a change time); for a constant coefficient and a power law
    :math:`\\zeta` tends at late times to the homogeneous cooling state's
    (:func:`kinetic_fem.solve_cooling`) and :math:`T(t)` to Haff's law.

    Parameters
    ----------
    alpha : float, RestitutionLaw or Mixture
        Restitution at ``t = 0``: a coefficient ``0 <= alpha <= 1`` or a law.  A
        free-cooling :class:`~kinetic_fem.Mixture`: as in :func:`evolve_heated`.
    density : float
        Number density ``n``.
    kernel : float or CollisionKernel
        ``gamma`` of :math:`|g|^\\gamma` or a kernel object.
    initial_temperature : float, optional
        Start from the Gaussian at this temperature (default 1).
    initial : VelocityDistribution, optional
        Start from this normalised distribution instead.
    times : array_like, shape (n_t,)
        Output times (physical units), strictly increasing, >= 0.
    protocol : Protocol, optional
        Restitution changes, ``Protocol(restitution=[(t1, alpha1), ...])``; a protocol
        with a thermostat (:math:`D` or :math:`\\xi`) is refused (free cooling has none:
        use :func:`evolve_heated`).
    method : str
        Registry key (``"fem"``).
    progress : bool, optional
        A bar over the simulated time (tqdm, on stderr); default (None): shown when
        the session is interactive (a terminal or a notebook), quiet otherwise
        (:func:`kinetic_fem.progress.resolve_progress`).
    **options
        Passed to the method: ``rtol`` (default 1e-6), ``spacing`` (element size in
        thermal velocities, default 0.25), ``cutoff``, ``rescale``, ``order``, step and
        Newton options (:func:`kinetic_fem.solvers.fem.cooling_transient.evolve_cooling_fem`).

    Returns
    -------
    Evolution

    Raises
    ------
    ValueError, TypeError
        For invalid parameters, times or initial states, unknown methods or options; a
        protocol with a thermostat; laws that are all elastic; a hot start whose relative
        speeds on the mesh exceed a law's range (viscoelastic ``max_speed``).
    ConvergenceError
        If the state can no longer be resolved on a mesh (refine ``spacing``).

    Examples
    --------
    >>> ev = evolve_cooling(0.8, times=[0.5, 1.0], spacing=0.5, rtol=1e-4)
    >>> bool(ev.temperature[1] < ev.temperature[0] < 1.0)
    True

    A quench of the restitution at :math:`t = 0.5`:

    >>> ev = evolve_cooling(0.9, times=[0.25, 0.5], spacing=0.5, rtol=1e-4,
    ...                     protocol=Protocol(restitution=[(0.5, 0.5)]))
    >>> z = ev.series["zeta"]             # at a change time: the new law's rate
    >>> bool(3.5 < z[1] / z[0] < 4.5)     # Gaussian estimate (1 - 0.25)/(1 - 0.81) = 3.9
    True
    """
    if isinstance(alpha, Mixture):
        return _evolve_mixture(  # type: ignore[return-value]
            alpha, heated=False, density=density, times=times,
            initial_temperature=initial_temperature, method=method,
            defaults={"kernel": (kernel, 1.0), "initial": (initial, None),
                      "protocol": (protocol, None)}, options=options)
    gas = InelasticGas(alpha, density, kernel)
    if protocol is None:
        protocol = Protocol()
    if not isinstance(protocol, Protocol):
        raise TypeError(f"protocol must be a Protocol, got {type(protocol).__name__}")
    initial, initial_temperature = _initial(initial, initial_temperature)
    times = check_times(times)
    check_cooling_span(gas, float(times[-1]), initial_temperature or (
        1.0 if initial is None else initial.temperature))
    solver = lookup_solver("transient-cooling", method)

    def run(**opts: Any) -> Evolution:
        return solver(gas, times=times, initial=initial,
                      initial_temperature=initial_temperature, protocol=protocol, **opts)

    return _with_error(run(**_with_progress(solver, progress, options)), run, solver,
                       options)


def _with_error(ev: Evolution, run: Callable[..., Evolution], solver: Callable[..., Any],
                options: dict[str, Any]) -> Evolution:
    """``ev`` with its lazy error estimate (:mod:`kinetic_fem.evolution_error`)."""
    if "rtol" not in options and "rtol" not in (option_names(solver) or ()):
        return ev   # a method without a tolerance: no estimate from it
    return ev.with_error(rerun_recipe(run, solver, dict(options)))
