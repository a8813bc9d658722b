"""Engine, driver and result types of the event-driven MD (see :mod:`particles.md`).

The engine holds the arrays of :mod:`particles._md_kernels` and advances them between
stop points (records, samples, snapshots, checkpoints) measured in collisions; the
driver turns the samples into a :class:`~kinetic_fem.VelocityDistribution`.  The
coarse-grained density fluctuation of rods in boxes of size :math:`\\ell` is

.. math::

    \\frac{\\operatorname{Var} N_\\ell}{\\langle N_\\ell \\rangle}, \\qquad
    N_\\ell = \\#\\{i: X_i \\in \\text{box}\\},

1 for independent points, :math:`(1 - n\\sigma)^2` for large boxes of equilibrium hard
rods, larger when the rods cluster.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field
from typing import Any, Mapping, NoReturn, Sequence

import numpy as np
from numpy.typing import NDArray
from tqdm.auto import tqdm

from kinetic_fem.distribution import RunInfo, VelocityDistribution

from . import _md_kernels as K
from .sampling import Accumulator, load_checkpoint, save_checkpoint

__all__ = ["MDRun", "Snapshot", "DensityFluctuations", "InelasticCollapseError",
           "density_fluctuations", "run_md"]

logger = logging.getLogger(__name__)

SERIES = ("t", "collisions_per_particle", "temperature", "energy", "energy_injected",
          "energy_dissipated", "momentum", "elastic_fraction")


class InelasticCollapseError(RuntimeError):
    """The collision count diverges in finite time (inelastic collapse)."""


@dataclass(frozen=True)
class Snapshot:
    """Positions of the rods (left ends in ``[0, L)``) and their scaled velocities."""

    collisions_per_particle: float
    time: float
    x: NDArray[np.float64]
    c: NDArray[np.float64]


@dataclass(frozen=True)
class DensityFluctuations:
    """Variance of the number of rods in boxes of size ``box_sizes``, over its mean.

    ``variance_ratio`` is 1 for independent points and :math:`(1 - n\\sigma)^2` for
    large boxes of equilibrium hard rods; clustering makes it grow.
    """

    box_sizes: NDArray[np.float64]
    mean_count: NDArray[np.float64]
    variance_ratio: NDArray[np.float64]


@dataclass(frozen=True)
class MDRun:
    """Result of an MD run.

    Attributes
    ----------
    distribution : VelocityDistribution
        Sampled velocities relative to the mean (heated, in units of v) or scaled
        velocities :math:`c` (cooling), with batch error bars.
    series : dict of str to ndarray
        ``t``, ``collisions_per_particle``, ``temperature``, ``energy``
        (:math:`\\sum v^2/2`), ``energy_injected``, ``energy_dissipated``,
        ``momentum``, ``elastic_fraction`` at the record points.
    snapshots : tuple of Snapshot
        x-c configurations at the requested collisions per particle.
    density_fluctuations : DensityFluctuations
        Averaged over the sample points.
    positions, velocities : ndarray, shape (N,)
        Final rod positions (left ends in ``[0, L)``, ring order) and velocities.
    n_collisions, n_elastic, n_kicks : int
        Binary collisions, those made elastic by the threshold, kicks.
    info : RunInfo
    params : dict
    """

    distribution: VelocityDistribution
    series: Mapping[str, NDArray[np.float64]]
    snapshots: tuple[Snapshot, ...]
    density_fluctuations: DensityFluctuations
    positions: NDArray[np.float64]
    velocities: NDArray[np.float64]
    n_collisions: int
    n_elastic: int
    n_kicks: int
    info: RunInfo
    params: Mapping[str, Any] = field(default_factory=dict)

    @property
    def a2(self) -> float:
        """Kurtosis coefficient of :attr:`distribution`."""
        return self.distribution.a2

    @property
    def a2_error(self) -> float:
        """Its standard error from the batch spread."""
        return self.distribution.a2_error

    @property
    def temperature(self) -> float:
        """Heated: the sampled temperature; cooling: the final temperature."""
        if self.params["problem"] == "heated":
            return self.distribution.temperature
        return float(self.series["temperature"][-1])

    @property
    def collisions_per_particle(self) -> float:
        """``2 * n_collisions / N``."""
        return 2.0 * self.n_collisions / self.params["n_particles"]

    @property
    def energy_balance_error(self) -> float:
        """Energy bookkeeping error over the records.

        ``max_t abs(E(t) - E(0) - (injected(t) - dissipated(t))) / max_t E(t)``.
        """
        s = self.series
        err = s["energy"] - s["energy"][0] - (s["energy_injected"] - s["energy_dissipated"])
        return float(np.max(np.abs(err)) / np.max(s["energy"]))


def density_fluctuations(x: NDArray[np.float64], length: float,
                         n_boxes: Sequence[int]) -> NDArray[np.float64]:
    """Var/mean of the number of rods per box, for each number of boxes, shape (k, 2).

    Column 0 is the mean count, column 1 the variance over the mean.  Box numbers
    ``m = odd * 2^j`` sharing the odd factor are counted once, at the largest
    ``M``, and summed in groups of ``M / m`` boxes: ``x M / L`` is exactly
    ``2^k x m / L`` in floating point, so the counts are those of binning with ``m``.
    """
    out = np.empty((len(n_boxes), 2))
    finest: dict[int, int] = {}
    for m in n_boxes:
        odd = m // (m & -m)
        finest[odd] = max(finest.get(odd, 0), m)
    base = {odd: np.bincount(np.minimum((x * (big / length)).astype(np.int64), big - 1),
                             minlength=big) for odd, big in finest.items()}
    for k, m in enumerate(n_boxes):
        big = finest[m // (m & -m)]
        counts = base[m // (m & -m)].reshape(m, big // m).sum(axis=1)
        out[k] = counts.mean(), counts.var() / counts.mean()
    return out


class _Engine:
    """Arrays and counters of one run; advances the kernel between stop points."""

    def __init__(self, y, v, *, free_length, sigma, alpha, threshold, kick_dt, kick_amp,
                 rng, collapse_tol, max_stall):
        n = y.size
        self.x, self.v, self.tl = y.astype(float), v.astype(float), np.zeros(n)
        self.heap = np.zeros(n, np.int32)
        self.hkey = np.full(n + K.HEAP_PAD, np.inf)
        self.where = np.full(n, -1, np.int32)
        self.fstate = np.zeros(K.N_FSTATE)
        self.istate = np.zeros(K.N_ISTATE, np.int64)
        self.fstate[K.F_T_KICK] = kick_dt
        self.rng_state = rng.bit_generator.random_raw(4).astype(np.uint64)
        if not self.rng_state.any():  # xoshiro256** must not start from zero
            self.rng_state[0] = 1
        self.xi = np.zeros(n)  # scratch: the normals of one kick
        self.free_length, self.sigma, self.alpha = free_length, sigma, alpha
        self.threshold, self.kick_dt, self.kick_amp = threshold, kick_dt, kick_amp
        self.rng, self.collapse_tol, self.max_stall = rng, collapse_tol, max_stall
        self._temp_key: tuple[int, int] | None = None
        self._temp = math.nan
        K.build_heap(0.0, kick_dt, self.x, self.v, self.tl, free_length, self.heap, self.hkey,
                     self.where, self.istate)

    _ARRAYS = ("x", "v", "tl", "heap", "hkey", "where", "fstate", "istate", "rng_state")

    def state(self) -> dict[str, NDArray]:
        return {f"md_{k}": getattr(self, k).copy() for k in self._ARRAYS}

    def restore(self, arrays: Mapping[str, NDArray]) -> None:
        if "md_rng_state" not in arrays or arrays["md_hkey"].size != self.hkey.size:
            raise ValueError("the checkpoint was written by an older version of the MD "
                             "engine (other heap and random-stream layout); it cannot be "
                             "resumed, rerun from the start")
        for k in self._ARRAYS:
            setattr(self, k, np.array(arrays[f"md_{k}"]))
        self._temp_key = None

    @property
    def n_collisions(self) -> int:
        return int(self.istate[K.I_NCOLL])

    def temperature(self) -> float:
        """``var(v)``; cached until the next collision or kick changes ``v``."""
        key = (int(self.istate[K.I_NCOLL]), int(self.istate[K.I_NKICK]))
        if self._temp_key != key:
            self._temp_key, self._temp = key, float(np.var(self.v))
        return self._temp

    def advance(self, coll_target: int, t_stop: float = np.inf) -> bool:
        """Run until ``coll_target`` collisions in total or time ``t_stop``.

        Returns True if ``t_stop`` came first (the state is then valid at ``t_stop``).
        """
        floor = self.collapse_tol * math.sqrt(max(self.temperature(), 1e-300))
        with np.errstate(over="ignore"):  # uint64 wrap-around of the generator (no-JIT mode)
            status = K.run_events(self.x, self.v, self.tl, self.heap, self.hkey,
                                  self.where, self.fstate, self.istate, self.rng_state,
                                  *K.ZIGGURAT, self.xi, self.free_length, self.alpha,
                                  self.threshold, self.kick_dt, self.kick_amp, floor,
                                  self.max_stall, t_stop, coll_target)
        if status == K.STATUS_COLLISIONS:
            return False
        if status == K.STATUS_TIME:
            return True
        if status == K.STATUS_NO_EVENTS:
            raise RuntimeError("no rods approach each other any more (all pairs recede): "
                               "the run cannot reach the requested collision count")
        self._collapse(status)

    def _collapse(self, status: int) -> NoReturn:
        what = ("an inelastic collision below the speed floor "
                f"{self.collapse_tol:g} sqrt(T)" if status == K.STATUS_COLLAPSE_SPEED else
                f"{self.max_stall} consecutive collisions without time advancing")
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
        y = self.x + self.v * (t - self.tl)
        big_l = self.free_length + self.sigma * y.size
        return np.mod(y + self.sigma * np.arange(y.size), big_l)


def _schedule(n: int, total: int, sample_from: int, n_samples: int, n_records: int,
              log_records: bool, snapshots: Sequence[int], every: int | None):
    """Sorted collision counts at which the run stops, and what happens there."""
    if log_records:
        rec = np.unique(np.geomspace(1, max(total, 1), n_records).astype(np.int64))
    else:
        rec = np.unique(np.linspace(0, total, n_records).astype(np.int64))
    rec = np.union1d(rec, [0, total])
    samples = np.unique(np.linspace(sample_from, total, n_samples).round().astype(np.int64))
    checks = (np.arange(every, total + 1, every, dtype=np.int64) if every
              else np.zeros(0, np.int64))
    stops = np.unique(np.concatenate([rec, samples, np.asarray(snapshots, np.int64), checks]))
    return stops, set(rec.tolist()), {int(s): i for i, s in enumerate(samples)}, \
        set(int(s) for s in snapshots), set(checks.tolist())


def run_md(problem: str, params: dict[str, Any], *, seed: Any, y: NDArray, v: NDArray,
         rng: np.random.Generator, engine_options: dict[str, Any], total: int, sample_from: int,
         n_samples: int, n_batches: int, hist_range: float, n_bins: int, snapshots_at: Sequence,
         n_records: int, box_counts: Sequence[int], progress: bool, checkpoint: Any,
         checkpoint_every: float | None, resume: Any, sample_dt: float | None = None) -> MDRun:
    """Shared driver of :func:`simulate_heated` and :func:`simulate_cooling`.

    Samples are taken at ``n_samples`` collision counts from ``sample_from`` on, or,
    with ``sample_dt``, every ``sample_dt`` of time from ``sample_from`` collisions on
    (uniform in time: bursts of collisions inside clusters do not bias the average).
    """
    start = time.perf_counter()
    n, big_l = params["n_particles"], params["n_particles"] / params["density"]
    cooling = problem == "cooling"
    snap_counts = [int(round(s * n / 2)) for s in snapshots_at]
    every = None if checkpoint_every is None else max(1, int(round(checkpoint_every * n / 2)))
    stops, rec_at, sample_at, snap_at, check_at = _schedule(
        n, total, sample_from, n_samples, n_records, cooling, snap_counts, every)
    timed = sample_dt is not None
    if timed:
        sample_at = {}
        stops = np.union1d(stops, [sample_from])
    t_next, n_sampled = np.inf, 0
    eng = _Engine(y, v, rng=rng, **engine_options)
    acc = Accumulator(-hist_range, hist_range, n_bins, n_batches)
    records: list[list[float]] = []
    snaps: list[Snapshot] = []
    dens = np.zeros((len(box_counts), 2))
    first, e0, p0 = 0, float(0.5 * np.sum(v * v)), float(np.sum(v))
    if resume is not None:
        arrays, meta = load_checkpoint(resume)
        if meta["params"] != json_params(params):
            raise ValueError(f"checkpoint {resume} was written for other parameters: "
                             f"{meta['params']} != {json_params(params)}")
        eng.restore(arrays)
        acc.restore(arrays)
        rng.bit_generator.state = meta["rng"]
        records = arrays["records"].tolist()
        dens = arrays["dens"].copy()
        snaps = [Snapshot(float(m[0]), float(m[1]), sx, sc) for m, sx, sc in
                 zip(arrays["snap_meta"], arrays["snap_x"], arrays["snap_c"], strict=True)]
        first = int(np.searchsorted(stops, meta["done"], side="right"))
        e0, p0, t_next, n_sampled = meta["e0"], meta["p0"], meta["t_next"], meta["n_sampled"]
    bar = tqdm(total=int(stops[-1]), initial=int(stops[first - 1]) if first else 0,
               disable=not progress, unit="coll", desc=f"MD {problem}")

    def take_sample(batch: int, at: float | None) -> None:
        nonlocal dens, n_sampled
        vel = eng.v
        u, temp = float(vel.mean()), eng.temperature()
        acc.add(batch, (vel - u) / math.sqrt(temp) if cooling else vel - u)
        dens += density_fluctuations(eng.rod_positions(at), big_l, box_counts)
        n_sampled += 1

    span = max(total - sample_from, 1)
    for idx in range(first, stops.size):
        target = int(stops[idx])
        if timed:
            while eng.advance(target, t_next):
                take_sample(min(n_batches - 1, (eng.n_collisions - sample_from) * n_batches
                                // span), t_next)
                t_next += sample_dt
            if target == sample_from and t_next == np.inf:
                t_next = float(eng.fstate[K.F_T]) + sample_dt
        else:
            eng.advance(target)
        bar.update(target - bar.n)
        vel, t = eng.v, float(eng.fstate[K.F_T])
        u, temp = float(vel.mean()), eng.temperature()
        if target in rec_at:
            ncoll = max(eng.n_collisions, 1)
            records.append([t, 2.0 * target / n, temp, float(0.5 * np.sum(vel * vel)),
                            float(eng.fstate[K.F_INJ]), float(eng.fstate[K.F_DISS]),
                            float(np.sum(vel)), eng.istate[K.I_NELASTIC] / ncoll])
        if target in sample_at:
            take_sample(sample_at[target] * n_batches // len(sample_at), None)
        if target in snap_at:
            snaps.append(Snapshot(2.0 * target / n, t, eng.rod_positions(),
                                  (vel - u) / math.sqrt(temp)))
        if target in check_at:
            arrays = {**eng.state(), **acc.state(), "records": np.array(records),
                      "dens": dens, "snap_meta": np.array([[s.collisions_per_particle, s.time]
                                                           for s in snaps]).reshape(-1, 2),
                      "snap_x": np.array([s.x for s in snaps]).reshape(-1, n),
                      "snap_c": np.array([s.c for s in snaps]).reshape(-1, n)}
            save_checkpoint(checkpoint, arrays, {
                "params": json_params(params), "rng": rng.bit_generator.state,
                "done": target, "e0": e0, "p0": p0, "t_next": t_next,
                "n_sampled": n_sampled})
    bar.close()
    series = {name: np.array([r[k] for r in records]) for k, name in enumerate(SERIES)}
    wall = time.perf_counter() - start
    n_sampled = max(1, n_sampled)
    fluct = DensityFluctuations(big_l / np.asarray(box_counts, float), dens[:, 0] / n_sampled,
                                dens[:, 1] / n_sampled)
    balance = float(np.max(np.abs(series["energy"] - e0 - series["energy_injected"]
                                  + series["energy_dissipated"])) / np.max(series["energy"]))
    info = RunInfo(converged=True, iterations=eng.n_collisions, residual=balance,
                   wall_time=wall,
                   message=f"{eng.n_collisions} collisions ({2 * eng.n_collisions / n:.4g} per "
                           f"particle) in {wall:.3g} s",
                   extra={"seed": None if seed is None else str(seed),
                          "n_kicks": int(eng.istate[K.I_NKICK]),
                          "n_elastic": int(eng.istate[K.I_NELASTIC]),
                          "momentum_drift": float(abs(np.sum(eng.v) - p0)),
                          "collisions_per_second": eng.n_collisions / max(wall, 1e-12)})
    dist = acc.distribution(method="md", params=params, info=info, series=series)
    logger.info("MD %s: %s", problem, info.message)
    return MDRun(distribution=dist, series=series, snapshots=tuple(snaps),
                 density_fluctuations=fluct, positions=eng.rod_positions(), velocities=eng.v.copy(),
                 n_collisions=eng.n_collisions, n_elastic=int(eng.istate[K.I_NELASTIC]),
                 n_kicks=int(eng.istate[K.I_NKICK]), info=info, params=params)


def json_params(params: Mapping[str, Any]) -> dict[str, Any]:
    """Parameters as JSON-comparable values (for checkpoint checks)."""
    return {k: (list(v) if isinstance(v, tuple) else v) for k, v in params.items()}
