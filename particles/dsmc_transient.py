"""DSMC of the heated gas under a protocol: ensembles of replicas, T(t) and a2(t).

The transient counterpart of :func:`particles.dsmc.simulate_heated`: ``N`` particles
(velocities only) follow

.. math::

    \\partial_t P = Q_{\\alpha(t)}[P] + \\partial_v(\\xi(t)\\, v P) + D(t)\\,\\partial_v^2 P

from an initial state to the requested output times, with the time dependence of
:math:`D`, :math:`\\xi` and the restitution given by a
:class:`kinetic_fem.model.protocol.Protocol` (the same object
:func:`kinetic_fem.evolve_heated` takes).  ``replicas`` independent runs (their own
seeds, spawned from one ``numpy.random.SeedSequence``) give ensemble means of
:math:`T(t)` and :math:`a_2(t)` with standard errors from the spread of the replicas
(:math:`s/\\sqrt R`), returned as one frozen :class:`ProtocolRun`.

Scheme (as :mod:`particles.dsmc`): Strang splitting
:math:`K(h/2)\\,C(h)\\,K(h/2)` of collisions ``C`` (thinning with the majorant
:math:`g_{max} = \\max v - \\min v`, candidates at rate :math:`nN g_{max}^\\gamma/2`,
the kernels :func:`particles._dsmc_kernels.collide_model`) and the thermostat ``K``:
the Ornstein-Uhlenbeck update

.. math::

    v \\to d\\,v + b\\,\\eta, \\qquad d = e^{-\\xi h'}, \\qquad
    b^2 = \\frac{D}{\\xi}\\big(1 - e^{-2\\xi h'}\\big)\\ (\\to 2Dh' \\text{ as } \\xi \\to 0),

over a half step :math:`h' = h/2` with :math:`D, \\xi` at the half step's midpoint
(exact for piecewise-constant protocols, second order for ramps and callables, like
the splitting), :math:`\\eta` standard normals (ziggurat of :mod:`particles.rng`).
Consecutive half kicks merge exactly (:math:`d = d_1 d_2`,
:math:`b^2 = d_2^2 b_1^2 + b_2^2`).  The time axis is cut at every output time and
every breakpoint of the protocol (:meth:`Protocol.breakpoints`: steps of :math:`D`,
:math:`\\xi`, restitution changes), each piece into equal steps no longer than ``dt``;
a restitution change therefore acts exactly at its time.  Measurements are taken
after the last half kick of a piece, in the centre-of-mass frame:
:math:`T = \\overline{(v-\\bar v)^2}`, :math:`a_2 = \\overline{(v-\\bar v)^4}/(3T^2) - 1`.

Free cooling (``diffusion=0``, no friction, a protocol of restitution changes only)
runs the same scheme without kicks: any restitution law, any kernel, from the initial
state (default a Gaussian at :math:`T_0 = 1`), the counterpart of
:func:`kinetic_fem.evolve_cooling`.

Finite-``N`` effects (of order :math:`1/N`: the kicks' centre-of-mass part, the
ratio estimator of :math:`a_2`, the expected rather than Poisson candidate count) are
not removed; they are small against the replica error bars as long as
``replicas << n_particles``.
"""

from __future__ import annotations

import logging
import math
import numbers
import time
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from kinetic_fem.distribution import RunInfo, VelocityDistribution
from kinetic_fem.evolve import check_times
from kinetic_fem.model import (
    CollisionKernel,
    HeatedProblem,
    InelasticGas,
    RestitutionLaw,
    check_positive,
)
from kinetic_fem.model.protocol import Protocol

from ._dsmc_kernels import collide_model
from ._dsmc_model import kernel_majorant, kernel_model
from ._jit import jit
from .rng import normal_slow, xoshiro, ziggurat_tables

__all__ = ["ProtocolRun", "simulate_protocol", "protocol_kicks"]

logger = logging.getLogger(__name__)

DT_FRACTION = 0.05
"""Default step: this fraction of the shortest of the mean free time at the highest
temperature expected and the bath's relaxation time :math:`1/(2\\xi)`."""


@dataclass(frozen=True)
class ProtocolRun:
    """Ensemble averages of a DSMC run under a protocol.

    Attributes
    ----------
    times : ndarray, shape (n_t,)
        Output times.
    temperature, temperature_error : ndarray, shape (n_t,)
        Ensemble mean of :math:`T(t)` and its standard error (replica spread).
    a2, a2_error : ndarray, shape (n_t,)
        Ensemble mean of :math:`a_2(t)` and its standard error.
    temperature_replicas, a2_replicas : ndarray, shape (replicas, n_t)
        The values of each replica.
    n_particles, replicas : int
    params : dict
        Model, protocol description, step and seed.
    info : RunInfo
        Wall time, collisions per particle and steps in ``extra``.
    """

    times: NDArray[np.float64]
    temperature: NDArray[np.float64]
    temperature_error: NDArray[np.float64]
    a2: NDArray[np.float64]
    a2_error: NDArray[np.float64]
    temperature_replicas: NDArray[np.float64]
    a2_replicas: NDArray[np.float64]
    n_particles: int
    replicas: int
    params: dict[str, Any] = field(default_factory=dict)
    info: RunInfo = field(default_factory=RunInfo)

    def deviation(self, temperature: ArrayLike, a2: ArrayLike
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Deviations of reference curves in units of the standard errors.

        Parameters
        ----------
        temperature, a2 : array_like, shape (n_t,)
            Reference :math:`T(t_i)` and :math:`a_2(t_i)` (e.g. of
            :func:`kinetic_fem.evolve_heated`).

        Returns
        -------
        (z_T, z_a2) : ndarrays, shape (n_t,)
            ``(self.temperature - temperature) / self.temperature_error`` and the same
            for ``a2`` (0 where the error is 0, e.g. a deterministic start at t = 0
            compared with itself).
        """
        out = []
        for mean, err, ref in ((self.temperature, self.temperature_error, temperature),
                               (self.a2, self.a2_error, a2)):
            ref = np.asarray(ref, dtype=float)
            if ref.shape != self.times.shape:
                raise ValueError(f"reference has shape {ref.shape}; expected {self.times.shape}")
            diff = mean - ref
            with np.errstate(divide="ignore", invalid="ignore"):
                out.append(np.where(err > 0, diff / np.where(err > 0, err, 1.0), 0.0))
        return out[0], out[1]


# ---------------------------------------------------------------------------- kernel
@jit
def _kick(v, decay, amp, s, ki, wi, fi):  # pragma: no cover - compiled
    """``v = decay v + amp eta`` (standard normals ``eta``); returns ``(min, max)``."""
    lo, hi = np.inf, -np.inf
    if amp == 0.0 and decay == 1.0:   # free cooling: no kick, no random numbers
        return v.min(), v.max()
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
    for k in range(v.shape[0]):
        r, s0, s1, s2, s3 = xoshiro(s0, s1, s2, s3)
        layer_sign = r & np.uint64(0x1FF)
        idx = int(layer_sign & np.uint64(0xFF))
        rabs = (r >> np.uint64(9)) & np.uint64(0x000FFFFFFFFFFFFF)
        x = float(np.int64(rabs)) * wi[layer_sign]
        if rabs >= ki[idx]:
            s[0], s[1], s[2], s[3] = s0, s1, s2, s3
            x = normal_slow(s, idx, x, ki, wi, fi)
            s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
        y = decay * v[k] + amp * x
        v[k] = y
        lo = min(lo, y)
        hi = max(hi, y)
    s[0], s[1], s[2], s[3] = s0, s1, s2, s3
    return lo, hi


@jit
def _segment(v, decay, amp, h, rate, kcode, gamma, lcode, p0, p1, g_limit, debt, s, ki, wi,
             fi):  # pragma: no cover - compiled
    """``len(decay) - 1`` Strang steps of length ``h`` with the kicks ``(decay, amp)[k]``.

    Kick ``k`` precedes step ``k`` (kick 0 the first half kick, the last one the final
    half kick, the others two merged halves).  Returns ``(accepted, debt, steps_done,
    g_max)``; ``steps_done`` falls short if ``g_max`` exceeds ``g_limit``.
    """
    n_steps = decay.shape[0] - 1
    accepted = 0
    lo, hi = _kick(v, decay[0], amp[0], s, ki, wi, fi)
    for step in range(n_steps):
        g_max = hi - lo
        if g_max > g_limit:
            return accepted, debt, step, g_max
        x = debt + h * rate * kernel_majorant(kcode, gamma, g_max)
        m = int(math.floor(x))
        debt = x - m
        a, _ = collide_model(v, m, kcode, gamma, lcode, p0, p1, g_max, 1.0, s)
        accepted += a
        lo, hi = _kick(v, decay[step + 1], amp[step + 1], s, ki, wi, fi)
    return accepted, debt, n_steps, hi - lo


# ---------------------------------------------------------------------------- schedule
def _half_kick(protocol: Protocol, t_mid: float, h: float, d0: float, xi0: float
               ) -> tuple[float, float]:
    """``(decay, amp^2)`` of the OU flow over ``h`` with D, xi at ``t_mid``."""
    d = protocol.diffusion_at(t_mid, d0)
    xi = protocol.friction_at(t_mid, xi0)
    if xi == 0.0:
        return 1.0, 2.0 * d * h
    return math.exp(-xi * h), -d / xi * math.expm1(-2.0 * xi * h)


def protocol_kicks(protocol: Protocol, start: float, stop: float, n_steps: int,
                   diffusion: float, friction: float
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The ``n_steps + 1`` merged thermostat kicks of ``n_steps`` Strang steps.

    Parameters
    ----------
    protocol : Protocol
        Time dependence of :math:`D` and :math:`\\xi`.
    start, stop : float
        The piece of the time axis (no breakpoint inside).
    n_steps : int
        Equal steps ``h = (stop - start) / n_steps``.
    diffusion, friction : float
        Values where the protocol leaves :math:`D`, :math:`\\xi` alone.

    Returns
    -------
    (decay, amp) : ndarrays, shape (n_steps + 1,)
        Kick ``k``: :math:`v \\to d_k v + b_k \\eta` (module docstring).

    Examples
    --------
    >>> d, b = protocol_kicks(Protocol(), 0.0, 1.0, 2, 1.0, 0.0)
    >>> d.tolist(), (b**2).round(12).tolist()  # 2 D h' over h' = 0.25, 0.5, 0.25
    ([1.0, 1.0, 1.0], [0.5, 1.0, 0.5])
    """
    h = (stop - start) / n_steps
    halves = [_half_kick(protocol, start + (2 * k + 1) * 0.25 * h, 0.5 * h, diffusion, friction)
              for k in range(2 * n_steps)]
    decay = np.empty(n_steps + 1)
    var = np.empty(n_steps + 1)
    decay[0], var[0] = halves[0]
    for k in range(1, n_steps):
        d1, v1 = halves[2 * k - 1]
        d2, v2 = halves[2 * k]
        decay[k] = d1 * d2
        var[k] = d2 * d2 * v1 + v2
    decay[n_steps], var[n_steps] = halves[-1]
    return decay, np.sqrt(var)


def _pieces(times: NDArray[np.float64], protocol: Protocol) -> list[tuple[float, float, bool]]:
    """``(start, stop, measure_at_stop)`` from 0 through every output time and breakpoint."""
    cuts = sorted((set(times.tolist()) | set(protocol.breakpoints(float(times[-1])))) - {0.0})
    out, start = [], 0.0
    output = set(times.tolist())
    for stop in cuts:
        out.append((start, stop, stop in output))
        start = stop
    return out


def _sample_initial(n: int, temperature: float, a2: float, initial: VelocityDistribution | None,
                    rng: np.random.Generator) -> NDArray[np.float64]:
    """``n`` velocities: from ``initial`` (inverse CDF) or :math:`\\Phi(c)(1 + a_2 S_2)`."""
    if initial is not None:
        v = np.asarray(initial.v, dtype=float)
        p = np.maximum(np.asarray(initial.values, dtype=float), 0.0)
        cdf = np.concatenate([[0.0], np.cumsum(0.5 * (p[1:] + p[:-1]) * np.diff(v))])
        return np.interp(rng.random(n) * cdf[-1], cdf, v)
    weight = lambda c2: np.maximum(1 + a2 * (c2**2 / 8 - 3 * c2 / 4 + 3 / 8), 0.0)  # noqa: E731
    top = float(weight(np.linspace(0.0, 6.0, 601) ** 2).max())
    out = np.empty(0)
    while out.size < n:
        c = rng.normal(size=2 * (n - out.size) + 16)
        keep = c[(np.abs(c) < 6) & (rng.random(c.size) * top < weight(c * c))]
        out = np.concatenate([out, keep])
    return out[:n] * math.sqrt(temperature)


def _observe(v: NDArray[np.float64]) -> tuple[float, float]:
    c = v - v.mean()
    c2 = c * c
    t = float(c2.mean())
    return t, float((c2 * c2).mean() / (3.0 * t * t) - 1.0)


# ---------------------------------------------------------------------------- driver
def _replica(problem: HeatedProblem | _FreeCooling, protocol: Protocol, pieces: list,
             steps: list[int], n: int, temperature: float, a2: float,
             initial: VelocityDistribution | None, seed: np.random.SeedSequence,
             measure_zero: bool
             ) -> tuple[NDArray[np.float64], NDArray[np.float64], int]:
    """One replica: ``(T at the outputs, a2 at the outputs, collisions)``."""
    init_seq, run_seq = seed.spawn(2)
    v = _sample_initial(n, temperature, a2, initial, np.random.default_rng(init_seq))
    v -= v.mean()
    state = np.random.default_rng(run_seq).integers(1, 2**63, size=4, dtype=np.uint64)
    ki, wi, fi = ziggurat_tables()
    gas = problem.gas
    kcode, gamma = kernel_model(gas.kernel)
    rate = 0.5 * gas.density * n
    temps, a2s = [], []
    if measure_zero:
        t0, b0 = _observe(v)
        temps.append(t0)
        a2s.append(b0)
    debt = 0.0
    collisions = 0
    for (start, stop, measure), m in zip(pieces, steps, strict=True):
        law = protocol.restitution_at(start, gas.restitution)
        p0, p1 = law.parameters
        if problem.diffusion == 0.0:   # free cooling
            decay, amp = np.ones(m + 1), np.zeros(m + 1)
        else:
            decay, amp = protocol_kicks(protocol, start, stop, m, problem.diffusion,
                                        problem.friction)
        acc, debt, done, g_max = _segment(v, decay, amp, (stop - start) / m, rate, kcode,
                                          gamma, law.code, float(p0), float(p1),
                                          float(law.max_speed), debt, state, ki, wi, fi)
        collisions += acc
        if done < m:
            law.check_speed(g_max, where=f"the DSMC at t={start + done * (stop - start) / m:g}")
        v -= v.mean()
        if measure:
            tk, bk = _observe(v)
            temps.append(tk)
            a2s.append(bk)
    return np.array(temps), np.array(a2s), collisions


def _check_int(name: str, value: object, lo: int) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or int(value) < lo:
        raise ValueError(f"{name} must be an integer >= {lo}, got {value!r}")
    return int(value)


@dataclass(frozen=True)
class _FreeCooling:
    """The gas without a thermostat (``diffusion=0``): what :func:`_replica` reads."""
    gas: InelasticGas
    diffusion: float = 0.0
    friction: float = 0.0


def _default_dt(problem: HeatedProblem | _FreeCooling, protocol: Protocol,
                times: NDArray[np.float64], temperature: float) -> float:
    """:data:`DT_FRACTION` of the shortest mean free time and bath time along the protocol."""
    probe = np.union1d(times, protocol.breakpoints(float(times[-1])))
    t_hi, xi_hi = temperature, problem.friction
    for t in probe if problem.diffusion > 0.0 else ():   # free cooling: T only falls
        law = protocol.restitution_at(float(t), problem.gas.restitution)
        d = protocol.diffusion_at(float(t), problem.diffusion)
        xi = protocol.friction_at(float(t), problem.friction)
        xi_hi = max(xi_hi, xi)
        local = HeatedProblem.from_parameters(law, density=problem.gas.density, diffusion=d,
                                              friction=xi, kernel=problem.gas.kernel)
        t_hi = max(t_hi, local.temperature_estimate())
    nu = problem.gas.density * problem.gas.kernel.gaussian_mean(t_hi)
    return DT_FRACTION / max(nu, 2.0 * xi_hi)


def simulate_protocol(alpha: float | RestitutionLaw, n_particles: int, *, times: ArrayLike,
                      protocol: Protocol | None = None, density: float = 1.0,
                      diffusion: float = 1.0, friction: float = 0.0,
                      kernel: float | CollisionKernel = 1.0,
                      initial_temperature: float | None = None, initial_a2: float = 0.0,
                      initial: VelocityDistribution | None = None, replicas: int = 16,
                      seed: int | np.random.SeedSequence | None = None,
                      dt: float | None = None, executor: Executor | None = None
                      ) -> ProtocolRun:
    """Ensemble of DSMC runs of the heated gas under a protocol.

    Parameters
    ----------
    alpha : float or RestitutionLaw
        Restitution at ``t = 0`` (changes: ``protocol.restitution``).
    n_particles : int
        Particles per replica, ``>= 2``.
    times : array_like, shape (n_t,)
        Output times, strictly increasing, ``>= 0`` (``0`` measures the initial state).
    protocol : Protocol, optional
        Time dependence of :math:`D`, :math:`\\xi` and the restitution (as
        :func:`kinetic_fem.evolve_heated`).
    density, diffusion, friction : float
        :math:`n`, and :math:`D`, :math:`\\xi` where the protocol leaves them alone.
        ``diffusion=0`` (with ``friction=0`` and a protocol of restitution changes only)
        is free cooling, as :func:`kinetic_fem.evolve_cooling`.
    kernel : float or CollisionKernel
        ``gamma`` of :math:`|g|^\\gamma` (0 Maxwell, 1 hard rods) or a kernel object.
    initial_temperature : float, optional
        Temperature of the initial state (default: the Gaussian-closure steady
        temperature of the parameters at ``t = 0``; free cooling: 1).
    initial_a2 : float
        Initial state :math:`\\Phi(c)(1 + a_2 S_2(c^2))_+` on ``|c| < 6`` (0: Gaussian;
        the cut and the clipping move the sampled :math:`a_2` slightly for
        ``|a2| > 0.5``).
    initial : VelocityDistribution, optional
        Sample the initial state from this distribution instead (inverse CDF of its
        nodal values).
    replicas : int
        Independent runs, ``>= 2`` (error bars from their spread).
    seed : int or SeedSequence, optional
        Root seed; replica ``r`` uses its ``r``-th spawned child.
    dt : float, optional
        Largest time step (default :data:`DT_FRACTION` of the shortest mean free time
        and bath time along the protocol).
    executor : concurrent.futures.Executor, optional
        Runs the replicas (default: one after the other in this process).

    Returns
    -------
    ProtocolRun

    Raises
    ------
    ValueError, TypeError
        For invalid parameters, protocols or times, relative speeds beyond the range of
        a restitution law, or free cooling (``diffusion=0``) with a thermostat protocol.

    Examples
    --------
    >>> run = simulate_protocol(0.5, 500, kernel=0.0, times=[0.0, 2.0], replicas=4,
    ...                         seed=1, initial_temperature=1.0)
    >>> bool(run.temperature[1] > 1.5), run.temperature_replicas.shape
    (True, (4, 2))
    """
    if protocol is None:
        protocol = Protocol()
    if not isinstance(protocol, Protocol):
        raise TypeError(f"protocol must be a Protocol, got {type(protocol).__name__}")
    problem: HeatedProblem | _FreeCooling
    if diffusion == 0.0 and not isinstance(diffusion, bool):
        if friction != 0.0 or protocol.diffusion is not None or protocol.friction is not None:
            raise ValueError("diffusion=0 is free cooling: friction and the protocol's D(t), "
                             "xi(t) must be left alone (a driven gas needs diffusion > 0)")
        problem = _FreeCooling(InelasticGas(alpha, density, kernel))
        if initial is None and initial_temperature is None:
            initial_temperature = 1.0
    else:
        problem = HeatedProblem.from_parameters(alpha, density=density, diffusion=diffusion,
                                                friction=friction, kernel=kernel)
    n = _check_int("n_particles", n_particles, 2)
    n_rep = _check_int("replicas", replicas, 2)
    t_out = check_times(times)
    if initial is not None and initial_temperature is not None:
        raise ValueError("give either initial (a VelocityDistribution) or "
                         "initial_temperature, not both")
    if initial is not None and not isinstance(initial, VelocityDistribution):
        raise TypeError(f"initial must be a VelocityDistribution, got {type(initial).__name__}")
    if initial is not None:
        temperature = float(initial.temperature)
    elif initial_temperature is None:
        assert isinstance(problem, HeatedProblem)  # free cooling defaults to 1 above
        temperature = problem.temperature_estimate()
    else:
        temperature = check_positive("initial_temperature", initial_temperature)
    a2 = float(initial_a2)
    if not (math.isfinite(a2) and -1.0 <= a2 <= 4.0):
        raise ValueError(f"initial_a2={initial_a2!r} is not allowed; it must lie in [-1, 4]")
    h_max = (_default_dt(problem, protocol, t_out, temperature) if dt is None
             else check_positive("dt", dt))
    pieces = _pieces(t_out, protocol)
    steps = [max(1, math.ceil((b - a) / h_max - 1e-9)) for a, b, _ in pieces]
    root = seed if isinstance(seed, np.random.SeedSequence) else np.random.SeedSequence(seed)
    seeds = root.spawn(n_rep)
    args = (problem, protocol, pieces, steps, n, temperature, a2, initial)
    zero = bool(t_out[0] == 0.0)
    start = time.perf_counter()
    if executor is None:
        results = [_replica(*args, s, zero) for s in seeds]
    else:
        futures = [executor.submit(_replica, *args, s, zero) for s in seeds]
        results = [f.result() for f in futures]
    wall = time.perf_counter() - start
    temps = np.array([r[0] for r in results])
    a2s = np.array([r[1] for r in results])
    collisions = sum(r[2] for r in results)
    root_scale = 1.0 / math.sqrt(n_rep)
    logger.info("DSMC protocol: %d replicas x %d particles, %d steps, %.2f s", n_rep, n,
                sum(steps), wall)
    params = {"alpha": repr(problem.gas.restitution),
              **{k: v for k, v in problem.gas.as_dict().items() if k in ("gamma", "kernel")},
              "density": problem.gas.density, "diffusion": problem.diffusion,
              "friction": problem.friction, "protocol": repr(protocol), "dt": h_max,
              "initial_temperature": temperature, "initial_a2": a2,
              "seed": f"{root.entropy}:{tuple(root.spawn_key)}"}
    info = RunInfo(converged=True, iterations=sum(steps), wall_time=wall,
                   message=f"{n_rep} replicas of {n} particles",
                   extra={"collisions_per_particle": 2.0 * collisions / (n * n_rep),
                          "steps": sum(steps)})
    return ProtocolRun(t_out, temps.mean(axis=0), temps.std(axis=0, ddof=1) * root_scale,
                       a2s.mean(axis=0), a2s.std(axis=0, ddof=1) * root_scale, temps, a2s,
                       n, n_rep, params, info)
