"""Free cooling with restitution protocols and speed-dependent laws (issue 11, item 1).

Parts (``--part``):

* ``maxwell``: the Maxwell model with an alpha step 0.9 -> 0.5 at t = 1 against the
  closed moment equations (:func:`kinetic_fem.solvers.maxwell.evolve_moments`): relative
  error of T and <v^4> over t <= 2 for a table of ``rtol``;
* ``rate0``: the cooling rate at t = 0 (a Gaussian) against the Gaussian loss
  :meth:`kinetic_fem.model.InelasticGas.loss_rate` for speed-dependent laws and the
  saturating kernel at T0 = 0.01, 1, 30 (the law and kernel in units V = sqrt(T0));
* ``visco``: viscoelastic hard rods from T0 = 1: local exponent d ln T / d ln t against
  -5/3, -dT/dt against the leading-order Gaussian A T^(8/5) and against the Gaussian loss
  of the full law;
* ``threshold``: the threshold law: T(t) levels off;
* ``dsmc``: DSMC ensembles (``simulate_protocol(..., diffusion=0)``, 32 replicas of
  N = 2e4) against the FEM curves, z-scores over root seeds.

Run: ``python benchmarks/cooling_protocol.py --part visco --t-end 200 --spacing 0.25``.
Results: ``benchmarks/results/cooling_protocol.md``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from scipy.special import gamma as gamma_fn

import kinetic_fem as kf
from kinetic_fem.model import (
    InelasticGas,
    SaturatingKernel,
    ThresholdRestitution,
    ViscoelasticRestitution,
)
from kinetic_fem.model.protocol import Protocol
from kinetic_fem.model.restitution import C1
from kinetic_fem.solvers.maxwell import evolve_moments

STEP = Protocol(restitution=[(1.0, 0.5)])


def maxwell(rtols: list[float], spacing: float, newton_tol: float) -> None:
    """Maxwell alpha step against the exact moments."""
    times = np.array([0.25, 0.5, 1.0, 1.5, 2.0])
    exact = evolve_moments(lambda t: 0.9 if t < 1.0 else 0.5, np.r_[0.0, times],
                           diffusion=0.0, friction=0.0, order=4, breakpoints=[1.0])
    print("| rtol | max dT/T | max d<v^4>/<v^4> | steps | CPU s |\n|---|---|---|---|---|")
    for rtol in rtols:
        start = time.process_time()
        ev = kf.evolve_cooling(0.9, kernel=0.0, times=times, spacing=spacing, rtol=rtol,
                               protocol=STEP, newton_tol=newton_tol)
        cpu = time.process_time() - start
        d_t = np.abs(ev.temperature / exact.temperature[1:] - 1).max()
        d_4 = np.abs(ev.moment(4) / exact.moments[1:, 4] - 1).max()
        print(f"| {rtol:g} | {d_t:.2e} | {d_4:.2e} | {ev.info.iterations} | {cpu:.1f} |")


def rate0() -> None:
    """Initial cooling rate against the Gaussian loss of the law."""
    cases = [(ViscoelasticRestitution(0.1), 1.0), (ThresholdRestitution(0.5, 0.6), 1.0),
             (ThresholdRestitution(0.3, 0.3), 0.0), (0.6, SaturatingKernel(2.0))]
    print("| law | kernel | T0 | spacing | rel. error |\n|---|---|---|---|---|")
    for law, kernel in cases:
        for t0 in (0.01, 1.0, 30.0):
            for spacing in (0.5, 0.25):
                ev = kf.evolve_cooling(law, kernel=kernel, initial_temperature=t0,
                                       times=[0.0, 1e-3 / math.sqrt(t0)], spacing=spacing,
                                       rtol=1e-4)
                loss = InelasticGas(law, 1.0, kernel).loss_rate(t0)
                err = ev.series["cooling_rate"][0] * t0 / loss - 1
                print(f"| {law!r} | {kernel!r} | {t0:g} | {spacing} | {err:.1e} |")


def visco(delta: float, t_end: float, spacing: float, rtol: float) -> None:
    """Late-time viscoelastic Haff law."""
    times = np.geomspace(0.1, t_end, 25)
    start = time.process_time()
    ev = kf.evolve_cooling(ViscoelasticRestitution(delta), times=times, spacing=spacing,
                           rtol=rtol)
    cpu = time.process_time() - start
    print(f"viscoelastic delta {delta}, spacing {spacing}, rtol {rtol:g}: {ev.info.message} "
          f"({cpu:.0f} CPU s)")
    temp = ev.temperature
    loss = ev.series["cooling_rate"] * temp                      # -dT/dt
    lead = 0.5 * C1 * delta * 4**1.6 * gamma_fn(2.1) / math.sqrt(math.pi)
    gas = InelasticGas(ViscoelasticRestitution(delta))
    slope = np.gradient(np.log(temp), np.log(times))
    print("| t | T | a2 | d ln T/d ln t | -T'/(A T^1.6) | -T'/Gaussian loss |")
    print("|---|---|---|---|---|---|")
    for i in range(0, times.size, 3):
        print(f"| {times[i]:.3g} | {temp[i]:.4e} | {ev.a2[i]:+.4f} | {slope[i]:+.4f} | "
              f"{loss[i] / (lead * temp[i] ** 1.6):.4f} | "
              f"{loss[i] / gas.loss_rate(temp[i]):.4f} |")
    np.savez(f"visco_{delta}_{spacing}_{rtol:g}.npz", times=times, temperature=temp,
             a2=ev.a2, rate=ev.series["cooling_rate"])


def threshold(t_end: float, spacing: float, rtol: float) -> None:
    """The threshold law: cooling stops."""
    times = np.geomspace(0.1, t_end, 13)
    start = time.process_time()
    ev = kf.evolve_cooling(ThresholdRestitution(0.5, 0.5), times=times, spacing=spacing,
                           rtol=rtol)
    print(f"{ev.info.message} ({time.process_time() - start:.0f} CPU s)")
    print("| t | T | a2 | -d ln T/dt |\n|---|---|---|---|")
    for i, t in enumerate(times):
        print(f"| {t:.3g} | {ev.temperature[i]:.5e} | {ev.a2[i]:+.4f} | "
              f"{ev.series['cooling_rate'][i]:.3e} |")


def dsmc(case: str, seeds: range) -> None:
    """z-scores of DSMC ensembles against the FEM curves."""
    from particles.dsmc_transient import simulate_protocol

    cases = {"step": (0.9, STEP, [0.5, 1.0, 1.5, 2.0, 4.0]),
             "visco": (ViscoelasticRestitution(0.2), None, [0.5, 2.0, 5.0, 10.0, 20.0]),
             "threshold": (ThresholdRestitution(0.5, 0.5), None, [1.0, 3.0, 10.0, 30.0, 100.0])}
    alpha, protocol, times = cases[case]
    ev = kf.evolve_cooling(alpha, times=times, protocol=protocol, spacing=0.5, rtol=1e-5)
    z_all = []
    for seed in seeds:
        run = simulate_protocol(alpha, 20_000, times=times, diffusion=0.0, protocol=protocol,
                                replicas=32, seed=seed)
        z_all.append(np.concatenate(run.deviation(ev.temperature, ev.a2)))
    z = np.array(z_all)
    print(f"{case}: {len(z)} seeds; |z| > 3: {(np.abs(z) > 3).sum()} of {z.size}, max "
          f"{np.abs(z).max():.2f}; mean z per output (T then a2) {z.mean(0).round(2)}")


def main() -> None:
    """Command line."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--part", choices=["maxwell", "rate0", "visco", "threshold", "dsmc"],
                   required=True)
    p.add_argument("--rtols", type=float, nargs="+", default=[1e-6, 1e-7, 1e-8])
    p.add_argument("--spacing", type=float, default=0.5)
    p.add_argument("--rtol", type=float, default=1e-4)
    p.add_argument("--newton-tol", type=float, default=1e-11)
    p.add_argument("--delta", type=float, default=0.2)
    p.add_argument("--t-end", type=float, default=200.0)
    p.add_argument("--case", default="step")
    p.add_argument("--seeds", type=int, nargs=2, default=[0, 64])
    a = p.parse_args()
    if a.part == "maxwell":
        maxwell(a.rtols, a.spacing, a.newton_tol)
    elif a.part == "rate0":
        rate0()
    elif a.part == "visco":
        visco(a.delta, a.t_end, a.spacing, a.rtol)
    elif a.part == "threshold":
        threshold(a.t_end, a.spacing, a.rtol)
    else:
        dsmc(a.case, range(*a.seeds))


if __name__ == "__main__":
    main()
