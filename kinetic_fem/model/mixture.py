"""Granular mixtures: several species of rods with their masses and number fractions.

A mixture of :math:`k` species, species :math:`s` of mass :math:`m_s` and number fraction
:math:`x_s` (:math:`\\sum_s x_s = 1`) in a gas of total number density :math:`n`, obeys
the coupled homogeneous Boltzmann equations

.. math::

    \\partial_t P_s = \\sum_r n x_r\\, Q_{sr}[P_s, P_r] + \\mathcal F_s[P_s],

with one collision kernel :math:`B(|g|)` for every pair, a restitution law
:math:`\\alpha_{sr} = \\alpha_{rs}` per pair and a thermostat :math:`\\mathcal F_s` per
species.  A collision of a rod of species :math:`s` with one of species :math:`r` at
relative velocity :math:`g = v_s - v_r` conserves momentum and maps

.. math::

    v_s' = v_s - \\mu_{sr}(1 + \\alpha_{sr})\\, g, \\qquad
    v_r' = v_r + \\mu_{rs}(1 + \\alpha_{sr})\\, g, \\qquad
    \\mu_{sr} = \\frac{m_r}{m_s + m_r},

so that equal masses (:math:`\\mu = 1/2`) give the one-species rule of the paper, and a
mixture of identical species is the one-species gas.  The kinetic temperature of a species
is :math:`T_s = m_s \\langle v^2\\rangle_s`, that of the mixture
:math:`T = \\sum_s x_s T_s`; energy equipartition breaks down (:math:`T_s \\ne T_r`)
as soon as the collisions are inelastic and the species differ.

Two forcing conventions of the literature are named by :meth:`Mixture.white_noise`:
``"same_diffusion"`` (every species gets the same :math:`D`) and ``"same_power"``
(:math:`D_s \\propto 1/m_s`: every rod receives the same mean power
:math:`m_s D_s`).

References
----------
V. Garzo and J. W. Dufty, Phys. Rev. E 60, 5706 (1999) (free cooling of mixtures);
A. Barrat and E. Trizac, Granular Matter 4, 57 (2002) (heated mixtures).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .kernel import as_kernel
from .kernel_base import CollisionKernel
from .restitution import RestitutionLaw, as_restitution
from .thermostat import NoThermostat, Thermostat, WhiteNoise
from .validation import check_positive, check_real

__all__ = ["Mixture", "FORCING_CONVENTIONS"]

#: the named forcing conventions of :meth:`Mixture.white_noise`
FORCING_CONVENTIONS = ("same_diffusion", "same_power")

#: the number fractions must sum to one to this relative accuracy
_FRACTION_SUM_TOL = 1e-12


def _restitution_matrix(alpha: object, k: int) -> tuple[tuple[RestitutionLaw, ...], ...]:
    """A symmetric k x k table of restitution laws from a scalar, a law or a table."""
    if isinstance(alpha, (int, float, np.floating, np.integer, RestitutionLaw)) \
            and not isinstance(alpha, bool):
        law = as_restitution(alpha)
        return tuple(tuple(law for _ in range(k)) for _ in range(k))
    if isinstance(alpha, (str, bytes)) or not isinstance(alpha, Sequence | np.ndarray):
        raise TypeError(f"alpha must be a restitution coefficient, a restitution law or a "
                        f"symmetric {k} x {k} table of them, got {alpha!r}")
    rows = [list(row) if isinstance(row, Sequence | np.ndarray) else None for row in alpha]
    if len(rows) != k or any(row is None or len(row) != k for row in rows):
        raise ValueError(f"alpha as a table must be {k} x {k} (one law per pair of the {k} "
                         f"species), got {alpha!r}")
    table = tuple(tuple(as_restitution(value) for value in row) for row in rows)  # type: ignore[union-attr]
    for s in range(k):
        for r in range(s + 1, k):
            if table[s][r] != table[r][s]:
                raise ValueError(f"alpha must be symmetric (one law per pair): alpha[{s}][{r}]"
                                 f" = {table[s][r]!r} differs from alpha[{r}][{s}] = "
                                 f"{table[r][s]!r}")
    return table


@dataclass(frozen=True, eq=False)
class Mixture:
    """A granular mixture: masses, number fractions, restitution per pair, one kernel.

    Parameters
    ----------
    masses : sequence of float, shape (k,)
        :math:`m_s > 0`, ``k >= 2`` species.
    fractions : sequence of float, shape (k,)
        Number fractions :math:`x_s > 0` summing to one.
    alpha : float, RestitutionLaw or k x k table of them
        The restitution law of each pair (a scalar or a law applies to every pair); a
        table must be symmetric.
    kernel : float or CollisionKernel
        The collision kernel of every pair (a float is the exponent of :math:`|g|^\\gamma`).
    thermostats : sequence of Thermostat, shape (k,), optional
        The forcing of each species; omitted: free cooling
        (:class:`~kinetic_fem.model.NoThermostat` for every species).  See
        :meth:`white_noise` for the usual conventions.

    Raises
    ------
    TypeError, ValueError
        With a message naming the parameter, what was given and what is allowed.

    Examples
    --------
    >>> mix = Mixture(masses=(1.0, 2.0), fractions=(0.5, 0.5), alpha=0.8)
    >>> mix.n_species, mix.reduced_mass(0, 1)
    (2, 0.6666666666666666)
    """

    masses: tuple[float, ...]
    fractions: tuple[float, ...]
    alpha: object = 0.9
    kernel: object = 1.0
    thermostats: tuple[Thermostat, ...] | None = None

    def __post_init__(self) -> None:
        masses = self._positive_tuple("masses", self.masses)
        k = len(masses)
        if k < 2:
            raise ValueError(f"a mixture needs at least 2 species, got masses={self.masses!r}"
                             " (a single species is kf.solve_heated / kf.solve_cooling)")
        fractions = self._positive_tuple("fractions", self.fractions)
        if len(fractions) != k:
            raise ValueError(f"fractions must give one number fraction per species ({k}), got "
                             f"{self.fractions!r}")
        total = sum(fractions)
        if abs(total - 1.0) > _FRACTION_SUM_TOL * k:
            raise ValueError(f"the number fractions must sum to 1, got {self.fractions!r} "
                             f"(sum {total!r}); normalise them")
        object.__setattr__(self, "masses", masses)
        object.__setattr__(self, "fractions", fractions)
        object.__setattr__(self, "alpha", _restitution_matrix(self.alpha, k))
        object.__setattr__(self, "kernel", as_kernel(self.kernel))
        if self.thermostats is None:
            object.__setattr__(self, "thermostats", tuple(NoThermostat() for _ in range(k)))
        else:
            thermostats = tuple(self.thermostats)
            if len(thermostats) != k or not all(isinstance(t, Thermostat) for t in thermostats):
                raise ValueError(f"thermostats must give one Thermostat per species ({k}), got "
                                 f"{self.thermostats!r}")
            drives = {t.drives for t in thermostats}
            if len(drives) != 1:
                raise ValueError("either every species is forced (a heated mixture) or none is "
                                 f"(free cooling), got {thermostats!r}")
            object.__setattr__(self, "thermostats", thermostats)

    @staticmethod
    def _positive_tuple(name: str, values: object) -> tuple[float, ...]:
        if isinstance(values, (str, bytes)) or not isinstance(values, Sequence | np.ndarray):
            raise TypeError(f"{name} must be a sequence of positive numbers, got {values!r}")
        out = tuple(check_real(f"{name}[{i}]", v) for i, v in enumerate(values))
        for i, v in enumerate(out):
            check_positive(f"{name}[{i}]", v)
        return out

    @classmethod
    def white_noise(cls, masses: Sequence[float], fractions: Sequence[float], *,
                    alpha: object = 0.9, kernel: object = 1.0, diffusion: float = 1.0,
                    convention: str = "same_diffusion") -> Mixture:
        """A mixture heated by white noise under a named forcing convention.

        Parameters
        ----------
        masses, fractions, alpha, kernel
            As in :class:`Mixture`.
        diffusion : float
            :math:`D > 0`: the diffusion coefficient of every species
            (``"same_diffusion"``), or that of a rod of unit mass
            (``"same_power"``: :math:`D_s = D/m_s`, the same mean power
            :math:`m_s D_s` for every rod).
        convention : {"same_diffusion", "same_power"}

        Returns
        -------
        Mixture
        """
        diffusion = check_positive("diffusion", diffusion)
        if convention not in FORCING_CONVENTIONS:
            raise ValueError(f"convention must be one of {FORCING_CONVENTIONS}, got "
                             f"{convention!r}")
        masses = cls._positive_tuple("masses", masses)
        strengths = [diffusion if convention == "same_diffusion" else diffusion / m
                     for m in masses]
        return cls(masses=masses, fractions=tuple(fractions), alpha=alpha, kernel=kernel,
                   thermostats=tuple(WhiteNoise(d) for d in strengths))

    @property
    def n_species(self) -> int:
        """The number of species :math:`k`."""
        return len(self.masses)

    @property
    def collision_kernel(self) -> CollisionKernel:
        """The kernel object (``kernel`` after validation)."""
        assert isinstance(self.kernel, CollisionKernel)
        return self.kernel

    @property
    def laws(self) -> tuple[tuple[RestitutionLaw, ...], ...]:
        """The symmetric table of restitution laws (``alpha`` after validation)."""
        return self.alpha  # type: ignore[return-value]

    @property
    def heated(self) -> bool:
        """True if the species are forced (a steady state exists)."""
        assert self.thermostats is not None
        return self.thermostats[0].drives

    def reduced_mass(self, s: int, r: int) -> float:
        """:math:`\\mu_{sr} = m_r/(m_s + m_r)`, the share of the velocity change of ``s``."""
        return self.masses[r] / (self.masses[s] + self.masses[r])

    def constant_alpha(self) -> NDArray[np.float64]:
        """The k x k table of constant restitution coefficients.

        Raises
        ------
        kinetic_fem.model.UnsupportedModelError
            If a pair has a velocity-dependent law.
        """
        from .validation import UnsupportedModelError

        table = np.empty((self.n_species, self.n_species))
        for s, row in enumerate(self.laws):
            for r, law in enumerate(row):
                if law.constant is None:
                    raise UnsupportedModelError(
                        f"this computation needs a constant restitution coefficient for every "
                        f"pair, got {law!r} for the pair ({s}, {r})")
                table[s, r] = law.constant
        return table

    def diffusions(self) -> NDArray[np.float64]:
        """:math:`D_s` of every species (0 in free cooling)."""
        assert self.thermostats is not None
        return np.array([t.diffusion for t in self.thermostats])

    def frictions(self) -> NDArray[np.float64]:
        """:math:`\\xi_s` of every species (0 without a bath)."""
        assert self.thermostats is not None
        return np.array([t.friction for t in self.thermostats])

    def __repr__(self) -> str:
        alpha = self.constant_alpha().tolist() if all(
            law.constant is not None for row in self.laws for law in row) else self.laws
        return (f"Mixture(masses={self.masses}, fractions={self.fractions}, alpha={alpha}, "
                f"kernel={self.kernel!r}, thermostats={self.thermostats!r})")
