r"""
Kovacs hump: the heated gas remembers its shape
===============================================

The Kovacs protocol (Prados and Trizac, PRL 112, 198001 (2014)): the gas is steady
under white noise :math:`D_0 = 1`, is quenched to :math:`D_1 = 10^{-3}` and ages for a
waiting time :math:`t_w`; then the noise is switched to the :math:`D_2` whose steady
temperature equals :math:`T(t_w)`.  If the temperature were the only variable nothing
would happen.  But during the quench the gas cools almost freely and its shape
(:math:`a_2`) moves away from the steady one, and the energy balance

.. math::

    \frac{dT}{dt} = 2D - \frac n4 (1-\alpha^2)\langle|v-v'|^3\rangle,
    \qquad \langle|v-v'|^3\rangle \propto T^{3/2}\Big(1 + \frac{3a_2}{16}\Big)

feels it: :math:`T` leaves :math:`T_{st}` and comes back, a hump whose sign is that of
:math:`a_2^{st} - a_2(t_w)` (negative at :math:`\alpha = 0.3`, where
:math:`a_2^{st} > 0`, positive at :math:`\alpha = 0.9`).  For the Maxwell model the
energy balance is closed and there is no hump.

The exact curves come from the FEM transient (:func:`kinetic_fem.evolve_heated`,
through :func:`kinetic_fem.analysis.memory_effects.kovacs`), beside the first Sonine
approximation and a DSMC ensemble of the same protocol
(:func:`particles.dsmc_transient.simulate_protocol`, error bars from the spread of the
replicas).  At :math:`\alpha = 0.3` the converged hump (spacing and tolerance studied
in ``benchmarks/memory_effects.py``) is :math:`(-4.094 \pm 0.005)\times10^{-3}` at
:math:`t - t_w = 0.740`, against :math:`-6.45\times10^{-3}` from first Sonine.  At
:math:`\alpha = 0.9` it is positive,
:math:`(+4.78 \pm 0.02)\times10^{-3}` at :math:`t - t_w = 2.3`, against
:math:`+2.59\times10^{-3}` from first Sonine; DSMC gives
:math:`(+4.47 \pm 0.29)\times10^{-3}` at :math:`t - t_w = 2.22` (64 replicas of
:math:`10^5` particles; the figure's 16 replicas have error bars twice as large, and
its DSMC curves stay within 2.5 standard errors of the exact ones).  The default run
(spacing 0.25, rtol :math:`10^{-5}`, the step Newton converging every ln P:
``newton_norm="ln_p"``, which :func:`~kinetic_fem.analysis.memory_effects.kovacs` sets)
gives :math:`-4.089\times10^{-3}` at 0.740 and :math:`+4.782\times10^{-3}` at 2.356,
within :math:`10^{-5}` of these; the quick documentation build draws
:math:`\alpha = 0.3` at spacing 0.5, rtol :math:`10^{-4}` (1 % off, about 10 CPU s).
"""

from __future__ import annotations

import os

import numpy as np

from kinetic_fem.analysis.memory_effects import kovacs
from particles.dsmc_transient import simulate_protocol

QUICK = bool(os.environ.get("KINETIC_FEM_DOCS_QUICK"))
TEST_KWARGS = {"alphas": (0.3,), "kernel": 0.0, "n_particles": 2000, "replicas": 4,
               "n_times": 11}


def main(alphas=(0.3, 0.9), kernel: float = 1.0, spacing: float = 0.25, rtol: float = 1e-5,
         n_particles: int = 100_000, replicas: int = 16, n_times: int = 41,
         seed: int = 20261125):
    """Kovacs runs (exact, first Sonine) and their DSMC ensembles; the Maxwell run."""
    out = []
    for k, alpha in enumerate(alphas):
        res = kovacs(alpha, kernel=kernel, spacing=spacing, rtol=rtol, n_times=n_times)
        run = simulate_protocol(alpha, n_particles, kernel=kernel, times=res.exact.times,
                                protocol=res.protocol, diffusion=res.diffusion[1],
                                initial=res.initial,
                                initial_temperature=None if res.initial is not None
                                else float(res.exact.temperature[0]),
                                initial_a2=0.0 if res.initial is not None
                                else float(res.exact.a2[0]),
                                replicas=replicas, seed=seed + k)
        out.append((res, run))
    maxwell = kovacs(alphas[0], kernel=0.0, n_times=n_times)
    return out, maxwell


if __name__ == "__main__":
    import matplotlib.pyplot as plt

    if QUICK:
        runs, maxwell = main(alphas=(0.3,), spacing=0.5, rtol=1e-4, n_particles=20_000,
                             replicas=16, n_times=21)
    else:
        runs, maxwell = main()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for res, run in runs:
        after = res.exact.times >= res.waiting_time
        x = (res.exact.times[after] - res.waiting_time) / res.waiting_time
        t_st = res.steady_temperature
        line = axes[0].semilogx(x, res.exact.temperature[after] / t_st - 1,
                                label=f"exact, alpha = {res.alpha}")[0]
        ts, dev_s = res.deviation(sonine=True)
        axes[0].semilogx(ts / res.waiting_time, dev_s, "--", color=line.get_color(),
                         label="first Sonine")
        axes[0].errorbar(x, run.temperature[after] / t_st - 1,
                         yerr=run.temperature_error[after] / t_st, fmt=".",
                         color=line.get_color(), label="DSMC")
        axes[1].plot(res.exact.times / res.waiting_time, res.exact.a2, color=line.get_color(),
                     label=f"exact, alpha = {res.alpha}")
        axes[1].errorbar(res.exact.times / res.waiting_time, run.a2, yerr=run.a2_error, fmt=".",
                         color=line.get_color())
        z_t, _ = run.deviation(res.exact.temperature, res.exact.a2)
        print(f"alpha = {res.alpha}: t_w = {res.waiting_time:.4f}, D2 = {res.diffusion[2]:.5f}, "
              f"hump {res.hump:+.3e} at t - t_w = {res.hump_time:.3f} (first Sonine "
              f"{res.sonine_hump:+.3e}); DSMC max |z| = {np.max(np.abs(z_t)):.2f}")
    ts, dev = maxwell.deviation()
    axes[0].semilogx(ts / maxwell.waiting_time, dev, "k:", label="Maxwell (exact)")
    axes[0].axhline(0.0, color="grey", lw=0.5)
    axes[0].set_xlabel(r"$(t - t_w)/t_w$")
    axes[0].set_ylabel(r"$T/T_{st}(D_2) - 1$")
    axes[0].legend(fontsize=7)
    axes[1].axvline(1.0, color="grey", lw=0.5)
    axes[1].set_xlabel(r"$t/t_w$")
    axes[1].set_ylabel(r"$a_2(t)$")
    print(f"Maxwell: hump {maxwell.hump:+.1e} (closed energy balance)")
    plt.show()
