"""First-Sonine dynamics of the heated gas: closed ODEs for :math:`T(t)` and :math:`a_2(t)`.

The Boltzmann equation of the heated 1D gas with kernel :math:`|g|^\\gamma`,

.. math::

    \\partial_t P = Q_{\\alpha}[P] + \\partial_v(\\xi v P) + D\\,\\partial_v^2 P,

is closed at the first Sonine order by the ansatz

.. math::

    P(v, t) = \\frac{e^{-c^2/2}}{\\sqrt{2\\pi T}}\\,[1 + a_2 S_2(c^2)], \\qquad
    c = v/\\sqrt T, \\qquad S_2(x) = \\tfrac{x^2}{8} - \\tfrac{3x}{4} + \\tfrac38,

which keeps :math:`\\langle v^2 \\rangle = T` and :math:`\\langle v^4\\rangle = 3T^2(1 + a_2)`.
*Derivation.*  The weak form with a test function :math:`\\varphi`,
:math:`\\frac{d}{dt}\\langle\\varphi\\rangle|_{coll} = \\frac n2\\langle |g|^\\gamma
[\\varphi(v_1') + \\varphi(v_2') - \\varphi(v_1) - \\varphi(v_2)]\\rangle`, in the
centre-of-mass variables :math:`G = (v_1+v_2)/2`, :math:`g = v_1 - v_2` (a collision
keeps :math:`G` and maps :math:`g \\to -\\alpha g`; :math:`v_1^2 + v_2^2 = 2G^2 + g^2/2`,
:math:`v_1^4 + v_2^4 = 2G^4 + 3G^2g^2 + g^4/8`) gives

.. math::

    \\frac{dT}{dt} = 2D - 2\\xi T - \\frac n4 (1-\\alpha^2)\\langle |g|^{\\gamma+2}\\rangle,
    \\qquad
    \\frac{d\\langle v^4\\rangle}{dt} = 12DT - 4\\xi\\langle v^4\\rangle
    - \\frac n2\\Big[3(1-\\alpha^2)\\langle G^2|g|^{\\gamma+2}\\rangle
    + \\frac{1-\\alpha^4}{8}\\langle|g|^{\\gamma+4}\\rangle\\Big],

with pair averages over :math:`P(v_1)P(v_2)`.  Under the ansatz, :math:`G` and
:math:`g` of the Gaussian part are independent (variances :math:`T/2` and
:math:`2T`) and the Sonine factors are polynomials in them, so every pair average is
:math:`T^{(\\gamma+k)/2}(A_0 + A_1 a_2 + A_2 a_2^2)` with numbers :math:`A_j`
computed here from Gaussian moments (:func:`pair_average`).  The first Sonine
approximation keeps them to first order in :math:`a_2` (``linear=True``, the usual
choice: Prados and Trizac 2014, Lasanta et al. 2017); ``linear=False`` keeps the
ansatz's quadratic terms.  With :math:`\\langle v^4\\rangle = 3T^2(1+a_2)`,

.. math::

    \\frac{da_2}{dt} = \\frac{1}{3T^2}\\Big[\\frac{d\\langle v^4\\rangle}{dt}\\Big|_{coll}
    - 6T(1+a_2)\\frac{dT}{dt}\\Big|_{coll}\\Big] - \\frac{4 D a_2}{T}

(the friction drops out of :math:`da_2/dt`).  Checks: for the Maxwell model
(:math:`\\gamma = 0`) the pair averages involve moments up to the fourth only, the
ansatz's quadratic terms vanish and the equations are exact (they equal the closed
moment equations of :mod:`kinetic_fem.solvers.maxwell`); for hard rods under white
noise the steady :math:`a_2` is :func:`kinetic_fem.sonine.a2_first_order`,
:math:`16(1-2\\alpha^2)/(129+30\\alpha^2)`.

References
----------
A. Prados and E. Trizac, Phys. Rev. Lett. 112, 198001 (2014);
A. Lasanta, F. Vega Reyes, A. Prados and A. Santos, Phys. Rev. Lett. 119, 148001 (2017).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import solve_ivp
from scipy.signal import convolve2d

from ..model import CollisionKernel, HeatedProblem, RestitutionLaw
from ..model.protocol import Protocol

__all__ = ["SonineTrajectory", "pair_average", "sonine_rates", "evolve_sonine",
           "steady_sonine", "sonine_relaxation_rates"]


def _gaussian_moment(k: int, variance: float) -> float:
    """:math:`E|x|^k` of :math:`x \\sim N(0, \\sigma^2)`, any real ``k >= 0``."""
    return variance ** (k / 2) * 2 ** (k / 2) * math.gamma((k + 1) / 2) / math.sqrt(math.pi)


def _sonine_factor(sign: float) -> NDArray[np.float64]:
    """Coefficients ``[i, j]`` of :math:`S_2(c^2)`, :math:`c = G \\pm g/2` (T = 1)."""
    c = np.array([[0.0, sign * 0.5], [1.0, 0.0]])  # c[i, j]: G^i g^j
    c2 = convolve2d(c, c)
    c4 = convolve2d(c2, c2)
    out = c4 / 8.0
    out[: c2.shape[0], : c2.shape[1]] -= 0.75 * c2
    out[0, 0] += 3.0 / 8.0
    return out


@lru_cache(maxsize=64)
def pair_average(g_power: float, G_power: int) -> tuple[float, float, float]:
    """:math:`\\langle G^{m}|g|^{p}\\rangle = A_0 + A_1 a_2 + A_2 a_2^2` at :math:`T = 1`.

    Parameters
    ----------
    g_power : float
        :math:`p \\ge 0` (e.g. :math:`\\gamma + 2`).
    G_power : int
        :math:`m \\ge 0`, even.

    Returns
    -------
    (A0, A1, A2) : tuple of float
        Average over :math:`P(v_1)P(v_2)` of the first-Sonine ansatz; at temperature
        :math:`T` multiply by :math:`T^{(p+m)/2}`.

    Examples
    --------
    >>> a0, a1, a2 = pair_average(3.0, 0)  # <|g|^3> = (8/sqrt(pi))(1 + 3 a2/16 + ...)
    >>> round(a0 * math.sqrt(math.pi) / 8, 12), round(a1 / a0, 12)
    (1.0, 0.1875)
    """
    s1, s2 = _sonine_factor(1.0), _sonine_factor(-1.0)
    one = np.zeros_like(s1)
    one[0, 0] = 1.0
    terms = (convolve2d(one, one), convolve2d(s1, one) + convolve2d(one, s2), convolve2d(s1, s2))
    out = []
    for poly in terms:
        total = 0.0
        for i, j in zip(*np.nonzero(poly), strict=True):
            if (i + G_power) % 2 or j % 2:
                continue
            total += (poly[i, j] * _gaussian_moment(i + G_power, 0.5)
                      * _gaussian_moment(j + g_power, 2.0))
        out.append(float(total))
    return out[0], out[1], out[2]


def _poly(coeffs: tuple[float, float, float], a2: float, linear: bool) -> float:
    return coeffs[0] + coeffs[1] * a2 + (0.0 if linear else coeffs[2] * a2 * a2)


def sonine_rates(temperature: float, a2: float, alpha: float, *, gamma: float = 1.0,
                 density: float = 1.0, diffusion: float = 1.0, friction: float = 0.0,
                 linear: bool = True) -> tuple[float, float]:
    """:math:`(dT/dt, da_2/dt)` of the first-Sonine closure (module docstring).

    Parameters
    ----------
    temperature, a2 : float
        State :math:`T > 0`, :math:`a_2`.
    alpha : float
        Restitution coefficient (constant).
    gamma, density, diffusion, friction : float
        Kernel exponent, :math:`n`, :math:`D`, :math:`\\xi`.
    linear : bool
        Pair averages to first order in :math:`a_2` (the first Sonine approximation).

    Returns
    -------
    (dT/dt, da2/dt) : tuple of float

    Examples
    --------
    The Maxwell model's steady state: :math:`T = 4D/(n(1-\\alpha^2))`,
    :math:`a_2 = 2(1-\\alpha^2)/(7+\\alpha^2)`.

    >>> t, a = 4 / 0.75, 2 * 0.75 / 7.25
    >>> [abs(x) < 1e-12 for x in sonine_rates(t, a, 0.5, gamma=0.0)]
    [True, True]
    """
    t, n = temperature, density
    e2 = 1.0 - alpha * alpha
    e4 = 1.0 - alpha**4
    g2 = _poly(pair_average(gamma + 2.0, 0), a2, linear) * t ** (1 + gamma / 2)
    big = _poly(pair_average(gamma + 2.0, 2), a2, linear) * t ** (2 + gamma / 2)
    g4 = _poly(pair_average(gamma + 4.0, 0), a2, linear) * t ** (2 + gamma / 2)
    dt_coll = -0.25 * n * e2 * g2
    dm4_coll = -0.5 * n * (3.0 * e2 * big + e4 * g4 / 8.0)
    dtemp = 2.0 * diffusion - 2.0 * friction * t + dt_coll
    da2 = (dm4_coll - 6.0 * t * (1.0 + a2) * dt_coll) / (3.0 * t * t) - 4.0 * diffusion * a2 / t
    return dtemp, da2


@dataclass(frozen=True)
class SonineTrajectory:
    """:math:`T(t)` and :math:`a_2(t)` of the first-Sonine closure at the output times.

    Attributes
    ----------
    times, temperature, a2 : ndarray, shape (n_t,)
    """

    times: NDArray[np.float64]
    temperature: NDArray[np.float64]
    a2: NDArray[np.float64]


def evolve_sonine(alpha: float | RestitutionLaw, *, times: ArrayLike,
                  protocol: Protocol | None = None, density: float = 1.0,
                  diffusion: float = 1.0, friction: float = 0.0,
                  kernel: float | CollisionKernel = 1.0,
                  initial_temperature: float | None = None,
                  initial_a2: float = 0.0, linear: bool = True, rtol: float = 1e-10
                  ) -> SonineTrajectory:
    """Integrate the first-Sonine ODEs along a protocol (as :func:`kinetic_fem.evolve_heated`).

    Parameters
    ----------
    alpha : float or RestitutionLaw
        Restitution at ``t = 0`` (a constant law; changes come from ``protocol``).
    times : array_like, shape (n_t,)
        Output times, strictly increasing, ``>= 0``; the state at ``t = 0`` is the
        initial one.
    protocol : Protocol, optional
        :math:`D(t)`, :math:`\\xi(t)` and restitution changes.
    density, diffusion, friction : float
        :math:`n`, and :math:`D`, :math:`\\xi` where the protocol leaves them alone.
    kernel : float or CollisionKernel
        :math:`|g|^\\gamma`.
    initial_temperature : float, optional
        Default: the Gaussian-closure steady temperature at ``t = 0``.
    initial_a2 : float
        :math:`a_2(0)`.
    linear : bool
        First order in :math:`a_2` in the pair averages (see :func:`sonine_rates`).
    rtol : float
        Relative tolerance of the integrator (DOP853; restarts at breakpoints).

    Returns
    -------
    SonineTrajectory

    Raises
    ------
    ValueError
        For invalid parameters or times, or a restitution law that is not constant.
    """
    from ..model.validation import check_times

    problem = HeatedProblem.from_parameters(alpha, density=density, diffusion=diffusion,
                                            friction=friction, kernel=kernel)
    protocol = Protocol() if protocol is None else protocol
    t_out = check_times(times)
    gamma = problem.gas.gamma
    temp0 = (problem.temperature_estimate() if initial_temperature is None
             else float(initial_temperature))
    if not (math.isfinite(temp0) and temp0 > 0):
        raise ValueError(f"initial_temperature={initial_temperature!r} must be finite and > 0")

    def alpha_at(t: float) -> float:
        law = protocol.restitution_at(t, problem.gas.restitution)
        if law.constant is None:
            raise ValueError(f"the first-Sonine closure needs a constant restitution, got {law!r}")
        return float(law.constant)

    cuts = [0.0, *protocol.breakpoints(float(t_out[-1])), float(t_out[-1])]
    state = np.array([temp0, float(initial_a2)])
    temps, a2s = [], []
    if t_out[0] == 0.0:
        temps.append(state[0])
        a2s.append(state[1])
    for lo, hi in zip(cuts[:-1], cuts[1:], strict=True):
        a = alpha_at(lo)

        def rhs(t: float, y: NDArray[np.float64], a: float = a) -> list[float]:
            return list(sonine_rates(y[0], y[1], a, gamma=gamma, density=problem.gas.density,
                                     diffusion=protocol.diffusion_at(t, problem.diffusion),
                                     friction=protocol.friction_at(t, problem.friction),
                                     linear=linear))

        sel = t_out[(t_out > lo) & (t_out <= hi)]
        sol = solve_ivp(rhs, (lo, hi), state, method="DOP853", t_eval=np.union1d(sel, [hi]),
                        rtol=rtol, atol=1e-14)
        if not sol.success:
            raise RuntimeError(f"the first-Sonine ODEs failed on [{lo}, {hi}]: {sol.message}")
        for t in sel:
            k = int(np.searchsorted(sol.t, t))
            temps.append(sol.y[0, k])
            a2s.append(sol.y[1, k])
        state = sol.y[:, -1]
    return SonineTrajectory(t_out, np.array(temps), np.array(a2s))


def steady_sonine(alpha: float, *, gamma: float = 1.0, density: float = 1.0,
                  diffusion: float = 1.0, friction: float = 0.0, linear: bool = True
                  ) -> tuple[float, float]:
    """Steady :math:`(T, a_2)` of the first-Sonine ODEs (a root of :func:`sonine_rates`).

    Parameters
    ----------
    alpha : float
        Restitution coefficient.
    gamma, density, diffusion, friction : float
        As :func:`sonine_rates`.
    linear : bool
        As :func:`sonine_rates`.

    Returns
    -------
    (T, a2) : tuple of float

    Examples
    --------
    >>> t, a = steady_sonine(0.5)
    >>> round(a, 12) == round(16 * (1 - 2 * 0.25) / (129 + 30 * 0.25), 12)
    True
    """
    from scipy.optimize import fsolve

    problem = HeatedProblem.from_parameters(alpha, density=density, diffusion=diffusion,
                                            friction=friction, kernel=gamma)
    guess = np.array([problem.temperature_estimate(), 0.0])
    scale = np.array([guess[0], 1.0])

    def f(y: NDArray[np.float64]) -> list[float]:
        dt, da = sonine_rates(y[0] * scale[0], y[1], alpha, gamma=gamma, density=density,
                              diffusion=diffusion, friction=friction, linear=linear)
        return [dt / (diffusion + friction * scale[0]), da * scale[0] / diffusion]

    y, _, _, msg = fsolve(f, guess / scale, full_output=True, xtol=1e-13)
    if not np.all(np.abs(f(y)) < 1e-11):
        raise RuntimeError(f"steady first-Sonine state not found: {msg}")
    return float(y[0] * scale[0]), float(y[1])


def sonine_relaxation_rates(alpha: float, *, gamma: float = 1.0, density: float = 1.0,
                            diffusion: float = 1.0, friction: float = 0.0,
                            linear: bool = True) -> tuple[float, float]:
    """Relaxation rates of the first-Sonine ODEs about their steady state.

    The eigenvalues of :math:`-\\partial(\\dot T, \\dot a_2)/\\partial(T, a_2)` at
    :func:`steady_sonine` (central differences), slowest first: the first-Sonine
    counterpart of the two slowest even rates of
    :func:`kinetic_fem.relaxation_spectrum`.

    Parameters
    ----------
    alpha : float
        Restitution coefficient.
    gamma, density, diffusion, friction : float
        As :func:`sonine_rates`.
    linear : bool
        As :func:`sonine_rates`.

    Returns
    -------
    (slow, fast) : tuple of float
        Real parts of the two rates (> 0 for a stable steady state).

    Examples
    --------
    The Maxwell model (exact): the rates of T and of the fourth moment,
    :math:`n(1-\\alpha^2)/2` and :math:`n(1 - a^4 - b^4)` with
    :math:`a, b = (1 \\mp \\alpha)/2`.

    >>> slow, fast = sonine_relaxation_rates(0.5, gamma=0.0)
    >>> round(slow, 8), round(fast, 8)
    (0.375, 0.6796875)
    """
    t0, a0 = steady_sonine(alpha, gamma=gamma, density=density, diffusion=diffusion,
                           friction=friction, linear=linear)
    kw = dict(gamma=gamma, density=density, diffusion=diffusion, friction=friction,
              linear=linear)
    jac = np.empty((2, 2))
    for j, (dt_, da_) in enumerate(((1e-5 * t0, 0.0), (0.0, 1e-5))):
        plus = sonine_rates(t0 + dt_, a0 + da_, alpha, **kw)  # type: ignore[arg-type]
        minus = sonine_rates(t0 - dt_, a0 - da_, alpha, **kw)  # type: ignore[arg-type]
        jac[:, j] = (np.array(plus) - np.array(minus)) / (2.0 * (dt_ + da_))
    rates = np.sort(-np.linalg.eigvals(jac).real)
    return float(rates[0]), float(rates[1])
