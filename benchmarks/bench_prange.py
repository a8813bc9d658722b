"""Issue 16: the parallel FEM pair kernel (numba prange over outer points) against the
serial one, on 2 threads, in one process.

The parallel kernel (:mod:`kinetic_fem.operators.fem_pair_parallel`, switched on by
``KINETIC_FEM_PARALLEL=1``) gives bit-identical results (checked here on every call);
this measures its speed.  BLAS stays single-threaded; numba gets ``--threads`` threads
(default 2).  Run it on a quiet machine: a prange speed-up measured while other jobs
hold the cores is meaningless (the load average is printed before and after).

1. The kernel alone (residual; with the Jacobian), P3, even sums (as in Newton), at
   several sizes: serial, parallel on 1 thread (the cost of buffering the sums) and on
   ``--threads`` threads; best of ``--repeat``, interleaved.
2. Whole solves ``kf.solve_heated(alpha)`` with the defaults, serial and parallel
   alternately, best of ``--repeat``; and the 25-point curve over [0, 0.99].

    NUMBA_NUM_THREADS=2 python benchmarks/bench_prange.py [--threads 2] [--repeat 5] [--quick]

Writes ``benchmarks/results/prange.md`` (``prange_quick.md`` with ``--quick``).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"
os.environ.setdefault("NUMBA_NUM_THREADS", "2")

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))

import numba  # noqa: E402
from bench_fem_speed import CURVE, yardstick  # noqa: E402

import kinetic_fem as kf  # noqa: E402
from kinetic_fem.operators.fem_discretisation import FEMDiscretisation  # noqa: E402
from kinetic_fem.operators.fem_pair_parallel import PARALLEL_ENV  # noqa: E402

SIZES = [253, 505, 1003, 2005]
ALPHAS = [0.0, 0.5, 0.9, 0.99]


def _load() -> str:
    return "/".join(f"{x:.2f}" for x in os.getloadavg())


def _setting(parallel: bool, threads: int) -> None:
    os.environ[PARALLEL_ENV] = "1" if parallel else "0"
    numba.set_num_threads(threads)


def _time(func) -> float:
    t0 = time.perf_counter()
    func()
    return time.perf_counter() - t0


def kernel_table(sizes: list[int], threads: int, repeat: int, out: list[str]) -> None:
    """Section 1."""
    out.append(f"## 1. Pair kernel alone (P3, even sums), ms, best of {repeat}\n")
    out.append(f"| nodes | residual serial | parallel 1 thread | parallel {threads} | "
               f"speed-up | Jacobian serial | parallel 1 thread | parallel {threads} | "
               "speed-up | bit-identical |")
    out.append("|---|---|---|---|---|---|---|---|---|---|")
    configs = [("serial", False, 1), ("par1", True, 1), ("parN", True, threads)]
    for n_nodes in sizes:
        n_el = (n_nodes - 1) // 3
        n_el += n_el % 2
        disc = FEMDiscretisation(0.6, np.linspace(-20.0, 20.0, n_el + 1), 3, 7)
        u = disc.gaussian(2.0)
        best: dict[tuple[str, bool], float] = {}
        results: dict[tuple[str, bool], tuple] = {}
        for rep in range(repeat + 1):  # the first round compiles
            for name, par, th in configs:
                for jac in (False, True):
                    _setting(par, th)
                    t0 = time.perf_counter()
                    results[(name, jac)] = disc.collision(u, jacobian=jac, energy_power=None,
                                                          even=True)
                    dt = time.perf_counter() - t0
                    if rep:
                        best[(name, jac)] = min(best.get((name, jac), np.inf), dt)
        same = all(np.array_equal(results[("serial", j)][i], results[(c, j)][i])
                   for c in ("par1", "parN") for j in (False, True) for i in (0, 1))
        row = [str(u.size)]
        for jac in (False, True):
            s, p1, pn = (1e3 * best[(c, jac)] for c in ("serial", "par1", "parN"))
            row += [f"{s:.1f}", f"{p1:.1f}", f"{pn:.1f}", f"{s / pn:.2f}"]
        out.append("| " + " | ".join(row + ["yes" if same else "**NO**"]) + " |")
        print(out[-1], flush=True)
    out.append("")


def solve_table(alphas: list[float], threads: int, repeat: int, curve: bool,
                out: list[str]) -> None:
    """Section 2."""
    out.append(f"## 2. `kf.solve_heated(alpha)` defaults, s, best of {repeat}\n")
    out.append(f"| alpha | nodes | serial | parallel ({threads} threads) | speed-up | "
               "same T, a2 |")
    out.append("|---|---|---|---|---|---|")
    for alpha in alphas:
        best = [np.inf, np.inf]
        dists = [None, None]
        for _ in range(repeat):
            for i, par in enumerate((False, True)):
                _setting(par, threads if par else 1)
                t0 = time.perf_counter()
                dists[i] = kf.solve_heated(alpha)
                best[i] = min(best[i], time.perf_counter() - t0)
        same = dists[0].temperature == dists[1].temperature and dists[0].a2 == dists[1].a2
        out.append(f"| {alpha} | {dists[0].c.size} | {best[0]:.3f} | {best[1]:.3f} | "
                   f"{best[0] / best[1]:.2f} | {'yes' if same else '**NO**'} |")
        print(out[-1], flush=True)
    if curve:
        times = [np.inf, np.inf]
        for _ in range(2):
            for i, par in enumerate((False, True)):
                _setting(par, threads if par else 1)
                times[i] = min(times[i], _time(lambda: [kf.solve_heated(a) for a in CURVE]))
        unit = yardstick()
        out.append(f"\n25-point curve (pointwise, best of 2): serial {times[0]:.2f} s = "
                   f"{times[0] / unit:.1f} units, parallel {times[1]:.2f} s = "
                   f"{times[1] / unit:.1f} units, speed-up {times[0] / times[1]:.2f} "
                   f"(yardstick {unit:.3f} s)")
        print(out[-1], flush=True)
    out.append("")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--threads", type=int, default=2, help="numba threads (default 2)")
    parser.add_argument("--repeat", type=int, default=5, help="best of this many")
    parser.add_argument("--quick", action="store_true", help="two sizes, two alphas, no curve")
    args = parser.parse_args()
    if args.threads > numba.config.NUMBA_NUM_THREADS:
        parser.error(f"--threads {args.threads} > NUMBA_NUM_THREADS "
                     f"{numba.config.NUMBA_NUM_THREADS}; set NUMBA_NUM_THREADS")
    out = ["# Parallel FEM pair kernel (numba prange over outer points), issue 16\n",
           f"numba {numba.__version__}, threading layer after the first parallel call "
           f"below; {os.cpu_count()} cores; BLAS single-threaded; load average "
           f"(1/5/15 min) at the start {_load()}.  A speed-up is meaningful only on a "
           "quiet machine.\n"]
    print("\n".join(out), flush=True)
    kernel_table(SIZES[:2] if args.quick else SIZES, args.threads, args.repeat, out)
    out[1] = out[1].replace("after the first parallel call below",
                            f"{numba.threading_layer()}")
    solve_table(ALPHAS[1:3] if args.quick else ALPHAS, args.threads, args.repeat,
                not args.quick, out)
    out.append(f"load average at the end {_load()}\n")
    text = "\n".join(out)
    print(out[-1])
    name = "prange_quick.md" if args.quick else "prange.md"
    (ROOT / "benchmarks" / "results" / name).write_text(text + "\n")


if __name__ == "__main__":
    main()
