"""``RestitutionLaw.rescaled(u)``: the law in velocity units of ``u``, alpha_u(g) = alpha(u g).

The free-cooling transient (kinetic_fem/solvers/fem/cooling_transient.py) evaluates
``law.rescaled(V)`` at relative speeds measured in the unit V of a segment.
"""

from __future__ import annotations

import numpy as np
import pytest

from kinetic_fem.model import (
    ConstantRestitution,
    SaturatingKernel,
    ThresholdRestitution,
    ViscoelasticRestitution,
)
from kinetic_fem.model.kernel import PowerLawKernel

LAWS = [ConstantRestitution(0.7), ThresholdRestitution(0.4, threshold=0.8),
        ViscoelasticRestitution(0.15)]


@pytest.mark.parametrize("law", LAWS, ids=lambda law: type(law).__name__)
@pytest.mark.parametrize("u", [1.0, 0.01, 0.37, 5.0])
def test_rescaled_law_is_the_law_at_u_times_g(law, u):
    g = np.geomspace(1e-6, 0.9 * law.max_speed / u if law.max_speed < np.inf else 50.0, 97)
    g = g[np.abs(g * u - getattr(law, "threshold", -1.0)) > 1e-9]   # not on the jump
    np.testing.assert_allclose(law.rescaled(u)(g), law(u * g), rtol=1e-14, atol=0)
    assert law.rescaled(u).max_speed == pytest.approx(law.max_speed / u, rel=1e-13)
    assert law.rescaled(u).min_alpha == pytest.approx(law.min_alpha, rel=1e-14)
    assert law.rescaled(1.0) is law


@pytest.mark.parametrize("kernel", [PowerLawKernel(1.0), PowerLawKernel(0.5),
                                    SaturatingKernel(2.0)], ids=str)
@pytest.mark.parametrize("u", [0.01, 0.37, 5.0])
def test_kernel_in_units_of_u(kernel, u):
    """The counterpart the transient uses for the kernel: B(u g) = u^d K_u(g)."""
    g = np.geomspace(1e-4, 1e3, 61)
    np.testing.assert_allclose(u**kernel.scale_degree * kernel.rescaled(u).rate(g),
                               kernel.rate(u * g), rtol=1e-14)
