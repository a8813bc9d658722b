"""Stored starts of the near-elastic cooling state and the faster default (issue 16)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from kinetic_fem.model import CoolingProblem
from kinetic_fem.solvers.fem import cooling as fc
from kinetic_fem.solvers.fem.cooling_generate import seed_state
from kinetic_fem.solvers.fem.cooling_hump import HUMP_FAST_LINK, P3_MONITOR_LOG_F
from kinetic_fem.solvers.fem.cooling_newton import newton_cooling
from kinetic_fem.solvers.fem.cooling_seeds import SEED_EPS, SeedStart, seed_start


@pytest.mark.parametrize("eps", SEED_EPS)
def test_stored_seeds_are_the_recomputed_link_states(eps):
    """The table is ln f rounded to 8 digits: a stale table (a changed link path) shows."""
    stored, eps_seed = seed_start(eps)
    assert eps_seed == eps
    zeta, c, log_f = stored.zeta, stored.c, stored.values
    fresh = seed_state(eps)
    assert zeta == pytest.approx(fresh.zeta, rel=1e-12)
    verts = fresh.disc.vertices
    nodes = verts[verts >= verts[verts <= 0.5].max()]
    np.testing.assert_allclose(c, nodes, rtol=1e-7, atol=1e-8)
    np.testing.assert_allclose(log_f, fresh.log_f(nodes), rtol=1e-7, atol=1e-8)


def test_seed_start_takes_the_nearest_seed_above():
    assert seed_start(1e-3)[1] == 0.0025
    assert seed_start(0.0025)[1] == 0.0025
    assert seed_start(0.003)[1] == 0.01
    assert seed_start(0.039)[1] == 0.04
    assert seed_start(0.05)[1] == 0.04  # above the largest: the largest


def test_seed_log_f_is_even_and_continued_linearly():
    start = SeedStart([0.4, 1.0, 2.0, 3.0], [0.0, 1.0, -2.0, -5.0], 0.01)
    c = np.array([1.0, 2.5, 4.0, 5.0])
    np.testing.assert_allclose(start.log_f(c), start.log_f(-c))
    np.testing.assert_allclose(start.log_f(np.array([1.0, 2.0, 3.0])), [1.0, -2.0, -5.0])
    assert start.log_f(np.array([5.0]))[0] == pytest.approx(-5.0 - 3.0 * 2.0)


@pytest.fixture(scope="module")
def default_0999():
    return fc.cooling_state(CoolingProblem.from_parameters(0.999))


def test_near_elastic_default_agrees_with_a_finer_reference(default_0999):
    """eps = 1e-3 against P3 at 0.1 hump widths (solved from it).

    Measured (benchmarks/archive/results/fem_cooling_speed.md, ninth round): zeta 2.3e-14
    relative, a2 4.3e-13, ln f 3.0e-7 where f > 1e-30; the P3 0.1 and P2 0.035
    references differ by 1.1e-14, 7.4e-12, 4.6e-7.  Bounds: 4 times the measured error."""
    state = default_0999
    assert state.disc.order == 3
    ref = fc.continued_state(state, 1e-3, 1e-3, resolution=0.1, order=3)
    c = np.linspace(0.0, 0.99 * state.disc.vertices[-1], 20001)
    lr = ref.log_f(c)
    keep = lr > math.log(1e-30)
    assert state.zeta == pytest.approx(ref.zeta, rel=1e-13)
    assert abs(state.disc.distribution(state.u).a2 - ref.disc.distribution(ref.u).a2) < 2e-12
    assert np.abs(state.log_f(c)[keep] - lr[keep]).max() < 1.2e-6


def test_speculative_jacobians_take_the_same_iterates():
    start, eps_seed = seed_start(0.02)
    states = [fc.continued_state(start, eps_seed, 0.03, resolution=HUMP_FAST_LINK, order=2,
                                 intorder=5, tol=1e-7, decades=30.0)]
    disc, zeta0 = states[0].disc, states[0].zeta * 1.001
    u0 = states[0].u + 0.01 * np.cos(disc.dof_locations)
    a, b = (newton_cooling(disc, u0, zeta0, tol=1e-9, pseudo_time=np.inf, speculative=s)
            for s in (False, True))
    assert a.info.converged and b.info.iterations == a.info.iterations
    np.testing.assert_array_equal(a.u, b.u)


def test_stopping_on_the_step_gives_the_state_to_tol(default_0999):
    """predict_iter: the same state as the residual rule to the Newton tolerance."""
    state = default_0999
    disc = state.disc
    u0 = state.u + 1e-4 * np.exp(-disc.dof_locations**2)
    kw = dict(tol=1e-11, pseudo_time=np.inf, monitor=P3_MONITOR_LOG_F, line_search=False)
    on_step = newton_cooling(disc, u0, state.zeta, predict_iter=8, **kw)
    on_residual = newton_cooling(disc, u0, state.zeta, **kw)
    assert on_step.info.converged and on_residual.info.converged
    assert on_step.zeta == pytest.approx(on_residual.zeta, rel=1e-13)
    watched = on_residual.u > P3_MONITOR_LOG_F
    assert np.abs(on_step.u - on_residual.u)[watched].max() < 1e-9
