"""Tests of the FEM homogeneous cooling state (kinetic_fem.solvers.fem.cooling)."""

from __future__ import annotations

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.solvers.fem import cooling as fem_cooling
from kinetic_fem.solvers.fem import cooling_links as fem_cooling_links


def test_registered_as_default_cooling_method():
    assert kf.COOLING_SOLVERS["fem"] is fem_cooling.solve_fem_cooling


@pytest.fixture(scope="module")
def hcs_085() -> kf.VelocityDistribution:
    return kf.solve_cooling(0.85, spacing=0.1)


def test_constraints_and_energy_identity(hcs_085):
    """Unit mass and temperature (imposed); zeta = <(1-alpha^2)|g|^3>/8 by the pair
    rule (not imposed). Measured: identity 1.7e-11 relative at alpha = 0.85, 9e-13 at 0.5."""
    dist = hcs_085
    assert dist.raw_moments[0] == pytest.approx(1.0, abs=1e-12)
    assert dist.temperature == pytest.approx(1.0, abs=1e-12)
    extra = dist.info.extra
    assert extra["zeta_identity"] == pytest.approx(extra["zeta"], rel=1e-9)
    assert np.all(dist.values > 0)


@pytest.mark.slow
def test_agrees_with_the_fd_cooling_state(hcs_085):
    """FEM (P2, bulk spacing 0.1) against the paper's FD HCS at alpha = 0.85.

    Measured: zeta 0.149084763567 (FEM) vs 0.149084758903 (FD), 3.1e-8 relative; a2
    -0.23948994 vs -0.23949009, 1.4e-7 (the FD is second order; FEM at bulk spacing
    0.04 gives zeta 0.149084759042, within 1e-9 of the FD).
    """
    fd = kf.solve_cooling(0.85, method="fd")
    assert hcs_085.info.extra["zeta"] == pytest.approx(fd.info.extra["zeta"], rel=1e-7)
    assert hcs_085.a2 == pytest.approx(fd.a2, abs=5e-7)


def test_power_kernel_energy_identity():
    """gamma = 2: zeta from Newton equals <(1-alpha^2)|g|^4>/8 of the discrete state."""
    dist = kf.solve_cooling(0.5, kernel=2.0)
    extra = dist.info.extra
    assert extra["zeta_identity"] == pytest.approx(extra["zeta"], rel=1e-9)


def test_strong_inelasticity_by_continuation():
    """alpha = 0.3 (Newton from the Gaussian start diverged there) is reached by
    continuation from alpha = 0.5. Measured against the fd state with two Richardson
    levels: a2 7e-9, zeta 7e-10 relative; alpha = 0: 6e-8 and 6e-10. On the coarse mesh
    of this test (spacing 0.2) the identity holds to 1e-9."""
    dist = kf.solve_cooling(0.3, spacing=0.2)
    extra = dist.info.extra
    assert extra["zeta_identity"] == pytest.approx(extra["zeta"], rel=1e-9)
    assert dist.temperature == pytest.approx(1.0, rel=1e-10)
    assert dist.a2 == pytest.approx(0.265054, abs=2e-5)


def test_velocity_dependent_law_is_refused():
    with pytest.raises(kf.model.UnsupportedModelError, match="speed scale"):
        kf.solve_cooling(kf.ThresholdRestitution(0.5, 1.0))


def test_bad_options():
    with pytest.raises(ValueError, match="order"):
        kf.solve_cooling(0.5, order=4)
    with pytest.raises(ValueError, match="order"):  # the hump mesh is P2
        kf.solve_cooling(0.99, order=3)
    with pytest.raises(TypeError):
        kf.solve_cooling(0.5, spacin=0.1)


@pytest.mark.slow
def test_maxwell_hcs_closed_form():
    """Maxwell model: f(c) = 2/(pi (1+c^2)^2), zeta = (1-alpha^2)/4 for every alpha.

    Measured (bulk spacing 0.04, geometric mesh to 1e8): zeta 1.5e-9 (alpha = 0.5),
    2.4e-9 (0.9); f over |c| <= 10: 1.2e-4 and 1.7e-5 relative (limited by the
    geometric far tail, ratio 1.1 beyond c = 30, which carries 4 % of the energy;
    halving the bulk spacing does not reduce it).
    """
    for alpha in (0.5, 0.9):
        problem = kf.CoolingProblem.from_parameters(alpha, kernel=0.0)
        state = fem_cooling.cooling_state(problem, spacing=0.04)
        assert state.zeta == pytest.approx((1 - alpha**2) / 4, rel=1e-8)
        c = np.linspace(0.0, 10.0, 1001)
        f = np.exp(state.log_f(c))
        assert np.abs(f / fem_cooling.maxwell_hcs(c) - 1).max() < 3e-4


@pytest.fixture(scope="module")
def hcs_093() -> kf.VelocityDistribution:
    return kf.solve_cooling(0.93, resolution=0.14)


def test_near_elastic_state_on_the_hump_mesh(hcs_093):
    """alpha = 0.93 by one continuation step from eps = 0.1 on the hump mesh.

    Measured zeta/eps: 1.0021305966 (resolution 0.14), 1.0021305926 (0.1), 1.0021305917
    (0.07), order ~4.3, so 0.14 hump widths is within ~6e-9 of the limit; a2
    -0.40527016 (0.14), -0.40527018 (0.07); the identity holds to 3e-12 (not imposed)."""
    dist = hcs_093
    extra = dist.info.extra
    assert dist.info.converged
    assert extra["zeta_identity"] == pytest.approx(extra["zeta"], rel=1e-10)
    assert extra["zeta"] / 0.07 == pytest.approx(1.0021305913, rel=1e-8)
    assert dist.a2 == pytest.approx(-0.4052701803, abs=1e-7)
    assert dist.temperature == pytest.approx(1.0, abs=1e-12)
    assert np.all(dist.values > 0)


def test_hump_chain_and_options():
    assert fem_cooling.hump_chain(0.05) == [0.05]
    chain = fem_cooling.hump_chain(1e-6)
    assert chain[-1] == 1e-6 and all(a / b <= 2.0 + 1e-12 for a, b in
                                     zip([0.1, *chain[:-1]], chain, strict=True))
    with pytest.raises(ValueError, match="resolution"):
        kf.solve_cooling(0.5, resolution=0.1)
    with pytest.raises(ValueError, match="resolution"):
        kf.solve_cooling(0.99, resolution=-0.1)


def test_unresolved_humps_say_so():
    """A Newton that cannot converge on the hump mesh names the mesh and the fix."""
    with pytest.raises(fem_cooling.ConvergenceError, match="smaller resolution"):
        kf.solve_cooling(0.93, resolution=0.14, max_iter=1)


def test_newton_stalled_at_round_off_reports_converged():
    """Issue 10, item 7: a tolerance below round-off is not a failure: Newton stops where
    the residual stalls and reports converged with the residual it reached."""
    dist = kf.solve_cooling(0.93, resolution=0.14, tol=1e-30)
    assert dist.info.converged
    assert "stalled at round-off" in dist.info.message
    assert 0.0 < dist.info.residual < 1e-9  # residual / zeta reached (about 1e-12)
    assert dist.info.extra["zeta"] / 0.07 == pytest.approx(1.0021305966, rel=1e-9)


def test_failure_below_the_frontier_names_the_limit(monkeypatch):
    """Below HUMP_FRONTIER a failed continuation step is reported as the known limit of
    the solver with the leading-order alternative, not as a resolution problem."""
    from types import SimpleNamespace

    def state(converged: bool) -> SimpleNamespace:
        return SimpleNamespace(info=SimpleNamespace(converged=converged, message="stalled"),
                               disc=SimpleNamespace(vertices=np.zeros(11)))

    lowest = {"eps": 8e-7}

    def step(prev, eps_prev, eps, **kwargs):  # converges down to lowest["eps"] only
        return state(eps >= lowest["eps"])

    monkeypatch.setattr(fem_cooling, "hump_start", lambda order, intorder: state(True))
    monkeypatch.setattr(fem_cooling_links, "continued_state", step)
    monkeypatch.setattr(fem_cooling_links, "HUMP_MIN_RATIO", 1e9)  # no step halving
    with pytest.raises(fem_cooling.ConvergenceError, match="solve_psi"):
        fem_cooling.solve_fem_cooling(kf.CoolingProblem.from_parameters(1 - 5e-7))
    lowest["eps"] = 1e-3
    with pytest.raises(fem_cooling.ConvergenceError, match="smaller resolution"):
        kf.solve_cooling(1 - 5e-4)


@pytest.fixture(scope="module")
def states_093():
    problem = kf.CoolingProblem.from_parameters(0.93)
    return (fem_cooling.cooling_state(problem, resolution=0.14),
            fem_cooling.cooling_state(problem, resolution=0.07))


def test_two_level_error_estimate_is_reliable(states_093):
    """One Newton step on the bisected mesh estimates the error of zeta and ln f.

    Measured at alpha = 0.93, 0.14 hump widths: zeta error 4.86e-9 against the state at
    0.07 (5.12e-9 against 0.035), estimate 4.86e-9; ln f on |c| < 1.2 1.04e-4 (1.28e-4),
    estimate 1.07e-4.  At eps = 1e-4 true/estimate is 0.86 to 1.02
    (benchmarks/results/fem_cooling.md)."""
    coarse, fine = states_093
    eta, dzeta = coarse.error_estimate()
    assert dzeta == pytest.approx(abs(coarse.zeta / fine.zeta - 1), rel=0.1)
    c = np.linspace(-1.2, 1.2, 2001)
    true = np.abs(coarse.log_f(c) - fine.log_f(c)).max()
    verts = coarse.disc.vertices
    inside = np.abs(0.5 * (verts[1:] + verts[:-1])) < 1.2
    assert 0.7 < true / eta[inside].max() < 1.4
    assert eta.shape == (verts.size - 1,)
    assert np.allclose(eta, eta[::-1])  # an even state has an even estimate


def test_no_growing_modes_on_the_hump_mesh(states_093):
    """The linearised discrete dynamics of a converged hump state has no mode growing
    faster than the cooling itself (an unresolved outer edge shows modes of tens to
    thousands of zeta at the cut-off: benchmarks/results/fem_cooling.md)."""
    coarse, _ = states_093
    rates, where = coarse.growth_rates(4)
    assert rates.shape == where.shape == (4,)
    assert np.all(np.diff(rates) <= 0.0)
    assert rates[0] < 1.0
    assert np.all(where >= 0.0) and np.all(where <= coarse.disc.vertices[-1])


def test_adapted_state_bad_target():
    from kinetic_fem.solvers.fem.cooling_adapt import adapted_state
    with pytest.raises(ValueError, match="target"):
        adapted_state(None, 0.0)  # type: ignore[arg-type]


@pytest.mark.slow
def test_deep_near_elastic_state_alpha_09999():
    """The default path at eps = 1e-4 (0.07 hump widths, Gauss degree 9).

    Convergence study (benchmarks/results/fem_cooling.md, reference 0.035 hump widths,
    Gauss degree 9): zeta/eps = 1.000000886408331, error 2.9e-13 at 0.07; a2 =
    -0.663288246600, error 2.8e-11 at 0.07; ln f where f > 1e-30 within 1.3e-5."""
    dist = kf.solve_cooling(0.9999)
    extra = dist.info.extra
    assert dist.info.converged
    assert extra["zeta"] / 1e-4 == pytest.approx(1.000000886408331, rel=2e-12)
    assert dist.a2 == pytest.approx(-0.663288246600, abs=1e-10)
    assert extra["zeta_identity"] == pytest.approx(extra["zeta"], rel=1e-10)


@pytest.mark.slow
def test_near_elastic_frontier_alpha_0999999():
    """The default path at eps = 1e-6 (the frontier; 2.4e-5 before round 6).

    Convergence study (benchmarks/results/fem_cooling.md, reference 0.035 hump widths):
    zeta/eps = 1.000000001941814, a2 = -0.666506511629; at this eps zeta's round-off is
    ~6e-11 relative (the Newton zeta and the energy identity differ by 5.6e-11), a2's
    differences between meshes 2e-11 to 4e-11; the default measured 3.6e-11 and 2.3e-11
    from the reference (107 CPU s at load 13)."""
    dist = kf.solve_cooling(0.999999)
    extra = dist.info.extra
    assert dist.info.converged
    assert extra["zeta"] / 1e-6 == pytest.approx(1.000000001941814, rel=2e-10)
    assert dist.a2 == pytest.approx(-0.666506511629, abs=1e-10)
    assert extra["zeta_identity"] == pytest.approx(extra["zeta"], rel=2e-10)
