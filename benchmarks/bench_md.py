"""Speed and accuracy of the event-driven MD (particles.md); prints tables.

1. Collisions per CPU second (one core): free cooling (alpha = 0.9 regularised,
   0.99) at N = 5000 and 1e5 over the homogeneous stage, cost per collision against
   log2 N; heated alpha = 0.9, N = 5000 with the kicks included at the default and
   other kick intervals, the cost of one kick per rod, and the split of the time
   into kicks and collisions.
2. Kick-interval convergence of the heated steady state (T/T_Sonine and a2) as
   dt_k -> 0, and the error of the default interval.
3. Threshold independence: heated (alpha = 0.9, 0.6) and freely cooling (alpha = 0.9)
   over more than a decade of thresholds.
4. Invariants over the longest run: rods ordered, momentum and energy balance.

Run ``python benchmarks/bench_md.py [--quick] [--part speed|kicks|threshold|invariants]``.
The machine may be shared: part 1 reports CPU time of the process (the event loop is
single-threaded), which does not count time spent descheduled but still feels the
other jobs in the caches; whole-run timings are wall-clock.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from kinetic_fem.sonine import a2_first_order, steady_temperature
from particles import _md_kernels as K
from particles import md
from particles._md_engine import _Engine

N_FREE = 2.0  # density on the reduced ring at n = 1, n sigma = 0.5


def _engine(alpha: float, n: int, seed: int, threshold: float | None,
            kick_fraction: float | None) -> _Engine:
    temp, kick_dt, kick_amp = 1.0, np.inf, 0.0
    if kick_fraction is not None:
        temp = steady_temperature(alpha, N_FREE)
        kick_dt = kick_fraction * md.mean_free_time(temp, 1.0, 0.5)
        kick_amp = math.sqrt(2.0 * kick_dt)
    rng = np.random.default_rng(seed)
    y, v = md.initial_state(n, density=1.0, sigma=0.5, temperature=temp, rng=rng)
    return _Engine(y, v, free_length=n - 0.5 * n, sigma=0.5, alpha=alpha,
                   threshold=threshold or 0.0, kick_dt=kick_dt, kick_amp=kick_amp, rng=rng,
                   collapse_tol=1e-12, max_stall=100 * n)


def _event_rate(alpha: float, n: int, cpp: float, threshold: float | None, repeats: int,
                kick_fraction: float | None = None,
                min_collisions: int = 200_000) -> tuple[int, float, float, int]:
    """CPU time of the event loop alone (kicks included, no sampling), best of ``repeats``.

    Each measurement runs ``cpp`` collisions per particle from the initial state, on
    as many independent realisations as needed for ``min_collisions`` in total.
    Returns collisions, CPU seconds, the final temperature of the last realisation,
    and the kicks.
    """
    per_run = int(cpp * n / 2)
    runs = max(1, -(-min_collisions // per_run))
    best = np.inf
    for _ in range(repeats):
        cpu, kicks = 0.0, 0
        for seed in range(runs):
            eng = _engine(alpha, n, seed + 1, threshold, kick_fraction)
            start = time.process_time()
            eng.advance(per_run)
            cpu += time.process_time() - start
            kicks += int(eng.istate[K.I_NKICK])
        best = min(best, cpu)
    return runs * per_run, best, eng.temperature(), kicks


def _kick_cost(alpha: float, n: int, kick_fraction: float, repeats: int = 200) -> float:
    """CPU seconds of one kick alone (normals + sweep + heap), on a steady-state configuration.

    The kick is repeated in place on the same configuration with amplitude 0 (the
    configuration and the screened pairs stay those of the real kick).
    """
    eng = _engine(alpha, n, 1, 0.01 * math.sqrt(steady_temperature(alpha, N_FREE)),
                  kick_fraction)
    eng.advance(10 * n)
    tk, dt = eng.fstate[K.F_T_KICK], eng.kick_dt
    ki, wi, fi = K.ZIGGURAT
    best = np.inf
    for _ in range(5):
        start = time.process_time()
        for _ in range(repeats):
            K.fill_normals(eng.xi, eng.rng_state, ki, wi, fi)
            K.kick_sweep(tk, tk + dt, 0.0, eng.xi, eng.x, eng.v, eng.tl, eng.free_length,
                         eng.heap, eng.hkey, eng.where, eng.istate)
        best = min(best, (time.process_time() - start) / repeats)
    return best


def speed(quick: bool) -> None:
    md.simulate_cooling(0.9, 100, seed=0, collisions_per_particle=10.0)  # compile / load cache
    md.simulate_heated(0.9, 100, seed=0, collisions_per_particle=10.0)
    print("\nCPU time of this process (one core; the machine may be shared, which slows "
          "memory access but does not count time spent descheduled)")
    print("\n== free cooling event loop, homogeneous stage, best of 3 "
          "(>= 2e5 collisions per measurement) ==")
    print(f"{'alpha':>6} {'threshold':>9} {'N':>7} {'cpp':>5} {'collisions':>11} {'cpu s':>7} "
          f"{'coll/s':>9} {'ns/coll':>8} {'ns/coll/log2N':>14} {'T_end':>6}")
    sizes = (5000, 20000) if quick else (5000, 100_000)
    for alpha, thr, cpp in ((0.9, 1e-4, 4.0), (0.99, None, 40.0)):
        for n in sizes:
            coll, cpu, t_end, _ = _event_rate(alpha, n, cpp / (4 if quick else 1), thr, 3)
            ns = 1e9 * cpu / coll
            print(f"{alpha:6.2f} {thr or 0:9.0e} {n:7d} {cpp:5.0f} {coll:11d} {cpu:7.3f} "
                  f"{coll / cpu:9.3g} {ns:8.1f} {ns / math.log2(n):14.2f} {t_end:6.3f}")
    n, cpp = 5000, (20.0 if quick else 100.0)
    thr = 0.01 * math.sqrt(steady_temperature(0.9, N_FREE))
    print(f"\n== heated alpha = 0.9, N = {n}, event loop with kicks (no sampling), {cpp:g} cpp "
          f"from the start, best of 3; default kick interval {md.KICK_FRACTION:g} tau ==")
    print(f"{'dt_k/tau':>8} {'kicks':>7} {'coll/kick':>9} {'cpu s':>7} {'coll/s':>9} "
          f"{'ns/coll':>8} {'us/interval':>11} {'kick alone: ns/rod':>18}")
    fracs = (0.05, 0.1, 0.25, 0.5, 1.0)
    rows = []
    for frac in fracs:
        coll, cpu, _, kicks = _event_rate(0.9, n, cpp, thr, 3, kick_fraction=frac)
        kick = _kick_cost(0.9, n, frac)
        rows.append((coll / kicks, 1e6 * cpu / kicks))
        mark = " (default)" if frac == md.KICK_FRACTION else ""
        print(f"{frac:8.2f} {kicks:7d} {coll / kicks:9.1f} {cpu:7.3f} {coll / cpu:9.3g} "
              f"{1e9 * cpu / coll:8.1f} {1e6 * cpu / kicks:11.1f} {1e9 * kick / n:18.2f}{mark}")
    c, t = np.array(rows).T
    slope, icpt = np.polyfit(1.0 / c, t / c, 1)  # time per collision against 1/(coll/kick)
    print(f"fit: time per collision = {1e3 * icpt:.0f} ns + (one kick in the run: "
          f"{slope:.1f} us = {1e3 * slope / n:.2f} ns per rod) / (collisions per kick);")
    print(f"a kick interval holds (dt_k/tau) N/2 collisions, so coll/s = 1 / ({1e3 * icpt:.0f} ns "
          f"+ {1e3 * slope / n:.2f} ns x 2 / (dt_k/tau)), at most {1e9 / (1e3 * icpt):.3g}/s")
    print(f"\n== heated alpha = 0.9, N = {n}, whole run (kicks, sampling every tau) ==")
    print(f"{'dt_k/tau':>8} {'kicks':>7} {'collisions':>11} {'s':>7} {'coll/s':>9} "
          f"{'coll/kick':>9}")
    for frac in fracs:
        tau = md.mean_free_time(steady_temperature(0.9, N_FREE), 1.0, 0.5)
        run = min((md.simulate_heated(0.9, n, seed=2, kick_interval=frac * tau,
                                      collisions_per_particle=cpp, n_records=5, box_counts=[2])
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
