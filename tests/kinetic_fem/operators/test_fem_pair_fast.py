"""The pair kernel's fast path for P2/P3 with a constant coefficient, and the P3 element.

The fast path (:mod:`kinetic_fem.operators.fem_pair_fast`) must equal the generic loop
of :func:`kinetic_fem.operators.fem_kernels.collision_operator`.  The generic loop is
reached with the same coefficient through a threshold law whose threshold (1e-300) no
pair reaches: the same pieces, the same rule, only the code differs.
"""

from __future__ import annotations

import numpy as np
import pytest

from kinetic_fem.model.restitution import CONSTANT, THRESHOLD
from kinetic_fem.operators.fem_discretisation import LAGRANGE_ELEMENTS, FEMDiscretisation
from kinetic_fem.operators.fem_kernels import collision_operator, evaluate_field


def _kernel(disc, u, code, gamma, mirror):
    verts, dofs = disc.mesh_arrays
    xq, wq, eq = disc.points
    rx, rw = disc.basis.quadrature
    args = (verts, dofs, disc.order, u, xq, wq, eq, np.ascontiguousarray(rx[0]), rw, 0.6, 1.0,
            True, 3, False, gamma, code, 0.6, 1e-300, 1.0, 0.8)
    return collision_operator(*args, mirror) if mirror is not None else collision_operator(*args)


@pytest.mark.parametrize("order", [2, 3])
@pytest.mark.parametrize("gamma", [1.0, 0.5, 0.0])
@pytest.mark.parametrize("even", [False, True])
def test_fast_path_equals_the_generic_loop(order, gamma, even):
    """Residual, Jacobian and both moments equal to round-off (measured <= 3e-15 of the
    largest entry; tolerance 1e-13)."""
    disc = FEMDiscretisation(0.6, np.linspace(-8.0, 8.0, 41), order, 2 * order + 1)
    x = disc.dof_locations
    u = -0.4 * x**2 + 0.05 * np.cos(x) - 1.0
    mirror = disc.mirror if even else None
    fast = _kernel(disc, u, CONSTANT, gamma, mirror)
    generic = _kernel(disc, u, THRESHOLD, gamma, mirror)
    for a, b in zip(fast[:2], generic[:2], strict=True):
        assert np.abs(a - b).max() <= 1e-13 * np.abs(b).max()
    assert fast[2] == pytest.approx(generic[2], rel=1e-13)
    assert fast[3] == pytest.approx(generic[3], rel=1e-13)


def test_no_moments_leaves_the_residual_unchanged():
    disc = FEMDiscretisation(0.6, np.linspace(-8.0, 8.0, 21), 3, 7)
    u = disc.gaussian(1.5)
    with_m = disc.collision(u, jacobian=True, even=True)
    without = disc.collision(u, jacobian=True, energy_power=None, even=True)
    np.testing.assert_array_equal(with_m[0], without[0])
    np.testing.assert_array_equal(with_m[1], without[1])
    assert without[2] == 0.0


def test_p3_element_matches_scikit_fem_and_is_cubic():
    """evaluate_field with the kernel's P3 shape functions equals scikit-fem's probes of
    ElementLineP3, and P3 interpolates cubics exactly."""
    disc = FEMDiscretisation(0.5, np.linspace(-3.0, 3.0, 7), 3, 7)
    assert isinstance(disc.basis.elem, LAGRANGE_ELEMENTS[3])
    x = disc.dof_locations
    v = np.linspace(-2.95, 2.95, 23)
    verts, dofs = disc.mesh_arrays
    u = np.sin(x)
    np.testing.assert_allclose(evaluate_field(verts, dofs, 3, u, v),
                               disc.basis.probes(v[None, :]) @ u, rtol=0, atol=1e-14)
    cubic = 0.3 * x**3 - x**2 + 2.0
    np.testing.assert_allclose(evaluate_field(verts, dofs, 3, cubic, v),
                               0.3 * v**3 - v**2 + 2.0, rtol=0, atol=1e-13)
