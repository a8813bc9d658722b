"""The model as the FEM solvers see it: scaled parameters, cut-offs, spacings, meshes.

Every heated steady state maps onto one at :math:`n = D = 1` by the velocity
:math:`u = (D/n)^{1/(2+d)}` (:attr:`kinetic_fem.model.HeatedProblem.velocity_scale`,
:math:`d = \\gamma` for a power law); there the kernel is
:attr:`~kinetic_fem.model.HeatedProblem.unit_kernel`, the bath friction is
:math:`\\xi/(n u^d)` and a restitution law is evaluated at the physical speed
:math:`u\\,|x - y|`.  Every rule below asks the kernel
(:class:`~kinetic_fem.model.kernel_base.CollisionKernel`), never an exponent.  The
numerical defaults derive from the model's own scales:

* the temperature of the Gaussian closure of the energy balance C1
  (:meth:`~kinetic_fem.model.HeatedProblem.temperature_estimate`);
* the tail: far from the bulk, :math:`D P'' + \\xi (vP)' \\approx n B(v) P`
  (the loss dominates the gain), whose WKB solution :math:`P \\sim e^{-S(v)}` has

  .. math::

      S'(v) = \\frac{\\xi v + \\sqrt{\\xi^2 v^2 + 4 D n B(v)}}{2D},

  :math:`S = \\tfrac{2}{2+\\gamma}\\sqrt{n/D}\\,v^{1+\\gamma/2}` for white noise
  (:math:`\\tfrac23 v^{3/2}` for hard rods, claim C4; :math:`v` for the Maxwell model,
  an exponential tail; :func:`kinetic_fem.model.scales.tail_action` for any kernel).
  The cut-off is where :math:`S` reaches 33 decades.
* the element size grows in the tail as :math:`h \\propto c^{\\kappa}` with
  :math:`\\kappa = (3 - \\beta)/3`, :math:`\\beta` the tail exponent of :math:`\\ln f`
  (P2 interpolates :math:`\\ln f` with error :math:`h^3 (\\ln f)'''`).

The paper's model (hard rods, constant alpha, white noise) keeps its own measured
defaults :func:`default_cutoff` and :func:`default_spacing` and uniform meshes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from ... import sonine
from ...model import CollisionKernel, HeatedProblem, PowerLawKernel, RestitutionLaw, as_kernel
from ...model.scales import heated_cutoff, quasi_elastic_cutoff, quasi_elastic_log_density
from ...model.scales import tail_action as model_tail_action
from .grading import graded_vertices
from .start import start_exponent

__all__ = ["default_cutoff", "default_spacing", "ScaledModel", "scaled_model",
           "tail_action", "tail_exponent", "gain_margin", "initial_log_density",
           "model_cutoff", "model_spacing", "graded_vertices", "DECADES", "P3_SPACING",
           "P3_SPACING_LOW", "default_order", "P3_MODEL_ALPHA", "P3_MODEL_SPACING",
           "action_root", "QUASI_ELASTIC_START"]

DECADES = 33.0
"""Decades of f(c) covered by the default cut-off."""


def default_cutoff(alpha: float) -> float:
    """Cut-off :math:`c_{max} = V/\\sqrt{T}` covering :math:`f(c) > 10^{-33}` (hard rods).

    The far tail :math:`\\exp(-A_c c^{3/2})` of claim C4
    (:func:`sonine.tail_exponent_amplitude`) or, if it reaches 1e-33 sooner, the
    smaller of the Gaussian and the quasi-elastic tail :math:`\\exp(-x^3/6)`,
    :math:`x = (\\varepsilon T)^{1/3} c` (claim C5); plus one thermal velocity: the
    model's rule (:func:`kinetic_fem.model.scales.heated_cutoff`).

    Parameters
    ----------
    alpha : float
        Coefficient of restitution (hard rods, white noise).

    Returns
    -------
    float
    """
    return heated_cutoff(alpha, 10.0**-DECADES, core_margin=1.0) + 1.0


def default_spacing(alpha: float, order: int = 2) -> float:
    """Element size (thermal velocities) meeting the production tolerances.

    P2: :math:`0.08\\,\\min(1, (\\varepsilon/0.1)^{1/5})`, from
    ``benchmarks/convergence_heated.py``: at 0.08, T is within 3e-9, a2 within 3e-8 and
    f(c) within 2e-6 for alpha <= 0.9; the cubic tails near alpha = 1 need finer
    elements for f (spacing 0.05 gives 1e-4 at alpha = 0.99, 0.032 at 0.999).
    P3: :data:`P3_SPACING` times the P2 size (2.5 times for alpha <= 0.3), where T, a2
    and f(c) are each at least as accurate as with P2 on every alpha of
    ``benchmarks/archive/bench_fem_speed.py`` (T and a2 10 to 1000 times more).  Other degrees:
    the P2 size.

    Parameters
    ----------
    alpha : float
        Coefficient of restitution.
    order : int
        Lagrange degree.

    Returns
    -------
    float
    """
    p2 = 0.08 * min(1.0, (10.0 * (1.0 - alpha)) ** 0.2)
    if order == 3:
        return (P3_SPACING_LOW if alpha <= 0.3 else P3_SPACING) * p2
    return p2


P3_SPACING = 2.0
"""P3 element size over the P2 default (alpha > 0.3)."""


def default_order(model: ScaledModel) -> int:
    """Lagrange degree of the default mesh: 3 for the paper's model (hard rods, constant
    alpha, white noise; as accurate as P2 with 25 to 40 % fewer nodes, see
    :func:`default_spacing`) and, with :data:`P3_MODEL_SPACING` times the P2 size
    (:func:`model_spacing`), for kernels growing at most linearly (:math:`\\gamma \\le
    1`, the kernel's ``tail_growth``) with a constant alpha, in a bath or under white noise
    up to the effective :math:`\\alpha =` :data:`P3_MODEL_ALPHA`; else 2.

    Measured (against P2 at half the default spacing; gamma = 0, 0.5, 2 under white
    noise and hard rods in a bath, alpha = 0, 0.6, 0.9): P3 at 1.7 times the P2 size has
    11 % fewer nodes, its T is 10 to 100 times more accurate (dT/T 4e-15 - 2e-10 against
    1e-13 - 1e-8), its a2 about 10 times (2e-10 - 3e-9 against 3e-9 - 5e-8) and its
    f(c) (f > 1e-30) 1.1 to 4 times (max df/f 3e-6 - 1.3e-3 against 1.3e-5 - 1.5e-3).
    At 2 and 2.5 times the P2 size the far tail of f(c) is up to 2 and 12 times less
    accurate than P2's.  Mean CPU time per state over 12 alphas in [0, 0.99] (P2 / P3):
    Maxwell 90 / 75 ms, gamma 0.5 122 / 101 ms, bath 61 / 51 ms, but gamma = 2 61 / 68 ms
    (its fine solve needs more Jacobians), so faster kernels keep P2 under white noise.
    Near elastic collisions (alpha 0.96-0.999, gamma 0, 1/2, saturating) P3 is 1.05-3x
    faster than P2, df/f 0.56-0.7x, T and a2 10-100x more accurate (issue 16).

    Parameters
    ----------
    model : ScaledModel
        The heated model.

    Returns
    -------
    int
    """
    if model.is_paper_model:
        return 3
    if model.law.constant is None:
        return 2
    if model.kernel.tail_growth[1] > 1.0:
        return 2
    if model.friction > 0.0 or 1.0 - model.effective_epsilon <= P3_MODEL_ALPHA:
        return 3
    return 2


QUASI_ELASTIC_START = 0.95
"""From this alpha soft kernels start at most at the quasi-elastic profile
(:func:`initial_log_density`; gamma = 1/2 at 0.99: 98 -> 77 ms, no change below)."""
P3_MODEL_ALPHA = 1.0
"""Largest effective alpha with P3 under white noise (:func:`default_order`; was 0.95)."""
P3_MODEL_SPACING = 1.7
"""P3 element size over the P2 :func:`model_spacing` (:func:`default_order`: the largest
factor at which f(c) stays at least as accurate as with P2)."""
P3_SPACING_LOW = 2.5
"""P3 element size over the P2 default for alpha <= 0.3 (the f(c) error of P2 is larger
there relative to P3's)."""


@dataclass(frozen=True)
class ScaledModel:
    """The heated problem at :math:`n = D = 1`.

    Attributes
    ----------
    law : RestitutionLaw
    kernel : CollisionKernel
        The kernel at ``n = D = 1`` (a float: the exponent of a power law).
    friction : float
        Scaled bath friction :math:`\\xi/(n u^d)` (0 for white noise).
    speed_scale : float
        :math:`u`, the physical speed of a unit of scaled velocity.
    temperature : float
        Scaled temperature estimate (first-order Sonine for the paper's model, the
        Gaussian closure of C1 otherwise).
    """

    law: RestitutionLaw
    kernel: CollisionKernel
    friction: float
    speed_scale: float
    temperature: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "kernel", as_kernel(self.kernel))

    @property
    def gamma(self) -> float:
        """Exponent of a power-law kernel (other kernels refuse)."""
        return self.kernel.gamma

    @property
    def alpha(self) -> float:
        """The constant coefficient, or the smallest value of the law."""
        const = self.law.constant
        return self.law.min_alpha if const is None else const

    @property
    def is_paper_model(self) -> bool:
        """Hard rods, constant alpha, white noise: the measured defaults apply."""
        return self.kernel.is_hard_rods and self.law.constant is not None and self.friction == 0.0

    @property
    def continues_near_elastic(self) -> bool:
        """Whether a near-elastic state (white noise, effective alpha above 0.95) starts
        from the state at ten times the inelasticity: for kernels that grow at least
        linearly (:math:`\\gamma \\ge 1`; the kernel's ``tail_growth``), whose
        quasi-elastic :math:`f(c)` is approached smoothly and Newton from a Gaussian is
        not robust.  Soft kernels :math:`\\gamma < 1` start from
        :func:`initial_log_density` instead: near elastic collisions their bulk is close
        to the Gaussian at :math:`T`, while the state at ten times the inelasticity,
        rescaled, lies many decades above the tail, and Newton diverges from it
        (measured: Maxwell model and :math:`\\gamma = 0.5` at alpha = 0.99; from the
        Gaussian start 4 to 9 Newton steps at alpha = 0.99 and 0.999)."""
        return self.kernel.tail_growth[1] >= 1.0

    @property
    def effective_epsilon(self) -> float:
        """:math:`1 - \\alpha_{eff}`, with :math:`1 - \\alpha_{eff}^2` the Gaussian average
        of :math:`1 - \\alpha(g)^2` weighted by the energy loss :math:`B(g)g^2`."""
        if self.law.constant is not None:
            return 1.0 - self.law.constant
        s, w = np.polynomial.hermite.hermgauss(120)
        g = 2.0 * math.sqrt(self.temperature) * np.abs(s)
        weight = w * self.kernel.weighted_rate(g, 2.0)
        alpha_g = self.law(np.minimum(g * self.speed_scale, self.law.max_speed))
        mean = float(np.sum(weight * (1.0 - alpha_g**2)) / np.sum(weight))
        return 1.0 - math.sqrt(max(1.0 - mean, 0.0))


def scaled_model(problem: HeatedProblem) -> ScaledModel:
    """The :class:`ScaledModel` of a heated problem.

    Parameters
    ----------
    problem : HeatedProblem
        The problem in its own units.

    Returns
    -------
    ScaledModel
    """
    gas = problem.gas
    u = problem.velocity_scale
    friction = problem.friction / (gas.density * u**gas.kernel.scale_degree)
    law = gas.restitution
    kernel = problem.unit_kernel
    if law.constant is not None and kernel.is_hard_rods and friction == 0.0:
        temperature = sonine.steady_temperature(law.constant)
    else:
        temperature = problem.temperature_estimate() / u**2
    return ScaledModel(law, kernel, friction, u, temperature)


def tail_action(v: float, gamma: float | CollisionKernel, friction: float) -> float:
    """:math:`S(v) = \\int_0^v S'` of the module docstring (``n = D = 1``): the model's
    :func:`kinetic_fem.model.scales.tail_action`.

    Parameters
    ----------
    v : float
        Velocity (``n = D = 1``).
    gamma : float or CollisionKernel
        The kernel at ``n = D = 1`` (a float: the exponent of a power law).
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
    return model_tail_action(v, gamma, friction)


def initial_log_density(v: NDArray[np.float64], model: ScaledModel) -> NDArray[np.float64]:
    """A starting :math:`\\ln P`: the Gaussian at the model's temperature in the bulk,
    the tail :math:`-S(|v|)` where that decays more slowly, for soft kernels under white
    noise continued from the Gaussian (:func:`~kinetic_fem.solvers.fem.start.start_exponent`),
    from alpha = :data:`QUASI_ELASTIC_START` at most the quasi-elastic profile
    (:func:`kinetic_fem.model.scales.quasi_elastic_log_density`), normalised (trapezoid).

    Parameters
    ----------
    v : ndarray
        Velocities (``n = D = 1``).
    model : ScaledModel
        The heated model.

    Returns
    -------
    ndarray
        :math:`\\ln P` at ``v``.
    """
    v = np.abs(np.asarray(v, dtype=float))
    top = max(float(v.max()), 1e-12)
    fine = np.linspace(0.0, top, 20001)
    if model.friction == 0.0 and isinstance(model.kernel, PowerLawKernel):
        action = model.kernel.wkb_action(fine)  # closed form
    else:  # the trapezoid rule on this grid (a kernel's numeric action costs ~8 ms here)
        xi = model.friction
        rate = 0.5 * (xi * fine + np.sqrt((xi * fine) ** 2 + 4.0 * model.kernel.rate(fine)))
        action = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1])
                                                  * np.diff(fine))])
    log_p = -start_exponent(0.5 * fine**2 / model.temperature, action, model)
    if model.friction == 0.0 and model.law.constant is not None and \
            model.kernel.tail_growth[1] < 1.0 and model.alpha >= QUASI_ELASTIC_START:
        # near elastic collisions: at most the quasi-elastic profile (lighter than the
        # Gaussian for gamma > 0; gamma = 1/2, alpha = 0.99: 5 coarse Jacobians -> 3)
        log_p = np.minimum(log_p, quasi_elastic_log_density(
            fine, model.kernel, model.alpha, model.temperature))
    weights = np.full(fine.size, fine[1] - fine[0])
    weights[[0, -1]] *= 0.5
    norm = 2.0 * float(np.sum(weights * np.exp(log_p)))
    return np.interp(v, fine, log_p) - math.log(norm)


def action_root(kernel: CollisionKernel, friction: float, value: float, lo: float,
                hi: float) -> float:
    """The root of :math:`S(v) = ` ``value`` in ``[lo, hi]`` (:func:`tail_action`).

    Newton from ``hi`` with the exact :math:`S'(v) = (\\xi v + \\sqrt{\\xi^2 v^2 +
    4B(v)})/2`: :math:`S` is increasing and convex (the loss frequency grows), so the
    iterates decrease monotonically to the root; a few actions in place of brentq's
    dozens (each a quadrature for kernels other than power laws, or with a bath: the
    saturating kernel's cut-off took 6-9 ms).

    Parameters
    ----------
    kernel : CollisionKernel
        The kernel at ``n = D = 1``.
    friction : float
        Bath friction (0: white noise).
    value : float
        The action to reach.
    lo, hi : float
        A bracket with :math:`S(lo) \\le` ``value`` :math:`\\le S(hi)`.

    Returns
    -------
    float
    """
    v = hi
    for _ in range(60):
        slope = 0.5 * (friction * v + math.sqrt((friction * v) ** 2
                                                 + 4.0 * float(kernel.rate(v))))
        step = (tail_action(v, kernel, friction) - value) / max(slope, 1e-300)
        v = max(v - step, lo)
        if abs(step) <= 1e-10 * max(v, 1.0):
            break
    return v


def gain_margin(model: ScaledModel) -> float:
    """Cut-off correction (thermal velocities) for the gain-delayed tail of soft kernels.

    A tail particle at :math:`v` is fed by collisions of a faster one, at
    :math:`v(1 + \\varepsilon')`, :math:`\\varepsilon' = (1-\\alpha)/(1+\\alpha)`, with a
    bulk partner, at about :math:`e^{-S'(v)\\,v\\,\\varepsilon'}` times the loss: near
    elastic collisions the gain keeps the bulk Gaussian (at the temperature :math:`T`)
    far beyond the point where the bare tail :math:`e^{-S}` would reach 33 decades.  The
    tail is then the Gaussian up to where its slope :math:`v/T` meets :math:`S'(v)`, and
    the tangent :math:`e^{-S}` beyond.  This returns how far (in :math:`\\sqrt T`) that
    tangent construction reaches 33 decades beyond the bare :math:`S`, plus one thermal
    velocity; 0 for :math:`\\gamma \\ge 1` and with a bath (the automatic widening copes
    there, measured), where larger intervals only cost elements.

    Measured (Maxwell model, white noise, 33 decades at): alpha = 0.88: c = 21.0 (this
    rule 22.2); 0.9: 20.0 (20.9); 0.95: 16.6 (17.1); the bare rule gives 19.0, 17.6,
    12.9, and the automatic widening of that truncated tail starts Newton from the
    truncated state, which lands on a spurious discrete state (alpha >= 0.88).

    Parameters
    ----------
    model : ScaledModel
        The heated model.

    Returns
    -------
    float

    Examples
    --------
    >>> from kinetic_fem.model import ConstantRestitution
    >>> m = ScaledModel(ConstantRestitution(0.9), 0.0, 0.0, 1.0, 400 / 19)
    >>> round(gain_margin(m), 3)                          # (T/2) / sqrt(T) + 1
    3.294
    """
    coefficient, gamma = model.kernel.tail_growth  # B(g) ~ c g^gamma far out
    if model.friction > 0.0 or gamma >= 1.0:
        return 0.0
    target = DECADES * math.log(10.0)
    temp, kernel, root = model.temperature, model.kernel, math.sqrt(coefficient)
    # the Gaussian slope v/T meets the tail's sqrt(c) v^(gamma/2) at v_t
    v_t = (temp * root) ** (1.0 / (1.0 - 0.5 * gamma))
    gauss_t = 0.5 * v_t**2 / temp
    reach = (target * (1.0 + 0.5 * gamma) / root) ** (1.0 / (1.0 + 0.5 * gamma))
    if gauss_t >= target:  # the Gaussian reaches 33 decades first
        v_cut = math.sqrt(2.0 * target * temp)
    else:
        s_t = tail_action(v_t, kernel, 0.0)
        v_cut = action_root(kernel, 0.0, s_t - gauss_t + target, v_t,
                             2.0 * v_t + 4.0 * (target / root) ** (1.0 / (1.0 + 0.5 * gamma))
                             + 1.0)
    if isinstance(kernel, PowerLawKernel):  # S = reach at v_bare, in closed form
        v_bare = reach
    else:
        top = reach + 1.0
        while tail_action(top, kernel, 0.0) < target:
            top *= 2.0
        v_bare = action_root(kernel, 0.0, target, 0.0, top)
    return max(v_cut - v_bare, 0.0) / math.sqrt(temp) + 1.0


def model_cutoff(model: ScaledModel) -> float:
    """Cut-off :math:`V/\\sqrt{T}` where the tail :math:`e^{-S}` reaches 1e-33, delayed by
    the gain (:func:`gain_margin`), plus one thermal velocity (:func:`default_cutoff`
    for the paper's model); for kernels growing slower than linearly under white noise at
    most where the quasi-elastic profile reaches 1e-33, plus one
    (:func:`kinetic_fem.model.scales.quasi_elastic_cutoff`: gamma = 1/2 at alpha = 0.99,
    11.3 instead of 14.3, the state's own 33 decades at 10.2).

    Parameters
    ----------
    model : ScaledModel
        The heated model.

    Returns
    -------
    float
    """
    if model.is_paper_model and model.law.constant is not None:
        return default_cutoff(model.law.constant)
    target = DECADES * math.log(10.0)
    if model.friction == 0.0 and isinstance(model.kernel, PowerLawKernel):
        top = 1.0
        while tail_action(top, model.kernel, model.friction) < target:
            top *= 2.0
        v_cut = brentq(lambda v: tail_action(v, model.kernel, 0.0) - target, 0.0, top,
                       xtol=1e-10)
    else:  # from the asymptotic reach of B ~ c g^p (fewer numeric actions)
        coefficient, growth = model.kernel.tail_growth
        top = (target * (1.0 + 0.5 * growth) / math.sqrt(coefficient)) ** (
            1.0 / (1.0 + 0.5 * growth))
        while tail_action(top, model.kernel, model.friction) < target:
            top *= 2.0
        v_cut = action_root(model.kernel, model.friction, target, 0.0, top)
    c_max = v_cut / math.sqrt(model.temperature) + 1.0 + gain_margin(model)
    if model.friction == 0.0 and model.law.constant is not None and \
            model.kernel.tail_growth[1] < 1.0:  # the lighter quasi-elastic tail of gamma > 0
        return min(c_max, 1.0 + quasi_elastic_cutoff(model.kernel, model.alpha,
                                                     model.temperature, 10.0**-DECADES))
    return c_max


def tail_exponent(model: ScaledModel) -> float:
    """:math:`\\beta` of :math:`\\ln f \\sim -c^\\beta`: 2 with friction, else 1 + p/2 with
    :math:`B(g) \\sim g^p` (the kernel's ``tail_growth``; 1 + gamma/2 for a power law).

    Parameters
    ----------
    model : ScaledModel
        The heated model.

    Returns
    -------
    float
    """
    return 2.0 if model.friction > 0.0 else 1.0 + 0.5 * model.kernel.tail_growth[1]


def model_spacing(model: ScaledModel, order: int = 2) -> float:
    """Bulk element size in thermal velocities: the P2 :func:`default_spacing` at the
    effective inelasticity, times :data:`P3_MODEL_SPACING` for P3.

    Parameters
    ----------
    model : ScaledModel
        The heated model.
    order : int
        Lagrange degree.

    Returns
    -------
    float
    """
    factor = P3_MODEL_SPACING if order == 3 else 1.0
    if model.friction > 0.0:  # the bath's Gaussian limit needs no quasi-elastic refinement
        return factor * default_spacing(min(1.0 - model.effective_epsilon, 0.9))
    return factor * default_spacing(1.0 - model.effective_epsilon)
