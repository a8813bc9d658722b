"""Sweeps over workers and the largest DSMC runs: speed-up, memory, collisions per second.

Run: ``python benchmarks/bench_sweep.py [--quick] [--part replicas|large|all]
[--sizes 1e7,1e8] [--dask]``.

*replicas*: a replica sweep ``{"replica": [0, ..., R-1]}`` of heated DSMC runs
(:func:`particles.dsmc.simulate_heated`, alpha = 0.6) through :func:`kinetic_fem.sweep`
on a local process pool of 1 and of 2 workers (and a dask LocalCluster of 2 worker
processes with ``--dask``).  Printed: wall time of each, the speed-up of 2 workers over
1 (ideal 2 on an idle 2-core machine; on a shared machine the other jobs take their
share), the sum of the points' own wall times (if it grows with the workers, the runs
slow each other down: cores or memory bandwidth taken by other jobs) and whether the
Datasets are bit-identical (they must be: seeds come from the grid point, not from the
worker).  First, what the machine offers at the moment: the work per second of 2
busy-looping processes against 1 (pure Python arithmetic; on a shared machine, or on two
hyper-threads of one core, 2 may do little more than 1).  Worker start-up (imports,
numba cache loading) is included, as a user sees it.

*large*: one heated DSMC run per size, each in a fresh subprocess, with a short run
(relaxation fixed at 1 collision per particle, 3 of averaging).  Printed: peak
resident memory, memory per particle (peak RSS minus that of the same process after a
run of N = 1000, over N), end-to-end wall time (initial state, kicks, collisions,
measurements) and collisions per second, and the accepted collisions.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

import kinetic_fem as kf


def replica_sweep(executor, replicas: int, n: int, cpp: float):
    from particles import dsmc

    start = time.perf_counter()
    ds = kf.sweep(dsmc.simulate_heated, {"replica": list(range(replicas))},
                  executor=executor, alpha=0.6, n_particles=n, collisions_per_particle=cpp,
                  relax=2.0, n_batches=5, seed=2002)
    return ds, time.perf_counter() - start


def _burn(seconds: float) -> float:
    """Busy-loop (pure Python arithmetic) for ``seconds`` of wall time; loops per second."""
    start, loops = time.perf_counter(), 0
    while time.perf_counter() - start < seconds:
        sum(i * i for i in range(10_000))
        loops += 1
    return loops / seconds


def cpu_capacity(workers: int, seconds: float = 2.0) -> float:
    """Work per second that ``workers`` busy processes do together right now (loops/s)."""
    with ProcessPoolExecutor(workers) as pool:
        pool.submit(_burn, 0.01).result()  # start the workers first
        return sum(pool.map(_burn, [seconds] * workers))


def part_replicas(quick: bool, use_dask: bool) -> None:
    cap = {w: cpu_capacity(w) for w in (1, 2)}
    print(f"machine now: 2 busy processes do {cap[2] / cap[1]:.2f} times the work of 1 (the "
          "speed-up a perfectly parallel job could reach)")
    replicas, n, cpp = (4, 20_000, 20.0) if quick else (8, 100_000, 40.0)
    print(f"replica sweep: {replicas} heated DSMC runs, alpha=0.6, N={n}, "
          f"{cpp:g} collisions per particle each")
    results = {}
    for workers in (1, 2):
        with ProcessPoolExecutor(workers) as pool:
            ds, wall = replica_sweep(pool, replicas, n, cpp)
        results[workers] = (ds, wall)
        coll = float(ds.n_collisions.sum())
        busy = float(ds.wall_time.sum())
        print(f"  {workers} worker(s): {wall:7.2f} s wall, {coll:.3g} collisions, "
              f"{coll / wall:.3g} collisions/s; points' own wall times add up to {busy:.2f} s "
              f"(workers busy {busy / (workers * wall):.0%} of the time)")
    (d1, w1), (d2, w2) = results[1], results[2]
    same = d1.drop_vars("wall_time").identical(d2.drop_vars("wall_time"))
    print(f"  speed-up 2 workers / 1: {w1 / w2:.2f}   (bit-identical results: {same})")
    print(f"  a2 over replicas: {float(d1.a2.mean()):+.4f} +- "
          f"{float(d1.a2.std(ddof=1)) / np.sqrt(replicas):.4f}")
    if use_dask:
        from distributed import Client, LocalCluster

        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            ds, wall = replica_sweep(client, replicas, n, cpp)
        same = ds.drop_vars("wall_time").identical(d1.drop_vars("wall_time"))
        print(f"  dask LocalCluster, 2 worker processes: {wall:7.2f} s wall, speed-up over "
              f"1 local worker {w1 / wall:.2f} (bit-identical: {same})")


def one_large(n: int) -> dict:
    """One short heated run of ``n`` particles in this process (called in a subprocess)."""
    from particles import dsmc

    def rss() -> float:  # peak resident set of this process, bytes (Linux: kB)
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024.0

    dsmc.simulate_heated(0.6, 1000, seed=0, collisions_per_particle=3, relax=1.0,
                         n_batches=2)  # compile / load the cache, baseline memory
    base = rss()
    start = time.perf_counter()
    run = dsmc.simulate_heated(0.6, n, seed=1, collisions_per_particle=3, relax=1.0,
                               n_batches=2)
    wall = time.perf_counter() - start
    return {"n": n, "wall": wall, "collisions": run.n_collisions, "peak": rss(),
            "base": base, "T": run.temperature, "a2": run.a2}


def part_large(sizes: list[int]) -> None:
    print("large heated DSMC runs (alpha=0.6, 1 relaxation + 3 averaging collisions per "
          "particle), each in a fresh process:")
    print(f"  {'N':>10s} {'peak RSS':>10s} {'B/particle':>10s} {'wall s':>8s} "
          f"{'collisions':>11s} {'coll/s':>9s} {'T':>7s} {'a2':>8s}")
    for n in sizes:
        done = subprocess.run([sys.executable, __file__, "--one-large", str(n)],
                              capture_output=True, text=True, check=False)
        if done.returncode != 0:
            print(f"  {n:10.3g} failed: {done.stderr.strip().splitlines()[-1:]}")
            continue
        r = json.loads(done.stdout.strip().splitlines()[-1])
        per = (r["peak"] - r["base"]) / n
        print(f"  {n:10.3g} {r['peak'] / 2**30:8.2f}GiB {per:10.1f} {r['wall']:8.1f} "
              f"{r['collisions']:11.3g} {r['collisions'] / r['wall']:9.3g} {r['T']:7.4f} "
              f"{r['a2']:+8.4f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes")
    parser.add_argument("--part", choices=("replicas", "large", "all"), default="all")
    parser.add_argument("--sizes", default=None, help="comma-separated N of the large runs")
    parser.add_argument("--dask", action="store_true", help="also a dask LocalCluster")
    parser.add_argument("--one-large", type=float, default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one_large is not None:
        print(json.dumps(one_large(int(args.one_large))))
        return
    print(time.strftime("%Y-%m-%d %H:%M"), "(timings on a shared machine: compare ratios)")
    if args.part in ("replicas", "all"):
        part_replicas(args.quick, args.dask)
    if args.part in ("large", "all"):
        default = "1e5,1e6" if args.quick else "1e6,1e7"
        part_large([int(float(s)) for s in (args.sizes or default).split(",")])


if __name__ == "__main__":
    main()
