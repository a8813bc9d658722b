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
