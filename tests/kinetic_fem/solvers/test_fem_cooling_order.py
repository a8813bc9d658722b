"""The P3 default of the FEM cooling state and the reused energy identity (issue 16)."""

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.model import CoolingProblem
from kinetic_fem.solvers.fem.cooling import cooling_state
from kinetic_fem.solvers.fem.cooling_order import P3_SPACING, cooling_order, order_spacing


def test_default_order():
    hard = CoolingProblem.from_parameters(0.5)
    soft = CoolingProblem.from_parameters(0.5, kernel=kf.PowerLawKernel(0.5))
    assert cooling_order(hard, None, default_mesh=True) == 3
    assert cooling_order(hard, None, default_mesh=False) == 2
    assert cooling_order(soft, None, default_mesh=True) == 2
    assert cooling_order(hard, 1, default_mesh=True) == 1
    assert order_spacing(0.05, 3) == pytest.approx(P3_SPACING * 0.05)
    assert order_spacing(0.05, 2) == 0.05


def test_p3_default_matches_fine_p2():
    """The P3 default (spacing 0.1) against P2 at 0.025, alpha = 0.6.

    Measured: zeta 2.2e-11 relative, a2 1.2e-10 apart, about the reference's own P2 error
    (the P2 default at 0.05 is 3.4e-10 and 1.8e-9 from it: fourth order, 16 times);
    the P3 default is 1e-14 from P3 at 0.025 (``fem_cooling_order`` notes)."""
    dist = kf.solve_cooling(0.6)
    assert dist.info.extra["order"] == 3
    ref = kf.solve_cooling(0.6, order=2, spacing=0.025)
    zeta, zeta_ref = dist.info.extra["zeta"], ref.info.extra["zeta"]
    assert zeta == pytest.approx(zeta_ref, rel=2e-10)
    assert dist.a2 == pytest.approx(ref.a2, abs=1e-9)
    # the energy identity, not imposed, holds to the pair rule's accuracy
    assert dist.info.extra["zeta_identity"] == pytest.approx(zeta, rel=1e-11)


def test_energy_identity_reuses_the_last_loss_moment():
    state = cooling_state(CoolingProblem.from_parameters(0.7), spacing=0.2, order=2)
    reused = state.energy_identity()
    state.disc._last_loss.clear()
    assert state.energy_identity() == reused  # bit for bit
    other = state.u + 1e-3 * np.cos(state.disc.dof_locations)
    state.disc.collision(other, even=True)
    assert state.energy_identity() == reused


def test_continuation_link_takes_few_newton_steps():
    """eps = 0.1 -> 0.05 on the link mesh: 8 Newton steps once decreases of ln f take the
    step on f after zeta settles (34 before: the far tail fell one e-fold per step)."""
    from kinetic_fem.solvers.fem import cooling as fc

    start = fc.hump_start(2, None)
    state = fc.continued_state(start, 0.1, 0.05, resolution=fc.HUMP_LINK_RESOLUTION,
                               tol=fc.HUMP_STEP_TOL, max_iter=fc.HUMP_STEP_ITER)
    assert state.info.converged
    assert state.info.iterations <= 12
    assert state.zeta / 0.05 == pytest.approx(1.00233726835, rel=1e-9)
