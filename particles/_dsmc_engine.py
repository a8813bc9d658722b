"""Run loop of :mod:`particles.dsmc`: segments, measurements, relaxation, checkpoints.

See :mod:`particles.dsmc` for the method; this module holds the state of one run
(velocities, the kernel's random-stream state, counters, time series, batch
histograms) and the loop shared by the heated and the cooling gas; the run is
configured by one frozen :class:`DSMCOptions`.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

import numpy as np
from numpy.typing import NDArray
from tqdm.auto import tqdm

from kinetic_fem.distribution import MAX_MOMENT, RunInfo, VelocityDistribution

from . import _dsmc_segments as seg
from ._dsmc_kernels import CANDIDATE_BLOCK
from .rng import cooling_state, heated_state, ziggurat_tables
from .run import Checkpointing, ParticleRun
from .sampling import (
    integrated_autocorrelation_time,
    load_checkpoint,
    save_checkpoint,
)

__all__ = ["DSMCRun", "DSMCOptions", "Engine"]

logger = logging.getLogger("particles.dsmc")

STREAMS = {"heated": 1, "cooling": 2}
"""Version of the random stream of each kind of run, stored in checkpoints: a checkpoint
of another stream cannot resume the run (1: the 5-word heated state of issue 13 and the
4-word xoshiro256** cooling state; 2: the cooling lanes of issue 31,
:func:`particles.rng.cooling_state`).  Checkpoints without the field are version 1."""

_SERIES = ("collisions_per_particle", "t", "log_t", "temperature", "log_temperature", "a2", "a3")


@dataclass(frozen=True)
class DSMCRun(ParticleRun):
    """Result of a DSMC run (the properties shared with MD: :class:`ParticleRun`).

    Attributes
    ----------
    distribution : VelocityDistribution
        Time-averaged histogram after relaxation, with error bars from ``n_batches``
        consecutive batches: of the velocity ``v`` (centre-of-mass frame, physical
        units) for the heated gas, of the scaled velocity ``c = v/sqrt(T)`` for free
        cooling.  Compare methods with ``distribution.f(c)``.
    problem : str
        ``"heated"`` or ``"cooling"``.
    n_particles, n_collisions : int
        Particles and accepted collisions (relaxation included).
    relaxed_at : float
        Collisions per particle at which averaging started.
    series : dict of str to ndarray
        At every measurement: ``collisions_per_particle``, ``t`` (physical time;
        may overflow to inf in very long cooling runs), ``log_t``, ``temperature``
        (physical, central; may underflow to 0 in cooling), ``log_temperature``,
        ``a2`` and ``a3`` (Sonine coefficients of the central moments).
    dissipation_rate, dissipation_error : float
        Heated: energy dissipated per particle and unit time during averaging,
        :math:`\\tfrac{1}{2N t}\\sum (1-\\alpha(g)^2) g^2` over the collisions, with
        its batch error.  Cooling: NaN.
    injection_rate : float
        Heated: the thermostat's input into the internal energy per particle,
        :math:`2D(1-1/N) - 2\\xi T` (``T`` the averaged temperature; ``xi = 0`` for
        white noise).
    edges, counts, power_sums : ndarray
        Raw batch histograms and power sums (:func:`combine_runs` merges replicas).
    info : RunInfo
        Convergence (relaxation detected), wall time, seeds and counters in ``extra``.
    """

    distribution: VelocityDistribution
    problem: str
    n_particles: int
    n_collisions: int
    relaxed_at: float
    series: Mapping[str, NDArray[np.float64]]
    dissipation_rate: float
    dissipation_error: float
    injection_rate: float
    edges: NDArray[np.float64]
    counts: NDArray[np.float64]
    power_sums: NDArray[np.float64]
    info: RunInfo = field(default_factory=RunInfo)

    @property
    def temperature(self) -> float:
        """Heated: time-averaged steady T.  Cooling: physical T at the end."""
        if self.problem == "heated":
            return self.distribution.temperature
        return float(math.exp(self.series["log_temperature"][-1]))

    def cooling_rate(self, n_batches: int = 20) -> tuple[float, float]:
        """Cooling rate :math:`\\zeta` of :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`, error.

        :math:`\\gamma > 0`: :math:`T^{-\\gamma/2} = \\gamma\\zeta n t + T_0^{-\\gamma/2}`;
        after relaxation (many e-folds of T) the constant is negligible, so every sample
        gives :math:`T^{-\\gamma/2}/(\\gamma n t)` (computed in logarithms: T and t leave
        the float range).  :math:`\\gamma = 0`: :math:`\\ln T` falls linearly in t, and
        each sample after the start of averaging gives
        :math:`-\\ln(T/T_r)/(2n(t - t_r))`.  The error is from ``n_batches`` consecutive
        batches equal in collisions per particle (each batch: its first-to-last slope for
        :math:`\\gamma = 0`).

        Parameters
        ----------
        n_batches : int
            Batches of the error estimate.

        Returns
        -------
        (zeta, error) : (float, float)

        Raises
        ------
        ValueError
            For a heated run.
        """
        if self.problem != "cooling":
            raise ValueError("cooling_rate needs a free-cooling run (simulate_cooling)")
        s = self.series
        params = self.distribution.params
        gamma, density = float(params.get("gamma", 1.0)), float(params.get("density", 1.0))
        late = s["collisions_per_particle"] >= self.relaxed_at
        log_temp, log_t = s["log_temperature"][late], s["log_t"][late]
        # batches equal in collisions per particle (the sampling cadence may change)
        cpp = s["collisions_per_particle"][late]
        span = max(float(cpp[-1] - cpp[0]), 1e-300)
        which = np.minimum((n_batches * (cpp - cpp[0]) / span).astype(np.int64), n_batches - 1)
        groups = [g for g in (np.flatnonzero(which == b) for b in range(n_batches))
                  if g.size >= (1 if gamma > 0.0 else 2)]
        if gamma > 0.0:
            z = np.exp(-0.5 * gamma * log_temp - log_t) / (gamma * density)
            means = np.array([z[g].mean() for g in groups])
        else:
            t = np.exp(log_t - log_t[-1])  # relative times (Maxwell: t grows linearly)
            means = np.array([-(log_temp[g[-1]] - log_temp[g[0]])
                              / (2.0 * density * (t[g[-1]] - t[g[0]])) for g in groups])
            means *= math.exp(-log_t[-1])
        return float(means.mean()), float(means.std(ddof=1) / math.sqrt(means.size))


@dataclass(frozen=True)
class DSMCOptions:
    """Everything a run needs besides the problem and the initial state (validated).

    Attributes
    ----------
    kind : str
        ``"heated"`` or ``"cooling"``.
    n : int
        Particles.
    relax : str or float
        ``"auto"`` or collisions per particle before averaging.
    sample_every : float
        Collisions per particle between measurements (cooling; heated: ``steps``).
    average_every : "auto" or float
        Collisions per particle between measurements once averaging has started
        (rounded to a multiple of ``sample_every``); "auto": from the integrated
        autocorrelation time of ``a2`` over the first batch (:meth:`Engine.cadence`).
    n_batches, n_samples, bins, window : int
        Batches, averaging samples, histogram bins, relaxation window (samples).
    lo, hi : float
        Histogram range (of ``v`` heated, of ``c`` cooling).
    entropy : str
        The root seed, recorded in results and checkpoints.
    key : dict
        What a checkpoint must match to be resumed.
    kcode, gamma, lcode, p0, p1, g_limit : int, float, int, float, float, float
        The model in kernel form: kernel code and parameter (``kernel_model``), restitution
        law code and parameters, largest relative speed the law allows.
    dt, steps : float, int
        Heated: time step and steps per measurement.
    decay, amp, half_decay, half_amp : float
        Heated: kick of a full and of a half step, :math:`v \\to d v + b \\xi`.
    checkpointing : Checkpointing
        Checkpoints, resume and wall-time limit (the spelling shared with MD).
    progress : bool
        As in :func:`particles.dsmc.simulate_heated`.
    """

    kind: str
    n: int
    relax: str | float
    sample_every: float
    average_every: str | float
    n_batches: int
    n_samples: int
    bins: int
    window: int
    lo: float
    hi: float
    entropy: str
    key: Mapping[str, Any]
    kcode: int
    gamma: float
    lcode: int
    p0: float
    p1: float
    g_limit: float = math.inf
    dt: float = math.nan
    steps: int = 0
    decay: float = 1.0
    amp: float = 0.0
    half_decay: float = 1.0
    half_amp: float = 0.0
    checkpointing: Checkpointing = field(default_factory=Checkpointing)
    progress: bool = False


class Engine:
    """Shared loop: advance a segment, measure, detect relaxation, accumulate, checkpoint."""

    def __init__(self, problem: Any, v: NDArray[np.float64], seed_seq: Any,
                 opts: DSMCOptions) -> None:
        self.kind, self.problem, self.opts = opts.kind, problem, opts
        self.gas = problem.gas
        self.v = v
        self.n = v.size
        self.state = (heated_state(seed_seq) if opts.kind == "heated"  # + the wyrand word
                      else cooling_state(seed_seq))  # + the candidate lanes
        # work space of the cooling candidate blocks (zeros: the prefetch reads ahead)
        self.work = (np.zeros(2 * CANDIDATE_BLOCK, np.uint64),
                     np.zeros(CANDIDATE_BLOCK + 32, np.uint64),
                     np.zeros(CANDIDATE_BLOCK + 32, np.uint64), np.zeros(CANDIDATE_BLOCK + 32))
        self.tables = ziggurat_tables()
        self.c = {"accepted": 0, "candidates": 0, "debt": 0.0, "log_t": -math.inf,
                  "log_scale": 0.0, "relaxed_at": -1.0, "avg_start_acc": 0,
                  "n_samples": 0, "windows": 0, "converged": False,
                  # averaging clock in units of sample_every (ticks): tick of the last
                  # sample, ticks per segment, and the measured a2 correlation time
                  "tick": -1, "k": 1, "k_set": False, "tau_a2": float("nan")}
        self.series: dict[str, list[float]] = {k: [] for k in _SERIES}
        nb = opts.n_batches
        self.counts = np.zeros((nb, opts.bins))
        self.sums = np.zeros((nb, MAX_MOMENT + 1))
        self.batch_loss = np.zeros(nb)
        self.batch_time = np.zeros(nb)
        self.seg_loss = self.seg_time = 0.0
        self.sample_counts = np.zeros(opts.bins)  # the last measurement's histogram
        self.sample_sums = np.zeros(MAX_MOMENT + 1)

    # ----------------------------------------------------------------- dynamics
    def _segment(self, k: int) -> None:
        with np.errstate(over="ignore"):  # uint64 wrap-around of the generator (no-JIT mode)
            self._segment_kernels(k)

    def _segment_kernels(self, k: int) -> None:
        """Advance ``k`` ticks: ``k * steps`` Strang steps, or ``k`` sample intervals."""
        o = self.opts
        model = (o.kcode, o.gamma, o.lcode, o.p0, o.p1)
        if self.kind == "heated":
            steps = k * o.steps
            acc, loss, debt, done, g_max = seg.heated_segment(
                self.v, steps, o.dt, o.decay, o.amp, o.half_decay, o.half_amp,
                0.5 * self.n * self.gas.density, *model, o.g_limit, self.c["debt"],
                self.state, *self.tables)
            if done < steps:
                self.gas.restitution.check_speed(
                    g_max, where="the DSMC velocities (max - min after a thermostat kick)")
            self.c["debt"] = debt
            t = steps * o.dt
            self.c["log_t"] = float(np.logaddexp(self.c["log_t"], math.log(t)))
            self.c["accepted"] += int(acc)
            self.seg_loss, self.seg_time = loss, t
            return
        target = k * max(1, int(round(0.5 * o.sample_every * self.n)))
        ratio = self.c["accepted"] / self.c["candidates"] if self.c["candidates"] else 0.1
        acc, cand, d_log_scale, log_time = seg.cooling_segment(
            self.v, target, self.n, max(ratio, 1e-3), *model, self.c["log_scale"], self.state,
            *self.work)
        self.c["accepted"] += int(acc)
        self.c["candidates"] += int(cand)
        if log_time > -math.inf:
            log_dt = (math.log(2.0 / (self.n * self.gas.density)) + log_time
                      - o.gamma * self.c["log_scale"])
            self.c["log_t"] = float(np.logaddexp(self.c["log_t"], log_dt))
        self.c["log_scale"] += d_log_scale  # rescaled to unit variance by _measure

    def _measure(self) -> tuple[float, float, float]:
        # centre (cooling: and rescale to unit variance), moments, histogram and power
        # sums in one kernel
        if self.kind == "heated":
            seg.measure_centred(self.v, self.opts.lo, self.opts.hi, self.sample_counts,
                                self.sample_sums)
        else:
            sd = seg.measure_scaled(self.v, self.opts.lo, self.opts.hi, self.sample_counts,
                                    self.sample_sums)
            if not sd > 0:
                raise FloatingPointError("all velocities became equal; no collision can occur")
            self.c["log_scale"] += math.log(sd)
        cm = self.sample_sums[:7] / self.n
        temp = cm[2]
        a2 = cm[4] / (3 * temp**2) - 1.0
        a3 = 1.0 + 3.0 * a2 - cm[6] / (15.0 * temp**3)
        log_temp = math.log(temp) + 2.0 * self.c["log_scale"]
        row = (2.0 * self.c["accepted"] / self.n, math.exp(min(self.c["log_t"], 700.0)),
               self.c["log_t"], math.exp(max(log_temp, -745.0)), log_temp, a2, a3)
        for key, val in zip(_SERIES, row, strict=True):
            self.series[key].append(float(val))
        return log_temp, a2, a3

    def _relaxed(self) -> bool:
        o = self.opts
        if not isinstance(o.relax, str):
            return 2.0 * self.c["accepted"] / self.n >= o.relax
        w = o.window
        k = len(self.series["a2"])
        if k < 2 * w or k % w:
            return False
        self.c["windows"] += 1
        second = "log_temperature" if self.kind == "heated" else "a3"
        ok = True
        for key in ("a2", second):
            x = np.asarray(self.series[key][-2 * w:])
            # standard errors from 5 sub-block means (the samples are correlated)
            means = [np.array([blk.mean() for blk in np.array_split(half, 5)])
                     for half in (x[:w], x[w:])]
            se = math.sqrt(sum(m.var(ddof=1) / m.size for m in means))
            ok &= abs(means[0].mean() - means[1].mean()) <= 3.0 * se
        if ok or self.c["windows"] >= 20:
            self.c["converged"] = bool(ok)
            if not ok:
                logger.warning("relaxation not detected after 20 windows; averaging anyway")
            return True
        return False

    def _accumulate(self) -> None:
        """Add the current sample to the batch of its tick (batches are equal in time)."""
        o = self.opts
        tick = int(self.c["tick"])
        b = tick * o.n_batches // o.n_samples
        self.counts[b] += self.sample_counts  # the histogram and sums of the last measurement
        self.sums[b] += self.sample_sums
        if tick > 0:  # energy of the segment that led to this sample
            self.batch_loss[b] += self.seg_loss
            self.batch_time[b] += self.seg_time
        self.c["n_samples"] += 1

    def cadence(self) -> int:
        """Ticks (``sample_every``) between samples once averaging has started.

        A number ``average_every`` gives ``round(average_every / sample_every)``.  "auto"
        keeps one tick during the first batch, then takes half the integrated
        autocorrelation time of ``a2`` measured over it (at least 50 samples, else one
        tick): samples closer than that add little information but cost a measurement
        each.  The time is the larger of Sokal's windowed sum
        (:func:`particles.sampling.integrated_autocorrelation_time`) and the AR(1)
        value :math:`(1+\\rho_1)/(1-\\rho_1)` of the lag-one autocorrelation: over a
        batch of a few hundred samples the windowed sum of a slowly decaying
        correlation is biased low (cooling at alpha = 0.9, N = 25000: 4 and 10 from
        200 samples against about 20 from 900), the lag-one value is not.  Capped so
        that every batch keeps 10 samples (the variance of the mean grows by a few %).
        """
        o, c = self.opts, self.c
        per_batch = o.n_samples // o.n_batches
        cap = max(1, per_batch // 10)
        if o.average_every != "auto":
            return int(min(max(1, round(float(o.average_every) / o.sample_every)), cap))
        if c["tick"] + 1 < per_batch or per_batch < 50:
            return 1
        a2 = np.asarray(self.series["a2"][-(int(c["tick"]) + 1):], dtype=float)
        d = a2 - a2.mean()
        var = float(np.dot(d, d))
        rho1 = min(float(np.dot(d[1:], d[:-1])) / var, 0.98) if var > 0.0 else 0.0
        tau = max(integrated_autocorrelation_time(a2), (1.0 + rho1) / (1.0 - rho1))
        c["tau_a2"] = tau * o.sample_every
        return int(min(max(1, math.floor(0.5 * c["tau_a2"] / o.sample_every)), cap))

    # ----------------------------------------------------------------- checkpoints
    def save(self, path: Path) -> None:
        arrays = {"v": self.v, "state": self.state, "counts": self.counts, "sums": self.sums,
                  "batch_loss": self.batch_loss, "batch_time": self.batch_time}
        arrays.update({f"series__{k}": np.asarray(s) for k, s in self.series.items()})
        meta = {"counters": self.c, "key": self.opts.key, "stream": STREAMS[self.kind]}
        save_checkpoint(path, arrays, meta)

    def load(self, path: Path) -> None:
        arrays, meta = load_checkpoint(path, like={"v": self.v, "counts": self.counts,
                                                   "sums": self.sums}, nonnegative=("counts",))
        if meta["key"] != self.opts.key:
            raise ValueError(f"checkpoint {path} belongs to a different run: {meta['key']} "
                             f"!= {self.opts.key}")
        stream = meta.get("stream", 1)
        if stream != STREAMS[self.kind]:
            raise ValueError(f"checkpoint {path} holds random stream {stream} of the {self.kind} "
                             f"DSMC, written by an earlier version of particles; this version "
                             f"runs stream {STREAMS[self.kind]} and cannot resume it: start the "
                             "run again (or finish it with the version that wrote it)")
        if arrays["state"].shape != self.state.shape:
            raise ValueError(f"checkpoint {path} was written by an earlier version with another "
                             f"random stream ({arrays['state'].size} state words, this version "
                             f"has {self.state.size}); start the run again")
        counters = dict(meta["counters"])
        if "tick" not in counters:  # checkpoints before the averaging cadence: one tick each
            counters.update(tick=counters["n_samples"] - 1, k=1, k_set=False,
                            tau_a2=float("nan"))
        self.c.update(counters)
        if "batch_g2" in arrays:  # checkpoints before restitution laws: hard rods, constant
            arrays["batch_loss"] = (1.0 - self.gas.alpha**2) * arrays["batch_g2"]
        for name in ("v", "state", "counts", "sums", "batch_loss", "batch_time"):
            setattr(self, name, arrays[name].copy())
        self.series = {k: list(arrays[f"series__{k}"]) for k in _SERIES}

    # ----------------------------------------------------------------- main loop
    def run(self) -> DSMCRun:
        o = self.opts
        t_start = last_ckpt = time.perf_counter()
        ck = o.checkpointing
        path = ck.path
        if path is not None and ck.resume and path.exists():
            self.load(path)
            logger.info("resumed from %s at %d collisions", path, self.c["accepted"])
        if not self.series["a2"]:
            self._measure()
        interrupted = False
        c = self.c
        with tqdm(total=o.n_samples, disable=not o.progress, desc=f"DSMC {self.kind}",
                  initial=c["tick"] + 1) as bar:
            while c["tick"] + c["k"] < o.n_samples:
                averaging = c["relaxed_at"] >= 0
                self._segment(int(c["k"]) if averaging else 1)
                self._measure()
                if averaging:
                    c["tick"] += c["k"]
                elif self._relaxed():
                    c["relaxed_at"] = 2.0 * c["accepted"] / self.n
                    c["avg_start_acc"] = c["accepted"]
                    c["tick"] = 0
                if c["relaxed_at"] >= 0:
                    self._accumulate()
                    bar.update(c["k"] if c["tick"] else 1)
                    if not c["k_set"]:
                        c["k"] = self.cadence()
                        c["k_set"] = c["k"] > 1 or o.average_every != "auto" or \
                            c["tick"] + 1 >= o.n_samples // o.n_batches
                        if c["k"] > 1 and o.average_every == "auto":
                            # the first batch was sampled every tick: weight its samples
                            # 1/k, so that every batch weighs its length in time
                            self.counts[0] /= c["k"]
                            self.sums[0] /= c["k"]
                now = time.perf_counter()
                if path is not None and now - last_ckpt >= ck.every:
                    self.save(path)
                    last_ckpt = now
                if ck.max_wall_time is not None and now - t_start >= ck.max_wall_time:
                    interrupted = c["tick"] + c["k"] < o.n_samples
                    break
        if path is not None:
            self.save(path)
        return self._result(time.perf_counter() - t_start, interrupted)

    def _result(self, wall: float, interrupted: bool) -> DSMCRun:
        o, c = self.opts, self.c
        keep = self.sums[:, 0] > 0
        params = {**self.problem.as_dict(), "n_particles": self.n}
        diss = diss_err = inj = float("nan")
        if self.kind == "heated":
            params.update(dt=o.dt, diffusion=self.problem.diffusion)
            if self.problem.friction > 0.0:
                params.update(friction=self.problem.friction)
            k = 0.5 / self.n
            ok = self.batch_time > 0
            if ok.any():
                rates = k * self.batch_loss[ok] / self.batch_time[ok]
                diss = k * self.batch_loss[ok].sum() / self.batch_time[ok].sum()
                diss_err = (float(rates.std(ddof=1) / math.sqrt(rates.size))
                            if rates.size > 1 else float("nan"))
            inj = 2.0 * self.problem.diffusion * (1.0 - 1.0 / self.n)
            xi = self.problem.friction
            if xi > 0.0 and keep.any():  # the exact input of the split OU kicks
                m0, m1, m2 = self.sums[keep, :3].sum(axis=0)
                temp = m2 / m0 - (m1 / m0) ** 2
                t_bath = self.problem.thermostat.bath_temperature * (1.0 - 1.0 / self.n)
                inj = (-math.expm1(-2.0 * xi * o.dt) * (t_bath - temp) / o.dt
                       - math.expm1(-xi * o.dt) * diss)
        msg = ("interrupted (resume from the checkpoint)" if interrupted else
               "relaxation detected" if c["converged"] else
               "fixed relaxation" if o.relax != "auto" else "relaxation not detected")
        info = RunInfo(converged=bool(c["converged"] and not interrupted),
                       iterations=int(round(2.0 * c["accepted"] / self.n)),
                       residual=abs(diss / inj - 1.0) if self.kind == "heated" else float("nan"),
                       wall_time=wall, message=msg,
                       extra={"seed_entropy": str(o.entropy), "n_collisions": c["accepted"],
                              "relaxed_at": c["relaxed_at"], "samples": c["n_samples"],
                              "average_every": c["k"] * o.sample_every,
                              "a2_correlation_time": c["tau_a2"]})
        series = {k: np.asarray(s, dtype=float) for k, s in self.series.items()}
        edges = np.linspace(o.lo, o.hi, o.bins + 1)
        if not keep.any():
            raise RuntimeError("run stopped before any sample was averaged; resume it from the "
                               "checkpoint or allow more wall time")
        dist = VelocityDistribution.from_batches(edges, self.counts[keep], self.sums[keep],
                                                 method="dsmc", params=params, info=info,
                                                 series=series)
        return DSMCRun(dist, self.kind, self.n, int(c["accepted"]), float(c["relaxed_at"]),
                       series, float(diss), float(diss_err), float(inj), edges,
                       self.counts.copy(), self.sums.copy(), info)
