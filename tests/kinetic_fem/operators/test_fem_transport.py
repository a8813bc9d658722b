"""The heated Newton iteration's thermostat forms from cached element arrays equal
scikit-fem's assembly to round-off (issue 16)."""

from __future__ import annotations

import numpy as np
import pytest
from skfem import asm

from kinetic_fem.operators.fem_discretisation import FEMDiscretisation, mass
from kinetic_fem.operators.fem_transport import TransportArrays


@pytest.mark.parametrize("order", [1, 2, 3])
@pytest.mark.parametrize("friction", [0.0, 1.3])
def test_transport_equals_assembly(order, friction):
    rng = np.random.default_rng(order)
    verts = np.concatenate([-np.geomspace(12.0, 0.1, 40), [0.0], np.geomspace(0.1, 12.0, 40)])
    disc = FEMDiscretisation(0.5, verts, order, 2 * order + 1, friction=friction)
    x = disc.dof_locations
    u = -0.5 * x**2 + 0.1 * rng.standard_normal(x.size)
    res0, jac0 = disc.transport(u, jacobian=True)
    mass0 = asm(mass, disc.basis, u=disc.field(u))
    forms = TransportArrays(disc.basis, friction)
    res1, jac1, mass1 = forms.transport(u, jacobian=True)
    res2, none, mass2 = forms.transport(u)
    assert none is None and np.array_equal(res1, res2) and np.array_equal(mass1, mass2)
    assert np.abs(res1 - res0).max() < 1e-14 * np.abs(res0).max()
    assert np.abs(jac1 - jac0).max() < 1e-14 * np.abs(jac0).max()
    assert np.abs(mass1 - mass0).max() < 1e-14 * np.abs(mass0).max()


@pytest.mark.parametrize("order", [2, 3])
def test_transport_jacobian_scatter_is_the_add_at_sum(order):
    """The per-(i, j) scatter of the thermostat Jacobian adds the same terms as
    ``np.add.at`` (at most two per entry, a shared vertex): equal bit for bit."""
    verts = np.concatenate([-np.geomspace(12.0, 0.1, 30), [0.0], np.geomspace(0.1, 12.0, 30)])
    disc = FEMDiscretisation(0.5, verts, order, 2 * order + 1, friction=0.7)
    forms = TransportArrays(disc.basis, 0.7)
    u = -0.5 * disc.dof_locations**2
    _, jac, _ = forms.transport(u, jacobian=True)
    _, slope, p = forms.fields(u)
    wp = forms.dx * p
    coef = wp * slope + 0.7 * (wp * forms.x)
    local = np.einsum("ieq,jeq,eq->ije", forms.dphi, forms.phi, coef) \
        + np.einsum("ieq,jeq,eq->ije", forms.dphi, forms.dphi, wp)
    n_local = forms.dofs.shape[0]
    rows = np.repeat(forms.dofs[:, None, :], n_local, axis=1).ravel()
    cols = np.repeat(forms.dofs[None, :, :], n_local, axis=0).ravel()
    ref = np.zeros_like(jac)
    np.add.at(ref, (rows, cols), -local.ravel())
    assert np.array_equal(jac, ref)
