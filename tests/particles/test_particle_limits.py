"""Particle runs refuse up front what cannot finish or is misspelt (issue 28)."""

import math
import time

import numpy as np
import pytest

from kinetic_fem import Mixture
from particles import dsmc, md, md_mixture

KW = dict(seed=1, collisions_per_particle=10, n_batches=2)


@pytest.mark.parametrize("changes, error, match", [
    (dict(seed=-1), ValueError, "seed=-1"),
    (dict(seed=True), TypeError, "seed must be"),
    (dict(sample_every=1e-300), ValueError, "sample_every"),
    (dict(collisions_per_particle=1e300), ValueError, "MAX_EVENTS"),
    (dict(dt=1e-300), ValueError, "dt=1e-300"),
])
def test_dsmc_heated_refuses_up_front(changes, error, match):
    with pytest.raises(error, match=match):
        dsmc.simulate_heated(0.6, 200, **{**KW, **changes})


def test_dsmc_near_elastic_cooling_is_refused_with_the_way_out():
    with pytest.raises(ValueError, match="relax=<collisions per particle>"):
        dsmc.simulate_cooling(0.999999, 200, **KW)


def test_dsmc_too_many_particles_is_a_memory_error_before_allocating():
    with pytest.raises(MemoryError, match="GiB"):
        dsmc.simulate_heated(0.6, 2**32 - 1, **KW)


@pytest.mark.parametrize("changes, match", [
    (dict(kick_interval=1e300), "kick_interval"),
    (dict(box_counts=[0]), "box_counts"),
    (dict(box_counts=[10**9]), "box_counts"),
    (dict(snapshots_at=[math.nan]), "snapshots_at"),
    (dict(seed=np.int64(-3)), "seed"),
])
def test_md_refuses_up_front(changes, match):
    with pytest.raises(ValueError, match=match):
        md.simulate_heated(0.9, 50, **{**KW, "collisions_per_particle": 10.0, **changes})


@pytest.mark.parametrize("simulate", [dsmc.simulate_heated, dsmc.simulate_cooling])
def test_equal_initial_velocities_are_refused_by_name(simulate):
    with pytest.raises(ValueError, match="initial_velocities are all equal"):
        simulate(0.6, 200, initial_velocities=np.zeros(200), **KW)


# sample_every: the engine advances whole collisions (cooling) or time steps (heated)
# between measurements; an interval rounding to zero was silently made one, so the run
# measured more rarely and ran far longer than asked (4.5 million measurements at N = 57)


@pytest.mark.parametrize("every", [1.19e-7, 1e-3, 1.0 / 200])
def test_dsmc_cooling_refuses_half_a_collision_between_measurements(every):
    # N = 200: 1/N = 0.005 is half a collision (rounds to none) and is refused too
    with pytest.raises(ValueError, match=r"sample_every=.*half a collision.*N=200.*"
                                         r"must be > 1/N = 0\.005"):
        dsmc.simulate_cooling(0.6, 200, **{**KW, "sample_every": every})


def test_dsmc_cooling_takes_just_over_half_a_collision():
    r = dsmc.simulate_cooling(0.6, 200, seed=1, collisions_per_particle=0.06, relax=0.0,
                              sample_every=0.0051, n_batches=2)
    assert r.info.extra["samples"] >= 2


@pytest.mark.parametrize("every", [1.19e-7, 0.02])
def test_dsmc_heated_refuses_half_a_time_step_between_measurements(every):
    # the default dt is 0.05 collisions per particle per step: refused up to 0.025
    with pytest.raises(ValueError, match=r"sample_every=.*half a time step.*must be > "
                                         r"0\.025.*smaller dt"):
        dsmc.simulate_heated(0.6, 200, **{**KW, "sample_every": every})


def test_dsmc_heated_hostile_example_is_refused_at_once():
    """The derandomized example of tests/test_hostile_api.py::test_dsmc_heated_many."""
    with pytest.raises(ValueError, match="sample_every=1.19e-07"):
        dsmc.simulate_heated(0.5326, 57, collisions_per_particle=0.5326, sample_every=1.19e-7,
                             n_batches=2, bins=20)


def test_dsmc_heated_measures_between_collisions_with_a_smaller_dt():
    # a heated run advances time steps, not collisions: 0.02 per particle at N = 10 (0.1
    # collision between measurements) is fine with steps of at most 0.02
    r = dsmc.simulate_heated(0.6, 10, seed=1, collisions_per_particle=0.1, relax=0.0,
                             sample_every=0.02, n_batches=2, dt=1e-3)
    assert r.info.extra["samples"] >= 2


@pytest.mark.parametrize("simulate, every", [(dsmc.simulate_cooling, 0.01),
                                             (dsmc.simulate_heated, 0.05)])
def test_dsmc_long_finely_sampled_runs_pass_the_checks(simulate, every):
    """N = 1e5, 1000 collisions per particle: 1e5 or 2e4 measurements are allowed (the
    run is stopped at once by the wall-time limit, before any averaging)."""
    with pytest.raises(RuntimeError, match="before any sample was averaged"):
        simulate(0.6, 100_000, seed=1, collisions_per_particle=1000.0, sample_every=every,
                 max_wall_time=1e-9)


def test_dsmc_measurements_are_bounded_by_their_cost():
    with pytest.raises(ValueError, match=r"1e\+08 measurements of N=1000000.*MAX_EVENTS"):
        dsmc.simulate_cooling(0.6, 10**6, seed=1, collisions_per_particle=1e4,
                              sample_every=1e-4, relax=0.0)


def test_dsmc_fixed_relax_counts_in_the_work_bound():
    with pytest.raises(ValueError, match="relax=1e\\+300"):
        dsmc.simulate_cooling(0.6, 200, **{**KW, "relax": 1e300})


# MD: every sample, record and snapshot reads the N rods (N + 5000 events each against
# MAX_EVENTS), cooling sample points and records are scheduled up front and the mixture
# keeps every sample's N velocities: hostile counts are refused by name before any work
# (n_samples=10**12 built a linspace of 8 TB; sample_interval=1e-9 kept 5e9 samples)

MD_KW = dict(seed=1, collisions_per_particle=10.0, n_batches=2)


def _refused_at_once(call, error, match):
    start = time.perf_counter()
    with pytest.raises(error, match=match):
        call()
    assert time.perf_counter() - start < 1.0


@pytest.mark.parametrize("simulate, changes, error, match", [
    (md.simulate_heated, dict(sample_interval=1e-9), ValueError,
     r"sample_interval=1e-09 \(about 5e\+09 samples.*MAX_EVENTS.*take fewer samples"),
    (md.simulate_heated, dict(sample_interval=1e-300), ValueError,
     r"sample_interval=1e-300 mean free times.*must be >= 1e-11"),
    (md.simulate_heated, dict(n_records=10**12), ValueError,
     r"n_records=1000000000000.*MAX_EVENTS"),
    (md.simulate_cooling, dict(n_samples=10**12), ValueError,
     r"n_samples=1000000000000.*MAX_EVENTS"),
    (md.simulate_cooling, dict(n_records=10**12), ValueError,
     r"n_records=1000000000000.*MAX_EVENTS"),
    (md.simulate_cooling, dict(n_samples=True), ValueError, "n_samples must be a positive int"),
    (md.simulate_cooling, dict(n_samples=50.0), ValueError, "n_samples must be a positive int"),
    (md.simulate_cooling, dict(n_samples=-5), ValueError, "n_samples must be a positive int"),
    (md.simulate_heated, dict(n_records=True), ValueError, "n_records must be a positive int"),
    (md.simulate_heated, dict(n_records=2.5), ValueError, "n_records must be a positive int"),
    (md.simulate_cooling, dict(n_records=0), ValueError, "n_records must be a positive int"),
    (md.simulate_cooling, dict(n_records=-1), ValueError, "n_records must be a positive int"),
])
def test_md_refuses_hostile_sample_counts_at_once(simulate, changes, error, match):
    _refused_at_once(lambda: simulate(0.9, 50, **{**MD_KW, **changes}), error, match)


def test_md_snapshots_beyond_the_memory_are_refused_by_name():
    # 1e5 snapshots of N = 1e7 rods: 16 TB of positions and velocities
    _refused_at_once(lambda: md.simulate_cooling(0.9, 10**7, snapshots_at=[1.0] * 10**5,
                                                 **MD_KW),
                     MemoryError, r"len\(snapshots_at\)=100000.*GiB.*take fewer samples")


HEATED_MIX = Mixture.white_noise((1.0, 4.0), (0.5, 0.5), alpha=0.9)
COOLING_MIX = Mixture((1.0, 2.0), (0.5, 0.5))


@pytest.mark.parametrize("mixture, n, changes, error, match", [
    (HEATED_MIX, 100, dict(sample_interval=1e-9), ValueError,
     r"keeping the velocities of sample_interval=1e-09 \(about 5e\+09 samples.*MAX_EVENTS"),
    (HEATED_MIX, 100, dict(sample_interval=1e-13), ValueError,
     r"sample_interval=1e-13 .*must be >= 1e-11"),
    (HEATED_MIX, 100, dict(sample_interval=-1.0), ValueError, "sample_interval"),
    (HEATED_MIX, 100, dict(sample_interval=math.nan), ValueError, "sample_interval"),
    # 5e5 samples of 1e6 velocities (4 TB) pass the work bound, not the memory
    (HEATED_MIX, 10**6, dict(sample_interval=1e-5), MemoryError,
     r"sample_interval=1e-05 \(about 5e\+05 samples.*GiB.*take fewer samples"),
    (COOLING_MIX, 100, dict(n_samples=10**12), ValueError,
     r"n_samples=1000000000000.*MAX_EVENTS"),
    (COOLING_MIX, 10**6, dict(n_samples=10**6), MemoryError, r"n_samples=1000000.*GiB"),
    (COOLING_MIX, 100, dict(n_samples=True), ValueError, "n_samples must be an integer"),
    (COOLING_MIX, 100, dict(n_samples=50.0), ValueError, "n_samples must be an integer"),
])
def test_md_mixture_refuses_hostile_sample_counts_at_once(mixture, n, changes, error, match):
    _refused_at_once(lambda: md_mixture.simulate_mixture(
        mixture, n, **{**MD_KW, "threshold": 1e-3, **changes}), error, match)


def test_md_largest_planned_runs_of_the_repository_pass_the_checks():
    """Beyond the largest stops among the callers (figures: heated N = 5000 over 3001
    collisions per particle, 2000 samples, here 10000 at the mixture figure's
    sample_interval 0.2; cooling 400 samples, 20000 records, 20 snapshots) are allowed (the
    run is stopped at once by the wall-time limit, before any sample)."""
    with pytest.raises(RuntimeError, match="before any sample was taken"):
        md.simulate_heated(0.999, 5000, seed=1, collisions_per_particle=3001.0,
                           warmup=1000.0, n_records=20000, sample_interval=0.2,
                           max_wall_time=1e-9)
    with pytest.raises(RuntimeError, match="before any sample was taken"):
        md.simulate_cooling(0.9, 25000, seed=1, collisions_per_particle=1e4, n_samples=400,
                            n_records=20000, snapshots_at=np.linspace(500.0, 1e4, 20),
                            threshold=1e-3, max_wall_time=1e-9)
