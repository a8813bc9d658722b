"""Memory effects of the heated gas: the Kovacs hump and the Mpemba effect.

Both protocols use white noise of strength :math:`D`.  For a power-law kernel
:math:`|g|^\\gamma` the steady temperature scales as
:math:`T_{st}(D) = T_{st}(D_0)(D/D_0)^{2/(\\gamma+2)}` and the steady shape
(:math:`a_2`) does not depend on :math:`D`; the same holds for the first-Sonine ODEs.

*Kovacs* (Prados and Trizac 2014): start in the steady state at :math:`D_0`, quench
to :math:`D_1 \\ll D_0` and age for a waiting time :math:`t_w`; then switch to the
:math:`D_2` whose steady temperature equals :math:`T(t_w)` (by the scaling above,
:math:`D_2 = D_0 (T(t_w)/T_{st}(D_0))^{(\\gamma+2)/2}`: each method, exact or
first-Sonine, switches to its own :math:`D_2`).  Had :math:`T` been the only variable
it would stay put.  The energy balance
:math:`dT/dt = 2D - \\tfrac n4(1-\\alpha^2)\\langle|g|^{\\gamma+2}\\rangle` depends on the
shape (hard rods: :math:`\\langle|g|^3\\rangle \\propto T^{3/2}(1 + 3a_2/16)`), and during
the quench the gas cools almost freely, so :math:`a_2(t_w)` moves towards the cooling
state's value, away from :math:`a_2^{st}`.  Right after the switch
:math:`dT/dt \\propto -(a_2(t_w) - a_2^{st})`: a hump of the sign of
:math:`a_2^{st} - a_2(t_w)`, in practice the sign of :math:`-a_2^{st}` (negative for
:math:`\\alpha < 1/\\sqrt 2` where :math:`a_2^{st} > 0`, positive above).  The deeper
the quench (:math:`D_1 \\to 0`) and the longer the wait, the larger the hump.  For the
Maxwell model the energy balance is closed, :math:`dT/dt = 2D - \\tfrac n2(1-\\alpha^2)T`,
and there is no hump at all.

*Mpemba* (Lasanta, Vega Reyes, Prados and Santos 2017): see :mod:`.mpemba`.

The exact curves come from :func:`kinetic_fem.evolve_heated` (any kernel; the quench
is one run, the relaxation after the switch a second run started from the state at
:math:`t_w`) or, for Maxwell, from the closed moment equations of
:mod:`kinetic_fem.solvers.maxwell`; the first-Sonine ones from
:mod:`kinetic_fem.analysis.sonine_dynamics`.  The result holds the protocol and the
initial state so that particle methods can run the same.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..distribution import VelocityDistribution
from ..model import HeatedProblem
from ..model.protocol import Protocol, steps
from .sonine_dynamics import evolve_sonine, steady_sonine

__all__ = ["Curves", "KovacsResult", "kovacs", "extremum", "sonine_distribution",
           "sonine_waiting_time", "sonine_kovacs", "exact_curves", "transient_spacing"]

logger = logging.getLogger(__name__)


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


def extremum(times: NDArray[np.float64], values: NDArray[np.float64]) -> tuple[float, float]:
    """Time and value of the largest ``|values|`` (parabola through its neighbours).

    Parameters
    ----------
    times, values : ndarray, shape (n,)
        A sampled curve, ``n >= 3``.

    Returns
    -------
    (t, value) : tuple of float
        At an end point the sample itself.

    Examples
    --------
    >>> t = np.linspace(0.0, 2.0, 9)
    >>> [round(x, 12) for x in extremum(t, -(t - 0.9) ** 2 * 0 - 1 + (t - 0.9) ** 2)]
    [0.9, -1.0]
    """
    k = int(np.argmax(np.abs(values)))
    if k == 0 or k == len(values) - 1:
        return float(times[k]), float(values[k])
    c = np.polyfit(times[k - 1:k + 2] - times[k], values[k - 1:k + 2], 2)
    if c[0] == 0.0:
        return float(times[k]), float(values[k])
    dt = -c[1] / (2.0 * c[0])
    return float(times[k] + dt), float(np.polyval(c, dt))


def transient_spacing(spacing: float, alpha: float, gamma: float, d_min: float,
                      t_min: float, t_start: float) -> float:
    """The ``spacing`` option of :func:`kinetic_fem.evolve_heated` for a quench.

    The FEM transient sizes its elements from the Gaussian-closure steady temperature
    of the smallest :math:`D` of the protocol; a quench never gets that cold.  This
    returns the option that gives elements of ``spacing`` thermal velocities of
    ``t_min``, the coldest temperature the run meets.

    Parameters
    ----------
    spacing : float
        Wanted element size in thermal velocities of ``t_min``.
    alpha, gamma : float
        Restitution coefficient and kernel exponent.
    d_min : float
        Smallest :math:`D` of the protocol.
    t_min : float
        Coldest temperature of the run.
    t_start : float
        Temperature of the initial state.

    Returns
    -------
    float
    """
    est = HeatedProblem.from_parameters(alpha, diffusion=d_min, kernel=gamma).temperature_estimate()
    return float(spacing * math.sqrt(max(t_min / min(est, t_start), 1.0)))


def exact_curves(alpha: float, gamma: float, times: NDArray[np.float64], diffusion: float,
                 initial: VelocityDistribution | None, moments: list[float] | None,
                 options: dict[str, Any], t_min: float | None = None
                 ) -> tuple[Curves, Any]:
    """Exact :math:`T(t), a_2(t)` at constant white noise from an initial state.

    Parameters
    ----------
    alpha, gamma : float
        Restitution coefficient and kernel exponent (0: the Maxwell moment equations).
    times : ndarray, shape (n_t,)
        Output times from 0.
    diffusion : float
        :math:`D`.
    initial : VelocityDistribution or None
        Initial state (FEM).
    moments : list of float or None
        Initial moments :math:`M_0 .. M_4` (Maxwell).
    options : dict
        Options of :func:`kinetic_fem.evolve_heated` (``spacing`` in thermal
        velocities of ``t_min``, see :func:`transient_spacing`).
    t_min : float, optional
        Coldest temperature of the run (default: that of ``initial``).

    Returns
    -------
    (Curves, Evolution or MaxwellTransient)
    """
    if gamma == 0.0:
        from ..solvers.maxwell import evolve_moments

        mom = evolve_moments(alpha, times, diffusion=diffusion, initial_moments=moments,
                             rtol=1e-12)
        return Curves(times, mom.temperature, mom.a2), mom
    from ..evolve import evolve_heated

    assert initial is not None  # FEM needs a distribution
    opts = dict(options)
    # BDF2 unless asked otherwise: the memory effects are differences of 1e-4 T_st between
    # runs, which BDF2's errors (correlated between runs) keep; at rtol 1e-4 the Mpemba
    # runs' errors of T were -1.4e-4, -1.3e-4, -1.2e-4 T_st with BDF2 and -4.2e-4,
    # -0.9e-4, -0.8e-4 with BDF4 (issue 30; reference rtol 1e-7)
    opts.setdefault("scheme", "bdf2")
    # every ln P converged by the step Newton: on the moments' norm the alpha 0.9 Kovacs
    # quench (spacing 0.25, rtol 1e-5) reached a state with no continuation at s = 1.288
    opts.setdefault("newton_norm", "ln_p")
    t_low = initial.temperature if t_min is None else t_min
    opts["spacing"] = transient_spacing(opts.get("spacing", 0.25), alpha, gamma, diffusion,
                                        t_low, initial.temperature)
    ev = evolve_heated(alpha, kernel=gamma, diffusion=diffusion, times=times, initial=initial,
                       **opts)
    logger.info("exact curve: %s (%.1f s)", ev.info.message, ev.info.wall_time)
    return Curves(times, ev.temperature, ev.a2), ev


@dataclass(frozen=True)
class KovacsResult:
    """A Kovacs protocol and its curves.

    Attributes
    ----------
    alpha, gamma : float
        Restitution coefficient and kernel exponent.
    diffusion : tuple of float
        :math:`(D_0, D_1, D_2)` of the exact solution.
    waiting_time : float
        :math:`t_w` (the same for every method).
    steady_temperature : float
        :math:`T_{st}(D_2) = T(t_w)` of the exact solution.
    protocol : Protocol
        :math:`D(t)`: :math:`D_1` on :math:`[0, t_w)`, then :math:`D_2` (exact).
    initial : VelocityDistribution or None
        The steady state at :math:`D_0` (None for Maxwell, whose exact curves start from
        its exact moments).
    exact, sonine : Curves
        Exact and first-Sonine curves on the same times.
    sonine_diffusion : float
        :math:`D_2` of the first-Sonine protocol.
    sonine_steady_temperature : float
        Its :math:`T_{st}(D_2) = T_{sonine}(t_w)`.
    restart_mismatch : float
        :math:`T/T(t_w) - 1` of the state the second exact run starts from (the FEM
        state at :math:`t_w` interpolated on the second run's mesh; 0 for Maxwell).
    info : dict
        Run details (FEM messages and wall times).
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
    sonine_diffusion: float
    sonine_steady_temperature: float
    restart_mismatch: float = 0.0
    info: dict = field(default_factory=dict)

    def deviation(self, sonine: bool = False) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """:math:`(t - t_w, T/T_{st} - 1)` after the switch.

        Parameters
        ----------
        sonine : bool
            The first-Sonine curve instead of the exact one.

        Returns
        -------
        (ndarray, ndarray)
        """
        c, t_st = (self.sonine, self.sonine_steady_temperature) if sonine else (
            self.exact, self.steady_temperature)
        after = c.times >= self.waiting_time
        return c.times[after] - self.waiting_time, c.temperature[after] / t_st - 1.0

    @property
    def hump(self) -> float:
        """Extremum of :math:`T/T_{st} - 1` after :math:`t_w` of the exact curve, signed."""
        return extremum(*self.deviation())[1]

    @property
    def hump_time(self) -> float:
        """:math:`t - t_w` of the exact hump's extremum."""
        return extremum(*self.deviation())[0]

    @property
    def sonine_hump(self) -> float:
        """Extremum of the first-Sonine :math:`T/T_{st} - 1` after :math:`t_w`."""
        return extremum(*self.deviation(sonine=True))[1]


def sonine_kovacs(alpha: float, gamma: float, d_start: float, d_quench: float, tw: float,
                  before: NDArray[np.float64], after: NDArray[np.float64]
                  ) -> tuple[Curves, float, float]:
    """First-Sonine Kovacs curve: quench to ``d_quench`` for ``tw``, then its own :math:`D_2`.

    Parameters
    ----------
    alpha, gamma : float
        Restitution coefficient and kernel exponent.
    d_start, d_quench : float
        :math:`D_0` (steady start) and :math:`D_1`.
    tw : float
        Waiting time.
    before, after : ndarray
        Output times in ``[0, tw]`` and after ``tw``.

    Returns
    -------
    (Curves, float, float)
        The curve on ``before`` and ``after``, :math:`D_2` and :math:`T(t_w)`.
    """
    s0, a0 = steady_sonine(alpha, gamma=gamma, diffusion=d_start)
    q = evolve_sonine(alpha, kernel=gamma, diffusion=d_quench, times=[0.0, tw],
                      initial_temperature=s0, initial_a2=a0)
    t_tw = float(q.temperature[-1])
    d2 = d_start * (t_tw / s0) ** ((gamma + 2.0) / 2.0)
    times = np.concatenate([before, after])
    s = evolve_sonine(alpha, kernel=gamma, diffusion=d_quench, times=times,
                      protocol=Protocol(diffusion=steps([tw], [d_quench, d2])),
                      initial_temperature=s0, initial_a2=a0)
    return Curves(times, s.temperature, s.a2), d2, t_tw


def sonine_waiting_time(alpha: float, *, kernel: float = 1.0, d_start: float = 1.0,
                        d_quench: float = 1e-3, d_final: float = 0.1) -> float:
    """First-Sonine time for the quench from :math:`T_{st}(D_0)` to reach :math:`T_{st}(D_2)`.

    Parameters
    ----------
    alpha : float
        Restitution coefficient.
    kernel : float
        :math:`\\gamma`.
    d_start, d_quench, d_final : float
        :math:`D_0 > D_2 > D_1 > 0`.

    Returns
    -------
    float
    """
    from scipy.optimize import brentq

    gamma = float(kernel)
    s0, a0 = steady_sonine(alpha, gamma=gamma, diffusion=d_start)
    target = s0 * (d_final / d_start) ** (2.0 / (gamma + 2.0))

    def gap(t: float) -> float:
        if t <= 0.0:
            return s0 - target
        q = evolve_sonine(alpha, kernel=gamma, diffusion=d_quench, times=[0.0, t],
                          initial_temperature=s0, initial_a2=a0)
        return float(q.temperature[-1] - target)

    hi = 1.0 / (s0 ** (gamma / 2.0) * max(1.0 - alpha * alpha, 1e-3))
    while gap(hi) > 0:
        hi *= 2.0
    return float(brentq(gap, 0.0, hi, xtol=1e-12, rtol=1e-12))


def kovacs(alpha: float, *, kernel: float = 1.0, d_start: float = 1.0, d_quench: float = 1e-3,
           d_final: float = 0.1, waiting_time: float | None = None, duration: float = 4.0,
           n_before: int = 11, n_times: int = 41, **options: Any) -> KovacsResult:
    """The Kovacs protocol (module docstring): exact and first-Sonine curves.

    Parameters
    ----------
    alpha : float
        Restitution coefficient.
    kernel : float
        :math:`\\gamma` (0 Maxwell, 1 hard rods).
    d_start, d_quench : float
        :math:`D_0 > D_1 > 0`.
    d_final : float
        Sets the default waiting time: the first-Sonine time for the quench to reach
        :math:`T_{st}(D_{final})` (:func:`sonine_waiting_time`); ``d_quench < d_final
        < d_start``.
    waiting_time : float, optional
        :math:`t_w` instead.
    duration : float
        Time after the switch to follow, in units of :math:`t_w`.
    n_before, n_times : int
        Output times before the switch (uniform) and after it (geometric in
        :math:`t - t_w`, from :math:`10^{-3} t_w`).
    **options
        For :func:`kinetic_fem.evolve_heated` (``rtol``, ``cutoff``, ``order`` and
        ``spacing``, here in thermal velocities of the coldest temperature met); the
        initial steady state is :func:`kinetic_fem.solve_heated` at its defaults.

    Returns
    -------
    KovacsResult

    Raises
    ------
    ValueError
        Unless ``0 < d_quench < d_final < d_start`` and ``waiting_time > 0``.
    """
    if not 0 < d_quench < d_final < d_start:
        raise ValueError(f"need 0 < d_quench < d_final < d_start, got {d_quench}, {d_final}, "
                         f"{d_start}")
    gamma = float(kernel)
    tw = (sonine_waiting_time(alpha, kernel=gamma, d_start=d_start, d_quench=d_quench,
                              d_final=d_final) if waiting_time is None else float(waiting_time))
    if not (math.isfinite(tw) and tw > 0):
        raise ValueError(f"waiting_time={waiting_time!r} must be finite and > 0")
    before = np.linspace(0.0, tw, n_before)
    offsets = tw * duration * np.geomspace(1e-3, 1.0, n_times)
    sonine, d2_s, t_s = sonine_kovacs(alpha, gamma, d_start, d_quench, tw, before, tw + offsets)
    info: dict[str, Any] = {}
    mismatch = 0.0
    if gamma == 0.0:
        from ..solvers.maxwell import steady_state

        st0 = steady_state(alpha, order=2, diffusion=d_start)
        t0, initial = st0.temperature, None
        first, _ = exact_curves(alpha, gamma, before, d_quench, None,
                                [float(x) for x in st0.moments], options)
        t_tw = float(first.temperature[-1])
        d2 = d_start * t_tw / t0
        m4 = 3.0 * t_tw**2 * (1.0 + float(first.a2[-1]))
        second, _ = exact_curves(alpha, gamma, np.concatenate([[0.0], offsets]), d2, None,
                                 [1.0, 0.0, t_tw, 0.0, m4], options)
    else:
        from ..solve import solve_heated

        initial = solve_heated(alpha, kernel=gamma, diffusion=d_start)
        t0 = initial.temperature
        t_guess = t0 * t_s / steady_sonine(alpha, gamma=gamma, diffusion=d_start)[0]
        first, ev1 = exact_curves(alpha, gamma, before, d_quench, initial, None, options,
                                  t_min=0.95 * t_guess)
        t_tw = float(first.temperature[-1])
        d2 = d_start * (t_tw / t0) ** ((gamma + 2.0) / 2.0)
        second, ev2 = exact_curves(alpha, gamma, np.concatenate([[0.0], offsets]), d2, ev1[-1],
                                   None, options, t_min=0.95 * t_tw)
        mismatch = float(second.temperature[0] / t_tw - 1.0)
        info = {"quench": ev1.info.message, "relaxation": ev2.info.message,
                "wall_time": ev1.info.wall_time + ev2.info.wall_time}
        logger.info("Kovacs alpha=%g: restart mismatch %.2e", alpha, mismatch)
    exact = Curves(np.concatenate([before, tw + offsets]),
                   np.concatenate([first.temperature, second.temperature[1:]]),
                   np.concatenate([first.a2, second.a2[1:]]))
    protocol = Protocol(diffusion=steps([tw], [d_quench, d2]))
    return KovacsResult(float(alpha), gamma, (d_start, d_quench, d2), tw, t_tw, protocol,
                        initial, exact, sonine, d2_s, t_s, mismatch, info)


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
