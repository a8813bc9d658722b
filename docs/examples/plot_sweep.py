r"""
A parameter sweep: a2 against the restitution coefficient
=========================================================

:func:`kinetic_fem.sweep.sweep` evaluates a solver or a particle simulation on the
outer product of a grid of parameters and returns an ``xarray.Dataset`` whose
variables (:math:`T`, :math:`a_2` and its error, the Sonine coefficients, :math:`f(c)`
on a common grid of :math:`c`, ...) carry the grid dimensions.  Here the kurtosis of
the heated gas,

.. math::

    a_2 = \frac{\langle (v-u)^4\rangle}{3T^2} - 1,

is swept over :math:`\alpha` twice: with a deterministic solver (the exact curve) and
with DSMC (points with batch error bars, each point seeded from its own parameters, so
the result does not depend on the number of workers), beside first-order Sonine
theory :math:`a_2 = 16(1-2\alpha^2)/(129+30\alpha^2)`.  With ``store=DIR`` every
finished point is written at once, and a sweep that is interrupted and run again
computes only the missing points; ``executor=client`` runs it on a dask cluster.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import kinetic_fem as kf
from kinetic_fem.sonine import a2_first_order
from particles import dsmc

TEST_KWARGS = {"alphas": (0.3, 0.9), "method": "spectral", "n_particles": 500,
               "collisions_per_particle": 20.0, "executor": "serial"}


@dataclass(frozen=True)
class SweepResult:
    """What :func:`main` computes: two ``xarray.Dataset`` over ``alpha``.

    Attributes
    ----------
    deterministic : xarray.Dataset
        :func:`kinetic_fem.solve_heated` with the given method.
    dsmc : xarray.Dataset
        :func:`particles.dsmc.simulate_heated`, with ``a2_error``.
    """

    deterministic: Any
    dsmc: Any


def main(alphas: tuple[float, ...] = (0.1, 0.3, 0.5, 0.7, 0.9), method: str = "fem",
         n_particles: int = 10_000, collisions_per_particle: float = 400.0,
         executor: Any = None, store: str | None = None) -> SweepResult:
    """Sweep :math:`a_2(\\alpha)` with ``method`` and with DSMC.

    ``executor``: None (local process pool), "serial", any Executor or a dask Client;
    ``store``: a directory for the DSMC points (resumable).
    """
    grid = {"alpha": list(alphas)}
    det = kf.sweep(kf.solve_heated, grid, method=method, executor=executor)
    runs = kf.sweep(dsmc.simulate_heated, grid, n_particles=n_particles,
                    collisions_per_particle=collisions_per_particle, seed=2002,
                    executor=executor, store=store)
    return SweepResult(det, runs)


# %%
# A small sweep: the Dataset, and :math:`a_2` of both methods side by side.
result = main(**TEST_KWARGS)
print(result.dsmc[["T", "a2", "a2_error", "n_collisions"]])
for alpha in result.dsmc.alpha.values:
    print(f"alpha={alpha:.2f}: a2 {result.deterministic.attrs['method']} "
          f"{float(result.deterministic.a2.sel(alpha=alpha)):+.4f}, DSMC "
          f"{float(result.dsmc.a2.sel(alpha=alpha)):+.4f} +- "
          f"{float(result.dsmc.a2_error.sel(alpha=alpha)):.4f}, first-order Sonine "
          f"{a2_first_order(alpha):+.4f}")

# %%
# :math:`a_2(\alpha)`: the deterministic curve, DSMC with error bars and the Sonine
# approximation; and the family :math:`f(c)` on a log scale.
if __name__ == "__main__":
    import os

    import matplotlib.pyplot as plt

    from kinetic_fem.plot import plot_a2, plot_f

    # The documentation build in CI sets KINETIC_FEM_DOCS_QUICK=1: three alphas, DSMC
    # with 5000 particles and 200 collisions per particle (the full run: five alphas,
    # 10000 particles, 400 collisions per particle; about a minute on 2 cores).
    quick = os.environ.get("KINETIC_FEM_DOCS_QUICK") == "1"
    result = (main(alphas=(0.2, 0.5, 0.8), n_particles=5000, collisions_per_particle=200.0)
              if quick else main())
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
    plot_a2(result.deterministic, ax=ax1, theory=a2_first_order,
            theory_label="first-order Sonine")
    plot_a2(result.dsmc, ax=ax1, label="DSMC")
    plot_f(result.deterministic, ax=ax2)
    plt.show()
