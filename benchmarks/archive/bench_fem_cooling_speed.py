"""Issue 16, seventh round: the cooling state before and after, in CPU-time units.

Two persistent workers, one on ``git archive BEFORE`` and one on the working tree
(single-threaded BLAS and numba), are driven alternately: each cold
``kf.solve_cooling(alpha)`` (the cached state at eps = 0.1 cleared) is timed in CPU
seconds of the worker (``time.process_time``, less sensitive than wall time to the other
jobs sharing the two cores) and divided by the yardstick (10 LU factorisations of a
1000 x 1000 matrix, CPU seconds, best of three) measured right before it in the same
worker; each row is the best of ``--repeat`` such ratios.

    python benchmarks/bench_fem_cooling_speed.py [--before COMMIT] [--repeat 3]
        [--alphas A ...] [--kernels GAMMA ...] [--curves N ...]

``--curves N``: a second table, curves of N hard-rod states log-spaced over
eps in [EPS_LO, EPS_HI]: before and after as pointwise cold solves, and after with
warm starts (``kinetic_fem.solvers.fem_cooling_curve.cooling_curve``), in units of the
yardstick measured before each curve.

A solve that raises ConvergenceError is reported as failed (its CPU time to the failure).

Prints a markdown table (``benchmarks/archive/results/fem_cooling_speed.md``).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]  # the repository (this file is in benchmarks/archive)
BEFORE = "b639886"
"""main at the start of the ninth round (39f99a9: of the eighth; d8971af: of the seventh;
85cc10e: i16c2's start)."""
EPS_LO, EPS_HI = 1e-3, 0.099
"""Inelasticity range of the curves (``--curves``)."""
ALPHAS = [0.0, 0.25, 0.5, 0.7, 0.8, 0.9, 0.93, 0.95, 0.96, 0.97, 0.98, 0.99, 0.995, 0.997,
          0.999]


def serve() -> None:
    """Worker: answer ``alpha`` lines with JSON (CPU s of the solve and the yardstick)."""
    import warnings

    from bench_fem_speed import cpu_yardstick as yardstick

    import kinetic_fem as kf
    from kinetic_fem.solvers import fem_cooling

    warnings.simplefilter("ignore")
    for alpha in (0.5, 0.95, 0.99):  # compile every kernel variant
        kf.solve_cooling(alpha)
    for line in sys.stdin:
        if line.startswith("curve"):
            print(json.dumps(curve(line.split()[1:], yardstick)), flush=True)
            continue
        alpha, kernel = (float(x) for x in line.split())
        unit = yardstick()
        fem_cooling.hump_start.cache_clear()
        t0 = time.process_time()
        try:
            dist = kf.solve_cooling(alpha, kernel=kernel)
        except Exception:  # noqa: BLE001 (ConvergenceError: reported as failed)
            print(json.dumps({"cpu": time.process_time() - t0, "unit": unit,
                              "failed": True}), flush=True)
            continue
        cpu = time.process_time() - t0
        extra = dist.info.extra
        print(json.dumps({"cpu": cpu, "unit": unit, "zeta": extra["zeta"], "a2": dist.a2,
                          "nodes": extra["n_dofs"], "order": extra.get("order", 2)}),
              flush=True)


def curve(args: list[str], yardstick) -> dict:
    """A cooling curve at ``n`` inelasticities log-spaced over [EPS_LO, EPS_HI]: warm
    (``cooling_curve``, each state from its neighbour) or pointwise cold solves."""
    import numpy as np

    import kinetic_fem as kf
    from kinetic_fem.solvers import fem_cooling

    n, mode = int(args[0]), args[1]
    alphas = 1.0 - np.geomspace(EPS_HI, EPS_LO, n)
    unit = yardstick()
    t0 = time.process_time()
    if mode == "warm":
        from kinetic_fem.solvers.fem_cooling_curve import cooling_curve

        zeta = cooling_curve(alphas).zeta
    else:
        zeta = []
        for alpha in alphas:
            fem_cooling.hump_start.cache_clear()  # cold calls
            zeta.append(kf.solve_cooling(float(alpha)).info.extra["zeta"])
    cpu = time.process_time() - t0
    return {"cpu": cpu, "unit": unit, "zeta": [float(z) for z in zeta]}


def run_curves(workers: list, sizes: list[int], repeat: int) -> None:
    """Second figure: curves, before (pointwise) and after (pointwise, warm)."""
    print("\n| points | eps range | before pointwise units | after pointwise units | "
          "after warm units | after warm CPU s | warm speed-up | max rel dzeta warm |")
    print("|---|---|---|---|---|---|---|---|")
    for n in sizes:
        best: dict[str, dict] = {}
        for _ in range(repeat):
            for key, w, mode in (("before", workers[0], "point"), ("after", workers[1], "point"),
                                 ("warm", workers[1], "warm")):
                w.stdin.write(f"curve {n} {mode}\n")
                w.stdin.flush()
                r = json.loads(w.stdout.readline())
                r["units"] = r["cpu"] / r["unit"]
                if key not in best or r["units"] < best[key]["units"]:
                    best[key] = r
        dz = max(abs(a / b - 1) for a, b in zip(best["warm"]["zeta"], best["after"]["zeta"],
                                                strict=True))
        print(f"| {n} | [{EPS_LO:g}, {EPS_HI:g}] | {best['before']['units']:.1f} | "
              f"{best['after']['units']:.1f} | {best['warm']['units']:.1f} | "
              f"{best['warm']['cpu']:.2f} | "
              f"{best['after']['units'] / best['warm']['units']:.2f} | {dz:.1e} |", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", default=BEFORE)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--alphas", type=float, nargs="*", default=ALPHAS)
    parser.add_argument("--kernels", type=float, nargs="*", default=[1.0],
                        help="kernel exponents gamma (rows per gamma and alpha)")
    parser.add_argument("--curves", type=int, nargs="*", default=[],
                        help="also time cooling curves of these many points over eps in "
                             f"[{EPS_LO:g}, {EPS_HI:g}] (pointwise and warm)")
    parser.add_argument("--serve", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.serve:
        serve()
        return
    with tempfile.TemporaryDirectory() as tmp:
        archive = subprocess.run(["git", "archive", args.before, "kinetic_fem"], cwd=ROOT,
                                 capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
        workers = [subprocess.Popen([sys.executable, __file__, "--serve"], text=True,
                                    env=dict(os.environ, PYTHONPATH=str(tree)), cwd=tree,
                                    stdin=subprocess.PIPE, stdout=subprocess.PIPE)
                   for tree in (Path(tmp), ROOT)]
        print(f"Before = {args.before}, after = working tree; CPU seconds, best of "
              f"{args.repeat} (solve / yardstick) per worker; load average "
              f"{os.getloadavg()[0]:.1f} at the start.\n")
        print("| gamma | alpha | eps | nodes before | nodes after | before CPU s | after CPU s | "
              "before units | after units | speed-up | rel dzeta | abs da2 |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|")
        for gamma, alpha in ((g, a) for g in args.kernels for a in args.alphas):
            best: list[dict] = [{}, {}]
            for _ in range(args.repeat):
                for i, w in enumerate(workers):
                    assert w.stdin is not None and w.stdout is not None
                    w.stdin.write(f"{alpha} {gamma}\n")
                    w.stdin.flush()
                    r = json.loads(w.stdout.readline())
                    r["units"] = r["cpu"] / r["unit"]
                    if not best[i] or r.get("failed") or r["units"] < best[i]["units"]:
                        best[i] = r
            b, a = best
            if b.get("failed") or a.get("failed"):
                cells = [f"{r['cpu']:.2f} (failed)" if r.get("failed") else f"{r['cpu']:.2f}"
                         for r in best]
                print(f"| {gamma:g} | {alpha} | {1 - alpha:.3g} | "
                      f"{'-' if b.get('failed') else b['nodes']} | "
                      f"{'-' if a.get('failed') else a['nodes']} | {cells[0]} | {cells[1]} | "
                      f"{'-' if b.get('failed') else format(b['units'], '.2f')} | "
                      f"{'-' if a.get('failed') else format(a['units'], '.2f')} | - | - | - |",
                      flush=True)
                continue
            print(f"| {gamma:g} | {alpha} | {1 - alpha:.3g} | {b['nodes']} (P{b['order']}) | "
                  f"{a['nodes']} "
                  f"(P{a['order']}) | {b['cpu']:.2f} | {a['cpu']:.2f} | {b['units']:.2f} | "
                  f"{a['units']:.2f} | {b['units'] / a['units']:.1f} | "
                  f"{abs(a['zeta'] / b['zeta'] - 1):.1e} | {abs(a['a2'] - b['a2']):.1e} |",
                  flush=True)
        if args.curves:
            run_curves(workers, args.curves, args.repeat)
        for w in workers:
            assert w.stdin is not None
            w.stdin.close()
            w.wait()
        print(f"\nload average at the end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
