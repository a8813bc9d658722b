"""Memory effects of the heated gas: the Kovacs hump and the Mpemba effect.

Both protocols use white noise of strength :math:`D` (steady temperature
:math:`T_{st}(D)`, for hard rods :math:`\\propto D^{2/3}`, Maxwell :math:`\\propto D`;
the steady :math:`a_2` does not depend on :math:`D`).

*Kovacs* (Prados and Trizac 2014): from the steady state at :math:`D_0`, quench to
:math:`D_1 < D_0`; at the waiting time :math:`t_w` where :math:`T(t_w) =
T_{st}(D_2)`, :math:`D_1 < D_2 < D_0`, switch to :math:`D_2`.  Had :math:`T` been
the only variable it would stay put; the energy balance
:math:`dT/dt = 2D - \\tfrac n4(1-\\alpha^2)\\langle|g|^{\\gamma+2}\\rangle` depends on
the shape through :math:`a_2` (hard rods:
:math:`\\langle|g|^3\\rangle \\propto T^{3/2}(1 + 3a_2/16)`), so right after the
switch :math:`dT/dt \\propto a_2^{st} - a_2(t_w)`: a hump whose sign is that of
:math:`a_2^{st} - a_2(t_w)` (not fixed here: the measured sign is reported by
:attr:`KovacsResult.hump`), and which vanishes for the Maxwell model, whose energy
balance is closed.

*Mpemba* (Lasanta, Vega Reyes, Prados and Santos 2017): two initial states above the
steady temperature, the hotter one with a larger :math:`a_2` (it dissipates faster);
if the difference is large enough the hotter one overtakes the colder one and
reaches the steady temperature first.  :func:`mpemba_threshold` finds the smallest
initial :math:`a_2` of the hotter state for which the first-Sonine curves cross;
there is none for the Maxwell model (:math:`T(t)` does not depend on the shape).

Each function returns the exact curves (hard rods and other kernels:
:func:`kinetic_fem.evolve_heated`; Maxwell: the closed moment equations of
:mod:`kinetic_fem.solvers.maxwell`) beside the first-Sonine ones
(:mod:`kinetic_fem.analysis.sonine_dynamics`), with the protocol and initial states
so that particle methods can run the same.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from ..distribution import VelocityDistribution
from ..model.protocol import Protocol, steps
from .sonine_dynamics import evolve_sonine, steady_sonine

__all__ = ["Curves", "KovacsResult", "MpembaResult", "kovacs", "mpemba", "mpemba_threshold",
           "sonine_distribution"]


@dataclass(frozen=True)
class Curves:
    """:math:`T(t)` and :math:`a_2(t)` at ``times`` (one method).

    Parameters
    ----------
    times : ndarray, shape (n_t,)
        Output times.
    temperature, a2 : ndarray, shape (n_t,)
        :math:`T(t_i)` and :math:`a_2(t_i)`.
    """

    times: NDArray[np.float64]
    temperature: NDArray[np.float64]
    a2: NDArray[np.float64]


@dataclass(frozen=True)
class KovacsResult:
    """A Kovacs protocol and its curves.

    Attributes
    ----------
    alpha, gamma : float
    diffusion : tuple of float
        :math:`(D_0, D_1, D_2)`.
    waiting_time : float
        :math:`t_w` of the exact solution (the protocol's switch).
    steady_temperature : float
        :math:`T_{st}(D_2)` of the exact solution.
    protocol : Protocol
        :math:`D(t)`: :math:`D_1` on :math:`[0, t_w)`, then :math:`D_2`.
    initial : VelocityDistribution or None
        The steady state at :math:`D_0` (None for Maxwell, whose exact curves start from
        its exact moments).
    exact, sonine : Curves
        Exact and first-Sonine curves (the Sonine one with its own :math:`t_w` and
        :math:`T_{st}`, ``sonine_waiting_time``, ``sonine_steady_temperature``).
    """

    alpha: float
    gamma: float
    diffusion: tuple[float, float, float]
    waiting_time: float
    steady_temperature: float
    protocol: Protocol
    initial: VelocityDistribution | None
    exact: Curves
    sonine: Curves
    sonine_waiting_time: float
    sonine_steady_temperature: float

    @property
    def hump(self) -> float:
        """Largest :math:`|T/T_{st} - 1|` after :math:`t_w` of the exact curve, signed."""
        after = self.exact.times >= self.waiting_time
        dev = self.exact.temperature[after] / self.steady_temperature - 1.0
        return float(dev[np.argmax(np.abs(dev))])


def _maxwell_exact(alpha: float, times: NDArray[np.float64], protocol: Protocol,
                   moments: list[float], diffusion: float) -> Curves:
    from ..solvers.maxwell import evolve_moments

    ev = evolve_moments(alpha, times, diffusion=lambda t: protocol.diffusion_at(t, diffusion),
                        initial_moments=moments, breakpoints=protocol.breakpoints(times[-1]),
                        rtol=1e-10)
    return Curves(times, ev.temperature, ev.a2)


def _exact(alpha: float, gamma: float, times: NDArray[np.float64], protocol: Protocol,
           diffusion: float, initial: VelocityDistribution | None, moments: list[float],
           options: dict[str, Any]) -> Curves:
    if gamma == 0.0:
        return _maxwell_exact(alpha, times, protocol, moments, diffusion)
    from ..evolve import evolve_heated

    ev = evolve_heated(alpha, kernel=gamma, diffusion=diffusion, times=times, protocol=protocol,
                       initial=initial, **options)
    return Curves(times, ev.temperature, ev.a2)


def _crossing(times: NDArray[np.float64], values: NDArray[np.float64], level: float) -> float:
    """First time the decreasing curve falls to ``level`` (cubic through 4 points)."""
    k = int(np.argmax(values <= level))
    if k == 0:
        raise ValueError("the quench never reaches the target temperature in the time span; "
                         "lengthen it or raise d_final")
    lo = max(0, min(k - 2, len(times) - 4))
    coeffs = np.polyfit(times[lo:lo + 4], values[lo:lo + 4] - level, 3)
    roots = [r.real for r in np.roots(coeffs) if abs(r.imag) < 1e-12
             and times[k - 1] - 1e-12 <= r.real <= times[k] + 1e-12]
    return float(roots[0]) if roots else float(np.interp(level, values[k - 1:k + 1][::-1],
                                                         times[k - 1:k + 1][::-1]))


def kovacs(alpha: float, *, kernel: float = 1.0, d_start: float = 1.0, d_quench: float = 0.05,
           d_final: float = 0.3, duration: float = 6.0, n_times: int = 61,
           **options: Any) -> KovacsResult:
    """The Kovacs protocol: exact and first-Sonine curves.

    Parameters
    ----------
    alpha : float
        Restitution coefficient.
    kernel : float
        :math:`\\gamma` (0 Maxwell, 1 hard rods).
    d_start, d_quench, d_final : float
        :math:`D_0 > D_2 > D_1 > 0`.
    duration : float
        Time after the switch to follow, in units of :math:`t_w`.
    n_times : int
        Output times after the switch (geometric in :math:`t - t_w`).
    **options
        For :func:`kinetic_fem.evolve_heated` and :func:`kinetic_fem.solve_heated`
        (e.g. ``spacing``, ``rtol``).

    Returns
    -------
    KovacsResult
    """
    from ..solve import solve_heated

    if not 0 < d_quench < d_final < d_start:
        raise ValueError(f"need 0 < d_quench < d_final < d_start, got {d_quench}, {d_final}, "
                         f"{d_start}")
    gamma = float(kernel)
    solve_opts = {k: v for k, v in options.items() if k in ("spacing", "cutoff", "order")}
    initial = solve_heated(alpha, kernel=gamma, diffusion=d_start, **solve_opts)
    final = solve_heated(alpha, kernel=gamma, diffusion=d_final, **solve_opts)
    if gamma == 0.0:
        from ..solvers.maxwell import steady_state

        st0 = steady_state(alpha, order=2, diffusion=d_start)
        moments = [float(x) for x in st0.moments]
        t_st = steady_state(alpha, order=2, diffusion=d_final).temperature
    else:
        moments = []
        t_st = final.temperature
    s0, a0 = steady_sonine(alpha, gamma=gamma, diffusion=d_start)
    s_st, _ = steady_sonine(alpha, gamma=gamma, diffusion=d_final)
    # waiting times: the quench alone, on a fine grid up to the Sonine estimate x 2
    probe = np.linspace(0.0, 1.0, 201)
    quench = evolve_sonine(alpha, kernel=gamma, diffusion=d_quench, times=probe * 50.0,
                           initial_temperature=s0, initial_a2=a0)
    tw_s = _crossing(quench.times, quench.temperature, s_st)
    span = probe * 2.0 * tw_s
    first = _exact(alpha, gamma, span, Protocol(), d_quench, initial, moments, options)
    tw = _crossing(span, first.temperature, t_st)
    after = tw + tw * duration * np.geomspace(1e-3, 1.0, n_times)
    times = np.concatenate([np.linspace(0.0, tw, 11), after])
    protocol = Protocol(diffusion=steps([tw], [d_quench, d_final]))
    exact = _exact(alpha, gamma, times, protocol, d_quench, initial, moments, options)
    s_times = np.concatenate([np.linspace(0.0, tw_s, 11),
                              tw_s + tw_s * duration * np.geomspace(1e-3, 1.0, n_times)])
    sonine = evolve_sonine(alpha, kernel=gamma, diffusion=d_quench, times=s_times,
                           protocol=Protocol(diffusion=steps([tw_s], [d_quench, d_final])),
                           initial_temperature=s0, initial_a2=a0)
    return KovacsResult(float(alpha), gamma, (d_start, d_quench, d_final), tw, float(t_st),
                        protocol, initial, exact,
                        Curves(sonine.times, sonine.temperature, sonine.a2), tw_s, s_st)


def sonine_distribution(temperature: float, a2: float, *, c_max: float = 10.0,
                        n_v: int = 801) -> VelocityDistribution:
    """:math:`P(v) = \\Phi(c)(1 + a_2 S_2(c^2))/\\sqrt T` on a grid (``0 <= a2 <= 4/3``).

    Parameters
    ----------
    temperature : float
        :math:`T > 0`.
    a2 : float
        Sonine coefficient in ``[0, 4/3]`` (where the density stays >= 0).
    c_max : float
        Grid extent in :math:`c`.
    n_v : int
        Number of nodes.

    Returns
    -------
    VelocityDistribution

    Examples
    --------
    >>> d = sonine_distribution(2.0, 0.5)
    >>> round(d.temperature, 8), round(d.a2, 8)
    (2.0, 0.5)
    """
    if not 0.0 <= a2 <= 4.0 / 3.0:
        raise ValueError(f"a2={a2!r} is not allowed: 0 <= a2 <= 4/3 keeps the density >= 0")
    if not (math.isfinite(temperature) and temperature > 0):
        raise ValueError(f"temperature={temperature!r} must be finite and > 0")
    c = np.linspace(-c_max, c_max, n_v)
    x = c * c
    p = np.exp(-0.5 * x) / math.sqrt(2 * math.pi) * (1 + a2 * (x * x / 8 - 0.75 * x + 0.375))
    v = c * math.sqrt(temperature)
    return VelocityDistribution.from_values(v, p / math.sqrt(temperature))


@dataclass(frozen=True)
class MpembaResult:
    """Two relaxations towards the steady state; the hotter one overtakes if ``crossing``.

    Attributes
    ----------
    alpha, gamma : float
    steady_temperature : float
        Exact :math:`T_{st}`.
    initial_temperatures : (float, float)
        Hot and cold start, :math:`T_A > T_B`.
    initial_a2 : (float, float)
        Their :math:`a_2`.
    threshold : float or None
        Smallest :math:`a_2` of the hot start for which the first-Sonine curves cross
        (None: no crossing for any allowed :math:`a_2`, e.g. Maxwell).
    hot, cold : Curves
        Exact curves; ``hot_sonine``, ``cold_sonine`` the first-Sonine ones.
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

    @property
    def crossing(self) -> float | None:
        """First output time at which the exact hot curve is below the cold one."""
        below = np.flatnonzero(self.hot.temperature < self.cold.temperature)
        return float(self.hot.times[below[0]]) if below.size else None


def mpemba_threshold(alpha: float, *, kernel: float = 1.0, hot: float = 1.5, cold: float = 1.4,
                     cold_a2: float = 0.0, horizon: float = 10.0) -> float | None:
    """Smallest :math:`a_2` of the hot start whose first-Sonine curve crosses the cold one.

    Parameters
    ----------
    alpha : float
    kernel : float
        :math:`\\gamma`.
    hot, cold : float
        Initial temperatures over the steady one (``hot > cold > 0``).
    cold_a2 : float
        :math:`a_2` of the cold start.
    horizon : float
        Time span searched, in units of the relaxation time of :math:`T`.

    Returns
    -------
    float or None
        None if even :math:`a_2 = 4/3` gives no crossing.
    """
    gamma = float(kernel)
    t_st, _ = steady_sonine(alpha, gamma=gamma)
    nu = t_st ** (gamma / 2) * max(1.0 - alpha * alpha, 1e-3)
    times = np.linspace(0.0, horizon / nu, 800)
    cold_curve = evolve_sonine(alpha, kernel=gamma, times=times, initial_temperature=cold * t_st,
                               initial_a2=cold_a2).temperature

    def gap(a2: float) -> float:
        hot_curve = evolve_sonine(alpha, kernel=gamma, times=times,
                                  initial_temperature=hot * t_st, initial_a2=a2).temperature
        return float(np.min((hot_curve - cold_curve)[1:]) / t_st)

    top = 4.0 / 3.0
    if gap(top) >= 0:
        return None
    return float(brentq(gap, cold_a2, top, xtol=1e-6)) if gap(cold_a2) > 0 else cold_a2


def mpemba(alpha: float, *, kernel: float = 1.0, hot: float = 1.5, cold: float = 1.4,
           hot_a2: float = 1.0, cold_a2: float = 0.0, n_times: int = 41,
           horizon: float = 4.0, **options: Any) -> MpembaResult:
    """The Mpemba protocol: exact and first-Sonine relaxations of a hot and a cold start.

    Parameters
    ----------
    alpha : float
    kernel : float
        :math:`\\gamma` (0 Maxwell, 1 hard rods).
    hot, cold : float
        Initial temperatures over the exact steady one.
    hot_a2, cold_a2 : float
        Initial :math:`a_2` (the initial states are
        :func:`sonine_distribution`; in ``[0, 4/3]``).
    n_times : int
        Output times (geometric).
    horizon : float
        Time span in relaxation times of :math:`T`.
    **options
        For :func:`kinetic_fem.evolve_heated` and :func:`kinetic_fem.solve_heated`.

    Returns
    -------
    MpembaResult
    """
    from ..solve import solve_heated

    gamma = float(kernel)
    if not hot > cold > 0:
        raise ValueError(f"need hot > cold > 0, got hot={hot}, cold={cold}")
    solve_opts = {k: v for k, v in options.items() if k in ("spacing", "cutoff", "order")}
    if gamma == 0.0:
        from ..solvers.maxwell import steady_state

        t_st = steady_state(alpha, order=2).temperature
    else:
        t_st = solve_heated(alpha, kernel=gamma, **solve_opts).temperature
    s_st, _ = steady_sonine(alpha, gamma=gamma)
    nu = s_st ** (gamma / 2) * max(1.0 - alpha * alpha, 1e-3)
    times = np.concatenate([[0.0], np.geomspace(1e-2, horizon, n_times - 1) / nu])
    curves = []
    for temp, a2 in ((hot, hot_a2), (cold, cold_a2)):
        start = sonine_distribution(temp * t_st, a2)
        moments = [1.0, 0.0, temp * t_st, 0.0, 3 * (temp * t_st) ** 2 * (1 + a2)]
        curves.append(_exact(alpha, gamma, times, Protocol(), 1.0, start, moments, options))
        son = evolve_sonine(alpha, kernel=gamma, times=times, initial_temperature=temp * t_st,
                            initial_a2=a2)
        curves.append(Curves(times, son.temperature, son.a2))
    threshold = mpemba_threshold(alpha, kernel=gamma, hot=hot, cold=cold, cold_a2=cold_a2)
    return MpembaResult(float(alpha), gamma, float(t_st), (hot * t_st, cold * t_st),
                        (hot_a2, cold_a2), threshold, curves[0], curves[2], curves[1], curves[3])
