r"""
Event-driven MD of freely cooling rods: Haff's law, clusters and x-c snapshots
===============================================================================

Without forcing the rods cool.  While the gas stays homogeneous the temperature
follows Haff's law (claim C9),

.. math::

    T(t) = \frac{T_0}{(1 + t/t_0)^2}, \qquad
    t_0^{-1} = \frac{n_f}{\sqrt\pi}(1-\alpha^2)\sqrt{T_0},

with the free-ring density :math:`n_f = n/(1 - n\sigma)`.  Later the gas clusters.
For a small system close to elastic (paper Fig. 8: :math:`N = 1000`,
:math:`\alpha = 0.9995`, :math:`N\varepsilon = 0.5`) the plain inelastic dynamics
ends in two groups of rods with opposite velocities and a sharply bimodal
:math:`f(c)` (claim C14).  Larger systems undergo inelastic collapse; the threshold
regularisation (``threshold=...``: collisions slower than it are elastic, Ben-Naim
et al.) lets them continue into the :math:`T \sim t^{-2/3}` regime (claim C13).
"""

from __future__ import annotations

import numpy as np

from kinetic_fem.sonine import haff_temperature
from particles import md

TEST_KWARGS = {"n_particles": 100, "alpha": 0.995, "collisions_per_particle": 3000.0}


def main(alpha: float = 0.9995, n_particles: int = 1000,
         collisions_per_particle: float = 6e4, threshold: float | None = None,
         seed: int = 2002) -> md.MDRun:
    """Free cooling from a unit Gaussian; snapshots at 1/15, 1/3, 2/3 and all of the run."""
    cpp = collisions_per_particle
    return md.simulate_cooling(alpha, n_particles, seed=seed, collisions_per_particle=cpp,
                               threshold=threshold, sample_from=2 * cpp / 3,
                               snapshots_at=(cpp / 15, cpp / 3, 2 * cpp / 3, cpp))


# %%
# A small run (N eps = 0.5 as in the paper): Haff's law early on, momentum and
# energy balance to round-off, and the late bimodal f(c).
run = main(**TEST_KWARGS)
s = run.series
early = s["temperature"] > 0.5
haff = haff_temperature(s["t"], run.params["alpha"], density=2.0)
haff_error = np.max(np.abs(s["temperature"] / haff - 1)[early])
print(f"max |T/T_Haff - 1| while T > T0/2: {haff_error:.3f}")
print(f"T(end) = {s['temperature'][-1]:.3e} at t = {s['t'][-1]:.3e}")
print(f"momentum drift {abs(s['momentum'][-1] - s['momentum'][0]):.1e}, "
      f"energy balance error {run.energy_balance_error:.1e}")
d = run.distribution
print(f"late f(0) / max f = {d.f(0.0) / d.f_values.max():.3f} (bimodal)")

# %%
# x-c snapshots (paper Fig. 8, left) and T(t) against Haff's law.
if __name__ == "__main__":
    import matplotlib.pyplot as plt

    run = main()
    fig, axes = plt.subplots(1, 5, figsize=(16, 3.2))
    for ax, snap in zip(axes[:4], run.snapshots, strict=True):
        ax.plot(snap.x, snap.c, ".", ms=1.5)
        ax.set(title=f"{snap.collisions_per_particle:g} coll/particle", xlabel="x")
    axes[0].set_ylabel("c")
    s = run.series
    axes[4].loglog(s["t"][1:], s["temperature"][1:], label="MD")
    axes[4].loglog(s["t"][1:], haff_temperature(s["t"][1:], run.params["alpha"], density=2.0),
                   "k:", label="Haff")
    axes[4].set(xlabel="t", ylabel="T")
    axes[4].legend()
    fig.tight_layout()
    plt.show()
