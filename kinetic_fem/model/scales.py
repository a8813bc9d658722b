"""The model's own scales: thermal speed, mean free time, and where the tail ends.

Numerical defaults (cut-offs, spacings, time steps) of every deterministic solver derive
from these scales, so that they follow the kernel and the thermostat instead of the
hard-rod formulas they began as.  All scales refer to the *unit problem*
:math:`n = D = 1` of a heated gas (:attr:`HeatedProblem.velocity_scale` maps back), or to
the scaled homogeneous cooling state (unit temperature).

**Thermal speed** :math:`\\sqrt T`, with :math:`T` the estimated steady temperature:
first-order Sonine for hard rods under white noise (the paper's scale,
:func:`kinetic_fem.sonine.steady_temperature`), otherwise the Gaussian closure of the
energy balance (:meth:`HeatedProblem.temperature_estimate`; exact for the Maxwell kernel).

**Mean free time** :math:`1/(n\\langle B(g)\\rangle)`, the average over a Gaussian at
:math:`T` of the collision rate, :math:`g \\sim N(0, 2T)`
(:meth:`~kinetic_fem.model.kernel_base.CollisionKernel.gaussian_mean`); for a power law

.. math::

    \\langle |g|^\\gamma \\rangle = \\frac{(4T)^{\\gamma/2}}{\\sqrt\\pi}\\,
        \\Gamma\\Big(\\frac{\\gamma+1}{2}\\Big).

**Cut-off** (in units of :math:`\\sqrt T`): where the tail of the steady state falls below
a target value of :math:`f(c)` (:data:`TAIL_TARGET` by default):

* hard rods, white noise: the far tail :math:`e^{-A_c c^{3/2}}`,
  :math:`A_c = \\tfrac23 T^{3/4}` (claim C4), or, if reached first, the core: the smaller
  of the Gaussian :math:`e^{-c^2/2}` and the quasi-elastic :math:`e^{-x^3/6}` (claim C5,
  :math:`x = \\varepsilon^{1/3} v`, a margin of 1.25 for the crossover; it keeps the
  cut-off short of double-precision underflow as :math:`\\alpha \\to 1`);
* Maxwell kernel, white noise: the loss frequency is :math:`n`, so :math:`D P'' \\approx
  n P` gives the exponential tail :math:`e^{-v}`; the core is Gaussian;
* other kernels (:math:`0 < \\gamma \\le 2`, :math:`\\gamma \\ne 1`): the loss frequency
  grows like :math:`|v|^\\gamma`, so :math:`P'' \\approx n|v|^\\gamma P` gives the tail
  :math:`e^{-\\frac{2}{2+\\gamma}|v|^{1+\\gamma/2}}` (WKB), which reduces to both cases
  above;
* any kernel growing as :math:`B(g) \\sim c\\,g^p` (its
  :attr:`~kinetic_fem.model.kernel_base.CollisionKernel.tail_growth`): the same WKB tail
  :math:`e^{-\\frac{2\\sqrt c}{2+p}|v|^{1+p/2}}` (the saturating kernel: :math:`p = 0`,
  :math:`c = g_0`, an exponential tail);
* Fokker-Planck bath: the friction adds the Gaussian :math:`e^{-\\xi v^2/2}` of the bath
  temperature, which bounds the cut-off from above.

**Cooling state** (hard rods, scaled to unit temperature): the exponential tail
:math:`e^{-c/\\zeta}` and, near elastic collisions, the outer edge of the humps of
claim C12, with the Gaussian estimate :math:`\\zeta \\approx (1-\\alpha^2)/\\sqrt\\pi`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import quad

from ..sonine import steady_temperature
from .kernel import HARD_RODS, as_kernel
from .kernel_base import CollisionKernel
from .problem import HeatedProblem
from .validation import check_alpha, check_positive

__all__ = ["TAIL_TARGET", "ModelScales", "heated_cutoff", "cooling_cutoff",
           "cooling_rate_estimate", "tail_action", "quasi_elastic_log_density",
           "quasi_elastic_cutoff"]

TAIL_TARGET = 1e-60
"""Value of f(c) at the default cut-off of the heated state."""


@dataclass(frozen=True)
class ModelScales:
    """Scales of the heated steady state of the unit problem ``n = D = 1``.

    Parameters
    ----------
    alpha : float
        Constant restitution coefficient, :math:`0 \\le \\alpha \\le 1`.
    kernel : float or CollisionKernel
        The kernel of the unit problem, or the exponent ``gamma`` of a power law
        (1: hard rods, 0: Maxwell).
    friction : float
        Bath friction of the unit problem, :math:`\\xi/(n u^d)` (0: white noise).
    temperature : float
        Estimated steady temperature of the unit problem (module docstring), > 0.

    Examples
    --------
    >>> s = ModelScales(0.5, 0.0, 0.0, 16 / 3)      # Maxwell, exact T = 16/3
    >>> round(s.cutoff(), 1), s.mean_free_time
    (59.8, 1.0)
    """

    alpha: float
    kernel: CollisionKernel
    friction: float
    temperature: float

    def __post_init__(self) -> None:
        check_alpha(self.alpha, allow_elastic=True)
        object.__setattr__(self, "kernel", as_kernel(self.kernel))
        if not self.friction >= 0.0:
            raise ValueError(f"friction={self.friction!r} is not allowed; it must be >= 0")
        check_positive("temperature", self.temperature)

    @classmethod
    def from_problem(cls, problem: HeatedProblem) -> ModelScales:
        """The scales of the unit problem of ``problem`` (constant restitution).

        Parameters
        ----------
        problem : HeatedProblem
            The heated problem; its restitution must be a constant ``alpha``.

        Returns
        -------
        ModelScales
        """
        alpha = problem.gas.alpha
        kernel = problem.unit_kernel
        degree = problem.gas.kernel.scale_degree
        xi = problem.friction / (problem.gas.density * problem.velocity_scale**degree)
        if kernel.is_hard_rods and xi == 0.0:
            return cls(alpha, kernel, 0.0, steady_temperature(alpha))
        unit = HeatedProblem.from_parameters(alpha, density=1.0, diffusion=1.0, friction=xi,
                                             kernel=kernel)
        return cls(alpha, kernel, xi, unit.temperature_estimate())

    @property
    def gamma(self) -> float:
        """The exponent of a power-law kernel (other kernels refuse,
        :attr:`~kinetic_fem.model.kernel_base.CollisionKernel.gamma`)."""
        return self.kernel.gamma

    @property
    def thermal_speed(self) -> float:
        """:math:`\\sqrt T` of the unit problem."""
        return math.sqrt(self.temperature)

    @property
    def mean_free_time(self) -> float:
        """:math:`1/\\langle B(g)\\rangle` over a Gaussian at :math:`T` (``n = 1``)."""
        return 1.0 / self.kernel.gaussian_mean(self.temperature)

    def cutoff(self, target: float = TAIL_TARGET, *, core_margin: float = 1.25) -> float:
        """Where :math:`f(c)` falls below ``target``, in units of :math:`\\sqrt T`.

        Parameters
        ----------
        target : float
            Value of :math:`f(c)` at the cut-off, in (0, 1).
        core_margin : float
            Factor (>= 1) on the quasi-elastic core :math:`e^{-x^3/6}` for the crossover
            to the far tail (hard rods, white noise).

        Returns
        -------
        float
            The cut-off :math:`c_{max}` (module docstring).

        Examples
        --------
        >>> [round(ModelScales(0.9, g, 0.0, 1.0).cutoff(), 1) for g in (0.0, 1.0, 2.0)]
        [138.2, 35.0, 16.6]
        """
        if not 0.0 < target < 1.0:
            raise ValueError(f"target={target!r} is not allowed; it must be in (0, 1)")
        if not core_margin >= 1.0:
            raise ValueError(f"core_margin={core_margin!r} is not allowed; it must be >= 1")
        s = self.thermal_speed
        log_target = -math.log(target)
        gauss = math.sqrt(2.0 * log_target)
        if self.kernel.is_hard_rods:
            tail = (log_target / (2.0 / 3.0 * self.temperature**0.75)) ** (2.0 / 3.0)
            if self.friction == 0.0 and self.alpha < 1.0:
                x_core = (6.0 * log_target) ** (1.0 / 3.0)
                quasi_elastic = core_margin * x_core / ((1.0 - self.alpha) ** (1.0 / 3.0) * s)
                core = min(gauss, quasi_elastic)
            else:
                core = gauss
        else:
            coefficient, growth = self.kernel.tail_growth
            power = 1.0 + 0.5 * growth
            tail = (log_target / (math.sqrt(coefficient) / power)) ** (1.0 / power) / s
            core = gauss
        white = max(tail, core)
        if self.friction > 0.0:
            bath = math.sqrt(2.0 * log_target / (self.friction * self.temperature))
            return max(min(white, bath), gauss)
        return white


def heated_cutoff(alpha: float, target: float = TAIL_TARGET, *,
                  core_margin: float = 1.25) -> float:
    """Cut-off (units of :math:`\\sqrt T`) of the heated hard-rod gas under white noise.

    Parameters
    ----------
    alpha : float
        Constant restitution coefficient.
    target : float
        Value of :math:`f(c)` at the cut-off.
    core_margin : float
        As in :meth:`ModelScales.cutoff`.

    Returns
    -------
    float
        :meth:`ModelScales.cutoff` with the first-order Sonine temperature.

    Examples
    --------
    >>> [round(heated_cutoff(a), 1) for a in (0.0, 0.9, 0.99, 0.9999)]
    [29.2, 16.6, 12.1, 12.1]
    """
    return ModelScales(alpha, HARD_RODS, 0.0, steady_temperature(alpha)).cutoff(
        target, core_margin=core_margin)


def cooling_rate_estimate(alpha: float) -> float:
    """Gaussian estimate of the hard-rod cooling rate, :math:`(1-\\alpha^2)/\\sqrt\\pi`.

    :math:`\\zeta \\approx (1-\\alpha^2)\\langle|g|^3\\rangle_G/8` with
    :math:`\\langle|g|^3\\rangle_G = 8/\\sqrt\\pi` at unit temperature.

    Parameters
    ----------
    alpha : float
        Constant restitution coefficient.

    Returns
    -------
    float
    """
    return (1.0 - alpha**2) / math.sqrt(math.pi)


def cooling_cutoff(alpha: float) -> float:
    """Cut-off :math:`c_{max}` (thermal velocities) of the hard-rod cooling state.

    The larger of the exponential tail :math:`e^{-c/\\zeta}` (80 decay lengths past
    :math:`c = 1.5`, :math:`f \\approx 10^{-35}`) and, near elastic collisions, the outer
    edge of the humps :math:`c = 1 + 12\\varepsilon^{1/3}` (where
    :math:`\\psi \\sim e^{y^3/3}` has fallen below 1e-35, claim C12).

    Parameters
    ----------
    alpha : float
        Constant restitution coefficient.

    Returns
    -------
    float

    Examples
    --------
    >>> [round(cooling_cutoff(a), 2) for a in (0.3, 0.9, 0.999)]
    [42.57, 10.08, 2.2]
    """
    check_alpha(alpha)
    eps = 1.0 - alpha
    return max(1.0 + 12.0 * eps ** (1.0 / 3.0), 1.5 + 80.0 * cooling_rate_estimate(alpha))


def tail_action(v: float, kernel: float | CollisionKernel, friction: float) -> float:
    """WKB action :math:`S(v)` of the far tail :math:`P \\sim e^{-S}` at ``n = D = 1``.

    Far from the bulk :math:`P'' + \\xi (vP)' \\approx B(v) P` (the loss dominates the
    gain, the loss frequency of a fast particle is :math:`B(v)`), so

    .. math::

        S'(v) = \\tfrac12\\big(\\xi v + \\sqrt{\\xi^2 v^2 + 4 B(v)}\\big),

    :math:`S = \\int_0^v\\sqrt{B}` for white noise
    (:meth:`~kinetic_fem.model.kernel_base.CollisionKernel.wkb_action`:
    :math:`\\tfrac{2}{2+\\gamma}v^{1+\\gamma/2}` for a power law).

    Parameters
    ----------
    v : float
        Velocity (``n = D = 1``), >= 0.
    kernel : float or CollisionKernel
        The kernel of the unit problem, or the exponent of a power law.
    friction : float
        Bath friction (0: white noise).

    Returns
    -------
    float

    Examples
    --------
    >>> round(tail_action(4.0, 1.0, 0.0), 12)  # (2/3) v^(3/2)
    5.333333333333
    """
    k = as_kernel(kernel)
    if friction == 0.0:
        return float(k.wkb_action(v))

    def rate(w: float) -> float:
        return 0.5 * (friction * w + math.sqrt((friction * w) ** 2 + 4.0 * float(k.rate(w))))

    return quad(rate, 0.0, v, limit=200)[0]


def quasi_elastic_log_density(v: ArrayLike, kernel: float | CollisionKernel, alpha: float,
                              temperature: float, *, points: int = 801) -> NDArray[np.float64]:
    """:math:`\\ln P(v) - \\ln P(0)` of the quasi-elastic (Fokker-Planck) limit of the
    heated state at ``n = D = 1``, white noise.

    In one dimension an elastic collision only exchanges the velocities, so near elastic
    collisions each collision moves a particle at :math:`v` by the small kick
    :math:`a\\,(w - v)`, :math:`a = (1-\\alpha)/2`, towards its partner :math:`w`.  The
    Kramers-Moyal expansion of these kicks, with the partners Gaussian at ``temperature``,
    gives the drift :math:`-a\\,m(v)` and the diffusion :math:`d(v)`,

    .. math::

        m(v) = \\langle B(|v-w|)(v-w)\\rangle_w, \\quad
        d(v) = \\tfrac{a^2}{2}\\langle B(|v-w|)(v-w)^2\\rangle_w,

    and the zero-flux steady state of :math:`\\partial_v[a m P + \\partial_v((1 + d)P)] =
    0`: :math:`\\ln P = -\\int_0^v a m/(1 + d) - \\ln(1 + d)`.  For the Maxwell model it
    is the Gaussian at :math:`T = 2/(1-\\alpha)` near the centre (exact: :math:`4/(1 -
    \\alpha^2)`) with a heavier tail; for :math:`B \\sim g^p`, :math:`p > 0`, the tail
    :math:`-a v^{2+p}/(2+p)` is lighter than the Gaussian (negative :math:`a_2`).  Measured
    against FEM states (:math:`\\gamma = 0, 1/2`, the saturating kernel, alpha = 0.7 ...
    0.99): within 0.1 of :math:`\\ln f` up to :math:`c = 4`, and above the state in the
    far tail (by 2-11 at :math:`c = 14`, alpha = 0.99), so the 33-decade point of this
    profile bounds the state's from above (:func:`quasi_elastic_cutoff`).

    Parameters
    ----------
    v : array_like
        Velocities (``n = D = 1``).
    kernel : float or CollisionKernel
        The kernel of the unit problem, or the exponent of a power law.
    alpha : float
        Constant restitution coefficient.
    temperature : float
        Temperature of the Gaussian partners (e.g. the Gaussian-closure estimate).
    points : int
        Trapezoid points of the integral over ``[0, max|v|]``.

    Returns
    -------
    ndarray
        :math:`\\ln P(v) - \\ln P(0)` at ``|v|``.

    Examples
    --------
    >>> lp = quasi_elastic_log_density([10.0], 0.0, 0.99, 200.0)   # Maxwell: ~ -v^2/400
    >>> round(float(lp[0]), 3)
    -0.25
    """
    k = as_kernel(kernel)
    check_alpha(alpha, allow_elastic=True)
    check_positive("temperature", temperature)
    speed = np.abs(np.asarray(v, dtype=float))
    a = 0.5 * (1.0 - alpha)
    grid = np.linspace(0.0, max(float(speed.max(initial=0.0)), 1e-12), points)
    s, w = np.polynomial.hermite.hermgauss(60)
    g = grid[:, None] - math.sqrt(2.0 * temperature) * s[None, :]
    rate = k.rate(np.abs(g)) * (w / math.sqrt(math.pi))[None, :]
    drift = a * np.sum(rate * g, axis=1)
    spread = 0.5 * a * a * np.sum(rate * g * g, axis=1)
    slope = drift / (1.0 + spread)
    action = np.concatenate([[0.0], np.cumsum(0.5 * (slope[1:] + slope[:-1]) * np.diff(grid))])
    return np.interp(speed, grid, -action - np.log1p(spread) + math.log1p(spread[0]))


def quasi_elastic_cutoff(kernel: float | CollisionKernel, alpha: float, temperature: float,
                         target: float = 1e-33) -> float:
    """Where :func:`quasi_elastic_log_density` (with :math:`P(0)` of the Gaussian at
    ``temperature``) falls to ``target``, in units of :math:`\\sqrt T`; ``inf`` if not
    within 40 thermal velocities.

    Parameters
    ----------
    kernel : float or CollisionKernel
        The kernel of the unit problem, or the exponent of a power law.
    alpha : float
        Constant restitution coefficient.
    temperature : float
        Temperature of the Gaussian partners and the unit of the result.
    target : float
        Value of :math:`f(c)` at the cut-off, in (0, 1).

    Returns
    -------
    float
    """
    if not 0.0 < target < 1.0:
        raise ValueError(f"target={target!r} is not allowed; it must be in (0, 1)")
    scale = math.sqrt(temperature)
    c = np.linspace(0.0, 40.0, 801)
    # ln f(c) = ln P(v) + ln sqrt(T), P(0) of the Gaussian
    log_f = quasi_elastic_log_density(c * scale, kernel, alpha, temperature, points=801) \
        - 0.5 * math.log(2.0 * math.pi)
    below = np.flatnonzero(log_f < math.log(target))
    return float(c[below[0]]) if below.size else math.inf
