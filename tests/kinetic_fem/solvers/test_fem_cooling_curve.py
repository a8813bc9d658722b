"""Tests of warm starts of the near-elastic cooling state (fem_cooling_links, _curve)."""

from __future__ import annotations

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.model import CoolingProblem
from kinetic_fem.solvers.fem import cooling as fem_cooling
from kinetic_fem.solvers.fem.cooling_curve import cooling_curve
from kinetic_fem.solvers.fem.cooling_links import link_chain, start_state

# Two converged solves of the same discrete equations differ by the Newton tolerance
# (tol = 1e-11 on ln f and the relative zeta; measured: zeta 1.1e-14, a2 1.9e-14 over
# a 10-point curve eps = 0.099 ... 1e-3, benchmarks/archive/results/fem_cooling_speed.md)
NEWTON_TOL = 1e-11


@pytest.fixture(scope="module")
def cold_002():
    return kf.solve_cooling(0.98)


def test_warm_start_from_a_state_equals_the_cold_solve(cold_002):
    neighbour = fem_cooling.cooling_state(CoolingProblem.from_parameters(0.97))
    warm = kf.solve_cooling(0.98, initial=neighbour)
    assert warm.info.extra["n_dofs"] == cold_002.info.extra["n_dofs"]  # the same mesh
    assert warm.info.extra["zeta"] == pytest.approx(cold_002.info.extra["zeta"],
                                                    rel=NEWTON_TOL)
    assert abs(warm.a2 - cold_002.a2) < NEWTON_TOL


def test_warm_start_from_a_distribution_and_upward(cold_002):
    """The distribution kf.solve_cooling returned, at a smaller eps (continuation up)."""
    warm = kf.solve_cooling(0.98, initial=kf.solve_cooling(0.985))
    assert warm.info.extra["zeta"] == pytest.approx(cold_002.info.extra["zeta"],
                                                    rel=NEWTON_TOL)
    assert abs(warm.a2 - cold_002.a2) < NEWTON_TOL


def test_initial_is_ignored_away_from_the_near_elastic_path():
    cold = kf.solve_cooling(0.5)
    warm = kf.solve_cooling(0.5, initial=kf.solve_cooling(0.98))
    assert warm.info.extra["zeta"] == cold.info.extra["zeta"]


def test_bad_initial_is_refused():
    with pytest.raises(ValueError, match="initial"):
        start_state(np.zeros(3))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="zeta"):
        kf.solve_cooling(0.98, initial=kf.solve_heated(0.98))


def test_link_chain_both_directions():
    assert link_chain(0.04, 0.01, 2.0) == pytest.approx([0.02, 0.04])
    assert link_chain(1e-3, 0.1, 16.0) == pytest.approx([0.01, 1e-3])
    assert link_chain(0.02, 0.021, 16.0) == [0.02]


def test_cooling_curve_equals_pointwise(cold_002):
    curve = cooling_curve([0.6, 0.97, 0.98])  # alpha 0.6: pointwise, no warm start
    assert curve.zeta[2] == pytest.approx(cold_002.info.extra["zeta"], rel=NEWTON_TOL)
    assert abs(curve.a2[2] - cold_002.a2) < NEWTON_TOL
    assert curve.zeta[0] == kf.solve_cooling(0.6).info.extra["zeta"]
    assert curve.wall_time > 0.0
    with pytest.raises(ValueError, match="non-empty"):
        cooling_curve([])
