"""The gas and the problems posed on it: heated steady state and free cooling.

A :class:`InelasticGas` is a collision kernel, a restitution law and a density; a
problem adds the forcing.  The homogeneous Boltzmann equation is

.. math::

    \\partial_t P = Q_{B,\\alpha}[P] + \\mathcal F[P],

with :math:`\\mathcal F` a thermostat (:class:`HeatedProblem`: white noise or a
Fokker-Planck bath) or absent (:class:`CoolingProblem`: the homogeneous cooling
state in scaled variables, cooling rate :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`).

Parameters are validated here, where they enter the package; solvers trust them but
state which models they support through :meth:`HeatedProblem.require`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .kernel import PowerLawKernel, as_kernel
from .kernel_base import CollisionKernel
from .restitution import RestitutionLaw, ThresholdRestitution, as_restitution
from .thermostat import FokkerPlanckBath, NoThermostat, Thermostat, WhiteNoise, as_thermostat
from .validation import UnsupportedModelError, check_positive

__all__ = ["InelasticGas", "HeatedProblem", "CoolingProblem", "bracketed_secant"]


def bracketed_secant(func: Callable[[float], float], lo: float, hi: float, start: float,
                     slope: float, *, tol: float = 1e-14, max_iter: int = 100) -> float:
    """Root of an increasing ``func`` in ``(lo, hi)``: secant steps inside a bracket.

    The first step is Newton's with the guessed ``slope``, the next ones secant steps
    through the last two points; a step that would leave the current bracket (the points
    where ``func`` was seen negative and positive, initially ``lo`` and ``hi``) is
    replaced by the bracket's midpoint.  Stops when a step is below ``tol`` times
    ``max(1, |x|)`` (brentq's ``xtol = rtol = 1e-14`` of the former rule) or ``func`` is
    0.  ``func`` may return ``-inf``/``inf`` (outside its domain).

    Parameters
    ----------
    func : callable
        Increasing function of one float with a sign change in ``(lo, hi)``.
    lo, hi : float
        The bracket.
    start : float
        First point, in ``(lo, hi)``.
    slope : float
        Guessed derivative, > 0.
    tol : float
        Relative step tolerance.
    max_iter : int
        Evaluation limit.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        If the iteration does not converge in ``max_iter`` evaluations.

    Examples
    --------
    >>> round(bracketed_secant(lambda x: x**3 - 2.0, 0.0, 10.0, 1.0, 3.0), 14)
    1.25992104989487
    """
    x, fx = start, func(start)
    prev: tuple[float, float] | None = None
    for _ in range(max_iter):
        if fx == 0.0:
            return x
        if fx < 0.0:
            lo = x
        else:
            hi = x
        if prev is not None and math.isfinite(fx) and math.isfinite(prev[1]) and \
                fx != prev[1]:
            step = fx * (x - prev[0]) / (fx - prev[1])
        elif math.isfinite(fx):
            step = fx / slope
        else:
            step = math.inf
        if abs(step) <= tol * max(1.0, abs(x)):
            return x - step
        target = x - step
        if not lo < target < hi:
            target = 0.5 * (lo + hi)
            if hi - lo <= tol * max(1.0, abs(target)):
                return target
        prev = (x, fx)
        x, fx = target, func(target)
    raise ValueError(f"bracketed_secant: no convergence in {max_iter} evaluations "
                     f"(bracket [{lo}, {hi}])")


@dataclass(frozen=True, init=False)
class InelasticGas:
    """A homogeneous one-dimensional gas of inelastic rods.

    Parameters
    ----------
    alpha : float or RestitutionLaw
        Restitution coefficient in ``[0, 1]`` or a restitution law.
    density : float
        Number density :math:`n > 0` (rods per unit length).
    kernel : float or CollisionKernel
        Collision kernel: ``gamma`` in ``[0, 2]`` for :math:`B(g) = |g|^\\gamma`, or a
        kernel object (:mod:`kinetic_fem.model.kernel`).

    Examples
    --------
    >>> gas = InelasticGas(0.9, density=2.0)
    >>> round(gas.epsilon, 12), gas.kernel.gamma
    (0.1, 1.0)
    """

    restitution: RestitutionLaw
    density: float
    kernel: CollisionKernel

    def __init__(self, alpha: float | RestitutionLaw, density: float = 1.0,
                 kernel: float | CollisionKernel = 1.0) -> None:
        object.__setattr__(self, "restitution", as_restitution(alpha))
        object.__setattr__(self, "density", check_positive("density", density))
        object.__setattr__(self, "kernel", as_kernel(kernel))

    @property
    def alpha(self) -> float:
        """The constant restitution coefficient.

        Raises
        ------
        UnsupportedModelError
            If the restitution law depends on the impact speed (read
            :attr:`restitution` instead).
        """
        value = self.restitution.constant
        if value is None:
            raise UnsupportedModelError(
                f"this computation needs a constant restitution coefficient, got "
                f"{self.restitution!r}")
        return value

    @property
    def epsilon(self) -> float:
        """Inelasticity :math:`\\varepsilon = 1 - \\alpha` (constant laws)."""
        return 1.0 - self.alpha

    @property
    def gamma(self) -> float:
        """Kernel exponent :math:`\\gamma` of a power law.

        Raises
        ------
        UnsupportedModelError
            For a kernel that is not a power law (:attr:`CollisionKernel.gamma`): the
            computations that read it assume :math:`|g|^\\gamma`.
        """
        return self.kernel.gamma

    def collide(self, v1: np.ndarray, v2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Post-collision velocities :math:`(v_1', v_2')` of the pairs ``(v1, v2)``.

        Examples
        --------
        >>> InelasticGas(0.5).collide(np.array([1.0]), np.array([-1.0]))
        (array([-0.5]), array([0.5]))
        """
        v1 = np.asarray(v1, dtype=float)
        v2 = np.asarray(v2, dtype=float)
        dv = 0.5 * (1.0 + self.restitution(v1 - v2)) * (v1 - v2)
        return v1 - dv, v2 + dv

    def loss_rate(self, temperature: float) -> float:
        """Gaussian estimate of the collisional loss :math:`-d\\langle v^2\\rangle/dt`.

        :math:`\\tfrac n4\\langle(1-\\alpha(g)^2)B(g)g^2\\rangle` over two
        independent Gaussians of variance ``temperature`` (exact for a Gaussian), from
        the kernel's Gaussian averages.

        Parameters
        ----------
        temperature : float
            Temperature, > 0.

        Returns
        -------
        float
        """
        law = self.restitution
        if law.constant is not None:
            return 0.25 * self.density * (1.0 - law.constant**2) * \
                self.kernel.gaussian_mean(temperature, 2.0)
        # The law is continued beyond its range (viscoelastic) by its value there: this
        # is a scale estimate, and problems that reach such speeds are refused elsewhere.
        def weight(g: float) -> float:
            a = float(law(min(g, law.max_speed)))
            return 1.0 - a * a

        breaks = [law.threshold] if isinstance(law, ThresholdRestitution) else []
        return 0.25 * self.density * self.kernel.gaussian_average(temperature, weight, 2.0,
                                                                  breaks)

    def as_dict(self) -> dict[str, Any]:
        """Plain parameters, as stored with results."""
        law = self.restitution
        kernel = self.kernel
        out: dict[str, Any] = {"density": self.density}
        if isinstance(kernel, PowerLawKernel):
            out["gamma"] = kernel.gamma
        else:
            out["kernel"] = repr(kernel)
        if law.constant is not None:
            out["alpha"] = law.constant
        else:
            out["restitution"] = repr(law)
            if hasattr(law, "alpha"):
                out["alpha"] = law.alpha
        return out


def _require(problem: Any, method: str, *, gammas: tuple[float, ...] | None,
             constant_restitution: bool, thermostats: tuple[type, ...] | None) -> None:
    gas = problem.gas
    if gammas is not None and not isinstance(gas.kernel, PowerLawKernel):
        raise UnsupportedModelError(
            f"method {method!r} supports the power-law kernels gamma in {list(gammas)} "
            f"only, got the {gas.kernel.name} kernel {gas.kernel!r}; the 'fem' method "
            "supports every kernel")
    if gammas is not None and gas.gamma not in gammas:
        raise UnsupportedModelError(
            f"method {method!r} supports the kernels gamma in {list(gammas)} only, got "
            f"gamma={gas.gamma:g}; the 'fem' method supports every kernel")
    if constant_restitution and gas.restitution.constant is None:
        raise UnsupportedModelError(
            f"method {method!r} needs a constant restitution coefficient, got "
            f"{gas.restitution!r}; the 'fem' method supports restitution laws")
    thermostat = getattr(problem, "thermostat", None)
    if thermostats is not None and thermostat is not None and \
            not isinstance(thermostat, thermostats):
        names = ", ".join(t.__name__ for t in thermostats)
        raise UnsupportedModelError(
            f"method {method!r} supports the thermostats {names} only, got {thermostat!r}")


@dataclass(frozen=True, init=False)
class HeatedProblem:
    """Steady state of the gas driven by a thermostat.

    Parameters
    ----------
    gas : InelasticGas
    thermostat : Thermostat or float
        White noise or a Fokker-Planck bath; a float is the strength ``D`` of white
        noise.

    Raises
    ------
    ValueError
        If no steady state exists (elastic collisions under white noise alone).

    Notes
    -----
    Dimensional analysis maps every steady state onto one at :math:`n = D = 1`:
    :math:`P_{n,D}(v) = P_{1,1}(v/u)/u` with :math:`u = (D/n)^{1/(2+d)}`
    (see :attr:`velocity_scale`), :math:`d` the kernel's
    :attr:`~kinetic_fem.model.kernel_base.CollisionKernel.scale_degree` (:math:`\\gamma` for a
    power law), and the kernel :attr:`unit_kernel`, :math:`B(ug)/u^d` (the same
    kernel for a power law); with a bath the friction becomes :math:`\\xi/(n u^d)`.

    Examples
    --------
    >>> HeatedProblem.from_parameters(0.5, diffusion=8.0).velocity_scale
    2.0
    """

    gas: InelasticGas
    thermostat: Thermostat

    def __init__(self, gas: InelasticGas, thermostat: Thermostat | float = 1.0) -> None:
        if not isinstance(gas, InelasticGas):
            raise TypeError(f"gas must be an InelasticGas, got {type(gas).__name__}")
        if not isinstance(thermostat, Thermostat):
            thermostat = WhiteNoise(thermostat)
        if isinstance(thermostat, NoThermostat):
            raise ValueError("a heated problem needs a thermostat (WhiteNoise or "
                             "FokkerPlanckBath); free cooling is a CoolingProblem")
        if gas.restitution.is_elastic and thermostat.friction == 0.0:
            raise ValueError(
                "elastic collisions (alpha = 1) under white noise alone have no steady "
                "state: the energy injected by the noise is never dissipated; add friction "
                "(a Fokker-Planck bath) or take alpha < 1")
        object.__setattr__(self, "gas", gas)
        object.__setattr__(self, "thermostat", thermostat)

    @classmethod
    def from_parameters(cls, alpha: float | RestitutionLaw, *, density: float = 1.0,
                        diffusion: float = 1.0, friction: float = 0.0,
                        kernel: float | CollisionKernel = 1.0) -> HeatedProblem:
        """Build the problem from plain numbers (or model objects), validating each."""
        return cls(InelasticGas(alpha, density, kernel), as_thermostat(diffusion, friction))

    @property
    def diffusion(self) -> float:
        """Noise strength :math:`D`."""
        return self.thermostat.diffusion

    @property
    def friction(self) -> float:
        """Bath friction :math:`\\xi` (0 for white noise)."""
        return self.thermostat.friction

    @property
    def velocity_scale(self) -> float:
        """:math:`u = (D/n)^{1/(2+d)}`, the velocity built from ``D`` and ``n``
        (:math:`d` the kernel's ``scale_degree``, :math:`\\gamma` for a power law)."""
        return (self.diffusion / self.gas.density) ** (1.0 / (2.0 + self.gas.kernel.scale_degree))

    @property
    def time_scale(self) -> float:
        """:math:`1/(n u^d)`, the collision time at the velocity :attr:`velocity_scale`."""
        return 1.0 / (self.gas.density * self.velocity_scale ** self.gas.kernel.scale_degree)

    @property
    def unit_kernel(self) -> CollisionKernel:
        """The kernel of the problem at :math:`n = D = 1`, :math:`B(ug)/u^d`
        (:meth:`~kinetic_fem.model.kernel_base.CollisionKernel.rescaled`; a power law is its
        own)."""
        return self.gas.kernel.rescaled(self.velocity_scale)

    def temperature_estimate(self) -> float:
        """Steady temperature of the Gaussian closure of the energy balance C1.

        Solves :math:`2D - 2\\xi T = \\tfrac n4\\langle(1-\\alpha(g)^2)|g|^{\\gamma+2}\\rangle_T`
        with the average over Gaussians; the scale from which numerical defaults
        (cut-offs, spacings, time steps) derive.  The root in :math:`s = \\ln T` of the
        log-balance :math:`\\ln(\\text{loss}/2D)` under white noise, increasing and
        nearly linear (slope :math:`1 + d/2` for a kernel of degree :math:`d`), by secant
        steps kept inside a bracket (:func:`bracketed_secant`): 5-7 loss evaluations where
        brentq on :math:`[-60, 60]` took 17-18; with a bath (the root near the bath
        temperature, where the log-balance has a logarithmic pole) brentq.

        Examples
        --------
        >>> import math
        >>> t = HeatedProblem.from_parameters(0.0).temperature_estimate()
        >>> round(t, 12) == round(math.pi ** (1 / 3), 12)
        True
        """
        if self.friction > 0.0:  # near the bath temperature: brentq on the plain balance
            from scipy.optimize import brentq

            def balance(log_t: float) -> float:
                t = float(np.exp(log_t))
                return self.thermostat.energy_input(t) - self.gas.loss_rate(t)

            t_bath = self.thermostat.bath_temperature  # (D/xi may underflow to 0)
            hi = min(math.log(t_bath), 60.0) if t_bath > 0 else -math.inf
            if hi <= -60.0 or balance(hi) >= 0.0:  # (beyond the bracket: the bath's scale)
                return self.thermostat.bath_temperature
            return float(np.exp(brentq(balance, -60.0, hi, xtol=1e-14, rtol=1e-14)))
        gain = self.thermostat.energy_input(1.0)  # 2D

        def log_balance(log_t: float) -> float:
            loss = self.gas.loss_rate(math.exp(log_t))
            return math.log(loss / gain) if loss > 0.0 else -math.inf

        slope = 1.0 + 0.5 * self.gas.kernel.scale_degree
        return math.exp(bracketed_secant(log_balance, -60.0, 60.0, 0.0, slope))

    def require(self, method: str, *, gammas: tuple[float, ...] | None = None,
                constant_restitution: bool = False,
                thermostats: tuple[type, ...] | None = None) -> None:
        """Raise :class:`UnsupportedModelError` unless ``method`` supports this model."""
        _require(self, method, gammas=gammas, constant_restitution=constant_restitution,
                 thermostats=thermostats)

    def as_dict(self) -> dict[str, Any]:
        """Plain parameters, as stored with results."""
        out: dict[str, Any] = {"problem": "heated", **self.gas.as_dict(),
                               "diffusion": self.diffusion}
        if isinstance(self.thermostat, FokkerPlanckBath):
            out["friction"] = self.friction
        return out


@dataclass(frozen=True, init=False)
class CoolingProblem:
    """Free cooling: the homogeneous cooling state in scaled variables.

    The temperature decays as :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}` (Haff's law
    for hard rods) and :math:`f(c) = \\sqrt{T} P(c\\sqrt T)` tends to a
    time-independent scaling form.

    Parameters
    ----------
    gas : InelasticGas
        The gas (kernel, restitution law, density); its restitution must be inelastic.

    Raises
    ------
    ValueError
        For elastic collisions (no cooling).
    UnsupportedModelError
        For a kernel that is not homogeneous (:math:`B(ug) \\ne u^d B(g)`: its
        ``homogeneity_degree`` is None): the cooling gas has no time-independent scaled
        state then.
    """

    gas: InelasticGas
    thermostat: Thermostat

    def __init__(self, gas: InelasticGas) -> None:
        if not isinstance(gas, InelasticGas):
            raise TypeError(f"gas must be an InelasticGas, got {type(gas).__name__}")
        if gas.restitution.is_elastic:
            raise ValueError("elastic collisions (alpha = 1) do not cool: there is no "
                             "homogeneous cooling state; take alpha < 1")
        if gas.kernel.homogeneity_degree is None:
            raise UnsupportedModelError(
                f"free cooling is solved in scaled variables, which needs a homogeneous "
                f"kernel B(ug) = u^d B(g) (a power law |g|^gamma); the {gas.kernel.name} "
                f"kernel {gas.kernel!r} is not: its cooling gas has no scaled steady state")
        object.__setattr__(self, "gas", gas)
        object.__setattr__(self, "thermostat", NoThermostat())

    @classmethod
    def from_parameters(cls, alpha: float | RestitutionLaw, *, density: float = 1.0,
                        kernel: float | CollisionKernel = 1.0) -> CoolingProblem:
        """Build the problem from plain numbers (or model objects), validating each.

        Parameters
        ----------
        alpha : float or RestitutionLaw
            Restitution coefficient or law.
        density : float
            :math:`n`.
        kernel : float or CollisionKernel
            ``gamma`` of a power law, or a homogeneous kernel.

        Returns
        -------
        CoolingProblem
        """
        return cls(InelasticGas(alpha, density, kernel))

    def zeta_estimate(self) -> float:
        """Gaussian estimate of the cooling rate at unit temperature.

        :math:`\\zeta = \\langle(1-\\alpha^2)|g|^{\\gamma+2}\\rangle_G/8` from
        :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`.

        Examples
        --------
        >>> import math
        >>> z = CoolingProblem.from_parameters(0.0).zeta_estimate()
        >>> round(z * math.sqrt(math.pi), 12)
        1.0
        """
        return self.gas.loss_rate(1.0) / (2.0 * self.gas.density)

    def require(self, method: str, *, gammas: tuple[float, ...] | None = None,
                constant_restitution: bool = False,
                thermostats: tuple[type, ...] | None = None) -> None:
        """Raise :class:`UnsupportedModelError` unless ``method`` supports this model."""
        _require(self, method, gammas=gammas, constant_restitution=constant_restitution,
                 thermostats=None)

    def as_dict(self) -> dict[str, Any]:
        """Plain parameters, as stored with results."""
        return {"problem": "cooling", **self.gas.as_dict()}
