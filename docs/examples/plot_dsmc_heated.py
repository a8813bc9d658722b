r"""
DSMC of the randomly heated gas: a2, f(c) and the energy balance
================================================================

Direct Simulation Monte Carlo (:func:`particles.dsmc.simulate_heated`) solves the
homogeneous Boltzmann equation of the heated one-dimensional inelastic gas,

.. math::

    \partial_t P - D\partial_v^2 P = Q[P, P],

with :math:`N` particles: candidate pairs are accepted with probability
:math:`|v_1 - v_2|/g_{max}`, :math:`g_{max} = \max v - \min v`, and white-noise kicks
:math:`v \to v + \sqrt{2D\,\Delta t}\,\xi` alternate with the collisions (Strang
splitting).  In the steady state the energy dissipated by the collisions,
:math:`\tfrac12(1-\alpha^2)\sum g^2` per unit time and particle, balances the
injection :math:`2D` (claim C1; :math:`2D(1-1/N)` into the internal energy of a
finite system).  The kurtosis :math:`a_2` is compared with a deterministic solver
when one is registered, and always with first-order Sonine theory (claim C3),

.. math::

    a_2 = \frac{16(1-2\alpha^2)}{129 + 30\alpha^2}.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import kinetic_fem as kf
from kinetic_fem.sonine import a2_first_order, steady_temperature
from particles import dsmc

TEST_KWARGS = {"n_particles": 2000, "collisions_per_particle": 60.0, "deterministic": False}


@dataclass(frozen=True)
class HeatedDSMCResult:
    """What :func:`main` computes.

    Attributes
    ----------
    run : particles.dsmc.DSMCRun
        The DSMC run (``run.distribution`` is P(v); ``run.distribution.f(c)`` the
        scaled distribution).
    a2_sonine, temperature_sonine : float
        First-order Sonine :math:`a_2` and steady temperature.
    deterministic : kinetic_fem.VelocityDistribution or None
        A deterministic steady state (``"fem"`` or ``"fd"``) when registered.
    """

    run: dsmc.DSMCRun
    a2_sonine: float
    temperature_sonine: float
    deterministic: kf.VelocityDistribution | None


def main(alpha: float = 0.6, n_particles: int = 25_000,
         collisions_per_particle: float = 1000.0, seed: int = 2002,
         deterministic: bool = True) -> HeatedDSMCResult:
    """Run the heated DSMC at ``alpha`` and collect the comparisons.

    With ``deterministic=True`` also solve the steady state with the first registered
    of ``"fem"``, ``"fd"`` (seconds).
    """
    run = dsmc.simulate_heated(alpha, n_particles, seed=seed,
                               collisions_per_particle=collisions_per_particle)
    det = None
    for method in ("fem", "fd") if deterministic else ():
        if method in kf.HEATED_SOLVERS:
            det = kf.solve_heated(alpha, method=method)
            break
    return HeatedDSMCResult(run, a2_first_order(alpha), steady_temperature(alpha), det)


# %%
# A small run: the steady temperature and :math:`a_2` with their batch errors, and
# the energy balance measured from the collisions.
result = main(**TEST_KWARGS)
run = result.run
print(f"N={run.n_particles}, {run.collisions_per_particle:.0f} collisions per particle, "
      f"averaging from {run.relaxed_at:.1f}")
print(f"T  = {run.temperature:.4f}   (first-order Sonine {result.temperature_sonine:.4f})")
print(f"a2 = {run.a2:+.4f} +- {run.a2_error:.4f}   (first-order Sonine {result.a2_sonine:+.4f})")
print(f"dissipation {run.dissipation_rate:.4f} +- {run.dissipation_error:.4f}, "
      f"injection 2D(1-1/N) = {run.injection_rate:.4f}")

# %%
# Plot f(c) with error bars, on a log scale, against the Gaussian and the
# deterministic solution (paper Fig. 2), and the time series of T and a2.
if __name__ == "__main__":
    import matplotlib.pyplot as plt

    result = main()
    d = result.run.distribution
    keep = d.values > 0
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    ax1.errorbar(d.c[keep], d.f_values[keep], yerr=d.f_errors[keep], fmt=".", ms=3,
                 label="DSMC")
    c = np.linspace(-6, 6, 301)
    ax1.plot(c, np.exp(-c**2 / 2) / np.sqrt(2 * np.pi), "k:", label="Gaussian")
    if result.deterministic is not None:
        ax1.plot(c, result.deterministic.f(c), "k-", label=result.deterministic.method)
    ax1.set(yscale="log", ylim=(1e-7, 1), xlabel="c", ylabel="f(c)")
    ax1.legend()
    s = result.run.series
    ax2.plot(s["collisions_per_particle"], s["a2"], label="a2")
    ax2.plot(s["collisions_per_particle"], s["temperature"] / result.temperature_sonine - 1,
             label="T / T_sonine - 1")
    ax2.axvline(result.run.relaxed_at, color="gray", ls=":")
    ax2.set(xlabel="collisions per particle")
    ax2.legend()
    fig.tight_layout()
    plt.show()
