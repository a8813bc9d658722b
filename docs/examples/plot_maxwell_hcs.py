r"""
The inelastic Maxwell model: a cooling state in closed form
===========================================================

For the Maxwell kernel :math:`B(g) = 1` (``kernel=0.0``) the homogeneous cooling state
is known for every restitution coefficient (Baldassarri, Marini Bettolo Marconi and
Puglisi, Europhys. Lett. 58, 14 (2002)):

.. math::

    f(c) = \frac{2}{\pi (1 + c^2)^2}, \qquad \zeta = \frac{1-\alpha^2}{4},

at unit temperature, with :math:`dT/dt = -2\zeta n T`.  Its :math:`c^{-4}` tail has
an infinite fourth moment, and :math:`c^2 f` carries :math:`4/(\pi V)` of the energy
beyond :math:`|c| = V`: the FEM mesh (:mod:`kinetic_fem.solvers.fem.cooling_maxwell`) is
uniform in the bulk and geometric out to :math:`V = 200`, and the state beyond is its
asymptotic series :math:`A c^{-4}(1 - 2c^{-2} + 3c^{-4})` with :math:`A` matched to the
mesh.  This example solves the state with
``kf.solve_cooling(alpha, kernel=0.0)`` and plots it with the closed form and the
relative error.
"""

from __future__ import annotations

import numpy as np

import kinetic_fem as kf
from kinetic_fem.solvers.fem.cooling import maxwell_hcs

TEST_KWARGS = {"alpha": 0.5, "spacing": 0.2}


def main(alpha: float = 0.5, spacing: float = 0.04) -> kf.VelocityDistribution:
    """The FEM Maxwell-model HCS at ``alpha`` (bulk element size ``spacing``)."""
    return kf.solve_cooling(alpha, kernel=0.0, spacing=spacing)


if __name__ == "__main__":
    import matplotlib.pyplot as plt

    dist = main()
    c = np.geomspace(1e-2, 1e3, 400)
    exact = maxwell_hcs(c)
    fem = dist.f(c)
    fig, (ax, ax_err) = plt.subplots(2, 1, sharex=True, figsize=(6, 6))
    ax.loglog(c, fem, label="FEM")
    ax.loglog(c, exact, "--", label=r"$2/(\pi(1+c^2)^2)$")
    ax.set_ylabel("f(c)")
    ax.legend()
    ax.set_title(f"zeta = {dist.info.extra['zeta']:.10f} (exact {(1 - 0.25) / 4:.10f})")
    ax_err.loglog(c, np.abs(fem / exact - 1))
    ax_err.set_xlabel("c")
    ax_err.set_ylabel("relative error")
    plt.show()
