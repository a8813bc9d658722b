"""Throughput of the homogeneous DSMC kernels (accepted collisions per second, one core).

Run: ``python benchmarks/bench_dsmc.py [--quick] [--no-replicas] [--baseline DIR]``.

``--baseline DIR``: DIR holds an older ``particles`` package (e.g. ``git archive <commit>
particles | tar -x -C DIR``); the hard-rod cases are then timed alternately with it (in
a subprocess with ``PYTHONPATH=DIR``) and with this checkout, twice each, best of all,
and printed side by side with the ratio (the machine's load changes slowly, so
alternating makes the ratio fair).  The Maxwell kernel (no rejection) and the other
power-law kernels are timed after the hard-rod table.

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

try:  # this checkout: the generator in particles.rng, segments in their own module
    from particles import _dsmc_segments as seg
    from particles import rng as _rng
    NEW_API = True
except ImportError:  # a baseline from before the model layer
    seg = _rng = kern
    NEW_API = False

TABLES = _rng.ziggurat_tables()


def _state(seed: int) -> np.ndarray:
    """A kernel state; 5 words (xoshiro256** and the heated kernels' wyrand word) where the
    heated kernels take them (since issue 13), else 4 (the cooling kernels read 4)."""
    words = 5 if hasattr(_rng, "heated_state") else 4
    return np.random.SeedSequence(seed).generate_state(words, dtype=np.uint64)


def cooling_block(v, m, refresh, alpha, s, kcode=1, gamma=1.0):
    """The cooling block of either kernel API (hard rods, constant alpha, unless new)."""
    if NEW_API:
        return seg.cooling_block(v, m, refresh, kcode, gamma, 0, alpha, 0.0, 0.0, s)
    return kern.cooling_block(v, m, refresh, alpha, s)


def heated_segment(v, steps, dt, amp, rate, alpha, debt, s, kcode=1, gamma=1.0):
    """The white-noise heated segment of either kernel API: ``(accepted, loss, debt)``."""
    if NEW_API:
        return seg.heated_segment(v, steps, dt, 1.0, amp, 1.0, amp / math.sqrt(2.0), rate,
                                  kcode, gamma, 0, alpha, 0.0, math.inf, debt, s, *TABLES)[:3]
    return kern.heated_segment(v, steps, dt, amp, rate, alpha, debt, s, *TABLES)


def null_kick(u, s):
    """A kick of amplitude 0 (leaves ``u`` unchanged) of either API."""
    return seg.kick(u, 1.0, 0.0, s, *TABLES) if NEW_API else kern.kick(u, 0.0, s, *TABLES)


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
    cooling_block(v, int(40 * n / 2 / 0.15), n, 0.9, s)
    best = None
    for _ in range(repeat):
        m = int(collisions_per_particle * n / 2 / 0.15)
        t0, c0 = time.perf_counter(), time.process_time()
        acc, _, _ = cooling_block(v, m, n, 0.9, s)
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
    heated_segment(v, int(10 / step), *args, 0.0, s)  # 10 collisions/particle
    best = None
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        acc, _, _ = heated_segment(v, steps, *args, 0.0, s)
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
            null_kick(u, s)
        kick = min(kick, (time.process_time() - c0) / (sweeps * n) * 1e9)
    best["ns_kick"] = kick
    best["kick_share"] = kick * n * best["steps"] / best["acc"] / best["ns_coll"]
    return best


def batch_ratio(v: np.ndarray, repeat: int = 3) -> tuple[float, float]:
    """ns per candidate of ``collide`` on (copies of) ``v``: plain loop, batches."""
    lo, hi = seg.extent(v)
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
    _rng.fill_normal(out, s, *TABLES)  # compile and touch every page before timing
    c0 = time.process_time()
    _rng.fill_normal(out, s, *TABLES)
    normal = (time.process_time() - c0) / n * 1e9
    v = np.random.default_rng(1).normal(size=1000)  # 8 kB: in the L1 cache
    lo, hi = seg.extent(v)
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


def hard_rod_rates(cpp: float, repeat: int) -> dict[str, float]:
    """Accepted collisions per CPU second of the hard-rod cases (kernels and whole calls)."""
    out = {}
    for n in (25_000, 1_000_000):
        out[f"cooling kernel alpha=0.9 N={n}"] = cooling(
            n, cpp if n < 10**6 else cpp / 4, repeat=repeat)["rate"]
    for n, step in ((25_000, 0.05), (1_000_000, 0.05), (25_000, 0.2)):
        out[f"heated kernel alpha=0.6 dt={step} N={n}"] = heated(
            n, cpp / 4 if n < 10**6 else cpp / 20, repeat=repeat, step=step)["rate"]
    for name, func, alpha in (("heated", dsmc.simulate_heated, 0.6),
                              ("cooling", dsmc.simulate_cooling, 0.9)):
        best = 0.0
        for _ in range(repeat):
            c0 = time.process_time()
            run = func(alpha, 25_000, seed=1, collisions_per_particle=cpp, relax=10.0)
            best = max(best, run.n_collisions / (time.process_time() - c0))
        out[f"simulate_{name}({alpha}, 25000) end to end"] = best
    return out


def maxwell_rates(cpp: float, repeat: int) -> None:
    """Print collisions per CPU second of the Maxwell kernel and of other exponents."""
    print("\nMaxwell kernel (gamma = 0: every candidate collides, one draw per pair):")
    for n in (25_000, 1_000_000):
        v = np.random.default_rng(0).normal(size=n)
        s = _state(0)
        m = int(cpp * n / 2)
        kern.collide_maxwell(v, 1000, 0, 0.9, 0.0, 1.0, s)
        best = math.inf
        for _ in range(repeat):
            c0 = time.process_time()
            kern.collide_maxwell(v, m, 0, 0.9, 0.0, 1.0, s)
            best = min(best, time.process_time() - c0)
        print(f"  collide_maxwell N={n}: {m / best:.3e} collisions/s ({best / m * 1e9:.2f} "
              f"ns per collision)")
    for kcode, gamma in ((0, 0.0), (3, 0.5), (1, 1.0), (3, 1.5), (2, 2.0)):
        n = 25_000
        v = np.random.default_rng(0).normal(size=n)
        s = _state(0)
        cooling_block(v, 20 * n, n, 0.9, s, kcode, gamma)
        m = int(cpp * n)
        best = 0.0
        for _ in range(repeat):
            c0 = time.process_time()
            acc, _, _ = cooling_block(v, m, n, 0.9, s, kcode, gamma)
            best = max(best, acc / (time.process_time() - c0))
        print(f"  cooling block gamma={gamma:<4} N={n}: {best:.3e} collisions/s "
              f"(acceptance {acc / m:.3f})")
    for name, func, alpha in (("heated", dsmc.simulate_heated, 0.6),
                              ("cooling", dsmc.simulate_cooling, 0.9)):
        c0 = time.process_time()
        run = func(alpha, 25_000, kernel=0.0, seed=1, collisions_per_particle=cpp, relax=10.0)
        cpu = time.process_time() - c0
        print(f"  simulate_{name}({alpha}, 25000, kernel=0) end to end: "
              f"{run.n_collisions / cpu:.3e} collisions per CPU second")


def compare(baseline: str, cpp: float, repeat: int) -> None:
    """Hard-rod rates of ``baseline`` and of this checkout, alternately, best of all."""
    import json
    import subprocess
    import sys

    env = {**os.environ, "PYTHONPATH": os.path.abspath(baseline)}
    cmd = [sys.executable, __file__, "--json", "--repeat", str(repeat), "--cpp", str(cpp)]
    before: dict[str, float] = {}
    after: dict[str, float] = {}
    for _ in range(2):
        done = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
        for k, val in json.loads(done.stdout.splitlines()[-1]).items():
            before[k] = max(before.get(k, 0.0), val)
        for k, val in hard_rod_rates(cpp, repeat).items():
            after[k] = max(after.get(k, 0.0), val)
    print(f"\nhard rods, before ({baseline}) and after (this checkout), alternately twice, "
          f"best of {2 * repeat}; collisions per CPU second (load average "
          f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} cores)")
    print(f"{'case':<52}{'before':>11}{'after':>11}{'after/before':>14}")
    for k in before:
        print(f"{k:<52}{before[k]:>11.3e}{after[k]:>11.3e}{after[k] / before[k]:>14.3f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="short runs")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--no-replicas", action="store_true",
                        help="skip the replicas (they use every core)")
    parser.add_argument("--baseline", help="directory with an older particles package")
    parser.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--cpp", type=float, help=argparse.SUPPRESS)
    args = parser.parse_args()
    cpp = args.cpp or (20.0 if args.quick else 100.0)
    if args.json:  # the hard-rod rates of whichever particles package is imported
        import json

        print(json.dumps(hard_rod_rates(cpp, args.repeat)))
        return
    if args.baseline:
        compare(args.baseline, cpp, args.repeat)
        maxwell_rates(cpp, args.repeat)
        return
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
    maxwell_rates(cpp, args.repeat)
    if not args.no_replicas:
        workers = os.cpu_count() or 1
        serial, parallel = replicas(25_000, 10 * cpp, workers)
        print(f"replicas: {workers} x cooling N=25000: serial {serial:.2f} s, process pool "
              f"{parallel:.2f} s, speed-up {serial / parallel:.2f} on {workers} cores")


if __name__ == "__main__":
    main()
