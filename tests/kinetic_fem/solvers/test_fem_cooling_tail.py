"""The Maxwell model's cooling state by FEM against its closed form 2/(pi (1+c^2)^2).

Convergence (``benchmarks/convergence_maxwell_hcs.py``; the whole mesh refines with the
bulk spacing h0): the largest relative error of the returned f over |c| <= 10 falls at
order 2.4 to 2.8; the raw Galerkin ln f_h at vertices and midpoints carries an
element-wise oscillation of order 2 that the recovery removes.
"""

from __future__ import annotations

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.solvers.fem import cooling as fem_cooling
from kinetic_fem.solvers.fem import cooling_tail as fem_cooling_tail

C = np.linspace(-10.0, 10.0, 4001)


def _error(dist: kf.VelocityDistribution) -> float:
    return float(np.abs(dist.f(C) / fem_cooling.maxwell_hcs(C) - 1.0).max())


# measured at h0 = 0.16 (821 dofs): f 1.63e-4, 1.76e-4, 1.77e-4 over |c| <= 10; T - 1 of
# the recovered values -1.9e-6, -2.5e-6 (alpha = 0.3, 0.5); zeta 1.5e-9 ... 7.6e-9
FAST = {0.3: 2.5e-4, 0.5: 2.5e-4, 0.9: 2.5e-4}


@pytest.mark.parametrize("alpha", sorted(FAST))
def test_maxwell_hcs_coarse(alpha):
    """The truncated mesh to c = 1e8 (``cutoff``; the default is the tail closure of
    :mod:`kinetic_fem.solvers.fem.cooling_maxwell`)."""
    dist = kf.solve_cooling(alpha, kernel=0.0, spacing=0.16, cutoff=1e8)
    assert dist.info.extra["zeta"] == pytest.approx((1 - alpha**2) / 4, rel=3e-8)
    assert dist.temperature == pytest.approx(1.0, rel=5e-6)
    assert _error(dist) < FAST[alpha]


def test_recovery_removes_the_element_oscillation():
    """At h0 = 0.16 the raw ln f_h at the nodes is off by 7.5e-4, the recovered f by
    1.8e-4; the oscillation vanishes at the two-point Gauss points."""
    problem = kf.CoolingProblem.from_parameters(0.5, kernel=0.0)
    state = fem_cooling.cooling_state(problem, spacing=0.16, cutoff=1e8)
    verts = state.disc.vertices
    nodes = np.union1d(verts, 0.5 * (verts[1:] + verts[:-1]))
    nodes = nodes[np.abs(nodes) <= 10.0]
    raw = np.abs(state.disc.evaluate(state.u, nodes) / fem_cooling.maxwell_hcs(nodes) - 1)
    rec = np.exp(fem_cooling_tail.recovered_log_f(state.disc, state.u, C))
    rec_err = np.abs(rec / fem_cooling.maxwell_hcs(C) - 1).max()
    assert rec_err < 0.5 * raw.max()


def test_power_tail_vertices():
    v = fem_cooling_tail.power_tail_vertices(1e8, 0.04)
    h = np.diff(v[v >= 0])
    assert v[-1] == 1e8 and np.allclose(v, -v[::-1])
    assert np.allclose(h[: int(2 / 0.04) - 1], 0.04)
    assert h.max() / v[-1] <= 1.25 * 0.04 + 1e-12
    coarse = fem_cooling_tail.power_tail_vertices(1e8, 0.2)
    assert np.diff(coarse).max() / 1e8 <= 0.1 + 1e-12
    with pytest.raises(ValueError):
        fem_cooling_tail.power_tail_vertices(1e8, 0.0)
    pts = fem_cooling_tail.superconvergent_points(np.array([0.0, 1.0]))
    assert np.allclose(pts, [0.5 - 0.5 / np.sqrt(3), 0.5 + 0.5 / np.sqrt(3)])
    pts3 = fem_cooling_tail.superconvergent_points(np.array([0.0, 2.0]), 3)
    assert np.allclose(pts3, 1.0 + np.array([-1.0, 0.0, 1.0]) * np.sqrt(0.6))
    v = fem_cooling_tail.power_tail_vertices(200.0, 0.04, near_factor=1.0, far_factor=0.625)
    h = np.diff(v[v >= 0])
    assert v[-1] == 200.0 and h[60] / v[v >= 0][60] <= 0.04 + 1e-12


@pytest.mark.slow
@pytest.mark.parametrize("alpha", [0.3, 0.5, 0.9])
def test_maxwell_hcs_to_1e6_with_defaults(alpha):
    """The default (h0 = 0.02): measured over |c| <= 10 in the module table."""
    dist = kf.solve_cooling(alpha, kernel=0.0)
    assert dist.info.extra["zeta"] == pytest.approx((1 - alpha**2) / 4, rel=1e-8)
    assert _error(dist) < 1e-6
