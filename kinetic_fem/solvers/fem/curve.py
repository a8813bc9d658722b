"""Curves of FEM heated steady states over the restitution coefficient, by continuation.

Along a curve :math:`\\alpha_1, \\alpha_2, \\ldots` the state at :math:`\\alpha_k` starts
Newton's method from a prediction made of the states already found: :math:`f(c)` and
:math:`\\ln T` extrapolated linearly in :math:`\\alpha` from the two previous states
(:func:`predict_log_density`; the previous state alone at the second point), in place of
the Gaussian and, above :data:`kinetic_fem.solvers.fem.CONTINUATION_ALPHA`, of the
coarse continuation solve.  The solve is otherwise the pointwise one (mesh sequencing:
the coarse solve from the prediction, where the interval is widened, then the fine
mesh from the coarse state), so each state ends on the mesh the pointwise solve uses,
to the same tolerance: the curve equals the pointwise solutions to the Newton
tolerance.  A start that fails is retried from the default start.

Measured (``benchmarks/archive/results/fem_heated_speed.md``): 4 % less collision work than
pointwise solves on the 25- and 100-point curves over [0, 0.99].  The pointwise solve is
already near its floor (one fine Jacobian and one residual after the coarse solve), and
the far tail of :math:`\\ln f` changes too fast with :math:`\\alpha` for a prediction to
replace the coarse solve: started on the fine mesh directly, Newton needs 2 to 3 fine
Jacobians (first update 0.3 to 0.9 in :math:`\\ln P` at :math:`c \\approx 14`-18), 1.3
times the work.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...distribution import VelocityDistribution
from ...gas import HeatedProblem
from ...model import PowerLawKernel
from ...run_info import RunInfo
from ..continuation import NO_RETRY, continuation
from .defaults import scaled_model
from .heated import ConvergenceError, SteadyState, state_distribution, steady_state

__all__ = ["HeatedCurve", "heated_curve", "predict_log_density", "MAX_EXTRAPOLATION"]

logger = logging.getLogger(__name__)

MAX_EXTRAPOLATION = 2.0
"""The linear prediction extrapolates at most this many previous steps ahead (else the
previous state alone is the start)."""
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
        """Newton (and chord) steps of each state's last solve, shape (K,)."""
        return np.array([d.info.iterations for d in self.distributions])


@dataclass(frozen=True)
class _Point:
    """A solved point of the curve: alpha, state, its temperature and the model's
    temperature estimate (``n = D = 1``)."""

    alpha: float
    state: SteadyState
    temperature: float
    estimate: float

    @property
    def info(self) -> RunInfo:
        """Converged (a state that fails from both starts raises)."""
        return _SOLVED


_SOLVED = RunInfo()


def _temperature(state: SteadyState) -> float:
    return float(state.disc.distribution(state.u).temperature)


def predict_log_density(states: Sequence[SteadyState], alphas: Sequence[float], alpha: float,
                        estimates: Sequence[float], estimate: float, *,
                        linear_tail: bool = False,
                        temperatures: Sequence[float] | None = None
                        ) -> Callable[[NDArray], NDArray]:
    """A start ``v -> ln P(v)`` at ``alpha`` from the states at the previous alphas.

    With two states, :math:`\\ln f(c)` and :math:`\\ln(T/T_{est})` are extrapolated
    linearly in :math:`\\alpha` (error :math:`O(\\Delta\\alpha^2)`); with one,
    :math:`f(c)` is kept and :math:`T/T_{est}` too (:math:`T_{est}` the model's temperature
    estimate, first-order Sonine for the paper's model).

    Parameters
    ----------
    states : sequence of SteadyState
        One or two states at ``n = D = 1``, the last the nearest.
    alphas : sequence of float
        Their restitution coefficients.
    alpha : float
        The restitution coefficient of the prediction.
    estimates : sequence of float
        The temperature estimates of the states' models.
    estimate : float
        The temperature estimate at ``alpha``.
    linear_tail : bool
        Continue :math:`\\ln f` beyond a state's mesh linearly (exponential tails), else
        as a Gaussian (:meth:`~kinetic_fem.solvers.fem.state.SteadyState.initial_guess`).
    temperatures : sequence of float, optional
        The states' temperatures, if known (else computed).

    Returns
    -------
    callable
        ``v -> ln P(v)`` at ``n = D = 1``.

    Raises
    ------
    ValueError
        If ``states`` is empty or the lengths differ.
    """
    if not 1 <= len(states) == len(alphas) == len(estimates):
        raise ValueError("predict_log_density needs one or two states, each with its alpha "
                         f"and temperature estimate; got {len(states)}, {len(alphas)}, "
                         f"{len(estimates)}")
    if temperatures is None:
        temperatures = [_temperature(s) for s in states]
    ratios = [t / e for t, e in zip(temperatures, estimates, strict=True)]
    weight = 0.0
    if len(states) >= 2 and alphas[-1] != alphas[-2]:
        weight = (alpha - alphas[-1]) / (alphas[-1] - alphas[-2])
        if not 0.0 <= weight <= MAX_EXTRAPOLATION:
            weight = 0.0
    log_ratio = math.log(ratios[-1])
    if weight:
        log_ratio += weight * (log_ratio - math.log(ratios[-2]))
    temperature = math.exp(log_ratio) * estimate
    last = states[-1]
    if weight == 0.0:
        return lambda v: last.initial_guess(v, temperature, linear_tail=linear_tail)
    before = states[-2]

    def start(v: NDArray) -> NDArray:
        new = last.initial_guess(v, temperature, linear_tail=linear_tail)
        old = before.initial_guess(v, temperature, linear_tail=linear_tail)
        return new + weight * (new - old)

    return start


def heated_curve(alphas: ArrayLike, *, density: float = 1.0, diffusion: float = 1.0,
                 friction: float = 0.0, kernel: float | PowerLawKernel = 1.0,
                 warm_start: bool = True, **options: Any) -> HeatedCurve:
    """FEM heated steady states along ``alphas``, each started from a prediction.

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
        Continuation: start each state from the prediction of the previous ones
        (:func:`predict_log_density`, module docstring); ``False``:
        every state from the solver's default start, as :func:`kinetic_fem.solve_heated`
        does.
    **options
        The options of :func:`kinetic_fem.solvers.fem.steady_state` (``mesh``,
        ``symmetric``, ``tol``, ``max_iter`` and the mesh's by keyword: ``order``,
        ``spacing``, ``cutoff`` ...); an unknown one raises :class:`TypeError`.

    Returns
    -------
    HeatedCurve

    Raises
    ------
    ValueError
        If ``alphas`` is empty or not one-dimensional.
    ConvergenceError
        If a state fails from both the prediction and the default start.

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

    def solve(problem: HeatedProblem,
              initial: Callable[[NDArray], NDArray] | None) -> SteadyState:
        return steady_state(problem, initial=initial, **options)

    points: list[_Point] = []
    dists = []

    def point(prev: _Point, alpha_prev: float, alpha: float) -> _Point:
        problem = HeatedProblem.from_parameters(alpha, density=density,
                                                diffusion=diffusion, friction=friction,
                                                kernel=kernel)
        problem.require("fem")
        scaled = scaled_model(problem)
        state = None
        if warm_start and points:
            near = points[-2:]
            guess = predict_log_density([p.state for p in near], [p.alpha for p in near],
                                        alpha, [p.estimate for p in near],
                                        scaled.temperature,
                                        linear_tail=not scaled.is_paper_model,
                                        temperatures=[p.temperature for p in near])
            try:
                state = solve(problem, guess)
            except ConvergenceError as err:
                logger.info("prediction failed at alpha=%g (%s); default start", alpha, err)
        if state is None:
            state = solve(problem, None)
        dist = state_distribution(problem, state, state.disc.order)
        temperature = dist.temperature / problem.velocity_scale**2  # at n = D = 1
        points.append(_Point(alpha, state, temperature, scaled.temperature))
        dists.append(dist)
        return points[-1]

    # the curve is a continuation along the alphas asked for, each step from the
    # prediction of the last two (a failed prediction falls back inside the step; no
    # start: the first state from the default start)
    continuation(cast(_Point, None), math.nan, [float(a) for a in values], point, rule=NO_RETRY)
    return HeatedCurve(values, tuple(dists), time.perf_counter() - start)
