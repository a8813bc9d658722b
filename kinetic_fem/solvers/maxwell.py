"""Exact results of the one-dimensional inelastic Maxwell model (kernel ``gamma = 0``).

With a collision rate independent of the relative speed the moment equations close.
A collision maps :math:`v_1' = a v_1 + b v_2`, :math:`v_2' = b v_1 + a v_2` with
:math:`a = (1-\\alpha)/2`, :math:`b = (1+\\alpha)/2`, so the weak form of the
Boltzmann equation with :math:`\\varphi = v^k` gives, for the moments
:math:`M_k = \\langle v^k\\rangle` (:math:`M_0 = 1`),

.. math::

    \\frac{dM_k}{dt} = \\frac n2\\Big[\\sum_{j=0}^{k}\\binom kj
        \\big(a^j b^{k-j} + a^{k-j} b^j\\big) M_j M_{k-j} - 2 M_k\\Big]
        + D\\,k(k-1) M_{k-2} - \\xi k M_k,

the last two terms from a Fokker-Planck bath :math:`\\partial_v(\\xi vP) + D\\partial_v^2P`
(white noise: :math:`\\xi = 0`; free cooling: :math:`D = \\xi = 0`).  The coefficient
of :math:`M_k` itself is :math:`n(a^k + b^k - 1) - \\xi k < 0`, and every other term
holds moments of lower order only: the system is triangular.

* Steady state: :math:`M_k = [\\tfrac n2\\sum_{j=1}^{k-1}\\dots + Dk(k-1)M_{k-2}] /
  [n(1-a^k-b^k) + \\xi k]`, every moment exactly; with white noise
  :math:`T = 4D/(n(1-\\alpha^2))` and :math:`a_2 = 2(1-\\alpha^2)/(7+\\alpha^2)`.
* Transient: the ODEs above for any protocol :math:`D(t), \\xi(t), \\alpha(t)`.
* Free cooling: :math:`T(t) = T_0 e^{-2\\zeta n t}` with :math:`\\zeta = (1-\\alpha^2)/4`
  for every initial state (the convention :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`);
  the scaled moments :math:`\\mu_k = M_k/T^{k/2}` obey
  :math:`d\\mu_k/dt = n(a^k + b^k - 1 + k\\,ab)\\mu_k + \\dots` with a positive rate for
  every ``k >= 4``: no moment of order 4 or more has a finite scaling limit
  (:math:`\\mu_4(t) = -3 + (\\mu_4(0) + 3)e^{2a^2b^2nt}`), as the closed-form
  homogeneous cooling state :math:`f(c) = 2/(\\pi(1+c^2)^2)` (power-law tail, infinite
  fourth moment) requires.

The derivations are in the user guide (``exact_solutions``).

References
----------
A. Baldassarri, U. Marini Bettolo Marconi and A. Puglisi, Europhys. Lett. 58, 14
(2002) (the cooling state); E. Ben-Naim and P. L. Krapivsky, Phys. Rev. E 61, R5
(2000) (the moment hierarchy of the inelastic Maxwell model).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import mpmath
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import solve_ivp

from ..model import check_alpha, check_nonnegative, check_positive
from ..options import gather, option_group
from ..sonine import sonine_norm, sonine_polynomial_coefficients

__all__ = ["MaxwellSteadyState", "MaxwellTransient", "collision_moment_rates",
           "moment_rates", "steady_state", "evolve_moments", "MomentOptions", "hcs_zeta",
           "hcs_pdf", "hcs_characteristic_function", "scaled_moment_growth_rates"]

Protocol = float | Callable[[float], float]


def _pair_coefficients(alpha: float | mpmath.mpf, k: int) -> list:
    """:math:`\\binom kj(a^j b^{k-j} + a^{k-j} b^j)`, ``j = 0 .. k``."""
    a = (1 - alpha) / 2
    b = (1 + alpha) / 2
    return [math.comb(k, j) * (a**j * b ** (k - j) + a ** (k - j) * b**j) for j in range(k + 1)]


def collision_moment_rates(moments: ArrayLike, alpha: float, density: float = 1.0
                           ) -> NDArray[np.float64]:
    """Collisional rates :math:`dM_k/dt|_{coll}`, ``k = 0 .. K``, of the Maxwell model.

    Parameters
    ----------
    moments : array_like, shape (K + 1,)
        :math:`M_0 .. M_K` (any distribution: odd moments allowed; :math:`M_0` the
        normalisation).
    alpha : float
        Restitution coefficient.
    density : float
        Number density :math:`n`.

    Returns
    -------
    ndarray, shape (K + 1,)
        :math:`\\tfrac n2[\\sum_j \\binom kj(a^jb^{k-j} + a^{k-j}b^j)M_jM_{k-j} - 2M_0M_k]`.

    Examples
    --------
    Energy loss of a unit Gaussian, :math:`-(n/2)(1-\\alpha^2)T`:

    >>> collision_moment_rates([1.0, 0.0, 1.0], 0.5)
    array([ 0.   ,  0.   , -0.375])
    """
    m = np.asarray(moments, dtype=float)
    out = np.zeros_like(m)
    for k in range(len(m)):
        c = _pair_coefficients(alpha, k)
        out[k] = 0.5 * density * (sum(c[j] * m[j] * m[k - j] for j in range(k + 1))
                                  - 2.0 * m[0] * m[k])
    return out


def moment_rates(moments: ArrayLike, alpha: float, density: float = 1.0,
                 diffusion: float = 0.0, friction: float = 0.0) -> NDArray[np.float64]:
    """Full right-hand side :math:`dM_k/dt`: collisions plus the thermostat.

    The thermostat adds :math:`Dk(k-1)M_{k-2} - \\xi k M_k`.

    Parameters
    ----------
    moments : array_like, shape (K + 1,)
        Raw moments :math:`M_0 .. M_K` (even ones used).
    alpha : float
        Coefficient of restitution.
    density : float
        Number density ``n``.
    diffusion : float
        Noise strength ``D``.
    friction : float
        Bath friction :math:`\\xi`.

    Returns
    -------
    ndarray, shape (K + 1,)

    Examples
    --------
    >>> moment_rates([1.0, 0.0, 1.0], 0.5, diffusion=0.1875)  # steady at T = 1
    array([0., 0., 0.])
    """
    m = np.asarray(moments, dtype=float)
    k = np.arange(len(m))
    out = collision_moment_rates(m, alpha, density) - friction * k * m
    out[2:] += diffusion * k[2:] * (k[2:] - 1) * m[:-2]
    return out


@dataclass(frozen=True)
class MaxwellSteadyState:
    """Exact steady state of the heated Maxwell model.

    Attributes
    ----------
    moments : ndarray, shape (2 * order + 1,)
        :math:`M_k = \\langle v^k\\rangle` (odd ones vanish).
    temperature : float
        :math:`T = M_2`.
    sonine : ndarray, shape (order + 1,)
        Sonine coefficients :math:`a_0 = 1, a_1 = 0, a_2, .., a_P`, computed with
        ``40 + 2P`` significant digits from the moments, then rounded once.
    """

    moments: NDArray[np.float64]
    temperature: float
    sonine: NDArray[np.float64]

    @property
    def a2(self) -> float:
        """Kurtosis coefficient :math:`a_2 = \\langle c^4\\rangle/3 - 1`."""
        return float(self.sonine[2])

    @property
    def scaled_moments(self) -> NDArray[np.float64]:
        """:math:`\\mu_k = M_k/T^{k/2}`."""
        k = np.arange(len(self.moments))
        return self.moments / self.temperature ** (0.5 * k)


def steady_state(alpha: float, order: int = 6, *, density: float = 1.0,
                 diffusion: float = 1.0, friction: float = 0.0) -> MaxwellSteadyState:
    """Exact steady moments and Sonine coefficients of the heated Maxwell model.

    Parameters
    ----------
    alpha : float
        Restitution coefficient in ``[0, 1)`` (``[0, 1]`` with friction).
    order : int
        Highest Sonine order :math:`P`; moments up to :math:`2P` are returned.
    density, diffusion : float
        :math:`n > 0`, :math:`D > 0`.
    friction : float
        :math:`\\xi \\ge 0` of a Fokker-Planck bath (0: white noise).

    Returns
    -------
    MaxwellSteadyState

    Notes
    -----
    Each moment follows from the lower ones (see the module docstring); the
    recursion runs in multiple precision (``40 + 2P`` digits: the recursion has
    positive terms only, and the Sonine coefficients, alternating sums of the
    moments, lose fewer digits than that), so every output is exact to its final
    rounding.

    Examples
    --------
    >>> s = steady_state(0.5)
    >>> round(s.temperature, 12), round(s.a2, 12)   # 4D/(n(1-a^2)), 2(1-a^2)/(7+a^2)
    (5.333333333333, 0.206896551724)
    """
    if isinstance(order, bool) or not isinstance(order, int) or order < 1:
        raise ValueError(f"order must be an integer >= 1, got {order!r}")
    n_f = check_positive("density", density)
    d_f = check_positive("diffusion", diffusion)
    xi_f = check_nonnegative("friction", friction)
    al_f = check_alpha(alpha, allow_elastic=xi_f > 0)
    kmax = 2 * order
    with mpmath.workprec(int(3.33 * (40 + 2 * order))):
        n, d, xi, al = (mpmath.mpf(x) for x in (n_f, d_f, xi_f, al_f))
        m = [mpmath.mpf(1)]
        for k in range(1, kmax + 1):
            if k % 2:
                m.append(mpmath.mpf(0))   # centred: the odd moments vanish
                continue
            c = _pair_coefficients(al, k)
            gain = n / 2 * mpmath.fsum(c[j] * m[j] * m[k - j] for j in range(1, k))
            m.append((gain + d * k * (k - 1) * m[k - 2]) / (n * (1 - c[0]) + xi * k))
        t = m[2]
        sonine = []
        for p in range(order + 1):
            coeffs = sonine_polynomial_coefficients(p)
            total = mpmath.fsum(mpmath.mpf(cf.numerator) / cf.denominator
                                * m[2 * j] / (2 * t) ** j for j, cf in enumerate(coeffs))
            norm = sonine_norm(p)
            sonine.append(total * norm.denominator / norm.numerator)
        return MaxwellSteadyState(np.array([float(x) for x in m]), float(t),
                                  np.array([float(x) for x in sonine]))


@dataclass(frozen=True)
class MaxwellTransient:
    """Moments of the Maxwell model along a protocol.

    Attributes
    ----------
    times : ndarray, shape (n_t,)
    moments : ndarray, shape (n_t, K + 1)
        :math:`M_0 .. M_K` at each time.
    """

    times: NDArray[np.float64]
    moments: NDArray[np.float64]

    @property
    def temperature(self) -> NDArray[np.float64]:
        """:math:`T(t) = M_2 - M_1^2`."""
        return self.moments[:, 2] - self.moments[:, 1] ** 2

    @property
    def a2(self) -> NDArray[np.float64]:
        """:math:`a_2(t) = \\langle c^4\\rangle/3 - 1` of the centred moments."""
        m = self.moments
        mean = m[:, 1]
        central4 = m[:, 4] - 4 * mean * m[:, 3] + 6 * mean**2 * m[:, 2] - 3 * mean**4
        return central4 / (3.0 * self.temperature**2) - 1.0


def _as_protocol(name: str, value: Protocol, *, allow_zero: bool = True
                 ) -> Callable[[float], float]:
    if callable(value):
        def checked(t: float) -> float:
            x = float(value(t))
            if not (math.isfinite(x) and x >= 0.0):
                raise ValueError(f"the protocol {name}(t) gave {x!r} at t = {t:g}; it must "
                                 "be finite and >= 0")
            return x
        return checked
    x = check_nonnegative(name, value) if allow_zero else check_positive(name, value)
    return lambda t: x


@option_group
@dataclass(frozen=True)
class MomentOptions:
    """Numerical options of :func:`evolve_moments`.

    Parameters
    ----------
    order : int
        Highest moment :math:`K` integrated (``>= 2``).
    breakpoints : sequence of float
        Times where a protocol jumps; the integration restarts there so the jump
        costs no accuracy.
    rtol : float
        Relative tolerance of the DOP853 integrator (the absolute tolerance is
        ``1e-20 rtol`` times the moment's Gaussian scale).

    Examples
    --------
    >>> MomentOptions(order=6)
    MomentOptions(order=6, breakpoints=(), rtol=1e-12)
    """

    order: int = 4
    breakpoints: Sequence[float] = ()
    rtol: float = 1e-12


def evolve_moments(alpha: float | Callable[[float], float], times: ArrayLike, *,
                   density: float = 1.0, diffusion: Protocol = 1.0, friction: Protocol = 0.0,
                   initial_moments: ArrayLike | None = None, initial_temperature: float = 1.0,
                   **options: Any) -> MaxwellTransient:
    """Integrate the closed moment equations of the Maxwell model along a protocol.

    Parameters
    ----------
    alpha : float or callable
        Restitution coefficient, constant or :math:`\\alpha(t)` with values in [0, 1].
    times : array_like, shape (n_t,)
        Increasing output times, ``times[0]`` the initial time.
    density : float
        :math:`n > 0`.
    diffusion, friction : float or callable
        :math:`D(t) \\ge 0` and :math:`\\xi(t) \\ge 0` (0 and 0: free cooling in
        physical variables).
    initial_moments : array_like, shape (K0 + 1,), optional
        :math:`M_0 = 1, M_1, ..`; missing orders up to ``order`` are taken from a
        Gaussian with these mean and temperature.  Default: a centred Gaussian at
        ``initial_temperature``.
    initial_temperature : float
        Temperature of the default Gaussian start.
    **options
        The numerical options of :class:`MomentOptions` (``order`` default 4,
        ``breakpoints``, ``rtol`` default 1e-12) by keyword, or as one object
        ``options=MomentOptions(...)`` (the keywords override its fields; an unknown
        keyword raises :class:`TypeError`).

    Returns
    -------
    MaxwellTransient

    Examples
    --------
    White noise from a cold start: :math:`T(t) = T_\\infty(1 - e^{-n(1-\\alpha^2)t/2})`.

    >>> ev = evolve_moments(0.5, [0.0, 1.0], initial_temperature=1e-12)
    >>> t_inf = 4 / 0.75
    >>> bool(abs(ev.temperature[1] / (t_inf * (1 - math.exp(-0.375))) - 1) < 1e-9)
    True
    """
    opts = gather(MomentOptions, options.pop("options", None), options, "evolve_moments")
    order, breakpoints, rtol = opts.order, opts.breakpoints, opts.rtol
    times = np.asarray(times, dtype=float)
    if times.ndim != 1 or len(times) < 1 or not np.all(np.isfinite(times)):
        raise ValueError("times must be a non-empty 1-d array of finite values")
    if np.any(np.diff(times) <= 0):
        raise ValueError("times must be strictly increasing")
    if isinstance(order, bool) or not isinstance(order, int) or order < 2:
        raise ValueError(f"order must be an integer >= 2, got {order!r}")
    n = check_positive("density", density)
    if callable(alpha):
        raw_alpha = alpha

        def alpha_of(t: float) -> float:
            x = float(raw_alpha(t))
            if not 0.0 <= x <= 1.0:
                raise ValueError(f"the protocol alpha(t) gave {x!r} at t = {t:g}; it must lie "
                                 "in [0, 1]")
            return x
    else:
        a0 = check_alpha(alpha, allow_elastic=True)

        def alpha_of(t: float) -> float:
            return a0
    d_of = _as_protocol("diffusion", diffusion)
    xi_of = _as_protocol("friction", friction)
    m0 = _initial_moments(initial_moments, initial_temperature, order)
    t_ref = max(m0[2], d_of(float(times[0])) / n)
    scale = np.array([t_ref ** (0.5 * k) * max(1.0, math.prod(
        range(k - 1, 0, -2))) for k in range(order + 1)])

    def rhs(t: float, m: NDArray[np.float64]) -> NDArray[np.float64]:
        return moment_rates(m, alpha_of(t), n, d_of(t), xi_of(t))

    cuts = sorted({float(b) for b in breakpoints if times[0] < b < times[-1]})
    edges = [float(times[0]), *cuts, float(times[-1])]
    out = np.empty((len(times), order + 1))
    out[0] = m0
    state = m0
    atol = 1e-20 * rtol * scale
    for lo, hi in zip(edges[:-1], edges[1:], strict=True):
        sel = (times > lo) & (times <= hi)
        t_eval = np.union1d(times[sel], [hi])
        sol = solve_ivp(rhs, (lo, hi), state, method="DOP853", t_eval=t_eval, rtol=rtol,
                        atol=atol)
        if not sol.success:
            raise RuntimeError(f"the moment equations failed to integrate on [{lo}, {hi}]: "
                               f"{sol.message}")
        out[sel] = sol.y[:, np.searchsorted(t_eval, times[sel])].T
        state = sol.y[:, -1]
    return MaxwellTransient(times, out)


def _initial_moments(initial: ArrayLike | None, temperature: float, order: int
                     ) -> NDArray[np.float64]:
    if initial is None:
        t = check_positive("initial_temperature", temperature)
        return np.array([0.0 if k % 2 else t ** (k // 2) * math.prod(range(k - 1, 0, -2))
                         for k in range(order + 1)])
    m = np.asarray(initial, dtype=float)
    if m.ndim != 1 or len(m) < 3 or not np.all(np.isfinite(m)):
        raise ValueError("initial_moments must be a 1-d array M_0, M_1, M_2, ... of finite "
                         "values")
    if abs(m[0] - 1.0) > 1e-12:
        raise ValueError(f"initial_moments[0] = {m[0]!r}: the distribution must be normalised "
                         "(M_0 = 1)")
    t = m[2] - m[1] ** 2
    if not t > 0:
        raise ValueError(f"initial moments give the temperature M_2 - M_1^2 = {t!r}; it must be "
                         "> 0")
    if len(m) >= order + 1:
        return m[: order + 1].copy()
    # complete with the moments of a Gaussian of this mean and temperature
    x, w = np.polynomial.hermite_e.hermegauss(order + 2)
    w = w / w.sum()
    gauss = [float(np.sum(w * (m[1] + math.sqrt(t) * x) ** k)) for k in range(order + 1)]
    return np.concatenate([m, gauss[len(m):]])


def hcs_zeta(alpha: float) -> float:
    """Cooling rate of the Maxwell model, :math:`\\zeta = (1-\\alpha^2)/4`.

    In the convention :math:`dT/dt = -2\\zeta n T` (``gamma = 0``); exact for every
    state, not only the scaling one.

    Parameters
    ----------
    alpha : float
        Coefficient of restitution.

    Returns
    -------
    float
        Cooling rate in :math:`dT/dt = -2\\zeta n T`.

    Examples
    --------
    >>> hcs_zeta(0.0)
    0.25
    """
    return 0.25 * (1.0 - check_alpha(alpha) ** 2)


def hcs_pdf(c: ArrayLike) -> NDArray[np.float64]:
    """Homogeneous cooling state :math:`f(c) = 2/(\\pi(1+c^2)^2)`, unit temperature.

    The same for every :math:`\\alpha < 1` (Baldassarri et al. 2002); its Fourier
    transform is :math:`(1+|k|)e^{-|k|}`.

    Parameters
    ----------
    c : array_like
        Scaled velocities.

    Returns
    -------
    ndarray

    Examples
    --------
    >>> float(hcs_pdf(0.0))  # 2/pi
    0.6366197723675814
    """
    c = np.asarray(c, dtype=float)
    return 2.0 / (math.pi * (1.0 + c * c) ** 2)


def hcs_characteristic_function(k: ArrayLike) -> NDArray[np.float64]:
    """:math:`\\hat f(k) = \\int f(c) e^{ikc}dc = (1+|k|)e^{-|k|}` of :func:`hcs_pdf`.

    Parameters
    ----------
    k : array_like
        Wave numbers.

    Returns
    -------
    ndarray
        :math:`(1 + |k|)e^{-|k|}`, the Fourier transform of :func:`hcs_pdf`.
    """
    k_abs: NDArray[np.float64] = np.abs(np.asarray(k, dtype=float))
    return (1.0 + k_abs) * np.exp(-k_abs)


def scaled_moment_growth_rates(alpha: float, order: int, density: float = 1.0
                               ) -> NDArray[np.float64]:
    """Rates :math:`n(a^k + b^k - 1 + k\\,ab)` of the scaled moments in free cooling.

    :math:`\\mu_k = M_k/T^{k/2}` obeys :math:`d\\mu_k/dt = \\lambda_k\\mu_k + \\dots`
    (lower moments); :math:`\\lambda_2 = \\lambda_3 = 0` (:math:`a^3 + b^3 = 1 - 3ab`)
    and :math:`\\lambda_k > 0` for ``k >= 4``: the scaled moments of order >= 4 grow
    without bound, so the scaling state has none.

    Parameters
    ----------
    alpha : float
        Coefficient of restitution.
    order : int
        Highest moment order.
    density : float
        Number density ``n``.

    Returns
    -------
    ndarray, shape (order + 1,)
        :math:`\\lambda_0 .. \\lambda_K`.

    Examples
    --------
    >>> r = scaled_moment_growth_rates(0.0, 4)      # a = b = 1/2, ab = 1/4
    >>> [float(x) for x in r[2:]]                   # 0, 0, 2 a^2 b^2 = 1/8
    [0.0, 0.0, 0.125]
    """
    al = check_alpha(alpha)
    n = check_positive("density", density)
    a, b = 0.5 * (1 - al), 0.5 * (1 + al)
    k = np.arange(order + 1)
    return n * (a**k + b**k - 1.0 + k * a * b)
