"""Tests of the near-elastic cooling state of hard kernels (solvers.fem.cooling_quasi)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.model import CoolingProblem, UnsupportedModelError
from kinetic_fem.solvers.fem.cooling import cooling_state
from kinetic_fem.solvers.fem.cooling_newton import CoolingState
from kinetic_fem.solvers.fem.cooling_quasi import (
    check_frontier,
    efold_vertices,
    quasi_elastic_chain,
)
from kinetic_fem.solvers.fem.heated import FEMDiscretisation

ZETA_REF = {0.995: 2.005042729432, 0.999: 2.001001674898}
"""zeta / eps of the default path at half the default spacing (0.0085, 0.005; 2097 and
2941 dofs), measured: the default spacing differs by 4.6e-11 and 3.1e-11."""


def _gaussian_humps(eps: float) -> CoolingState:
    verts = np.linspace(-2.0, 2.0, 801)
    disc = FEMDiscretisation(1.0 - eps, verts, 2, 5, gamma=2.0)
    c = disc.dof_locations
    return CoolingState(disc, -((np.abs(c) - 1.0) ** 2) / (2.0 * eps), 2.0 * eps, None)


def test_efold_vertices_follow_the_humps():
    eps = 2e-3
    state = _gaussian_humps(eps)
    verts = efold_vertices(state, eps, efolds=1.0, depth=100.0, cutoff_depth=110.0)
    assert np.all(np.diff(verts) > 0) and 0.0 in verts
    np.testing.assert_allclose(verts, -verts[::-1], atol=1e-14)
    # the cut-off: the first vertex beyond 1 + sqrt(2 * 110 * eps) (at most one element of
    # max_size 0.05 beyond: below the depth 100 the elements are not limited)
    edge = 1.0 + math.sqrt(220.0 * eps)
    assert edge < verts[-1] <= edge + 0.05
    log_f = state.log_f(verts)
    fall = np.abs(np.diff(log_f))
    shallow = np.maximum(log_f[1:], log_f[:-1]) > -100.0
    assert fall[shallow].max() < 1.1  # 1 e-fold (slope at the left end of each element)
    assert np.diff(verts).max() <= 0.05 + 1e-12
    core = np.abs(verts[1:] - 1.0) < 3.0 * math.sqrt(eps)
    assert np.diff(verts)[core].max() <= math.sqrt(eps) / 3.0 + 1e-12


def test_efold_vertices_reject_broad_states():
    state = _gaussian_humps(0.5)
    with pytest.raises(ValueError, match="not a near-elastic state"):
        efold_vertices(state, 0.5)


def test_gamma2_quasi_elastic_link():
    """One continuation from alpha 0.99 to 0.995 on e-fold meshes: zeta against the default
    path at half the spacing, the energy identity, the second-order estimate
    zeta/eps = 2 + eps (two Gaussian humps of variance eps at +-sqrt(1 - eps)), bimodal."""
    start = cooling_state(CoolingProblem.from_parameters(0.99, kernel=2.0), tol=1e-7)
    state = quasi_elastic_chain(start, 0.01, 0.995, tol=1e-11, max_iter=40)
    assert state.info.converged
    eps = 0.005
    assert state.zeta / eps == pytest.approx(ZETA_REF[0.995], rel=1e-8)
    assert state.energy_identity() == pytest.approx(state.zeta, rel=1e-8)
    assert state.zeta / eps - 2.0 - eps == pytest.approx(1.7 * eps**2, rel=0.2)
    assert state.log_f(np.array([0.0]))[0] < -60.0 < state.log_f(np.array([1.0]))[0]


@pytest.mark.slow
def test_gamma2_alpha0999():
    """The bug: kf.solve_cooling(0.999, kernel=2.0) raised ConvergenceError (alpha 0.99794).
    The chain's state was 3.8e-8 from the reference, the identity 3.6e-8 from zeta; the
    default is now one Newton solve from the anchors (.fem_cooling_gamma2): 1.1e-9 and
    9.2e-10 (benchmarks/archive/results/fem_cooling_models_speed.md)."""
    dist = kf.solve_cooling(0.999, kernel=2.0)
    extra = dist.info.extra
    assert extra["zeta"] / 1e-3 == pytest.approx(ZETA_REF[0.999], rel=1e-7)
    assert extra["zeta_identity"] == pytest.approx(extra["zeta"], rel=1e-7)
    assert dist.temperature == pytest.approx(1.0, abs=1e-10)


def test_frontier_error_says_what_is_allowed():
    check_frontier(0.9995, 2.0)
    with pytest.raises(UnsupportedModelError, match=r"alpha <= 0.9995"):
        check_frontier(0.9999, 2.0)


@pytest.mark.slow
def test_gamma2_beyond_frontier():
    with pytest.raises(UnsupportedModelError, match=r"alpha <= 0.9995"):
        kf.solve_cooling(0.9999, kernel=2.0)
