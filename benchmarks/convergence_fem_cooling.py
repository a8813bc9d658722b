"""Mesh convergence of the FEM homogeneous cooling state (issue 10, part 3).

For each alpha the bulk element size is halved from ``spacing`` and zeta, a2 and the
energy identity are compared with the finest mesh (observed orders ``log2`` of
successive error ratios), and with the FD cooling state (second order) beside.

    python benchmarks/convergence_fem_cooling.py [--alphas 0.5 0.85 0.9] [--quick]
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import kinetic_fem as kf  # noqa: E402


def study(alpha: float, spacings: list[float]) -> None:
    runs = []
    for h in spacings:
        t0 = time.perf_counter()
        dist = kf.solve_cooling(alpha, spacing=h)
        runs.append((h, dist, time.perf_counter() - t0))
    ref = runs[-1][1]
    z_ref, a_ref = ref.info.extra["zeta"], ref.a2
    print(f"\nalpha = {alpha}  (P2; reference: spacing {spacings[-1]})")
    print(f"{'spacing':>8} {'n_dofs':>7} {'iter':>5} {'time/s':>7} {'zeta':>18} {'|dz|/z':>9} "
          f"{'ord':>5} {'a2':>15} {'|da2|':>9} {'ord':>5} {'identity':>9}")
    prev = None
    for h, dist, wall in runs:
        zeta = dist.info.extra["zeta"]
        err = (abs(zeta / z_ref - 1), abs(dist.a2 - a_ref))
        ident = abs(dist.info.extra["zeta_identity"] / zeta - 1)
        last = dist is ref
        orders = ["" if prev is None or last or e == 0 else f"{math.log2(p / e):5.2f}"
                  for e, p in zip(err, prev or err, strict=True)]
        errs = ["(ref)"] * 2 if last else [f"{e:9.2e}" for e in err]
        print(f"{h:8.4f} {dist.info.extra['n_dofs']:7d} {dist.info.iterations:5d} {wall:7.1f} "
              f"{zeta:18.14f} {errs[0]:>9} {orders[0]:>5} {dist.a2:15.11f} {errs[1]:>9} "
              f"{orders[1]:>5} {ident:9.1e}")
        prev = err
    t0 = time.perf_counter()
    fd = kf.solve_cooling(alpha, method="fd")
    print(f"FD (default grid, {time.perf_counter() - t0:.1f} s): zeta {fd.info.extra['zeta']:.14f}"
          f" ({fd.info.extra['zeta'] / z_ref - 1:.1e}), a2 {fd.a2:.11f} ({fd.a2 - a_ref:.1e})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--alphas", type=float, nargs="*", default=[0.5, 0.85, 0.9])
    parser.add_argument("--quick", action="store_true", help="three meshes")
    args = parser.parse_args()
    spacings = [0.2, 0.1, 0.05] if args.quick else [0.2, 0.1, 0.05, 0.025]
    for alpha in args.alphas:
        study(alpha, spacings)


if __name__ == "__main__":
    main()
