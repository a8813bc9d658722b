"""Event-driven molecular dynamics of inelastic hard rods on a ring.

``N`` rods of length :math:`\\sigma` on a ring of length :math:`L = N/n`
(:math:`n\\sigma < 1`) move freely between binary collisions

.. math::

    v_1' + v_2' = v_1 + v_2, \\qquad v_1' - v_2' = -a\\,(v_1 - v_2),

with :math:`a = \\alpha(|v_1 - v_2|)` of the restitution law (a constant
:math:`\\alpha`, or a :mod:`kinetic_fem.model` law:
:class:`~kinetic_fem.model.ThresholdRestitution`,
:class:`~kinetic_fem.model.ViscoelasticRestitution`; evaluated in the kernel by
:func:`kinetic_fem.model.restitution_value`, the one implementation every method
uses), or :math:`a = 1` (elastic) when the relative speed is below ``threshold`` (the
regularisation of inelastic collapse of Ben-Naim et al., PRL 83, 4069 (1999)).  The
regularisation composes with a law: below ``threshold`` a collision is elastic, above
it the law applies; a :class:`~kinetic_fem.model.ThresholdRestitution` law with its
own threshold ``s`` is thus elastic below ``max(threshold, s)`` (both counted in
``n_elastic``).  MD is hard rods by physics: the collision rate of a pair is its
relative speed, kernel :math:`\\gamma = 1`; other kernels raise
:class:`~kinetic_fem.model.UnsupportedModelError` (use :mod:`particles.dsmc`).

Heated runs kick every rod every ``kick_interval`` :math:`\\Delta t_k`:

* white noise of strength :math:`D` (``friction=0``, the paper):
  :math:`v_i \\to v_i + \\sqrt{2 D \\Delta t_k}\\,\\xi_i`, a discretisation that
  converges as :math:`\\Delta t_k \\to 0`;
* a Fokker-Planck (Langevin) bath with friction :math:`\\xi` (``friction > 0``) and
  bath temperature :math:`T_b = D/\\xi`: the exact Ornstein-Uhlenbeck transition over
  the interval, :math:`v_i \\to v_i e^{-\\xi\\Delta t_k} + \\sqrt{T_b(1 -
  e^{-2\\xi\\Delta t_k})}\\,\\xi_i`, so only the splitting of collisions and bath is
  approximate.  Elastic rods (``alpha=1``) in a bath relax to the Gaussian at
  :math:`T_b` exactly.

Both act on each rod independently in the lab frame: under white noise the total
momentum performs a random walk (variance :math:`2 D N t`), in a bath it is an
Ornstein-Uhlenbeck process around 0.  Velocities are sampled relative to the
instantaneous mean velocity and moments are central, so neither enters the
distribution; ``series["momentum"]`` records it.

In one dimension a rod of length :math:`\\sigma` is a point on the *reduced ring* of
length :math:`L - N\\sigma` (subtract :math:`i\\sigma` from the ``i``-th rod's
position): the dynamics is event-driven and exact on that ring, with one predicted
collision time per neighbour pair in an indexed heap (:mod:`particles._md_kernels`).
The collision frequency is therefore that of points at the density
:math:`n/(1 - n\\sigma)` (the exact 1D Enskog factor); the model's scales
(:meth:`kinetic_fem.model.HeatedProblem.temperature_estimate`, the Gaussian closure of
the energy balance) are taken at that density.

Time unit of a run: *collisions per particle*, ``2 * n_collisions / N`` (the mean
number of collisions each rod has suffered).  Heated runs are sampled uniformly
in time after the warm-up (inside clusters bursts of collisions happen in very little
time); cooling runs at evenly spaced collision counts of the requested window.
Checkpoints: ``checkpoint``, ``checkpoint_every`` (seconds), ``resume``,
``max_wall_time``, as in :mod:`particles.dsmc`.

Defaults and their checks (``benchmarks/bench_md.py``): kicks every 0.1 mean free
times (and at most 0.1/xi in a bath).  The kick-interval study (``--part kicks``:
N = 5000, n sigma = 0.5, 2000 collisions per particle per run, 12-48 seeds per
interval, dt_k/tau = 0.025 ... 0.4; white noise) resolves no dependence at alpha =
0.99 and 0.9 (linear slopes of T/T_Sonine and a2 within 0.9 and 1.8 standard errors;
at 0.1 tau the bias is at most 0.0008 in T/T_Sonine and 0.0006 in a2 at alpha = 0.99,
0.006 and 0.009 at alpha = 0.9, two-sigma bounds, against standard deviations of one
run of 0.006, 0.007 and 0.044, 0.035).  At alpha = 0.6 and 0.3, where clusters
collapse between kicks and the threshold makes half the collisions elastic, T
decreases linearly in dt_k (slopes -0.25 +- 0.07 and -0.38 +- 0.07 in T/T_Sonine per
mean free time, first order): at 0.1 tau T is low by 1.5% and 2% (a third and a half
of the standard deviation of one such run), a2 unchanged within errors.  0.2 tau
would reach one standard deviation at alpha = 0.3; take a shorter ``kick_interval``
(or extrapolate) for precision studies of T at strong inelasticity.  Heated threshold
0.01 thermal speeds (it never acts at alpha >= 0.9; at alpha = 0.6, 0.01 ... 0.1 give
a2 equal within errors).  In a bath the splitting of collisions and kicks is the
only approximation: at alpha = 0.95, xi = D = 1 (N = 2000, 6 seeds of 800 collisions
per particle) the default and a quarter of it give T = 0.9046 +- 0.0016 and
0.9050 +- 0.0008, a2 = -0.0116 +- 0.0009 and -0.0117 +- 0.0008 (FEM: 0.9054, -0.0121);
at alpha = 0.6 with xi about the collision rate, 2, 1 and 1/4 times the default give
T = 1.2005, 1.2080, 1.2127 (+- 0.003) and a2 = 0.037, 0.029, 0.027 (+- 0.002): the
default is about 0.5 % low in T and 0.002-0.006 high in a2 there.  Plain inelastic
dynamics collapses for large N (1 - alpha); the collapse is detected and raised as
:class:`InelasticCollapseError`.
"""

from __future__ import annotations

import logging
import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike

from kinetic_fem.model import (
    HeatedProblem,
    InelasticGas,
    PowerLawKernel,
    RestitutionLaw,
    check_positive,
)
from kinetic_fem.progress import resolve_progress

from ._md_engine import EngineOptions, InelasticCollapseError, Kicks, MDEngine
from ._md_run import (
    Checkpointing,
    DensityFluctuations,
    MDRun,
    RunPlan,
    Snapshot,
    density_fluctuations,
    run_md,
)
from .rods import (
    check_geometry,
    check_sample_interval,
    hard_rods,
    initial_state,
    mean_free_time,
)
from .run import check_measurements, check_memory, check_seed, check_work

__all__ = ["simulate_heated", "simulate_cooling", "MDRun", "Snapshot", "DensityFluctuations",
           "InelasticCollapseError", "initial_state", "density_fluctuations",
           "mean_free_time", "hard_rods", "MDEngine", "EngineOptions", "Kicks",
           "KICK_FRACTION", "HEATED_THRESHOLD", "LAW_SPEED_SPAN"]

logger = logging.getLogger(__name__)

KICK_FRACTION = 0.1
"""Default kick interval, in estimated mean free times (and in 1/xi in a bath)."""
MAX_KICK_INTERVAL = 10.0
"""Largest kick interval of heated runs, in estimated mean free times."""
_BYTES_PER_ROD = 160
"""Arrays per rod of an MD run (positions, velocities, event calendar), for the check."""
_BYTES_PER_RECORD = 600
"""Memory of one record of the time series (its place in the schedule and the set of
stops, its row of 8 floats as a Python list, the series arrays and checkpoint copy)."""
_BYTES_PER_SAMPLE_POINT = 200
"""Memory of one sample point of a cooling run (its collision count in the schedule arrays
and in the dict of sample points)."""
HEATED_THRESHOLD = 1e-2
"""Default threshold of heated runs, in units of the estimated thermal speed."""
LAW_SPEED_SPAN = 10.0
"""Relative speeds a heated run's restitution law must cover, in units of
:math:`\\sqrt{2T_{est}}` (the spread of :math:`g` between Gaussian velocities)."""


def _common(n_particles, density, sigma, collisions_per_particle, n_samples, n_batches,
            n_bins, n_records, box_counts, collapse_tol, max_stall):
    n, sig = check_geometry(n_particles, density, sigma)
    cpp = check_positive("collisions_per_particle", collisions_per_particle)
    for name, val in (("n_samples", n_samples), ("n_batches", n_batches), ("n_bins", n_bins),
                      ("n_records", n_records)):
        if isinstance(val, bool) or not isinstance(val, (int, np.integer)) or val < 1:
            raise ValueError(f"{name} must be a positive int, got {val!r}")
    if n_samples < n_batches:
        raise ValueError(f"n_samples={n_samples} must be >= n_batches={n_batches}")
    if box_counts is None:
        box_counts = [2**k for k in range(1, int(math.log2(max(n // 4, 2))) + 1)]
    boxes = tuple(box_counts)
    for m in boxes:
        if isinstance(m, bool) or not isinstance(m, (int, np.integer)) or not 1 <= m <= n:
            raise ValueError(f"box_counts must be integers in [1, n_particles={n}] (numbers "
                             f"of boxes for the density fluctuations), got {m!r}")
    check_positive("collapse_tol", collapse_tol)
    stall = 100 * n + 100_000 if max_stall is None else int(max_stall)
    check_work(0.5 * n * cpp, f"collisions_per_particle={cpp:g} with N={n}")
    check_memory(_BYTES_PER_ROD * n, f"MD of N={n}")
    return n, sig, cpp, tuple(int(m) for m in boxes), stall


def _check_stops(n: int, samples: float, sample_bytes: float, given: str, n_records: int,
                 n_snapshots: int) -> None:
    """Refuse up front the stops of a run beyond ``MAX_EVENTS`` or the available memory.

    Each sample, record and snapshot reads the N rods (``N + MEASUREMENT_EVENTS`` events,
    :func:`particles.run.check_measurements`); beside the rods' arrays, a sample point
    costs ``sample_bytes``, a record ``_BYTES_PER_RECORD``, a snapshot its ``16 N`` bytes
    of positions and velocities.

    Parameters
    ----------
    n : int
        Rods.
    samples : float
        Planned samples (an estimate for samples uniform in time).
    sample_bytes : float
        Memory of one sample point.
    given : str
        The arguments that set ``samples``, for the message.
    n_records, n_snapshots : int
        Records of the time series and snapshots asked for.
    """
    n_bytes = (_BYTES_PER_ROD * n + samples * sample_bytes + n_records * _BYTES_PER_RECORD
               + n_snapshots * (16.0 * n + _BYTES_PER_RECORD))
    check_measurements(samples + n_records + n_snapshots, n, n_bytes,
                       f"MD of N={n} with {given}, n_records={n_records} and "
                       f"len(snapshots_at)={n_snapshots}",
                       "take fewer samples, records or snapshots")


def _check_snapshots(snapshots_at: Sequence[float], cpp: float) -> tuple[float, ...]:
    snaps = tuple(snapshots_at)
    for s in snaps:
        if (isinstance(s, bool) or not isinstance(s, (int, float, np.integer, np.floating))
                or not 0.0 <= s <= cpp):
            raise ValueError(f"snapshots_at must hold numbers of collisions per particle in "
                             f"[0, collisions_per_particle={cpp:g}], got {s!r}")
    return tuple(float(s) for s in snaps)


def _seeded(seed: Any) -> np.random.Generator:
    seed = check_seed(seed)
    ss = seed if isinstance(seed, np.random.SeedSequence) else np.random.SeedSequence(seed)
    return np.random.default_rng(ss)


def simulate_heated(alpha: float | RestitutionLaw, n_particles: int, *, density: float = 1.0,
                    sigma: float | None = None, diffusion: float = 1.0, friction: float = 0.0,
                    kernel: float | PowerLawKernel = 1.0, seed: Any = None,
                    collisions_per_particle: float = 200.0, warmup: float | None = None,
                    kick_interval: float | None = None, threshold: float | None = None,
                    sample_interval: float = 1.0, n_batches: int = 10, n_bins: int = 240,
                    snapshots_at: Sequence[float] = (), n_records: int = 200,
                    box_counts: Sequence[int] | None = None, positions: ArrayLike | None = None,
                    velocities: ArrayLike | None = None, progress: bool | None = None,
                    checkpoint: str | Path | None = None, checkpoint_every: float = 300.0,
                    resume: bool = False, max_wall_time: float | None = None,
                    collapse_tol: float = 1e-12, max_stall: int | None = None) -> MDRun:
    """Heated inelastic rods: random kicks every ``kick_interval``, sampled steady state.

    Parameters
    ----------
    alpha : float or RestitutionLaw
        Restitution coefficient in ``[0, 1]`` (1 only with ``friction > 0``) or a law
        of :mod:`kinetic_fem.model`.
    n_particles : int
        Number of rods N >= 2.
    density, sigma : float
        n = N/L and rod length (default ``0.5/density``, i.e. n sigma = 0.5 as in the
        paper); n sigma < 1.
    diffusion, friction : float
        Noise strength D > 0 and friction xi >= 0: white noise (each kick adds
        :math:`\\sqrt{2 D \\Delta t_k}\\,\\xi`) for ``friction=0``, else the
        Fokker-Planck bath at :math:`T_b = D/\\xi` (exact Ornstein-Uhlenbeck kicks).
    kernel : float or PowerLawKernel
        Must be hard rods (1): MD has no other collision rate.
    seed : int or SeedSequence, optional
        Root of every random stream (initial state, kicks).
    collisions_per_particle : float
        Run length in collisions per particle (``2 * collisions / N``).
    warmup : float, optional
        Collisions per particle before sampling starts (default half the run).
    kick_interval : float, optional
        :math:`\\Delta t_k`; default ``KICK_FRACTION`` (0.1) estimated mean free times
        (:func:`mean_free_time` at the model's temperature estimate for the density
        :math:`n/(1-n\\sigma)`), and at most ``KICK_FRACTION / friction``.  Its bias
        is below the statistical error of a run of 2000 collisions per particle at
        N = 5000 (module docstring).
    threshold : float, optional
        Collisions with relative speed below it are elastic; default
        ``HEATED_THRESHOLD`` (1e-2) times the estimated thermal speed.  Between kicks
        clusters can collapse; the threshold keeps runs finite.  It only acts at
        strong inelasticity (no elastic collision at alpha >= 0.9); at alpha = 0.6
        thresholds 1e-2 ... 1e-1 give the same T and a2, while below ~3e-3 collapsing
        clusters eat most collisions with time hardly advancing
        (``benchmarks/bench_md.py --part threshold``).  Composes with a law (module
        docstring).
    sample_interval : float
        Time between samples (all N velocities and positions each), in estimated mean
        free times; sampling is uniform in time after the warm-up.  At least
        ``1e-12 * collisions_per_particle``; the planned samples, about
        ``(collisions_per_particle - warmup) / sample_interval``, records and snapshots
        count ``N + 5000`` events each against ``particles.run.MAX_EVENTS``.
    n_batches, n_bins : int
        Batches for error bars (consecutive stretches of the sampling period) and
        histogram bins on :math:`\\pm 12\\sqrt{T_{est}}`.
    snapshots_at : sequence of float
        Collisions per particle of x-c snapshots.
    n_records : int
        Points of the time series (linear in collisions), a positive int.
    box_counts : sequence of int, optional
        Numbers of boxes for the density fluctuations (default 2, 4, ..., N/4).
    positions, velocities : array_like, optional
        Initial rod left ends and velocities (default random, Gaussian at the
        temperature estimate).
    progress : bool, optional
        tqdm progress bar; default (None): shown when the session is interactive (a
        terminal or a notebook).
    checkpoint, checkpoint_every, resume : path, float, bool
        Write the state every ``checkpoint_every`` seconds (at the next record or
        sample) and at the end; with ``resume=True`` continue from the file if it
        exists (bit-identical).  As in :func:`particles.dsmc.simulate_heated`.
    max_wall_time : float, optional
        Stop after this many seconds (checkpoint written; ``info.message`` says so).
    collapse_tol, max_stall : float, int
        Inelastic collapse is reported when a collision slower than
        ``collapse_tol * sqrt(T)`` is inelastic, or after ``max_stall`` (default
        100 N + 1e5) consecutive collisions without time advancing.

    Returns
    -------
    MDRun
        ``series["energy_injected"]`` is the net energy the thermostat gave (a bath's
        friction also takes energy out).

    Raises
    ------
    UnsupportedModelError
        For a kernel other than hard rods.
    ValueError
        For invalid parameters, alpha = 1 under white noise (no steady state), or a
        restitution law whose range does not cover the run's relative speeds.
    InelasticCollapseError
        With advice on the regularisation.

    Examples
    --------
    >>> run = simulate_heated(0.9, 200, seed=1, collisions_per_particle=20.0)
    >>> bool(run.energy_balance_error < 1e-10)
    True
    >>> bath = simulate_heated(1.0, 200, friction=1.0, seed=1, collisions_per_particle=20.0)
    >>> bath.params["friction"], bool(abs(bath.temperature - 1.0) < 0.2)  # T_b = D/xi = 1
    (1.0, True)
    """
    problem = HeatedProblem.from_parameters(alpha, density=density, diffusion=diffusion,
                                            friction=friction, kernel=hard_rods(kernel))
    gas, law = problem.gas, problem.gas.restitution
    n, sig, cpp, boxes, stall = _common(
        n_particles, gas.density, sigma, collisions_per_particle, n_batches, n_batches,
        n_bins, n_records, box_counts, collapse_tol, max_stall)
    ck = Checkpointing.from_arguments(checkpoint, checkpoint_every, resume, max_wall_time)
    dens = gas.density
    # the model's scales at the collision density of the reduced ring (Enskog factor)
    free_gas = InelasticGas(law, dens / (1.0 - dens * sig), gas.kernel)
    t_est = HeatedProblem(free_gas, problem.thermostat).temperature_estimate()
    tau = mean_free_time(t_est, dens, sig)
    if kick_interval is None:
        dt_k = KICK_FRACTION * (min(tau, 1.0 / problem.friction) if problem.friction > 0
                                else tau)
    else:
        dt_k = check_positive("kick_interval", kick_interval)
        if dt_k > MAX_KICK_INTERVAL * tau:
            raise ValueError(f"kick_interval={dt_k:g} is {dt_k / tau:.3g} mean free times; at "
                             f"most {MAX_KICK_INTERVAL:g} (<= {MAX_KICK_INTERVAL * tau:.4g}) "
                             "are allowed: rarer kicks do not model the white noise (default "
                             f"{KICK_FRACTION:g} mean free times)")
    warm = 0.5 * cpp if warmup is None else float(warmup)
    if not 0.0 <= warm < cpp:
        raise ValueError(f"warmup={warmup!r} must lie in [0, collisions_per_particle)")
    every, samples = check_sample_interval(sample_interval, cpp, warm)
    snaps = _check_snapshots(snapshots_at, cpp)
    # samples are accumulated, not kept: they cost work only
    _check_stops(n, samples, 0.0, f"sample_interval={every:g} (about {samples:.3g} samples "
                 f"in collisions_per_particle - warmup = {cpp - warm:g} mean free times)",
                 n_records, len(snaps))
    sample_dt = every * tau
    thr = (HEATED_THRESHOLD * math.sqrt(t_est) if threshold is None
           else check_positive("threshold", threshold))
    logger.info("heated MD %r N=%d: T_est %.4g, kick interval %.4g (%.3g mean free times), "
                "threshold %.3g (%.2g thermal speeds)", law, n, t_est, dt_k, dt_k / tau, thr,
                thr / math.sqrt(t_est))
    rng = _seeded(seed)
    y, v = initial_state(n, density=dens, sigma=sig, temperature=t_est, rng=rng,
                         positions=positions, velocities=velocities)
    law.check_speed(max(LAW_SPEED_SPAN * math.sqrt(2.0 * t_est), float(np.ptp(v))),
                    where=f"the heated run (relative speeds up to {LAW_SPEED_SPAN:g} "
                          f"sqrt(2 T) at the estimated T = {t_est:.4g}, or the initial state)")
    params = {**problem.as_dict(), "n_particles": n, "sigma": sig, "kick_interval": dt_k,
              "threshold": thr, "collisions_per_particle": cpp, "warmup": warm,
              "seed": None if seed is None else str(seed)}
    options = EngineOptions(n / dens - n * sig, sig, law, thr,
                            Kicks.from_thermostat(problem.thermostat, dt_k), collapse_tol, stall)
    plan = RunPlan(scaled=False, total=int(round(cpp * n / 2)),
                   sample_from=int(round(warm * n / 2)), n_samples=n_batches,
                   n_batches=n_batches, hist_range=12.0 * math.sqrt(t_est), n_bins=n_bins,
                   snapshots_at=snaps, n_records=int(n_records), box_counts=boxes,
                   sample_dt=sample_dt)
    return run_md(params, seed=seed, y=y, v=v, rng=rng, options=options, plan=plan,
                  checkpointing=ck, progress=resolve_progress(progress))


def simulate_cooling(alpha: float | RestitutionLaw, n_particles: int, *, density: float = 1.0,
                     sigma: float | None = None, threshold: float | None = None,
                     kernel: float | PowerLawKernel = 1.0, seed: Any = None,
                     collisions_per_particle: float = 100.0,
                     snapshots_at: Sequence[float] = (), sample_from: float | None = None,
                     n_samples: int = 50, n_batches: int = 10, n_bins: int = 160,
                     c_max: float = 8.0, n_records: int = 200,
                     box_counts: Sequence[int] | None = None, temperature0: float = 1.0,
                     positions: ArrayLike | None = None, velocities: ArrayLike | None = None,
                     progress: bool | None = None, checkpoint: str | Path | None = None,
                     checkpoint_every: float = 300.0, resume: bool = False,
                     max_wall_time: float | None = None, collapse_tol: float = 1e-12,
                     max_stall: int | None = None) -> MDRun:
    """Freely cooling inelastic rods, plain or threshold-regularised.

    Parameters
    ----------
    alpha : float or RestitutionLaw
        Restitution coefficient, ``0 <= alpha <= 1`` (1: elastic, P(v) frozen, C17),
        or a law of :mod:`kinetic_fem.model`.
    threshold : float, optional
        None: plain inelastic dynamics (collapse is detected and raised).  A float:
        collisions with relative speed below it are elastic (Ben-Naim et al.);
        composes with a law (module docstring).
    kernel : float or PowerLawKernel
        Must be hard rods (1).
    sample_from : float, optional
        Collisions per particle from which scaled velocities
        :math:`c = (v - u)/\\sqrt{T}` are sampled (default half the run).
    c_max : float
        Histogram range :math:`|c| \\le c_{max}`.
    temperature0 : float
        Initial temperature (Gaussian velocities, zero momentum).
    density, sigma, seed, collisions_per_particle, snapshots_at, n_samples, n_batches, \
n_bins, n_records, box_counts, positions, velocities, progress, checkpoint, \
checkpoint_every, resume, max_wall_time, collapse_tol, max_stall
        As in :func:`simulate_heated`.

    Returns
    -------
    MDRun
        The run; its distribution is that of the scaled velocity ``c``.

    Notes
    -----
    Records are spaced geometrically in collisions.  Free cooling never widens the
    range of velocities (every collision maps the pair into the interval between
    them), so a restitution law is checked once, on the initial velocities.

    Examples
    --------
    >>> run = simulate_cooling(0.99, 100, seed=2, collisions_per_particle=50.0)
    >>> bool(run.temperature < 1.0 and abs(run.series["momentum"][-1]) < 1e-10)
    True
    """
    gas = InelasticGas(alpha, density, hard_rods(kernel))
    law = gas.restitution
    n, sig, cpp, boxes, stall = _common(
        n_particles, gas.density, sigma, collisions_per_particle, n_samples, n_batches,
        n_bins, n_records, box_counts, collapse_tol, max_stall)
    ck = Checkpointing.from_arguments(checkpoint, checkpoint_every, resume, max_wall_time)
    thr = 0.0 if threshold is None else check_positive("threshold", threshold)
    start = 0.5 * cpp if sample_from is None else float(sample_from)
    if not 0.0 <= start <= cpp:
        raise ValueError(f"sample_from={sample_from!r} must lie in [0, collisions_per_particle]")
    snapshots_at = _check_snapshots(snapshots_at, cpp)
    _check_stops(n, n_samples, _BYTES_PER_SAMPLE_POINT, f"n_samples={n_samples}", n_records,
                 len(snapshots_at))
    rng = _seeded(seed)
    dens = gas.density
    y, v = initial_state(n, density=dens, sigma=sig, rng=rng, positions=positions,
                         temperature=check_positive("temperature0", temperature0),
                         velocities=velocities)
    law.check_speed(float(np.ptp(v)), where="the initial velocities (max - min)")
    params = {"problem": "cooling", **gas.as_dict(), "n_particles": n, "sigma": sig,
              "threshold": threshold, "collisions_per_particle": cpp, "sample_from": start,
              "seed": None if seed is None else str(seed)}
    options = EngineOptions(n / dens - n * sig, sig, law, thr, Kicks(), collapse_tol, stall)
    plan = RunPlan(scaled=True, total=int(round(cpp * n / 2)),
                   sample_from=int(round(start * n / 2)), n_samples=n_samples,
                   n_batches=n_batches, hist_range=c_max, n_bins=n_bins,
                   snapshots_at=tuple(float(s) for s in snapshots_at), n_records=int(n_records),
                   box_counts=boxes)
    return run_md(params, seed=seed, y=y, v=v, rng=rng, options=options, plan=plan,
                  checkpointing=ck, progress=resolve_progress(progress))
