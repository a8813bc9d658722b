r"""
Relaxation spectrum: how fast the heated gas forgets
====================================================

Linearising the Galerkin system about the steady state :math:`P^*` gives the
generalised eigenproblem :math:`J x = -\lambda M x` (:math:`J` the Jacobian of the
collision and noise terms in :math:`u = \ln P`, :math:`M_{ij} = \int\varphi_i\varphi_j
P^*`), whose eigenvalues are the relaxation rates of small perturbations
(:func:`kinetic_fem.relaxation_spectrum`).  Mass is conserved and, under white noise, so
is momentum: both give a zero rate, which is dropped.  The slowest even mode relaxes the
temperature.

Two checks on this page:

* the Maxwell model (``kernel=0.0``): its moment equations close and are triangular, so
  the rate of the ``k``-th moment is exact (:func:`kinetic_fem.solvers.relaxation.maxwell_rates`);
  the FEM rates match them;
* hard rods near elastic collisions: claim C2 of the paper, a relaxation time
  :math:`\tau \sim \varepsilon^{-2/3}`, measured here without any particle noise.  The
  slowest even rate times :math:`\tau_{C2} = [D/(n(1-\alpha^2))]^{2/3}/D` tends to a
  constant.
"""

from __future__ import annotations

import os

import numpy as np

import kinetic_fem as kf
from kinetic_fem import sonine
from kinetic_fem.solvers.relaxation import maxwell_rates

QUICK = bool(os.environ.get("KINETIC_FEM_DOCS_QUICK"))
TEST_KWARGS = {"alphas": (0.6, 0.9), "spacing": 0.2}


def main(alphas=(0.6, 0.9, 0.99, 0.999), spacing: float | None = None):
    """Maxwell rates (FEM, exact) at alpha = 0.5 and the hard-rod slowest rates."""
    maxwell = kf.relaxation_spectrum(0.5, kernel=0.0, n_rates=6,
                                     spacing=0.2 if spacing is None else spacing)
    exact = maxwell_rates(0.5, 7)[1:]
    rods = [kf.relaxation_spectrum(a, n_rates=4, spacing=spacing) for a in alphas]
    return maxwell, exact, rods


if __name__ == "__main__":
    import matplotlib.pyplot as plt

    alphas = (0.6, 0.9, 0.99) if QUICK else (0.6, 0.9, 0.99, 0.999)
    maxwell, exact, rods = main(alphas)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    k = np.arange(2, 2 + exact.size)
    ax1.plot(k, exact, "o", label="exact moment rates")
    ax1.plot(k, maxwell.rates, "x", label="FEM")
    ax1.set_xlabel("moment k")
    ax1.set_ylabel(r"rate $\lambda$ (n = 1)")
    ax1.set_title("Maxwell model, alpha = 0.5")
    ax1.legend()
    eps = 1 - np.array(alphas)
    even = np.array([s.slowest("even") for s in rods])
    ax2.loglog(eps, even, "o-", label="slowest even rate")
    ax2.loglog(eps, even[-1] * (eps / eps[-1]) ** (2 / 3), "--", label=r"$\varepsilon^{2/3}$")
    ax2.set_xlabel(r"$\varepsilon = 1 - \alpha$")
    ax2.set_ylabel(r"rate $\lambda$ (n = D = 1)")
    ax2.set_title("hard rods, white noise")
    ax2.legend()
    for a, lam in zip(alphas, even, strict=True):
        print(f"alpha = {a}: slowest even rate {lam:.6g}, times tau_C2 "
              f"{lam * sonine.relaxation_time(a):.4f}")
    plt.show()
