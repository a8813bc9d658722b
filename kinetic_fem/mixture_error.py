"""Error estimates of a mixture's state: one per species, the temperature ratio and zeta.

A :class:`~kinetic_fem.mixture_state.MixtureState` from a deterministic solver answers
``state.error`` with a :class:`MixtureError`: the :class:`~kinetic_fem.error.ErrorEstimate`
of every species (the names of one species: ``temperature`` relative, ``a2`` absolute,
``f(c)`` relative; also ``state.distributions[s].error``), the relative errors of the
temperature ratios :math:`T_s/T_r` and of the mixture temperature, and in free cooling
the relative error of the common cooling rate :math:`\\zeta`.  As for one species
(:mod:`kinetic_fem.error`) the estimate is the difference from a better result times
:math:`\\kappa`:

- FEM: one Newton step of the coupled system on the meshes with every element bisected
  (:func:`kinetic_fem.solvers.fem.mixture_error.fem_mixture_recipe`),
  :math:`\\kappa = 1/(1 - 2^{-(k+1)})`;
- Sonine Galerkin: the orders :math:`P \\pm 2`, the geometric tail of the changes, flagged
  ``asymptotic`` when they stop decreasing
  (:func:`kinetic_fem.solvers.mixture_spectral.order_recipe`).

Estimates are computed when first read (cached; shared by the species' distributions),
so a solve costs nothing extra; they do not survive pickling.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .error import ErrorEstimate, ErrorRecipe

__all__ = ["MixtureError", "MixtureErrorRecipe", "compare_species"]


@dataclass(frozen=True)
class MixtureError:
    """Estimated errors of a mixture state (``state.error``).

    Attributes
    ----------
    species : tuple of ErrorEstimate
        The estimate of each species' distribution (``temperature`` relative, ``a2``
        absolute, ``f(c)`` relative), the same object as ``state.distributions[s].error``.
    ratios : ndarray, shape (k, k)
        Relative error of :math:`T_s/T_r`.
    temperature : float
        Relative error of the mixture temperature :math:`T = \\sum_s x_s T_s`.
    zeta : float or None
        Relative error of the common cooling rate (free cooling), else None.
    method : str
        How the estimate was obtained.
    asymptotic : bool
        The method's sequence of approximations stopped converging (the error may be
        larger than estimated).
    note : str
        Anything else the user should know.
    """

    species: tuple[ErrorEstimate, ...]
    ratios: NDArray[np.float64]
    temperature: float
    zeta: float | None = None
    method: str = ""
    asymptotic: bool = False
    note: str = ""

    def temperature_ratio(self, s: int = 0, r: int = 1) -> float:
        """Relative error of :math:`T_s/T_r` (default: species 0 over species 1)."""
        return float(self.ratios[s, r])

    @property
    def temperatures(self) -> NDArray[np.float64]:
        """Relative errors of the species temperatures :math:`T_s`, shape (k,)."""
        return np.array([e.temperature for e in self.species])

    @property
    def a2(self) -> NDArray[np.float64]:
        """Absolute errors of :math:`a_{2,s}`, shape (k,)."""
        return np.array([e.a2 for e in self.species])

    def meets(self, target: float) -> bool:
        """Whether every species' T and a2 errors, the ratios' and zeta's are below
        ``target``."""
        worst = max(float(np.max(self.ratios)), self.temperature, self.zeta or 0.0)
        return all(e.meets(target) for e in self.species) and worst <= target

    def __repr__(self) -> str:
        zeta = "" if self.zeta is None else f", zeta={self.zeta:.2g}"
        flags = ", asymptotic=True" if self.asymptotic else ""
        return (f"MixtureError(T_s={np.array2string(self.temperatures, precision=2)}, "
                f"a2={np.array2string(self.a2, precision=2)}, "
                f"ratio={self.temperature_ratio() if len(self.species) > 1 else 0.0:.2g}"
                f"{zeta}, method={self.method!r}{flags})")

    @classmethod
    def unavailable(cls, k: int, reason: str, *, method: str = "none") -> MixtureError:
        """NaN estimates of ``k`` species that say why there are none."""
        one = ErrorEstimate.unavailable(reason, method=method)
        return cls((one,) * k, np.full((k, k), np.nan), float("nan"), None, method=method,
                   note=reason)


def compare_species(mine: Sequence[Any], better: Sequence[Any], masses: Sequence[float],
                    fractions: Sequence[float], *, method: str, factor: float = 1.0,
                    zeta: tuple[float, float] | None = None) -> MixtureError:
    """The estimate ``factor`` times the difference of one state from a better one.

    Parameters
    ----------
    mine, better : sequence of VelocityDistribution
        Each species' distribution of the result and of a more accurate result.
    masses, fractions : sequence of float
        :math:`m_s`, :math:`x_s`.
    method : str
        How ``better`` was obtained.
    factor : float
        :math:`\\kappa`, the ratio of the result's error to the difference.
    zeta : (float, float), optional
        The result's and the better result's cooling rates.

    Returns
    -------
    MixtureError
    """
    species = tuple(ErrorEstimate.from_comparison(a, b, method=method, factor=factor,
                                                  zeta=zeta)
                    for a, b in zip(mine, better, strict=True))
    m = np.asarray(masses, dtype=float)
    t_mine = m * np.array([d.moment(2, central=False) for d in mine])
    t_better = m * np.array([d.moment(2, central=False) for d in better])
    ratios = factor * np.abs((t_better[:, None] / t_better[None, :])
                             / (t_mine[:, None] / t_mine[None, :]) - 1.0)
    x = np.asarray(fractions, dtype=float)
    temp = factor * abs(float(x @ t_better) / float(x @ t_mine) - 1.0)
    d_zeta = None if zeta is None else factor * abs(zeta[1] / zeta[0] - 1.0)
    return MixtureError(species, ratios, temp, d_zeta, method=method)


class MixtureErrorRecipe:
    """How to compute a mixture state's :class:`MixtureError` when first asked (cached).

    Parameters
    ----------
    compute : callable or None
        ``() -> MixtureError`` (a closure over the solver's state); None once pickled.
    method : str
        Short description of the estimate.
    n_species : int
        Number of species (for the unavailable case).
    """

    def __init__(self, compute: Callable[[], MixtureError] | None, method: str,
                 n_species: int) -> None:
        self.compute = compute
        self.method = method
        self.n_species = n_species
        self._value: MixtureError | None = None

    def __call__(self) -> MixtureError:
        """The estimate (computed once)."""
        if self._value is None:
            if self.compute is None:
                return MixtureError.unavailable(
                    self.n_species, f"the {self.method} estimate was not computed before the "
                    "result was pickled; read state.error in the process that solved",
                    method=self.method)
            self._value = self.compute()
        return self._value

    def species_recipe(self, s: int) -> ErrorRecipe:
        """The :class:`~kinetic_fem.error.ErrorRecipe` of species ``s``'s distribution."""
        return ErrorRecipe(lambda dist: self().species[s], self.method)

    def attach(self, state: Any) -> Any:
        """A copy of the :class:`~kinetic_fem.mixture_state.MixtureState` ``state`` that
        answers ``state.error`` and ``state.distributions[s].error`` with this recipe."""
        dists = tuple(d.with_error(self.species_recipe(s))
                      for s, d in enumerate(state.distributions))
        return replace(state, distributions=dists, error_recipe=self)

    def __reduce__(self) -> tuple[Any, ...]:
        return (MixtureErrorRecipe, (None, self.method, self.n_species))

    def __repr__(self) -> str:
        return f"MixtureErrorRecipe({self.method!r})"
