"""The FEM collision kernel's fast paths (issue 16): per-piece sums, the mirrored even sum.

The kernel's Jacobian is checked against central differences of its residual, and the
even path (outer points at v > 0 only, mirrored) against the full sum, for every element
degree, bracket, kernel exponent and restitution law.  Sizes are small so the tests also
run with ``NUMBA_DISABLE_JIT=1``.
"""

from __future__ import annotations

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.operators.fem_discretisation import FEMDiscretisation

CASES = [(order, symmetric, gamma, None) for order in (1, 2, 3) for symmetric in (False, True)
         for gamma in (1.0, 0.0, 0.5)]
LAWS = [(2, False, 1.0, kf.ViscoelasticRestitution(0.3)),
        (2, False, 0.5, kf.ThresholdRestitution(0.5, 1.0))]


def _disc(order, symmetric, gamma, law, n_el=24):
    return FEMDiscretisation(0.6, np.linspace(-9.0, 9.0, n_el + 1), order, 2 * order + 1,
                             symmetric, gamma=gamma, law=law)


def _even_u(disc):
    x = disc.dof_locations
    return -0.3 * x**2 + 0.05 * np.cos(x) - 1.0


@pytest.mark.parametrize(("order", "symmetric", "gamma", "law"), CASES + LAWS)
def test_even_sum_equals_full_sum(order, symmetric, gamma, law):
    """Mirrored half sum = full sum to round-off (measured 1e-14 relative to the largest
    entry; tolerance 1e-12) for the residual, the Jacobian and both pair moments."""
    disc = _disc(order, symmetric, gamma, law)
    u = _even_u(disc)
    full = disc.collision(u, jacobian=True, energy_power=3)
    half = disc.collision(u, jacobian=True, energy_power=3, even=True)
    for a, b in zip(full[:2], half[:2], strict=True):
        assert np.abs(a - b).max() <= 1e-12 * np.abs(a).max()
    assert half[2] == pytest.approx(full[2], rel=1e-12)
    assert disc.energy_loss(u, even=True) == pytest.approx(disc.energy_loss(u), rel=1e-12)


@pytest.mark.parametrize(("order", "symmetric", "gamma", "law"), CASES)
def test_jacobian_matches_central_differences(order, symmetric, gamma, law):
    """dC/du against (C(u + h) - C(u - h)) / 2 with |h| = 1e-6: the difference error is
    O(h^2) ~ 1e-12 plus round-off 1e-16/1e-6; tolerance 1e-7 of the largest product."""
    disc = _disc(order, symmetric, gamma, law)
    rng = np.random.default_rng(3)
    u = _even_u(disc) + 0.1 * rng.standard_normal(disc.dof_locations.size)
    _, jac, _ = disc.collision(u, jacobian=True)
    du = 1e-6 * rng.standard_normal(u.size)
    diff = 0.5 * (disc.collision(u + du)[0] - disc.collision(u - du)[0])
    assert np.abs(diff - jac @ du).max() < 1e-7 * np.abs(jac @ du).max()


def test_even_residual_conserves_mass():
    """The mirrored sum keeps the exact mass conservation of the pair rule."""
    disc = _disc(2, False, 1.0, None)
    coll, _, rate = disc.collision(_even_u(disc), even=True, energy_power=1)
    assert abs(coll.sum()) < 1e-13 * rate


def test_mirror_is_the_dof_at_minus_v():
    disc = _disc(2, False, 1.0, None, n_el=6)
    x = disc.dof_locations
    np.testing.assert_allclose(x[disc.mirror], -x, atol=1e-14)
    np.testing.assert_array_equal(disc.mirror[disc.mirror], np.arange(x.size))


def test_mirror_refuses_an_asymmetric_mesh():
    disc = FEMDiscretisation(0.6, np.array([-2.0, -0.5, 0.0, 1.0, 2.0]), 2, 5)
    with pytest.raises(ValueError, match="symmetric"):
        disc.collision(np.zeros(disc.dof_locations.size), even=True)


def test_negative_energy_power_is_refused():
    disc = _disc(1, False, 1.0, None, n_el=4)
    with pytest.raises(ValueError, match="energy_power"):
        disc.collision(np.zeros(disc.dof_locations.size), energy_power=-1)
