r"""
Event-driven MD of heated inelastic rods: f(c), a2 and density fluctuations
============================================================================

:func:`particles.md.simulate_heated` follows :math:`N` hard rods of length
:math:`\sigma` on a ring of length :math:`L = N/n` exactly, collision by collision
(:math:`v_1' - v_2' = -\alpha(v_1 - v_2)`, momentum conserved), and kicks every rod,
:math:`v \to v + \sqrt{2D\,\Delta t_k}\,\xi`, every :math:`\Delta t_k` (0.1 mean free
times by default).  Unlike DSMC it keeps the spatial correlations: at strong
inelasticity the rods cluster (paper Fig. 1, inset) and :math:`f(c)` departs from the
homogeneous Boltzmann prediction; as :math:`\alpha \to 1` the kurtosis approaches
first-order Sonine theory (claim C3, the MD inset of Fig. 3),

.. math::

    a_2 = \frac{16(1-2\alpha^2)}{129 + 30\alpha^2} \to -\frac{16}{159}.

The collision frequency of rods is that of point particles at the density
:math:`n/(1 - n\sigma)` (free length of the ring), which sets the Sonine temperature
compared with below.
"""

from __future__ import annotations

import numpy as np

from kinetic_fem.sonine import a2_first_order, steady_temperature
from particles import md

TEST_KWARGS = {"n_particles": 500, "collisions_per_particle": 200.0}


def main(alpha: float = 0.99, n_particles: int = 5000, collisions_per_particle: float = 2000.0,
         packing: float = 0.5, seed: int = 2002) -> md.MDRun:
    """Heated MD at ``alpha`` with n sigma = ``packing``; the second half is sampled."""
    return md.simulate_heated(alpha, n_particles, sigma=packing, seed=seed,
                              collisions_per_particle=collisions_per_particle)


# %%
# A small run: temperature and a2 against first-order Sonine theory (at the density
# of the free ring), and the exact energy balance of the run.
run = main(**TEST_KWARGS)
alpha, n_free = run.params["alpha"], 1.0 / (1.0 - 0.5)
print(f"N={run.params['n_particles']}, {run.collisions_per_particle:.0f} collisions per "
      f"particle, {run.n_kicks} kicks")
print(f"T  = {run.temperature:.4f}   (Sonine {steady_temperature(alpha, n_free):.4f})")
print(f"a2 = {run.a2:+.4f} +- {run.a2_error:.4f}   (Sonine {a2_first_order(alpha):+.4f})")
print(f"energy balance error {run.energy_balance_error:.1e}")

# %%
# f(c) on a log scale against the Gaussian, and the density fluctuations
# Var N / <N> in boxes of increasing size (1 for independent points,
# (1 - n sigma)^2 = 0.25 for equilibrium hard rods).
if __name__ == "__main__":
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    c = np.linspace(-5, 5, 201)
    for a in (0.6, 0.99):
        r = main(alpha=a)
        d = r.distribution
        keep = d.values > 0
        ax1.errorbar(d.c[keep], d.f_values[keep], yerr=d.f_errors[keep], fmt=".", ms=3,
                     label=f"MD alpha={a}")
        fl = r.density_fluctuations
        ax2.semilogx(fl.box_sizes, fl.variance_ratio, "o-", label=f"alpha={a}")
    ax1.plot(c, np.exp(-c**2 / 2) / np.sqrt(2 * np.pi), "k-", label="Gaussian")
    ax1.set(yscale="log", ylim=(1e-6, 1), xlabel="c", ylabel="f(c)")
    ax1.legend()
    ax2.axhline(0.25, color="gray", ls=":")
    ax2.set(xlabel="box size", ylabel="Var N / <N>")
    ax2.legend()
    fig.tight_layout()
    plt.show()
