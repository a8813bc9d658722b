"""Direct Simulation Monte Carlo of the homogeneous Boltzmann equation (1D inelastic rods).

The ``N`` particles have velocities only (no positions).  The model comes from
:mod:`kinetic_fem.model`: a kernel :math:`B(g) = |g|^\\gamma`, ``0 <= gamma <= 2``
(1: hard rods, the paper; 0: Maxwell), a restitution law :math:`\\alpha(g)` and a
thermostat.  The pair ``(i, j)`` collides at rate :math:`n|v_i - v_j|^\\gamma/(N-1)`,
so that particle ``i`` collides at rate :math:`n \\langle |v_i - v'|^\\gamma\\rangle`
over the others, the loss rate of

.. math::

    \\partial_t P = Q[P] + \\mathcal F[P], \\qquad
    Q[P](v) = n\\int dv'\\,|v-v'|^\\gamma\\,[\\text{gain} - P(v)P(v')],

(for hard rods with constant ``alpha`` the gain is
:math:`\\tfrac{4}{(1+\\alpha)^2}P(v')P(\\tfrac{2v-(1-\\alpha)v'}{1+\\alpha})`).
The total rate is :math:`\\Lambda = \\tfrac n{N-1}\\sum_{i<j} g_{ij}^\\gamma`.
*Thinning*: candidate pairs (two distinct uniform indices, each unordered pair with
probability :math:`2/(N(N-1))`) are drawn at rate
:math:`\\Lambda_{max} = N n g_{max}^\\gamma/2` and accepted with probability
:math:`(g_{ij}/g_{max})^\\gamma`; each pair then collides at rate
:math:`n g_{ij}^\\gamma/(N-1)` as required, and each candidate advances time by
:math:`2/(N n g_{max}^\\gamma)`.  The majorant :math:`g_{max} = \\max v - \\min v` is
the exact largest relative speed, and a collision,
:math:`v_{1,2}' = v_{1,2} \\mp \\tfrac{1+\\alpha(g)}{2}(v_1 - v_2)`, replaces two
velocities by convex combinations of them, so it can never exceed ``g_max``; it is
re-measured after every kick (heated) or every ``N`` candidates (cooling).  No
collision is ever lost.  For the Maxwell kernel (``gamma = 0``) every candidate
collides: no rejection and no acceptance draw.  A restitution law is evaluated by
:func:`kinetic_fem.model.restitution_value` at the physical relative speed; a run
whose relative speeds leave the law's range (``law.max_speed``) stops with a
``ValueError``.

*Heated* (:func:`simulate_heated`): Strang splitting
:math:`e^{\\Delta t(C+K)} \\approx e^{\\Delta t K/2} e^{\\Delta t C} e^{\\Delta t K/2}`
of collisions ``C`` and thermostat kicks ``K``, each exact on its own: white noise
:math:`v \\to v + \\sqrt{2D\\Delta t}\\,\\xi`; the Fokker-Planck bath by its exact
Ornstein-Uhlenbeck update :math:`v \\to v e^{-\\xi\\Delta t} +
\\sqrt{T_b(1 - e^{-2\\xi\\Delta t})}\\,\\xi`, :math:`T_b = D/\\xi`.  Consecutive half
kicks merge (exactly, for both), measurements are taken after a half kick.  Weak
error :math:`O(\\Delta t^2)`; the measured orders (hard rods, white noise) are
1.7 +- 0.1 for T and 1.9 +- 0.3 for a2 (``benchmarks/convergence_dsmc.py``).  Kicks
are applied to every particle at every step: "lazy" kicks (one Gaussian summing a
particle's pending kicks when it is next touched) would leave the stored velocities
without a true majorant, because a pending Gaussian is unbounded (the bound of the
generator's largest normal, 13.7 standard deviations, would raise the number of
candidates by more than the kicks it saves; see :mod:`particles._dsmc_heated`).  The
collision
count per step is the time counter
:math:`\\lfloor \\text{debt} + \\Delta t\\,\\Lambda_{max} \\rfloor` (fraction carried
over): the expected count rather than a Poisson one, a difference of order
:math:`1/N`, like the other finite-N effects (all together they lower T by about
:math:`2T/N`, see the N table of ``benchmarks/convergence_dsmc.py``).  The dynamics
depend on velocity differences only, so velocities are kept in the centre-of-mass
frame (the mean, a random walk driven by the kicks, is subtracted at every
measurement); white-noise kicks inject :math:`2D(1 - 1/N)` per particle into the
internal energy.  Numerical defaults come from the model: the reference temperature
``T_ref`` is the Gaussian closure of the energy balance
(:meth:`~kinetic_fem.model.HeatedProblem.temperature_estimate`), the collision
rate per particle :math:`n\\langle|g|^\\gamma\\rangle` at ``T_ref``
(:meth:`~kinetic_fem.model.CollisionKernel.gaussian_mean`).

*Free cooling* (:func:`simulate_cooling`): velocities are moved to the centre-of-mass
frame and rescaled to unit temperature every ``N`` candidates (inside the kernel)
while :math:`\\ln` of the scale and :math:`\\ln t` are accumulated (``logaddexp``),
so nothing under- or overflows over any number of collisions; a candidate at scale
``S`` (physical velocity per unit) advances time by
:math:`2/(N n (S g_{max})^\\gamma)`, so that :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`
(:meth:`DSMCRun.cooling_rate`).  Time advances by the expected candidate spacing:
the sequence of collisions is exact, and the clock differs from the exponential
waiting times of the exact process by a relative :math:`O(\\text{candidates}^{-1/2})`.

Random numbers: an explicit-state xoshiro256** stream inside the kernels (seeded
from a ``numpy.random.SeedSequence``, saved in checkpoints) for pairs and acceptance;
heated runs draw the Gaussian kicks (ziggurat) and the hard-rod candidates from a second
word of the state, a wyrand counter (one draw per candidate; the ziggurat's rare slow
paths stay on xoshiro256**); free cooling of hard rods with a constant ``alpha`` draws
its candidates in blocks from eight lock-step xoshiro256++ streams (a fixed layout, the
same numbers on every machine); see :mod:`particles.rng`.

*Relaxation detector* (``relax="auto"``): the time series are cut into windows of
:math:`W = \\max(2, 2/(1-\\alpha^2))` collisions per particle (at least 10 samples;
for a restitution law :math:`1-\\alpha^2` is its average weighted by
:math:`|g|^{\\gamma+2}` at ``T_ref``), about three linear relaxation times of T
(:math:`\\tau\\nu = 2/(3(1-\\alpha^2))` collisions per particle from the energy
balance).  Averaging starts after the first window whose means of ``a2`` and of
``ln T`` (heated) or ``a3`` (cooling) differ from those of the previous window by less
than three combined standard errors (each from the spread of five sub-block means, as
the samples are correlated; at least two windows, at most 20; ``info.converged`` is
False if the cap is hit).

References
----------
G. A. Bird, *Molecular Gas Dynamics and the Direct Simulation of Gas Flows* (1994).
Barrat, Biben, Racz, Trizac, van Wijland, J. Phys. A 35, 463 (2002).
"""

from __future__ import annotations

import logging
import math
import numbers
from pathlib import Path
from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from kinetic_fem.distribution import VelocityDistribution
from kinetic_fem.model import (
    CollisionKernel,
    CoolingProblem,
    HeatedProblem,
    InelasticGas,
    RestitutionLaw,
    check_positive,
)
from kinetic_fem.progress import resolve_progress
from kinetic_fem.sonine import a2_first_order

from ._dsmc_engine import DSMCOptions, DSMCRun, Engine
from ._dsmc_model import kernel_model
from .run import MEASUREMENT_EVENTS, Checkpointing, check_memory, check_seed, check_work
from .sampling import initial_velocities_of

__all__ = ["DSMCRun", "simulate_heated", "simulate_cooling", "combine_runs",
           "MAX_COLLISIONS_PER_STEP"]

logger = logging.getLogger(__name__)

MAX_COLLISIONS_PER_STEP = 0.5
"""Largest allowed expected number of collisions per particle in one heated step."""

MAX_AUTO_WINDOW = 1e5
"""Longest relaxation window (collisions per particle) that ``relax='auto'`` watches:
alpha <= 0.99999 for hard rods; beyond, give ``relax`` explicitly."""

_BYTES_PER_PARTICLE = 48
"""Arrays per particle of a DSMC run (velocities, their copy, indices), for the check."""


def _check_int(name: str, value: object, lo: int, hi: int | None = None) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__} {value!r}")
    value = int(value)
    if value < lo or (hi is not None and value > hi):
        allowed = f">= {lo}" if hi is None else f"in [{lo}, {hi}]"
        raise ValueError(f"{name}={value!r} is not allowed; it must be {allowed}")
    return int(value)


def _seeds(seed: int | np.random.SeedSequence | None) -> tuple[Any, Any, str]:
    """Two independent children (initial state, kernel stream) without mutating ``seed``."""
    seed = check_seed(seed)  # type: ignore[assignment]
    root = seed if isinstance(seed, np.random.SeedSequence) else np.random.SeedSequence(seed)
    kids = [np.random.SeedSequence(root.entropy, spawn_key=(*root.spawn_key, k))
            for k in (0, 1)]
    return kids[0], kids[1], f"{root.entropy}:{tuple(root.spawn_key)}"


def _common(n_particles: int, collisions_per_particle: float, relax: str | float,
            sample_every: float, average_every: str | float, n_batches: int, bins: int,
            c_max: float,
            checkpoint: str | Path | None, checkpoint_every: float, resume: bool,
            max_wall_time: float | None, progress: bool | None,
            w: float, step: float | None = None) -> dict[str, Any]:
    """Validate the run options shared by both problems.

    Parameters
    ----------
    w : float
        The relaxation window, :func:`_window`.
    step : float, optional
        Heated: expected collisions per particle in one time step (``dt`` times the
        collision rate), the unit a measurement interval is rounded to; None (cooling):
        the interval is rounded to whole collisions.
    """
    n = _check_int("n_particles", n_particles, 2, 2**32 - 1)
    cpp = check_positive("collisions_per_particle", collisions_per_particle)
    every = check_positive("sample_every", sample_every)
    _check_sample_every(every, n, step)
    nb = _check_int("n_batches", n_batches, 2)
    if not (relax == "auto" or (isinstance(relax, numbers.Real) and not isinstance(relax, bool)
                                and math.isfinite(relax) and relax >= 0)):
        raise ValueError(f"relax must be 'auto' or a number of collisions per particle >= 0, "
                         f"got {relax!r}")
    fixed = 0.0 if relax == "auto" else float(relax)
    check_work(0.5 * n * (cpp + fixed), f"collisions_per_particle={cpp:g}"
               + (f" after relax={fixed:g}" if fixed else "") + f" with N={n}")
    # measurements of the averaging and of a fixed relaxation (relax='auto': its first
    # two windows, the fewest the detector needs); each costs N and the Python around it
    measurements = (cpp + fixed) / every + (2 * max(10.0, w / every) if relax == "auto" else 0)
    check_work(measurements * (n + MEASUREMENT_EVENTS),
               f"{measurements:.3g} measurements of N={n} (collisions_per_particle={cpp:g}"
               + (f" and relax={fixed:g}" if fixed else "") + f" / sample_every={every:g})")
    check_memory(_BYTES_PER_PARTICLE * n + 100.0 * measurements,
                 f"DSMC of N={n} with {measurements:.3g} measurements")
    n_samples = int(math.ceil(cpp / every - 1e-9))
    if n_samples < nb:
        raise ValueError(f"collisions_per_particle={cpp} / sample_every={every} gives "
                         f"{n_samples} samples, fewer than n_batches={nb}")
    if not (average_every == "auto" or (isinstance(average_every, numbers.Real) and not
            isinstance(average_every, bool) and 0 < average_every < math.inf)):
        raise ValueError(f"average_every must be 'auto' or a positive number of collisions per "
                         f"particle, got {average_every!r}")
    ck = Checkpointing.from_arguments(checkpoint, checkpoint_every, resume, max_wall_time)
    if relax == "auto" and w > MAX_AUTO_WINDOW:
        raise ValueError(f"the relaxation window is {w:.3g} collisions per particle (3 "
                         "relaxation times of T; 2/(1-alpha^2) for hard rods), above "
                         f"{MAX_AUTO_WINDOW:g}: relax='auto' would watch up to 20 windows "
                         f"({0.5 * n * 20 * w:.3g} collisions for N={n}).  Pass relax=<collisions "
                         "per particle> to run this near-elastic gas anyway, or use the "
                         "quasi-elastic solutions kinetic_fem.scaling.solve_phi / solve_psi")
    if cpp / nb < w:
        logger.warning("batches of %.3g collisions per particle are shorter than the "
                       "relaxation window %.3g (2/(1-alpha^2) for hard rods): consecutive "
                       "batches are "
                       "correlated and the error bars too small; run longer or use fewer "
                       "batches", cpp / nb, w)
    return {"n": n, "relax": relax if relax == "auto" else float(relax),
            "sample_every": every, "n_batches": nb, "n_samples": n_samples,
            "average_every": average_every if average_every == "auto" else float(average_every),
            "bins": _check_int("bins", bins, 1),
            "window": max(10, int(math.ceil(w / every))), "checkpointing": ck,
            "progress": resolve_progress(progress)}


def _check_sample_every(every: float, n: int, step: float | None) -> None:
    """Refuse a measurement interval the engine would round to nothing.

    The engine advances whole units between measurements: ``round(0.5 * N *
    sample_every)`` collisions (cooling) or ``round(sample_every / step)`` time steps
    (heated).  An interval that rounds to zero was silently made one unit, so the run
    measured more rarely than asked and, counting ``collisions_per_particle /
    sample_every`` intervals, ran far longer; such an interval is refused (the
    bound is exact: Python's ``round`` gives 0 up to and including one half).
    """
    units = 0.5 * n * every if step is None else every / step if step > 0 else math.inf
    if units > 0.5:
        return
    if step is None:
        raise ValueError(
            f"sample_every={every:.6g} collisions per particle is at most half a collision "
            f"between measurements for N={n} (0.5 * N * sample_every = {units:.3g}; the "
            f"run advances whole collisions and would round it up to one): sample_every "
            f"must be > 1/N = {1.0 / n:.6g} (2/N = {2.0 / n:.6g} is one collision per "
            f"measurement)")
    raise ValueError(
        f"sample_every={every:.6g} collisions per particle is at most half a time step "
        f"between measurements (one step of dt is {step:.6g} expected collisions per "
        f"particle; the run advances whole steps and would round it up to one): "
        f"sample_every must be > {0.5 * step:.6g}, or pass a smaller dt")


def _check_dt(dt: float, per_step: float) -> None:
    """Refuse a heated time step with more than :data:`MAX_COLLISIONS_PER_STEP` collisions."""
    if per_step > MAX_COLLISIONS_PER_STEP:
        raise ValueError(f"dt={dt!r} gives {per_step:.3g} expected collisions per particle per "
                         f"step; at most {MAX_COLLISIONS_PER_STEP} are allowed (dt <= "
                         f"{MAX_COLLISIONS_PER_STEP / per_step * dt:.3g})")


def _window(gas: InelasticGas, temperature: float, friction: float = 0.0) -> float:
    """Relaxation window: three linear relaxation times of T, in collisions per particle.

    The Gaussian closure gives the relaxation rate of T over the collision rate
    :math:`\\nu = n\\langle B(g)\\rangle`:
    :math:`\\lambda/\\nu = (2+\\gamma)(1+\\gamma)(1-\\alpha^2)/4 + 2\\xi/\\nu`, with
    :math:`\\gamma` the kernel's local exponent at thermal speeds (that of a power law), so
    :math:`W = \\max(2, 3\\nu/\\lambda)`; hard rods under white noise:
    :math:`2/(1-\\alpha^2)`.
    """
    diss = _dissipation(gas, temperature)
    gamma = gas.kernel.local_exponent(temperature)  # the exponent of a power law
    inverse = diss / 2.0 if gas.kernel.is_hard_rods else (2 + gamma) * (1 + gamma) * diss / 12.0
    if friction > 0.0:
        nu = gas.density * gas.kernel.gaussian_mean(temperature)
        inverse += 2.0 * friction / (3.0 * nu)
    return max(2.0, 1.0 / inverse)


def _dissipation(gas: InelasticGas, temperature: float) -> float:
    """:math:`1-\\alpha^2`, or for a law its average weighted by :math:`|g|^{\\gamma+2}`."""
    law = gas.restitution
    if law.constant is not None:
        return 1.0 - law.constant**2
    return gas.loss_rate(temperature) / (0.25 * gas.density
                                         * gas.kernel.gaussian_mean(temperature, 2.0))


def _model(gas: InelasticGas) -> dict[str, Any]:
    """The model in kernel form (codes and parameters) and the key entries beyond hard rods."""
    law = gas.restitution
    p0, p1 = law.parameters
    kcode, kparam = kernel_model(gas.kernel)
    return {"kcode": kcode, "gamma": kparam, "lcode": law.code,
            "p0": float(p0), "p1": float(p1), "g_limit": float(law.max_speed)}


def _key_model(gas: InelasticGas, friction: float = 0.0) -> dict[str, Any]:
    """Checkpoint-key entries of the model; the paper's model keeps its old entries only."""
    out = {k: val for k, val in gas.as_dict().items() if not (k == "gamma" and val == 1.0)}
    if friction > 0.0:
        out["friction"] = friction
    return out


def _check_spread(v: NDArray[np.float64]) -> None:
    """Initial velocities must differ: a run measures T = var(v) from the start."""
    if not np.ptp(v) > 0:
        raise ValueError("initial_velocities are all equal (temperature 0): no collision can "
                         "happen and the scaled velocities v/sqrt(T) are undefined; give "
                         "velocities with a positive spread")


def _check_range(gas: InelasticGas, v: NDArray[np.float64], where: str) -> None:
    """A restitution law must cover the initial relative speeds."""
    if math.isfinite(gas.restitution.max_speed):
        gas.restitution.check_speed(float(np.ptp(v)), where=where)


def simulate_heated(alpha: float | RestitutionLaw, n_particles: int, *, density: float = 1.0,
                    diffusion: float = 1.0, friction: float = 0.0,
                    kernel: float | CollisionKernel = 1.0,
                    seed: int | np.random.SeedSequence | None = None,
                    collisions_per_particle: float = 100.0, dt: float | None = None,
                    relax: str | float = "auto", sample_every: float = 1.0,
                    average_every: str | float = "auto",
                    n_batches: int = 20, bins: int = 200, c_max: float = 10.0,
                    initial_velocities: ArrayLike | None = None,
                    checkpoint: str | Path | None = None, checkpoint_every: float = 300.0,
                    resume: bool = False, max_wall_time: float | None = None,
                    progress: bool | None = None) -> DSMCRun:
    """DSMC steady state of the gas driven by white noise or a Fokker-Planck bath.

    Parameters
    ----------
    alpha : float or RestitutionLaw
        Restitution coefficient in ``[0, 1]`` (``1`` only with ``friction > 0``) or a
        law of :mod:`kinetic_fem.model`.
    n_particles : int
        Number of particles ``N``, ``2 <= N < 2^32``.
    density, diffusion, friction : float
        :math:`n`, the noise strength :math:`D` and the bath friction :math:`\\xi \\ge 0`
        (``0``: white noise; ``> 0``: Fokker-Planck bath at :math:`T_b = D/\\xi`).
    kernel : float or CollisionKernel
        Collision kernel: ``gamma`` in ``[0, 2]`` of :math:`|g|^\\gamma` (1: hard rods), or
        a kernel object (:class:`~kinetic_fem.model.CollisionKernel`).
    seed : int or SeedSequence, optional
        Root seed; the same seed gives the same run (``None``: fresh entropy, recorded
        in ``info.extra["seed_entropy"]``).
    collisions_per_particle : float
        Length of the averaging after relaxation, in collisions per particle.
    dt : float, optional
        Time step of the splitting (physical time).  Default: 0.05 mean free times
        :math:`1/(n\\langle |g|^\\gamma\\rangle)` at ``T_ref`` and at most 0.05 of the
        bath's relaxation time of T, :math:`1/(2\\xi)` (at 0.05/xi the Strang error of
        a2 was -5e-4 in the Maxwell gas at alpha = 0.9, xi = 1, three standard errors;
        at 0.05/(2 xi) +1e-4 +- 2.6e-4), ``T_ref`` the model's Gaussian-closure steady
        temperature
        (:meth:`kinetic_fem.model.HeatedProblem.temperature_estimate`).  The expected
        number of collisions per particle per step must not exceed
        :data:`MAX_COLLISIONS_PER_STEP`.  Measuring every 0.025 collisions per particle or
        more often may need a smaller ``dt`` (``sample_every`` below).
    relax : "auto" or float
        Start of averaging: the detector of the module docstring, or a fixed number
        of collisions per particle.
    sample_every : float
        Collisions per particle between measurements (time series and histogram)
        until averaging starts.  The run advances whole time steps between
        measurements (cooling: whole collisions), so ``sample_every`` must exceed half
        a step, ``0.5 * dt`` times the collision rate at ``T_ref`` (at most 0.025 at the
        default ``dt``; cooling: half a collision, ``sample_every > 1/N``); a smaller
        value is refused (it was silently rounded up to one step or collision).
    average_every : "auto" or float
        Collisions per particle between measurements while averaging (a multiple of
        ``sample_every``; batches and run length count time).  "auto": half the
        correlation time of ``a2`` measured over the first batch (in
        ``info.extra["a2_correlation_time"]``; N = 25000: ~2 heated, 10-20 cooling
        at alpha = 0.9), see ``particles._dsmc_engine.Engine.cadence``.
    n_batches, bins, c_max : int, int, float
        Consecutive batches for error bars (each should be longer than the correlation
        time, about ``2/(1-alpha^2)`` collisions per particle near ``alpha = 1``, where
        the shape changes slowly; a warning is logged otherwise); histogram of ``v``
        with ``bins`` bins on :math:`|v| \\le c_{max}\\sqrt{T_{ref}}` (the same edges
        for every seed, so replicas merge).  Moments use every sample.
    initial_velocities : array_like, shape (N,), optional
        Initial state (finite); default a Gaussian at ``T_ref`` (for hard rods with
        constant ``alpha`` under white noise the first-order Sonine distribution
        :math:`\\Phi(c)(1 + a_2 S_2)`, close to the steady state, so that the slow shape
        relaxation near ``alpha = 1``, ~``1/(1-alpha)`` collisions per particle, starts
        near its end).
    checkpoint, checkpoint_every, resume : path, float, bool
        Write the state every ``checkpoint_every`` seconds and at the end; with
        ``resume=True`` continue from the file if it exists (bit-identical).
    max_wall_time : float, optional
        Stop after this many seconds (checkpoint written; ``info.message`` says so).
    progress : bool, optional
        tqdm progress bar over the averaging samples; default (None): shown when the
        session is interactive (a terminal or a notebook).

    Returns
    -------
    DSMCRun
        ``.distribution`` is P(v) in the centre-of-mass frame.

    Raises
    ------
    TypeError, ValueError
        For invalid parameters (``N < 2``, gamma outside [0, 2], ``friction < 0``,
        too large ``dt``, non-finite initial state, relative speeds beyond the range
        of a restitution law).

    Examples
    --------
    >>> run = simulate_heated(0.6, 2000, seed=1, collisions_per_particle=40)
    >>> abs(run.a2 - 0.03) < 0.02, run.info.converged
    (True, True)
    >>> abs(run.dissipation_rate / run.injection_rate - 1) < 0.03
    True
    >>> maxwell = simulate_heated(0.6, 2000, kernel=0.0, seed=1, collisions_per_particle=40)
    >>> abs(maxwell.temperature / (4 / (1 - 0.6**2)) - 1) < 0.05  # T = 4D/(n(1-alpha^2))
    True
    """
    problem = HeatedProblem.from_parameters(alpha, density=density, diffusion=diffusion,
                                            friction=friction, kernel=kernel)
    gas = problem.gas
    t_ref = problem.temperature_estimate()
    rate = gas.density * gas.kernel.gaussian_mean(t_ref)  # collisions per particle and time
    xi = problem.friction
    dt = 0.05 / max(rate, 2.0 * xi) if dt is None else check_positive("dt", dt)
    _check_dt(dt, dt * rate)  # at T_ref; at the initial state's T once it is drawn
    o = _common(n_particles, collisions_per_particle, relax, sample_every, average_every,
                n_batches, bins, c_max, checkpoint, checkpoint_every, resume, max_wall_time,
                progress, _window(gas, t_ref, problem.friction), step=dt * rate)
    c_max = check_positive("c_max", c_max)
    init_seq, run_seq, entropy = _seeds(seed)
    paper = gas.kernel.is_hard_rods and gas.restitution.constant is not None and \
        problem.friction == 0
    a2 = float(a2_first_order(gas.alpha)) if paper else 0.0
    v = initial_velocities_of(initial_velocities, o["n"], t_ref, init_seq, a2=a2)
    _check_spread(v)
    _check_range(gas, v, "the initial velocities")
    t_max = max(t_ref, float(np.mean(v**2)))
    _check_dt(dt, dt * gas.density * gas.kernel.gaussian_mean(t_max))
    if xi > 0.0:  # exact Ornstein-Uhlenbeck flow over dt and dt/2
        t_bath = problem.thermostat.bath_temperature
        kicks: dict[str, Any] = {
            "decay": math.exp(-xi * dt), "amp": math.sqrt(-t_bath * math.expm1(-2 * xi * dt)),
            "half_decay": math.exp(-0.5 * xi * dt),
            "half_amp": math.sqrt(-t_bath * math.expm1(-xi * dt))}
    else:
        amp = math.sqrt(2.0 * problem.diffusion * dt)
        kicks = {"decay": 1.0, "amp": amp, "half_decay": 1.0, "half_amp": amp / math.sqrt(2.0)}
    half = c_max * math.sqrt(t_ref)
    # steps per measurement: sample_every is more than half a step (_check_sample_every)
    per_sample = o["sample_every"] / (dt * rate) if dt * rate > 0 else math.inf
    check_work(o["n"] * (o["n_samples"] + 20 * o["window"]) * (per_sample + 0.5),
               f"dt={dt:g} (time steps times particles)")
    steps = max(1, int(round(per_sample)))
    key = {"kind": "heated", **_key_model(gas, xi), "diffusion": problem.diffusion,
           "n": o["n"], "dt": dt, "steps": steps, "samples": o["n_samples"],
           "batches": o["n_batches"], "bins": o["bins"], "lo": -half, "relax": o["relax"],
           "average_every": o["average_every"], "seed": entropy}
    opts = DSMCOptions(kind="heated", lo=-half, hi=half, entropy=entropy, key=key, dt=dt,
                       steps=steps, **kicks, **_model(gas), **o)
    o["checkpointing"].guard("dsmc", ("key", key))
    return Engine(problem, v, run_seq, opts).run()


def simulate_cooling(alpha: float | RestitutionLaw, n_particles: int, *, density: float = 1.0,
                     kernel: float | CollisionKernel = 1.0,
                     seed: int | np.random.SeedSequence | None = None,
                     collisions_per_particle: float = 100.0, relax: str | float = "auto",
                     sample_every: float = 1.0, average_every: str | float = "auto",
                     n_batches: int = 20, bins: int = 240,
                     c_max: float = 6.0, initial_velocities: ArrayLike | None = None,
                     checkpoint: str | Path | None = None, checkpoint_every: float = 300.0,
                     resume: bool = False, max_wall_time: float | None = None,
                     progress: bool | None = None) -> DSMCRun:
    """DSMC of the freely cooling gas: Haff's law and the homogeneous cooling state.

    Parameters are those of :func:`simulate_heated` without ``diffusion``, ``friction``
    and ``dt``; the histogram is of the scaled velocity ``c = v/sqrt(T)`` on
    ``|c| <= c_max``, and the default initial state is a unit Gaussian (physical
    units: a restitution law is evaluated at the physical relative speed, and the
    initial extent of the velocities must lie within its range).
    ``series["log_temperature"]`` and ``series["log_t"]`` give the physical
    :math:`T(t)` without under- or overflow; :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`
    (Haff for hard rods: :math:`T \\sim t^{-2}`, compare
    :func:`kinetic_fem.sonine.haff_temperature`; Maxwell: exponential decay), with
    :math:`\\zeta` measured by :meth:`DSMCRun.cooling_rate`.

    Parameters
    ----------
    alpha : float or RestitutionLaw
        Restitution coefficient in ``[0, 1)`` or a law of :mod:`kinetic_fem.model`.
    n_particles : int
        Number of particles ``N``, ``2 <= N < 2^32``.
    density : float
        Number density ``n``.
    kernel : float or CollisionKernel
        Collision kernel :math:`|g|^\\gamma`, ``gamma`` in ``[0, 2]`` (a homogeneous kernel:
        other families have no scaled cooling state and are refused).
    seed : int or SeedSequence, optional
        Root seed (``None``: fresh entropy, recorded in the result).
    collisions_per_particle : float
        Length of the averaging after relaxation, in collisions per particle.
    relax, sample_every, average_every, n_batches, bins, c_max
        As in :func:`simulate_heated`; ``c_max`` bounds the histogram of ``c``.
    initial_velocities : array_like, shape (N,), optional
        Initial state (finite); default a unit Gaussian.
    checkpoint, checkpoint_every, resume, max_wall_time, progress
        As in :func:`simulate_heated`.

    Returns
    -------
    DSMCRun
        ``.distribution`` is the time-averaged scaled distribution f(c).

    Examples
    --------
    >>> run = simulate_cooling(0.9, 2000, seed=1, collisions_per_particle=40)
    >>> bool(run.a2 < -0.2)  # two humps at c = +-1
    True
    >>> s = run.series
    >>> late = s["collisions_per_particle"] > run.relaxed_at
    >>> slope = np.polyfit(s["log_t"][late], s["log_temperature"][late], 1)[0]
    >>> bool(abs(slope + 2) < 0.05)  # Haff law T ~ t^-2
    True
    """
    problem = CoolingProblem.from_parameters(alpha, density=density, kernel=kernel)
    gas = problem.gas
    o = _common(n_particles, collisions_per_particle, relax, sample_every, average_every,
                n_batches, bins, c_max, checkpoint, checkpoint_every, resume, max_wall_time,
                progress, _window(gas, 1.0))
    c_max = check_positive("c_max", c_max)
    init_seq, run_seq, entropy = _seeds(seed)
    v = initial_velocities_of(initial_velocities, o["n"], 1.0, init_seq)
    _check_spread(v)
    _check_range(gas, v, "the initial velocities")
    key = {"kind": "cooling", **_key_model(gas), "n": o["n"], "every": o["sample_every"],
           "samples": o["n_samples"], "batches": o["n_batches"], "bins": o["bins"],
           "lo": -c_max, "relax": o["relax"], "average_every": o["average_every"],
           "seed": entropy}
    opts = DSMCOptions(kind="cooling", lo=-c_max, hi=c_max, entropy=entropy, key=key,
                       **_model(gas), **o)
    o["checkpointing"].guard("dsmc", ("key", key))
    return Engine(problem, v, run_seq, opts).run()


def combine_runs(runs: Sequence[DSMCRun]) -> VelocityDistribution:
    """Merge independent replicas (same parameters) into one distribution.

    Every batch of every replica is kept, so errors come from the spread over all of
    them.  Replicas run in parallel with :func:`particles.sampling.run_replicas`::

        seeds = spawn_seeds(1, 4)
        runs = run_replicas(simulate_heated, seeds, alpha=0.6, n_particles=25_000)
        dist = combine_runs(runs)

    Parameters
    ----------
    runs : sequence of DSMCRun
        Replicas with the same parameters and histogram edges.

    Returns
    -------
    VelocityDistribution
        Errors from the spread over every batch of every replica.

    Raises
    ------
    ValueError
        If the runs differ in parameters or histogram edges, or none is given.
    """
    if not runs:
        raise ValueError("combine_runs needs at least one run")
    edges = runs[0].edges
    for r in runs[1:]:
        if r.edges.shape != edges.shape or not np.array_equal(r.edges, edges):
            raise ValueError("runs have different histogram edges; use the same parameters")
    counts = np.concatenate([r.counts[r.power_sums[:, 0] > 0] for r in runs])
    sums = np.concatenate([r.power_sums[r.power_sums[:, 0] > 0] for r in runs])
    first = runs[0].distribution
    return VelocityDistribution.from_batches(edges, counts, sums, method="dsmc",
                                             params=first.params, info=first.info)
