"""The Maxwell model's cooling state on the short mesh with the analytic tail closure.

Measured with the defaults (P3, h0 = 0.04, mesh to c = 200, 1171 dofs), against the
closed form f = 2/(pi (1+c^2)^2), zeta = (1 - alpha^2)/4 (relative zeta error, largest
relative f error over |c| <= 10; benchmarks/archive/results/fem_cooling_models_speed.md):
alpha 0: 9.7e-12, 4.0e-8; 0.3: 2.2e-11, 1.6e-8; 0.5: 4.5e-11, 1.6e-8; 0.9: 1.4e-10,
2.0e-8; 0.99: 7.0e-11, 7.0e-8; 0.999: 9.7e-12, 9.9e-7; T - 1 of the returned
distribution <= 5.1e-10.  The bounds are twice these.
"""

from __future__ import annotations

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.solvers.fem import cooling as fem_cooling
from kinetic_fem.solvers.fem import cooling_maxwell as fem_cooling_maxwell
from kinetic_fem.solvers.fem.cooling_tail import maxwell_hcs

C = np.linspace(-10.0, 10.0, 4001)
MEASURED = {0.0: (9.7e-12, 4.0e-8), 0.3: (2.2e-11, 1.6e-8), 0.9: (1.4e-10, 2.0e-8),
            0.99: (7.0e-11, 7.0e-8), 0.999: (9.7e-12, 9.9e-7)}


@pytest.mark.parametrize("alpha", sorted(MEASURED))
def test_default_state_against_the_closed_form(alpha):
    dist = kf.solve_cooling(alpha, kernel=0.0)
    zeta_err, f_err = MEASURED[alpha]
    extra = dist.info.extra
    assert extra["order"] == 3 and extra["cutoff"] == fem_cooling_maxwell.MAXWELL_TAIL_CUTOFF
    assert extra["zeta"] == pytest.approx((1 - alpha**2) / 4, rel=2 * zeta_err)
    assert extra["zeta_identity"] == pytest.approx(extra["zeta"], rel=2 * zeta_err)
    assert np.abs(dist.f(C) / maxwell_hcs(C) - 1.0).max() < 2 * f_err
    # mesh plus tail nodes: unit mass and temperature to the Newton tolerance
    assert dist.temperature == pytest.approx(1.0, abs=1e-9)
    assert dist.v[-1] > 1e8


def test_heavy_tail_moments_are_reported_infinite():
    """f ~ c^-4: <c^4> diverges, so a2 is infinite, not the quadrature's truncated value."""
    dist = kf.solve_cooling(0.5, kernel=0.0)
    assert dist.a2 == np.inf and dist.moment(4) == np.inf and dist.moment(6) == np.inf
    assert dist.mean == 0.0 and dist.moment(3) == 0.0
    assert np.isnan(dist.sonine_coefficient(3))
    assert dist.temperature == pytest.approx(1.0, abs=1e-9)


def test_one_jacobian_from_the_closed_form():
    """Newton from the closed form: one Newton step (and at most one chord step)."""
    state = fem_cooling.cooling_state(kf.CoolingProblem.from_parameters(0.7, kernel=0.0))
    assert isinstance(state, fem_cooling_maxwell.MaxwellTailState)
    assert state.info.converged and state.info.iterations <= 2
    # the tail amplitude is the closed form's 2/pi (measured 1.2e-7 relative at V = 200)
    assert state.amplitude == pytest.approx(2.0 / np.pi, rel=2.4e-7)
    c = np.array([0.5, 150.0, 250.0, 1e6])
    assert np.allclose(state.log_f(c), np.log(maxwell_hcs(c)), rtol=0, atol=3e-7)


def test_jacobian_matches_finite_differences():
    disc = fem_cooling.FEMDiscretisation(0.6, fem_cooling_maxwell.maxwell_tail_vertices(
        0.5, cutoff=12.0), 2, 5, gamma=0.0)
    system = fem_cooling_maxwell.MaxwellTailSystem(disc)
    u = np.log(maxwell_hcs(disc.dof_locations)) + 0.01 * np.cos(disc.dof_locations)
    x = np.append(system.reduce(u), 0.2)
    r, j = system(x)
    rng = np.random.default_rng(0)
    d = rng.standard_normal(x.size) * 1e-6
    r2, _ = system(x + d, False)
    r1, _ = system(x - d, False)
    assert np.allclose((r2 - r1) / 2.0, j @ d, rtol=1e-5, atol=1e-12)


def test_truncated_mesh_with_a_cutoff_and_order_options():
    """``cutoff`` keeps the truncated mesh (no tail closure); ``order`` and ``spacing``
    set the tail mesh."""
    problem = kf.CoolingProblem.from_parameters(0.5, kernel=0.0)
    truncated = fem_cooling.cooling_state(problem, spacing=0.16, cutoff=1e8)
    assert not isinstance(truncated, fem_cooling_maxwell.MaxwellTailState)
    p2 = fem_cooling.cooling_state(problem, order=2, spacing=0.08)
    assert isinstance(p2, fem_cooling_maxwell.MaxwellTailState) and p2.disc.order == 2
    assert p2.zeta == pytest.approx(0.1875, rel=1e-9)
