"""Issue 16: cooling states of the Maxwell model (gamma = 0) and gamma = 2, before and after.

Two persistent workers, one on ``git archive BEFORE`` and one on the working tree
(single-threaded BLAS and numba), are driven alternately: each cold
``kf.solve_cooling(alpha, kernel=gamma)`` is timed in CPU seconds of the worker
(``time.process_time``) and divided by the yardstick (10 LU factorisations of a
1000 x 1000 matrix, CPU seconds, best of three) measured right before it in the same
worker; each row is the best of ``--repeat`` such ratios.  For the Maxwell model the
errors are against the closed form f = 2/(pi (1+c^2)^2), zeta = (1 - alpha^2)/4: relative
zeta, the largest relative error of the returned ``dist.f`` over |c| <= 10 and over
10 <= |c| <= 100, and ``dist.temperature - 1``; for other kernels zeta and a2 of both
against the state at half the default spacing (``--reference``, solved untimed by the
after worker; a failed before row still prints the after figures).  Near elastic
collisions (gamma = 2, alpha >= 0.995) use ``--repeat 1``: before the ninth round the
continuation remembered its near-elastic states (``fem_cooling_alpha``), so a repeated
call in the same worker is a cache hit.

    python benchmarks/bench_fem_cooling_models.py [--before COMMIT] [--repeat 2]
        [--kernels 0 2] [--alphas A ...] [--reference]

Prints markdown tables (``benchmarks/archive/results/fem_cooling_models_speed.md``).
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
BEFORE = "39f99a9"
"""main at the start of the eighth round."""
ALPHAS = [0.0, 0.3, 0.5, 0.7, 0.8, 0.9, 0.95, 0.99, 0.995, 0.999]


def serve() -> None:
    """Worker: answer ``alpha gamma`` lines with JSON (CPU s, yardstick, errors)."""
    import warnings

    import numpy as np
    from bench_fem_speed import cpu_yardstick as yardstick

    import kinetic_fem as kf

    def closed(c):
        return 2.0 / (np.pi * (1.0 + c * c) ** 2)

    warnings.simplefilter("ignore")
    for gamma in (0.0, 2.0):  # compile every kernel variant
        kf.solve_cooling(0.5, kernel=gamma)
    c_in = np.linspace(0.0, 10.0, 4001)
    c_out = np.linspace(10.0, 100.0, 4001)
    for line in sys.stdin:
        alpha, gamma, want_ref = (float(x) for x in line.split())
        unit = yardstick()
        t0 = time.process_time()
        try:
            dist = kf.solve_cooling(alpha, kernel=gamma)
        except Exception:  # noqa: BLE001 (ConvergenceError: reported as failed)
            print(json.dumps({"cpu": time.process_time() - t0, "unit": unit,
                              "failed": True}), flush=True)
            continue
        cpu = time.process_time() - t0
        extra = dist.info.extra
        out = {"cpu": cpu, "unit": unit, "zeta": extra["zeta"], "nodes": extra["n_dofs"],
               "order": extra.get("order", 2), "a2": dist.a2}
        if want_ref and gamma != 0.0:
            from kinetic_fem.model import CoolingProblem
            from kinetic_fem.solvers.fem_cooling_mesh import hcs_spacing
            from kinetic_fem.solvers.fem_cooling_order import order_spacing
            problem = CoolingProblem.from_parameters(alpha, kernel=gamma)
            ref = kf.solve_cooling(alpha, kernel=gamma, spacing=0.5 * order_spacing(
                hcs_spacing(problem), out["order"]))
            out.update(ref_zeta=ref.info.extra["zeta"], ref_a2=ref.a2,
                       ref_nodes=ref.info.extra["n_dofs"])
        if gamma == 0.0:
            out.update(
                dzeta=abs(extra["zeta"] / ((1.0 - alpha**2) / 4.0) - 1.0),
                f_in=float(np.abs(dist.f(c_in) / closed(c_in) - 1.0).max()),
                f_out=float(np.abs(dist.f(c_out) / closed(c_out) - 1.0).max()),
                dT=dist.temperature - 1.0)
        print(json.dumps(out), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", default=BEFORE)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--alphas", type=float, nargs="*", default=ALPHAS)
    parser.add_argument("--kernels", type=float, nargs="*", default=[0.0, 2.0])
    parser.add_argument("--reference", action="store_true",
                        help="errors against the state at half the default spacing")
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
        for gamma in args.kernels:
            print(f"\n### gamma = {gamma:g}\n")
            if gamma == 0.0:
                print("| alpha | dofs before | dofs after | CPU s before | CPU s after | "
                      "units before | units after | speed-up | dzeta before | dzeta after | "
                      "f(c<=10) before | f(c<=10) after | f(10..100) before | "
                      "f(10..100) after | T-1 before | T-1 after |")
                print("|---" * 16 + "|")
            else:
                print("| alpha | dofs before | dofs after | CPU s before | CPU s after | "
                      "units before | units after | speed-up | rel dzeta | abs da2 | "
                      "ref dofs | dzeta before vs ref | dzeta after vs ref | "
                      "da2 after vs ref |")
                print("|---" * 14 + "|")
            for alpha in args.alphas:
                best: list[dict] = [{}, {}]
                for _ in range(args.repeat):
                    for i, w in enumerate(workers):
                        assert w.stdin is not None and w.stdout is not None
                        want = int(args.reference and i == 1)
                        w.stdin.write(f"{alpha} {gamma} {want}\n")
                        w.stdin.flush()
                        r = json.loads(w.stdout.readline())
                        r["units"] = r["cpu"] / r["unit"]
                        if not best[i] or r.get("failed") or r["units"] < best[i]["units"]:
                            best[i] = r
                b, a = best
                if a.get("failed"):
                    print(f"| {alpha} | failed: before {b.get('failed', False)}, after "
                          f"True ({a['cpu']:.2f} CPU s) |", flush=True)
                    continue
                if b.get("failed"):
                    b = {"nodes": "failed", "order": "-", "cpu": b["cpu"], "units": b["units"],
                         "zeta": float("nan"), "a2": float("nan")}
                row = (f"| {alpha} | {b['nodes']} (P{b['order']}) | {a['nodes']} "
                       f"(P{a['order']}) | {b['cpu']:.2f} | {a['cpu']:.2f} | "
                       f"{b['units']:.2f} | {a['units']:.2f} | {b['units'] / a['units']:.1f} |")
                if gamma == 0.0:
                    row += "".join(f" {r[k]:.1e} |" for k in ("dzeta", "f_in", "f_out", "dT")
                                   for r in (b, a))
                else:
                    row += (f" {abs(a['zeta'] / b['zeta'] - 1):.1e} | "
                            f"{abs(a['a2'] - b['a2']):.1e} |")
                    if "ref_zeta" in a:
                        row += (f" {a['ref_nodes']} | {abs(b['zeta'] / a['ref_zeta'] - 1):.1e} | "
                                f"{abs(a['zeta'] / a['ref_zeta'] - 1):.1e} | "
                                f"{abs(a['a2'] - a['ref_a2']):.1e} |")
                print(row, flush=True)
        for w in workers:
            assert w.stdin is not None
            w.stdin.close()
            w.wait()
        print(f"\nload average at the end {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
