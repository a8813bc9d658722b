"""Relaxation of the species temperatures of a mixture in time: :func:`evolve_mixture`.

The homogeneous Boltzmann equations of a mixture (:mod:`kinetic_fem.model.mixture`) from
Gaussian species at given temperatures :math:`T_s(0)` to the requested output times, in
physical units (free cooling is not rescaled).  Two methods, both cheap ODE systems:

* ``"maxwell"``: the inelastic Maxwell mixture (kernel :math:`\\gamma = 0`) has closed
  moment equations (:func:`kinetic_fem.solvers.maxwell_mixture.moment_rates`); the moments
  up to order 4 are integrated exactly (to the ODE tolerance), so :math:`T_s(t)` and
  :math:`a_{2,s}(t)` are exact;
* ``"gaussian"``: any kernel, every species kept Gaussian
  (:func:`kinetic_fem.solvers.mixture_gaussian.variance_rates`), :math:`a_{2,s} = 0`.

The DSMC time series of the same problem is
:func:`particles.dsmc_mixture.evolve_mixture` (it returns a :class:`MixtureEvolution`
with standard errors).  :func:`kinetic_fem.evolve_heated` and
:func:`kinetic_fem.evolve_cooling` given a :class:`~kinetic_fem.Mixture` call
:func:`evolve_mixture`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import solve_ivp

from .model.mixture import Mixture
from .model.validation import UnsupportedModelError, check_positive, check_times

__all__ = ["MixtureEvolution", "evolve_mixture", "MIXTURE_EVOLUTION_METHODS",
           "initial_temperatures_of"]

#: the methods of :func:`evolve_mixture`
MIXTURE_EVOLUTION_METHODS = ("maxwell", "gaussian")


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
    """

    mixture: Mixture
    times: NDArray[np.float64]
    temperatures: NDArray[np.float64]
    a2: NDArray[np.float64]
    method: str
    temperature_errors: NDArray[np.float64] | None = None
    a2_errors: NDArray[np.float64] | None = None
    info: dict[str, Any] = field(default_factory=dict)

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
                   method: str = "maxwell", rtol: float = 1e-10) -> MixtureEvolution:
    """Species temperatures of a mixture from Gaussian species at ``initial_temperature``.

    Parameters
    ----------
    mixture : Mixture
        Constant restitution per pair; forced species (heated) or none (free cooling).
    times : array_like, shape (n_t,)
        Output times, >= 0, strictly increasing.
    density : float
        Total number density :math:`n`.
    initial_temperature : float or sequence of float, optional
        :math:`T_s(0)`: one value for every species or one per species (default 1).
    method : {"maxwell", "gaussian"}
        Exact moments of the Maxwell mixture (kernel 0), or Gaussian species (any kernel).
    rtol : float
        Relative tolerance of the ODE integration (absolute: ``rtol`` times 1e-6 of the
        initial moments).

    Returns
    -------
    MixtureEvolution

    Raises
    ------
    UnsupportedModelError
        ``"maxwell"`` for a kernel other than 0; a velocity-dependent restitution law.
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
        raise ValueError(f"method must be one of {MIXTURE_EVOLUTION_METHODS} for a mixture "
                         f"(no FEM transient of mixtures), got {method!r}")
    t = _times(times)
    density = check_positive("density", density)
    rtol = check_positive("rtol", rtol)
    mixture.constant_alpha()
    var0 = initial_temperatures_of(mixture, initial_temperature) / np.asarray(mixture.masses)
    k = mixture.n_species
    if method == "maxwell":
        from .solvers import maxwell_mixture

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

        y0 = m0.ravel()
    else:
        from .solvers import mixture_gaussian

        def rhs(_: float, y: NDArray[np.float64]) -> NDArray[np.float64]:
            return mixture_gaussian.variance_rates(mixture, y, density)

        y0 = var0
    atol = rtol * 1e-6 * np.maximum(np.abs(y0), float(np.max(np.abs(y0))))
    sol = solve_ivp(rhs, (0.0, float(t[-1])), y0, method="DOP853", t_eval=t, rtol=rtol,
                    atol=atol)
    if not sol.success:
        raise RuntimeError(f"the mixture's moment equations failed to integrate: "
                           f"{sol.message}")
    masses = np.asarray(mixture.masses)
    if method == "maxwell":
        mom = sol.y.T.reshape(t.size, k, 5)
        var, a2 = mom[:, :, 2], mom[:, :, 4] / (3.0 * mom[:, :, 2]**2) - 1.0
    else:
        var, a2 = sol.y.T, np.zeros((t.size, k))
    return MixtureEvolution(mixture, t, var * masses[None, :], a2, method,
                            info={"nfev": int(sol.nfev), "rtol": rtol, "density": density})
