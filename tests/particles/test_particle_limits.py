"""Particle runs refuse up front what cannot finish or is misspelt (issue 28)."""

import math

import numpy as np
import pytest

from particles import dsmc, md

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
