"""DSMC of the homogeneous Boltzmann equations of a granular mixture (heated or cooling).

The equations are those of :mod:`kinetic_fem.model.mixture`.  ``N`` rods,
:math:`N_s = x_s N` of species :math:`s`, evolve by Strang splitting over steps ``dt``:
half a step of forcing, a collision phase, half a step of forcing.

* **Collisions** ("no time counter"): a candidate pair is two distinct rods drawn
  uniformly, whatever their species (a rod of species :math:`s` then meets species
  :math:`r` in proportion to :math:`x_r`, as the equations ask); with the majorant
  :math:`g_{max}` of the relative speed (the velocity range at the start of the step),
  :math:`N n\\,dt\\,B(g_{max})/2` candidates per step (the remainder carried over),
  each accepted with probability :math:`B(|g|)/B(g_{max})` for any kernel the DSMC has an
  acceptance rule for (power laws, the saturating kernel; :mod:`particles._dsmc_model`),
  and colliding with the pair's restitution law at :math:`|g|` (any law of
  :mod:`kinetic_fem.model`; a run whose relative speeds leave a law's range stops with a
  ``ValueError``).
* **Forcing** per species: white noise :math:`v \\mathrel{+}= \\sqrt{2D_s\\,\\delta t}\\,\\xi`;
  a bath by its exact Ornstein-Uhlenbeck step.  Under white noise alone the
  centre-of-mass velocity performs a random walk that has nothing to do with the
  Boltzmann equation of an infinite system; it is removed before every measurement
  (collisions and white noise are Galilean invariant, so this changes nothing else).
  Without forcing, collisions conserve the momentum, but the rescaling below multiplies
  its round-off by :math:`e^{\\zeta n t}` (:math:`10^{30}` after 250 mean free times at
  :math:`\alpha = 0.7`): it is removed there too.
* **Free cooling** in scaled variables (power-law kernels, constant restitution: the
  scaled state exists only for them; :func:`evolve_mixture` follows any kernel and law in
  physical time, by the steps above without forcing): no splitting, so no time step; the
  collisions between two measurements run on a clock that advances by the expected
  candidate spacing :math:`2/(N n B(g_{max}))` per candidate, with the velocity range
  measured every ``N`` candidates and widened by every collision that leaves it
  (:func:`particles._dsmc_mixture_kernels.cooling_segment`); the velocities are then
  rescaled to the mixture temperature :math:`T = \\sum_i m_i v_i^2 / N = 1`.  The
  cooling rate of the convention :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}` is the
  energy lost weighted by :math:`T^{-(1+\\gamma/2)}` over :math:`N n` times the time, the
  temperature falling by :math:`2\\Delta E/N` per collision (the sum over the
  collisions is the integral :math:`(N/2)\\int dT/T^{1+\\gamma/2}`).

The time step of the forced runs puts ``collisions_per_step`` collisions per rod per step
on average (default 0.05; the splitting error is :math:`O(dt^2)`).  Measurements
(per-species power sums and histograms) are taken every ``sample_every`` collisions per
rod after ``relax`` collisions per rod, in ``n_batches`` consecutive batches: the error
bars are standard errors of the batch means.

The collisions between two measurements run in one call of a compiled kernel
(:mod:`particles._dsmc_mixture_kernels`; random numbers from its own streams,
:mod:`particles.rng`, the candidates from eight lock-step lanes as in the one-species free
cooling, the initial velocities from ``numpy.random``, all from ``seed``): 10.1 million
collisions per CPU second heated and 38 million cooling against 0.51 and 0.80 million when
every step went through numpy (N = 5000, masses 1:2, hard rods, alpha 0.9; 0.85 and 0.85
of the one-species DSMC, 0.86 and 0.71 at N = 20000;
``benchmarks/bench_dsmc_mixture.py``).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray

from kinetic_fem.distribution import MAX_MOMENT, RunInfo, VelocityDistribution
from kinetic_fem.evolve import check_times
from kinetic_fem.mixture_evolution import MixtureEvolution, initial_temperatures_of
from kinetic_fem.mixture_state import SpeciesTemperatures
from kinetic_fem.model import UnsupportedModelError, check_positive
from kinetic_fem.model.mixture import Mixture
from kinetic_fem.progress import resolve_progress

from ._dsmc_mixture_kernels import (
    cool_measure,
    mean_squares,
    mixture_segment,
    recentre,
    recentre_measure,
)
from ._dsmc_model import kernel_model, power_exponent
from .rng import mixture_state, ziggurat_tables
from .run import check_seed

__all__ = ["MixtureRun", "simulate_mixture", "simulate_binary", "evolve_mixture", "species_counts",
           "MixtureDSMCOptions"]

logger = logging.getLogger(__name__)

#: the time step is recomputed when a species' <v^2> has moved by this fraction (the step,
#: proportional to <v^2>^(-gamma/2), then within 5 % of its value for hard rods)
STEP_REFRESH = 0.1

#: at most this many collisions per rod per step (the splitting would be inaccurate)
MAX_COLLISIONS_PER_STEP = 0.5


@dataclass(frozen=True)
class MixtureRun(SpeciesTemperatures):
    """A DSMC run of a mixture: one distribution per species and the batch statistics.

    Attributes
    ----------
    mixture : Mixture
    distributions : tuple of VelocityDistribution
        One per species (velocities of that species; in free cooling scaled to the
        mixture temperature 1).
    batch_temperatures : ndarray, shape (n_batches, k)
        :math:`T_s = m_s\\langle v^2\\rangle_s` of each batch.
    batch_zeta : ndarray, shape (n_batches,) or None
        The cooling rate of each batch (free cooling).
    n_particles, n_collisions : int
    collision_counts : ndarray, shape (k, k)
        Collisions per pair of species.
    info : RunInfo
    """

    mixture: Mixture
    distributions: tuple[VelocityDistribution, ...]
    batch_temperatures: NDArray[np.float64]
    batch_zeta: NDArray[np.float64] | None
    n_particles: int
    n_collisions: int
    collision_counts: NDArray[np.int64]
    info: RunInfo = field(default_factory=RunInfo)

    @property
    def temperatures(self) -> NDArray[np.float64]:
        """:math:`T_s`, mean over the batches, shape (k,)."""
        return self.batch_temperatures.mean(axis=0)

    @property
    def temperature_errors(self) -> NDArray[np.float64]:
        """Standard errors of :attr:`temperatures`."""
        return np.asarray(_standard_error(self.batch_temperatures))

    def temperature_ratio_error(self, s: int = 0, r: int = 1) -> float:
        """Standard error of :meth:`temperature_ratio` (from the batch ratios)."""
        ratios = self.batch_temperatures[:, s] / self.batch_temperatures[:, r]
        return float(_standard_error(ratios))

    @property
    def a2(self) -> NDArray[np.float64]:
        """:math:`a_{2,s}` of each species."""
        return np.array([d.a2 for d in self.distributions])

    @property
    def a2_errors(self) -> NDArray[np.float64]:
        """Standard errors of :attr:`a2`."""
        return np.array([d.a2_error for d in self.distributions])

    @property
    def zeta(self) -> float | None:
        """The cooling rate (free cooling), else None."""
        return None if self.batch_zeta is None else float(self.batch_zeta.mean())

    @property
    def zeta_error(self) -> float | None:
        """Standard error of :attr:`zeta` (free cooling), else None."""
        return None if self.batch_zeta is None else float(_standard_error(self.batch_zeta))


def _standard_error(batches: NDArray[np.float64]) -> NDArray[np.float64] | float:
    n = batches.shape[0]
    if n < 2:
        return np.full(batches.shape[1:], np.nan) if batches.ndim > 1 else math.nan
    return batches.std(axis=0, ddof=1) / math.sqrt(n)


def species_counts(mixture: Mixture, n_particles: object) -> NDArray[np.int64]:
    """Rods per species, ``n_particles * x_s``, checked to be whole numbers >= 2.

    Parameters
    ----------
    mixture : Mixture
        The mixture (its number fractions).
    n_particles : int
        Total number of particles.

    Returns
    -------
    ndarray of int64, shape (k,)
    """
    if isinstance(n_particles, bool) or not isinstance(n_particles, (int, np.integer)):
        raise TypeError(f"n_particles must be an integer, got {n_particles!r}")
    n = int(n_particles)
    exact = np.asarray(mixture.fractions) * n
    counts = np.rint(exact).astype(np.int64)
    if np.any(np.abs(counts - exact) > 1e-9 * n) or counts.sum() != n:
        raise ValueError(f"n_particles * fractions must be whole numbers of rods per species, "
                         f"got n_particles={n} and fractions={mixture.fractions}")
    if np.any(counts < 2):
        raise ValueError(f"every species needs at least 2 rods, got {counts.tolist()} for "
                         f"n_particles={n}")
    return counts


def _mean_rate(var: NDArray[np.float64], mixture: Mixture, gamma: float | None) -> float:
    """:math:`\\langle B(|g|)\\rangle` of Gaussian species of variances ``var`` (``gamma``
    the exponent of a power law, None for another kernel)."""
    if gamma == 0.0:
        return 1.0
    k = mixture.n_species
    x = mixture.fractions
    if gamma is None:
        kernel = mixture.collision_kernel
        return sum(x[s] * x[r] * kernel.gaussian_mean(0.5 * (var[s] + var[r]))
                   for s in range(k) for r in range(k))
    # <|g|^gamma> for g Gaussian of variance var_s + var_r (floats: called per measurement)
    factor = math.gamma(0.5 * (gamma + 1.0)) / math.sqrt(math.pi)
    return factor * sum(x[s] * x[r] * (2.0 * (float(var[s]) + float(var[r])))**(0.5 * gamma)
                        for s in range(k) for r in range(k))


def simulate_mixture(mixture: Mixture, n_particles: int, *, density: float = 1.0,
                     seed: int | np.random.SeedSequence | None = None,
                     collisions_per_particle: float = 200.0, relax: float = 50.0,
                     options: MixtureDSMCOptions | None = None,
                     progress: bool | None = None) -> MixtureRun:
    """DSMC steady state (forced species) or scaled cooling state of a mixture.

    Parameters
    ----------
    mixture : Mixture
        Any kernel with a DSMC acceptance rule and any restitution law per pair
        (:class:`kinetic_fem.Mixture`); free cooling (the scaled state): power laws and
        constant coefficients.
    n_particles : int
        Rods in all; ``n_particles * x_s`` must be whole numbers, at least 2 each.
    density : float
        Total number density :math:`n`.
    seed : int or SeedSequence, optional
        The same seed gives the same run.
    collisions_per_particle : float
        Length of the measurement, in collisions per rod.
    relax : float
        Collisions per rod before measuring (the initial Gaussians relax to the state).
    options : MixtureDSMCOptions, optional
        Step size, sampling cadence, batches, histogram.
    progress : bool, optional
        Show a progress bar (tqdm); default (None): shown when the session is
        interactive (a terminal or a notebook).

    Returns
    -------
    MixtureRun
    """
    if not isinstance(mixture, Mixture):
        raise TypeError(f"mixture must be a kinetic_fem.Mixture, got {mixture!r}")
    opts = options or MixtureDSMCOptions()
    counts = species_counts(mixture, n_particles)
    density = check_positive("density", density)
    collisions_per_particle = check_positive("collisions_per_particle", collisions_per_particle)
    relax = float(relax)
    if not (math.isfinite(relax) and relax >= 0.0):
        raise ValueError(f"relax must be a finite number of collisions per rod >= 0, got "
                         f"{relax!r}")
    total = relax + collisions_per_particle
    if total / opts.collisions_per_step > 1e8:
        raise ValueError(f"relax + collisions_per_particle = {total:g} collisions per rod at "
                         f"{opts.collisions_per_step:g} per step is more than 1e8 steps")
    gamma = power_exponent(mixture.collision_kernel)
    if not mixture.heated and (gamma is None or any(
            law.constant is None for row in mixture.laws for law in row)):
        raise UnsupportedModelError(
            "the scaled cooling state of simulate_mixture needs a power-law kernel and "
            "constant restitution coefficients (no scaled state exists otherwise); "
            "particles.dsmc_mixture.evolve_mixture follows free cooling with any kernel and "
            f"law in physical time; got kernel {mixture.collision_kernel!r} and alpha "
            f"{mixture.alpha!r}")
    if collisions_per_particle < opts.n_batches * opts.sample_every:
        raise ValueError(f"collisions_per_particle={collisions_per_particle:g} is too short "
                         f"for n_batches={opts.n_batches} measured every "
                         f"{opts.sample_every:g} collisions per rod (at least "
                         f"{opts.n_batches * opts.sample_every:g})")
    if 0.5 * int(n_particles) * opts.sample_every < 1.0 - 1e-9:
        # measurements are at least one collision apart (each segment's target is at
        # least one): a shorter interval was silently a measurement every collision
        raise ValueError(f"options.sample_every={opts.sample_every:.6g} collisions per rod is "
                         f"less than one collision between measurements for n_particles="
                         f"{int(n_particles)} (0.5 * N * sample_every = "
                         f"{0.5 * int(n_particles) * opts.sample_every:.3g}): it must be "
                         f">= 2/N = {2.0 / int(n_particles):.6g}")
    masses = np.asarray(mixture.masses, dtype=float)
    checked = check_seed(seed)
    root = checked if isinstance(checked, np.random.SeedSequence) \
        else np.random.SeedSequence(checked)  # type: ignore[arg-type]
    start_seq, kernel_seq = root.spawn(2)
    rng = np.random.default_rng(start_seq)
    n = int(n_particles)
    species = np.repeat(np.arange(mixture.n_species, dtype=np.int64), counts)
    mass = masses[species]
    heated = mixture.heated
    rods = _Rods.of(mixture, species, density)
    state = mixture_state(kernel_seq)
    # initial Gaussians: the Gaussian-approximation temperatures would be closer; unit
    # variance per species is enough, the relaxation does the rest
    v = rng.standard_normal(n)
    v -= np.sum(mass * v) / np.sum(mass)
    if not heated:
        v /= math.sqrt(np.sum(mass * v * v) / n)

    from tqdm.auto import tqdm

    sums = np.zeros((opts.n_batches, mixture.n_species, MAX_MOMENT + 1))
    hist = np.zeros((opts.n_batches, mixture.n_species, opts.bins))
    batch_loss = np.zeros(opts.n_batches)
    batch_time = np.zeros(opts.n_batches)
    pair_counts = np.zeros((mixture.n_species, mixture.n_species), dtype=np.int64)
    lows = np.zeros(mixture.n_species)
    widths = np.zeros(mixture.n_species)
    debt = 0.0
    done = 0.0  # collisions per rod so far
    next_sample = relax
    n_collisions = 0
    # one call of the compiled steps per measurement: it ends after the step that
    # reaches the collisions of the next one (at most twice the expected steps)
    steps = 2 * max(1, math.ceil(opts.sample_every / opts.collisions_per_step))
    bar = tqdm(total=total, disable=not resolve_progress(progress), unit="coll/rod",
               leave=False)

    def batch_of(x: float) -> int:
        return min(int((x - relax) / collisions_per_particle * opts.n_batches),
                   opts.n_batches - 1)

    while done < total:
        target = max(1, math.ceil(0.5 * n * (min(next_sample, total) - done)))
        fused = False
        if heated:
            dt = rods.time_step(v, opts.collisions_per_step, mixture, gamma)
            new, debt, taken = rods.segment(v, dt, steps, debt, pair_counts, state,
                                            max_collisions=target, centre=False)
            elapsed = taken * dt
        else:
            # the segment reaches its target exactly: a measurement now is known before it
            after = done + 2.0 * target / n
            fused = bool(widths[0]) and after >= next_sample and after >= relax
            b = batch_of(after) if fused else 0
            new, elapsed, end = rods.cool(v, pair_counts, state, target, fused, lows, widths,
                                          sums[b], hist[b])
        n_collisions += new
        step = 2.0 * new / n
        done += step
        bar.update(step)
        # heated: the centre-of-mass velocity removed (unless a bath holds it) and the
        # measurement in the same pass; free cooling: recentred and rescaled to T = 1 by
        # the cooling call (measured there too once the histograms have their ranges)
        centre = heated and rods.free_centre
        if done >= next_sample and done >= relax:
            if not fused:
                if not widths[0]:  # the histograms' ranges from the first measured state
                    recentre(v, rods.bounds, rods.masses, centre, False)
                    centre = False
                    for s in range(mixture.n_species):
                        half = opts.c_max * math.sqrt(np.mean(v[species == s]**2))
                        lows[s], widths[s] = -half, 2.0 * half / opts.bins
                batch = batch_of(done)
                recentre_measure(v, rods.bounds, rods.masses, centre, False, lows, widths,
                                 sums[batch], hist[batch])
            next_sample += opts.sample_every
        elif heated:
            recentre(v, rods.bounds, rods.masses, centre, False)
        if done >= relax:
            batch = batch_of(done)
            if not heated:
                assert gamma is not None  # a power law in free cooling (checked above)
                # free cooling: each collision's loss over the temperature at the middle
                # of its drop
                batch_loss[batch] += rods.weighted(end, gamma)
            batch_time[batch] += elapsed
    bar.close()
    if np.any(sums[:, :, 0] == 0):
        raise ValueError(f"a batch holds no measurement: collisions_per_particle="
                         f"{collisions_per_particle:g} is too short for n_batches="
                         f"{opts.n_batches} at sample_every={opts.sample_every:g}")
    params: dict[str, Any] = {"n_particles": n, "density": density, "seed": seed,
                              "collisions_per_particle": collisions_per_particle,
                              "relax": relax}
    edges = [lows[s] + widths[s] * np.arange(opts.bins + 1) for s in range(mixture.n_species)]
    dists = tuple(VelocityDistribution.from_batches(
        edges[s], hist[:, s], sums[:, s], method="dsmc-mixture",
        params={**params, "species": s, "mass": float(masses[s])})
        for s in range(mixture.n_species))
    batch_temps = sums[:, :, 2] / sums[:, :, 0] * masses[None, :]
    batch_zeta = None if heated else batch_loss / (n * density * batch_time)
    info = RunInfo(converged=True, iterations=n_collisions,
                   message=f"{n_collisions} collisions, {opts.n_batches} batches")
    return MixtureRun(mixture, dists, batch_temps, batch_zeta, n, n_collisions, pair_counts,
                      info)


@dataclass(frozen=True, eq=False)
class _Rods:  # (cached properties: frozen, not slotted)
    """The rods of a mixture DSMC and one Strang step of forcing and collisions."""

    species: NDArray[np.int64]
    masses: NDArray[np.float64]
    mass: NDArray[np.float64]
    #: each species' diffusion coefficient and friction rate
    diffusions: NDArray[np.float64]
    frictions: NDArray[np.float64]
    heated: bool
    density: float
    kcode: int
    kparam: float
    lcode: NDArray[np.int64]
    p0: NDArray[np.float64]
    p1: NDArray[np.float64]
    #: the largest relative speed every pair's restitution law allows
    g_limit: float

    @cached_property
    def bounds(self) -> NDArray[np.int64]:
        """The rods of species ``s`` are ``bounds[s] <= i < bounds[s + 1]``."""
        if np.any(np.diff(self.species) < 0):
            raise ValueError("the rods must be sorted by species")
        return np.searchsorted(self.species, np.arange(self.masses.size + 1)).astype(np.int64)

    @cached_property
    def free_centre(self) -> bool:
        """No bath holds the centre of mass (it is removed before every measurement)."""
        return not bool(np.any(self.frictions > 0.0))

    @cached_property
    def mu(self) -> NDArray[np.float64]:
        """:math:`\\mu_{sr} = m_r/(m_s + m_r)`."""
        m = self.masses
        return m[None, :] / (m[:, None] + m[None, :])

    @cached_property
    def reduced(self) -> NDArray[np.float64]:
        """Half the reduced mass of each pair, :math:`m_s m_r / (2(m_s + m_r))`."""
        m = self.masses
        return 0.5 * m[:, None] * m[None, :] / (m[:, None] + m[None, :])

    @classmethod
    def of(cls, mixture: Mixture, species: NDArray[np.int64], density: float) -> _Rods:
        """The rods of ``mixture`` (``species[i]`` of rod i) at total density ``density``."""
        masses = np.asarray(mixture.masses, dtype=float)
        kcode, kparam = kernel_model(mixture.collision_kernel)
        k = mixture.n_species
        lcode = np.array([[law.code for law in row] for row in mixture.laws], dtype=np.int64)
        params = np.array([[law.parameters for law in row] for row in mixture.laws],
                          dtype=float).reshape(k, k, 2)
        g_limit = min(float(law.max_speed) for row in mixture.laws for law in row)
        return cls(species, masses, masses[species], mixture.diffusions(),
                   mixture.frictions(), mixture.heated, density, kcode, kparam,
                   lcode, np.ascontiguousarray(params[..., 0]),
                   np.ascontiguousarray(params[..., 1]), g_limit)

    def time_step(self, v: NDArray[np.float64], per_step: float, mixture: Mixture,
                  gamma: float | None) -> float:
        """The step with ``per_step`` expected collisions per rod (Gaussian species at the
        current variances), recomputed only when a species' :math:`\\langle v^2\\rangle`
        has moved by :data:`STEP_REFRESH` since (the same step, and its kick factors,
        otherwise: 14 of the 25 microseconds of Python per call at N = 1000; the test in
        Python floats, 1.4 against 3.6 microseconds with numpy's on two species)."""
        var = mean_squares(v, self.bounds)
        kept = self._step
        if kept and kept[0] == per_step:
            for now, then in zip(var.tolist(), kept[1], strict=True):
                if not (then > 0.0 and abs(now / then - 1.0) <= STEP_REFRESH):  # (NaN: new)
                    break
            else:
                return float(kept[2])
        dt = per_step / (self.density * _mean_rate(var, mixture, gamma))
        self._step[:] = [per_step, var.tolist(), dt]
        return dt

    @cached_property
    def _step(self) -> list[Any]:
        """``[per_step, variances, dt]`` of the last :meth:`time_step` (empty at first)."""
        return []

    def kicks(self, dt: float) -> tuple[NDArray[np.float64], ...]:
        """Each species' kick factors ``(decay, amp)`` of a full and of a half step
        (white noise: decay 1, amp :math:`\\sqrt{2D_s\\,\\delta t}`; a bath: the exact
        Ornstein-Uhlenbeck step)."""
        if self._kicks and self._kicks[0] == dt:
            return self._kicks[1]
        out = []
        for step in (dt, 0.5 * dt):
            decay, amp = [], []
            for d, xi in zip(self.diffusions.tolist(), self.frictions.tolist(), strict=True):
                decay.append(math.exp(-xi * step))
                amp.append(math.sqrt(d * -math.expm1(-2.0 * xi * step) / xi if xi > 0.0
                                     else 2.0 * d * step))
            out += [np.array(decay), np.array(amp)]
        self._kicks[:] = [dt, tuple(out)]
        return tuple(out)

    @cached_property
    def _kicks(self) -> list[Any]:
        """``[dt, factors]`` of the last :meth:`kicks` (empty at first)."""
        return []

    def segment(self, v: NDArray[np.float64], dt: float, n_steps: int, debt: float,
                pair_counts: NDArray[np.int64], state: NDArray[np.uint64], *,
                max_collisions: int = 2**62, centre: bool = True
                ) -> tuple[int, float, int]:
        """``n_steps`` Strang steps of ``dt`` (:func:`particles._dsmc_mixture_kernels.
        mixture_segment`; free cooling in physical velocities), then the centre-of-mass
        velocity removed (unless a bath holds it); it ends early after the step in which
        the collisions reach ``max_collisions``.  ``centre=False``: the velocities are
        left as they are (the caller recentres them, with its measurement).

        Returns
        -------
        (collisions, debt, steps)
            The carried fraction of a candidate, the steps taken.

        Raises
        ------
        ValueError
            If the relative speeds leave the range of a restitution law.
        """
        decay, amp, half_decay, half_amp = self.kicks(dt)
        ki, wi, fi = _ZIGGURAT
        out = mixture_segment(v, self.bounds, self.mu, self.lcode, self.p0, self.p1,
                              self.kcode, self.kparam, decay, amp, half_decay, half_amp,
                              self.heated, 0.5 * v.size * self.density, dt, n_steps,
                              self.g_limit, debt, state, ki, wi, fi, pair_counts,
                              max_collisions)
        collisions, debt, steps, g_max, exceeded = out
        if exceeded:
            raise ValueError(f"a relative speed {g_max:.4g} exceeds {self.g_limit:.4g}, the "
                             "largest a restitution law of the mixture allows (its "
                             "max_speed); lower the temperature or widen the law's range")
        if centre:
            recentre(v, self.bounds, self.masses, self.free_centre, False)
        return int(collisions), float(debt), int(steps)

    def cool(self, v: NDArray[np.float64], pair_counts: NDArray[np.int64],
             state: NDArray[np.uint64], max_collisions: int, fused: bool,
             lows: NDArray[np.float64], widths: NDArray[np.float64],
             sums: NDArray[np.float64], hist: NDArray[np.float64]) -> tuple[int, float, float]:
        """Scaled free cooling (``v`` at :math:`T = 1`) for ``max_collisions`` collisions,
        then recentred and rescaled to :math:`T = 1`, measured into ``sums`` and ``hist``
        if ``fused`` (:func:`particles._dsmc_mixture_kernels.cool_measure`).

        Returns
        -------
        (collisions, time, temperature)
            The temperature reached before the rescaling (:meth:`weighted`).
        """
        collisions, time, end = cool_measure(
            v, self.bounds, self.masses, self.mu, self.reduced, self.p0, self.kcode,
            self.kparam, 0.5 * v.size * self.density, state, pair_counts, max_collisions,
            fused, lows, widths, sums, hist)
        return int(collisions), float(time), float(end)

    def weighted(self, end: float, gamma: float) -> float:
        """The energy lost while the temperature fell from 1 to ``end``, weighted by
        :math:`T^{-(1+\\gamma/2)}`: each collision lowers :math:`T` by :math:`2\\Delta E/N`,
        so the sum over the collisions is the integral :math:`(N/2)\\int_{end}^1
        dT/T^{1+\\gamma/2}` (no power per collision); over :math:`N n` times the time it
        estimates :math:`\\zeta`."""
        n = self.species.size
        power = 1.0 + 0.5 * gamma
        if power == 1.0:
            return 0.5 * n * math.log(1.0 / end)
        return 0.5 * n * (end ** (1.0 - power) - 1.0) / (power - 1.0)


_ZIGGURAT = ziggurat_tables()


@dataclass(frozen=True)
class MixtureDSMCOptions:
    """Numerical options of :func:`simulate_mixture` that travel together.

    Parameters
    ----------
    collisions_per_step : float
        Mean collisions per rod per time step of the forced runs, in (0, 0.5] (free
        cooling in scaled variables has no time step).
    sample_every : float
        Collisions per rod between measurements; :func:`simulate_mixture` refuses less
        than one collision between them (``sample_every < 2/N``).
    n_batches : int
        Consecutive batches for the error bars, >= 2.
    bins : int
        Histogram bins per species.
    c_max : float
        Histogram range in units of the species' standard deviation at the first
        measurement.
    """

    collisions_per_step: float = 0.05
    sample_every: float = 1.0
    n_batches: int = 20
    bins: int = 200
    c_max: float = 10.0

    def __post_init__(self) -> None:
        step = check_positive("collisions_per_step", self.collisions_per_step)
        if step > MAX_COLLISIONS_PER_STEP:
            raise ValueError(f"collisions_per_step must be in (0, {MAX_COLLISIONS_PER_STEP}],"
                             f" got {step!r}")
        check_positive("sample_every", self.sample_every)
        check_positive("c_max", self.c_max)
        for name in ("n_batches", "bins"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) \
                    or value < (2 if name == "n_batches" else 1):
                raise ValueError(f"{name} must be an integer >= "
                                 f"{2 if name == 'n_batches' else 1}, got {value!r}")


def evolve_mixture(mixture: Mixture, n_particles: int, *, times: Any, density: float = 1.0,
                   initial_temperature: float | Any = None,
                   seed: int | np.random.SeedSequence | None = None, n_runs: int = 4,
                   collisions_per_step: float = 0.05) -> MixtureEvolution:
    """DSMC time series of the species temperatures, from Gaussian species.

    The step of :func:`simulate_mixture` in physical time (free cooling is not rescaled),
    landing on every output time; ``n_runs`` independent runs (seeds spawned from
    ``seed``) give the mean and its standard error.  The deterministic counterpart is
    :func:`kinetic_fem.mixture_evolution.evolve_mixture` (exact for the Maxwell mixture).

    Parameters
    ----------
    mixture : Mixture
        Any kernel with a DSMC acceptance rule (power laws, the saturating kernel), any
        restitution law per pair, forced or freely cooling (physical time).
    n_particles : int
        Rods per run; ``n_particles * x_s`` whole numbers, at least 2 each.
    times : array_like, shape (n_t,)
        Output times, >= 0, strictly increasing.
    density : float
        Total number density.
    initial_temperature : float or sequence of float, optional
        :math:`T_s(0)` (default 1 for every species).
    seed : int or SeedSequence, optional
    n_runs : int
        Independent runs, >= 2 (for the error bars).
    collisions_per_step : float
        At most this many collisions per rod per time step, in (0, 0.5].

    Returns
    -------
    MixtureEvolution
        ``method="dsmc-mixture"``, with ``temperature_errors`` and ``a2_errors``.
    """
    if not isinstance(mixture, Mixture):
        raise TypeError(f"mixture must be a kinetic_fem.Mixture, got {mixture!r}")
    counts = species_counts(mixture, n_particles)
    t_out = check_times(times)
    density = check_positive("density", density)
    MixtureDSMCOptions(collisions_per_step=collisions_per_step)  # validates it
    if isinstance(n_runs, bool) or not isinstance(n_runs, (int, np.integer)) or n_runs < 2:
        raise ValueError(f"n_runs must be an integer >= 2 (for the error bars), got "
                         f"{n_runs!r}")
    temps0 = initial_temperatures_of(mixture, initial_temperature)
    gamma = power_exponent(mixture.collision_kernel)
    masses = np.asarray(mixture.masses, dtype=float)
    species = np.repeat(np.arange(mixture.n_species, dtype=np.int64), counts)
    mass = masses[species]
    rods = _Rods.of(mixture, species, density)
    k = mixture.n_species
    temps = np.zeros((n_runs, t_out.size, k))
    a2 = np.zeros((n_runs, t_out.size, k))
    sel = [species == s for s in range(k)]
    pair_counts = np.zeros((k, k), dtype=np.int64)
    checked = check_seed(seed)
    ss = checked if isinstance(checked, np.random.SeedSequence) \
        else np.random.SeedSequence(checked)  # type: ignore[arg-type]
    steps = max(1, int(round(1.0 / collisions_per_step)))  # about a collision per rod
    for run, child in enumerate(ss.spawn(n_runs)):
        start_seq, kernel_seq = child.spawn(2)
        rng = np.random.default_rng(start_seq)
        state = mixture_state(kernel_seq)
        v = rng.standard_normal(n_particles) * np.sqrt(temps0 / masses)[species]
        v -= np.sum(mass * v) / np.sum(mass)
        t, debt = 0.0, 0.0
        for i, t_next in enumerate(t_out):
            while t < t_next:
                dt = rods.time_step(v, collisions_per_step, mixture, gamma)
                n_steps = min(steps, math.ceil((t_next - t) / dt))
                if n_steps * dt >= t_next - t:  # land on the output time
                    dt, t = (t_next - t) / n_steps, t_next
                else:
                    t += n_steps * dt
                debt = rods.segment(v, dt, n_steps, debt, pair_counts, state)[1]
            for s in range(k):
                m2, m4 = np.mean(v[sel[s]]**2), np.mean(v[sel[s]]**4)
                temps[run, i, s] = masses[s] * m2
                a2[run, i, s] = m4 / (3.0 * m2 * m2) - 1.0
    return MixtureEvolution(
        mixture, t_out, temps.mean(axis=0), a2.mean(axis=0), "dsmc-mixture",
        temperature_errors=temps.std(axis=0, ddof=1) / math.sqrt(n_runs),
        a2_errors=a2.std(axis=0, ddof=1) / math.sqrt(n_runs),
        info={"n_particles": int(n_particles), "n_runs": n_runs, "density": density,
              "seed": None if seed is None else str(seed),
              "collision_counts": pair_counts.tolist()})


def simulate_binary(mass_ratio: float, n_particles: int, *, fraction: float = 0.5,
                    alpha: float = 0.9, alpha_11: float | None = None,
                    alpha_12: float | None = None, alpha_22: float | None = None,
                    kernel: Any = 1.0, forcing: str = "same_diffusion",
                    diffusion: float = 1.0, method: str = "dsmc", **options: Any
                    ) -> MixtureRun:
    """A particle run of :func:`kinetic_fem.mixture_solve.binary_mixture`: a sweep function.

    Parameters
    ----------
    mass_ratio, fraction, alpha, alpha_11, alpha_12, alpha_22, kernel, forcing, diffusion
        As in :func:`kinetic_fem.mixture_solve.binary_mixture`.
    n_particles : int
        Rods in all.
    method : {"dsmc", "md"}
        :func:`simulate_mixture` or :func:`particles.md_mixture.simulate_mixture`.
    **options
        Passed on (``seed``, ``collisions_per_particle``, ``density``, ...).

    Returns
    -------
    MixtureRun
    """
    from kinetic_fem.mixture_solve import binary_mixture

    mix = binary_mixture(mass_ratio, fraction=fraction, alpha=alpha, alpha_11=alpha_11,
                         alpha_12=alpha_12, alpha_22=alpha_22, kernel=kernel, forcing=forcing,
                         diffusion=diffusion)
    if method == "dsmc":
        return simulate_mixture(mix, n_particles, **options)
    if method == "md":
        from .md_mixture import simulate_mixture as simulate_md

        return simulate_md(mix, n_particles, **options)
    raise ValueError(f"method must be 'dsmc' or 'md', got {method!r}")
