"""Issue 16: the parallel FEM pair kernel (numba prange) against the serial one.

The parallel kernel (:mod:`kinetic_fem.operators.fem_pair_parallel`, switched on by
``KINETIC_FEM_PARALLEL=1``) gives bit-identical results (checked here on every call).
BLAS stays single-threaded; numba gets ``--threads`` threads (default 2).

1. Work on one thread, in CPU seconds of the calling thread (reliable under load): the
   serial kernel, the parallel setting on one thread (it runs the serial kernel) and the
   parallel kernel's two passes forced onto one thread (its extra work: what a
   ``--threads`` run can at best divide by ``--threads``), and a model of the wall time on
   ``--threads`` idle cores (each block's passes timed, the slowest block per
   synchronisation summed).  P3, even sums (as in Newton), residual and Jacobian, best of
   ``--repeat``, interleaved.
2. Wall clock on ``--threads`` threads against the serial kernel, ``--rounds`` times,
   the load average printed with each round (a speed-up needs idle cores: on a loaded
   machine each of the kernel's synchronisations waits for a time slice).
3. Whole calls ``kf.solve_heated(alpha)`` with the defaults: serial, the setting on one
   thread and on ``--threads`` threads, wall clock (and CPU for the one-thread runs),
   ``--rounds`` times; same T and a2 checked.

    python benchmarks/bench_prange.py [--quick] [--threads 2] [--repeat 5] [--rounds 5]

``OMP_WAIT_POLICY`` is ``PASSIVE`` unless set (numba's OpenMP threads then sleep while they
wait instead of spinning; see the docs); ``OMP_WAIT_POLICY=active python
benchmarks/bench_prange.py --quick`` measures the spinning default and writes
``prange_quick_active.md``.

``--quick`` (three sizes, two alphas; under a minute) writes
``benchmarks/archive/results/prange_quick.md``, else ``prange.md``.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"
os.environ.setdefault("NUMBA_NUM_THREADS", "2")
# OpenMP threads that spin while they wait hold a core that the other thread needs on a
# loaded machine (measured at load 5: 2 threads up to 30x slower than serial); passive: sleep
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]  # the repository (this file is in benchmarks/archive)
sys.path.insert(0, str(ROOT))

import numba  # noqa: E402

import kinetic_fem as kf  # noqa: E402
from kinetic_fem.operators.fem_discretisation import FEMDiscretisation  # noqa: E402
from kinetic_fem.operators.fem_pair_breaks import GRADING_LEVELS, kernel_graded  # noqa: E402
from kinetic_fem.operators.fem_pair_fast import pair_sweep  # noqa: E402
from kinetic_fem.operators.fem_pair_parallel import (  # noqa: E402
    CHUNK_VALUES,
    PARALLEL_ENV,
    block_owners,
    collision_constant_parallel,
    pass_rows,
)
from kinetic_fem.operators.fem_pair_sums import visited_points, work_arrays  # noqa: E402

SIZES = [253, 505, 1003, 2005, 4000]
QUICK_SIZES = [253, 505, 1003]
ALPHAS = [0.0, 0.5, 0.9, 0.99]
QUICK_ALPHAS = [0.5, 0.9]


def _busy() -> tuple[float, float, float]:
    """Busy CPU seconds of the machine (``/proc/stat``, 0 where unreadable), CPU seconds of
    this process (all threads) and the wall clock."""
    try:
        with open("/proc/stat") as stat:
            ticks = [float(v) for v in stat.readline().split()[1:]]
        machine = (sum(ticks[:8]) - ticks[3] - ticks[4]) / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        machine = 0.0
    own = os.times()
    return machine, own.user + own.system, time.perf_counter()


def _others(since: tuple[float, float, float]) -> str:
    """Cores the other jobs kept busy since ``since`` (:func:`_busy`)."""
    now = _busy()
    if now[0] == 0.0:
        return "?"
    return f"{max(0.0, (now[0] - since[0]) - (now[1] - since[1])) / (now[2] - since[2]):.2f}"


def _load() -> str:
    return "/".join(f"{x:.2f}" for x in os.getloadavg())


def _setting(parallel: bool, threads: int) -> None:
    os.environ[PARALLEL_ENV] = "1" if parallel else "0"
    numba.set_num_threads(threads)


def _disc(n_nodes: int) -> FEMDiscretisation:
    n_el = (n_nodes - 1) // 3
    n_el += n_el % 2
    return FEMDiscretisation(0.6, np.linspace(-20.0, 20.0, n_el + 1), 3, 7)


def _two_passes(disc: FEMDiscretisation, u: np.ndarray, jac: bool):
    """The parallel kernel's two passes on one element block (one thread)."""
    verts, dofs = disc.mesh_arrays
    xq, wq, eq = disc.points
    rx, rw = disc.basis.quadrature
    kernel = 1.0  # hard rods (the kernel of _disc)
    return collision_constant_parallel(verts, dofs, u, xq, wq, eq, np.ascontiguousarray(rx[0]),
                                       rw, disc.alpha, 1.0, jac, -1, kernel,
                                       bool(kernel_graded(kernel)), 1, disc.mirror)


def modelled_time(disc: FEMDiscretisation, u: np.ndarray, jac: bool, threads: int
                  ) -> tuple[float, float]:
    """The parallel kernel's passes run one block after the other on this thread, each
    timed in thread CPU seconds: returns the total and the critical path on ``threads``
    idle cores (per synchronisation the slowest block; no memory contention counted)."""
    verts, dofs = disc.mesh_arrays
    xq, wq, eq = disc.points
    rx, rw = disc.basis.quadrature
    rx = np.ascontiguousarray(rx[0])
    k = dofs.shape[1]
    n_ref = rx.size
    n_val = 2 * k + n_ref
    res, jmat, bq, cy, jac_x = work_arrays(u.size, jac)
    first, owner, runs = block_owners(dofs, u.size, threads)
    n_max = 2 * verts.size + 2 * (GRADING_LEVELS + 1)
    visit = visited_points(xq, disc.mirror)
    chunk = max(1, min(visit.size, CHUNK_VALUES // (n_max * n_val)))
    n_chunks = (visit.size + chunk - 1) // chunk
    ids = np.empty((2, chunk, threads, n_max, 2), dtype=np.int64)
    vals = np.empty((2, chunk, threads, n_max, n_val))
    phq = np.empty((2, chunk, k))
    n_p = np.empty((2, chunk, threads), dtype=np.int64)
    buf = np.empty(3 * verts.size + 3)
    starts = np.empty(n_max)
    lengths = np.empty(n_max)
    scratch = np.empty(3 * n_ref)
    chains = np.zeros(2)
    total = path = 0.0
    for c in range(n_chunks + 1):
        slowest = 0.0
        for p in range(threads):
            t0 = time.thread_time()
            if c > 0:
                b = (c - 1) % 2
                done = visit[(c - 1) * chunk:c * chunk]
                pass_rows(p, done, done.size, dofs, eq, n_ref, jac, False, first, owner, runs,
                          n_p[b], phq[b], ids[b], vals[b], res, bq, jac_x, chains)
            if c < n_chunks:
                b = c % 2
                todo = visit[c * chunk:(c + 1) * chunk]
                pair_sweep(todo, todo.size, verts, dofs, u, xq, wq, eq, rx, rw, disc.alpha,
                           1.0, jac, -1, 1.0, False, p, first, owner, runs, buf, starts,
                           lengths, scratch, n_p[b], phq[b], ids[b], vals[b], res, jmat, bq,
                           cy, jac_x, chains)
            dt = time.thread_time() - t0
            total += dt
            slowest = max(slowest, dt)
        path += slowest
    return total, path


def _same(a, b) -> bool:
    return bool(np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1]))


def work_table(sizes: list[int], threads: int, repeat: int, out: list[str]) -> None:
    """Section 1 (thread CPU time)."""
    out.append(f"## 1. One thread, CPU ms of the calling thread (best of {repeat})\n")
    out.append("Ratios to the serial kernel.  *Two passes*: the parallel kernel forced onto one "
               f"thread; *model {threads} cores*: its passes per block timed one after the "
               f"other, the slowest block per synchronisation summed (the wall time on "
               f"{threads} idle cores without memory contention or synchronisation cost).\n")
    out.append("| nodes | residual serial | setting on, 1 thread | two passes, 1 thread | "
               f"model {threads} cores | Jacobian serial | setting on, 1 thread | "
               f"two passes, 1 thread | model {threads} cores | bit-identical |")
    out.append("|---|---|---|---|---|---|---|---|---|---|")
    for n_nodes in sizes:
        disc = _disc(n_nodes)
        u = disc.gaussian(2.0)
        row = [str(u.size)]
        same = True
        for jac in (False, True):
            def coll(j=jac, d=disc, v=u):
                return d.collision(v, jacobian=j, energy_power=None, even=True)

            calls = {"serial": (False, coll), "on1": (True, coll),
                     "passes": (True, lambda j=jac, d=disc, v=u: _two_passes(d, v, j)),
                     "model": (True, lambda j=jac, d=disc, v=u: modelled_time(d, v, j,
                                                                              threads))}
            best = dict.fromkeys(calls, np.inf)
            results = {}
            for rep in range(repeat + 1):  # the first round compiles
                for name, (par, func) in calls.items():
                    _setting(par, 1)
                    t0 = time.thread_time()
                    results[name] = func()
                    dt = time.thread_time() - t0
                    if name == "model":
                        dt = results[name][1]
                    if rep:
                        best[name] = min(best[name], dt)
            same &= _same(results["serial"], results["on1"])
            same &= _same(results["serial"], results["passes"])
            s = best["serial"]
            row += [f"{1e3 * s:.1f}", f"{best['on1'] / s:.2f}x",
                    f"{best['passes'] / s:.2f}x", f"{best['model'] / s:.2f}x"]
        out.append("| " + " | ".join(row + ["yes" if same else "**NO**"]) + " |")
        print(out[-1], flush=True)
    out.append("")


def kernel_rounds(sizes: list[int], threads: int, repeat: int, rounds: int,
                  out: list[str]) -> None:
    """Section 2 (wall clock, ``threads`` threads)."""
    out.append(f"## 2. Kernel alone, wall ms, serial vs {threads} threads (best of "
               f"{repeat} per round)\n")
    out.append("| round | load (1/5/15 min) | other jobs (cores) | nodes | residual serial | "
               f"{threads} threads | speed-up | Jacobian serial | {threads} threads | "
               "speed-up | bit-identical |")
    out.append("|---|---|---|---|---|---|---|---|---|---|---|")
    discs = {n: _disc(n) for n in sizes}
    for rnd in range(1, rounds + 1):
        load = _load()
        for disc in discs.values():
            u = disc.gaussian(2.0)
            row = [str(rnd), load, "", str(u.size)]
            same = True
            since = _busy()
            for jac in (False, True):
                best = [np.inf, np.inf]
                res = [None, None]
                for rep in range(repeat + 1):
                    for i, (par, th) in enumerate(((False, 1), (True, threads))):
                        _setting(par, th)
                        t0 = time.perf_counter()
                        res[i] = disc.collision(u, jacobian=jac, energy_power=None, even=True)
                        dt = time.perf_counter() - t0
                        if rep:
                            best[i] = min(best[i], dt)
                same &= _same(res[0], res[1])
                row += [f"{1e3 * best[0]:.1f}", f"{1e3 * best[1]:.1f}",
                        f"{best[0] / best[1]:.2f}"]
            row[2] = _others(since)
            out.append("| " + " | ".join(row + ["yes" if same else "**NO**"]) + " |")
            print(out[-1], flush=True)
    out.append("")


def solve_rounds(alphas: list[float], threads: int, repeat: int, rounds: int,
                 out: list[str]) -> None:
    """Section 3 (whole ``kf.solve_heated`` calls)."""
    out.append(f"## 3. `kf.solve_heated(alpha)` defaults, whole call, ms (best of {repeat} "
               "per round)\n")
    out.append("| round | load (1/5/15 min) | other jobs (cores) | alpha | nodes | "
               "serial wall (CPU) | setting on, 1 thread: wall (CPU) | "
               f"{threads} threads wall | speed-up | same T, a2 |")
    out.append("|---|---|---|---|---|---|---|---|---|---|")
    configs = ((False, 1), (True, 1), (True, threads))
    for rnd in range(1, rounds + 1):
        load = _load()
        for alpha in alphas:
            wall = [np.inf] * 3
            cpu = [np.inf] * 3
            dists = [None] * 3
            since = _busy()
            for rep in range(repeat + 1):
                for i, (par, th) in enumerate(configs):
                    _setting(par, th)
                    t0 = time.perf_counter()
                    c0 = time.thread_time()
                    dists[i] = kf.solve_heated(alpha)
                    c1 = time.thread_time()
                    if rep:
                        wall[i] = min(wall[i], time.perf_counter() - t0)
                        cpu[i] = min(cpu[i], c1 - c0)
            same = all(d.temperature == dists[0].temperature and d.a2 == dists[0].a2
                       for d in dists)
            out.append(f"| {rnd} | {load} | {_others(since)} | {alpha} | {dists[0].c.size} | "
                       f"{1e3 * wall[0]:.0f} ({1e3 * cpu[0]:.0f}) | "
                       f"{1e3 * wall[1]:.0f} ({1e3 * cpu[1]:.0f}) | {1e3 * wall[2]:.0f} | "
                       f"{wall[0] / wall[2]:.2f} | {'yes' if same else '**NO**'} |")
            print(out[-1], flush=True)
    out.append("")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--threads", type=int, default=2, help="numba threads (default 2)")
    parser.add_argument("--repeat", type=int, default=5, help="best of this many")
    parser.add_argument("--rounds", type=int, default=5,
                        help="repetitions of the wall-clock comparisons (default 5)")
    parser.add_argument("--quick", action="store_true",
                        help="sizes 253-1003 and alpha 0.5, 0.9 (about a minute)")
    args = parser.parse_args()
    if args.threads > numba.config.NUMBA_NUM_THREADS:
        parser.error(f"--threads {args.threads} > NUMBA_NUM_THREADS "
                     f"{numba.config.NUMBA_NUM_THREADS}; set NUMBA_NUM_THREADS")
    start = time.perf_counter()
    out = ["# Parallel FEM pair kernel (numba prange), issue 16\n",
           f"numba {numba.__version__}, threading layer LAYER, OMP_WAIT_POLICY="
           f"{os.environ.get('OMP_WAIT_POLICY', '(unset)')}; {os.cpu_count()} cores; "
           f"BLAS single-threaded; load average (1/5/15 min) at the start {_load()}.  "
           f"A wall-clock speed-up on {args.threads} threads needs {args.threads} idle "
           "cores: read the rows whose *other jobs* (the cores that other processes kept "
           "busy during the row, from /proc/stat) are near 0.\n"]
    print("\n".join(out), flush=True)
    sizes = QUICK_SIZES if args.quick else SIZES
    work_table(sizes, args.threads, args.repeat, out)
    kernel_rounds(sizes, args.threads, args.repeat, args.rounds, out)
    out[1] = out[1].replace("LAYER", numba.threading_layer())
    solve_rounds(QUICK_ALPHAS if args.quick else ALPHAS, args.threads, args.repeat,
                 args.rounds, out)
    out.append(f"load average at the end {_load()}; {time.perf_counter() - start:.0f} s\n")
    print(out[-1], flush=True)
    name = "prange_quick" if args.quick else "prange"
    policy = os.environ["OMP_WAIT_POLICY"].lower()
    name += ".md" if policy == "passive" else f"_{policy}.md"
    (ROOT / "benchmarks" / "archive" / "results" / name).write_text("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
