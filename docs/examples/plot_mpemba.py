r"""
Mpemba effect: the hotter gas gets there first
==============================================

Two samples of the heated gas relax under the same white noise (Lasanta, Vega Reyes,
Prados and Santos, PRL 119, 148001 (2017)): a hot one at :math:`1.5\,T_{st}` whose
initial distribution has a fat tail, :math:`a_2 = 1` (the initial states are
:math:`\Phi(c)[1 + a_2 S_2(c^2)]`), and a cold one at :math:`1.4\,T_{st}`, Gaussian.
Fast particles dissipate more, :math:`\langle|v-v'|^3\rangle \propto 1 + 3a_2/16`,
so the hot sample cools faster, overtakes the cold one and stays below it: it is the
first to come close to :math:`T_{st}`.

There is a threshold: the hot start needs :math:`a_2` above a critical value
(:func:`kinetic_fem.analysis.mpemba.mpemba_threshold`, here taken as "below the cold
curve after four relaxation times").  For the Maxwell model the energy balance is
closed, :math:`dT/dt = 2D - \tfrac n2(1-\alpha^2)T`: :math:`T(t)` depends on
:math:`T(0)` only, two temperature curves never cross, and no initial shape gives a
Mpemba effect.

Curves: exact (FEM, :func:`kinetic_fem.evolve_heated`; Maxwell: its moment
equations), first Sonine, and DSMC ensembles of the same initial states
(:func:`particles.dsmc_transient.simulate_protocol`).
"""

from __future__ import annotations

import os

import numpy as np

from kinetic_fem.analysis.mpemba import mpemba
from kinetic_fem.figures.memory import MPEMBA_CUTOFF
from particles.dsmc_transient import simulate_protocol

QUICK = bool(os.environ.get("KINETIC_FEM_DOCS_QUICK"))
TEST_KWARGS = {"kernels": (0.0,), "n_particles": 2000, "replicas": 4, "n_times": 11}


def main(kernels=(1.0, 0.0), alpha: float = 0.6, spacing: float = 0.25, rtol: float = 1e-5,
         n_particles: int = 100_000, replicas: int = 64, n_times: int = 31,
         seed: int = 20261126):
    """Exact and first-Sonine Mpemba curves and their DSMC ensembles, per kernel.

    The FEM mesh ends at 10 thermal velocities (``MPEMBA_CUTOFF``), inside the
    tabulated initial states.
    """
    out = []
    for k, gamma in enumerate(kernels):
        res = mpemba(alpha, kernel=gamma, spacing=spacing, rtol=rtol, n_times=n_times,
                     cutoff=MPEMBA_CUTOFF)
        runs = [simulate_protocol(alpha, n_particles, kernel=gamma, times=res.hot.times,
                                  initial=start, replicas=replicas, seed=seed + 2 * k + j)
                for j, start in enumerate(res.initial_states)]
        out.append((res, runs))
    return out


if __name__ == "__main__":
    import matplotlib.pyplot as plt

    # The quick documentation build: a coarser mesh and smaller ensembles.
    results = (main(spacing=0.5, n_particles=20_000, replicas=16, n_times=21)
               if QUICK else main())
    fig, axes = plt.subplots(1, len(results), figsize=(5 * len(results), 4), squeeze=False)
    for ax, (res, runs) in zip(axes[0], results, strict=True):
        t_st = res.steady_temperature
        for curve, son, run, name in ((res.hot, res.hot_sonine, runs[0], "hot"),
                                      (res.cold, res.cold_sonine, runs[1], "cold")):
            line = ax.semilogx(curve.times[1:], curve.temperature[1:] / t_st - 1,
                               label=f"{name}, exact")[0]
            ax.semilogx(son.times[1:], son.temperature[1:] / son.temperature[-1] - 1, "--",
                        color=line.get_color(), label=f"{name}, first Sonine")
            ax.errorbar(run.times[1:], run.temperature[1:] / t_st - 1,
                        yerr=run.temperature_error[1:] / t_st, fmt=".", color=line.get_color(),
                        label=f"{name}, DSMC")
        name = "hard rods" if res.gamma == 1.0 else "Maxwell"
        ax.set_title(f"{name}, alpha = {res.alpha}")
        ax.set_xlabel("t")
        ax.set_ylabel(r"$T/T_{st} - 1$")
        ax.legend(fontsize=7)
        gap = (runs[0].temperature - runs[1].temperature)[-1]
        err = np.hypot(runs[0].temperature_error, runs[1].temperature_error)[-1]
        print(f"{name}: exact crossing at t = {res.crossing}, first Sonine at "
              f"{res.sonine_crossing}; first-Sonine threshold a2 = {res.threshold}; "
              f"DSMC T_hot - T_cold at the last time {gap / t_st:+.4f} +- {err / t_st:.4f}")
    plt.show()
