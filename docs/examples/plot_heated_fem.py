r"""
Heated steady state by Galerkin finite elements
===============================================

The randomly heated inelastic gas reaches a steady state of

.. math::

    0 = D\,\partial_v^2 P + Q[P, P],

solved here with scikit-fem P2 elements on the logarithm :math:`u_h = \ln P_h`
(``method="fem"``, :mod:`kinetic_fem.solvers.fem`) by Newton's method from a Gaussian.  The
logarithmic unknown keeps :math:`P_h > 0` and resolves :math:`f(c)` over 30 decades
relative to itself.  We check three things:

* the energy balance (claim C1), :math:`2D = \tfrac n4 (1-\alpha^2)\langle|v-v'|^3\rangle`,
  holds to round-off in the solver's own quadrature;
* :math:`a_2` is close to first-order Sonine theory (claim C3);
* the far tail decays as :math:`\exp(-A_c c^{3/2})` with
  :math:`A_c = \tfrac23 T^{3/4}` at :math:`n = D = 1` (claim C4).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import kinetic_fem as kf
from kinetic_fem import sonine

TEST_KWARGS = {"alpha": 0.6, "spacing": 0.4}


@dataclass(frozen=True)
class HeatedFEMResult:
    r"""What :func:`main` computes.

    Attributes
    ----------
    distribution : VelocityDistribution
        The FEM steady state.
    energy_injection, energy_loss : float
        Both sides of the discrete energy balance (C1).
    tail_amplitude, tail_amplitude_theory : float
        Fitted slope of :math:`-\ln f` against :math:`c^{3/2}` over the last decade of
        the resolved range and the prediction :math:`\tfrac23 T^{3/4}` (C4).
    """

    distribution: kf.VelocityDistribution
    energy_injection: float
    energy_loss: float
    tail_amplitude: float
    tail_amplitude_theory: float


def main(alpha: float = 0.6, spacing: float | None = None) -> HeatedFEMResult:
    """Solve at ``alpha`` on P2 elements of ``spacing`` thermal velocities (default: production)."""
    dist = kf.solve_heated(alpha, method="fem", spacing=spacing)
    c, f = dist.c, dist.f_values
    tail = (c > 0) & (f > 1e-30)
    sel = tail & (c > 0.8 * c[tail].max())
    amplitude = -np.polyfit(c[sel] ** 1.5, np.log(f[sel]), 1)[0]
    return HeatedFEMResult(dist, dist.info.extra["c1_injection"], dist.info.extra["c1_loss"],
                           float(amplitude),
                           sonine.tail_exponent_amplitude(temperature=dist.temperature))


# %%
# Solve at a few restitution coefficients and print the checks.

if __name__ == "__main__":
    import matplotlib.pyplot as plt

    alphas = (0.0, 0.6, 0.9, 0.99)
    results = {a: main(alpha=a) for a in alphas}
    for a, r in results.items():
        d = r.distribution
        print(f"alpha={a}: T={d.temperature:.10f} a2={d.a2:.8f} (Sonine "
              f"{sonine.a2_first_order(a):.5f})  C1: 2D={2.0:.1f}, injection="
              f"{r.energy_injection:.12f}, loss={r.energy_loss:.12f}  tail A_c fit "
              f"{r.tail_amplitude:.4f} vs {r.tail_amplitude_theory:.4f}  "
              f"({d.info.iterations} Newton iterations, {d.info.wall_time:.1f} s)")

    # %%
    # f(c) over 30 decades against the Gaussian, and the far tail against c^(3/2).
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    cc = np.linspace(0, 20, 400)
    ax1.semilogy(cc, np.exp(-cc**2 / 2) / np.sqrt(2 * np.pi), "k--", label="Gaussian")
    for a, r in results.items():
        d = r.distribution
        keep = (d.c >= 0) & (d.f_values > 1e-30)
        ax1.semilogy(d.c[keep], d.f_values[keep], label=f"alpha = {a}")
        ax2.plot(d.c[keep] ** 1.5, np.log(d.f_values[keep]), label=f"alpha = {a}")
    ax1.set(xlabel="c", ylabel="f(c)", ylim=(1e-30, 1))
    ax2.set(xlabel="c^(3/2)", ylabel="ln f(c)")
    ax1.legend()
    fig.tight_layout()
    plt.show()
