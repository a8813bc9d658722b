"""Throughput of the homogeneous DSMC kernels (accepted collisions per second, one core).

Run: ``python benchmarks/bench_dsmc.py [--quick] [--no-replicas]``.

Cases (issue 5): free cooling at alpha = 0.9 and the heated gas at alpha = 0.6 with a
time step of 0.05 mean free times (kicks included), each for N = 25000 and N = 1e6
(and the heated gas at dt = 0.2 for comparison).  Printed for each case: accepted
collisions per CPU second, ns per collision and per candidate, the acceptance ratio
(heated: the exact expected one, mean |v_i - v_j| over all pairs / g_max, of the final
state), and for the heated gas the ns per kick (one normal added to one velocity) and
the share of the kicks in the cost.  Then the ratios N = 1e6 / N = 25000 of the cost
per collision (issue target: at most 1.5), the batched ``collide`` (pairs drawn and
prefetched ``PREFETCH_BATCH`` candidates ahead) against its plain loop at both sizes,
the cost of the random numbers alone (what bounds a candidate at N = 25000) and the
speed-up of independent replicas over the cores.

Each timing is the best of ``--repeat`` runs on a relaxed state (40 collisions per
particle of relaxation for cooling, 10 for the heated gas; compilation excluded),
measured in CPU seconds of this process (``time.process_time``), which on a machine
shared with other jobs is closer to the cost on an idle core than the wall time
(printed as ``wall coll/s`` beside it).  The cache is shared too: at N = 1e6 the 8 MB
velocity array lives in the L3 cache only if the other jobs leave room for it.
"""

from __future__ import annotations

import argparse
import math
import os
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from kinetic_fem.sonine import steady_temperature
from particles import _dsmc_kernels as kern
from particles import dsmc

TABLES = kern.ziggurat_tables()


def _state(seed: int) -> np.ndarray:
    return np.random.SeedSequence(seed).generate_state(4, dtype=np.uint64)


def mean_acceptance(v: np.ndarray) -> float:
    """Exact expected acceptance of a candidate: mean ``|v_i - v_j|`` over pairs / extent."""
    x = np.sort(v)
    n = x.size
    mean_g = 2.0 * np.dot(x, 2.0 * np.arange(n) - (n - 1)) / (n * (n - 1))
    return float(mean_g / (x[-1] - x[0]))


def cooling(n: int, collisions_per_particle: float, seed: int = 0,
            repeat: int = 3) -> dict[str, float]:
    """Best-of-``repeat`` throughput of ``cooling_block`` at alpha = 0.9."""
    s = _state(seed)
    v = np.random.default_rng(seed).normal(size=n)
    # relax: 40 collisions per particle (the acceptance settles after about 30)
    kern.cooling_block(v, int(40 * n / 2 / 0.15), n, 0.9, s)
    best = None
    for _ in range(repeat):
        m = int(collisions_per_particle * n / 2 / 0.15)
        t0, c0 = time.perf_counter(), time.process_time()
        acc, _, _ = kern.cooling_block(v, m, n, 0.9, s)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        if best is None or acc / cpu > best["rate"]:
            best = {"rate": acc / cpu, "ns_coll": cpu / acc * 1e9, "wall": acc / wall,
                    "ns_cand": cpu / m * 1e9, "accept": acc / m}
    best["v"] = v
    return best


def heated(n: int, collisions_per_particle: float, seed: int = 0, repeat: int = 3,
           step: float = 0.05) -> dict[str, float]:
    """Best-of-``repeat`` throughput of ``heated_segment`` at alpha = 0.6, dt = step mft."""
    alpha = 0.6
    t_ref = steady_temperature(alpha)
    dt = step / (2.0 * math.sqrt(t_ref / math.pi))
    s = _state(seed)
    v = np.random.default_rng(seed).normal(0.0, math.sqrt(t_ref), n)
    steps = max(1, int(collisions_per_particle / step))
    args = (dt, math.sqrt(2 * dt), 0.5 * n, alpha)
    kern.heated_segment(v, int(10 / step), *args, 0.0, s, *TABLES)  # 10 collisions/particle
    best = None
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        acc, _, _ = kern.heated_segment(v, steps, *args, 0.0, s, *TABLES)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        if best is None or acc / cpu > best["rate"]:
            best = {"rate": acc / cpu, "ns_coll": cpu / acc * 1e9, "wall": acc / wall,
                    "steps": steps, "acc": acc}
    best["accept"] = mean_acceptance(v)
    # split: the kicks alone (amplitude 0 leaves v unchanged)
    u = v.copy()
    kick = math.inf
    sweeps = max(1, min(steps, 10**7 // n))
    for _ in range(2 * repeat):
        c0 = time.process_time()
        for _ in range(sweeps):
            kern.kick(u, 0.0, s, *TABLES)
        kick = min(kick, (time.process_time() - c0) / (sweeps * n) * 1e9)
    best["ns_kick"] = kick
    best["kick_share"] = kick * n * best["steps"] / best["acc"] / best["ns_coll"]
    return best


def batch_ratio(v: np.ndarray, repeat: int = 3) -> tuple[float, float]:
    """ns per candidate of ``collide`` on (copies of) ``v``: plain loop, batches."""
    lo, hi = kern.extent(v)
    m = v.size
    calls = max(1, 4_000_000 // m)
    out = []
    for batch in (0, kern.PREFETCH_BATCH):
        best = math.inf
        for r in range(repeat):
            s = _state(r)
            cpu = 0.0
            for _ in range(calls):
                u = v.copy()
                c0 = time.process_time()
                kern.collide(u, m, 0.9, hi - lo, s, batch)
                cpu += time.process_time() - c0
            best = min(best, cpu / (calls * m) * 1e9)
        out.append(best)
    return out[0], out[1]


def rng_costs(n: int = 4_000_000) -> dict[str, float]:
    """Nanoseconds per normal and per candidate with every velocity in the L1 cache."""
    s = _state(1)
    out = np.empty(n)
    kern.fill_normal(out, s, *TABLES)  # compile and touch every page before timing
    c0 = time.process_time()
    kern.fill_normal(out, s, *TABLES)
    normal = (time.process_time() - c0) / n * 1e9
    v = np.random.default_rng(1).normal(size=1000)  # 8 kB: in the L1 cache
    lo, hi = kern.extent(v)
    kern.collide(v, 1000, -1.0, hi - lo, s)
    c0 = time.process_time()
    kern.collide(v, n, -1.0, hi - lo, s)  # alpha = -1: collisions leave v unchanged
    candidate = (time.process_time() - c0) / n * 1e9
    return {"normal": normal, "candidate_l1": candidate}


def _replica(seed: int, n: int, cpp: float) -> float:
    return cooling(n, cpp, seed=seed, repeat=1)["rate"]


def replicas(n: int, cpp: float, workers: int) -> tuple[float, float]:
    """Aggregate accepted collisions/s of ``workers`` replicas: serial vs process pool."""
    t0 = time.perf_counter()
    for k in range(workers):
        _replica(k, n, cpp)
    serial = time.perf_counter() - t0
    with ProcessPoolExecutor(workers) as pool:
        list(pool.map(_replica, [0], [1000], [1.0]))  # start and compile the workers
        t0 = time.perf_counter()
        list(pool.map(_replica, range(workers), [n] * workers, [cpp] * workers))
        parallel = time.perf_counter() - t0
    return serial, parallel


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="short runs")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--no-replicas", action="store_true",
                        help="skip the replicas (they use every core)")
    args = parser.parse_args()
    cpp = 20.0 if args.quick else 100.0
    print(f"DSMC throughput, one core, best of {args.repeat} (machine shared with other "
          f"jobs; load average {os.getloadavg()[0]:.2f})")
    print(f"{'case':<26}{'N':>9}{'coll/s':>11}{'ns/coll':>9}{'ns/cand':>9}{'accept':>8}"
          f"{'ns/kick':>9}{'kicks':>7}{'wall coll/s':>13}")
    cool, heat = {}, {}
    for n in (25_000, 1_000_000):
        c = cool[n] = cooling(n, cpp if n < 10**6 else cpp / 4, repeat=args.repeat)
        print(f"{'cooling alpha=0.9':<26}{n:>9}{c['rate']:>11.3e}{c['ns_coll']:>9.1f}"
              f"{c['ns_cand']:>9.2f}{c['accept']:>8.3f}{'':>16}{c['wall']:>13.3e}")
    for n, step in ((25_000, 0.05), (1_000_000, 0.05), (25_000, 0.2)):
        h = heated(n, cpp / 4 if n < 10**6 else cpp / 20, repeat=args.repeat, step=step)
        heat[n, step] = h
        ns_cand = h["ns_coll"] * h["accept"] * (1.0 - h["kick_share"])
        print(f"{f'heated alpha=0.6 dt={step}':<26}{n:>9}{h['rate']:>11.3e}"
              f"{h['ns_coll']:>9.1f}{ns_cand:>9.2f}{h['accept']:>8.3f}{h['ns_kick']:>9.2f}"
              f"{h['kick_share']:>7.0%}{h['wall']:>13.3e}")
    print("  (heated ns/cand: the collision part only, from the expected acceptance; "
          "kicks: their share of the cost)")
    rc = cool[10**6]["ns_coll"] / cool[25_000]["ns_coll"]
    rh = heat[10**6, 0.05]["ns_coll"] / heat[25_000, 0.05]["ns_coll"]
    print(f"cost per collision, N = 1e6 / N = 25000: cooling {rc:.2f} (acceptance "
          f"{cool[25_000]['accept'] / cool[10**6]['accept']:.2f}, per candidate "
          f"{cool[10**6]['ns_cand'] / cool[25_000]['ns_cand']:.2f}); heated dt=0.05 "
          f"{rh:.2f}; target <= 1.5")
    for n in (25_000, 1_000_000):
        if not hasattr(kern, "PREFETCH_BATCH"):  # kernels older than the prefetch
            break
        plain, batched = batch_ratio(cool[n]["v"], repeat=args.repeat)
        auto = "batches" if n >= kern.PREFETCH_MIN_N else "plain loop"
        print(f"collide N={n}: plain loop {plain:.2f} ns/cand, batched (pairs drawn and "
              f"prefetched {kern.PREFETCH_BATCH} ahead) {batched:.2f} ns/cand, plain/batched "
              f"{plain / batched:.2f} (default: {auto})")
    c0 = time.process_time()
    run = dsmc.simulate_heated(0.6, 25_000, seed=1, collisions_per_particle=cpp, relax=10.0)
    wall = time.process_time() - c0
    print(f"end to end: simulate_heated(0.6, 25000), {run.collisions_per_particle:.0f} "
          f"collisions per particle incl. relaxation, sampling and moments: "
          f"{run.n_collisions / wall:.3e} collisions per CPU second")
    r = rng_costs()
    print(f"random numbers: {r['normal']:.2f} ns per normal (ziggurat on xoshiro256**); "
          f"{r['candidate_l1']:.2f} ns per candidate with v in L1 (2 draws, pair, "
          f"accept, 2 loads, 2 stores)")
    if not args.no_replicas:
        workers = os.cpu_count() or 1
        serial, parallel = replicas(25_000, 10 * cpp, workers)
        print(f"replicas: {workers} x cooling N=25000: serial {serial:.2f} s, process pool "
              f"{parallel:.2f} s, speed-up {serial / parallel:.2f} on {workers} cores")


if __name__ == "__main__":
    main()
