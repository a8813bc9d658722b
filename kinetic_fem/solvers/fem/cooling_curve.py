"""Curves of FEM homogeneous cooling states over the restitution coefficient.

Near elastic collisions (hard rods, :math:`\\varepsilon = 1 - \\alpha <` 0.1) a
cooling state is reached by continuation in :math:`\\varepsilon` from 0.1
(:mod:`kinetic_fem.solvers.fem.cooling_links`); along a curve each state instead starts
from its neighbour (the ``initial`` warm start of
:func:`~kinetic_fem.solvers.fem.cooling.solve_fem_cooling`): one link on a coarse mesh
and the solve on the default mesh.  The states are those of pointwise solves to the
Newton tolerance (same meshes; ``benchmarks/archive/results/fem_cooling_speed.md``).  Elsewhere
(:math:`\\varepsilon \\ge 0.1`, other kernels) the pointwise solve is used.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...distribution import VelocityDistribution
from ...model import CollisionKernel, CoolingProblem
from ...run_info import RunInfo
from ..continuation import NO_RETRY, continuation
from .cooling import (
    cooling_distribution,
    cooling_state,
    solve_fem_cooling,
    uses_hump_mesh,
)
from .cooling_newton import CoolingState

__all__ = ["CoolingCurve", "cooling_curve"]


@dataclass(frozen=True)
class CoolingCurve:
    """FEM homogeneous cooling states along a list of restitution coefficients.

    Attributes
    ----------
    alphas : ndarray, shape (K,)
        The restitution coefficients, in the order solved.
    distributions : tuple of VelocityDistribution
        One cooling state (unit temperature) per alpha.
    wall_time : float
        Seconds for the whole curve.
    """

    alphas: NDArray[np.float64]
    distributions: tuple[VelocityDistribution, ...]
    wall_time: float

    @property
    def zeta(self) -> NDArray[np.float64]:
        """Cooling rates :math:`\\zeta`, shape (K,)."""
        return np.array([d.info.extra["zeta"] for d in self.distributions])

    @property
    def a2(self) -> NDArray[np.float64]:
        """Kurtosis coefficients :math:`a_2`, shape (K,)."""
        return np.array([d.a2 for d in self.distributions])


def cooling_curve(alphas: ArrayLike, *, kernel: float | CollisionKernel = 1.0,
                  warm_start: bool = True, tol: float = 1e-11,
                  max_iter: int = 100) -> CoolingCurve:
    """FEM cooling states along ``alphas``, near elastic each from its neighbour.

    Parameters
    ----------
    alphas : array_like, shape (K,)
        Constant restitution coefficients in [0, 1), solved in this order (sort them so
        that neighbours are close).
    kernel : float or CollisionKernel
        Kernel exponent :math:`\\gamma` (or the kernel); warm starts are used for hard
        rods (:math:`\\gamma = 1`) below :math:`\\varepsilon = 0.1`.
    warm_start : bool
        Start each near-elastic state from the previous one (module docstring);
        ``False``: every state as :func:`kinetic_fem.solve_cooling` solves it.
    tol, max_iter
        As for :func:`~kinetic_fem.solvers.fem.cooling.solve_fem_cooling`.

    Returns
    -------
    CoolingCurve

    Raises
    ------
    ValueError
        If ``alphas`` is empty or not one-dimensional.
    ConvergenceError
        If a state does not converge.

    Examples
    --------
    >>> curve = cooling_curve([0.98, 0.99])
    >>> bool(curve.a2[1] < curve.a2[0] < 0)
    True
    """
    values = np.asarray(alphas, dtype=float)
    if values.ndim != 1 or values.size == 0:
        raise ValueError(f"alphas must be a non-empty 1-D list of restitution coefficients, "
                         f"got shape {values.shape}")
    start = time.perf_counter()

    def solve(prev: _Point, alpha_prev: float, alpha: float) -> _Point:
        problem = CoolingProblem.from_parameters(float(alpha), kernel=kernel)
        if not (warm_start and uses_hump_mesh(problem)):
            return _Point(None, solve_fem_cooling(problem, tol=tol, max_iter=max_iter))
        near = prev.state if prev.state is not None and uses_hump_mesh(
            CoolingProblem.from_parameters(prev.state.disc.alpha)) else None
        state = cooling_state(problem, tol=tol, max_iter=max_iter, initial=near)
        return _Point(state, cooling_distribution(problem, state))

    dists: list[VelocityDistribution] = []

    def keep(point: _Point, alpha: float) -> None:
        assert point.dist is not None
        dists.append(point.dist)

    continuation(_Point(None, None), math.nan, [float(a) for a in values], solve,
                 rule=NO_RETRY, on_converged=keep)
    return CoolingCurve(values, tuple(dists), time.perf_counter() - start)


@dataclass(frozen=True)
class _Point:
    """A point of the curve: the state (None if not a warm start) and its distribution
    (a solve that fails raises :class:`~kinetic_fem.exceptions.ConvergenceError`)."""

    state: CoolingState | None
    dist: VelocityDistribution | None

    @property
    def info(self) -> RunInfo:
        return _SOLVED


_SOLVED = RunInfo()
