"""Driver and result types of the event-driven MD (see :mod:`particles.md`).

:func:`run_md` advances an :class:`~particles._md_engine.MDEngine` between stop points
(records, samples, snapshots) measured in collisions, or samples uniformly in time,
and turns the samples into a :class:`~kinetic_fem.VelocityDistribution`.  What it
samples is a :class:`RunPlan`; checkpoints follow :class:`Checkpointing`, the names
and semantics of :mod:`particles.dsmc` (``checkpoint`` path, ``checkpoint_every``
seconds of wall time, ``resume=True`` continues from the file if it exists,
``max_wall_time``).  The coarse-grained density fluctuation of rods in boxes of size
:math:`\\ell` is

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
from typing import Any, Mapping, Sequence

import numpy as np
from numpy.typing import NDArray
from tqdm.auto import tqdm

from kinetic_fem.distribution import RunInfo, VelocityDistribution

from . import _md_kernels as K
from ._jit import jit
from ._md_engine import EngineOptions, MDEngine
from .run import Checkpointing, ParticleRun
from .sampling import Accumulator, load_checkpoint, save_checkpoint

__all__ = ["MDRun", "Snapshot", "DensityFluctuations", "density_fluctuations",
           "box_square_sums", "BoxCounts", "RunPlan",
           "Checkpointing", "run_md", "json_params", "SERIES"]

logger = logging.getLogger(__name__)

SERIES = ("t", "collisions_per_particle", "temperature", "energy", "energy_injected",
          "energy_dissipated", "momentum", "elastic_fraction")


@dataclass(frozen=True)
class Snapshot:
    """Positions of the rods (left ends in ``[0, L)``) and their scaled velocities.

    Parameters
    ----------
    collisions_per_particle : float
        When the snapshot was taken.
    time : float
        Physical time.
    x : ndarray, shape (N,)
        Rod left ends in ``[0, L)``.
    c : ndarray, shape (N,)
        Scaled velocities :math:`v/\\sqrt{T}`.
    """

    collisions_per_particle: float
    time: float
    x: NDArray[np.float64]
    c: NDArray[np.float64]


@dataclass(frozen=True)
class DensityFluctuations:
    """Variance of the number of rods in boxes of size ``box_sizes``, over its mean.

    ``variance_ratio`` is 1 for independent points and :math:`(1 - n\\sigma)^2` for
    large boxes of equilibrium hard rods; clustering makes it grow.

    Parameters
    ----------
    box_sizes : ndarray, shape (k,)
        Box sizes (length units).
    mean_count : ndarray, shape (k,)
        Mean number of rods per box.
    variance_ratio : ndarray, shape (k,)
        Variance of that number over its mean.
    """

    box_sizes: NDArray[np.float64]
    mean_count: NDArray[np.float64]
    variance_ratio: NDArray[np.float64]


@dataclass(frozen=True)
class MDRun(ParticleRun):
    """Result of an MD run (the properties shared with DSMC: :class:`ParticleRun`).

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
    n_collisions, n_elastic, n_kicks, n_particles : int
        Binary collisions, those made elastic by the threshold, kicks; rods.
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
    n_particles: int
    info: RunInfo
    params: Mapping[str, Any] = field(default_factory=dict)

    @property
    def temperature(self) -> float:
        """Heated: the sampled temperature; cooling: the final temperature."""
        if self.params["problem"] == "heated":
            return self.distribution.temperature
        return float(self.series["temperature"][-1])

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
    ``2^k x m / L`` in floating point, so the counts are those of binning with ``m``
    (:func:`box_square_sums`, compiled).  Mean and variance/mean are then computed from
    the integer sums exactly and rounded once (the numpy ``mean``/``var`` calls per box
    number took 12 % of a heated run at N = 5000).

    Parameters
    ----------
    x : ndarray, shape (N,)
        Rod positions in ``[0, length)``.
    length : float
        Ring length ``L``.
    n_boxes : sequence of int
        Numbers of boxes ``m`` (box size ``L/m``).

    Returns
    -------
    ndarray, shape (k, 2)
    """
    return BoxCounts(n_boxes).fluctuations(x, length)


class BoxCounts:
    """The grouping of :func:`density_fluctuations`, worked out once for a run's samples.

    Parameters
    ----------
    n_boxes : sequence of int
        Numbers of boxes ``m``.
    """

    def __init__(self, n_boxes: Sequence[int]) -> None:
        boxes = [int(m) for m in n_boxes]
        finest: dict[int, int] = {}
        for m in boxes:
            odd = m // (m & -m)
            finest[odd] = max(finest.get(odd, 0), m)
        self.n_boxes = np.array(boxes, np.int64)
        # per odd factor: the finest count, the numbers of boxes and their rows
        self.groups = [(big, np.array([m for m in boxes if m // (m & -m) == odd], np.int64),
                        np.array([k for k, m in enumerate(boxes) if m // (m & -m) == odd],
                                 np.int64)) for odd, big in finest.items()]

    def fluctuations(self, x: NDArray[np.float64], length: float) -> NDArray[np.float64]:
        """Mean count and variance over mean per number of boxes, shape (k, 2)."""
        sq = np.empty(self.n_boxes.size, np.int64)
        for big, ms, rows in self.groups:
            sq[rows] = box_square_sums(x, big / length, big, ms)
        return self.from_square_sums(x.size, sq)

    def from_square_sums(self, n: int, sq: NDArray[np.int64]) -> NDArray[np.float64]:
        """Rows of :meth:`fluctuations` from the sums of squared counts ``sq``."""
        out = np.empty((self.n_boxes.size, 2))
        for k, (m, s2) in enumerate(zip(self.n_boxes.tolist(), sq.tolist(), strict=True)):
            # exact integers: mean n/m, variance/mean (m s2 - n^2)/(m n), one rounding each
            out[k] = n / m, (m * s2 - n * n) / (m * n)
        return out


@jit
def box_square_sums(x, scale, big, ms):  # pragma: no cover - compiled
    """:math:`\\sum_b c_b^2` of the counts per box for each number of boxes in ``ms``.

    ``x`` (shape (N,), in ``[0, L)``) is binned once into ``big`` boxes
    (``min(int(x scale), big - 1)``, ``scale = big / L``); each ``m`` in ``ms`` divides
    ``big`` and its counts are sums of ``big / m`` consecutive fine counts.  Returns
    int64, shape ``ms.shape``.
    """
    fine = np.zeros(big, np.int64)
    for i in range(x.shape[0]):
        b = int(x[i] * scale)
        fine[min(b, big - 1)] += 1
    out = np.zeros(ms.shape[0], np.int64)
    for k in range(ms.shape[0]):
        group = big // ms[k]
        total = 0
        for b in range(ms[k]):
            c = 0
            for q in range(b * group, (b + 1) * group):
                c += fine[q]
            total += c * c
        out[k] = total
    return out


@dataclass(frozen=True)
class RunPlan:
    """What a run samples and records, and when.

    Attributes
    ----------
    scaled : bool
        Free cooling: sample :math:`c = (v - u)/\\sqrt T` and space the records
        geometrically in collisions; else sample :math:`v - u` on a linear record grid.
    total, sample_from : int
        Collisions of the run, and from which sampling starts.
    n_samples, n_batches : int
        Samples at evenly spaced collision counts (unless :attr:`sample_dt`), and
        consecutive batches for error bars.
    hist_range, n_bins : float, int
        Histogram of the samples on ``[-hist_range, hist_range)``.
    snapshots_at : tuple of float
        Collisions per particle of x-c snapshots.
    n_records : int
        Points of the time series.
    box_counts : tuple of int
        Numbers of boxes of the density fluctuations.
    sample_dt : float, optional
        Sample every ``sample_dt`` of time from ``sample_from`` on (uniform in time:
        bursts of collisions inside clusters do not bias the average).
    """

    scaled: bool
    total: int
    sample_from: int
    n_samples: int
    n_batches: int
    hist_range: float
    n_bins: int
    snapshots_at: tuple[float, ...] = ()
    n_records: int = 200
    box_counts: tuple[int, ...] = (2,)
    sample_dt: float | None = None


def _schedule(n: int, plan: RunPlan) -> tuple[NDArray[np.int64], set, dict, set]:
    """Sorted collision counts at which the run stops, and what happens there."""
    total = plan.total
    if plan.scaled:
        rec = np.unique(np.geomspace(1, max(total, 1), plan.n_records).astype(np.int64))
    else:
        rec = np.unique(np.linspace(0, total, plan.n_records).astype(np.int64))
    rec = np.union1d(rec, [0, total])
    snaps = [int(round(s * n / 2)) for s in plan.snapshots_at]
    if plan.sample_dt is None:
        samples = np.unique(np.linspace(plan.sample_from, total, plan.n_samples).round()
                            .astype(np.int64))
        sample_at = {int(s): i for i, s in enumerate(samples)}
    else:  # timed samples start at sample_from
        samples, sample_at = np.array([plan.sample_from], np.int64), {}
    stops = np.unique(np.concatenate([rec, samples, np.asarray(snaps, np.int64)]))
    return stops, set(rec.tolist()), sample_at, set(snaps)


def run_md(params: dict[str, Any], *, seed: Any, y: NDArray, v: NDArray,
           rng: np.random.Generator, options: EngineOptions, plan: RunPlan,
           checkpointing: Checkpointing, progress: bool) -> MDRun:
    """Shared driver of :func:`~particles.md.simulate_heated` and ``simulate_cooling``.

    Samples are taken at ``plan.n_samples`` collision counts from ``plan.sample_from``
    on, or, with ``plan.sample_dt``, every ``sample_dt`` of time from ``sample_from``
    collisions on.  ``params`` (JSON-able) identify the run in checkpoints.
    """
    start = time.perf_counter()
    n, big_l = params["n_particles"], params["n_particles"] / params["density"]
    ck = checkpointing
    stops, rec_at, sample_at, snap_at = _schedule(n, plan)
    timed = plan.sample_dt is not None
    sample_dt = 0.0 if plan.sample_dt is None else plan.sample_dt
    n_batches, boxes = plan.n_batches, list(plan.box_counts)
    t_next, n_sampled = np.inf, 0
    eng = MDEngine(y, v, options, rng)
    acc = Accumulator(-plan.hist_range, plan.hist_range, plan.n_bins, n_batches)
    records: list[list[float]] = []
    snaps: list[Snapshot] = []
    dens = np.zeros((len(boxes), 2))
    p0, e0, _ = eng.moments()
    first, done, e0 = 0, None, 0.5 * e0
    ck.guard("md", ("params", json_params(params)))
    if ck.resume and ck.path is not None and ck.path.exists():
        current = {**eng.state(), **acc.state()}
        arrays, meta = load_checkpoint(
            ck.path, engine="md", like={k: current[k] for k in ("md_x", "md_v", "md_tl",
                                                                "acc_counts", "acc_sums")},
            nonnegative=("acc_counts",))
        eng.restore(arrays)
        acc.restore(arrays)
        rng.bit_generator.state = meta["rng"]
        records = arrays["records"].tolist()
        dens = arrays["dens"].copy()
        snaps = [Snapshot(float(m[0]), float(m[1]), sx, sc) for m, sx, sc in
                 zip(arrays["snap_meta"], arrays["snap_x"], arrays["snap_c"], strict=True)]
        done = int(meta["done"])
        first = int(np.searchsorted(stops, done, side="right"))
        e0, p0, t_next, n_sampled = meta["e0"], meta["p0"], meta["t_next"], meta["n_sampled"]
        logger.info("resumed from %s at %d collisions", ck.path, done)
    bar = tqdm(total=int(stops[-1]), initial=int(stops[first - 1]) if first else 0,
               disable=not progress, unit="coll", desc="MD")

    counts = BoxCounts(boxes)

    def take_sample(batch: int, at: float | None) -> None:
        nonlocal dens, n_sampled
        vel = eng.v
        s1, _, temp = eng.moments()
        u = s1 / n
        acc.add(batch, (vel - u) / math.sqrt(temp) if plan.scaled else vel - u)
        dens += counts.fluctuations(eng.rod_positions(at), big_l)
        n_sampled += 1

    def save() -> None:
        assert ck.path is not None  # save() runs only with a checkpoint path
        arrays = {**eng.state(), **acc.state(), "records": np.array(records),
                  "dens": dens, "snap_meta": np.array([[s.collisions_per_particle, s.time]
                                                       for s in snaps]).reshape(-1, 2),
                  "snap_x": np.array([s.x for s in snaps]).reshape(-1, n),
                  "snap_c": np.array([s.c for s in snaps]).reshape(-1, n)}
        save_checkpoint(ck.path, arrays, {
            "params": json_params(params), "rng": rng.bit_generator.state, "done": done,
            "e0": e0, "p0": p0, "t_next": t_next, "n_sampled": n_sampled}, engine="md")

    span = max(plan.total - plan.sample_from, 1)
    interrupted, last_save = False, start
    for idx in range(first, stops.size):
        target = int(stops[idx])
        if timed:
            while eng.advance(target, t_next):
                take_sample(min(n_batches - 1, (eng.n_collisions - plan.sample_from)
                                * n_batches // span), t_next)
                t_next += sample_dt
            if target == plan.sample_from and t_next == np.inf:
                t_next = float(eng.fstate[K.F_T]) + sample_dt
        else:
            eng.advance(target)
        bar.update(target - bar.n)
        vel, t = eng.v, float(eng.fstate[K.F_T])
        s1, s2, temp = eng.moments()
        u = s1 / n
        if target in rec_at:
            ncoll = max(eng.n_collisions, 1)
            records.append([t, 2.0 * target / n, temp, 0.5 * s2, float(eng.fstate[K.F_INJ]),
                            float(eng.fstate[K.F_DISS]), s1,
                            eng.istate[K.I_NELASTIC] / ncoll])
        if target in sample_at:
            take_sample(sample_at[target] * n_batches // len(sample_at), None)
        if target in snap_at:
            snaps.append(Snapshot(2.0 * target / n, t, eng.rod_positions(),
                                  (vel - u) / math.sqrt(temp)))
        done = target
        now = time.perf_counter()
        if ck.path is not None and now - last_save >= ck.every:
            save()
            last_save = now
        if ck.max_wall_time is not None and now - start >= ck.max_wall_time \
                and idx < stops.size - 1:
            interrupted = True
            break
    bar.close()
    if ck.path is not None and done is not None:
        save()
    return _result(params, seed, eng, acc, records, snaps, dens, n_sampled, e0, p0, big_l,
                   boxes, time.perf_counter() - start, interrupted)


def _result(params, seed, eng, acc, records, snaps, dens, n_sampled, e0, p0, big_l, boxes,
            wall, interrupted) -> MDRun:
    n = params["n_particles"]
    series = {name: np.array([r[k] for r in records]) for k, name in enumerate(SERIES)}
    n_sampled = max(1, n_sampled)
    fluct = DensityFluctuations(big_l / np.asarray(boxes, float), dens[:, 0] / n_sampled,
                                dens[:, 1] / n_sampled)
    balance = float(np.max(np.abs(series["energy"] - e0 - series["energy_injected"]
                                  + series["energy_dissipated"])) / np.max(series["energy"]))
    message = f"{eng.n_collisions} collisions ({2 * eng.n_collisions / n:.4g} per particle)"
    if interrupted:
        message = "interrupted (resume from the checkpoint) after " + message
    info = RunInfo(converged=not interrupted, iterations=eng.n_collisions, residual=balance,
                   wall_time=wall, message=f"{message} in {wall:.3g} s",
                   extra={"seed": None if seed is None else str(seed),
                          "n_kicks": int(eng.istate[K.I_NKICK]),
                          "n_elastic": int(eng.istate[K.I_NELASTIC]),
                          "momentum_drift": float(abs(np.sum(eng.v) - p0)),
                          "collisions_per_second": eng.n_collisions / max(wall, 1e-12)})
    if not acc.filled().any():
        raise RuntimeError(f"MD run stopped before any sample was taken ({info.message}); "
                           "resume it from the checkpoint (resume=True) or allow more wall "
                           "time")
    dist = acc.distribution(method="md", params=params, info=info, series=series)
    logger.info("MD %s: %s", params["problem"], info.message)
    return MDRun(distribution=dist, series=series, snapshots=tuple(snaps),
                 density_fluctuations=fluct, positions=eng.rod_positions(),
                 velocities=eng.v.copy(), n_collisions=eng.n_collisions,
                 n_elastic=int(eng.istate[K.I_NELASTIC]), n_kicks=int(eng.istate[K.I_NKICK]),
                 n_particles=int(n), info=info, params=params)


def json_params(params: Mapping[str, Any]) -> dict[str, Any]:
    """Parameters as JSON-comparable values (for checkpoint checks)."""
    return {k: (list(v) if isinstance(v, tuple) else v) for k, v in params.items()}
