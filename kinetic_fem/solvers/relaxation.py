"""Relaxation spectrum of the heated gas: the linearised Galerkin system about the steady state.

With :math:`u_h = \\ln P_h` the Galerkin system of :mod:`kinetic_fem.solvers.fem` reads
:math:`\\frac{d}{dt}\\int\\varphi_i P_h = R_i(u_h)`.  About the steady state
:math:`u^*` a perturbation :math:`\\delta u = x e^{-\\lambda t}` obeys the generalised
eigenproblem

.. math::

    J x = -\\lambda M x, \\qquad J_{ij} = \\frac{\\partial R_i}{\\partial u_j}(u^*),
    \\qquad M_{ij} = \\int \\varphi_i\\varphi_j P^*,

whose eigenvalues :math:`\\lambda` are the relaxation rates of the gas (in the units of
the problem: ``1/time``).  Mass conservation makes :math:`\\lambda = 0` an eigenvalue
(its left eigenvector is :math:`(1, .., 1)`); with white noise the momentum is not damped
either (a second zero rate, odd); the slowest even non-zero rate is the temperature
mode (claim C2: :math:`\\tau \\sim \\varepsilon^{-2/3}` near elastic collisions).

Exact check: for the Maxwell kernel (``gamma = 0``) the moment equations close
(:mod:`kinetic_fem.solvers.maxwell`) and are triangular, so the rates of the linearised
hierarchy are its diagonal, :func:`maxwell_rates`; the FEM rates converge to them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg
from numpy.typing import NDArray
from skfem import asm

from ..model import CollisionKernel, HeatedProblem
from ..operators.fem_thermostat import weighted_mass
from ..options import gather
from . import maxwell
from .fem.defaults import scaled_model
from .fem.heated import steady_state
from .fem.options import MeshOptions

__all__ = ["RelaxationSpectrum", "relaxation_spectrum", "maxwell_rates"]


@dataclass(frozen=True)
class RelaxationSpectrum:
    """The slowest relaxation rates of a heated steady state.

    Parameters
    ----------
    rates : ndarray, shape (k,)
        Rates :math:`\\lambda` (physical ``1/time``), increasing; the conserved modes
        (mass; momentum under white noise) are not included.
    parity : tuple of str
        ``"even"`` or ``"odd"``: the symmetry of each mode's :math:`\\delta P`.
    temperature : float
        Steady temperature (physical units).
    n_dofs : int
        Size of the Galerkin system.
    zero_rates : ndarray
        The rates dropped as conserved modes (round-off of 0).
    """

    rates: NDArray[np.float64]
    parity: tuple[str, ...]
    temperature: float
    n_dofs: int
    zero_rates: NDArray[np.float64]

    def slowest(self, parity: str = "even") -> float:
        """The slowest rate of the given parity.

        Parameters
        ----------
        parity : {"even", "odd"}
            Symmetry of the mode.

        Returns
        -------
        float
        """
        for rate, p in zip(self.rates, self.parity, strict=True):
            if p == parity:
                return float(rate)
        raise ValueError(f"no {parity} mode among the {self.rates.size} rates computed")


def relaxation_spectrum(alpha: float, *, density: float = 1.0, diffusion: float = 1.0,
                        friction: float = 0.0, kernel: float | CollisionKernel = 1.0,
                        n_rates: int = 6, zero_tol: float = 1e-8,
                        **mesh_keywords: Any) -> RelaxationSpectrum:
    """Relaxation rates of the heated gas by the linearised FEM system (module notes).

    Parameters
    ----------
    alpha : float
        Constant coefficient of restitution.
    density, diffusion, friction : float
        :math:`n`, :math:`D` and the bath friction :math:`\\xi` (0: white noise).
    kernel : float or CollisionKernel
        Exponent :math:`\\gamma` of :math:`|g|^\\gamma`, or a kernel object (any kernel:
        the unit problem's rates times :math:`n u^d`, the inverse of
        :attr:`~kinetic_fem.model.HeatedProblem.time_scale`).
    n_rates : int
        Number of non-conserved rates returned (the slowest).
    zero_tol : float
        Rates below ``zero_tol`` times the collision rate count as conserved modes.
    **mesh_keywords
        The mesh of the steady state: ``mesh`` (a
        :class:`~kinetic_fem.solvers.fem.options.MeshOptions`) or its fields by keyword
        (``spacing``, ``cutoff``, ... in thermal velocities); defaults of the FEM solver.

    Returns
    -------
    RelaxationSpectrum

    Raises
    ------
    ValueError
        For invalid parameters or ``n_rates < 1``.
    ConvergenceError
        If the steady state is not found.

    Examples
    --------
    The Maxwell model's temperature mode relaxes at :math:`(1-\\alpha^2)/2` (``n = 1``):

    >>> spec = relaxation_spectrum(0.5, kernel=0.0, n_rates=2, spacing=0.2)
    >>> round(spec.slowest("even") / ((1 - 0.5**2) / 2), 6)
    1.0
    """
    if isinstance(n_rates, bool) or not isinstance(n_rates, int) or n_rates < 1:
        raise ValueError(f"n_rates must be a positive integer, got {n_rates!r}")
    problem = HeatedProblem.from_parameters(alpha, density=density, diffusion=diffusion,
                                            friction=friction, kernel=kernel)
    scaled = scaled_model(problem)
    mesh = gather(MeshOptions, mesh_keywords.pop("mesh", None), mesh_keywords,
                  "relaxation_spectrum")
    state = steady_state(problem, mesh=mesh)
    disc, u = state.disc, state.u
    _, jac = disc.residual(u, jacobian=True)  # full space: even and odd perturbations
    assert jac is not None
    weight = asm(weighted_mass, disc.basis, u=disc.field(u)).toarray()
    # the pencil scaled to a unit-diagonal mass matrix: rows and columns of far-tail dofs
    # scale with P (down to 1e-33), which the QZ algorithm does not resolve unscaled
    scale = 1.0 / np.sqrt(np.diag(weight))
    values, vectors = scipy.linalg.eig(-jac * scale[:, None] * scale[None, :],
                                       weight * scale[:, None] * scale[None, :])
    # parity is judged on the scaled vectors (delta u times sqrt(M_ii), about delta P):
    # delta u itself is dominated by far-tail dofs where P is tiny
    finite = np.isfinite(values)
    values, vectors = values[finite], vectors[:, finite]
    order = np.argsort(values.real)
    values, vectors = values[order].real, vectors[:, order].real
    # scaled units: n = D = 1 with speeds in units of u, times in units of 1/(n u^d)
    u_scale = scaled.speed_scale
    rate_unit = problem.gas.density * u_scale**problem.gas.kernel.scale_degree
    zero = np.abs(values) < zero_tol
    x = disc.dof_locations
    # the dof at -x of each dof (the mesh is symmetric; dofs are not stored in order)
    by_x = np.argsort(x, kind="stable")
    mirror = np.empty_like(by_x)
    mirror[by_x] = by_x[::-1]
    keep = np.flatnonzero(~zero)[:n_rates]
    parity = []
    for k in keep:
        vec = vectors[:, k]
        even = np.linalg.norm(vec - vec[mirror]) <= np.linalg.norm(vec + vec[mirror])
        parity.append("even" if even else "odd")
    temperature = disc.distribution(u).temperature * u_scale**2
    return RelaxationSpectrum(values[keep] * rate_unit, tuple(parity), temperature,
                              int(u.size), values[zero] * rate_unit)


def maxwell_rates(alpha: float, order: int, *, density: float = 1.0, diffusion: float = 1.0,
                  friction: float = 0.0) -> NDArray[np.float64]:
    """Exact relaxation rates of the heated Maxwell model's moments 1 .. ``order``.

    The moment hierarchy :math:`\\dot M_k = F_k(M_0, .., M_k)` is closed and triangular,
    so its linearisation about the steady moments has the eigenvalues
    :math:`-\\partial F_k/\\partial M_k`; ``F`` is quadratic, so central differences give
    the derivatives to round-off.

    Parameters
    ----------
    alpha : float
        Coefficient of restitution.
    order : int
        Highest moment.
    density, diffusion, friction : float
        :math:`n`, :math:`D` and :math:`\\xi`.

    Returns
    -------
    ndarray, shape (order,)
        The rate of moment ``k = 1 .. order`` (odd ``k``: odd modes).
    """
    steady = maxwell.steady_state(alpha, order=max(1, math.ceil(order / 2)), density=density,
                                  diffusion=diffusion, friction=friction)
    moments = np.zeros(order + 1)
    n_known = min(order + 1, steady.moments.size)
    moments[:n_known] = steady.moments[:n_known]
    rates = np.empty(order)
    for k in range(1, order + 1):
        h = 1e-3 * max(abs(moments[k]), 1.0)
        up, down = moments.copy(), moments.copy()
        up[k] += h
        down[k] -= h
        fu = maxwell.moment_rates(up, alpha, density, diffusion, friction)[k]
        fd = maxwell.moment_rates(down, alpha, density, diffusion, friction)[k]
        rates[k - 1] = -(fu - fd) / (2.0 * h)
    return rates
