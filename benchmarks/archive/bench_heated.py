"""Speed of the FEM heated solver (issue 3, part 6).

1. Cost of one collision-operator evaluation (residual) and of its dense Jacobian
   against the number of P2 velocity nodes, with the fitted growth exponent; and the
   O(N) cost of the collision frequency by cumulative moments (grid.abs_power_convolution).
2. FEM Newton against the finite-difference time marching (``method="fd"``) to the
   same a2 accuracy (1e-6, against a fine FEM reference) at alpha = 0.9 and 0.99.

    python benchmarks/bench_heated.py [--quick] [--skip-fd]

Timings are wall-clock on whatever machine runs this (single BLAS thread).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # dense LU; avoid oversubscription

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import kinetic_fem as kf  # noqa: E402
from kinetic_fem.operators.grid import abs_power_convolution  # noqa: E402
from kinetic_fem.solvers import fem  # noqa: E402


def best_of(func, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        func()
        times.append(time.perf_counter() - t0)
    return min(times)


def operator_cost(sizes: list[int]) -> None:
    print("\n1. cost per call against the number of P2 nodes (alpha = 0.6, 3-point Gauss)")
    print(f"{'nodes':>6} {'residual/s':>11} {'jacobian/s':>11} {'nu O(N)/s':>10}")
    rows = []
    for n_nodes in sizes:
        n_el = (n_nodes - 1) // 2
        n_el += n_el % 2
        disc = fem.FEMDiscretisation(0.6, np.linspace(-20.0, 20.0, n_el + 1), 2, 5)
        u = disc.gaussian(2.0)
        disc.collision(u)  # compile
        t_res = best_of(lambda d=disc, u=u: d.collision(u), 3 if n_nodes <= 1000 else 1)
        t_jac = best_of(lambda d=disc, u=u: d.collision(u, jacobian=True),
                        2 if n_nodes <= 1000 else 1)
        xq, wq, _ = disc.points
        p = disc.values(u)
        t_nu = best_of(lambda x=xq, wp=wq * p: abs_power_convolution(x, wp, 1), 5)
        rows.append((disc.dof_locations.size, t_res, t_jac, t_nu))
        print(f"{rows[-1][0]:6d} {t_res:11.4f} {t_jac:11.4f} {t_nu:10.2e}")
    n = np.log([r[0] for r in rows])
    for k, name in ((1, "residual"), (2, "jacobian"), (3, "nu (cumulative moments)")):
        slope = np.polyfit(n[1:], np.log([r[k] for r in rows[1:]]), 1)[0]
        print(f"fitted exponent ({name}): {slope:.2f}")


def fem_vs_fd(alphas: list[float], skip_fd: bool) -> None:
    print("\n2. steady state to a2 within 1e-6 (reference: FEM P2, spacing 0.04)")
    print(f"{'alpha':>6} {'method':>22} {'nodes':>6} {'time/s':>8} {'a2':>14} {'|a2-ref|':>9} "
          f"{'|T/Tref-1|':>10}")
    for alpha in alphas:
        ref = kf.solve_heated(alpha, method="fem", spacing=0.04)
        runs = []
        for spacing in (0.4, 0.3, 0.2, 0.15) if alpha < 0.95 else (0.3, 0.2, 0.15, 0.1):
            t0 = time.perf_counter()
            d = kf.solve_heated(alpha, method="fem", spacing=spacing)
            runs.append((f"fem P2 spacing {spacing}", d, time.perf_counter() - t0))
        if not skip_fd:
            t0 = time.perf_counter()
            d = kf.solve_heated(alpha, method="fd")
            runs.append(("fd march (defaults)", d, time.perf_counter() - t0))
        for name, d, wall in runs:
            print(f"{alpha:6.3f} {name:>22} {d.v.size:6d} {wall:8.2f} {d.a2:14.10f} "
                  f"{abs(d.a2 - ref.a2):9.1e} {abs(d.temperature / ref.temperature - 1):10.1e}")
        fems = [(abs(d.a2 - ref.a2), w) for name, d, w in runs if name.startswith("fem")]
        for name, d, wall in runs:
            if not name.startswith("fd"):
                continue
            err = abs(d.a2 - ref.a2)
            tight = [w for e, w in fems if e < 1e-6]
            same = [w for e, w in fems if e <= err]
            if tight:
                print(f"       time ratio fd / fem(a2 within 1e-6): {wall / min(tight):.0f}  "
                      f"(the fd run is only within {err:.1e})")
            if same:
                print(f"       time ratio fd / fem(a2 within the fd error {err:.1e}): "
                      f"{wall / min(same):.0f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="sizes up to 1000 nodes")
    parser.add_argument("--skip-fd", action="store_true", help="FEM only")
    parser.add_argument("--skip-cost", action="store_true", help="part 2 only")
    args = parser.parse_args()
    sizes = [250, 500, 1000] if args.quick else [250, 500, 1000, 2000, 4000]
    if not args.skip_cost:
        operator_cost(sizes)
    fem_vs_fd([0.9, 0.99], args.skip_fd)


if __name__ == "__main__":
    main()
