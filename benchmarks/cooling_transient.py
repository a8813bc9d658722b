"""Checks of the FEM free-cooling transient ``kf.evolve_cooling`` (issue 11).

Parts (``--part``):

* ``maxwell``: the Maxwell model (gamma = 0) against its exact closed moment equations
  (:func:`kinetic_fem.solvers.maxwell.evolve_moments`): relative error of T and <v^4>
  at the output times, for a table of ``rtol`` (and spacing);
* ``hcs``: hard rods from a Gaussian to late times: zeta(t) and a2(t) against the
  homogeneous cooling state of ``kf.solve_cooling``, and T(t) against Haff's law with
  the HCS zeta, ``T(t) = T(t1) / (1 + zeta n sqrt(T(t1)) (t - t1))^2``, from ``t1`` on;
* ``dsmc``: DSMC ensembles (``particles.dsmc.simulate_cooling``, replicas of N
  particles) against the FEM T(t) and a2(t): z-scores at every output time.

Run: ``python benchmarks/cooling_transient.py --part maxwell [--alpha 0.5]``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

import kinetic_fem as kf
from kinetic_fem.solvers.maxwell import evolve_moments


def maxwell(alpha: float, grid: list[tuple[float, float]], t_end: float) -> None:
    """T and <v^4> against the exact moment equations."""
    times = np.array([t for t in (0.1, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0) if t <= t_end])
    exact = evolve_moments(alpha, np.r_[0.0, times], diffusion=0.0, friction=0.0, order=4)
    print(f"Maxwell model, alpha = {alpha}, Gaussian start T0 = 1, times {times.tolist()}")
    print("| spacing | rtol | max dT/T | max d<v^4>/<v^4> | steps | segments | mass - 1 | s |")
    print("|---|---|---|---|---|---|---|---|")
    for spacing, rtol in grid:
        start = time.process_time()
        ev = kf.evolve_cooling(alpha, kernel=0.0, times=times, spacing=spacing, rtol=rtol)
        cpu = time.process_time() - start
        d_t = np.abs(ev.temperature / exact.temperature[1:] - 1.0).max()
        d_4 = np.abs(ev.moment(4) / exact.moments[1:, 4] - 1.0).max()
        print(f"| {spacing} | {rtol:g} | {d_t:.2e} | {d_4:.2e} | {ev.info.iterations} | "
              f"{int(ev.series['segments'][-1]) + 1} | {np.abs(ev.series['mass'] - 1).max():.1e}"
              f" | {cpu:.1f} |")


def hcs(alpha: float, t_end: float, spacing: float, rtol: float) -> None:
    """Approach to the homogeneous cooling state and Haff's law."""
    state = kf.solve_cooling(alpha)
    zeta_hcs, a2_hcs = state.info.extra["zeta"], state.a2
    times = np.geomspace(0.1, t_end, 25)
    start = time.process_time()
    ev = kf.evolve_cooling(alpha, times=times, spacing=spacing, rtol=rtol)
    cpu = time.process_time() - start
    print(f"hard rods, alpha = {alpha}, spacing {spacing}, rtol {rtol:g}: {ev.info.message} "
          f"({cpu:.1f} CPU s)")
    print(f"HCS (kf.solve_cooling): zeta = {zeta_hcs:.8f}, a2 = {a2_hcs:.8f}")
    temp = ev.temperature
    i1 = int(np.searchsorted(times, times[-1] / 10.0))
    haff = temp[i1] / (1.0 + zeta_hcs * math.sqrt(temp[i1]) * (times - times[i1])) ** 2
    slope = np.gradient(np.log(temp), np.log(times))
    print("| t | T | zeta - zeta_HCS | a2 - a2_HCS | T/T_Haff - 1 | d ln T/d ln t |")
    print("|---|---|---|---|---|---|")
    for k in range(0, times.size, 3):
        h = f"{temp[k] / haff[k] - 1:.2e}" if k >= i1 else "-"
        print(f"| {times[k]:.4g} | {temp[k]:.6e} | {ev.series['zeta'][k] - zeta_hcs:+.2e} | "
              f"{ev.a2[k] - a2_hcs:+.2e} | {h} | {slope[k]:.4f} |")


def dsmc(alpha: float, gamma: float, n_particles: int, replicas: int, seeds: int,
         collisions: float, spacing: float, rtol: float) -> None:
    """DSMC ensembles against FEM: z-scores of T and a2 at every output time, per seed."""
    from particles.dsmc import simulate_cooling

    times = np.array([0.25, 1.0, 2.0, 4.0, 8.0])
    start = time.process_time()
    ev = kf.evolve_cooling(alpha, kernel=gamma, times=times, spacing=spacing, rtol=rtol)
    print(f"alpha = {alpha}, gamma = {gamma}: FEM (spacing {spacing}, rtol {rtol:g}) "
          f"{time.process_time() - start:.1f} CPU s; DSMC N = {n_particles} x {replicas} "
          f"replicas, times {times.tolist()}")
    print(f"FEM T {np.array2string(ev.temperature, precision=6)}, "
          f"a2 {np.array2string(ev.a2, precision=5)}")
    print("| seed | z(T) | z(a2) | max abs z | s.e. T/T (last) | s.e. a2 (last) | CPU s |")
    print("|---|---|---|---|---|---|---|")
    worst = []
    for seed in range(seeds):
        start = time.process_time()
        temps, a2s = [], []
        for r in range(replicas):
            s = simulate_cooling(alpha, n_particles, kernel=gamma, seed=seed * 1000 + r,
                                 collisions_per_particle=collisions, relax=0.0,
                                 sample_every=0.05, n_batches=2).series
            t = np.asarray(s["t"])
            temps.append(np.exp(np.interp(times, t, s["log_temperature"])))
            a2s.append(np.interp(times, t, s["a2"]))
        temps_a, a2s_a = np.array(temps), np.array(a2s)
        se_t = temps_a.std(0, ddof=1) / math.sqrt(replicas)
        se_a = a2s_a.std(0, ddof=1) / math.sqrt(replicas)
        z_t = (temps_a.mean(0) - ev.temperature) / se_t
        z_a = (a2s_a.mean(0) - ev.a2) / se_a
        worst.append(max(np.abs(z_t).max(), np.abs(z_a).max()))
        print(f"| {seed} | {np.array2string(z_t, precision=2)} | "
              f"{np.array2string(z_a, precision=2)} | {worst[-1]:.2f} | "
              f"{se_t[-1] / temps_a.mean(0)[-1]:.1e} | {se_a[-1]:.1e} | "
              f"{time.process_time() - start:.1f} |")
    z_all = np.array(worst)
    print(f"max |z| over {seeds} seeds: {z_all.max():.2f}; seeds with max |z| > 3: "
          f"{int((z_all > 3).sum())}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", choices=("maxwell", "hcs", "dsmc"), default="maxwell")
    parser.add_argument("--alpha", type=float, default=0.5)
    parser.add_argument("--t-end", type=float, default=1.0)
    parser.add_argument("--spacing", type=float, default=0.25)
    parser.add_argument("--rtol", type=float, default=1e-7)
    parser.add_argument("--gamma", type=float, default=1.0)
    parser.add_argument("--particles", type=int, default=20_000)
    parser.add_argument("--replicas", type=int, default=32)
    parser.add_argument("--seeds", type=int, default=16)
    parser.add_argument("--collisions", type=float, default=6.0)
    parser.add_argument("--grid", nargs="*", default=["0.25:1e-6", "0.25:1e-7", "0.25:1e-8",
                                                       "0.25:2e-9", "0.125:2e-9"])
    args = parser.parse_args()
    if args.part == "maxwell":
        grid = [(float(a), float(b)) for a, b in (g.split(":") for g in args.grid)]
        maxwell(args.alpha, grid, args.t_end)
    elif args.part == "hcs":
        hcs(args.alpha, args.t_end, args.spacing, args.rtol)
    else:
        dsmc(args.alpha, args.gamma, args.particles, args.replicas, args.seeds,
             args.collisions, args.spacing, args.rtol)


if __name__ == "__main__":
    main()
