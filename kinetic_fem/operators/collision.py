"""Exact moment identities of the inelastic collision operator.

For any test function :math:`\\varphi` the collision operator satisfies the weak form

.. math::

    \\int \\varphi\\, Q[P,P]\\, dv = \\frac n2 \\iint dv_1 dv_2\\, |v_1 - v_2| P(v_1) P(v_2)
    \\left[\\varphi(v_1') + \\varphi(v_2') - \\varphi(v_1) - \\varphi(v_2)\\right].

With :math:`\\varphi = 1, v` the right side vanishes (mass and momentum); with
:math:`\\varphi = v^2`, :math:`v_1'^2 + v_2'^2 - v_1^2 - v_2^2 = -\\tfrac12(1-\\alpha^2)
(v_1-v_2)^2` gives the exact energy balance (claim C1)

.. math::

    \\frac{d\\langle v^2\\rangle}{dt} = 2D - \\frac n4 (1-\\alpha^2)\\langle|v - v'|^3\\rangle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .fd_kernels import gain_integral
from .grid import abs_power_convolution, simpson_kink_correction, simpson_weights, symmetric_grid

__all__ = ["pair_moment", "energy_loss_rate", "EnergyBalance", "energy_balance",
           "HalfGrid", "half_grid", "loss_frequency", "gain_term", "collision_term",
           "STRONG_FORM_GAMMAS", "kernel_power"]

STRONG_FORM_GAMMAS = (0.0, 1.0)
"""Kernel exponents of the strong form on the half grid: Maxwell and hard rods."""


def kernel_power(gamma: float) -> int:
    """The integer exponent of :math:`|g|^\\gamma` the strong form supports (0 or 1).

    Parameters
    ----------
    gamma : float
        Kernel exponent.

    Returns
    -------
    int

    Raises
    ------
    ValueError
        For other exponents: :math:`|g|^\\gamma` has a kink of fractional order at
        :math:`g = 0` that the Simpson rule with its kink correction does not integrate
        to fourth order (``gamma = 2`` would need its own correction).

    Examples
    --------
    >>> kernel_power(1.0), kernel_power(0.0)
    (1, 0)
    """
    if gamma not in STRONG_FORM_GAMMAS:
        raise ValueError(f"the finite-difference strong form supports the kernels gamma = 0 "
                         f"(Maxwell) and gamma = 1 (hard rods), got gamma={gamma!r}; use "
                         "method='fem' for other kernels")
    return int(gamma)


def pair_moment(v: NDArray[np.float64], p: NDArray[np.float64], w: NDArray[np.float64],
                power: int) -> float:
    """:math:`\\langle |v - v'|^{p}\\rangle = \\iint |v-v'|^p P(v)P(v')`, O(N), odd ``power``.

    Parameters
    ----------
    v : ndarray, shape (n,)
        Increasing nodes.
    p : ndarray, shape (n,)
        Nodal values of :math:`P`.
    w : ndarray, shape (n,)
        Quadrature weights on ``v``.
    power : int
        Odd power ``p >= 1``.

    Returns
    -------
    float
    """
    wp = np.asarray(w) * np.asarray(p)
    return float(np.sum(wp * abs_power_convolution(v, wp, power)))


def energy_loss_rate(v: NDArray[np.float64], p: NDArray[np.float64], w: NDArray[np.float64],
                     alpha: float, density: float) -> float:
    """Collisional loss :math:`\\tfrac n4 (1-\\alpha^2)\\langle|v-v'|^3\\rangle` by quadrature.

    Parameters
    ----------
    v : ndarray, shape (n,)
        Nodes on the whole line.
    p : ndarray, shape (n,)
        Nodal values of :math:`P`.
    w : ndarray, shape (n,)
        Quadrature weights on ``v``.
    alpha : float
        Coefficient of restitution.
    density : float
        Number density ``n``.

    Returns
    -------
    float
    """
    return 0.25 * density * (1.0 - alpha**2) * pair_moment(v, p, w, 3)


@dataclass(frozen=True)
class EnergyBalance:
    """Terms of :math:`dT/dt = 2D - \\text{loss}` and the relative imbalance.

    Parameters
    ----------
    injection : float
        Energy input :math:`2D` of the white noise (per unit time, ``n`` folded in).
    loss : float
        Collisional loss rate of :math:`\\langle v^2\\rangle`.
    """

    injection: float
    loss: float

    @property
    def relative_residual(self) -> float:
        """:math:`|2D - \\text{loss}| / 2D` (zero in an exact steady state)."""
        return abs(self.injection - self.loss) / self.injection


def energy_balance(v: NDArray[np.float64], p: NDArray[np.float64], w: NDArray[np.float64], *,
                   alpha: float, density: float, diffusion: float) -> EnergyBalance:
    """Both sides of the steady energy balance C1 for nodal values ``p``.

    Parameters
    ----------
    v : ndarray, shape (n,)
        Nodes on the whole line.
    p : ndarray, shape (n,)
        Nodal values of :math:`P`.
    w : ndarray, shape (n,)
        Quadrature weights on ``v``.
    alpha : float
        Coefficient of restitution.
    density : float
        Number density ``n``.
    diffusion : float
        White-noise strength ``D``.

    Returns
    -------
    EnergyBalance
    """
    return EnergyBalance(2.0 * diffusion, energy_loss_rate(v, p, w, alpha, density))


# ---------------------------------------------------------------------------------
# Strong form on a uniform half grid (the finite-difference solver's operator)
# ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class HalfGrid:
    """Uniform nodes :math:`v_i = i h` on ``[0, cutoff]`` and their mirrored quadrature.

    Attributes
    ----------
    v : ndarray, shape (n,)
        Half-grid nodes, ``v[0] = 0``.
    h : float
        Spacing.
    v_full : ndarray, shape (2n - 1,)
        The symmetric grid :func:`~kinetic_fem.operators.grid.symmetric_grid`.
    weights : ndarray, shape (2n - 1,)
        Simpson weights on ``v_full`` (1/3 rule throughout: ``2n - 2`` is even).
    kink : ndarray, shape (2n - 1,)
        :func:`~kinetic_fem.operators.grid.simpson_kink_correction` on ``v_full``.
    """

    v: NDArray[np.float64]
    h: float
    v_full: NDArray[np.float64]
    weights: NDArray[np.float64]
    kink: NDArray[np.float64]

    @property
    def n(self) -> int:
        """Number of half-grid nodes."""
        return self.v.size

    @property
    def half_weights(self) -> NDArray[np.float64]:
        """Weights on ``v`` for even integrands: :math:`\\sum_i w^{1/2}_i g_i = \\sum_k w_k g_k`."""
        w = self.weights[self.n - 1:].copy()
        w[1:] *= 2.0
        return w

    def full(self, p: NDArray[np.float64]) -> NDArray[np.float64]:
        """Mirror half-grid values to ``v_full`` (:math:`P(-v) = P(v)`)."""
        return np.concatenate([p[:0:-1], p])


def half_grid(cutoff: float, n_v: int) -> HalfGrid:
    """:class:`HalfGrid` with ``n_v >= 3`` nodes on ``[0, cutoff]``.

    Parameters
    ----------
    cutoff : float
        Last node.
    n_v : int
        Number of nodes on ``[0, cutoff]``, at least 3.

    Returns
    -------
    HalfGrid

    Examples
    --------
    >>> g = half_grid(1.0, 3)
    >>> g.v_full, g.weights * 12
    (array([-1. , -0.5,  0. ,  0.5,  1. ]), array([2., 8., 4., 8., 2.]))
    """
    if int(n_v) < 3:
        raise ValueError(f"a half grid needs at least 3 nodes, got n_v={n_v}")
    v = np.linspace(0.0, float(cutoff), int(n_v))
    v_full = symmetric_grid(v)
    return HalfGrid(v, float(v[1] - v[0]), v_full, simpson_weights(v_full),
                    simpson_kink_correction(v_full))


def loss_frequency(grid: HalfGrid, p: NDArray[np.float64], *, density: float,
                   gamma: float = 1.0) -> NDArray[np.float64]:
    """Collision frequency :math:`\\nu(v_i) = n\\int dv' |v_i - v'|^\\gamma P(v')`, O(n).

    Parameters
    ----------
    grid : HalfGrid
    p : ndarray, shape (n,)
        :math:`P` on the half grid (even extension to ``v < 0``).
    density : float
        :math:`n`.
    gamma : {1, 0}
        Kernel exponent: hard rods or Maxwell (:math:`\\nu = n\\int P`, the same at
        every node).

    Notes
    -----
    Cumulative moments (:func:`~kinetic_fem.operators.grid.abs_power_convolution`) with Simpson
    weights on the mirrored grid plus the kink correction, fourth order in ``h``.
    """
    if kernel_power(gamma) == 0:
        return np.full(grid.n, density * float(np.dot(grid.half_weights, p)))
    wf = grid.weights * grid.full(p)
    conv = abs_power_convolution(grid.v_full, wf, 1, at=grid.v)
    return density * (conv + grid.kink[grid.n - 1:] * p)


def gain_term(grid: HalfGrid, p: NDArray[np.float64], *, alpha: float, density: float,
              log_interp: bool = True, order: int = 2, gamma: float = 1.0
              ) -> NDArray[np.float64]:
    """Gain term of the strong collision operator on the half grid, O(n^2).

    .. math::

        G(v) = n\\Big(\\frac{2}{1+\\alpha}\\Big)^{1+\\gamma}\\int dv' |v - v'|^\\gamma P(v')
               P\\Big(\\frac{2v - (1-\\alpha)v'}{1+\\alpha}\\Big)

    (the pre-collision partner of :math:`v` and :math:`v'` is the argument of the second
    :math:`P`; the Jacobian :math:`2/(1+\\alpha)` of that map and
    :math:`|g_{pre}| = 2|v - v'|/(1+\\alpha)` give the prefactor).

    Parameters
    ----------
    grid : HalfGrid
    p : ndarray, shape (n,)
        Non-negative :math:`P` on the half grid.
    alpha, density : float
        Restitution coefficient and :math:`n`.
    log_interp : bool
        Interpolate :math:`\\ln P` quadratically (exact for Gaussians, positive,
        accurate relative to the tail value) instead of :math:`P`; falls back to
        :math:`P` where a stencil value is zero.
    order : {2, 3}
        Quadratic interpolation on the three nearest nodes (the paper) or cubic on the
        four nodes around the argument.
    gamma : {1, 0}
        Kernel exponent (hard rods or Maxwell; the Maxwell integrand has no kink).

    Notes
    -----
    Simpson weights on the mirrored grid with the kink correction; the off-grid
    argument by quadratic interpolation on the three nearest nodes, ``P = 0`` beyond
    the cut-off (see :mod:`kinetic_fem.operators.fd_kernels`).
    """
    p = np.ascontiguousarray(p, dtype=float)
    with np.errstate(divide="ignore"):
        lnp = np.where(p > 0, np.log(np.where(p > 0, p, 1.0)), -np.inf)
    if order not in (2, 3):
        raise ValueError(f"interpolation order must be 2 or 3, got {order!r}")
    power = kernel_power(gamma)
    kink = grid.kink if power == 1 else np.zeros_like(grid.kink)
    g = gain_integral(p, lnp, grid.weights, kink, float(alpha), grid.h, bool(log_interp),
                      int(order), power)
    return density * (2.0 / (1.0 + alpha)) ** (1 + power) * g


def collision_term(grid: HalfGrid, p: NDArray[np.float64], *, alpha: float, density: float,
                   log_interp: bool = True, order: int = 2, gamma: float = 1.0
                   ) -> NDArray[np.float64]:
    """Strong form :math:`Q[P,P](v_i) = G(v_i) - \\nu(v_i) P(v_i)` on the half grid.

    Parameters
    ----------
    grid : HalfGrid
        Nodes on :math:`v \\ge 0` (:func:`half_grid`).
    p : ndarray, shape (n_v,)
        The even distribution at the nodes of ``grid``.
    alpha : float
        Constant coefficient of restitution.
    density : float
        Number density ``n``.
    log_interp : bool
        Interpolate :math:`\\ln P` (not :math:`P`) at the pre-collision velocities.
    order : int
        Degree of that interpolation (2: the paper's, 3: cubic).
    gamma : float
        Kernel exponent, 0 or 1 (:func:`kernel_power`).

    Returns
    -------
    ndarray, shape (n_v,)

    Examples
    --------
    >>> g = half_grid(10.0, 201)
    >>> p = np.exp(-g.v**2 / 2) / np.sqrt(2 * np.pi)
    >>> q = collision_term(g, p, alpha=0.5, density=1.0)
    >>> bool(abs(np.sum(g.weights * g.full(q))) < 1e-6)  # mass conserved
    True
    """
    return (gain_term(grid, p, alpha=alpha, density=density, log_interp=log_interp,
                      order=order, gamma=gamma)
            - loss_frequency(grid, p, density=density, gamma=gamma) * p)
