"""Exact moments of the inelastic Maxwell mixture (kernel ``gamma = 0``).

With a collision rate independent of the relative speed the moment equations of a
mixture close as they do for one species (:mod:`kinetic_fem.solvers.maxwell`).  A
collision of species :math:`s` with species :math:`r` maps
:math:`v_s' = c_1 v_s + c_2 v_r` with :math:`c_2 = \\mu_{sr}(1+\\alpha_{sr})`,
:math:`c_1 = 1 - c_2`, :math:`\\mu_{sr} = m_r/(m_s + m_r)`
(:mod:`kinetic_fem.model.mixture`), and a rod of species :math:`s` meets one of species
:math:`r` at the rate :math:`n x_r`.  The weak form with :math:`\\varphi = v^k` gives,
for symmetric states (odd moments zero) and :math:`M^s_k = \\langle v^k\\rangle_s`,

.. math::

    \\frac{dM^s_k}{dt} = n\\sum_r x_r\\Big[\\sum_{j=0}^{k}\\binom kj c_1^j c_2^{k-j}
        M^s_j M^r_{k-j} - M^s_k\\Big] + D_s k(k-1) M^s_{k-2} - \\xi_s k M^s_k .

Order by order this is linear in :math:`M_k = (M^s_k)_s`:
:math:`\\dot M_k = A_k M_k + L_k` with

.. math::

    (A_k)_{ss} = n\\sum_r x_r (c_{1,sr}^k - 1) + n x_s c_{2,ss}^k - \\xi_s k,\\qquad
    (A_k)_{sr} = n x_r c_{2,sr}^k \\ (r \\ne s),

and :math:`L_k` holding moments of lower order only (the :math:`j = 1 .. k-1` terms and
the noise).

* Heated steady state: :math:`M_k = -A_k^{-1} L_k`, order by order, every moment exactly.
* Free cooling: :math:`A_2` has non-negative off-diagonal entries, so its largest
  eigenvalue :math:`\\lambda` is real with a positive eigenvector (Perron-Frobenius): the
  scaling state has :math:`M^s_2 \\propto e^{\\lambda t}` for every species, the
  temperature ratios of that eigenvector, and the cooling rate
  :math:`\\zeta = -\\lambda/(2n)` (:math:`dT/dt = -2\\zeta n T`).  The scaled moments of
  order :math:`k` solve :math:`(A_k - \\tfrac{k\\lambda}{2}) m_k = -L_k`; they are finite
  only if every eigenvalue of :math:`A_k - k\\lambda/2` is negative (else the moment
  grows without bound relative to :math:`T^{k/2}`, a power-law tail, as for one species
  where the fourth moment of the cooling state diverges) and are reported as ``inf``
  then.

For one species split into identical halves these are the one-species equations of
:mod:`kinetic_fem.solvers.maxwell`: :math:`T = 4D/(n(1-\\alpha^2))`,
:math:`a_2 = 2(1-\\alpha^2)/(7+\\alpha^2)`, :math:`\\zeta = (1-\\alpha^2)/4`.

References
----------
E. Ben-Naim and P. L. Krapivsky, Phys. Rev. E 66, 011309 (2002) and U. Marini Bettolo
Marconi and A. Puglisi, Phys. Rev. E 66, 011301 (2002) (inelastic Maxwell mixtures).
"""

from __future__ import annotations

from math import comb

import numpy as np
from numpy.typing import NDArray

from ..mixture_state import MixtureMoments
from ..model.mixture import Mixture
from ..model.validation import UnsupportedModelError, check_positive

__all__ = ["rate_matrix", "steady_state", "cooling_state", "moment_rates"]


def _check_maxwell(mixture: Mixture) -> None:
    if not isinstance(mixture, Mixture):
        raise TypeError(f"mixture must be a kinetic_fem.Mixture, got {mixture!r}")
    if not mixture.collision_kernel.is_maxwell:
        raise UnsupportedModelError(
            f"the closed moment equations hold for the Maxwell kernel (gamma = 0) only, got "
            f"{mixture.collision_kernel!r}; use the Gaussian approximation "
            "(kinetic_fem.solvers.mixture_gaussian) or a particle method")


def _check_order(order: int) -> int:
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or order < 2 \
            or order % 2:
        raise ValueError(f"order must be an even integer >= 2 (the highest moment), got "
                         f"{order!r}")
    return int(order)


def _post_collision_weights(mixture: Mixture) -> tuple[NDArray[np.float64],
                                                      NDArray[np.float64]]:
    """``(c1, c2)``: :math:`v_s' = c_1 v_s + c_2 v_r` for every pair, shape (k, k)."""
    alpha = mixture.constant_alpha()
    masses = np.asarray(mixture.masses)
    mu = masses[None, :] / (masses[:, None] + masses[None, :])
    c2 = mu * (1.0 + alpha)
    return 1.0 - c2, c2


def rate_matrix(mixture: Mixture, k: int, density: float = 1.0) -> NDArray[np.float64]:
    """:math:`A_k` of the module notes (collisions and friction), shape (k_s, k_s).

    Parameters
    ----------
    mixture : Mixture
        Maxwell kernel, constant restitution per pair.
    k : int
        Moment order, >= 1.
    density : float
        Total number density :math:`n`.

    Returns
    -------
    ndarray
    """
    _check_maxwell(mixture)
    density = check_positive("density", density)
    c1, c2 = _post_collision_weights(mixture)
    x = np.asarray(mixture.fractions)
    a = density * x[None, :] * c2**k
    np.fill_diagonal(a, 0.0)
    diag = density * (np.sum(x[None, :] * (c1**k - 1.0), axis=1) + x * np.diag(c2)**k) \
        - k * mixture.frictions()
    return a + np.diag(diag)


def _lower_terms(mixture: Mixture, moments: NDArray[np.float64], k: int,
                 density: float) -> NDArray[np.float64]:
    """:math:`L_k`: the terms of order ``k`` with moments of lower order only."""
    c1, c2 = _post_collision_weights(mixture)
    x = np.asarray(mixture.fractions)
    n_s = mixture.n_species
    out = np.zeros(n_s)
    for s in range(n_s):
        for r in range(n_s):
            total = 0.0
            for j in range(1, k):
                total += comb(k, j) * c1[s, r]**j * c2[s, r]**(k - j) \
                    * moments[s, j] * moments[r, k - j]
            out[s] += density * x[r] * total
    if k >= 2:
        out += mixture.diffusions() * k * (k - 1) * moments[:, k - 2]
    return out


def moment_rates(mixture: Mixture, moments: np.ndarray, density: float = 1.0
                 ) -> NDArray[np.float64]:
    """:math:`dM^s_k/dt` of every species and order for given moments.

    Parameters
    ----------
    mixture : Mixture
        Maxwell kernel, constant restitution per pair.
    moments : array_like, shape (k_s, K + 1)
        :math:`M^s_j`, ``j = 0 .. K`` (``M^s_0 = 1``).
    density : float
        Total number density.

    Returns
    -------
    ndarray, shape (k_s, K + 1)
        The rates (zero for ``j = 0``).
    """
    _check_maxwell(mixture)
    m = np.asarray(moments, dtype=float)
    if m.ndim != 2 or m.shape[0] != mixture.n_species or m.shape[1] < 1:
        raise ValueError(f"moments must have shape ({mixture.n_species}, K + 1), got "
                         f"{m.shape}")
    rates = np.zeros_like(m)
    for k in range(1, m.shape[1]):
        rates[:, k] = rate_matrix(mixture, k, density) @ m[:, k] \
            + _lower_terms(mixture, m, k, density)
    return rates


def steady_state(mixture: Mixture, order: int = 4, *, density: float = 1.0) -> MixtureMoments:
    """The heated steady state's moments, exactly (order by order).

    Parameters
    ----------
    mixture : Mixture
        Maxwell kernel, constant restitution, every species forced.
    order : int
        The highest (even) moment, >= 2.
    density : float
        Total number density :math:`n > 0`.

    Returns
    -------
    MixtureMoments

    Examples
    --------
    >>> from kinetic_fem.model.mixture import Mixture
    >>> mix = Mixture.white_noise((1.0, 1.0), (0.5, 0.5), alpha=0.6, kernel=0.0)
    >>> state = steady_state(mix)
    >>> round(float(state.temperatures[0]), 12), round(float(state.a2[0]), 12)
    (6.25, 0.173913043478)

    (:math:`T = 4D/(1-\\alpha^2)`, :math:`a_2 = 2(1-\\alpha^2)/(7+\\alpha^2)`.)
    """
    _check_maxwell(mixture)
    order = _check_order(order)
    density = check_positive("density", density)
    if not mixture.heated:
        raise ValueError("a steady state needs forced species (Mixture.white_noise or "
                         "thermostats=...); for free cooling use cooling_state")
    moments = np.zeros((mixture.n_species, order + 1))
    moments[:, 0] = 1.0
    for k in range(2, order + 1, 2):
        moments[:, k] = np.linalg.solve(rate_matrix(mixture, k, density),
                                        -_lower_terms(mixture, moments, k, density))
    return MixtureMoments(mixture, density, moments, "maxwell-exact")


def cooling_state(mixture: Mixture, order: int = 4, *, density: float = 1.0
                  ) -> MixtureMoments:
    """The homogeneous cooling state's scaled moments and cooling rate, exactly.

    Parameters
    ----------
    mixture : Mixture
        Maxwell kernel, constant restitution, no forcing.
    order : int
        The highest (even) moment, >= 2.
    density : float
        Total number density :math:`n > 0`.

    Returns
    -------
    MixtureMoments
        Scaled to the mixture temperature :math:`T = 1`; ``zeta`` the cooling rate;
        moments that have no scaling limit are ``inf``.

    Examples
    --------
    >>> from kinetic_fem.model.mixture import Mixture
    >>> state = cooling_state(Mixture((1.0, 1.0), (0.3, 0.7), alpha=0.6, kernel=0.0))
    >>> round(state.zeta, 12), round(state.temperature_ratio(), 12)   # (1 - alpha^2)/4
    (0.16, 1.0)
    """
    _check_maxwell(mixture)
    order = _check_order(order)
    density = check_positive("density", density)
    if mixture.heated:
        raise ValueError("the homogeneous cooling state is for free cooling; this mixture is "
                         "forced (use steady_state)")
    eigenvalues, vectors = np.linalg.eig(rate_matrix(mixture, 2, density))
    lead = int(np.argmax(eigenvalues.real))
    lam = float(eigenvalues[lead].real)
    m2 = np.abs(vectors[:, lead].real)
    m2 /= float(np.dot(np.asarray(mixture.fractions) * np.asarray(mixture.masses), m2))
    moments = np.zeros((mixture.n_species, order + 1))
    moments[:, 0] = 1.0
    moments[:, 2] = m2
    growth = {}
    for k in range(4, order + 1, 2):
        shifted = rate_matrix(mixture, k, density) - 0.5 * k * lam * np.eye(mixture.n_species)
        growth[k] = float(np.max(np.linalg.eigvals(shifted).real))
        if growth[k] >= 0.0 or not np.all(np.isfinite(moments[:, k - 2])):
            moments[:, k] = np.inf
        else:
            moments[:, k] = np.linalg.solve(shifted, -_lower_terms(mixture, moments, k,
                                                                   density))
    return MixtureMoments(mixture, density, moments, "maxwell-exact",
                          zeta=-lam / (2.0 * density),
                          info={"eigenvalue": lam, "scaled_growth_rates": growth})
