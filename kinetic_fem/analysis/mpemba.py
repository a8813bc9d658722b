"""The Mpemba effect of the heated gas (Lasanta, Vega Reyes, Prados and Santos 2017).

Two initial states above the steady temperature :math:`T_{st}` relax under the same
white noise: the hot one, :math:`T_A > T_B`, with a larger :math:`a_2` (a fatter tail
dissipates faster, :math:`\\langle|g|^3\\rangle \\propto 1 + 3a_2/16` for hard rods).
If the difference is large enough the hot curve overtakes the cold one and reaches
the neighbourhood of :math:`T_{st}` first.

*Threshold.*  Near the steady state :math:`T - T_{st}` is a sum of decaying modes;
the difference :math:`\\Delta(t) = T_A(t) - T_B(t)` starts positive and changes sign
once if and only if its slowest-mode amplitude is negative, and at the threshold the
crossing time diverges.  :func:`mpemba_threshold` therefore asks for a crossing
before a stated *horizon* :math:`t_H` (in relaxation times :math:`1/\\lambda_1`, the
slowest first-Sonine rate): the smallest :math:`a_2` of the hot start with
:math:`\\Delta(t_H) \\le 0`.  As the horizon grows it tends to the threshold of an
eventual crossing.

*Maxwell model.*  Its energy balance is closed,
:math:`dT/dt = 2D - \\tfrac n2(1-\\alpha^2)T`: :math:`T(t)` depends on :math:`T(0)` alone,
two temperature curves of one ODE never cross, and there is no Mpemba effect for any
initial shape (:func:`mpemba_threshold` returns None); the initial :math:`a_2` only
changes :math:`a_2(t)`.

Each curve is exact (:func:`kinetic_fem.evolve_heated` from
:func:`~kinetic_fem.analysis.memory_effects.sonine_distribution` initial states, or the
Maxwell moment equations) beside the first-Sonine one.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from .memory_effects import Curves, exact_curves, sonine_distribution
from .sonine_dynamics import evolve_sonine, sonine_relaxation_rates, steady_sonine

__all__ = ["MpembaResult", "mpemba", "mpemba_threshold", "mpemba_times", "crossing_time"]

logger = logging.getLogger(__name__)


def crossing_time(hot: Curves, cold: Curves) -> float | None:
    """First time the hot curve falls below the cold one (linear interpolation).

    Parameters
    ----------
    hot, cold : Curves
        On the same times.

    Returns
    -------
    float or None
        None if they do not cross.
    """
    diff = hot.temperature - cold.temperature
    below = np.flatnonzero(diff < 0)
    if not below.size or below[0] == 0:
        return None
    k = int(below[0])
    t0, t1 = hot.times[k - 1], hot.times[k]
    return float(t0 + (t1 - t0) * diff[k - 1] / (diff[k - 1] - diff[k]))


def mpemba_times(alpha: float, *, kernel: float = 1.0, horizon: float = 4.0,
                 n_times: int = 41) -> NDArray[np.float64]:
    """Output times: 0, then geometric to ``horizon`` first-Sonine relaxation times.

    Parameters
    ----------
    alpha : float
        Restitution coefficient.
    kernel : float
        :math:`\\gamma`.
    horizon : float
        Last time, in units of :math:`1/\\lambda_1` (white noise ``D = n = 1``).
    n_times : int
        Number of times.

    Returns
    -------
    ndarray, shape (n_times,)
    """
    rate = sonine_relaxation_rates(alpha, gamma=float(kernel))[0]
    return np.concatenate([[0.0], np.geomspace(1e-2, horizon, n_times - 1) / rate])


@dataclass(frozen=True)
class MpembaResult:
    """Two relaxations towards the steady state; the hotter one overtakes if ``crossing``.

    Attributes
    ----------
    alpha, gamma : float
        Restitution coefficient and kernel exponent.
    steady_temperature : float
        Exact :math:`T_{st}`.
    initial_temperatures : (float, float)
        Hot and cold start, :math:`T_A > T_B`.
    initial_a2 : (float, float)
        Their :math:`a_2`.
    threshold : float or None
        First-Sonine threshold (:func:`mpemba_threshold`) at the result's horizon.
    hot, cold : Curves
        Exact curves; ``hot_sonine``, ``cold_sonine`` the first-Sonine ones.
    initial_states : (VelocityDistribution, VelocityDistribution)
        The initial distributions (for particle runs).
    """

    alpha: float
    gamma: float
    steady_temperature: float
    initial_temperatures: tuple[float, float]
    initial_a2: tuple[float, float]
    threshold: float | None
    hot: Curves
    cold: Curves
    hot_sonine: Curves
    cold_sonine: Curves
    initial_states: tuple = ()

    @property
    def crossing(self) -> float | None:
        """Time at which the exact hot curve first falls below the cold one."""
        return crossing_time(self.hot, self.cold)

    @property
    def sonine_crossing(self) -> float | None:
        """The same for the first-Sonine curves."""
        return crossing_time(self.hot_sonine, self.cold_sonine)


def _steady_temperature(alpha: float, gamma: float, options: dict[str, Any]) -> float:
    if gamma == 0.0:
        from ..solvers.maxwell import steady_state

        return float(steady_state(alpha, order=2).temperature)
    from ..solve import solve_heated

    return float(solve_heated(alpha, kernel=gamma).temperature)


def _exact_start(alpha: float, gamma: float, times: NDArray[np.float64], temp: float,
                 a2: float, t_st: float, options: dict[str, Any]) -> Curves:
    start = sonine_distribution(temp, a2)
    moments = [1.0, 0.0, temp, 0.0, 3.0 * temp**2 * (1.0 + a2)]
    return exact_curves(alpha, gamma, times, 1.0, start, moments, options, t_min=t_st)[0]


def mpemba_threshold(alpha: float, *, kernel: float = 1.0, hot: float = 1.5, cold: float = 1.4,
                     cold_a2: float = 0.0, horizon: float = 4.0, method: str = "sonine",
                     xtol: float = 1e-4, **options: Any) -> float | None:
    """Smallest :math:`a_2` of the hot start that is below the cold curve at the horizon.

    Parameters
    ----------
    alpha : float
        Restitution coefficient.
    kernel : float
        :math:`\\gamma`.
    hot, cold : float
        Initial temperatures over the steady one (``hot > cold > 0``).
    cold_a2 : float
        :math:`a_2` of the cold start.
    horizon : float
        :math:`t_H` in first-Sonine relaxation times :math:`1/\\lambda_1`.
    method : {"sonine", "exact"}
        First-Sonine ODEs, or the exact curves (FEM or Maxwell; secant iterations on
        :math:`\\Delta(t_H)`, a few transient runs).
    xtol : float
        Tolerance on the threshold.
    **options
        For :func:`kinetic_fem.evolve_heated` (``method="exact"``).  The threshold is
        sensitive to the time error (the gap moves by only :math:`3.4\times10^{-3}
        T_{st}` per unit :math:`a_2` at :math:`\alpha = 0.6`): measured, hard rods,
        spacing 0.25, ``cutoff=10``: rtol 1e-5 / 1e-6 / 1e-7 give 0.45717 / 0.45671 /
        0.45666 against the converged 0.45663 (``benchmarks/results/memory_effects.md``),
        so ``rtol=1e-6`` for four digits; rtol 1e-4 (the default, at spacing 0.5) is
        3e-3 to 6e-3 off.

    Returns
    -------
    float or None
        None if even :math:`a_2 = 4/3` gives no crossing (e.g. Maxwell).

    Raises
    ------
    ValueError
        Unless ``hot > cold > 0``, or for an unknown ``method``.
    """
    if not hot > cold > 0:
        raise ValueError(f"need hot > cold > 0, got hot={hot}, cold={cold}")
    if method not in ("sonine", "exact"):
        raise ValueError(f"method must be 'sonine' or 'exact', got {method!r}")
    gamma = float(kernel)
    top = 4.0 / 3.0
    t_h = horizon / sonine_relaxation_rates(alpha, gamma=gamma)[0]
    times = np.array([0.0, t_h])
    if method == "sonine":
        t_st = steady_sonine(alpha, gamma=gamma)[0]
        t_cold = evolve_sonine(alpha, kernel=gamma, times=times, initial_temperature=cold * t_st,
                               initial_a2=cold_a2).temperature[-1]

        def gap(a2: float) -> float:
            return float(evolve_sonine(alpha, kernel=gamma, times=times,
                                       initial_temperature=hot * t_st,
                                       initial_a2=a2).temperature[-1] - t_cold) / t_st

        if gap(top) >= 0:
            return None
        return float(brentq(gap, 0.0, top, xtol=xtol)) if gap(0.0) > 0 else 0.0
    t_st = _steady_temperature(alpha, gamma, options)
    t_cold = _exact_start(alpha, gamma, times, cold * t_st, cold_a2, t_st, options).temperature[-1]

    def gap_exact(a2: float) -> float:
        t_hot = _exact_start(alpha, gamma, times, hot * t_st, a2, t_st, options).temperature[-1]
        return float(t_hot - t_cold) / t_st

    guess = mpemba_threshold(alpha, kernel=gamma, hot=hot, cold=cold, cold_a2=cold_a2,
                             horizon=horizon)
    x0 = 0.5 * top if guess is None else min(guess, 0.9 * top)
    x1 = min(x0 + 0.05, top)
    f0, f1 = gap_exact(x0), gap_exact(x1)
    if gamma == 0.0 and abs(f1 - f0) < 1e-9:
        return None  # T(t) does not depend on the shape
    for _ in range(12):
        x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
        if not 0.0 <= x2 <= top:
            return None if x2 > top else 0.0
        logger.info("exact Mpemba threshold: a2 = %.6f (gap %.3e)", x2, f1)
        if abs(x2 - x1) < xtol:
            return float(x2)
        x0, f0, x1, f1 = x1, f1, x2, gap_exact(x2)
    raise RuntimeError("the secant iteration for the exact Mpemba threshold did not converge")


def mpemba(alpha: float, *, kernel: float = 1.0, hot: float = 1.5, cold: float = 1.4,
           hot_a2: float = 1.0, cold_a2: float = 0.0, n_times: int = 41,
           horizon: float = 4.0, **options: Any) -> MpembaResult:
    """The Mpemba protocol: exact and first-Sonine relaxations of a hot and a cold start.

    Parameters
    ----------
    alpha : float
        Restitution coefficient.
    kernel : float
        :math:`\\gamma` (0 Maxwell, 1 hard rods).
    hot, cold : float
        Initial temperatures over the exact steady one.
    hot_a2, cold_a2 : float
        Initial :math:`a_2` (the initial states are
        :func:`~kinetic_fem.analysis.memory_effects.sonine_distribution`; in ``[0, 4/3]``).
    n_times : int
        Output times (:func:`mpemba_times`).
    horizon : float
        Time span in first-Sonine relaxation times of :math:`T`.
    **options
        For :func:`kinetic_fem.evolve_heated` (``spacing`` in thermal velocities at
        :math:`T_{st}`); :math:`T_{st}` is :func:`kinetic_fem.solve_heated` at its
        defaults.

    Returns
    -------
    MpembaResult

    Raises
    ------
    ValueError
        Unless ``hot > cold > 0``.
    """
    gamma = float(kernel)
    if not hot > cold > 0:
        raise ValueError(f"need hot > cold > 0, got hot={hot}, cold={cold}")
    t_st = _steady_temperature(alpha, gamma, options)
    s_st = steady_sonine(alpha, gamma=gamma)[0]
    times = mpemba_times(alpha, kernel=gamma, horizon=horizon, n_times=n_times)
    curves, starts = [], []
    for temp, a2 in ((hot, hot_a2), (cold, cold_a2)):
        curves.append(_exact_start(alpha, gamma, times, temp * t_st, a2, t_st, options))
        son = evolve_sonine(alpha, kernel=gamma, times=times, initial_temperature=temp * s_st,
                            initial_a2=a2)
        curves.append(Curves(times, son.temperature, son.a2))
        starts.append(sonine_distribution(temp * t_st, a2))
    threshold = mpemba_threshold(alpha, kernel=gamma, hot=hot, cold=cold, cold_a2=cold_a2,
                                 horizon=horizon)
    return MpembaResult(float(alpha), gamma, t_st, (hot * t_st, cold * t_st),
                        (hot_a2, cold_a2), threshold, curves[0], curves[2], curves[1], curves[3],
                        tuple(starts))
