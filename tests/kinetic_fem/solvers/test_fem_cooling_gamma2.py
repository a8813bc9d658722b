"""Tests of the gamma = 2 cooling state from the stored anchors (solvers.fem.cooling_gamma2)."""

from __future__ import annotations

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.model import CoolingProblem
from kinetic_fem.solvers.fem import cooling_gamma2 as g2
from kinetic_fem.solvers.fem import regimes as fem_regimes
from kinetic_fem.solvers.fem.cooling import cooling_state
from kinetic_fem.solvers.fem.cooling_mesh import hcs_bulk, hcs_cutoff, hcs_spacing, hcs_vertices
from kinetic_fem.solvers.fem.cooling_stored import gamma2_anchors

ANCHOR_POINTS, ANCHORS = gamma2_anchors()


def _default_vertices(problem: CoolingProblem) -> np.ndarray:
    eps = problem.gas.epsilon
    return hcs_vertices(hcs_cutoff(problem), hcs_spacing(problem), gamma=2.0,
                        bulk=hcs_bulk(eps))


def test_uses_anchors():
    assert g2.uses_anchors(CoolingProblem.from_parameters(0.9, kernel=2.0))
    assert g2.uses_anchors(CoolingProblem.from_parameters(0.9995, kernel=2.0))
    assert g2.uses_anchors(CoolingProblem.from_parameters(0.0, kernel=2.0))
    assert g2.uses_anchors(CoolingProblem.from_parameters(0.5, kernel=2.0))
    assert not g2.uses_anchors(CoolingProblem.from_parameters(0.9999, kernel=2.0))
    assert not g2.uses_anchors(CoolingProblem.from_parameters(0.9, kernel=1.5))


def test_wkb_exponent():
    """The Hamilton-Jacobi exponent: zero at the humps, curvature 1 there (variance eps),
    the valley 0.3734 (Fokker-Planck limit 0.4135), increasing outward, tail slope -> c/2."""
    phi = g2.wkb_exponent(np.array([0.0, 1.0, -1.0]))
    assert phi[0] == pytest.approx(0.37340, abs=1e-4)
    assert phi[1:] == pytest.approx([0.0, 0.0], abs=1e-12)
    assert g2.wkb_exponent(np.array([0.0]), fokker_planck=True)[0] == pytest.approx(
        0.41346, abs=1e-4)
    h = 0.02
    curv = (g2.wkb_exponent(np.array([1.0 + h, 1.0 - h])).sum()) / h**2
    assert curv == pytest.approx(1.0, rel=2e-3)
    c = np.linspace(1.0, 6.0, 51)
    assert np.all(np.diff(g2.wkb_exponent(c)) > 0)
    slope = np.diff(g2.wkb_exponent(np.array([5.9, 6.0])))[0] / 0.1
    assert 2.0 * slope / 5.95 == pytest.approx(1.0, abs=0.1)


def test_wkb_exponent_against_the_state():
    """eps (ln f(peak) - ln f(c)) of the state at alpha 0.999 against Phi: measured within
    2e-3 on the hump's flanks (the O(eps) term Psi)."""
    dist = kf.solve_cooling(0.999, kernel=2.0)
    c = np.array([0.8, 0.9, 1.1, 1.2])
    log_f = np.log(np.interp(c, dist.v, dist.values))
    peak = np.log(dist.values.max())
    np.testing.assert_allclose(1e-3 * (peak - log_f), g2.wkb_exponent(c), atol=2e-3)


def test_anchored_start_is_close():
    """Between anchors the interpolated zeta is within 2e-4 (alpha 0.7) of the state's."""
    for alpha in (0.7, 0.999):
        eps = 1.0 - alpha
        state = cooling_state(CoolingProblem.from_parameters(alpha, kernel=2.0))
        assert g2.anchored_zeta(eps) == pytest.approx(state.zeta, rel=2e-4)


@pytest.mark.parametrize("alpha", [0.3, 0.9, 0.99])
def test_gamma2_is_the_chains_state(alpha):
    """The anchored start converges to the state of the path it replaces (the default path
    without the anchors: at 0.3 the pseudo-transient iteration, above 0.5 the chain on the
    coarse mesh, then Newton on the default mesh): equal to round-off where f > 1e-40
    (Newton's monitored range; at 0.9 the far tail below moved 3e-3 in ln f at
    ln f = -154; at 0.99 the mesh ends where the start is 150 below its peak, 929 -> 549
    dofs: measured 1.7e-13 in ln f, zeta 5.6e-16), in at
    most 4 Newton steps (3 measured); the energy identity holds."""
    problem = CoolingProblem.from_parameters(alpha, kernel=2.0)
    state = cooling_state(problem)
    assert state.info.iterations <= 4
    chain = fem_regimes.solve_state(problem, fem_regimes.CoolingOptions(stored=False))
    common = min(state.disc.vertices[-1], chain.disc.vertices[-1])
    np.testing.assert_array_equal(state.disc.vertices[np.abs(state.disc.vertices) <= common],
                                  chain.disc.vertices[np.abs(chain.disc.vertices) <= common])
    assert state.zeta == pytest.approx(chain.zeta, rel=1e-13)
    watched = state.u > state.u.max() - 92.0
    c = state.disc.dof_locations[watched]
    np.testing.assert_allclose(state.u[watched], chain.log_f(c), rtol=0, atol=1e-9)
    assert state.energy_identity() == pytest.approx(state.zeta, rel=1e-9)


def test_gamma2_alpha09_against_finer():
    """zeta and a2 against the anchored state on meshes twice finer: measured 1.3e-8 and
    1.9e-8 (benchmarks/convergence_gamma2_cooling.py); tolerance twice that."""
    problem = CoolingProblem.from_parameters(0.9, kernel=2.0)
    dist = kf.solve_cooling(0.9, kernel=2.0)
    fine = g2.anchored_state(problem, order=2, intorder=None, tol=1e-11, max_iter=40,
                             refine=2.0)
    assert fine is not None
    from kinetic_fem.solvers.fem.cooling import cooling_distribution

    ref = cooling_distribution(problem, fine)
    assert dist.info.extra["zeta"] == pytest.approx(fine.zeta, rel=3e-8)
    assert dist.a2 == pytest.approx(ref.a2, abs=4e-8)


def test_gamma2_near_elastic_from_the_anchors():
    """alpha 0.999 (was 20 links of the chain): zeta against the default path at half the
    spacing (2.001001674898 eps, tests of fem_cooling_quasi), measured 1.1e-9; the energy
    identity; unit temperature; bimodal."""
    dist = kf.solve_cooling(0.999, kernel=2.0)
    extra = dist.info.extra
    assert extra["zeta"] / 1e-3 == pytest.approx(2.001001674898, rel=3e-9)
    assert extra["zeta_identity"] == pytest.approx(extra["zeta"], rel=1e-8)
    assert dist.temperature == pytest.approx(1.0, abs=1e-10)
    f0, f1 = np.interp([0.0, 1.0], dist.v, dist.values)
    assert f0 < 1e-30 * f1


def test_failed_anchored_start_falls_back(monkeypatch):
    """A Newton failure from the anchors leaves the continuation to solve: same state."""
    problem = CoolingProblem.from_parameters(0.7, kernel=2.0)
    fast = cooling_state(problem)
    monkeypatch.setattr(g2, "ANCHORED_ITER", 1)
    assert g2.anchored_state(problem, order=2, intorder=None, tol=1e-11, max_iter=40) is None
    slow = cooling_state(problem)
    assert slow.zeta == pytest.approx(fast.zeta, rel=1e-12)


def test_table_entry_reproduces():
    """An anchor of the table is the old default path's state sampled (alpha 0.195; the
    table is generated by kinetic_fem.solvers.fem.cooling_generate, 8 significant digits)."""
    eps, zeta_ratio, c_end, values = ANCHORS[1]
    problem = CoolingProblem.from_parameters(1.0 - eps, kernel=2.0)
    chain = cooling_state(problem, vertices=_default_vertices(problem))
    ratio, end, samples = g2.anchor_samples(chain, eps, ANCHOR_POINTS)
    assert ratio == pytest.approx(zeta_ratio, rel=1e-12)
    assert end == pytest.approx(c_end, rel=1e-12)
    np.testing.assert_allclose(samples, values, rtol=1e-7, atol=1e-9)


def test_gamma2_alpha0998_on_the_cut_default_mesh():
    """alpha 0.998 (eps >= ANCHORED_DEFAULT_EPS): the default mesh cut 150 below the peak,
    zeta against the e-fold mesh four times finer (0.0040040134660751,
    benchmarks/convergence_gamma2_cooling.py) measured 2.3e-11; the energy identity."""
    dist = kf.solve_cooling(0.998, kernel=2.0)
    extra = dist.info.extra
    assert extra["n_dofs"] < 700
    assert extra["zeta"] == pytest.approx(0.0040040134660751, rel=5e-11)
    assert extra["zeta_identity"] == pytest.approx(extra["zeta"], rel=1e-10)
