"""Engine of the event-driven MD (see :mod:`particles.md`): typed options, event loop.

The engine holds the arrays of :mod:`particles._md_kernels` and advances them between
stop points (records, samples, snapshots, checkpoints) measured in collisions or time;
:mod:`particles._md_run` drives it and turns the samples into a
:class:`~kinetic_fem.VelocityDistribution`.  It takes typed options
(:class:`EngineOptions`, :class:`Kicks`), built by :mod:`particles.md` from the model
(:mod:`kinetic_fem.model`: restitution law and thermostat).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from typing import Mapping, NoReturn

import numba
import numpy as np
from numpy.typing import NDArray

from kinetic_fem.model import RestitutionLaw, Thermostat, ThresholdRestitution

from . import _md_kernels as K

__all__ = ["InelasticCollapseError", "Kicks", "EngineOptions", "MDEngine", "MixtureRods"]

logger = logging.getLogger(__name__)

_JIT = not numba.config.DISABLE_JIT  # type: ignore[attr-defined]


class InelasticCollapseError(RuntimeError):
    """The collision count diverges in finite time (inelastic collapse)."""


@dataclass(frozen=True)
class Kicks:
    """Random kicks of every rod every ``interval``: :math:`v \\to d\\,v + b\\,\\xi`.

    ``interval = inf`` (the default) is free cooling.  Build them from a thermostat
    with :meth:`from_thermostat`.

    Attributes
    ----------
    interval : float
        :math:`\\Delta t_k` (time).
    decay : float
        :math:`d`: 1 for white noise, :math:`e^{-\\xi\\Delta t_k}` for a bath.
    amplitude : float
        :math:`b` (velocity).
    """

    interval: float = math.inf
    decay: float = 1.0
    amplitude: float = 0.0

    @classmethod
    def from_thermostat(cls, thermostat: Thermostat, interval: float) -> Kicks:
        """The kicks of ``thermostat`` over ``interval``.

        White noise of strength :math:`D`: :math:`d = 1`,
        :math:`b = \\sqrt{2D\\Delta t_k}` (the Euler-Maruyama step of
        :math:`D\\partial_v^2 P`).  A Fokker-Planck bath (friction :math:`\\xi`, bath
        temperature :math:`T_b = D/\\xi`): the exact Ornstein-Uhlenbeck transition
        over :math:`\\Delta t_k`, :math:`d = e^{-\\xi\\Delta t_k}`,
        :math:`b = \\sqrt{T_b(1 - e^{-2\\xi\\Delta t_k})}`.

        Examples
        --------
        >>> from kinetic_fem.model import FokkerPlanckBath, WhiteNoise
        >>> Kicks.from_thermostat(WhiteNoise(2.0), 0.25)
        Kicks(interval=0.25, decay=1.0, amplitude=1.0)
        >>> k = Kicks.from_thermostat(FokkerPlanckBath(1.0, 2.0), 1e9)  # T_b = 2
        >>> k.decay, round(k.amplitude**2, 12)
        (0.0, 2.0)
        """
        xi, d = thermostat.friction, thermostat.diffusion
        if xi > 0.0:
            return cls(interval, math.exp(-xi * interval),
                       math.sqrt(d / xi * -math.expm1(-2.0 * xi * interval)))
        return cls(interval, 1.0, math.sqrt(2.0 * d * interval))


@dataclass(frozen=True, eq=False)
class MixtureRods:
    """The species of the rods of a mixture run, as the kernel takes them.

    Attributes
    ----------
    species : ndarray of int64, shape (N,)
        The species of each rod (in ring order).
    masses : ndarray, shape (k,)
    lcodes, lp0, lp1 : ndarray, shape (k, k)
        The restitution law of each pair (symmetric): its code and parameters
        (:func:`kinetic_fem.model.restitution_value`).
    max_speed : float
        The smallest relative speed range of those laws.
    kick_scale : ndarray, shape (N,)
        Each rod's kick amplitude over :attr:`Kicks.amplitude`
        (:math:`\\sqrt{D_s/D}`).
    """

    species: NDArray[np.int64]
    masses: NDArray[np.float64]
    lcodes: NDArray[np.int64]
    lp0: NDArray[np.float64]
    lp1: NDArray[np.float64]
    kick_scale: NDArray[np.float64]
    max_speed: float = math.inf

    @classmethod
    def of(cls, species: NDArray[np.int64], masses: NDArray[np.float64],
           laws: tuple[tuple[RestitutionLaw, ...], ...],
           kick_scale: NDArray[np.float64]) -> MixtureRods:
        """The rods of a mixture with the symmetric table of restitution ``laws``."""
        k = len(laws)
        params = np.array([[law.parameters for law in row] for row in laws],
                          dtype=float).reshape(k, k, 2)
        return cls(species, masses,
                   np.array([[law.code for law in row] for row in laws], dtype=np.int64),
                   np.ascontiguousarray(params[..., 0]), np.ascontiguousarray(params[..., 1]),
                   kick_scale, min(float(law.max_speed) for row in laws for law in row))


_NO_SPECIES = MixtureRods(np.zeros(0, np.int64), np.zeros(0), np.zeros((0, 0), np.int64),
                          np.zeros((0, 0)), np.zeros((0, 0)), np.zeros(0))


@dataclass(frozen=True)
class EngineOptions:
    """Everything the event loop needs besides the state (validated by the callers).

    Attributes
    ----------
    free_length, sigma : float
        Length of the reduced ring :math:`L - N\\sigma` and the rod length.
    restitution : RestitutionLaw
        :math:`\\alpha(g)`, evaluated in the kernel by
        :func:`kinetic_fem.model.restitution_value`.
    threshold : float
        Regularisation: collisions slower than it are elastic (0: none).  Composes
        with the law: below :attr:`elastic_below` a collision is elastic (and counted
        in ``n_elastic``), above it the law applies.
    kicks : Kicks
        The thermostat's kicks (none: free cooling).
    collapse_tol : float
        Collapse is reported for an inelastic collision slower than
        ``collapse_tol * sqrt(T)``.
    max_stall : int
        ... or after this many consecutive collisions without time advancing.
    species : MixtureRods, optional
        A mixture (:mod:`particles.md_mixture`); None: one species.
    """

    free_length: float
    sigma: float
    restitution: RestitutionLaw
    threshold: float = 0.0
    kicks: Kicks = field(default_factory=Kicks)
    collapse_tol: float = 1e-12
    max_stall: int = 10**6
    species: MixtureRods | None = None

    @property
    def elastic_below(self) -> float:
        """The larger of :attr:`threshold` and a threshold law's own threshold."""
        law = self.restitution
        own = law.threshold if isinstance(law, ThresholdRestitution) else 0.0
        return max(self.threshold, own)


class MDEngine:
    """Arrays and counters of one run; advances the kernel between stop points.

    Parameters
    ----------
    y, v : ndarray, shape (N,)
        Sorted positions on the reduced ring and velocities.
    options : EngineOptions
    rng : numpy.random.Generator
        Seeds the kernel's generator of the kick normals.
    """

    def __init__(self, y: NDArray[np.float64], v: NDArray[np.float64],
                 options: EngineOptions, rng: np.random.Generator) -> None:
        n = y.size
        o = self.options = options
        kick_dt = o.kicks.interval
        self.x, self.v, self.tl = y.astype(float), v.astype(float), np.zeros(n)
        self.heap = np.zeros(n, np.int32)
        self.hkey = np.full(n + K.HEAP_PAD, np.inf)
        self.where = np.full(n, -1, np.int32)
        self.ptime = np.full(n, np.inf)
        self.head = np.full(n, -1, np.int32)
        self.nxt = np.full(n, -1, np.int32)
        self.prv = np.full(n, -1, np.int32)
        self.bkt = np.full(n, -1, np.int32)
        self.fstate = np.zeros(K.N_FSTATE)
        self.istate = np.zeros(K.N_ISTATE, np.int64)
        self.fstate[K.F_T_KICK] = kick_dt
        # the counter of the kick normals (_md_kicks.fill_normals)
        self.rng_state = rng.bit_generator.random_raw(1).astype(np.uint64)
        self.stream = np.array([K.STREAM_VERSION], np.int64)
        self.xi = np.zeros(n + n % 2)  # scratch: the normals of one kick (even length)
        self.free_length, self.sigma = o.free_length, o.sigma
        self.kick_dt = kick_dt
        law = o.restitution
        mix = o.species or _NO_SPECIES
        self._law = (law.code, *law.parameters, min(law.max_speed, mix.max_speed),
                     o.elastic_below)
        k = mix.masses.size
        #: collisions per ordered pair of species (the kernel counts the left rod first)
        self.pair_counts = np.zeros((k, k), np.int64)
        self._species = (mix.species, mix.masses, mix.lcodes, mix.lp0, mix.lp1,
                         mix.kick_scale)
        self._temp_key: tuple[int, int] | None = None
        self._moments = (math.nan, math.nan, math.nan)
        # free cooling: calendar epochs of about N collisions, the first from T
        # (collision rate N n_f sqrt(T/pi) of points at the reduced density n_f)
        temp = float(np.var(self.v)) if n > 1 else 0.0
        span = (o.free_length / n) * math.sqrt(math.pi / temp) if temp > 0.0 else 1.0
        self.fstate[K.F_SPAN] = span
        horizon = kick_dt if kick_dt < math.inf else span
        K.build_heap(0.0, horizon, self.x, self.v, self.tl, o.free_length, self.heap,
                     self.hkey, self.where, self.ptime, self.head, self.nxt, self.prv,
                     self.bkt, self.fstate, self.istate)
        self._args = self._kernel_args()

    _ARRAYS = ("x", "v", "tl", "heap", "hkey", "where", "ptime", "head", "nxt", "prv", "bkt",
               "fstate", "istate", "rng_state", "stream")

    def state(self) -> dict[str, NDArray]:
        return {f"md_{k}": getattr(self, k).copy() for k in self._ARRAYS}

    def restore(self, arrays: Mapping[str, NDArray]) -> None:
        if "md_head" not in arrays or arrays["md_fstate"].size != self.fstate.size:
            raise ValueError("the checkpoint was written by an older version of the MD "
                             "engine (other event calendar layout); it cannot be "
                             "resumed, rerun from the start")
        version = int(arrays["md_stream"][0]) if "md_stream" in arrays else 1
        if version != K.STREAM_VERSION:
            raise ValueError(f"the checkpoint was written with version {version} of the MD "
                             f"random stream (kick normals), this engine draws version "
                             f"{K.STREAM_VERSION}: it cannot be resumed bit-identically, "
                             "rerun from the start")
        for k in self._ARRAYS:
            setattr(self, k, np.array(arrays[f"md_{k}"]))
        self._temp_key = None
        self._args = self._kernel_args()

    def _kernel_args(self) -> tuple:
        """The arrays and constants of :func:`K.run_events` before the stop arguments."""
        o = self.options
        return (self.x, self.v, self.tl, self.heap, self.hkey, self.where, self.ptime,
                self.head, self.nxt, self.prv, self.bkt, self.fstate, self.istate,
                self.rng_state, self.xi, self.free_length, *self._law, self.kick_dt,
                o.kicks.decay, o.kicks.amplitude, *self._species, self.pair_counts)

    @property
    def n_collisions(self) -> int:
        return int(self.istate[K.I_NCOLL])

    def moments(self) -> tuple[float, float, float]:
        """``(sum v, sum v^2, var v)``; cached until a collision or kick changes ``v``."""
        key = (int(self.istate[K.I_NCOLL]), int(self.istate[K.I_NKICK]))
        if self._temp_key != key:
            s1, s2, var = K.velocity_moments(self.v)
            self._temp_key, self._moments = key, (float(s1), float(s2), float(var))
        return self._moments

    def temperature(self) -> float:
        """``var(v)`` (central); cached until the next collision or kick changes ``v``."""
        return self.moments()[2]

    def advance(self, coll_target: int, t_stop: float = np.inf) -> bool:
        """Run until ``coll_target`` collisions in total or time ``t_stop``.

        Returns True if ``t_stop`` came first (the state is then valid at ``t_stop``).
        """
        o = self.options
        floor = o.collapse_tol * math.sqrt(max(self.temperature(), 1e-300))
        if _JIT:
            status = K.run_events(*self._args, floor, o.max_stall, t_stop, coll_target)
        else:
            with np.errstate(over="ignore"):  # uint64 wrap-around of the generator
                status = K.run_events(*self._args, floor, o.max_stall, t_stop, coll_target)
        if status == K.STATUS_COLLISIONS:
            return False
        if status == K.STATUS_TIME:
            return True
        if status == K.STATUS_NO_EVENTS:
            raise RuntimeError("no rods approach each other any more (all pairs recede): "
                               "the run cannot reach the requested collision count")
        if status == K.STATUS_LAW_RANGE:
            p = int(self.istate[K.I_BAD_PAIR])
            g = float(self.v[p] - self.v[(p + 1) % self.v.size])
            where = f"a collision of the MD run at t={self.fstate[K.F_T]:.6g}"
            mix = self.options.species
            if mix is not None and g > mix.max_speed:
                raise ValueError(f"{where}: relative speed {g:.4g} exceeds {mix.max_speed:.4g}, "
                                 "the largest a restitution law of the mixture allows (its "
                                 "max_speed); lower the temperature or widen the law's range")
            self.options.restitution.check_speed(g, where=where)
        self._collapse(status)

    def _collapse(self, status: int) -> NoReturn:
        o = self.options
        what = ("an inelastic collision below the speed floor "
                f"{o.collapse_tol:g} sqrt(T)" if status == K.STATUS_COLLAPSE_SPEED else
                f"{o.max_stall} consecutive collisions without time advancing")
        raise InelasticCollapseError(
            f"inelastic collapse at t={self.fstate[K.F_T]:.6g} after "
            f"{self.n_collisions} collisions ({what}, pair {int(self.istate[K.I_BAD_PAIR])}). "
            "Regularise with threshold=<small relative speed> (collisions slower than it "
            "are elastic, Ben-Naim et al.), or use fewer rods or alpha closer to 1 "
            "(plain inelastic dynamics needs N (1 - alpha) small); heated runs can also "
            "use a shorter kick_interval.")

    def rod_positions(self, t: float | None = None) -> NDArray[np.float64]:
        """Rod left ends at time ``t`` (default: the last event), in ``[0, L)``, ring order."""
        t = self.fstate[K.F_T] if t is None else t
        out = np.empty(self.x.size)
        K.rod_positions_at(float(t), self.x, self.v, self.tl, self.sigma,
                           self.free_length + self.sigma * self.x.size, out)
        return out
