"""Speed and accuracy of the event-driven MD (particles.md); prints tables.

1. Collisions per second on one core: free cooling (alpha = 0.9 regularised, 0.99)
   at N = 5000 and 1e5 over the homogeneous stage, heated alpha = 0.9 with the kicks
   included (for several kick intervals); cost per collision against log2 N.
2. Kick-interval convergence of the heated steady state (T/T_Sonine and a2) as
   dt_k -> 0, and the error of the default interval.
3. Threshold independence: heated (alpha = 0.9, 0.6) and freely cooling (alpha = 0.9)
   over more than a decade of thresholds.
4. Invariants over the longest run: rods ordered, momentum and energy balance.

Run ``python benchmarks/bench_md.py [--quick] [--part speed|kicks|threshold|invariants]``.
The machine may be shared: timings are wall-clock on one core under whatever load.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from kinetic_fem.sonine import a2_first_order, steady_temperature
from particles import md
from particles._md_engine import _Engine

N_FREE = 2.0  # density on the reduced ring at n = 1, n sigma = 0.5


def _event_rate(alpha: float, n: int, cpp: float, threshold: float | None,
                repeats: int, kick_fraction: float | None = None) -> tuple[int, float, float]:
    """Best-of-``repeats`` wall time of the event loop alone (kicks included, no sampling)."""
    best = np.inf
    temp, kick_dt, kick_amp = 1.0, np.inf, 0.0
    if kick_fraction is not None:
        temp = steady_temperature(alpha, N_FREE)
        kick_dt = kick_fraction * md.mean_free_time(temp, 1.0, 0.5)
        kick_amp = math.sqrt(2.0 * kick_dt)
    for _ in range(repeats):
        rng = np.random.default_rng(1)
        y, v = md.initial_state(n, density=1.0, sigma=0.5, temperature=temp, rng=rng)
        eng = _Engine(y, v, free_length=n - 0.5 * n, sigma=0.5, alpha=alpha,
                      threshold=threshold or 0.0, kick_dt=kick_dt, kick_amp=kick_amp, rng=rng,
                      collapse_tol=1e-12, max_stall=100 * n)
        target = int(cpp * n / 2)
        start = time.perf_counter()
        eng.advance(target)
        best = min(best, time.perf_counter() - start)
    return target, best, eng.temperature()


def speed(quick: bool) -> None:
    md.simulate_cooling(0.9, 100, seed=0, collisions_per_particle=10.0)  # compile / load cache
    md.simulate_heated(0.9, 100, seed=0, collisions_per_particle=10.0)
    print("\n== free cooling event loop, homogeneous stage, one core, best of 3 ==")
    print(f"{'alpha':>6} {'threshold':>9} {'N':>7} {'cpp':>5} {'collisions':>11} {'s':>7} "
          f"{'coll/s':>9} {'ns/coll':>8} {'ns/coll/log2N':>14} {'T_end':>6}")
    sizes = (5000, 20000) if quick else (5000, 20000, 100_000)
    for alpha, thr, cpp in ((0.9, 1e-4, 4.0), (0.99, None, 40.0)):
        for n in sizes:
            coll, wall, t_end = _event_rate(alpha, n, cpp / (4 if quick else 1), thr, 3)
            ns = 1e9 * wall / coll
            print(f"{alpha:6.2f} {thr or 0:9.0e} {n:7d} {cpp:5.0f} {coll:11d} {wall:7.3f} "
                  f"{coll / wall:9.3g} {ns:8.1f} {ns / math.log2(n):14.2f} {t_end:6.3f}")
    print("\n== heated alpha = 0.9, N = 5000, event loop with kicks (no sampling), best of 3 ==")
    print(f"{'dt_k/tau':>8} {'collisions':>11} {'s':>7} {'coll/s':>9}")
    for frac in (0.05, 0.1, 0.25, 0.5, 1.0):
        coll, wall, _ = _event_rate(0.9, 5000, 20.0 if quick else 100.0,
                                    0.01 * math.sqrt(steady_temperature(0.9, N_FREE)), 3,
                                    kick_fraction=frac)
        print(f"{frac:8.2f} {coll:11d} {wall:7.3f} {coll / wall:9.3g}")
    print("\n== heated alpha = 0.9, N = 5000, whole run (kicks, sampling every tau) ==")
    print(f"{'dt_k/tau':>8} {'kicks':>7} {'collisions':>11} {'s':>7} {'coll/s':>9} "
          f"{'coll/kick':>9}")
    for frac in (0.05, 0.1, 0.25, 0.5, 1.0):
        tau = md.mean_free_time(steady_temperature(0.9, N_FREE), 1.0, 0.5)
        run = min((md.simulate_heated(0.9, 5000, seed=2, kick_interval=frac * tau,
                                      collisions_per_particle=20.0 if quick else 100.0,
                                      n_records=5, box_counts=[2])
                   for _ in range(2)), key=lambda r: r.info.wall_time)
        print(f"{frac:8.2f} {run.n_kicks:7d} {run.n_collisions:11d} {run.info.wall_time:7.3f} "
              f"{run.n_collisions / run.info.wall_time:9.3g} "
              f"{run.n_collisions / max(run.n_kicks, 1):9.1f}")


def kicks(quick: bool) -> None:
    n, cpp = (1000, 400.0) if quick else (2000, 2000.0)
    seeds = 2 if quick else 4
    for alpha in (0.9, 0.99):
        t_est = steady_temperature(alpha, N_FREE)
        tau = md.mean_free_time(t_est, 1.0, 0.5)
        print(f"\n== kick-interval convergence, alpha = {alpha}, N = {n}, {cpp:g} cpp x "
              f"{seeds} seeds (Sonine a2 = {a2_first_order(alpha):.4f}) ==")
        print(f"{'dt_k/tau':>8} {'T/T_sonine':>11} {'+-':>7} {'a2':>8} {'+-':>7} {'s':>6}")
        rows = []
        for frac in (0.8, 0.4, 0.2, 0.1, 0.05, 0.025):
            runs = [md.simulate_heated(alpha, n, seed=100 + s, kick_interval=frac * tau,
                                       collisions_per_particle=cpp, warmup=0.2 * cpp)
                    for s in range(seeds)]
            temps = np.array([r.temperature / t_est for r in runs])
            a2 = np.array([r.a2 for r in runs])
            a2e = math.sqrt(sum(r.a2_error**2 for r in runs)) / seeds
            te = temps.std(ddof=1) / math.sqrt(seeds)
            wall = sum(r.info.wall_time for r in runs)
            rows.append((frac, temps.mean(), a2.mean()))
            print(f"{frac:8.3f} {temps.mean():11.4f} {te:7.4f} {a2.mean():8.4f} {a2e:7.4f} "
                  f"{wall:6.1f}")
        ref = rows[-1]
        print("differences from dt_k = 0.025 tau:")
        for frac, temp, a2 in rows[:-1]:
            print(f"  dt_k/tau = {frac:5.3f}: dT/T = {temp / ref[1] - 1:+.4f}, "
                  f"da2 = {a2 - ref[2]:+.4f}")


def threshold(quick: bool) -> None:
    n, cpp = (1000, 300.0) if quick else (5000, 400.0)
    for alpha in (0.9, 0.6):
        vth = math.sqrt(steady_temperature(alpha, N_FREE))
        print(f"\n== heated threshold independence, alpha = {alpha}, N = {n}, {cpp:g} cpp ==")
        print(f"{'thr/v_th':>8} {'T/T_sonine':>11} {'a2':>8} {'+-':>7} {'elastic':>8} "
              f"{'t_end':>8}")
        for rel in (1e-3, 3e-3, 1e-2, 3e-2, 1e-1):
            run = md.simulate_heated(alpha, n, seed=5, threshold=rel * vth,
                                     collisions_per_particle=cpp)
            print(f"{rel:8.0e} {run.temperature / vth**2:11.4f} {run.a2:8.4f} "
                  f"{run.a2_error:7.4f} {run.n_elastic / run.n_collisions:8.4f} "
                  f"{run.series['t'][-1]:8.2f}")
    n, cpp = (2000, 300.0) if quick else (10000, 1000.0)
    print(f"\n== free cooling threshold independence, alpha = 0.9, N = {n}: T at fixed times ==")
    times = np.geomspace(1.0, 60.0 if quick else 150.0, 6)
    print(f"{'threshold':>9} " + " ".join(f"{'T(' + format(t, '.3g') + ')':>10}" for t in times)
          + f" {'a2(late)':>9} {'elastic':>8}")
    for thr in (1e-5, 1e-4, 1e-3):
        run = md.simulate_cooling(0.9, n, seed=8, threshold=thr, collisions_per_particle=cpp,
                                  n_records=400)
        s = run.series
        temps = np.interp(times, s["t"], s["temperature"], right=np.nan)
        print(f"{thr:9.0e} " + " ".join(f"{x:10.4g}" for x in temps)
              + f" {run.a2:9.4f} {run.n_elastic / run.n_collisions:8.4f}")


def invariants(quick: bool) -> None:
    n, cpp = (2000, 2000.0) if quick else (5000, 20000.0)
    start = time.perf_counter()
    run = md.simulate_cooling(0.9, n, seed=3, threshold=1e-4, collisions_per_particle=cpp,
                              snapshots_at=np.linspace(cpp / 20, cpp, 20))
    length = float(n)
    worst = min(np.min(np.mod(np.diff(np.append(s.x, s.x[0])), length))
                for s in run.snapshots)
    p = run.series["momentum"]
    print(f"\n== invariants, cooling alpha = 0.9 threshold 1e-4, N = {n}, "
          f"{run.n_collisions:.3e} collisions ({time.perf_counter() - start:.1f} s) ==")
    print(f"smallest gap between rod left ends over 20 snapshots: {worst:.15f} (sigma = 0.5)")
    print(f"max |P(t) - P(0)|: {np.max(np.abs(p - p[0])):.3e}")
    print(f"energy balance error max|E - E0 + dissipated| / E0: {run.energy_balance_error:.3e}")
    heated = md.simulate_heated(0.9, n, seed=3, collisions_per_particle=cpp / 4)
    print(f"heated alpha = 0.9, {heated.n_collisions:.3e} collisions, {heated.n_kicks} kicks: "
          f"energy balance error |E - E0 - (injected - dissipated)| / max E = "
          f"{heated.energy_balance_error:.3e}")


PARTS = {"speed": speed, "kicks": kicks, "threshold": threshold, "invariants": invariants}

if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--part", choices=sorted(PARTS), action="append")
    args = parser.parse_args()
    for name in args.part or list(PARTS):
        PARTS[name](args.quick)
