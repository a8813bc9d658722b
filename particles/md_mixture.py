"""Event-driven MD of a granular mixture: hard rods of several masses on a ring.

The rods of :mod:`particles.md` (length :math:`\\sigma`, ``N`` of them at density
:math:`n` on a ring, exact event-driven dynamics on the reduced ring), ``N x_s`` of
species :math:`s` with mass :math:`m_s`, placed in random order along the ring (rods
never pass: a rod keeps its neighbours' species).  A collision of rods ``i`` (left)
and ``j`` at relative velocity :math:`g = v_i - v_j > 0` is the mixture rule of
:mod:`kinetic_fem.model.mixture`,

.. math::

    v_i' = v_i - \\mu_{ij}(1 + a)\\,g, \\qquad v_j' = v_j + \\mu_{ji}(1 + a)\\,g,
    \\qquad \\mu_{ij} = \\frac{m_j}{m_i + m_j},

with :math:`a = \\alpha_{s_i s_j}(g)` (the pair's restitution law, a constant or any law
of :mod:`kinetic_fem.model` in the heated state), or :math:`a = 1` below
``threshold`` (the Ben-Naim et al. regularisation, as in :mod:`particles.md`).  Momentum
:math:`\\sum_i m_i v_i` is conserved and each collision loses
:math:`\\tfrac12 m_{ij}(1 - a^2) g^2` (:math:`m_{ij} = m_i m_j/(m_i + m_j)`).

* **Heated** (every species forced): each rod is kicked every ``kick_interval``,
  :math:`v_i \\to v_i + \\sqrt{2 D_{s_i}\\Delta t_k}\\,\\xi_i` under white noise, or the
  exact Ornstein-Uhlenbeck step of a bath :math:`(\\xi, D_s)` (one friction for every
  species).  Sampled uniformly in time after ``warmup``, velocities relative to the
  centre-of-mass velocity :math:`u = \\sum m_i v_i / \\sum m_i` (under white noise it
  performs a random walk).
* **Free cooling**: plain (collapse raised) or threshold-regularised dynamics, sampled at
  evenly spaced collision counts after ``sample_from``, velocities scaled to the mixture
  temperature :math:`T = \\sum_i m_i (v_i - u)^2 / N = 1`.  The cooling rate of the
  convention :math:`dT/dt = -2\\zeta n T^{3/2}` follows from
  :math:`d\\,T^{-1/2}/dt = \\zeta n_f` between samples, with :math:`n_f = n/(1 - n\\sigma)`
  the density of the points on the reduced ring (the collision density of the rods): so
  ``zeta`` is comparable with the Boltzmann equation's (DSMC, theory).

The result is a :class:`particles.dsmc_mixture.MixtureRun`, as for DSMC: one
distribution per species (in free cooling of the scaled velocities), the species
temperatures :math:`T_s = m_s\\langle (v - u)^2\\rangle_s` per batch (consecutive
stretches of the sampling period) with their standard errors.  The kernel is the one of
:mod:`particles.md` (:func:`particles._md_kernels.run_events`), given the species
arrays; the one-species MD is unchanged by them.  Hard rods only (:math:`\\gamma = 1`);
a run whose relative speeds leave a law's range stops with a ``ValueError``.
"""

from __future__ import annotations

import logging
import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from kinetic_fem.distribution import RunInfo
from kinetic_fem.model import check_positive
from kinetic_fem.model.mixture import Mixture
from kinetic_fem.model.restitution import ConstantRestitution
from kinetic_fem.model.validation import UnsupportedModelError
from kinetic_fem.solvers import mixture_gaussian

from ._md_engine import EngineOptions, Kicks, MDEngine, MixtureRods
from ._md_kernels import F_T
from .dsmc_mixture import MixtureRun, species_counts
from .md import _BYTES_PER_ROD, HEATED_THRESHOLD, KICK_FRACTION
from .rods import check_geometry, check_sample_interval, hard_rods, initial_state
from .run import check_measurements, check_seed, check_work
from .sampling import Accumulator

__all__ = ["simulate_mixture"]

logger = logging.getLogger(__name__)

_SAMPLE_OVERHEAD = 300
"""Memory of one kept sample beyond its N velocities (the array object and its list entry,
free cooling's (time, temperature) and schedule entry)."""


def _mean_relative_speed(mixture: Mixture, temperatures: NDArray[np.float64]) -> float:
    """:math:`\\sum_{sr} x_s x_r \\langle|g|\\rangle_{sr}` of Gaussian species."""
    var = temperatures / np.asarray(mixture.masses)
    x = np.asarray(mixture.fractions)
    pair = np.sqrt(2.0 * (var[:, None] + var[None, :]) / math.pi)
    return float(x @ pair @ x)


def _estimate(mixture: Mixture, density: float) -> NDArray[np.float64]:
    """The species' temperatures of the Gaussian theory (the time scales and default
    threshold of a run): with restitution laws, each pair's law at the mean relative
    speed of a first estimate at the laws' values at unit speed, then once more."""
    if not mixture.heated:
        return mixture_gaussian.cooling_state(mixture, density=density).temperatures
    if all(law.constant is not None for row in mixture.laws for law in row):
        return mixture_gaussian.steady_state(mixture, density=density).temperatures
    masses = np.asarray(mixture.masses)
    speed = np.ones((mixture.n_species,) * 2)
    for _ in range(2):
        table = [[float(law(min(speed[s, r], 0.5 * law.max_speed)))
                  for r, law in enumerate(row)] for s, row in enumerate(mixture.laws)]
        surrogate = Mixture(mixture.masses, mixture.fractions, alpha=table,
                            kernel=mixture.collision_kernel, thermostats=mixture.thermostats)
        temps = mixture_gaussian.steady_state(surrogate, density=density).temperatures
        var = temps / masses
        speed = np.sqrt(2.0 * (var[:, None] + var[None, :]) / math.pi)
    return temps


def simulate_mixture(mixture: Mixture, n_particles: int, *, density: float = 1.0,
                     sigma: float | None = None, seed: Any = None,
                     collisions_per_particle: float = 200.0, warmup: float | None = None,
                     kick_interval: float | None = None, threshold: float | None = None,
                     sample_interval: float = 1.0, n_samples: int = 50,
                     n_batches: int = 10, n_bins: int = 200, c_max: float = 10.0
                     ) -> MixtureRun:
    """MD steady state (forced species) or scaled cooling state of a mixture of rods.

    Parameters
    ----------
    mixture : Mixture
        Hard rods (kernel 1), a restitution law per pair (constant coefficients in free
        cooling); white noise per species, or a bath with one friction for all species;
        or free cooling.
    n_particles : int
        Rods in all; ``n_particles * x_s`` must be whole numbers, at least 2 each.
    density, sigma : float
        :math:`n` and the rod length (default ``0.5/density``); :math:`n\\sigma < 1`.
    seed : int or SeedSequence, optional
        The same seed gives the same run.
    collisions_per_particle : float
        Run length, in collisions per rod (``2 * collisions / N``).
    warmup : float, optional
        Collisions per rod before sampling (default half the run); in free cooling the
        first sample is taken there.
    kick_interval : float, optional
        Heated: time between kicks; default ``KICK_FRACTION`` (0.1) mean free times of
        the Gaussian estimate of the state (and at most 0.1/xi in a bath).
    threshold : float, optional
        Collisions slower than it are elastic.  Heated default ``HEATED_THRESHOLD``
        (1e-2) times the largest estimated thermal speed :math:`\\sqrt{T_s/m_s}`; free
        cooling default None (plain dynamics: inelastic collapse is raised).
    sample_interval : float
        Heated: time between samples, in mean free times (measured over the warm-up;
        without one, the Gaussian estimate), at least ``1e-12 *
        collisions_per_particle``.  Every sample's N velocities are kept: about
        ``(collisions_per_particle - warmup) / sample_interval`` samples (free cooling:
        ``n_samples``) must fit in the memory and ``particles.run.MAX_EVENTS`` (``N +
        5000`` events each).
    n_samples : int
        Free cooling: samples (evenly spaced in collisions from ``warmup`` to the end), more
        than ``n_batches`` (each batch's cooling rate needs an interval between samples).
    n_batches, n_bins, c_max : int, int, float
        Batches of the error bars (>= 2), histogram bins per species and the histogram
        range in units of the species' standard deviation at the first sample.

    Returns
    -------
    MixtureRun
        ``collision_counts`` per pair of species; ``zeta`` in free cooling.

    Raises
    ------
    UnsupportedModelError
        For a kernel other than hard rods, a velocity-dependent restitution law in free
        cooling, or baths of different frictions.
    ValueError, TypeError
        For invalid parameters (naming the parameter).
    InelasticCollapseError
        As :mod:`particles.md` (regularise with ``threshold``).

    Examples
    --------
    >>> from kinetic_fem import Mixture
    >>> mix = Mixture.white_noise((1.0, 4.0), (0.5, 0.5), alpha=0.9)
    >>> run = simulate_mixture(mix, 200, seed=1, collisions_per_particle=40.0)
    >>> run.temperatures.shape, bool(run.temperature_ratio() < 1.0)
    ((2,), True)
    """
    if not isinstance(mixture, Mixture):
        raise TypeError(f"mixture must be a kinetic_fem.Mixture, got {mixture!r}")
    hard_rods(mixture.collision_kernel)
    constant = all(law.constant is not None for row in mixture.laws for law in row)
    if not (constant or mixture.heated):
        raise UnsupportedModelError(
            "MD of a freely cooling mixture samples its scaled state, which exists only for "
            "constant restitution coefficients; particles.dsmc_mixture.evolve_mixture "
            f"follows a restitution law in physical time; got alpha {mixture.alpha!r}")
    counts = species_counts(mixture, n_particles)
    n, sig = check_geometry(n_particles, density, sigma)
    density = float(density)
    cpp = check_positive("collisions_per_particle", collisions_per_particle)
    # free cooling: zeta comes from the intervals between samples, at least one per batch
    fewest = n_batches + (0 if mixture.heated else 1) \
        if isinstance(n_batches, (int, np.integer)) else 2
    for name, val, least in (("n_samples", n_samples, fewest), ("n_batches", n_batches, 2),
                             ("n_bins", n_bins, 1)):
        if isinstance(val, bool) or not isinstance(val, (int, np.integer)) or val < least:
            raise ValueError(f"{name} must be an integer >= {least}, got {val!r}")
    c_max = check_positive("c_max", c_max)
    warm = 0.5 * cpp if warmup is None else float(warmup)
    if not (math.isfinite(warm) and 0.0 <= warm < cpp):
        raise ValueError(f"warmup must lie in [0, collisions_per_particle={cpp:g}), got "
                         f"{warmup!r}")
    check_work(0.5 * n * cpp, f"collisions_per_particle={cpp:g} with N={n}")
    heated = mixture.heated
    # every sample's N velocities are kept until the end
    if heated:
        every, samples = check_sample_interval(sample_interval, cpp, warm)
        given = (f"sample_interval={every:g} (about {samples:.3g} samples in "
                 f"collisions_per_particle - warmup = {cpp - warm:g} mean free times)")
    else:
        samples, given = float(n_samples), f"n_samples={n_samples}"
    check_measurements(samples, n, (_BYTES_PER_ROD + 24 + mixture.n_species) * n
                       + samples * (8.0 * n + _SAMPLE_OVERHEAD),
                       f"MD of a mixture of N={n} keeping the velocities of {given}")
    masses = np.asarray(mixture.masses, dtype=float)
    frictions = mixture.frictions()
    if heated and np.ptp(frictions) > 0.0:
        raise UnsupportedModelError(
            f"MD of a mixture kicks every rod at once: the species must share one friction "
            f"(white noise, or one bath friction), got frictions {frictions.tolist()}")
    n_f = density / (1.0 - density * sig)  # collision density of the reduced ring
    temps = _estimate(mixture, n_f)
    tau = 1.0 / (n_f * _mean_relative_speed(mixture, temps))
    speed = float(np.sqrt(np.max(temps / masses)))
    rng = np.random.default_rng(check_seed(seed))  # type: ignore[arg-type]
    species = rng.permutation(np.repeat(np.arange(mixture.n_species, dtype=np.int64), counts))
    y, v = initial_state(n, density=density, sigma=sig, temperature=1.0, rng=rng)
    v *= np.sqrt(temps / masses)[species]
    mass = masses[species]
    v -= np.sum(mass * v) / np.sum(mass)
    if heated:
        xi = float(frictions[0])
        dt_k = (KICK_FRACTION * (min(tau, 1.0 / xi) if xi > 0.0 else tau)
                if kick_interval is None else check_positive("kick_interval", kick_interval))
        diff = mixture.diffusions()
        d_ref = float(np.max(diff))
        kicks = Kicks.from_thermostat(mixture.thermostats[int(np.argmax(diff))],  # type: ignore[index]
                                      dt_k)
        scale = np.sqrt(diff / d_ref)[species]
        thr = (HEATED_THRESHOLD * speed if threshold is None
               else check_positive("threshold", threshold))
    else:
        kicks, scale = Kicks(), np.zeros(0)
        thr = 0.0 if threshold is None else check_positive("threshold", threshold)
    rods = MixtureRods.of(species, masses, mixture.laws, np.ascontiguousarray(scale))
    law = ConstantRestitution(1.0)  # (the laws of the pairs are the rods')
    options = EngineOptions(n / density - n * sig, sig, law, thr, kicks,
                            max_stall=100 * n + 100_000, species=rods)
    engine = MDEngine(y, v, options, rng)
    logger.info("MD mixture N=%d: tau %.4g, threshold %.3g, kicks every %.4g", n, tau, thr,
                kicks.interval)
    total = int(round(cpp * n / 2))
    engine.advance(int(round(warm * n / 2)))
    sel = [species == s for s in range(mixture.n_species)]
    start = engine.n_collisions
    # every sample's velocities (relative to u; scaled in free cooling) and, in free
    # cooling, the (time, temperature) of each; batches are consecutive equal runs of
    # samples, formed at the end (collisions come in bursts: batches by collision count
    # can miss every sample time)
    kept: list[NDArray[np.float64]] = []
    clock: list[tuple[float, float]] = []

    def sample() -> None:
        u = float(np.sum(mass * engine.v) / np.sum(mass))
        w = engine.v - u
        if not heated:
            temp = float(np.sum(mass * w * w) / n)
            clock.append((float(engine.fstate[F_T]), temp))
            w = w / math.sqrt(temp)
        kept.append(w)

    if heated:
        # the mean free time measured in the warm-up (the Gaussian estimate can be far
        # off: light rods caged between heavy ones recollide)
        warm_cpp = 2.0 * engine.n_collisions / n
        if warm_cpp > 0.0:
            tau = float(engine.fstate[F_T]) / warm_cpp
        sample_dt = every * tau
        t_next = float(engine.fstate[F_T]) + sample_dt
        while engine.advance(total, t_next):
            sample()
            t_next += sample_dt
    else:
        for target in np.linspace(start, total, n_samples).round().astype(np.int64):
            engine.advance(int(target))
            sample()
    if len(kept) < n_batches:
        raise ValueError(f"{len(kept)} samples for n_batches={n_batches}: "
                         f"collisions_per_particle={cpp:g} with warmup={warm:g} is too short "
                         f"at sample_interval={sample_interval:g}")
    accs = []
    for s in range(mixture.n_species):
        width = c_max * math.sqrt(float(np.mean(kept[0][sel[s]]**2)))
        accs.append(Accumulator(-width, width, n_bins, n_batches))
    batch_temps = np.zeros((n_batches, mixture.n_species))
    batch_rows = np.zeros(n_batches)
    zeta_sum = np.zeros(n_batches)
    zeta_time = np.zeros(n_batches)
    for i, w in enumerate(kept):
        batch = i * n_batches // len(kept)
        for s in range(mixture.n_species):
            ws = w[sel[s]]
            accs[s].add(batch, ws)
            batch_temps[batch, s] += masses[s] * float(np.mean(ws * ws))
        batch_rows[batch] += 1
        if clock and i > 0:
            zeta_sum[batch] += (clock[i][1]**-0.5 - clock[i - 1][1]**-0.5) / n_f
            zeta_time[batch] += clock[i][0] - clock[i - 1][0]
    pc = engine.pair_counts
    pair_counts = pc + pc.T - np.diag(np.diag(pc))
    n_coll = engine.n_collisions
    params: dict[str, Any] = {"n_particles": n, "density": density, "sigma": sig,
                              "threshold": thr, "kick_interval": kicks.interval,
                              "collisions_per_particle": cpp, "warmup": warm,
                              "seed": None if seed is None else str(seed)}
    info = RunInfo(converged=True, iterations=n_coll,
                   message=f"{n_coll} collisions, {n_batches} batches")
    dists = tuple(acc.distribution(method="md-mixture",
                                   params={**params, "species": s, "mass": float(masses[s])},
                                   info=info) for s, acc in enumerate(accs))
    if not heated and not np.all(zeta_time > 0.0):
        raise ValueError(f"no time passed between the samples of a batch (N={n}, "
                         f"collisions_per_particle={cpp:g}, n_samples={n_samples}): the "
                         "cooling rate is undefined; run longer or take fewer samples")
    batch_zeta = None if heated else zeta_sum / zeta_time
    return MixtureRun(mixture, dists, batch_temps / batch_rows[:, None], batch_zeta, n,
                      n_coll, pair_counts, info)
