"""Relaxation of the species temperatures of a mixture in time: :func:`evolve_mixture`.

The homogeneous Boltzmann equations of a mixture (:mod:`kinetic_fem.model.mixture`) from
Gaussian species at given temperatures :math:`T_s(0)` to the requested output times, in
physical units (free cooling is not rescaled).  Two methods, both cheap ODE systems:

* ``"maxwell"``: the inelastic Maxwell mixture (kernel :math:`\\gamma = 0`) has closed
  moment equations (:func:`kinetic_fem.solvers.maxwell_mixture.moment_rates`); the moments
  up to order 4 are integrated exactly (to the ODE tolerance), so :math:`T_s(t)` and
  :math:`a_{2,s}(t)` are exact;
* ``"gaussian"``: any kernel, every species kept Gaussian
  (:func:`kinetic_fem.solvers.mixture_gaussian.variance_rates`), :math:`a_{2,s} = 0`;
* ``"fem"``: the coupled Galerkin system of the species integrated by the one-species
  adaptive BDF integrator; heated (:mod:`kinetic_fem.solvers.fem.mixture_transient`, any
  compiled kernel) or free cooling on segments of fixed velocity unit, remapped as the
  temperatures fall (:mod:`kinetic_fem.solvers.fem.mixture_cooling_transient`, any
  compiled kernel; it also keeps every species' distribution at the output times and the
  cooling rates); ``ev.error`` reruns it at ``rtol / 100`` (heated: on the same meshes;
  cooling: with the same options) when first read.

The DSMC time series of the same problem is
:func:`particles.dsmc_mixture.evolve_mixture` (it returns a :class:`MixtureEvolution`
with standard errors).  :func:`kinetic_fem.evolve_heated` and
:func:`kinetic_fem.evolve_cooling` given a :class:`~kinetic_fem.Mixture` call
:func:`evolve_mixture`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .distribution import VelocityDistribution
from .model.mixture import Mixture
from .model.validation import UnsupportedModelError, check_positive, check_times

__all__ = ["MixtureEvolution", "MixtureEvolutionError", "evolve_mixture",
           "MIXTURE_EVOLUTION_METHODS",
           "initial_temperatures_of"]

#: the methods of :func:`evolve_mixture`
MIXTURE_EVOLUTION_METHODS = ("maxwell", "gaussian", "fem")


@dataclass(frozen=True, eq=False)
class MixtureEvolution:
    """Species temperatures of a mixture over time.

    Parameters
    ----------
    mixture : Mixture
    times : ndarray, shape (n_t,)
    temperatures : ndarray, shape (n_t, k)
        :math:`T_s(t) = m_s\\langle v^2\\rangle_s`.
    a2 : ndarray, shape (n_t, k)
        :math:`a_{2,s}(t)` (0 for ``"gaussian"``).
    method : str
    temperature_errors, a2_errors : ndarray, shape (n_t, k), optional
        Standard errors (sampling methods).
    info : dict
    distributions : tuple of tuple of VelocityDistribution, optional
        ``distributions[i][s]``: species ``s`` at ``times[i]`` (FEM, heated and free
        cooling).
    series : dict of ndarray
        More series over ``times`` (FEM free cooling: ``"zeta"``,
        :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}` of the mixture temperature,
        ``"cooling_rate"`` :math:`-d\\ln T/dt`, ``"species_cooling_rates"``
        :math:`-d\\ln T_s/dt` of shape (n_t, k), ``"segments"``).
    """

    mixture: Mixture
    times: NDArray[np.float64]
    temperatures: NDArray[np.float64]
    a2: NDArray[np.float64]
    method: str
    temperature_errors: NDArray[np.float64] | None = None
    a2_errors: NDArray[np.float64] | None = None
    info: dict[str, Any] = field(default_factory=dict)
    error_recipe: Callable[[MixtureEvolution], MixtureEvolution] | None = field(
        default=None, repr=False, compare=False)
    distributions: tuple[tuple[VelocityDistribution, ...], ...] | None = field(
        default=None, repr=False)
    series: dict[str, NDArray[np.float64]] = field(default_factory=dict, repr=False)

    @cached_property
    def error(self) -> MixtureEvolutionError | None:
        """Estimated global errors of the time integration (``"fem"``), or None.

        The same evolution at ``rtol / 100`` on the same meshes (computed when first
        read), the difference times :math:`1/(1 - 1/100)`, as for one species
        (:mod:`kinetic_fem.evolution_error`).
        """
        if self.error_recipe is None:
            return None
        better = self.error_recipe(self)
        kappa = 1.0 / (1.0 - 1.0 / 100.0)
        ratio = self.temperatures[:, :, None] / self.temperatures[:, None, :]
        ratio_b = better.temperatures[:, :, None] / better.temperatures[:, None, :]
        return MixtureEvolutionError(
            kappa * np.abs(self.temperatures / better.temperatures - 1.0),
            kappa * np.abs(self.a2 - better.a2), kappa * np.abs(ratio / ratio_b - 1.0))

    @property
    def temperature(self) -> NDArray[np.float64]:
        """The mixture temperature :math:`T(t) = \\sum_s x_s T_s(t)`, shape (n_t,)."""
        return self.temperatures @ np.asarray(self.mixture.fractions)

    def temperature_ratio(self, s: int = 0, r: int = 1) -> NDArray[np.float64]:
        """:math:`T_s(t)/T_r(t)`, shape (n_t,)."""
        return self.temperatures[:, s] / self.temperatures[:, r]

    def temperature_ratio_error(self, s: int = 0, r: int = 1) -> NDArray[np.float64] | None:
        """Standard error of :meth:`temperature_ratio` (first-order propagation), or None."""
        if self.temperature_errors is None:
            return None
        rel = np.hypot(self.temperature_errors[:, s] / self.temperatures[:, s],
                       self.temperature_errors[:, r] / self.temperatures[:, r])
        return np.asarray(self.temperature_ratio(s, r) * rel)


@dataclass(frozen=True)
class MixtureEvolutionError:
    """Estimated errors of a :class:`MixtureEvolution` (``ev.error``).

    Parameters
    ----------
    temperatures : ndarray, shape (n_t, k)
        Relative errors of :math:`T_s(t_i)`.
    a2 : ndarray, shape (n_t, k)
        Absolute errors of :math:`a_{2,s}(t_i)`.
    ratios : ndarray, shape (n_t, k, k)
        Relative errors of :math:`T_s/T_r`.
    """

    temperatures: NDArray[np.float64]
    a2: NDArray[np.float64]
    ratios: NDArray[np.float64]


def initial_temperatures_of(mixture: Mixture, initial_temperature: object
                            ) -> NDArray[np.float64]:
    """:math:`T_s(0)` from None (1 for every species), a float or one value per species.

    Parameters
    ----------
    mixture : Mixture
        The mixture (its number of species).
    initial_temperature : None, float or sequence of float
        The initial temperatures.

    Returns
    -------
    ndarray, shape (k,)

    Raises
    ------
    ValueError, TypeError
        Naming ``initial_temperature``.
    """
    k = mixture.n_species
    if initial_temperature is None:
        return np.ones(k)
    if isinstance(initial_temperature, (Sequence, np.ndarray)) \
            and not isinstance(initial_temperature, (str, bytes)):
        values = list(initial_temperature)
        if len(values) != k:
            raise ValueError(f"initial_temperature must be a number or one temperature per "
                             f"species ({k}), got {initial_temperature!r}")
        return np.array([check_positive(f"initial_temperature[{i}]", t)
                         for i, t in enumerate(values)])
    return np.full(k, check_positive("initial_temperature", initial_temperature))


def _times(times: ArrayLike) -> NDArray[np.float64]:
    return check_times(times)


def evolve_mixture(mixture: Mixture, *, times: ArrayLike, density: float = 1.0,
                   initial_temperature: float | Sequence[float] | None = None,
                   method: str = "maxwell", rtol: float | None = None,
                   **fem_options: Any) -> MixtureEvolution:
    """Species temperatures of a mixture from Gaussian species at ``initial_temperature``.

    Parameters
    ----------
    mixture : Mixture
        Forced species (heated) or none (free cooling); any restitution law per pair
        (``"maxwell"``: constant coefficients).
    times : array_like, shape (n_t,)
        Output times, >= 0, strictly increasing.
    density : float
        Total number density :math:`n`.
    initial_temperature : float or sequence of float, optional
        :math:`T_s(0)`: one value for every species or one per species (default 1).
    method : {"maxwell", "gaussian", "fem"}
        Exact moments of the Maxwell mixture (kernel 0), Gaussian species (any kernel),
        or the FEM transient (any compiled kernel, any restitution law per pair).
    rtol : float, optional
        Relative tolerance of the ODE integration (absolute: ``rtol`` times 1e-6 of the
        initial moments; default 1e-10); ``"fem"``: the tolerance of the local error
        per collision time on every :math:`T_s` and :math:`a_{2,s}` (default 1e-4
        heated, 1e-6 free cooling).
    **fem_options
        ``"fem"`` only.  Heated: ``vertices`` (explicit meshes) and the fields of
        :class:`~kinetic_fem.solvers.fem.options.EvolveOptions` (``spacing``,
        ``cutoff``, ``order``, ``scheme``, ...); free cooling: the fields of
        :class:`~kinetic_fem.solvers.fem.options.CoolingEvolveOptions` (also
        ``rescale``).

    Returns
    -------
    MixtureEvolution

    Raises
    ------
    UnsupportedModelError
        ``"maxwell"`` for a kernel other than 0 or a velocity-dependent restitution law.
    ValueError
        An unknown method, bad times or temperatures.

    Examples
    --------
    >>> mix = Mixture.white_noise((1.0, 4.0), (0.5, 0.5), alpha=0.8, kernel=0.0)
    >>> ev = evolve_mixture(mix, times=[0.0, 200.0])
    >>> from kinetic_fem.solvers import maxwell_mixture
    >>> steady = maxwell_mixture.steady_state(mix).temperature_ratio()
    >>> bool(abs(ev.temperature_ratio()[-1] - steady) < 1e-8)
    True
    """
    if not isinstance(mixture, Mixture):
        raise TypeError(f"mixture must be a kinetic_fem.Mixture, got {mixture!r}")
    if method not in MIXTURE_EVOLUTION_METHODS:
        raise ValueError(f"method must be one of {MIXTURE_EVOLUTION_METHODS} for a mixture, "
                         f"got {method!r}")
    t = _times(times)
    density = check_positive("density", density)
    if fem_options and method != "fem":
        raise TypeError(f"unknown option(s) {sorted(fem_options)} for method={method!r} "
                        "(allowed: rtol)")
    if method == "fem":
        return _evolve_fem(mixture, t, density, initial_temperature, rtol, fem_options)
    rtol = check_positive("rtol", 1e-10 if rtol is None else rtol)
    var0 = initial_temperatures_of(mixture, initial_temperature) / np.asarray(mixture.masses)
    k = mixture.n_species
    from .solvers import mixture_gaussian

    if method == "maxwell":
        from .solvers import maxwell_mixture

        mixture.constant_alpha()  # the moment equations close for constant coefficients
        if mixture.collision_kernel.gamma != 0.0:
            raise UnsupportedModelError(
                f"method='maxwell' is the Maxwell mixture (kernel 0), got kernel "
                f"{mixture.collision_kernel!r}; use method='gaussian' (any kernel) or "
                "particles.dsmc_mixture.evolve_mixture")
        m0 = np.zeros((k, 5))
        m0[:, 0] = 1.0
        m0[:, 2] = var0
        m0[:, 4] = 3.0 * var0**2

        def rhs(_: float, y: NDArray[np.float64]) -> NDArray[np.float64]:
            return maxwell_mixture.moment_rates(mixture, y.reshape(k, 5), density).ravel()

        y, nfev = mixture_gaussian.integrate(rhs, m0.ravel(), t, rtol)
        mom = y.reshape(t.size, k, 5)
        var, a2 = mom[:, :, 2], mom[:, :, 4] / (3.0 * mom[:, :, 2]**2) - 1.0
    else:
        var, nfev = mixture_gaussian.integrate(
            lambda _, y: mixture_gaussian.variance_rates(mixture, y, density), var0, t, rtol)
        a2 = np.zeros((t.size, k))
    masses = np.asarray(mixture.masses)
    return MixtureEvolution(mixture, t, var * masses[None, :], a2, method,
                            info={"nfev": nfev, "rtol": rtol, "density": density})


def _evolve_fem(mixture: Mixture, t: NDArray[np.float64], density: float,
                initial_temperature: Any, rtol: float | None,
                options: dict[str, Any]) -> MixtureEvolution:
    """``method="fem"``: :func:`kinetic_fem.solvers.fem.mixture_transient.evolve_mixture_fem`
    (heated) or
    :func:`kinetic_fem.solvers.fem.mixture_cooling_transient.evolve_mixture_cooling_fem`
    (free cooling), with the lazy error estimate (the same run at ``rtol / 100``)."""
    t0 = initial_temperatures_of(mixture, initial_temperature)
    if rtol is not None:
        options = {**options, "rtol": check_positive("rtol", rtol)}
    if not mixture.heated:
        from .solvers.fem.mixture_cooling_transient import evolve_mixture_cooling_fem

        run = evolve_mixture_cooling_fem(mixture, times=t, density=density,
                                         initial_temperatures=t0, **options)
        ev = MixtureEvolution(mixture, t, run.temperatures, run.a2, "fem", info=run.info,
                              distributions=run.distributions, series=run.series)
        rerun = options
    else:
        from .solvers.fem.mixture_transient import evolve_mixture_fem

        temps, a2, dists, info = evolve_mixture_fem(mixture, times=t, density=density,
                                                    initial_temperatures=t0, **options)
        ev = MixtureEvolution(mixture, t, temps, a2, "fem", info=info, distributions=dists)
        rerun = {**options, "vertices": info["vertices"]}
    tol = float(ev.info["rtol"])

    def recipe(ev: MixtureEvolution) -> MixtureEvolution:
        return _evolve_fem(mixture, t, density, t0, None, {**rerun, "rtol": tol / 100.0})

    return replace(ev, error_recipe=recipe)
