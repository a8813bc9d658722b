r"""
DSMC of the freely cooling gas: Haff's law and the two-hump cooling state
==========================================================================

Without forcing the homogeneous gas cools.  At fixed shape of the scaled
distribution :math:`f(c)`, :math:`c = v/\sqrt{T}`, the energy balance

.. math::

    \frac{dT}{dt} = -\frac n4 (1-\alpha^2)\langle |v - v'|^3 \rangle
    \propto -T^{3/2}

gives Haff's law :math:`T(t) = T_0/(1 + t/t_0)^2 \sim t^{-2}` (claim C9;
:func:`kinetic_fem.sonine.haff_temperature`).  :func:`particles.dsmc.simulate_cooling`
rescales the velocities to unit temperature as it goes and keeps :math:`\ln T` and
:math:`\ln t`, so it runs for any number of collisions.  For :math:`\alpha > 0.8` the
homogeneous cooling state is bimodal (claim C10): :math:`f(c)` has two humps near
:math:`c = \pm 1` and :math:`a_2 < 0`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from kinetic_fem.sonine import haff_temperature
from particles import dsmc

TEST_KWARGS = {"n_particles": 2000, "collisions_per_particle": 60.0}


@dataclass(frozen=True)
class CoolingDSMCResult:
    """What :func:`main` computes.

    Attributes
    ----------
    run : particles.dsmc.DSMCRun
        The DSMC run; ``run.distribution`` is the time-averaged f(c).
    haff_exponent : float
        Fitted exponent of :math:`T \\propto t^{x}` after relaxation (Haff: -2).
    haff_prefactor_ratio : float
        :math:`T(t)` of the run over Haff's law with the measured :math:`a_2`, the
        decay rate fitted to the late times: tends to a constant.
    """

    run: dsmc.DSMCRun
    haff_exponent: float
    haff_prefactor_ratio: float


def main(alpha: float = 0.9, n_particles: int = 25_000,
         collisions_per_particle: float = 1000.0, seed: int = 2002) -> CoolingDSMCResult:
    """Cool the gas from a unit Gaussian and fit Haff's law to the late times."""
    run = dsmc.simulate_cooling(alpha, n_particles, seed=seed,
                                collisions_per_particle=collisions_per_particle)
    s = run.series
    late = s["collisions_per_particle"] > run.relaxed_at
    exponent = float(np.polyfit(s["log_t"][late], s["log_temperature"][late], 1)[0])
    # Haff's law at the measured shape, T0 = 1: compare the late-time prefactor
    haff = haff_temperature(np.exp(s["log_t"][late]), alpha, a2=run.a2)
    ratio = float(np.exp(np.mean(s["log_temperature"][late] - np.log(haff))))
    return CoolingDSMCResult(run, exponent, ratio)


# %%
# A small run: the Haff exponent and the kurtosis of the cooling state.
result = main(**TEST_KWARGS)
run = result.run
print(f"N={run.n_particles}, {run.collisions_per_particle:.0f} collisions per particle; "
      f"ln T fell to {run.series['log_temperature'][-1]:.1f}")
print(f"T ~ t^{result.haff_exponent:.3f} after relaxation (Haff: t^-2); T / Haff -> "
      f"{result.haff_prefactor_ratio:.3f}")
print(f"a2 = {run.a2:+.4f} +- {run.a2_error:.4f} (bimodal: negative)")

# %%
# Plot T(t) against Haff's law and the scaled distribution f(c).
if __name__ == "__main__":
    import matplotlib.pyplot as plt

    result = main()
    s = result.run.series
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    t = np.exp(s["log_t"][1:])
    ax1.loglog(t, np.exp(s["log_temperature"][1:]), label="DSMC")
    ax1.loglog(t, result.haff_prefactor_ratio * haff_temperature(t, 0.9, a2=result.run.a2),
               "k--", label="Haff")
    ax1.set(xlabel="t", ylabel="T")
    ax1.legend()
    d = result.run.distribution
    keep = d.values > 0
    ax2.errorbar(d.c[keep], d.f_values[keep], yerr=d.f_errors[keep], fmt=".", ms=3)
    ax2.set(xlabel="c", ylabel="f(c)")
    fig.tight_layout()
    plt.show()
