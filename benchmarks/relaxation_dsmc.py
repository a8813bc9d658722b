"""DSMC relaxation time against the relaxation spectrum (issue 11 item 5, claim C2).

For each alpha (hard rods, white noise, n = D = 1): two DSMC ensembles start in the
exact steady shape (the FEM steady state, velocities rescaled) at temperatures
(1 + d) T_st and (1 - d) T_st, d = 0.3, and relax under D = 1.  Their difference
``T_+(t) - T_-(t)`` is odd in d: the second-order (nonlinear) terms, which decay at
2 lambda and would bias a fit of one curve by several per cent, cancel, and so does
the particle method's own bias of T_st.  The late decay ``c + A exp(-lambda t)`` is
fitted to the ensemble mean of the differences on the window [1.5, 5] / lambda_spec
(:func:`kinetic_fem.analysis.decay_fit.fit_decay`, jackknife error bars over 16
replica groups) and compared with the slowest even rate of
:func:`kinetic_fem.relaxation_spectrum` (``benchmarks/results/relaxation_spectrum.md``;
``--recompute`` computes it again).  The window's own bias (faster modes and
third-order terms not yet gone) is measured by the same fit on the first-Sonine
difference curve from the same starts, against the first-Sonine slowest rate.

Run: ``python benchmarks/relaxation_dsmc.py [--alphas 0.6 0.9 0.99] [--particles N]
[--replicas R] [--seed S] [--recompute]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import kinetic_fem as kf
from kinetic_fem.analysis.decay_fit import fit_decay, window_bias
from kinetic_fem.analysis.sonine_dynamics import (
    evolve_sonine,
    sonine_relaxation_rates,
    steady_sonine,
)
from kinetic_fem.distribution import VelocityDistribution
from particles.dsmc_transient import simulate_protocol

SPECTRUM_RATES = {0.0: 2.1343242, 0.3: 1.9901616, 0.6: 1.5373577, 0.9: 0.65670537,
                  0.99: 0.14377827, 0.999: 0.031022379}
"""Slowest even rate of the FEM linearisation (n = D = 1), mesh error <= 9e-9 relative
(``benchmarks/results/relaxation_spectrum.md``)."""

PERTURBATION = 0.3
"""The starts are the steady shape at (1 +- PERTURBATION) T_st."""

WINDOW = (1.5, 5.0)
"""Fit window in units of 1/lambda."""


def measure(alpha: float, n_particles: int, replicas: int, seed: int,
            rate: float) -> dict:
    """DSMC decay rate of T at ``alpha`` with its error bar and the window bias.

    Parameters
    ----------
    alpha : float
        Restitution coefficient.
    n_particles, replicas : int
        DSMC size.
    seed : int
        Root seed.
    rate : float
        The spectrum's slowest even rate (sets the times and the window).

    Returns
    -------
    dict
    """
    steady = kf.solve_heated(alpha)
    t_st = steady.temperature
    times = np.linspace(0.0, 5.5 / rate, 89)
    window = (WINDOW[0] / rate, WINDOW[1] / rate)
    t0 = time.process_time()
    curves = []
    for k, sign in enumerate((1.0, -1.0)):
        scale = np.sqrt(1.0 + sign * PERTURBATION)
        start = VelocityDistribution.from_values(steady.v * scale, steady.values / scale)
        run = simulate_protocol(alpha, n_particles, times=times, initial=start, diffusion=1.0,
                                replicas=replicas, seed=seed + k)
        curves.append(run.temperature_replicas)
    cpu = time.process_time() - t0
    fit = fit_decay(times, (curves[0] - curves[1]) / t_st, window, rate_guess=rate)
    s_t, s_a2 = steady_sonine(alpha)
    son = [evolve_sonine(alpha, times=times, initial_temperature=s_t * (1.0 + sign * PERTURBATION),
                         initial_a2=s_a2).temperature for sign in (1.0, -1.0)]
    bias = window_bias(times, son[0] - son[1], window, sonine_relaxation_rates(alpha)[0])
    return {"alpha": alpha, "N": n_particles, "R": replicas, "rate": fit.rate,
            "error": fit.rate_error, "spectrum": rate,
            "z": (fit.rate - rate) / fit.rate_error, "bias": bias,
            "offset": fit.asymptote, "offset_err": fit.asymptote_error,
            "chi2": fit.chi2_dof, "cpu": cpu}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--alphas", type=float, nargs="+", default=[0.6, 0.9, 0.99])
    parser.add_argument("--particles", type=int, default=100_000)
    parser.add_argument("--replicas", type=int, default=32)
    parser.add_argument("--seed", type=int, default=20261125)
    parser.add_argument("--recompute", action="store_true",
                        help="compute the spectrum's rate instead of the table's")
    args = parser.parse_args()
    print(f"DSMC: N = {args.particles}, {args.replicas} replicas, seed {args.seed}; "
          f"starts: steady shape at (1 +- {PERTURBATION}) T_st; fit window "
          f"[{WINDOW[0]}, {WINDOW[1]}]/lambda")
    print("| alpha | DSMC rate | +- | spectrum rate | (DSMC - spec)/sigma | "
          "window bias (Sonine) | offset/T_st | chi2/dof | CPU s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for alpha in args.alphas:
        rate = (kf.relaxation_spectrum(alpha).slowest("even") if args.recompute
                else SPECTRUM_RATES[alpha])
        r = measure(alpha, args.particles, args.replicas, args.seed, rate)
        print(f"| {alpha} | {r['rate']:.5f} | {r['error']:.5f} | {r['spectrum']:.5f} | "
              f"{r['z']:+.2f} | {r['bias']:+.1e} | {r['offset']:+.1e} +- {r['offset_err']:.0e} "
              f"| {r['chi2']:.2f} | {r['cpu']:.0f} |", flush=True)


if __name__ == "__main__":
    main()
