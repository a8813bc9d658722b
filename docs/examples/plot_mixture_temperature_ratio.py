r"""
Granular mixtures: the temperature ratio against the mass ratio
===============================================================

Beyond the paper: a binary mixture of rods of masses :math:`m_1, m_2` (equal number
fractions), one restitution coefficient for every pair, heated by white noise or cooling
freely (:class:`kinetic_fem.model.Mixture`).  The kinetic temperatures
:math:`T_s = m_s\langle v^2\rangle_s` of the two species differ as soon as collisions are
inelastic: energy equipartition breaks down.

Three methods:

* the **exact moments of the inelastic Maxwell mixture** (kernel ``gamma = 0``,
  :mod:`kinetic_fem.solvers.maxwell_mixture`): the moment equations close;
* the **Gaussian approximation** (first-order Sonine theory of the ratio,
  :mod:`kinetic_fem.solvers.mixture_gaussian`), for any kernel, here hard rods; it is
  exact for the Maxwell kernel, which the tests check to 1e-11;
* **DSMC** of the mixture (:func:`particles.dsmc_mixture.simulate_mixture`), the exact
  solution of the Boltzmann equations up to statistical errors.

Two forcing conventions: the same diffusion coefficient :math:`D` for both species, or
the same mean power per rod (:math:`D_s \propto 1/m_s`).
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from kinetic_fem.model import Mixture
from kinetic_fem.solvers import maxwell_mixture, mixture_gaussian
from particles.dsmc_mixture import simulate_mixture

MASS_RATIOS = tuple(float(m) for m in np.geomspace(0.1, 10.0, 21))
"""The default mass ratios m2/m1 of the curves."""

TEST_KWARGS = {"mass_ratios": (0.2, 5.0), "dsmc_ratios": (5.0,), "n_particles": 400,
               "collisions_per_particle": 40.0}


@dataclass(frozen=True)
class RatioCurves:
    """T_1/T_2 against m_2/m_1 for each alpha and convention.

    ``maxwell[(alpha, convention)]`` and ``gaussian[...]`` are arrays over ``mass_ratios``;
    ``dsmc[(alpha, convention)]`` a list of ``(mass ratio, T1/T2, standard error)``.
    """

    mass_ratios: np.ndarray
    maxwell: dict
    gaussian: dict
    dsmc: dict


def _mixture(mass_ratio: float, alpha: float, kernel: float, convention: str) -> Mixture:
    return Mixture.white_noise((1.0, mass_ratio), (0.5, 0.5), alpha=alpha, kernel=kernel,
                               convention=convention)


def main(alphas=(0.5, 0.9), conventions=("same_diffusion", "same_power"),
         mass_ratios=MASS_RATIOS, dsmc_ratios=(0.1, 1.0, 10.0),
         n_particles: int = 2000, collisions_per_particle: float = 400.0,
         seed: int = 27) -> RatioCurves:
    """Compute the three methods' temperature ratios (DSMC at ``dsmc_ratios`` only)."""
    ratios = np.asarray(mass_ratios, dtype=float)
    maxwell, gaussian, dsmc = {}, {}, {}
    for alpha in alphas:
        for conv in conventions:
            key = (alpha, conv)
            maxwell[key] = np.array([maxwell_mixture.steady_state(
                _mixture(m, alpha, 0.0, conv)).temperature_ratio() for m in ratios])
            gaussian[key] = np.array([mixture_gaussian.steady_state(
                _mixture(m, alpha, 1.0, conv)).temperature_ratio() for m in ratios])
            dsmc[key] = []
            for m in dsmc_ratios:
                run = simulate_mixture(_mixture(m, alpha, 1.0, conv), n_particles, seed=seed,
                                       collisions_per_particle=collisions_per_particle)
                dsmc[key].append((m, run.temperature_ratio(), run.temperature_ratio_error()))
    return RatioCurves(ratios, maxwell, gaussian, dsmc)


# %%
# A small computation: the Gaussian ratio of hard rods at mass ratio 5 against DSMC.
small = main(**TEST_KWARGS)
for key, points in small.dsmc.items():
    for m, ratio, err in points:
        g = small.gaussian[key][list(small.mass_ratios).index(m)]
        print(f"alpha={key[0]}, {key[1]}, m2/m1={m:g}: T1/T2 Gaussian {g:.4f}, "
              f"DSMC {ratio:.4f} +- {err:.4f}")

# %%
# The curves: T_1/T_2 on a log scale against m_2/m_1, Maxwell (exact) dashed, hard
# rods (Gaussian) solid, DSMC of hard rods as points.
if __name__ == "__main__":
    import matplotlib.pyplot as plt

    quick = os.environ.get("KINETIC_FEM_DOCS_QUICK") == "1"
    curves = main(n_particles=500, collisions_per_particle=60.0) if quick else main()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, conv in zip(axes, ("same_diffusion", "same_power"), strict=True):
        for color, alpha in zip(("C0", "C1"), (0.5, 0.9), strict=True):
            key = (alpha, conv)
            ax.plot(curves.mass_ratios, curves.gaussian[key], "-", color=color,
                    label=f"hard rods, Gaussian, alpha={alpha}")
            ax.plot(curves.mass_ratios, curves.maxwell[key], "--", color=color,
                    label=f"Maxwell, exact, alpha={alpha}")
            pts = np.array(curves.dsmc[key])
            ax.errorbar(pts[:, 0], pts[:, 1], yerr=pts[:, 2], fmt="o", color=color, ms=4)
        ax.set(xscale="log", yscale="log", xlabel="m2/m1", title=conv.replace("_", " "))
    axes[0].set_ylabel("T1/T2")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    plt.show()
