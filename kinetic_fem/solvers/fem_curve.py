"""Curves of FEM heated steady states over the restitution coefficient, warm started.

Along a curve :math:`\\alpha_1, \\alpha_2, \\ldots` the state at :math:`\\alpha_k` starts
Newton's method from :math:`f(c)` of the state at :math:`\\alpha_{k-1}` rescaled to the
first-order Sonine temperature of :math:`\\alpha_k`
(:meth:`kinetic_fem.solvers.fem.SteadyState.initial_guess`), in place of the Gaussian
(and, above :data:`kinetic_fem.solvers.fem.CONTINUATION_ALPHA`, of the coarse
continuation solve).  Each state is still solved to the same tolerance on its own
default mesh, so the curve equals the pointwise solutions to the Newton tolerance;
only the number of Newton steps falls.  A warm start that fails is retried from the
default start.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..distribution import VelocityDistribution
from ..gas import HeatedProblem
from ..model import PowerLawKernel
from .fem import ConvergenceError, SteadyState, state_distribution, steady_state

__all__ = ["HeatedCurve", "heated_curve"]

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class HeatedCurve:
    """FEM heated steady states along a list of restitution coefficients.

    Attributes
    ----------
    alphas : ndarray, shape (K,)
        The restitution coefficients, in the order solved.
    distributions : tuple of VelocityDistribution
        One steady state per alpha.
    wall_time : float
        Seconds for the whole curve.
    """

    alphas: NDArray[np.float64]
    distributions: tuple[VelocityDistribution, ...]
    wall_time: float

    @property
    def temperature(self) -> NDArray[np.float64]:
        """Steady temperatures, shape (K,)."""
        return np.array([d.temperature for d in self.distributions])

    @property
    def a2(self) -> NDArray[np.float64]:
        """Kurtosis coefficients :math:`a_2`, shape (K,)."""
        return np.array([d.a2 for d in self.distributions])

    @property
    def newton_iterations(self) -> NDArray[np.int64]:
        """Newton (and chord) steps of each state, shape (K,)."""
        return np.array([d.info.iterations for d in self.distributions])


def heated_curve(alphas: ArrayLike, *, density: float = 1.0, diffusion: float = 1.0,
                 friction: float = 0.0, kernel: float | PowerLawKernel = 1.0,
                 warm_start: bool = True, order: int | None = None, spacing: float | None = None,
                 cutoff: float | None = None, tol: float = 1e-11,
                 max_iter: int = 40) -> HeatedCurve:
    """FEM heated steady states along ``alphas``, each warm started from the previous.

    Parameters
    ----------
    alphas : array_like, shape (K,)
        Constant restitution coefficients in [0, 1), solved in this order (sort them so
        that neighbours are close).
    density, diffusion, friction : float
        Number density, noise strength :math:`D` and bath friction :math:`\\xi`.
    kernel : float or PowerLawKernel
        Kernel exponent :math:`\\gamma` (or the kernel).
    warm_start : bool
        Start each state from the previous one (``False``: every state from the
        solver's default start, as :func:`kinetic_fem.solve_heated` does).
    order, spacing, cutoff, tol, max_iter
        As for :func:`kinetic_fem.solvers.fem.solve_fem_heated`.

    Returns
    -------
    HeatedCurve

    Raises
    ------
    ValueError
        If ``alphas`` is empty or not one-dimensional.
    ConvergenceError
        If a state fails from both the warm and the default start.

    Examples
    --------
    >>> curve = heated_curve([0.5, 0.6], spacing=0.3)
    >>> bool(curve.temperature[1] > curve.temperature[0])
    True
    """
    values = np.asarray(alphas, dtype=float)
    if values.ndim != 1 or values.size == 0:
        raise ValueError(f"alphas must be a non-empty 1-D list of restitution coefficients, "
                         f"got shape {values.shape}")
    start = time.perf_counter()

    def solve(problem: HeatedProblem, initial: SteadyState | None) -> SteadyState:
        return steady_state(problem, order=order, spacing=spacing, cutoff=cutoff, tol=tol,
                            max_iter=max_iter, initial=initial)

    previous: SteadyState | None = None
    dists = []
    for alpha in values:
        problem = HeatedProblem.from_parameters(float(alpha), density=density,
                                                diffusion=diffusion, friction=friction,
                                                kernel=kernel)
        problem.require("fem")
        state = None
        if warm_start and previous is not None:
            try:
                state = solve(problem, previous)
            except ConvergenceError as err:
                logger.info("warm start failed at alpha=%g (%s); default start", alpha, err)
        if state is None:
            state = solve(problem, None)
        dists.append(state_distribution(problem, state, state.disc.order))
        previous = state
    return HeatedCurve(values, tuple(dists), time.perf_counter() - start)
