"""Tests of kinetic_fem.solvers.fem.cooling_forms (element-array forms = skfem asm)."""

from __future__ import annotations

import numpy as np
import pytest
from skfem import asm

from kinetic_fem.operators.fem_transport import TransportArrays
from kinetic_fem.solvers.fem.cooling_forms import cooling_forms
from kinetic_fem.solvers.fem.cooling_newton import second_moment
from kinetic_fem.solvers.fem.heated import FEMDiscretisation, bath_drift, bath_drift_jacobian, mass


@pytest.mark.parametrize("order", [1, 2, 3])
def test_forms_equal_assembly(order):
    verts = np.concatenate([-np.geomspace(6.0, 0.05, 20), [0.0], np.geomspace(0.05, 6.0, 20)])
    disc = FEMDiscretisation(0.9, verts, order, 2 * order + 3)
    u = -0.5 * disc.dof_locations**2 + 0.1 * np.sin(disc.dof_locations)
    field = disc.field(u)
    drift, grad_mass, grad_temp, djac = cooling_forms(TransportArrays(disc.basis), u, True)
    for mine, ref in ((drift, asm(bath_drift, disc.basis, u=field)),
                      (grad_mass, asm(mass, disc.basis, u=field)),
                      (grad_temp, asm(second_moment, disc.basis, u=field)),
                      (djac, asm(bath_drift_jacobian, disc.basis, u=field).toarray())):
        # round-off: each entry sums at most 2 elements x 7 points in another order
        assert np.abs(mine - ref).max() <= 16 * np.finfo(float).eps * np.abs(ref).max()
    assert cooling_forms(TransportArrays(disc.basis), u, False)[3] is None
